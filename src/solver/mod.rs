//! The event-driven block solver.
//!
//! One analysis is one [`Block`] with its restitution and friction
//! ([`Analysis`]) under one [`Record`](crate::motion::Record), solved by
//! [`simulate`] into an [`Outcome`](crate::outcome::Outcome).
//!
//! The files, one concept each (their own docs derive the equations and
//! the event rules; `cargo doc --document-private-items` shows them):
//!
//! - `block.rs`: geometry and derived constants ([`Block`]);
//! - `settings.rs`: what an analysis is and how it is solved ([`Analysis`],
//!   [`SolverSettings`]);
//! - `physics.rs`: the equations of each mode as plain functions;
//! - `impact.rs`: corner impacts, Newton and energy-consistent laws
//!   ([`corner_impact`], [`rock_impact_ratio`], [`rock_impact_mu`], and
//!   [`eq5_mu`], the paper's eq. (5) reconstructed);
//! - `taylor.rs`: Taylor-series steps of the rock equation (the default);
//! - `dopri.rs`: the Dormand–Prince 5(4) stepper with dense output (slide-rock,
//!   and rock on request);
//! - `roots.rs`, `scan.rs`: root finding and sign-change scans for events;
//! - `driver/`: the event loop, one file per mode (rest, slide, rock,
//!   flight), events and impacts, the cascade rule, bookkeeping;
//! - `history.rs`: the optional full time history ([`History`]);
//! - `sensitivity.rs`: the analysis solved again under a record scaled by
//!   1 + 1e-9, and whether its outcome changed ([`sensitivity()`]).

mod block;
mod dopri;
mod driver;
mod history;
pub(crate) mod impact;
mod physics;
mod roots;
mod scan;
pub mod sensitivity;
mod settings;
pub mod stack;
mod taylor;

pub use block::{ASPECT_RANGE, Block, WIDTH_RANGE, aspect_expected, width_expected};
pub use driver::simulate;
pub use history::{History, HistoryRow};
pub use impact::{
    ImpactLaw, ImpactResult, TwoCornerImpact, Velocity, corner_impact, eq5_mu, rock_impact_mu,
    rock_impact_ratio, two_corner_impact,
};
pub use sensitivity::{Sensitivity, sensitivity};
pub use settings::{Analysis, Friction, Initial, Integrator, Model, RockImpact, SolverSettings};
