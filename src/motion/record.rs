//! The ground-motion record: uniformly sampled ground acceleration, velocity
//! and displacement, in SI units.
//!
//! Between samples the acceleration is taken as **linear** in time; velocity
//! and displacement are its exact integrals under that rule. This is the rule
//! the solver assumes, so a record whose `vel`/`disp` obey it is "consistent".

use crate::error::{Error, Result};

/// Standard gravity used to convert accelerations given in g (m/s²).
pub const G_STANDARD: f64 = 9.81;

/// The most samples a record may have: 2²² = 4,194,304 (23.3 h at
/// Δt = 0.02 s, 70 min at Δt = 0.001 s; the longest earthquake records
/// hold a few 10⁴). A record costs about 110 bytes of memory a sample while
/// it is made and solved, for each thread of a study: 448 MB a thread at
/// this limit (measured, `rockfrag motion --duration 83886`). Longer inputs
/// (`duration = 1e9`, `dt = 1e-9`) are refused, not left to abort on an
/// allocation.
pub const MAX_SAMPLES: usize = 1 << 22;

/// A uniformly sampled ground-motion record (SI units), sample k at t = k·dt.
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    /// Human-readable name (file name, or `seed/index` for synthetic records).
    pub name: String,
    /// Sample interval Δt (s).
    pub dt: f64,
    /// Horizontal ground acceleration ẍg (m/s²).
    pub acc: Vec<f64>,
    /// Horizontal ground velocity ẋg (m/s), consistent with `acc`.
    pub vel: Vec<f64>,
    /// Horizontal ground displacement xg (m), consistent with `vel`.
    pub disp: Vec<f64>,
    /// Vertical ground acceleration ÿg (m/s²), if the record has one.
    pub acc_v: Option<Vec<f64>>,
}

impl Record {
    /// A record of no samples at interval `dt`, to be filled (its buffers
    /// grow once and are reused, as [`super::Synthesizer::generate_into`]
    /// and [`super::Pair::rotate_into`] do).
    pub fn empty(dt: f64) -> Record {
        Record {
            name: String::new(),
            dt,
            acc: Vec::new(),
            vel: Vec::new(),
            disp: Vec::new(),
            acc_v: None,
        }
    }

    /// Builds a record from accelerations alone, integrating velocity and
    /// displacement from rest by the linear-acceleration rule.
    ///
    /// ```
    /// use rockfrag::motion::Record;
    /// let r = Record::from_acc("step", 0.5, vec![0.0, 1.0, 1.0]).unwrap();
    /// assert_eq!(r.vel, vec![0.0, 0.25, 0.75]);
    /// ```
    pub fn from_acc(name: impl Into<String>, dt: f64, acc: Vec<f64>) -> Result<Self> {
        let (vel, disp) = integrate_linear(dt, &acc, 0.0, 0.0);
        Record::new(name, dt, acc, vel, disp)
    }

    /// A horizontal record from its three series, checked by
    /// [`Record::validate`].
    pub fn new(
        name: impl Into<String>,
        dt: f64,
        acc: Vec<f64>,
        vel: Vec<f64>,
        disp: Vec<f64>,
    ) -> Result<Self> {
        let r = Record {
            name: name.into(),
            dt,
            acc,
            vel,
            disp,
            acc_v: None,
        };
        r.validate()?;
        Ok(r)
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.acc.len()
    }

    /// True if the record has no samples.
    pub fn is_empty(&self) -> bool {
        self.acc.is_empty()
    }

    /// Duration (s) from the first to the last sample.
    pub fn duration(&self) -> f64 {
        self.dt * (self.len().saturating_sub(1)) as f64
    }

    /// Peak |ẍg| (m/s²).
    pub fn pga(&self) -> f64 {
        self.acc.iter().fold(0.0_f64, |m, a| m.max(a.abs()))
    }

    /// Peak |ẋg| (m/s).
    pub fn pgv(&self) -> f64 {
        self.vel.iter().fold(0.0_f64, |m, a| m.max(a.abs()))
    }

