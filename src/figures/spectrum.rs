//! The ensemble's power spectrum against the target PSD S(f) of the
//! ground-motion model (Clough–Penzien), for the records the study ran.
//!
//! Three estimates are drawn over the target S(f):
//!
//! - the **records as generated** (modulated, high-passed, scaled): the
//!   ensemble mean periodogram of the whole record (zero-padded to twice a
//!   power of two), each record's periodogram first rescaled so that its
//!   area equals the target variance Σ A_k²/2 (records are scaled to a
//!   PGA, so only the shape is comparable);
//! - **what the records should show** (dashed): their expected periodogram,
//!   computed exactly from the model, S(f) smoothed by the envelope's
//!   spectral window and multiplied by the high-pass's |H(f)|²
//!   (`expected_periodogram`). A record is the stationary process times
//!   the envelope c(t), and the periodogram of a product is the process's
//!   spectrum convolved with c's: the default envelope's strong phase
//!   lasts a few seconds, so its window is about 0.1 Hz wide, and below
//!   0.2 Hz, where S(f) rises steeply, it carries energy down from higher
//!   frequencies. The records lie 2–3× above S(f) there (and below it
//!   under the high-pass's corner), by the model's design, not by a fault
//!   of the synthesis or of the estimate: they follow the dashed curve.
//!   Below about 0.03 Hz (five decades under the peak) the records keep a
//!   floor the dashed curve lacks: the high-pass's acausal tails cut at
//!   the record's ends;
//! - the **stationary process** (before envelope, filter and scaling): the
//!   ensemble mean of the one-sided periodogram P_k = 2|X_k|²Δt/N of one
//!   period (N = 1/(Δf·Δt) samples, so every component falls on a DFT bin).
//!   With the spectral representation's fixed amplitudes it equals S(f_k)
//!   record by record: it checks the synthesis, and is drawn as markers.
//!
//! The records are the study's own: its seed and its number of records
//! (both components of each pair for a study of pairs).
//!
//! A study of recorded motions has no target: [`SpectrumFigure::recorded`]
//! draws the mean periodogram of its records as recorded (each record's
//! periodogram averaged in 1/20-decade bins, then over the records), so the
//! figure shows the study's own motions.

use crate::detmath as dm;
use plotters::coord::Shift;
use plotters::prelude::{BindKeyPoints, DrawingArea, DrawingBackend, IntoLogRange};
use plotters::style::{BLACK, Color};
use realfft::RealFftPlanner;
use realfft::num_complex::Complex;

use super::figure::{DrawResult, Figure};
use super::layout::{self, Dash, Entry, Frame, LogAxis, Margins, Marker, Sample, curve, markers};
use super::style::{COLUMN_WIDTH_IN, LINE_PT, PALETTE, Style};
use crate::error::Result;
use crate::motion::{Record, SynthesisSettings, Synthesizer, second_component_seed};

/// Figure height (in).
const HEIGHT_IN: f64 = 2.9;
/// Room right of the panel (pt), for half the last frequency label.
const RIGHT_PT: f64 = 10.0;
/// Room left of the plot beyond its widest y tick label (pt): the tick
/// marks and a gap.
const Y_TICK_ROOM_PT: f64 = 9.0;
/// Markers per decade for the stationary estimate (thinned on a log grid).
const MARKERS_PER_DECADE: f64 = 12.0;
/// Points of the target curve.
const TARGET_POINTS: usize = 240;
/// Bins per decade of the recorded motions' mean periodogram.
const BINS_PER_DECADE: f64 = 20.0;
/// Lowest frequency shown for recorded motions (Hz).
const RECORDED_F_MIN: f64 = 0.05;
/// Highest frequency shown for recorded motions (Hz), below their Nyquist.
const RECORDED_F_MAX: f64 = 25.0;
/// Samples of the envelope's spectral window per bin of the records'
/// periodogram.
const WINDOW_OVERSAMPLE: usize = 8;

