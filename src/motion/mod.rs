//! Ground motions: stochastic synthesis (Clough–Penzien spectrum, time
//! envelope, zero-phase high-pass) and recorded motions (PEER `.AT2`, CSV).
//!
//! Data flow of a synthetic record, one file per concept:
//!
//! ```text
//! psd (eq. 6) ─▶ synth: random phases, inverse FFT ─▶ envelope (eq. 7)
//!   ─▶ baseline: zero-phase high-pass, drift-free linear-rule integration
//!   ─▶ scale to the target PGA ─▶ Record (acc, vel, disp)
//! ```
//!
//! A block on a floor of a building feels the floor's motion:
//! [`floor_record`] filters a record through the building's modes (linear
//! building, exact recurrence for piecewise-linear ground acceleration). A
//! block facing some direction feels the two horizontal components of a
//! recorded [`Pair`] projected onto its rocking plane ([`Pair::rotated`]);
//! [`rotd`] is the pair's orientation-independent RotD50 intensity.
//!
//! Units are SI throughout; intensities in g are converted once, at the
//! edge, with `g` = [`G_STANDARD`] unless a setting overrides it.

mod baseline;
mod envelope;
mod floor;
mod io;
mod orientation;
mod psd;
mod record;
mod synth;
pub mod units;

pub use baseline::Baseline;
pub use envelope::Envelope;
pub use floor::{Floor, Mode, Oscillator, OscillatorState, floor_into, floor_record};
pub use io::{
    At2, DT_REL_TOL, MAX_RECORD_BYTES, read_at2, read_csv, read_record, read_record_bytes,
    write_csv, write_csv_to,
};
pub use orientation::{
    MeasuredPair, ORIENTATION_EXPECTED, Pair, ROTD_ANGLES, is_orientation, rotated_peaks, rotd,
    rotd_series,
};
pub use psd::CloughPenzien;
pub use record::{G_STANDARD, MAX_SAMPLES, Record, integrate_linear};
pub use synth::{
    Natural, PRESETS, SynthesisSettings, Synthesizer, preset, record_seed, second_component_seed,
    synthesize,
};
