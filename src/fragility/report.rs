//! What a fit tells its user: the table of curves, the notes on the
//! bootstrap and on failed analyses, and the files written ([`FitReport`],
//! made by [`fit_and_write`] for the `fragility` command, a study run and
//! Python alike).

use std::path::{Path, PathBuf};

use super::bootstrap::Interval;
use super::case::{BetaModel, CaseFit, caveat_note, fit_cases};
use super::data::read_outcomes_for;
use super::files::write_outputs_with;
use super::options::FragilityOptions;
use super::status::{UnfitKind, unfit_advice, unfit_words};
use super::surface::surface_words;
use super::surface_files::{SURFACE_FILE, SurfaceRow, fit_surfaces};
use crate::error::{Error, Result};
use crate::io_util::{aligned, sig3};

/// What a fit wrote and has to say.
#[derive(Clone, Debug)]
pub struct FitReport {
    /// The table of cases (header and one row per case and limit state).
    pub table: String,
    /// One note per case whose bootstrap had replicates it could not fit.
    pub case_notes: Vec<String>,
    /// Those notes in one line, or empty.
    pub bootstrap_line: String,
    /// One line per curve that could not be fitted: which, why and what to
    /// try (empty when every curve was fitted).
    pub unfitted: Vec<String>,
    /// One line per fitted curve with a caveat (median outside the
    /// stripes, limit states out of order): which and what it means.
    pub caveats: Vec<String>,
    /// A note on failed analyses skipped, or empty.
    pub failed_note: String,
    /// `wrote …` (one line).
    pub wrote: String,
    /// Curves fitted, and curves asked for.
    pub fitted: usize,
    /// Curves asked for (cases × limit states).
    pub curves: usize,
    /// The fragility.csv written.
    pub fragility_csv: PathBuf,
    /// The fits, one per case and limit state.
    pub fits: Vec<CaseFit>,
    /// The fragility surfaces, one per case and limit state, when the fit
    /// asked for one ([`FragilityOptions::surface`]).
    pub surfaces: Option<Vec<SurfaceRow>>,
    /// One line per surface that could not be fitted or cannot be read as
    /// a surface in both IMs (`fragility_surface.csv`'s status not `ok`).
    pub surface_notes: Vec<String>,
}

impl FitReport {
    /// The notes: the curves that could not be fitted and what to try, the
    /// bootstrap's notes (every case's when `verbose`, else one line), then
    /// the note on failed analyses.
    pub fn notes(&self, verbose: bool) -> String {
        let mut text = self.unfitted.concat();
        text.push_str(&self.caveats.concat());
        text.push_str(&self.surface_notes.concat());
        if verbose {
            text.push_str(&self.case_notes.concat());
        } else {
            text.push_str(&self.bootstrap_line);
        }
        text.push_str(&self.failed_note);
        text
    }

    /// One line: curves fitted and where they went.
    pub fn summary(&self) -> String {
        let see = if self.fitted < self.curves {
            " (its status column says why a curve was not fitted)"
        } else {
            ""
        };
        let surface = match &self.surfaces {
            Some(rows) => format!(
                ", {SURFACE_FILE} ({} of {} surfaces fitted)",
                rows.iter().filter(|r| r.is_fitted()).count(),
                rows.len()
            ),
            None => String::new(),
        };
        format!(
            "fragility: {} of {} curves fitted; wrote {}{see}, fragility_curves.csv, fragility_bootstrap.csv, fragility.xml{surface}\n",
            self.fitted,
            self.curves,
            self.fragility_csv.display()
        )
    }
}

