//! The seed paper as a layer on top: Shenton and Jones, "Effect of friction
//! and restitution on rocking response" — its Tables 1–3, its readings of
//! the ground-motion model, its statistics and its figures.
//!
//! Everything that exists only because of the paper lives here, above
//! [`crate::study`], [`crate::fragility`] and [`crate::figures`], and uses
//! them; the generic modules never name the paper. A study that is the
//! paper's set-up ([`is_papers`]) gets the generic outputs plus this layer:
//!
//! - `summary.md`: a section with the study's results in the layout of the
//!   paper's Tables 1–3, the published values beside ours in every cell,
//!   Fisher's test per cell and the trend of the paper's counts over e;
//! - figures: the paper's values drawn beside ours in the friction-demand
//!   and restitution figures, the paper's illustrative response history
//!   (H/B 2, e 0.6, μs 0.6, μk 0.4 at 0.9 g), and `e_trend`, the trend of
//!   overturning with e under our physics, under the paper's program rule
//!   and in the paper's counts;
//! - `rockfrag paper`: the study over K ensembles under each reading of the
//!   paper's section 4, scored against Tables 1–3 ([`check()`]).

mod check;
pub(crate) mod figures;
mod summary;
mod tables;

pub use check::{
    CheckOptions, ReadingResult, Scores, check, markdown as check_markdown, paper_totals, score,
    write_report,
};
pub use figures::{history_case, most_modes};
pub use tables::{Reading, readings};

use std::path::Path;

use crate::case::Param;
use crate::error::Result;
use crate::figures::{FigureOptions, FiguresReport};
use crate::motion::G_STANDARD;
use crate::solver::Friction;
use crate::spec::{Intensity, Motions, Study};
use crate::study::Tally;

/// Whether `study` is the paper's set-up, cell for cell comparable with
/// Tables 1–3: synthetic records under one of the readings of section 4
/// ([`readings`]), 25 per level, standard gravity, PGA levels, 2B = 0.5 m,
/// infinite friction among its models, and H/B among 2, 4, 6 (its grids may
/// be a subset of the paper's).
pub fn is_papers(study: &Study) -> bool {
    let synthetic_default = match &study.motions {
        Motions::Synthetic {
            settings,
            records,
            pairs: None,
            ..
        } => readings().iter().any(|r| r.settings == *settings) && *records == tables::RECORDS,
        Motions::Synthetic { .. } => false,
        Motions::Files(_) | Motions::Pairs { .. } => false,
    };
    synthetic_default
        && study.g == G_STANDARD
        && matches!(study.intensity, Intensity::Pga(_))
        && study.widths == [Param::Fixed(tables::WIDTH)]
        && study.frictions.contains(&Param::Fixed(Friction::Infinite))
        && study
            .aspects
            .iter()
            .all(|a| a.fixed().is_some_and(|a| [2.0, 4.0, 6.0].contains(&a)))
}

/// The paper's section of `summary.md` for `study` (its Tables 1–3 beside
/// ours), `None` for a study that is not the paper's.
pub(crate) fn summary_section(study: &Study, tally: &Tally) -> Option<String> {
    is_papers(study).then(|| summary::tables_section(tally, study))
}

/// Draws the trend of overturning with e of `rockfrag paper`'s check
/// ([`check()`]) to `path` (SVG or PNG by its extension): the rad/s grid's
/// ensembles under the physics and under the paper's program rule, pooled,
/// beside the paper's counts. Nothing is drawn (`Ok(false)`) when the
/// check lacks either.
pub fn write_e_trend(results: &[ReadingResult], path: &Path) -> Result<bool> {
    match figures::ETrendFigure::from_check(results) {
        Some(f) => crate::figures::save(&f, path).map(|()| true),
        None => Ok(false),
    }
}

/// The figures of `study`'s folder `dir`, drawn into `out`: the generic
/// figures ([`crate::figures::study_figures`]), and for the paper's study
/// this layer's ([`figures::draw`]).
pub(crate) fn study_figures(
    study: &Study,
    dir: &Path,
    out: &Path,
    options: &FigureOptions,
) -> Result<FiguresReport> {
    if is_papers(study) {
        figures::draw(dir, out, options, study)
    } else {
        crate::figures::study_figures(dir, out, options)
    }
}
