//! What an inference writes: `posterior.csv`, `inference.json`, the
//! `## Inference` section of `summary.md` and `figures/inference.svg`, each
//! atomically and with nothing of the run's own (times, threads), so that a
//! rerun reproduces them byte for byte.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::inference::{Inference, PriorChoice};
use super::pair::PairPosterior;
use super::posterior::{Bounds, McError, Posterior, Summary};
use super::survey::{KindModel, SlideRule, Survey};
use crate::detmath as dm;
use crate::error::{Error, Result};
use crate::fragility::FitStatus;
use crate::io_util::{number, sig3, write_atomic};
use crate::spec::Study;

/// The posterior's file.
pub const POSTERIOR: &str = "posterior.csv";
/// The summary's file.
pub const INFERENCE: &str = "inference.json";
/// The markdown summary (its `## Inference` section).
pub const SUMMARY: &str = "summary.md";
/// The figure, under `figures/`.
pub const FIGURE: &str = "inference.svg";

/// Header of `posterior.csv`, one row per grid point, IM ascending: `im`
/// (unit of `inference.json`'s `im_unit`), `prior` (density per unit IM),
/// `likelihood` (the joint method's L), `posterior` (density per unit IM),
/// `cdf`, and the naive method's `naive_likelihood`, `naive_posterior`,
/// `naive_cdf` (empty when its likelihood vanishes on the grid).
pub const POSTERIOR_HEADER: &str =
    "im,prior,likelihood,posterior,cdf,naive_likelihood,naive_posterior,naive_cdf";

/// What the writers need besides the inference.
pub struct Context<'a> {
    /// The study.
    pub study: &'a Study,
    /// The survey.
    pub survey: &'a Survey,
    /// How its kinds were simulated.
    pub models: &'a [KindModel],
    /// The spec file as named.
    pub spec_file: &'a Path,
    /// The prior asked for.
    pub prior: &'a PriorChoice,
    /// The sliding limit state, if slides were counted.
    pub slide: Option<&'a SlideRule>,
    /// Bootstrap replicates asked for.
    pub bootstrap: usize,
    /// Analyses solved.
    pub analyses: u64,
    /// Records per level.
    pub records: usize,
    /// Levels.
    pub levels: usize,
}

/// Writes every output into `dir` (with `pair`, the joint posterior over
/// two IMs too, [`super::pair_output`]; without, a former run's joint
/// posterior is removed); returns the paths written.
pub fn write_all(
    dir: &Path,
    inference: &Inference,
    context: &Context,
    figure: Option<crate::figures::Format>,
    pair: Option<&PairPosterior>,
) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    let path = dir.join(POSTERIOR);
    write_posterior(&path, inference)?;
    written.push(path);
    let path = dir.join(INFERENCE);
    let mut summary = summary_json(inference, context);
    summary.two_im = pair.map(|p| super::pair_output::json(inference, p));
    let json = serde_json::to_string_pretty(&summary).expect("the summary serialises");
    write_atomic(&path, |w| writeln!(w, "{json}")).map_err(Error::io(&path))?;
    written.push(path);
    let path = dir.join(SUMMARY);
    let mut text = section(inference, context);
    if let Some(p) = pair {
        text.push_str(&super::pair_output::section(inference, p));
    }
    update_section(&path, &text)?;
    written.push(path);
    if let Some(format) = figure {
        let path = dir
            .join("figures")
            .join(FIGURE)
            .with_extension(format.extension());
        let fig = super::figure::InferenceFigure::new(inference, context.survey);
        crate::figures::save(&fig, &path)?;
        written.push(path);
    }
    match pair {
        Some(p) => written.extend(super::pair_output::write_all(dir, inference, p, figure)?),
        None => super::pair_output::remove_stale(dir)?,
    }
    Ok(written)
}

