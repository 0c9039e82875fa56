//! Study specs: the TOML file a user writes once and runs anywhere.
//!
//! This is the only module that knows about TOML. A spec is read in two
//! stages, like ripgrep's `LowArgs` → `HiArgs`: serde reads the text into the
//! raw [`SpecFile`] (every field has a default, unknown fields are errors),
//! then [`SpecFile::validate`] checks every value once and builds the
//! validated [`Study`], which nothing downstream re-checks. Every error names
//! the file, the line, the field path (e.g. `grid.aspect[2]`) and the accepted
//! range.
//!
//! ```toml
//! name = "example"            # default: the file's stem
//! seed = 7                    # ensemble seed (default: 1)
//! records = 25                # synthetic records per intensity level (default: 25)
//! # record_files = ["motions/elcentro.AT2"]   # or recorded motions instead,
//! # record_files = [["a-H1.AT2", "a-H2.AT2"]]   # or pairs of components
//!
//! [motion]                    # SynthesisSettings (default: the paper's firm soil)
//! duration = 30.0
//!
//! [grid]
//! width = [0.5]               # base width 2B, m
//! aspect = [2, 4, 6]          # H/B
//! restitution = [0.0, 0.6]    # e
//! friction = ["inf", { mu_s = 0.7, mu_k = 0.6 }]
//! pga = [0.3, 0.6]            # g; or pgv = [0.2, 0.4] in m/s
//!
//! # [[grid.stack]]            # or stacks of 2–3 blocks, bottom first (spec::stack)
//! # blocks = [{ width = 0.6, height = 1.0 }, { width = 0.3, height = 1.2 }]
//! # interfaces = [{ restitution = 0.3 }, { restitution = 0.3, mu_s = 0.5, mu_k = 0.4 }]
//!
//! # [uncertainty]             # or drawn per analysis, instead of a grid list:
//! # restitution = { dist = "uniform", min = 0.0, max = 0.9 }
//!
//! [solver]                    # SolverSettings (default: nonlinear, rtol 1e-8, …)
//! [output]
//! summary = true

mod adaptive;
mod draw_checks;
mod infer;
mod locate;
mod raw;
mod stack;
mod stack_draws;
mod study;
mod uncertainty;
mod validate;

pub use infer::InferSettings;
pub use raw::{
    FrictionEntry, GridFile, LevelRange, Levels, MotionFile, OutputFile, RecordEntry, SpecFile,
    StackBlockEntry, StackDrawEntry, StackEntry, StackInterfaceEntry, UncertaintyFile,
};
pub use stack::{BodyForm, StudyStack};
pub use stack_draws::StackDraws;
pub use study::{
    Adaptive, Intensity, MAX_SPEC_BYTES, Motions, Orientation, RecordFile, SHENTON_JONES_ORIGIN,
    SHENTON_JONES_TOML, Study, Uncertainty, analysis_values, fnv1a64, friction_label,
};
pub use validate::{MAX_PGA_G, MAX_PGV};
