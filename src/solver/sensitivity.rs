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
//! ensemble (`rockfrag bench`: 1800 analyses, 25 records of the default
//! motion model at 0.2 … 1.2 g, reference settings) |Δθmax/θc| is at most
//! 1e-9 in 1304 runs, in (1e-9, 1e-6] in 323, (1e-6, 1e-4] in 74,
//! (1e-4, 1e-3] in 23 and above 1e-3 in 71, and overturning flips in 5; of
//! the 626 runs that overturn in both, the overturning time moves by at most
//! 1e-6 s in 377, by (1e-6, 1e-2] s in 211 and by more in 38 (up to 1.5 s).
//! The tail is continuous, so the thresholds are a convention, stated: 114
//! runs (6.3 %) are sensitive, none at 0.2 g, then 2.0, 1.3, 7.0, 16.7 and
//! 11.0 % at 0.4, 0.6, 0.8, 1.0 and 1.2 g; a perturbation of 1e-6 flags 349
//! (19.4 %), which says that the sensitive fraction is a lower bound on the
//! chaotic runs and grows with the size of what is ignored. The overturning
//! time matters: 38 of the 114 are flagged by it alone, runs that stay
//! overturned under the perturbation but 0.01 to 1.5 s earlier or later,
//! and ten of those (five blocks and records, each under both friction
//! models) flip between solver settings.
//!
//! What it does not see: a run decided by a hair in a direction the
//! record's amplitude does not probe, and a solver's own mistake. Of the 75
//! overturning mismatches between the bench's nonlinear settings and the
//! reference (`figures/work_precision.md`), 73 are runs it flags on the
//! reference; the other 2 are one block and record under both friction
//! models (H/B 4, e = 0 at 1.2 g, record 24, mismatched by Dormand–Prince at
//! rtol 1e-9 alone), which a scaling of the record by 1e-7 flips: a hair, at
//! a size that tolerance errs by. Before the rock searches bounded θ's
//! curvature over a step (`scan::first_descent_bounded`, on all three rock
//! paths) there were 140, 66 of them on six runs (H/B 4, e = 0 at 1.0 g,
//! records 22 and 23; H/B 6, e = 0 at 0.8 g, record 10, each under both
//! friction models) that were solver errors: no scaling from 1e-9 to 1e-6,
//! either way, changed their outcome under any setting, and each setting
//! was either robustly right or robustly wrong. The looser settings, the
//! default among them, missed a rock impact: while the block rocks at
//! 1e-6 rad near the uplift threshold, θ returns to 0 and leaves it again
//! within one step (one record sample), θ̇ changes sign twice in that step,
//! and a search for one interior minimum per piece finds none. The bounded
//! search cannot miss such a return; with it every setting matches the
//! reference on all six (`tests/impact_double_crossing.rs`).
//!
//! **Cost.** One more solve of the analysis (and a copy of its record), so
//! it doubles the solver's time: on the bench ensemble at 0.6 and 1.2 g,
//! one thread, default settings, 477 µs per analysis without it and 987 µs
//! with it (minima of 7 alternating passes; medians 513 and 1027 µs; ratio
//! 2.07 of the minima, 1.98 the median of the passes' ratios; `cargo run
//! --release --example sensitivity_cost`, the 2 cores shared, load 9). A
//! study pays a little less, since its records are made once: the default
//! study on one thread, without and with it, 0.92 and 1.94 s (minima of 7
//! alternating runs; medians 1.25 and 2.10 s; the runs' ratios 1.35–2.29,
//! median 1.63). It is therefore off by default (`simulate --sensitivity`; a
//! study's `[output] sensitivity`).

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
/// // 0.5 s at 0.28 g (above the uplift threshold g·B/H = 0.25 g): the block
/// // tips to 0.12 θc and does not overturn, far from any threshold, so a
/// // perturbation of 1e-9 changes nothing that matters
/// let record = Record::from_acc("pulse", 0.01, vec![0.28 * 9.81; 51]).unwrap();
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