/// Writes `posterior.csv` (header [`POSTERIOR_HEADER`]).
pub fn write_posterior(path: &Path, inference: &Inference) -> Result<()> {
    let naive = inference.naive.as_ref();
    write_atomic(path, |w| {
        writeln!(w, "{POSTERIOR_HEADER}")?;
        for i in 0..inference.grid.len() {
            let opt = |v: Option<f64>| v.map_or(String::new(), number);
            writeln!(
                w,
                "{},{},{},{},{},{},{},{}",
                number(inference.grid.x[i]),
                number(inference.prior[i]),
                number(dm::exp(inference.joint_ln_l[i])),
                number(inference.joint.density[i]),
                number(inference.joint.cdf[i]),
                number(dm::exp(inference.naive_ln_l[i])),
                opt(naive.map(|p| p.density[i])),
                opt(naive.map(|p| p.cdf[i])),
            )?;
        }
        Ok(())
    })
    .map_err(Error::io(path))
}

/// Reads `posterior.csv` back: the columns by name, in the file's order
/// (empty fields are NaN). For tests and Python.
///
/// Errors: [`Error::Parse`] naming the line of a malformed row.
pub fn read_posterior(path: &Path) -> Result<Vec<(String, Vec<f64>)>> {
    let text = std::fs::read_to_string(path).map_err(Error::io(path))?;
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap_or_default()
        .split(',')
        .map(str::to_string)
        .collect();
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); header.len()];
    for (i, line) in lines.enumerate() {
        let fields: Vec<&str> = line.split(',').collect();
        if fields.len() != header.len() {
            return Err(Error::Parse {
                path: path.to_path_buf(),
                line: i + 2,
                message: format!("expected {} fields", header.len()),
            });
        }
        for (c, f) in cols.iter_mut().zip(fields) {
            c.push(if f.is_empty() {
                f64::NAN
            } else {
                f.parse().map_err(|_| Error::Parse {
                    path: path.to_path_buf(),
                    line: i + 2,
                    message: format!("\"{f}\" is not a number"),
                })?
            });
        }
    }
    Ok(header.into_iter().zip(cols).collect())
}

/// One method's results in `inference.json`.
#[derive(Serialize)]
struct MethodJson {
    median: f64,
    p05: f64,
    p95: f64,
    mode: f64,
    mc_error: Option<McError>,
    bounds: Bounds,
}

fn method(p: &Posterior, mc: Option<McError>) -> MethodJson {
    let s = p.summary;
    MethodJson {
        median: s.median,
        p05: s.p05,
        p95: s.p95,
        mode: s.mode,
        mc_error: mc,
        bounds: p.bounds,
    }
}

/// The likelihood at grid point i relative to its peak.
fn relative_likelihood(ln_l: &[f64], i: usize) -> f64 {
    let top = ln_l
        .iter()
        .copied()
        .filter(|l| l.is_finite())
        .fold(f64::NEG_INFINITY, f64::max);
    dm::exp(ln_l[i] - top)
}

/// What to report, in words (after "to report: "): the joint result, or
/// the one bound the data give and why (console, summary and
/// `inference.json` alike).
pub fn report_text(inf: &Inference) -> String {
    let (unit, name) = (inf.im.unit(), inf.im.name().to_uppercase());
    let s = inf.joint.summary;
    let n = inf.grid.len();
    let (x0, x1) = (inf.grid.x[0], inf.grid.x[n - 1]);
    let pct = |i: usize| format!("{:.0} %", 100.0 * relative_likelihood(&inf.joint_ln_l, i));
    match inf.joint.bounds {
        Bounds::Both => "the joint result (every object felt the same motion; its 90 % interval \
                         is calibrated, docs/infer.md); the naive one treats each object as if it \
                         had its own earthquake, is overconfident, and is shown for comparison only"
            .to_string(),
        Bounds::LowerOnly => format!(
            "{name} ≥ {} {unit} (the joint 5 % bound): the data bound the {name} from below \
             only. The likelihood at the highest level, {} {unit}, is still {} of its \
             peak, so the median and the 95 % bound are set by where the levels end and by the \
             prior, not by the data; add levels above {} {unit} to bound it from above",
            sig3(s.p05),
            sig3(x1),
            pct(n - 1),
            sig3(x1)
        ),
        Bounds::UpperOnly => format!(
            "{name} ≤ {} {unit} (the joint 95 % bound): the data bound the {name} from above \
             only. The likelihood at the lowest level, {} {unit}, is still {} of its \
             peak, so the median and the 5 % bound are set by where the levels end and by the \
             prior, not by the data; add levels below {} {unit} to bound it from below",
            sig3(s.p95),
            sig3(x0),
            pct(0),
            sig3(x0)
        ),
        Bounds::Neither => format!(
            "no bound: the data bound the {name} on neither side within the levels (the \
             likelihood at {} {unit} and at {} {unit} is still {} and {} of its peak), so the \
             interval is mostly the prior's; add kinds that overturn within the levels, or \
             widen them",
            sig3(x0),
            sig3(x1),
            pct(0),
            pct(n - 1)
        ),
    }
}

