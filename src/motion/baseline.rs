//! Baseline processing: zero-phase high-pass filter and drift-free,
//! consistent integration.
//!
//! 1. The acceleration is zero-padded by `pad_factor·order/fc` seconds on each
//!    side (Boore 2005's rule for acausal filters) up to an FFT length with
//!    only small prime factors, and multiplied in the frequency domain by the
//!    Butterworth magnitude `|H(f)| = 1/sqrt(1 + (fc/f)^(2n))` (zero phase,
//!    `H(0) = 0`).
//! 2. The velocity is the linear-acceleration integral of the filtered
//!    acceleration over the record window, with the initial velocity chosen so
//!    that its **mean over the record window is zero**, and the displacement
//!    is counted from the record's first sample (`disp[0] = 0`). Changing the
//!    initial velocity is an exact constant-velocity shift, so the rule the
//!    solver assumes still holds; the ground need not start at rest.
//!
//! Zero mean velocity means (almost) zero net displacement: under the linear
//! rule, d_end − d_0 = Δt·Σ_{k<L−1} v_k + Δt²·Σ(2a_k + a_{k+1})/6, so with
//! Σ_k v_k = 0 what remains is of order Δt·(|v_0| + |v_end|), small because
//! the record starts and ends quietly. (Zeroing the mean velocity over the
//! padded window instead leaves the acausal filter's slow tails in the record
//! window: end displacements up to ~10 % of the peak at the defaults.)
//!
//! References: Boore, D. M. (2005). On pads and filters: processing
//! strong-motion data. *Bull. Seismol. Soc. Am.* 95(2), 745–750.

use crate::detmath as dm;
use std::sync::Arc;

use realfft::num_complex::Complex;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};

use super::record::{Record, integrate_linear};
use crate::error::{Error, Result};

/// Baseline-processing settings (high-pass filter and its zero padding).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Baseline {
    /// High-pass corner frequency fc, Hz (default: 0.07, the paper's value).
    /// 0 disables the filter; the drift-free integration is still applied.
    pub highpass_hz: f64,
    /// Butterworth order n of the magnitude `1/sqrt(1 + (fc/f)^(2n))`, ≥ 1
    /// (default: 4). Applied zero-phase in the frequency domain.
    pub order: u32,
    /// Zero padding on each side, in units of `order/fc` seconds (default:
    /// 0.75, i.e. 43 s each side at the defaults).
    pub pad_factor: f64,
}

impl Default for Baseline {
    fn default() -> Self {
        Baseline {
            highpass_hz: 0.07,
            order: 4,
            pad_factor: 0.75,
        }
    }
}

impl Baseline {
    /// Checks the settings for records sampled every `dt` seconds; errors
    /// name the field as `baseline.<name>`.
    pub fn validate(&self, dt: f64) -> Result<()> {
        let nyquist = 0.5 / dt;
        if !(self.highpass_hz.is_finite() && self.highpass_hz >= 0.0 && self.highpass_hz < nyquist)
        {
            return Err(Error::invalid(
                "baseline.highpass_hz",
                self.highpass_hz,
                &format!(
                    "0 (no filter) or a frequency in (0, {}) Hz, below Nyquist",
                    crate::error::number(nyquist)
                ),
            ));
        }
        if self.order == 0 || self.order > 64 {
            return Err(Error::invalid(
                "baseline.order",
                self.order,
                "an integer in 1..=64",
            ));
        }
        if !(self.pad_factor.is_finite() && self.pad_factor >= 0.0) {
            return Err(Error::invalid(
                "baseline.pad_factor",
                self.pad_factor,
                "a finite number ≥ 0",
            ));
        }
        Ok(())
    }