/// The ensemble spectrum figure: data computed once, drawn by [`Figure`].
#[derive(Clone, Debug, PartialEq)]
pub struct SpectrumFigure {
    /// Title.
    pub title: String,
    /// Target S(f): (Hz, (m/s²)²/Hz).
    pub target: Vec<(f64, f64)>,
    /// Mean periodogram of the stationary process, thinned to a log grid.
    pub stationary: Vec<(f64, f64)>,
    /// Mean periodogram of the processed records, scaled to the target
    /// variance; for recorded motions, their mean periodogram as recorded.
    pub records: Vec<(f64, f64)>,
    /// The records' expected periodogram (the target seen through the
    /// envelope and the high-pass), on the bins of `records`; empty for
    /// recorded motions.
    pub expected: Vec<(f64, f64)>,
}

impl SpectrumFigure {
    /// Computes the spectra of records 0..`count` of ensemble `seed` with the
    /// generator `settings`.
    pub fn compute(settings: &SynthesisSettings, seed: u64, count: usize) -> Result<Self> {
        let members: Vec<(u64, u64)> = (0..count as u64).map(|i| (seed, i)).collect();
        Self::compute_members(settings, &members, &ensemble_text(count, seed))
    }

    /// As [`SpectrumFigure::compute`], for a study of synthetic record
    /// pairs: both components of pairs 0..`pairs` (H1 from ensemble `seed`,
    /// H2 from [`second_component_seed`]`(seed)`), 2·`pairs` records.
    pub fn compute_pairs(settings: &SynthesisSettings, seed: u64, pairs: usize) -> Result<Self> {
        let h2 = second_component_seed(seed);
        let members: Vec<(u64, u64)> = (0..pairs as u64)
            .flat_map(|i| [(seed, i), (h2, i)])
            .collect();
        let what = format!(
            "the {} components of {pairs} record pair{} (seed {seed})",
            2 * pairs,
            if pairs == 1 { "" } else { "s" }
        );
        Self::compute_members(settings, &members, &what)
    }

    /// The spectra of the records `members` ((ensemble seed, index) each),
    /// named `what` in the title.
    fn compute_members(
        settings: &SynthesisSettings,
        members: &[(u64, u64)],
        what: &str,
    ) -> Result<Self> {
        let count = members.len().max(1);
        let mut synth = Synthesizer::new(settings)?;
        let freqs = synth.frequencies();
        let amps = synth.amplitudes();
        let variance: f64 = amps.iter().map(|a| a * a / 2.0).sum();
        let dt = settings.dt;
        let (f_lo, f_hi) = (freqs[0], *freqs.last().expect("at least one component"));

        // stationary process: one period, components on DFT bins
        let n = synth.period_len();
        let k_min = (f_lo / settings.frequency_step()).round() as usize;
        let mut planner = RealFftPlanner::<f64>::new();
        let fft = planner.plan_fft_forward(n);
        let mut input = fft.make_input_vec();
        let mut spectrum = fft.make_output_vec();
        let mut mean = vec![0.0; freqs.len()];
        for &(seed, i) in members {
            input.copy_from_slice(synth.stationary(seed, i));
            fft.process(&mut input, &mut spectrum)
                .expect("buffers sized by the plan");
            for (j, m) in mean.iter_mut().enumerate() {
                *m += periodogram(spectrum[k_min + j], dt, n) / count as f64;
            }
        }
        let stationary = thin_log(freqs.iter().copied().zip(mean).collect());

        // processed records, zero-padded
        let len = synth.samples();
        let m = len.next_power_of_two() * 2;
        let fft = planner.plan_fft_forward(m);
        let mut input = fft.make_input_vec();
        let mut spectrum = fft.make_output_vec();
        let df_pad = 1.0 / (m as f64 * dt);
        let bins: Vec<usize> = (1..m / 2)
            .filter(|&j| {
                let f = j as f64 * df_pad;
                f >= f_lo && f <= f_hi
            })
            .collect();
        let mut mean = vec![0.0; bins.len()];
        for &(seed, i) in members {
            let r = synth.generate(seed, i, 1.0)?;
            input.fill(0.0);
            input[..len].copy_from_slice(&r.acc);
            let mean_square = r.acc.iter().map(|a| a * a).sum::<f64>() / len as f64;
            fft.process(&mut input, &mut spectrum)
                .expect("buffers sized by the plan");
            for (m, &j) in mean.iter_mut().zip(&bins) {
                *m += periodogram(spectrum[j], dt, len) * variance / mean_square / count as f64;
            }
        }
        let records = bins.iter().map(|&j| j as f64 * df_pad).zip(mean).collect();
        let expected_all = expected_periodogram(settings, &freqs, &amps, m)?;
        let expected = bins
            .iter()
            .map(|&j| (j as f64 * df_pad, expected_all[j]))
            .collect();

        let target = (0..TARGET_POINTS)
            .map(|i| {
                let f = f_lo * dm::powf(f_hi / f_lo, i as f64 / (TARGET_POINTS - 1) as f64);
                (f, settings.psd.density(f))
            })
            .collect();
        Ok(SpectrumFigure {
            title: format!("Mean spectrum of {what}"),
            target,
            stationary,
            records,
            expected,
        })
    }
}

