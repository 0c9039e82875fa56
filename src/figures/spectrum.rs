//! The ensemble's power spectrum against the target PSD (paper eq. 6).
//!
//! Two estimates are drawn over the target S(f):
//!
//! - the **stationary process** (before envelope, filter and scaling): the
//!   ensemble mean of the one-sided periodogram P_k = 2|X_k|²Δt/N of one
//!   period (N = 1/(Δf·Δt) samples, so every component falls on a DFT bin).
//!   With the spectral representation's fixed amplitudes it equals S(f_k)
//!   record by record: it checks the synthesis, and is drawn as markers;
//! - the **records as generated** (modulated, high-passed, scaled): the
//!   ensemble mean periodogram of the whole record (zero-padded to a power of
//!   two), each record's periodogram first rescaled so that its area equals
//!   the target variance Σ A_k²/2. Records are scaled to a PGA, so only the
//!   shape is comparable: it shows the high-pass filter below 0.1 Hz and the
//!   smoothing by the envelope.
//!
//! A study of recorded motions has no target: [`SpectrumFigure::recorded`]
//! draws the mean periodogram of its records as recorded (each record's
//! periodogram averaged in 1/20-decade bins, then over the records), so the
//! figure shows the study's own motions.

use crate::detmath as dm;
use plotters::coord::Shift;
use plotters::prelude::{DrawingArea, DrawingBackend, IntoLogRange};
use plotters::style::{BLACK, Color};
use realfft::RealFftPlanner;
use realfft::num_complex::Complex;

use super::figure::{DrawResult, Figure};
use super::layout::{self, Dash, Entry, Frame, Margins, Marker, Sample, curve, markers};
use super::style::{COLUMN_WIDTH_IN, PALETTE, Style};
use crate::error::Result;
use crate::motion::{Record, SynthesisSettings, Synthesizer};

/// Figure height (in).
const HEIGHT_IN: f64 = 2.9;
/// Panel margins: 33 pt for the y tick labels, 10 pt on the right.
const MARGINS: Margins = Margins::new(33.0, 10.0);
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
}

impl SpectrumFigure {
    /// Computes the spectra of records 0..`count` of ensemble `seed` with the
    /// generator `settings`.
    pub fn compute(settings: &SynthesisSettings, seed: u64, count: usize) -> Result<Self> {
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
        for i in 0..count {
            input.copy_from_slice(synth.stationary(seed, i as u64));
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
        for i in 0..count {
            let r = synth.generate(seed, i as u64, 1.0)?;
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

        let target = (0..TARGET_POINTS)
            .map(|i| {
                let f = f_lo * dm::powf(f_hi / f_lo, i as f64 / (TARGET_POINTS - 1) as f64);
                (f, settings.psd.density(f))
            })
            .collect();
        Ok(SpectrumFigure {
            title: format!("Spectrum of {count} records (ensemble seed {seed})"),
            target,
            stationary,
            records,
        })
    }
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
                }
            }
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
            title: format!("Mean spectrum of {} {what}", records.len()),
            target: Vec::new(),
            stationary: Vec::new(),
            records: points,
        }
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
                Entry::new(Sample::Line(BLACK, Dash::Solid), "target S(f), eq. (6)"),
                Entry::new(
                    Sample::Point(PALETTE[0], Marker::Circle, false),
                    "stationary",
                ),
                Entry::new(Sample::Line(PALETTE[1], Dash::Solid), "records, rescaled"),
            ]
        } else {
            vec![Entry::new(
                Sample::Line(PALETTE[1], Dash::Solid),
                "records as recorded, mean",
            )]
        };
        let frame = Frame::new(root, style, &self.title, &entries, MARGINS)?;
        frame.heading(&frame.body, "One-sided PSD ((m/s²)²/Hz)")?;

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
        let shown = if synthetic {
            &self.target
        } else {
            &self.records
        };
        let (f_lo, f_hi) = match (shown.first(), shown.last()) {
            (Some(a), Some(b)) if b.0 > a.0 => (a.0, b.0),
            _ => (RECORDED_F_MIN, RECORDED_F_MAX),
        };
        if y_hi <= 0.0 || y_lo.is_infinite() {
            (y_lo, y_hi) = (1e-6, 1.0);
        }
        let mut chart = frame.chart(&frame.body, true).build_cartesian_2d(
            (f_lo..f_hi).log_scale(),
            (y_lo * 0.5..y_hi * 2.0).log_scale(),
        )?;
        let mut mesh = layout::mesh(&mut chart, style);
        mesh.x_label_formatter(&|v| layout::log_tick_label(*v))
            .y_label_formatter(&|v| layout::log_tick_label(*v))
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
