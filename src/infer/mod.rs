//! From what fell to how hard it shook: the intensity a site felt, inferred
//! from the objects that overturned there (`rockfrag infer`).
//!
//! ```text
//! survey.csv (kinds: 2B, H/B, count, overturned[, slid])   spec.toml (records, levels,
//!      │                                                   solver, [uncertainty], [infer])
//!      └──────────────▶ simulate: every kind × record × level × draw ─▶ simulations.csv
//!                        ─▶ likelihood: joint (one motion for all) and naive (one per object)
//!                        ─▶ posterior (prior: log-uniform or a hazard curve), Monte Carlo
//!                           error by bootstrap ─▶ posterior.csv, inference.json,
//!                           summary.md ## Inference, figures/inference.svg
//! ```
//!
//! After an earthquake, a cemetery's tombstones of a few standard sizes
//! (some toppled, some standing), a museum's objects or a hillside's
//! precariously balanced rocks record how hard the ground shook. For every
//! record r of the study at intensity x, each kind j of object is simulated
//! D times, each time with its uncertain properties drawn; the objects of a
//! site all felt one motion, so the likelihood of the survey is the mean
//! over records of the product over kinds ([`likelihood`]):
//!
//! ```text
//! L(x) = (1/R) Σ_r Π_j P(k_j of n_j overturned | x, r)
//! ```
//!
//! Multiplying each kind's fitted fragility curve instead treats every
//! object as if it had its own earthquake; it is computed too (`naive`),
//! and is overconfident. The posterior is prior × L on the grid of the
//! study's levels ([`posterior`]); its Monte Carlo error comes from a
//! bootstrap over records and draws.
//!
//! **Determinism.** Every analysis is a pure function of (kind, record,
//! level, draw), the bootstrap's replicates of (seed, replicate), and sums
//! run in a fixed order: the outputs are byte-identical on any thread
//! count, after an interruption and on a rerun. The simulations are kept in
//! `simulations.csv` with a checkpoint after each level
//! (`simulations.json`, keyed by a hash of everything they depend on): a
//! killed run resumes, and a rerun with other counts or another prior
//! reuses them.
//!
//! ## References
//! - Housner, G. W. (1963). The behavior of inverted pendulum structures
//!   during earthquakes. *Bull. Seismol. Soc. Am.* 53(2), 403–417 (the
//!   inverse problem: intensities from overturned objects).
//! - Purvance, M. D., Anooshehpoor, A. and Brune, J. N. (2008). Freestanding
//!   block overturning fragilities: numerical simulation and experimental
//!   validation. *Earthquake Eng. Struct. Dyn.* 37, 791–808 (precariously
//!   balanced rocks).

pub mod calibrate;
pub mod figure;
mod inference;
pub mod likelihood;
pub mod output;
pub mod pair;
mod pair_figure;
pub mod pair_output;
pub mod posterior;
mod run;
pub mod simulate;
pub mod survey;

pub use inference::{Inference, PriorChoice, infer};
pub use likelihood::{Grid, KindCurve};
pub use pair::PairPosterior;
pub use posterior::{Bounds, McBand, McError, OPEN_EDGE, Posterior, Prior, Summary};
pub use run::{InferOptions, InferReport, default_out, run, settings};
pub use simulate::{Cell, Im, Table, inferable};
pub use survey::{Kind, KindModel, SlideRule, Survey};