/// The expected one-sided periodogram of the records as generated, on the
/// DFT bins j = 0..=m/2 of a record zero-padded to `m` samples, scaled (as
/// each record's is) so that its area is the target variance Σ A_k²/2.
///
/// A record is x_n = c_n·a_n: the envelope c times the sum of cosines
/// a_n = Σ A_k cos(2π f_k nΔt + φ_k) with independent uniform phases, so
/// E|X(f)|² = Σ_k (A_k²/4)·(W(f − f_k) + W(f + f_k)) with
/// W(ν) = |Σ_n c_n e^{−2πiνnΔt}|², the envelope's spectral window; the
/// high-pass multiplies it by |H(f)|² = 1/(1 + (fc/f)^(2n)). W is sampled by
/// one FFT of the envelope zero-padded to [`WINDOW_OVERSAMPLE`]·m samples
/// and interpolated linearly between its samples.
fn expected_periodogram(
    settings: &SynthesisSettings,
    freqs: &[f64],
    amps: &[f64],
    m: usize,
) -> Result<Vec<f64>> {
    let dt = settings.dt;
    let envelope = settings.envelope.sample(dt, settings.samples());
    let q = m * WINDOW_OVERSAMPLE;
    let mut planner = RealFftPlanner::<f64>::new();
    let fft = planner.plan_fft_forward(q);
    let mut input = fft.make_input_vec();
    let mut spectrum = fft.make_output_vec();
    input[..envelope.len()].copy_from_slice(&envelope);
    fft.process(&mut input, &mut spectrum)
        .expect("buffers sized by the plan");
    // W at bin b of the q-grid (period q, W(−ν) = W(ν))
    let window = |b: usize| {
        let b = b % q;
        spectrum[b.min(q - b)].norm_sqr()
    };
    let at = |nu: f64| {
        let p = (nu * q as f64 * dt).abs();
        let (b, t) = (p.floor(), p - p.floor());
        let b = b as usize;
        window(b) * (1.0 - t) + window(b + 1) * t
    };
    let (fc, order) = (settings.baseline.highpass_hz, settings.baseline.order);
    let df_pad = 1.0 / (m as f64 * dt);
    let mut expected: Vec<f64> = (0..=m / 2)
        .map(|j| {
            let f = j as f64 * df_pad;
            // |H(f)|² of the zero-phase Butterworth high-pass
            let gain = if fc == 0.0 {
                1.0
            } else if f == 0.0 {
                0.0
            } else {
                1.0 / (1.0 + dm::powf(fc / f, 2.0 * f64::from(order)))
            };
            gain * freqs
                .iter()
                .zip(amps)
                .map(|(&fk, &a)| a * a / 4.0 * (at(f - fk) + at(f + fk)))
                .sum::<f64>()
        })
        .collect();
    let variance: f64 = amps.iter().map(|a| a * a / 2.0).sum();
    let area: f64 = expected.iter().skip(1).sum::<f64>() * df_pad;
    if area > 0.0 {
        for e in &mut expected {
            *e *= variance / area;
        }
    }
    Ok(expected)
}