/// One kind in `inference.json`.
#[derive(Serialize)]
struct KindJson {
    name: String,
    width: f64,
    aspect: f64,
    restitution: String,
    friction: String,
    count: u64,
    overturned: u64,
    slid: Option<u64>,
    draws: usize,
    median: Option<f64>,
    beta: Option<f64>,
    fit: FitStatus,
}

/// `inference.json`.
#[derive(Serialize)]
struct InferenceJson {
    study: String,
    spec: String,
    observations: String,
    im: String,
    im_unit: &'static str,
    prior: String,
    grid_points: usize,
    grid_min: f64,
    grid_max: f64,
    grid_is_levels: bool,
    records: usize,
    effective_records: f64,
    levels: usize,
    analyses: u64,
    bootstrap: usize,
    slide_limit_state: Option<String>,
    report: String,
    joint: MethodJson,
    naive: Option<MethodJson>,
    kinds: Vec<KindJson>,
    #[serde(skip_serializing_if = "Option::is_none")]
    two_im: Option<super::pair_output::PairJson>,
}

fn summary_json(inf: &Inference, c: &Context) -> InferenceJson {
    let kinds = c
        .survey
        .kinds
        .iter()
        .zip(c.models)
        .zip(&inf.curves)
        .map(|((k, m), curve)| KindJson {
            name: k.name.clone(),
            width: k.width,
            aspect: k.aspect,
            restitution: m.case.restitution.text(),
            friction: crate::spec::friction_label(m.case.friction),
            count: k.count,
            overturned: k.overturned,
            slid: k.slid,
            draws: m.draws,
            median: curve.fit.as_ref().ok().map(|f| f.median()),
            beta: curve.fit.as_ref().ok().map(|f| f.beta()),
            fit: FitStatus::of(&curve.fit, None),
        })
        .collect();
    InferenceJson {
        study: c.study.name.clone(),
        spec: c.spec_file.display().to_string(),
        observations: c.survey.path.display().to_string(),
        im: inf.im.name(),
        im_unit: inf.im.unit(),
        prior: c.prior.to_string(),
        grid_points: inf.grid.len(),
        grid_min: inf.grid.x[0],
        grid_max: inf.grid.x[inf.grid.len() - 1],
        grid_is_levels: inf.grid.exact,
        records: c.records,
        effective_records: inf.effective_records,
        levels: c.levels,
        analyses: c.analyses,
        bootstrap: c.bootstrap,
        slide_limit_state: c.slide.map(|s| s.name.clone()),
        report: report_text(inf),
        joint: method(&inf.joint, inf.joint_mc),
        naive: inf.naive.as_ref().map(|p| method(p, inf.naive_mc)),
        kinds,
        two_im: None,
    }
}

fn bounds(s: &Summary, unit: &str) -> [String; 3] {
    [
        format!("{} {unit}", sig3(s.median)),
        format!("{}–{} {unit}", sig3(s.p05), sig3(s.p95)),
        format!("{} {unit}", sig3(s.mode)),
    ]
}

fn mc_text(mc: Option<McError>) -> String {
    mc.map_or("—".into(), |m| {
        format!("{} / {} / {}", sig3(m.p05), sig3(m.median), sig3(m.p95))
    })
}

