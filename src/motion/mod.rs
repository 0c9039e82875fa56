//! Ground motions: stochastic synthesis (Clough–Penzien spectrum, time
//! envelope, zero-phase high-pass) and recorded motions (PEER `.AT2`, CSV).

mod record;

pub use record::{G_STANDARD, Record, integrate_linear};