impl SpectrumFigure {
    /// The mean one-sided periodogram of recorded motions as recorded
    /// ((m/s²)²/Hz): each record zero-padded to twice the next power of two,
    /// its periodogram 2|X|²Δt/L averaged in 1/20-decade bins from 0.05 Hz
    /// to 25 Hz (or the lowest Nyquist frequency), then the bins averaged
    /// over the records that reach them. No target: the records are what
    /// the study ran. `what` names them in the title.
    pub fn recorded(records: &[Record], what: &str) -> SpectrumFigure {
        let nyquist = records
            .iter()
            .map(|r| 0.5 / r.dt)
            .fold(f64::INFINITY, f64::min);
        let f_hi = RECORDED_F_MAX.min(nyquist);
        let decades = dm::log10(f_hi / RECORDED_F_MIN);
        let n_bins = (decades * BINS_PER_DECADE).ceil().max(1.0) as usize;
        let bin_of = |f: f64| (dm::log10(f / RECORDED_F_MIN) * BINS_PER_DECADE).floor();
        let (mut sum, mut count) = (vec![0.0; n_bins], vec![0usize; n_bins]);
        // records with at least one frequency bin in the mean
        let mut averaged = 0;
        let mut planner = RealFftPlanner::<f64>::new();
        for r in records {
            let len = r.acc.len();
            let m = len.next_power_of_two() * 2;
            let fft = planner.plan_fft_forward(m);
            let mut input = fft.make_input_vec();
            let mut spectrum = fft.make_output_vec();
            input[..len].copy_from_slice(&r.acc);
            fft.process(&mut input, &mut spectrum)
                .expect("buffers sized by the plan");
            let (mut b_sum, mut b_n) = (vec![0.0; n_bins], vec![0usize; n_bins]);
            let mut contributes = false;
            for (j, x) in spectrum.iter().enumerate().skip(1) {
                let f = j as f64 / (m as f64 * r.dt);
                let b = bin_of(f);
                if f > f_hi || b < 0.0 || b as usize >= n_bins {
                    continue;
                }
                b_sum[b as usize] += periodogram(*x, r.dt, len);
                b_n[b as usize] += 1;
            }
            for b in 0..n_bins {
                if b_n[b] > 0 {
                    sum[b] += b_sum[b] / b_n[b] as f64;
                    count[b] += 1;
                    contributes = true;
                }
            }
            averaged += usize::from(contributes);
        }
        let points = (0..n_bins)
            .filter(|&b| count[b] > 0)
            .map(|b| {
                // the bin's geometric centre
                let f = RECORDED_F_MIN * dm::powf(10.0, (b as f64 + 0.5) / BINS_PER_DECADE);
                (f.min(f_hi), sum[b] / count[b] as f64)
            })
            .collect();
        SpectrumFigure {
            title: format!("Mean spectrum of {averaged} {what}"),
            target: Vec::new(),
            stationary: Vec::new(),
            records: points,
            expected: Vec::new(),
        }
    }
}

/// `the 50 records (seed 7)`: the records a synthetic spectrum averages
/// (records 0 to n − 1 of the ensemble), as its title names them.
fn ensemble_text(n: usize, seed: u64) -> String {
    match n {
        1 => format!("record 0 (seed {seed})"),
        n => format!("the {n} records (seed {seed})"),
    }
}