    /// The record with every series (acceleration, velocity, displacement,
    /// vertical acceleration) multiplied by `k`: ground motion is linear in
    /// its amplitude, so this is the record scaled to k times its PGA and PGV.
    pub fn scaled(mut self, k: f64) -> Record {
        for s in [&mut self.acc, &mut self.vel, &mut self.disp] {
            s.iter_mut().for_each(|x| *x *= k);
        }
        if let Some(v) = self.acc_v.as_mut() {
            v.iter_mut().for_each(|x| *x *= k);
        }
        self
    }

    /// Checks that the record is usable: at least two samples and at most
    /// [`MAX_SAMPLES`], a positive finite Δt, equal lengths and finite
    /// values.
    pub fn validate(&self) -> Result<()> {
        self.validate_forcing()?;
        if self.acc.len() > MAX_SAMPLES {
            return Err(self.invalid(format!(
                "{} samples: at most {MAX_SAMPLES} are taken (2^22, 23.3 h at dt = 0.02 s; \
                 about 110 bytes of memory each per thread)",
                self.acc.len()
            )));
        }
        if self.vel.len() != self.acc.len() || self.disp.len() != self.acc.len() {
            return Err(self.invalid("acc, vel and disp have different lengths".into()));
        }
        self.check_finite("vel", &self.vel)?;
        self.check_finite("disp", &self.disp)
    }

    /// The part of [`Record::validate`] the solver relies on: Δt, at least two
    /// samples, and finite accelerations (horizontal, and vertical if given,
    /// of the same length). The solver checks this for every analysis.
    pub fn validate_forcing(&self) -> Result<()> {
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return Err(self.invalid(format!(
                "sample interval dt = {} must be positive and finite",
                crate::error::number(self.dt)
            )));
        }
        if self.acc.len() < 2 {
            return Err(self.invalid(format!("{} samples; at least 2 are needed", self.acc.len())));
        }
        self.check_finite("acc", &self.acc)?;
        if let Some(v) = &self.acc_v {
            if v.len() != self.acc.len() {
                return Err(self.invalid("vertical acceleration has a different length".into()));
            }
            self.check_finite("acc_v", v)?;
        }
        Ok(())
    }

    fn invalid(&self, message: String) -> Error {
        Error::InvalidRecord {
            name: self.name.clone(),
            message,
        }
    }

    /// Errors with the first non-finite sample of `series`, if any: a
    /// branch-free pass first (it vectorises), the position only if needed.
    fn check_finite(&self, label: &str, series: &[f64]) -> Result<()> {
        if !series.iter().fold(true, |ok, x| ok & x.is_finite())
            && let Some(k) = series.iter().position(|x| !x.is_finite())
        {
            return Err(self.invalid(format!("{label} sample {k} is {}", series[k])));
        }
        Ok(())
    }
}

/// Integrates a piecewise-linear acceleration exactly: returns (velocity,
/// displacement) at the samples, starting from `v0`, `d0`.
///
/// v_{k+1} = v_k + Δt (a_k + a_{k+1})/2 ;
/// d_{k+1} = d_k + Δt v_k + Δt² (2 a_k + a_{k+1})/6   (linear-acceleration rule).
pub fn integrate_linear(dt: f64, acc: &[f64], v0: f64, d0: f64) -> (Vec<f64>, Vec<f64>) {
    let mut vel = Vec::with_capacity(acc.len());
    let mut disp = Vec::with_capacity(acc.len());
    let (mut v, mut d) = (v0, d0);
    for k in 0..acc.len() {
        vel.push(v);
        disp.push(d);
        if k + 1 < acc.len() {
            let (a0, a1) = (acc[k], acc[k + 1]);
            d += dt * v + dt * dt * (2.0 * a0 + a1) / 6.0;
            v += dt * (a0 + a1) / 2.0;
        }
    }
    (vel, disp)
}
