//! The fitted curves in the formats of the tools that use them downstream,
//! written so that those tools compute rockfrag's numbers:
//!
//! - [`openquake`]: a runnable OpenQuake `classical_damage` job folder
//!   (`job.ini`, `exposure.xml`, `fragility.xml`, a one-site `hazard.csv`
//!   resampled densely enough for OpenQuake's own quadrature);
//! - [`pelicun`]: a pelicun (FEMA P-58) damage database (`<name>.csv` and
//!   `<name>.json`).
//!
//! Every export names a case by its one id ([`crate::case::Case::id`]): the
//! `case_id` column of `fragility.csv` and `risk.csv`, the NRML function id,
//! the exposure taxonomy and the pelicun component id are the same string,
//! so the tools' outputs join with rockfrag's.

pub mod openquake;
pub mod pelicun;

pub use openquake::{OpenQuakeJob, export_openquake};
pub use pelicun::{PelicunDatabase, export_pelicun};