impl SpectrumFigure {
    /// The frequency range shown (the target's, or the records' without one)
    /// and the PSD range (the data's, with a factor of 2 of room either side).
    pub fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        let all = self
            .target
            .iter()
            .chain(&self.stationary)
            .chain(&self.records);
        let (mut y_lo, mut y_hi) = (f64::INFINITY, 0.0_f64);
        for &(_, s) in all {
            if s > 0.0 {
                y_lo = y_lo.min(s);
                y_hi = y_hi.max(s);
            }
        }
        let shown = if self.target.is_empty() {
            &self.records
        } else {
            &self.target
        };
        let f = match (shown.first(), shown.last()) {
            (Some(a), Some(b)) if b.0 > a.0 => (a.0, b.0),
            _ => (RECORDED_F_MIN, RECORDED_F_MAX),
        };
        if y_hi <= 0.0 || y_lo.is_infinite() {
            (y_lo, y_hi) = (1e-6, 1.0);
        }
        (f, (y_lo * 0.5, y_hi * 2.0))
    }

    /// The labels of the PSD axis's ticks, bottom to top.
    pub fn y_tick_labels(&self) -> Vec<String> {
        let (_, (lo, hi)) = self.ranges();
        let axis = LogAxis::new(lo, hi);
        axis.ticks.iter().map(|&t| axis.label(t)).collect()
    }
}

/// One-sided periodogram 2|X|²Δt/L of a DFT bin of a record of L samples.
fn periodogram(x: Complex<f64>, dt: f64, len: usize) -> f64 {
    2.0 * x.norm_sqr() * dt / len as f64
}

/// Keeps the first point of each 1/[`MARKERS_PER_DECADE`]-decade bin.
fn thin_log(points: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    let mut last = f64::NEG_INFINITY;
    points
        .into_iter()
        .filter(|&(f, _)| {
            let cell = (dm::log10(f) * MARKERS_PER_DECADE).floor();
            let keep = cell > last;
            last = last.max(cell);
            keep
        })
        .collect()
}