/// The `## Inference` section of `summary.md`.
pub fn section(inf: &Inference, c: &Context) -> String {
    let unit = inf.im.unit();
    let mut s = format!(
        "## Inference\n\nThe {} the site felt, inferred from what overturned (`rockfrag infer`): \
         survey `{}`, study `{}` ({} records × {} levels, {} analyses), prior {}. Joint: every \
         object felt the same motion (the mean over records of the product over kinds). Naive: \
         each kind's fitted fragility curve multiplied as if every object had its own \
         earthquake (overconfident). MC error: bootstrap standard deviation over records and \
         draws ({} replicates); the joint posterior rests on {} of the {} records (effective \
         number).\n\n\
         | method | median | 90 % interval | mode | MC error of 5 % / 50 % / 95 % ({unit}) |\n\
         |---|---|---|---|---|\n",
        inf.im.name().to_uppercase(),
        c.survey.path.display(),
        c.study.name,
        c.records,
        c.levels,
        c.analyses,
        c.prior,
        c.bootstrap,
        sig3(inf.effective_records),
        c.records
    );
    let [m, i, mo] = bounds(&inf.joint.summary, unit);
    s.push_str(&format!(
        "| joint | {m} | {i} | {mo} | {} |\n",
        mc_text(inf.joint_mc)
    ));
    match &inf.naive {
        Some(p) => {
            let [m, i, mo] = bounds(&p.summary, unit);
            s.push_str(&format!(
                "| naive | {m} | {i} | {mo} | {} |\n",
                mc_text(inf.naive_mc)
            ));
        }
        None => s.push_str("| naive | its likelihood vanishes on the grid | | | |\n"),
    }
    s.push_str(&format!("\n**To report:** {}.\n", report_text(inf)));
    s.push_str(&format!(
        "\n| kind | 2B (m) | H/B | e | friction | overturned / count | draws | fragility θ ({unit}), β |\n\
         |---|---|---|---|---|---|---|---|\n"
    ));
    for ((k, m), curve) in c.survey.kinds.iter().zip(c.models).zip(&inf.curves) {
        let fit = match &curve.fit {
            Ok(f) => format!("{}, {}", sig3(f.median()), sig3(f.beta())),
            Err(u) => format!("not fitted ({})", u.status()),
        };
        let slid = k.slid.map_or(String::new(), |s| format!(" ({s} slid)"));
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} / {}{slid} | {} | {fit} |\n",
            k.name,
            k.width,
            k.aspect,
            m.case.restitution.text(),
            crate::spec::friction_label(m.case.friction),
            k.overturned,
            k.count,
            m.draws
        ));
    }
    s
}

/// Replaces the `## Inference` section of the markdown file at `path` (up
/// to the next `## ` heading) with `section`, or appends it, or writes the
/// file with a title; atomically.
fn update_section(path: &Path, section: &str) -> Result<()> {
    if path.exists() {
        return crate::io_util::replace_section(path, "## Inference", section, &[])
            .map_err(Error::io(path));
    }
    write_atomic(path, |w| {
        writeln!(w, "# Inference of the intensity from a survey\n")?;
        write!(w, "{}", section.trim_end())?;
        writeln!(w)
    })
    .map_err(Error::io(path))
}

/// The console's table: both methods' bounds and Monte Carlo errors.
pub fn console(inf: &Inference) -> String {
    let unit = inf.im.unit();
    let mut rows = vec![vec![
        "method".to_string(),
        "median".into(),
        "90% interval".into(),
        "mode".into(),
        format!("MC error 5%/50%/95% ({unit})"),
    ]];
    let mut push = |name: &str, p: Option<&Posterior>, mc: Option<McError>| match p {
        Some(p) => {
            let [m, i, mo] = bounds(&p.summary, unit);
            rows.push(vec![name.to_string(), m, i, mo, mc_text(mc)]);
        }
        None => rows.push(vec![
            name.to_string(),
            "likelihood vanishes on the grid".into(),
            String::new(),
            String::new(),
            String::new(),
        ]),
    };
    push("joint", Some(&inf.joint), inf.joint_mc);
    push("naive", inf.naive.as_ref(), inf.naive_mc);
    let mut text = crate::io_util::aligned(&rows);
    text.push_str(&format!(
        "the joint posterior rests on {} records (effective number; more records lower its MC \
         error)\n",
        sig3(inf.effective_records)
    ));
    text.push_str(&format!("to report: {}\n", report_text(inf)));
    text
}
