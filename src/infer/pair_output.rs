//! What a two-IM inference adds to the outputs: `posterior_2d.csv`,
//! `inference.json`'s `two_im`, the `### Two IMs` part of `summary.md`'s
//! `## Inference`, the console's lines and `figures/inference_2d.svg`.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::inference::Inference;
use super::pair::{PairPosterior, Quantiles, REGIONS, Ratio, ratio_name};
use super::posterior::{Bounds, Summary};
use crate::error::{Error, Result};
use crate::io_util::{number, sig3, write_atomic};

/// The joint posterior's file.
pub const POSTERIOR_2D: &str = "posterior_2d.csv";
/// Its figure, under `figures/`.
pub const FIGURE_2D: &str = "inference_2d.svg";

/// Header of `posterior_2d.csv`, one row per node of the (IM1, IM2) grid,
/// IM1 then IM2 ascending: `iml1` and `iml2` (the units of
/// `inference.json`'s `two_im.im1_unit`, `im2_unit`), `density` (per unit
/// IM1 per unit IM2) and `credible` (the smallest highest-density credible
/// level, in ln IM1 and ln IM2, whose region holds the node: the 90 %
/// region is `credible <= 0.9`).
pub const POSTERIOR_2D_HEADER: &str = "iml1,iml2,density,credible";

/// Writes `posterior_2d.csv` and, with a format, `figures/inference_2d.svg`;
/// returns the paths written.
pub fn write_all(
    dir: &Path,
    inference: &Inference,
    pair: &PairPosterior,
    figure: Option<crate::figures::Format>,
) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    let path = dir.join(POSTERIOR_2D);
    let ny = pair.y.len();
    write_atomic(&path, |w| {
        writeln!(w, "{POSTERIOR_2D_HEADER}")?;
        for (i, &x) in pair.x.iter().enumerate() {
            for (k, &y) in pair.y.iter().enumerate() {
                writeln!(
                    w,
                    "{},{},{},{}",
                    number(x),
                    number(y),
                    number(pair.density[i * ny + k] / (x * y)),
                    number(pair.credible[i * ny + k])
                )?;
            }
        }
        Ok(())
    })
    .map_err(Error::io(&path))?;
    written.push(path);
    if let Some(format) = figure {
        let path = dir
            .join("figures")
            .join(FIGURE_2D)
            .with_extension(format.extension());
        let fig = super::pair_figure::PairFigure::new(inference, pair);
        crate::figures::save(&fig, &path)?;
        written.push(path);
    }
    Ok(written)
}

/// Removes a two-IM run's files from `dir` (a one-IM run into a folder
/// that held one must not leave its joint posterior beside a new posterior).
pub fn remove_stale(dir: &Path) -> Result<()> {
    let mut paths = vec![dir.join(POSTERIOR_2D)];
    for format in [crate::figures::Format::Svg, crate::figures::Format::Png] {
        paths.push(
            dir.join("figures")
                .join(FIGURE_2D)
                .with_extension(format.extension()),
        );
    }
    for p in paths {
        match std::fs::remove_file(&p) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(Error::io(&p)(e)),
            _ => {}
        }
    }
    Ok(())
}

/// One record in `two_im.records`.
#[derive(Serialize)]
struct RecordJson {
    record: usize,
    ratio: f64,
    share: f64,
}

/// `inference.json`'s `two_im`.
#[derive(Serialize)]
pub struct PairJson {
    im1: String,
    im1_unit: &'static str,
    im2: String,
    im2_unit: &'static str,
    im1_marginal: Summary,
    im2_marginal: Summary,
    correlation_ln: f64,
    im2_prior: String,
    ratio: Ratio,
    bandwidth_ln: f64,
    regions: [f64; 2],
    records: Vec<RecordJson>,
    report: String,
}

/// `two_im` of `inference.json`.
pub fn json(inf: &Inference, p: &PairPosterior) -> PairJson {
    PairJson {
        im1: p.ims.first().name(),
        im1_unit: p.ims.first().unit(),
        im2: p.ims.second().name(),
        im2_unit: p.ims.second().unit(),
        im1_marginal: p.first,
        im2_marginal: p.second,
        correlation_ln: p.correlation,
        im2_prior: prior_text(p),
        ratio: p.ratio.clone(),
        bandwidth_ln: p.bandwidth,
        regions: REGIONS,
        records: p
            .shares
            .iter()
            .enumerate()
            .map(|(r, &(ratio, share))| RecordJson {
                record: r,
                ratio,
                share,
            })
            .collect(),
        report: report_text(inf, p),
    }
}

fn q_text(q: &Quantiles, unit: &str) -> String {
    format!(
        "{} ({}–{}){}",
        sig3(q.median),
        sig3(q.p05),
        sig3(q.p95),
        if unit == "1" {
            String::new()
        } else {
            format!(" {unit}")
        }
    )
}

/// What the second IM's prior is, in words.
pub fn prior_text(p: &PairPosterior) -> String {
    let r = &p.ratio;
    format!(
        "the records' spread of {}: each of the study's {} records 1/{}, median and 90 % {}; \
         the posterior cannot leave it",
        ratio_name(p.ims),
        p.records,
        p.records,
        q_text(&r.prior, &r.unit)
    )
}

