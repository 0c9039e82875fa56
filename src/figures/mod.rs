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
//! [`study_figures`] (the CLI's `rockfrag figures DIR`). Each is a plain data
//! struct built once from the folder's [`StudyData`] ([`SpectrumFigure`],
//! [`HistoryFigure`] or [`StackHistoryFigure`], [`FragilityFigure`], [`FrictionDemandFigure`],
//! [`RestitutionFigure`]) and drawn by [`Figure`]; the stage files are read
//! through their row types ([`crate::outcomes_csv::OutcomesFile`],
//! [`crate::fragility::read_curves_csv`]), and the shared titles, legends
//! and markers come from one layout module. Published values to compare
//! with are added by a layer above (the paper's, for its own study).
//!
//! ```no_run
//! use rockfrag::motion::Record;
//! use std::path::Path;
//! let record = Record::from_acc("pulse", 0.01, vec![0.0, 1.0, 0.0, -1.0, 0.0]).unwrap();
//! rockfrag::figures::plot_record(&record, Path::new("pulse.svg")).unwrap();
//! ```

mod batch;
mod compare;
mod data;
mod figure;
mod font;
mod fragility;
mod friction;
mod history;
pub(crate) mod layout;
mod motion;
mod raster;
mod restitution;
mod risk;
mod spectrum;
mod stack_history;
pub mod style;
mod surface;

pub use batch::{FigureOptions, FiguresReport, StudyFigures, study_figures, study_of_folder};
pub use compare::{CompareFigure, CompareSeries};
pub use data::{CurvePoint, LognormalCurve, ObservedStripe, PlotRow, StudyData};
pub use figure::{DrawResult, Figure, Format, save};
pub use fragility::{FragilityFigure, ShortCurves};
pub use friction::FrictionDemandFigure;
pub use history::{
    HistoryCase, HistoryChoice, HistoryFigure, MIN_MODE_S, ModeInterval, bounce_colour, mode_colour,
};
pub use motion::plot_record;
pub use restitution::RestitutionFigure;
pub(crate) use restitution::trend_text;
pub use risk::{RiskCase, RiskFigure, RiskSeries};
pub use spectrum::SpectrumFigure;
pub use stack_history::{BodySeries, StackHistoryFigure};
pub use style::Style;
pub use surface::SurfaceFigure;