    /// Applies baseline processing to a record (for recorded motions):
    /// filters `acc` and replaces `vel` and `disp` by its consistent,
    /// drift-free integrals (see the module documentation). A vertical
    /// acceleration, if any, is left unchanged.
    ///
    /// ```
    /// use rockfrag::motion::{Baseline, Record};
    /// let acc: Vec<f64> = (0..2000).map(|k| (k as f64 * 0.01).sin() + 0.01).collect();
    /// let raw = Record::from_acc("demo", 0.01, acc).unwrap();
    /// let clean = Baseline::default().apply(&raw).unwrap();
    /// assert_eq!(clean.disp[0], 0.0);
    /// assert_eq!(clean.len(), raw.len());
    /// ```
    pub fn apply(&self, record: &Record) -> Result<Record> {
        record.validate()?;
        let mut p = Processor::new(self, record.dt, record.len())?;
        let mut acc = record.acc.clone();
        let v0 = p.process(&mut acc);
        let (vel, disp) = integrate_linear(record.dt, &acc, v0, 0.0);
        let out = Record {
            name: record.name.clone(),
            dt: record.dt,
            acc,
            vel,
            disp,
            acc_v: record.acc_v.clone(),
        };
        out.validate()?;
        Ok(out)
    }
}

/// The smallest even length ≥ `n` whose prime factors are all 2, 3, 5 or 7
/// (fast for rustfft; even for realfft's fast path).
pub(crate) fn fast_len(n: usize) -> usize {
    let mut m = n.max(2);
    loop {
        if m.is_multiple_of(2) {
            let mut r = m;
            for p in [2, 3, 5, 7] {
                while r.is_multiple_of(p) {
                    r /= p;
                }
            }
            if r == 1 {
                return m;
            }
        }
        m += 1;
    }
}

/// High-pass filter and velocity-origin computation for records of one
/// length and time step, with its FFT plans, gains and scratch buffers.
#[derive(Clone)]
pub(crate) struct Processor {
    dt: f64,
    len: usize,
    /// Leading zeros before the record in the padded window.
    pad: usize,
    filter: Option<Filter>,
}

#[derive(Clone)]
struct Filter {
    forward: Arc<dyn RealToComplex<f64>>,
    inverse: Arc<dyn ComplexToReal<f64>>,
    /// |H(f_k)|/P for k = 0..=P/2 (the 1/P normalises the inverse FFT).
    gains: Vec<f64>,
    padded: Vec<f64>,
    spectrum: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
}

impl Processor {
    /// Plans the processing of records of `len` samples at `dt`.
    pub(crate) fn new(b: &Baseline, dt: f64, len: usize) -> Result<Self> {
        b.validate(dt)?;
        if b.highpass_hz == 0.0 {
            return Ok(Processor {
                dt,
                len,
                pad: 0,
                filter: None,
            });
        }
        let pad_s = b.pad_factor * f64::from(b.order) / b.highpass_hz;
        let pad = (pad_s / dt).ceil() as usize;
        let n = fast_len(len + 2 * pad);
        let mut planner = RealFftPlanner::<f64>::new();
        let forward = planner.plan_fft_forward(n);
        let inverse = planner.plan_fft_inverse(n);
        let scratch_len = forward.get_scratch_len().max(inverse.get_scratch_len());
        let two_n = 2.0 * f64::from(b.order);
        let gains = (0..=n / 2)
            .map(|k| {
                if k == 0 {
                    0.0
                } else {
                    let f = k as f64 / (n as f64 * dt);
                    1.0 / (1.0 + dm::powf(b.highpass_hz / f, two_n)).sqrt() / n as f64
                }
            })
            .collect();
        Ok(Processor {
            dt,
            len,
            pad,
            filter: Some(Filter {
                padded: forward.make_input_vec(),
                spectrum: forward.make_output_vec(),
                scratch: vec![Complex::default(); scratch_len],
                forward,
                inverse,
                gains,
            }),
        })
    }

    /// Total length of the padded window (samples).
    #[cfg(test)]
    pub(crate) fn padded_len(&self) -> usize {
        self.filter.as_ref().map_or(self.len, |f| f.padded.len())
    }