/// Fits the curves of `dir/outcomes.csv`, writes the fragility files into
/// `out` and returns what to tell the user (the `fragility` command, and a
/// study run whose spec has a `[fragility]` table).
pub fn fit_and_write(dir: &Path, out: &Path, options: &FragilityOptions) -> Result<FitReport> {
    let input = dir.join("outcomes.csv");
    let outcomes = read_outcomes_for(&input, options)?;
    if outcomes.cases.is_empty() {
        return Err(Error::Parse {
            path: input,
            line: 0,
            message: "no analyses to fit".to_string(),
        });
    }
    let fits = fit_cases(&outcomes, options)?;
    let surfaces = match options.surface_pair() {
        Some(pair) => {
            let second = FragilityOptions {
                im: Some(pair.second()),
                surface: None,
                ..options.clone()
            };
            let against_second = read_outcomes_for(&input, &second)?;
            Some(fit_surfaces(&outcomes, &against_second)?)
        }
        None => None,
    };
    let paths = write_outputs_with(out, &fits, surfaces.as_deref())?;

    let failed: usize = fits.iter().map(|f| f.n_failed).sum();
    let failed_note = if failed > 0 {
        format!("note: {failed} failed analyses skipped (error or status not ok in outcomes.csv)\n")
    } else {
        String::new()
    };
    let mut table = table(&fits, options);
    if let Some(rows) = &surfaces {
        table.push('\n');
        table.push_str(&surface_table(rows));
    }
    let surface_notes = surfaces
        .iter()
        .flatten()
        .filter(|r| r.status != "ok")
        .map(|r| {
            format!(
                "surface: {} {}: {}\n",
                r.case.id(),
                r.limit_state,
                surface_words(&r.status, &r.ims.first().short(), &r.ims.second().short())
            )
        })
        .collect();
    let surface_file = match &surfaces {
        Some(_) => format!(", {}", out.join(SURFACE_FILE).display()),
        None => String::new(),
    };
    Ok(FitReport {
        table,
        case_notes: case_notes(&fits),
        bootstrap_line: bootstrap_line(&fits, &paths.fragility, options.confidence),
        unfitted: unfitted_notes(&fits),
        caveats: (0..fits.len())
            .filter_map(|i| {
                let note = caveat_note(&fits, i)?;
                Some(format!(
                    "note: {} {}: {note}\n",
                    fits[i].key.id(),
                    fits[i].limit_state
                ))
            })
            .collect(),
        failed_note,
        wrote: format!(
            "wrote {}, {}, {}, {}{surface_file}\n",
            paths.fragility.display(),
            paths.curves.display(),
            paths.bootstrap.display(),
            paths.nrml.display()
        ),
        fitted: fits.iter().filter(|f| f.fit.is_ok()).count(),
        curves: fits.len(),
        fragility_csv: paths.fragility.clone(),
        fits,
        surfaces,
        surface_notes,
    })
}

/// The surfaces as a table for the terminal: per case and limit state,
/// the slopes with their standard errors, the median IM1 at the median
/// IM2 and the status.
fn surface_table(rows: &[SurfaceRow]) -> String {
    let Some(first) = rows.first() else {
        return String::new();
    };
    let (im1, im2) = (first.ims.first(), first.ims.second());
    let mut out = vec![vec![
        "case".to_string(),
        "limit state".to_string(),
        format!("b1 (ln {})", im1.short()),
        format!("b2 (ln {})", im2.short()),
        format!(
            "{} at median {}{}",
            im1.short(),
            im2.short(),
            im1.unit_suffix()
        ),
        "LR chi2".to_string(),
        "status".to_string(),
    ]];
    let pm = |r: &SurfaceRow, i: usize| match (r.coefficients, r.se) {
        (Some(c), Some(s)) => format!("{} ± {}", sig3(c[i]), sig3(s[i])),
        _ => "-".to_string(),
    };
    for r in rows {
        out.push(vec![
            r.case.to_string(),
            r.limit_state.clone(),
            pm(r, 1),
            pm(r, 2),
            r.median_im1_at_im2_median.map_or("-".into(), sig3),
            r.lr_chi2.map_or("-".into(), sig3),
            r.status.clone(),
        ]);
    }
    format!(
        "fragility surface P = Φ(a + b1 ln {} + b2 ln {}) ({SURFACE_FILE}):\n{}",
        im1.short(),
        im2.short(),
        aligned(&out)
    )
}

/// One line per curve that could not be fitted: its case id, limit state,
/// why in words and what to try ([`unfit_advice`]).
fn unfitted_notes(fits: &[CaseFit]) -> Vec<String> {
    fits.iter()
        .filter_map(|f| {
            let reason = f.fit.as_ref().err()?;
            Some(format!(
                "not fitted: {} {}: {}\n",
                f.key.id(),
                f.limit_state,
                unfit_advice(reason.kind(), f.im_range)
            ))
        })
        .collect()
}

/// One note per curve whose bootstrap had replicates that could not be
/// fitted.
fn case_notes(fits: &[CaseFit]) -> Vec<String> {
    fits.iter()
        .filter_map(|f| {
            let b = f.bootstrap.as_ref().filter(|b| b.unfit_total() > 0)?;
            let reasons: Vec<String> = b.unfit.iter().map(|(k, n)| format!("{k} {n}")).collect();
            Some(format!(
                "note: {} {}: {} of {} bootstrap replicates could not be fitted ({}); \
                 the intervals come from the other {}\n",
                f.key,
                f.limit_state,
                b.unfit_total(),
                b.replicates,
                reasons.join(", "),
                b.fitted
            ))
        })
        .collect()
}

