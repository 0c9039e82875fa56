//! # rockfrag
//!
//! Monte Carlo fragility analysis of free-standing rigid blocks under
//! earthquakes.
//!
//! Data flows one way:
//!
//! ```text
//! spec ─▶ motion ─▶ solver ─▶ outcome ─▶ study ─▶ fragility ─▶ risk ─▶ figures
//! ```
//!
//! and imports go one way too: each module uses only modules declared above
//! it in this file (`tests/architecture.rs` checks it), so none imports one
//! that imports it back. A stage's vocabulary comes before the stages that
//! use it: the [`outcome`] type before the [`solver`] that fills it, the
//! [`outcomes_csv`] table before the [`fragility`] fit that reads it, and
//! every stage's settings before the [`spec`] that reads them from TOML and
//! the [`study`] that runs them.
//!
//! - [`detmath`]: the transcendental functions (sin, exp, ln, Φ, …), the
//!   same bits on every platform (no call to the platform's math library);
//! - [`threads`]: how many worker threads a run uses (capped per core), and
//!   their pool;
//! - [`spec`]: study specs (TOML) read once into a validated [`spec::Study`];
//! - [`motion`]: ground-motion records, synthetic (Clough–Penzien spectrum,
//!   modulated, high-passed) or recorded (PEER `.AT2`, CSV);
//! - [`im`]: intensity measures, one type for every stage (names, units,
//!   columns, OpenQuake's IMTs, pelicun's demands, how each is measured);
//! - [`uncertainty`]: distributions of uncertain block parameters and the
//!   per-analysis draws from them;
//! - [`solver`]: the event-driven block solver (rest, slide, rock, slide-rock,
//!   free flight; impacts with restitution and Coulomb friction);
//! - [`outcome`]: what one analysis produces;
//! - [`case`]: one block configuration (H/B, 2B, e, friction), each
//!   parameter fixed or drawn per analysis;
//! - [`outcomes_csv`]: the `outcomes.csv` table of a study's analyses, its
//!   columns defined once for the writer and every reader;
//! - [`study`]: running a study (parallel, resumable, shardable) into
//!   `outcomes.csv`, `summary.md` and `manifest.json`;
//! - [`fragility`]: lognormal overturning fragility curves (probit MLE, bootstrap);
//! - [`risk`]: the annual rate of each limit state at a site, the fragility
//!   integrated over a hazard curve (OpenQuake's or a plain table);
//! - [`export`]: the fitted curves as an OpenQuake job and a pelicun
//!   damage database that compute rockfrag's numbers;
//! - [`figures`]: publication figures drawn with an embedded font;
//! - [`paper`]: the seed paper as a layer on top (its Tables 1–3 beside a
//!   study's results, its figures, `rockfrag paper`);
//! - [`pipeline`]: one run sequence (analyses, summary, fit, figures) for
//!   the command line and Python;
//! - [`infer`]: the intensity a site felt, inferred from the objects that
//!   overturned there (`rockfrag infer`).
//!
//! ## Governing equations
//!
//! Symmetric block, width 2B, height 2H, R = √(B²+H²), θc = atan(B/H),
//! I_O = 4mR²/3 about a corner, p² = 3g/(4R). Rocking about a corner
//! (S = sign θ), paper eq. (1):
//!
//! ```text
//! I_O θ̈ = m R cos(θc − |θ|) ẍg − S m R sin(θc − |θ|) (g + ÿg)
//! ```
//!
//! Impacts: impulse–momentum at the striking corner with Newton restitution e
//! (or an energy-consistent law); at a rock impact ω₂/ω₁ = 1 − 1.5(1+e)sin²θc.
//!
//! ## References
//! - Shenton, H. W. and Jones, N. P. (1991). Base excitation of rigid bodies.
//!   I: Formulation. *J. Eng. Mech.* 117(10), 2286–2306.
//! - Shenton, H. W. and Jones, N. P. Effect of friction and restitution on
//!   rocking response (the seed paper of this crate).
//! - Housner, G. W. (1963). The behavior of inverted pendulum structures during
//!   earthquakes. *Bull. Seismol. Soc. Am.* 53(2), 403–417.
//! - Clough, R. W. and Penzien, J. (1975). *Dynamics of Structures*.
//! - Dormand, J. R. and Prince, P. J. (1980). A family of embedded Runge–Kutta
//!   formulae. *J. Comput. Appl. Math.* 6(1), 19–26.
//! - Jorba, À. and Zou, M. (2005). A software package for the numerical
//!   integration of ODEs by means of high-order Taylor methods. *Experimental
//!   Mathematics* 14(1), 99–117 (the Taylor integrator of rock).
//! - Baker, J. W. (2015). Efficient analytical fragility function fitting
//!   using dynamic structural analysis. *Earthquake Spectra* 31(1), 579–599.

// Each module uses only the modules declared above it (tests/architecture.rs).
pub mod detmath;
pub mod error;
pub mod io_util;
pub mod threads;
pub mod stats;
pub mod uncertainty;
pub mod motion;
pub mod im;
pub mod outcome;
pub mod solver;
pub mod case;
pub mod table;
pub mod outcomes_csv;
pub mod fragility;
pub mod spec;
pub mod study;
pub mod risk;
pub mod export;
pub mod figures;
pub mod paper;
pub mod pipeline;
pub mod infer;

pub use error::{Error, Result};
