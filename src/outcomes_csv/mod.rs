//! `outcomes.csv`: the table of per-analysis outcomes that a study writes
//! and the summary, the fragility fit, the figures, `merge` and Python read.
//! One row per analysis, in the canonical order of units and cases (see
//! [`crate::study::Unit`]; cases in the order of the study's grid lists,
//! aspect, then width, then e, then friction).
//!
//! Columns, in order (the bracketed ones only when the study uses them):
//!
//! ```text
//! aspect,width,restitution,friction,mu_s,mu_k,pga,pgv,[pfa,pfv],record,[record_file],
//! [scale],status,overturned,overturn_time,uplifted,moved,theta_max_over_theta_c,
//! mu_motion,mu_impact,mu_impact_eq5,impacts,flights,uplifts,liftoff_holds,
//! energy_gains,settles,slip_max,slip_final,stick_holds,end_time,first_impact_time,
//! [t_rest,t_slide,t_rock,t_slide_rock,t_flight],
//! [rhs_calls,steps_accepted,steps_rejected,events],[sensitive],error
//! ```
//!
//! - the case columns are the analysis's own block ([`crate::case`]): a
//!   parameter drawn per analysis has its drawn value;
//! - `friction` is `inf` or `coulomb` (then `mu_s`, `mu_k` are set, else empty);
//! - `pga` (g) and `pgv` (m/s): one is the study's intensity level, the
//!   other the scaled record's measured peak (PGV for PGA studies, PGA for
//!   PGV studies), so that fragility can be fitted against either;
//! - `pfa` (g) and `pfv` (m/s), only in a study on a floor (`[support]
//!   floor`): the peak absolute acceleration and velocity of the floor the
//!   block stands on, which is what it feels; `pga`, `pgv` stay the ground's;
//! - `record` is the ensemble index (0-based); `record_file` the spec's path;
//! - `status` is `ok` or `failed`; a failed analysis leaves the outcome
//!   columns empty and says why in `error`;
//! - `mu_impact` is the peak impulse ratio |P_t/P_n| of the impacts,
//!   `mu_impact_eq5` the peak of the paper's eq. (5) (the same ratio with
//!   |·| also when P_n ≤ 0; unbounded near some landings after flight);
//! - `sensitive` (`[output] sensitivity`): the analysis solved again under
//!   its record scaled by 1 + 1e-9 changed its outcome — overturning
//!   flipped, θmax/θc moved by more than 1e-3 or the overturning time by
//!   more than 0.01 s ([`crate::solver::sensitivity()`]); empty when the
//!   analysis or its second solve failed;
//! - absent times (no overturn, no impact) are empty;
//! - floats use Rust's shortest round-trip form, so the file holds the exact
//!   `f64` values, and the same run gives the same bytes.
//!
//! The columns are defined once, in [`Column`] and the lists [`CASE`],
//! [`FLOOR`], [`OUTCOME`], [`TIME_IN_MODE`], [`STATS`] and [`SENSITIVITY`]; a row is one type,
//! [`OutcomeRow`], written by [`Columns::write_row`] and read by
//! [`OutcomesFile`] beside it.

mod columns;
mod row;

pub use columns::{
    BodyField, CASE, Column, Columns, FLOOR, MeasureKind, OUTCOME, SENSITIVITY, STACK_EMPTY, STATS,
    TIME_IN_MODE, ValueKind,
};
pub use row::{OutcomeRow, OutcomesFile, RecordInfo};