/// The bootstrap notes in one line of words, by reason (`bootstrap: for 16
/// curves, up to 12 of 1000 replicates could not be fitted (…); their 90 %
/// bands come from the other replicates …`); empty if none.
fn bootstrap_line(fits: &[CaseFit], csv: &Path, confidence: f64) -> String {
    // reason -> (curves with it, most replicates of one curve, its replicates)
    let mut by_reason: std::collections::BTreeMap<UnfitKind, (usize, usize, usize)> =
        std::collections::BTreeMap::new();
    for b in fits.iter().filter_map(|f| f.bootstrap.as_ref()) {
        for (reason, &n) in &b.unfit {
            let e = by_reason.entry(*reason).or_insert((0, 0, b.replicates));
            e.0 += 1;
            if n > e.1 {
                (e.1, e.2) = (n, b.replicates);
            }
        }
    }
    if by_reason.is_empty() {
        return String::new();
    }
    // More than a tenth of a curve's replicates left out: its band is not
    // one to quote.
    let worst = by_reason
        .values()
        .map(|&(_, max, of)| max as f64 / of.max(1) as f64)
        .fold(0.0, f64::max);
    let narrow = if worst > 0.1 {
        "narrow on the steep side, too narrow to quote where more than a tenth were left out"
    } else {
        "a little narrow on the steep side"
    };
    let parts: Vec<String> = by_reason
        .iter()
        .map(|(reason, (curves, max, of))| {
            let what = if *curves == 1 { "curve" } else { "curves" };
            let why = match *reason {
                UnfitKind::Separated => {
                    " (separated: none exceeded below some stripe, all above it)".to_string()
                }
                other => format!(" ({})", unfit_words(other)),
            };
            format!("for {curves} {what}, up to {max} of {of} replicates could not be fitted{why}")
        })
        .collect();
    format!(
        "bootstrap: {}; their {} % bands come from the other replicates and are {}; \
         more records per stripe, or stripes closer together near \
         the median, make such replicates fewer (boot_unfit in {}; --verbose lists them)\n",
        parts.join("; "),
        (100.0 * confidence).round(),
        narrow,
        csv.display()
    )
}

fn table(fits: &[CaseFit], options: &FragilityOptions) -> String {
    // The band's heading only when there is a band (a bootstrap).
    let pct = match options.bootstrap {
        0 => String::new(),
        _ => format!(" [{}%]", (options.confidence * 100.0).round()),
    };
    let unit = options.im().unit_suffix();
    let header: Vec<String> = [
        "case",
        "limit state",
        "analyses",
        "exceeded",
        "stripes",
        "records",
        &format!("median{unit}{pct}"),
        &format!("beta{pct}"),
        "status",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let mut rows = vec![header];
    for f in fits {
        let band = |i: Option<Interval>| {
            i.map_or(String::new(), |i| {
                format!(" [{}, {}]", sig3(i.lo), sig3(i.hi))
            })
        };
        let boot = f.bootstrap.as_ref();
        let (median, beta, status) = match &f.fit {
            Ok(fit) => (
                format!(
                    "{}{}",
                    sig3(fit.median()),
                    band(boot.and_then(|b| b.median))
                ),
                format!("{}{}", sig3(fit.beta()), band(boot.and_then(|b| b.beta))),
                match (f.caveat, f.beta_model) {
                    (Some(c), BetaModel::Separate) => c.status().to_string(),
                    (Some(c), BetaModel::Common) => format!("{} (common β)", c.status()),
                    (None, BetaModel::Separate) => "ok".to_string(),
                    (None, BetaModel::Common) => {
                        "ok (β common to the case's limit states)".to_string()
                    }
                },
            ),
            Err(reason) => ("-".into(), "-".into(), format!("not fitted: {reason}")),
        };
        rows.push(vec![
            f.key.to_string(),
            f.limit_state.clone(),
            f.n_analyses.to_string(),
            f.n_exceeded.to_string(),
            f.n_stripes.to_string(),
            f.n_records.to_string(),
            median,
            beta,
            status,
        ]);
    }
    aligned(&rows)
}