impl Figure for SpectrumFigure {
    fn size_in(&self) -> (f64, f64) {
        (COLUMN_WIDTH_IN, HEIGHT_IN)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        style: &Style,
    ) -> DrawResult<DB> {
        let synthetic = !self.target.is_empty();
        let entries = if synthetic {
            vec![
                Entry::new(
                    Sample::Line(BLACK, Dash::Solid),
                    "target S(f) (Clough–Penzien)",
                ),
                Entry::new(
                    Sample::Line(BLACK, Dash::Dashed),
                    "S(f) through envelope and high-pass",
                ),
                Entry::new(Sample::Line(PALETTE[1], Dash::Solid), "records (mean)"),
                Entry::new(
                    Sample::Point(PALETTE[0], Marker::Circle, false),
                    "stationary process (synthesis check)",
                ),
            ]
        } else {
            vec![Entry::new(
                Sample::Line(PALETTE[1], Dash::Solid),
                "records as recorded, mean",
            )]
        };
        let ((f_lo, f_hi), (y_lo, y_hi)) = self.ranges();
        let (x_axis, y_axis) = (LogAxis::new(f_lo, f_hi), LogAxis::new(y_lo, y_hi));
        // room for the widest y label, measured in the font it is drawn in
        let widest = layout::widest(root, style, y_axis.ticks.iter().map(|&t| y_axis.label(t)));
        let margins = Margins::new(
            widest as f64 * 72.0 / style.px_per_in + Y_TICK_ROOM_PT,
            RIGHT_PT,
        );
        let frame = Frame::new(root, style, &self.title, &entries, margins)?;
        frame.heading(&frame.body, "One-sided PSD ((m/s²)²/Hz)")?;
        let mut chart = frame.chart(&frame.body, true).build_cartesian_2d(
            (f_lo..f_hi)
                .log_scale()
                .with_key_points(x_axis.ticks.clone()),
            (y_lo..y_hi)
                .log_scale()
                .with_key_points(y_axis.ticks.clone()),
        )?;
        let mut mesh = layout::mesh(&mut chart, style);
        mesh.x_label_formatter(&|v| x_axis.label(*v))
            .y_label_formatter(&|v| y_axis.label(*v))
            .x_desc("Frequency (Hz)")
            .draw()?;

        curve!(
            chart,
            self.records.iter().copied(),
            style.series(1),
            Dash::Solid,
            style
        );
        let target_style = BLACK.stroke_width(style.ipx(0.8));
        curve!(
            chart,
            self.target.iter().copied(),
            target_style,
            Dash::Solid,
            style
        );
        curve!(
            chart,
            self.expected.iter().copied().filter(|p| p.1 >= y_lo),
            BLACK.stroke_width(style.ipx(LINE_PT)),
            Dash::Dashed,
            style
        );
        markers!(
            chart,
            self.stationary.iter().copied(),
            PALETTE[0],
            Marker::Circle,
            false,
            style
        );
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_xoshiro::Xoshiro256PlusPlus;

    /// The PSD axis of a spectrum spanning seven decades labels each decade
    /// as a power of ten, every label different (issue 29: `0.00001` and
    /// `0.000001` were both clipped to `00001`); the title counts the
    /// records the mean was taken over.
    #[test]
    fn psd_axis_labels_are_distinct_powers_of_ten_and_the_title_counts_the_records() {
        let fig = SpectrumFigure::compute(&SynthesisSettings::default(), 5, 3).unwrap();
        assert!(
            fig.title
                .contains("Mean spectrum of the 3 records (seed 5)"),
            "{}",
            fig.title
        );
        let fig = SpectrumFigure {
            title: String::new(),
            target: vec![(0.01, 1.2e-6), (1.0, 0.5)],
            stationary: Vec::new(),
            records: Vec::new(),
            expected: Vec::new(),
        };
        let labels = fig.y_tick_labels();
        assert_eq!(
            labels,
            ["10⁻⁶", "10⁻⁵", "10⁻⁴", "10⁻³", "10⁻²", "10⁻¹", "10⁰"]
        );
        let distinct: std::collections::BTreeSet<&String> = labels.iter().collect();
        assert_eq!(distinct.len(), labels.len());
    }

    /// White noise of variance σ² sampled at Δt has the flat one-sided PSD
    /// 2σ²Δt. Over 8 records of 60 s at 0.01 s (independent periodogram
    /// values every 1/60 Hz), each 1/20-decade bin above 2 Hz (0.24 Hz wide
    /// or more) averages at least 14 independent values per record, 112 in
    /// all: a relative standard error below 10 %, so every bin is within 35 %
    /// (3.7 standard errors) of 2σ²Δt and the mean of the 22 bins within 5 %.
    #[test]
    fn recorded_spectrum_of_white_noise_is_flat_at_two_sigma_squared_dt() {
        let (dt, n, sigma) = (0.01, 6000, 0.5);
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
        let records: Vec<Record> = (0..8)
            .map(|_| {
                // uniform on [−a, a] has variance a²/3
                let a = sigma * 3f64.sqrt();
                let acc = (0..n)
                    .map(|_| a * (2.0 * rng.random::<f64>() - 1.0))
                    .collect();
                Record::from_acc("noise", dt, acc).unwrap()
            })
            .collect();
        let fig = SpectrumFigure::recorded(&records, "noise records");
        let flat = 2.0 * sigma * sigma * dt;
        let upper: Vec<f64> = fig
            .records
            .iter()
            .filter(|p| p.0 > 2.0)
            .map(|p| p.1)
            .collect();
        assert!(upper.len() >= 20, "{} bins", upper.len());
        for p in &upper {
            assert!((p / flat - 1.0).abs() < 0.35, "{p} vs {flat}");
        }
        let mean = upper.iter().sum::<f64>() / upper.len() as f64;
        assert!((mean / flat - 1.0).abs() < 0.05, "{mean} vs {flat}");
        assert!(fig.target.is_empty() && fig.title.contains("8 noise records"));
    }
}
