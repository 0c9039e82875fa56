//! Publication figures, drawn with an embedded font so that nothing depends on
//! a system library or a system font.
//!
//! A figure implements [`Figure`] once, for any plotters backend, and
//! [`save`] writes it in the format named by the file's extension: `.svg`
//! (also the default when there is no extension) or `.png`. The file is
//! written to a temporary name in the same directory and then renamed, so a
//! reader never sees half a figure. Sizes, fonts and colours come from
//! [`style`].
//!
//! The study figures of a folder written by the study runner
//! (`outcomes.csv`, optionally `fragility_curves.csv`) are drawn by
//! [`study_figures`] (the CLI's `rockfrag figures DIR`): see [`batch`] for
//! the list. Each is a plain data struct built once ([`spectrum`],
//! [`history`], [`fragility`], [`friction`], [`restitution`]) and drawn by
//! [`Figure`]; [`data`] reads the CSV files by header name, [`crate::study::paper`]
//! holds the seed paper's Tables 1–3 and [`layout`] the shared titles, legends and
//! markers.
//!
//! ```no_run
//! use rockfrag::motion::Record;
//! use std::path::Path;
//! let record = Record::from_acc("pulse", 0.01, vec![0.0, 1.0, 0.0, -1.0, 0.0]).unwrap();
//! rockfrag::figures::plot_record(&record, Path::new("pulse.svg")).unwrap();
//! ```

pub mod batch;
pub mod data;
mod figure;
pub mod font;
pub mod fragility;
pub mod friction;
pub mod history;
pub mod layout;
pub mod motion;
pub mod restitution;
pub mod spectrum;
pub mod style;
pub mod work_precision;

pub use batch::{FigureOptions, FiguresReport, study_figures};
pub use figure::{DrawResult, Figure, Format, save};
pub use motion::plot_record;
pub use style::Style;
