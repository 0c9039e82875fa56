//! The event-driven block solver.
//!
//! One analysis is one [`Block`] with its restitution and friction
//! ([`Analysis`]) under one [`Record`](crate::motion::Record), solved by
//! [`simulate`] into an [`Outcome`](crate::outcome::Outcome).
//!
//! - [`block`]: geometry and derived constants;
//! - [`physics`]: the equations of each mode as plain functions;
//! - [`impact`]: corner impacts (Newton and energy-consistent laws);
//! - [`taylor`]: Taylor-series steps of the rock equation (the default);
//! - [`dopri`]: the Dormand–Prince 5(4) stepper with dense output (slide-rock,
//!   and rock on request);
//! - [`driver`]: the event loop (stops at samples, locates events, applies resets);
//! - [`history`]: the optional full time history.

pub mod block;
pub mod dopri;
pub mod driver;
pub mod history;
pub mod impact;
pub mod physics;
pub mod roots;
pub mod scan;
pub mod settings;
pub mod taylor;

pub use block::Block;
pub use driver::simulate;
pub use history::{History, HistoryRow};
pub use impact::ImpactLaw;
pub use settings::{Analysis, Friction, Initial, Integrator, Model, SolverSettings};
