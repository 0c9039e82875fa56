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

use plotters::coord::Shift;
use plotters::prelude::{DrawingArea, DrawingBackend, IntoLogRange};
use plotters::style::{BLACK, Color};
use realfft::RealFftPlanner;
use realfft::num_complex::Complex;

use super::figure::{DrawResult, Figure};
use super::layout::{self, Dash, Entry, Frame, Margins, Marker, Sample, curve, markers};
use super::style::{COLUMN_WIDTH_IN, PALETTE, Style};
use crate::error::Result;
use crate::motion::{SynthesisSettings, Synthesizer};

/// Figure height (in).
const HEIGHT_IN: f64 = 2.9;
/// Panel margins: 33 pt for the y tick labels, 10 pt on the right.
const MARGINS: Margins = Margins::new(33.0, 10.0);
/// Markers per decade for the stationary estimate (thinned on a log grid).
const MARKERS_PER_DECADE: f64 = 12.0;
/// Points of the target curve.
const TARGET_POINTS: usize = 240;

/// The ensemble spectrum figure: data computed once, drawn by [`Figure`].
#[derive(Clone, Debug, PartialEq)]
pub struct SpectrumFigure {
    /// Title.
    pub title: String,
    /// Target S(f): (Hz, (m/s²)²/Hz).
    pub target: Vec<(f64, f64)>,
    /// Mean periodogram of the stationary process, thinned to a log grid.
    pub stationary: Vec<(f64, f64)>,
    /// Mean periodogram of the processed records, scaled to the target variance.
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
        let k_min = (f_lo / settings.df).round() as usize;
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
                let f = f_lo * (f_hi / f_lo).powf(i as f64 / (TARGET_POINTS - 1) as f64);
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
            let cell = (f.log10() * MARKERS_PER_DECADE).floor();
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
        let entries = [
            Entry::new(Sample::Line(BLACK, Dash::Solid), "target S(f), eq. (6)"),
            Entry::new(
                Sample::Point(PALETTE[0], Marker::Circle, false),
                "stationary",
            ),
            Entry::new(Sample::Line(PALETTE[1], Dash::Solid), "records, rescaled"),
        ];
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
        let (f_lo, f_hi) = (self.target[0].0, self.target[self.target.len() - 1].0);
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
