//! Whether one analysis is decided by a hair: the analysis solved again under
//! a perturbation far below any physical uncertainty, and its outcome
//! compared.
//!
//! Near overturning the rigid block is chaotic: whether it is still rocking
//! at 1e-4 rad when the next pulse above the uplift threshold arrives, or
//! whether it balances past θc a moment longer, decides the run. Such a run
//! flips between solver settings, and between solvers, without either being
//! wrong. [`sensitivity`] tells those runs apart: it solves the analysis
//! again with the record's amplitude scaled by 1 + [`PERTURBATION`] (every
//! sample, so the same shape and a PGA larger by 1e-9 relative) and the same
//! settings, and calls the run *sensitive* when
//!
//! - overturning flipped, or
//! - θmax/θc moved by more than [`THETA_TOL`] (1e-3), or
//! - both overturned and the time of overturning moved by more than
//!   [`TIME_TOL`] (0.01 s).
//!
//! **Why the record, and why 1e-9.** A change of the input, not of the
//! numerics, measures the problem's own conditioning, whatever the solver:
//! the same test applies to the reference solutions of `rockfrag bench`
//! (Dormand–Prince at rtol 1e-12) and to a study's default Taylor runs. The
//! size is that of the default solver's own error (its median relative θmax
//! error against the reference is 2e-10, at rtol 1e-8), so a run the
//! perturbation changes is one the solver's error can change too; and it is
//! six orders below any physical uncertainty of a record's amplitude (1e-3 at
//! best). The thresholds are a gain of 1e6 on that: a regular run moves by
//! about the perturbation times an amplification of 1–1e3. On the bench
//! ensemble (`rockfrag bench`: 1800 analyses, 25 records at 0.2 … 1.2 g,
//! reference settings) |Δθmax/θc| is at most 1e-9 in 1328 runs, in
//! (1e-9, 1e-6] in 282, (1e-6, 1e-4] in 95, (1e-4, 1e-3] in 30 and above
//! 1e-3 in 56, and overturning flips in 9; of the 640 runs that overturn in
//! both, the overturning time moves by at most 1e-6 s in 423, by
//! (1e-6, 1e-2] s in 197 and by more in 20 (up to 0.3 s). The tail is
//! continuous, so the thresholds are a convention, stated: 85 runs (4.7 %)
//! are sensitive, none at 0.2 and 0.4 g, then 2.7, 6.0, 10.0 and 9.7 % at
//! 0.6, 0.8, 1.0 and 1.2 g; a
//! perturbation of 1e-6 flags 297 (16.5 %), which says that the sensitive
//! fraction is a lower bound on the chaotic runs and grows with the size of
//! what is ignored. The overturning time matters: 20 of the 85 are flagged
//! by it alone, runs that stay overturned under the perturbation but 0.01 to
//! 0.3 s earlier or later, and three of those flip between solver settings
//! (H/B 6, e = 0 at 0.6 g, record 17, under Dormand–Prince at rtol 1e-7 and
//! 1e-8; H/B 4, e = 0.9 at 1.2 g, record 11, under the chatter rule).
//!
//! What it does not see: a run decided by a hair in a direction the
//! record's amplitude does not probe. Of the 188 overturning mismatches
//! between the bench's nonlinear settings and the reference, 159 are runs it
//! flags on the reference; the other 29 fall on 5 runs
//! (`figures/work_precision.md`): two that a scaling of 1e-6 flips (loose
//! Dormand–Prince tolerances err by more than that), two where Dormand–Prince
//! at rtol 1e-8 alone errs, and one the chatter rule decides, where the
//! ring-down that every bounce followed sets at rest and the rule leaves
//! rocking at 4e-9 rad meet the next pulse differently.
//!
//! **Cost.** One more solve of the analysis (and a copy of its record), so
//! it doubles the solver's time: on the bench ensemble, one thread, default
//! settings, 290 µs per analysis without it and 572 µs with it (minima of 7
//! alternating passes; medians 298 and 597 µs; ratio 1.97 of the minima,
//! 2.03 the median of the passes' ratios; `cargo run --release --example
//! sensitivity_cost`). It is therefore off by default (`simulate
//! --sensitivity`; a study's `[output] sensitivity`).

use super::driver::simulate;
use super::settings::{Analysis, SolverSettings};
use crate::error::Result;
use crate::motion::Record;
use crate::outcome::Outcome;
use serde::Serialize;

/// Relative perturbation of the record's amplitude (1e-9).
pub const PERTURBATION: f64 = 1e-9;

/// Change of θmax/θc above which a run is sensitive (1e-3).
pub const THETA_TOL: f64 = 1e-3;

/// Change of the overturning time above which a run that overturns in both
/// solutions is sensitive (0.01 s, half a sample of the synthetic records).
pub const TIME_TOL: f64 = 0.01;

/// What the perturbed solution found, and whether it differs.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Sensitivity {
    /// Overturning flipped, θmax/θc moved by more than [`THETA_TOL`], or the
    /// overturning time by more than [`TIME_TOL`].
    pub sensitive: bool,
    /// The perturbed run overturned.
    pub overturned: bool,
    /// θmax/θc of the perturbed run.
    pub theta_max_over_theta_c: f64,
    /// Time of overturning of the perturbed run (s), if it overturned.
    pub overturn_time: Option<f64>,
}

impl Sensitivity {
    /// Compares the outcome of the perturbed run with that of the run itself.
    pub fn compare(base: &Outcome, perturbed: &Outcome) -> Sensitivity {
        let time_moved = match (base.overturn_time, perturbed.overturn_time) {
            (Some(a), Some(b)) => (a - b).abs() > TIME_TOL,
            _ => false,
        };
        let theta_moved =
            (base.theta_max_over_theta_c - perturbed.theta_max_over_theta_c).abs() > THETA_TOL;
        Sensitivity {
            sensitive: base.overturned != perturbed.overturned || theta_moved || time_moved,
            overturned: perturbed.overturned,
            theta_max_over_theta_c: perturbed.theta_max_over_theta_c,
            overturn_time: perturbed.overturn_time,
        }
    }
}

/// The record with its amplitude scaled by 1 + [`PERTURBATION`].
pub fn perturbed(record: &Record) -> Record {
    record.clone().scaled(1.0 + PERTURBATION)
}

/// Solves `analysis` again under the [`perturbed`] record with the same
/// settings and compares the outcome with `base`, the outcome of the
/// analysis itself (`simulate(analysis, record, settings, None)`, which the
/// caller has). Errors are the solver's on the perturbed record.
///
/// ```
/// use rockfrag::motion::Record;
/// use rockfrag::solver::{simulate, sensitivity, Analysis, Block, SolverSettings};
/// let block = Block::new(0.5, 4.0, 9.81).unwrap();
/// // 2 s at 0.3 g: the block tips, rocks and does not overturn, far from any
/// // threshold, so a perturbation of 1e-9 changes nothing that matters
/// let record = Record::from_acc("pulse", 0.01, vec![0.3 * 9.81; 201]).unwrap();
/// let (an, set) = (Analysis::new(block, 0.0), SolverSettings::default());
/// let out = simulate(&an, &record, &set, None).unwrap();
/// let s = sensitivity(&an, &record, &set, &out).unwrap();
/// assert!(!s.sensitive && !s.overturned);
/// ```
pub fn sensitivity(
    analysis: &Analysis,
    record: &Record,
    settings: &SolverSettings,
    base: &Outcome,
) -> Result<Sensitivity> {
    let other = simulate(analysis, &perturbed(record), settings, None)?;
    Ok(Sensitivity::compare(base, &other))
}