/// What to make of the second IM, in words (console, summary and
/// `two_im.report`).
pub fn report_text(inf: &Inference, p: &PairPosterior) -> String {
    let (n1, n2) = (
        p.ims.first().name().to_uppercase(),
        p.ims.second().name().to_uppercase(),
    );
    let rn = ratio_name(p.ims);
    let r = &p.ratio;
    let mc = |v: f64, e: Option<f64>| match e {
        Some(e) => format!("{} ± {}", sig3(v), sig3(e)),
        None => sig3(v),
    };
    let moved = format!(
        "shift of its mean {} prior standard deviations, spread {} of the prior's, ± their \
         Monte Carlo error",
        mc(r.shift, r.mc_error.map(|m| m.shift)),
        mc(r.spread, r.mc_error.map(|m| m.spread))
    );
    let mut s = match r.informed {
        Some(false) => format!(
            "the survey does not inform {n2} beyond the records' spread: the posterior {rn}, \
             {}, is the records', {}, within Monte Carlo error ({moved}); the {n2} posterior is \
             the {n1} posterior times the records' {rn}, as wide as the ensemble's spread makes \
             it",
            q_text(&r.posterior, &r.unit),
            q_text(&r.prior, &r.unit)
        ),
        Some(true) => format!(
            "the survey informs {rn}: posterior {} against the records' {} ({moved}, beyond {} \
             standard deviations)",
            q_text(&r.posterior, &r.unit),
            q_text(&r.prior, &r.unit),
            super::pair::INFORMED_SIGMAS
        ),
        None => format!(
            "whether the survey informs {n2} beyond the records' spread is not assessed (no \
             bootstrap: [infer] bootstrap = 0); the posterior {rn}, {}, cannot leave the \
             records' spread, {}",
            q_text(&r.posterior, &r.unit),
            q_text(&r.prior, &r.unit)
        ),
    };
    if let Some(e) = r.edge {
        let (side, more) = if e.high {
            ("highest", "higher")
        } else {
            ("lowest", "lower")
        };
        s.push_str(&format!(
            "; {:.0} % of the posterior rests on the record with the {side} {rn} of the \
             ensemble ({}): the site's {rn} may lie beyond the records', and the {n2} bound on \
             that side is the ensemble's, not the data's; add records with {more} {rn}",
            100.0 * e.share,
            sig3(e.ratio)
        ));
    }
    if inf.joint.bounds != Bounds::Both {
        s.push_str(&format!(
            "; {n2} is bounded only as {n1} is ({}): see the report above",
            inf.joint.bounds.name()
        ));
    }
    if p.records < 10 {
        s.push_str(&format!(
            "; the prior of {rn} is {} records' values, too few for the tails of {n2}",
            p.records
        ));
    }
    s
}

fn bounds(s: &Summary, unit: &str) -> [String; 3] {
    [
        format!("{} {unit}", sig3(s.median)),
        format!("{}–{} {unit}", sig3(s.p05), sig3(s.p95)),
        format!("{} {unit}", sig3(s.mode)),
    ]
}

/// The `### Two IMs` part of `summary.md`'s `## Inference`.
pub fn section(inf: &Inference, p: &PairPosterior) -> String {
    let (i1, i2) = (p.ims.first(), p.ims.second());
    let (n1, n2) = (i1.name().to_uppercase(), i2.name().to_uppercase());
    let mut s = format!(
        "\n### Two IMs: {n1} and {n2}\n\n\
         The joint posterior over ({n1}, {n2}) (`--im {}`; `{POSTERIOR_2D}`, \
         `figures/{FIGURE_2D}`): record r at {n1} = x, with its own {n2} there, has the \
         survey's likelihood Π_j ℓ_j(x, r); summed over the records it is the {n1} posterior \
         above. The prior of {n2} given {n1} is {}. Bounds from the posterior's point masses; \
         the regions and contours smooth them over ln {n2} by a Gaussian of {} \
         (Silverman's rule on the records).\n\n\
         | IM | median | 90 % interval | mode |\n|---|---|---|---|\n",
        p.ims,
        prior_text(p),
        sig3(p.bandwidth)
    );
    for (im, sm) in [(i1, &p.first), (i2, &p.second)] {
        let [m, i, mo] = bounds(sm, im.unit());
        s.push_str(&format!(
            "| {} | {m} | {i} | {mo} |\n",
            im.name().to_uppercase()
        ));
    }
    s.push_str(&format!(
        "\nCorrelation of ln {n1} and ln {n2}: {}. {}: records {}; posterior {}.\n\n\
         **About {n2}:** {}.\n",
        sig3(p.correlation),
        ratio_name(p.ims),
        q_text(&p.ratio.prior, &p.ratio.unit),
        q_text(&p.ratio.posterior, &p.ratio.unit),
        report_text(inf, p)
    ));
    s
}

/// The console's lines of a two-IM inference.
pub fn console(inf: &Inference, p: &PairPosterior) -> String {
    let mut rows = vec![vec![
        "two IMs".to_string(),
        "median".into(),
        "90% interval".into(),
        "mode".into(),
    ]];
    for (im, sm) in [(p.ims.first(), &p.first), (p.ims.second(), &p.second)] {
        let [m, i, mo] = bounds(sm, im.unit());
        rows.push(vec![im.name().to_uppercase(), m, i, mo]);
    }
    let mut text = crate::io_util::aligned(&rows);
    let (n1, n2) = (
        p.ims.first().name().to_uppercase(),
        p.ims.second().name().to_uppercase(),
    );
    text.push_str(&format!(
        "correlation of ln {n1} and ln {n2}: {}; {}: records {}, posterior {}\n",
        sig3(p.correlation),
        ratio_name(p.ims),
        q_text(&p.ratio.prior, &p.ratio.unit),
        q_text(&p.ratio.posterior, &p.ratio.unit)
    ));
    text.push_str(&format!(
        "prior of {n2}: {}\nabout {n2}: {}\n",
        prior_text(p),
        report_text(inf, p)
    ));
    text
}