    /// Filters `acc` in place (length `len`) and returns the initial velocity
    /// that makes the mean velocity over the record window zero.
    pub(crate) fn process(&mut self, acc: &mut [f64]) -> f64 {
        assert_eq!(acc.len(), self.len, "record length differs from the plan");
        let dt = self.dt;
        match &mut self.filter {
            None => -mean_velocity(dt, acc),
            Some(f) => {
                let (pad, len) = (self.pad, self.len);
                // The forward FFT uses its input as scratch: re-zero the pads.
                f.padded[..pad].fill(0.0);
                f.padded[pad..pad + len].copy_from_slice(acc);
                f.padded[pad + len..].fill(0.0);
                f.forward
                    .process_with_scratch(&mut f.padded, &mut f.spectrum, &mut f.scratch)
                    .expect("buffers sized by the plan");
                for (x, g) in f.spectrum.iter_mut().zip(&f.gains) {
                    *x *= *g;
                }
                // A real signal's DC and Nyquist bins are real; clear any
                // rounding residue so the inverse transform accepts them.
                f.spectrum[0].im = 0.0;
                if let Some(last) = f.spectrum.last_mut() {
                    last.im = 0.0;
                }
                f.inverse
                    .process_with_scratch(&mut f.spectrum, &mut f.padded, &mut f.scratch)
                    .expect("buffers sized by the plan");
                acc.copy_from_slice(&f.padded[pad..pad + len]);
                -mean_velocity(dt, acc)
            }
        }
    }
}

/// Mean over k = 0..P of v_k, the linear-rule velocity of `y` (length P)
/// from v_0 = 0:
/// v̄ = Δt/(2P) Σ_{j=0}^{P-2} (y_j + y_{j+1})(P−1−j).
fn mean_velocity(dt: f64, y: &[f64]) -> f64 {
    let p = y.len();
    if p < 2 {
        return 0.0;
    }
    // Σ_j (y_j + y_{j+1})(P−1−j) = Σ_k y_k w_k, w_0 = P−1,
    // w_k = 2P−1−2k (0 < k < P−1), w_{P−1} = 1.
    let pf = p as f64;
    let mut acc = [0.0; 4];
    let inner = &y[1..p - 1];
    let chunks = inner.chunks_exact(4);
    let rest = chunks.remainder();
    let mut k = 1.0;
    for c in chunks {
        for i in 0..4 {
            acc[i] += c[i] * (2.0 * pf - 1.0 - 2.0 * (k + i as f64));
        }
        k += 4.0;
    }
    let mut s = (acc[0] + acc[1]) + (acc[2] + acc[3]);
    for (i, x) in rest.iter().enumerate() {
        s += x * (2.0 * pf - 1.0 - 2.0 * (k + i as f64));
    }
    s += y[0] * (pf - 1.0) + y[p - 1];
    0.5 * dt * s / pf
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_lengths_are_even_and_smooth() {
        assert_eq!(fast_len(5787), 5832);
        assert_eq!(fast_len(1), 2);
        assert_eq!(fast_len(1000), 1000);
        assert_eq!(fast_len(1001), 1008);
    }

    #[test]
    fn mean_velocity_matches_direct_integration() {
        let y: Vec<f64> = (0..37).map(|k| dm::sin((k * k) as f64 * 0.37)).collect();
        let (v, _) = integrate_linear(0.02, &y, 0.0, 0.0);
        let direct = v.iter().sum::<f64>() / v.len() as f64;
        assert!((mean_velocity(0.02, &y) - direct).abs() < 1e-15);
    }

    #[test]
    fn unfiltered_processing_zeroes_the_mean_velocity() {
        let b = Baseline {
            highpass_hz: 0.0,
            ..Default::default()
        };
        let acc: Vec<f64> = (0..500).map(|k| dm::cos(k as f64 * 0.05) + 0.3).collect();
        let r = b.apply(&Record::from_acc("x", 0.01, acc).unwrap()).unwrap();
        let mean = r.vel.iter().sum::<f64>() / r.len() as f64;
        assert!(mean.abs() < 1e-13, "{mean}");
    }

    #[test]
    fn filter_removes_a_constant_offset() {
        // A constant acceleration is pure DC plus the edges of the window:
        // after the high-pass, the middle of the record is far below it.
        let acc = vec![1.0; 3001];
        let r = Baseline::default()
            .apply(&Record::from_acc("dc", 0.01, acc).unwrap())
            .unwrap();
        assert!(r.acc[1500].abs() < 0.05, "{}", r.acc[1500]);
        let p = Processor::new(&Baseline::default(), 0.01, 3001).unwrap();
        assert!(p.padded_len() >= 3001 + 2 * 4286);
    }
}
