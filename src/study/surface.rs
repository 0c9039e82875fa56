//! `summary.md`'s `## Fragility surface`: the surfaces P(LS | IM1, IM2) of
//! `fragility_surface.csv` in a table and plain words, written when a fit
//! asks for a surface (`[fragility] im = ["pga", "pgv"]`, `rockfrag
//! fragility DIR --im pga,pgv`) and removed by a refit that does not.

use std::fmt::Write;

use crate::fragility::{SURFACE_FILE, SurfaceRow, surface_words};
use crate::io_util::sig3;

/// The heading of the section.
pub const SURFACE_HEADING: &str = "## Fragility surface";

/// `## Fragility surface` for `rows` (`fragility_surface.csv`'s, in its
/// order): the model, how to read it, a row per case and limit state, and
/// what each status means for that curve.
pub fn surface_section(rows: &[SurfaceRow]) -> String {
    let Some(first) = rows.first() else {
        return format!("{SURFACE_HEADING}\n\nNo surfaces: `{SURFACE_FILE}` has no rows.\n");
    };
    let (im1, im2) = (first.ims.first(), first.ims.second());
    let (s1, s2) = (im1.short(), im2.short());
    let mut s = format!(
        "{SURFACE_HEADING}\n\nProbit surfaces P(limit state | {s1}, {s2}) = Φ(a + b1 ln {s1} + \
         b2 ln {s2}), {s1} being {}, {s2} {}, fitted by maximum likelihood over the analyses \
         (`{SURFACE_FILE}`: a, b1, b2, their standard errors and correlations). The standard \
         errors count every analysis as independent; the same records at every stripe make \
         them somewhat small. {s2} adds to {s1} when b2 is beyond 2 standard errors of 0 \
         (and the likelihood-ratio χ² against the curve in {s1} alone exceeds 3.84, the 5 % \
         level). *{s1} at median {s2}*: where the surface gives 0.5 at the analyses' median \
         {s2}; *β at fixed {s2}* = 1/b1; *β alone → implied*: the curve in {s1} alone, and \
         the one the surface implies over the records' own spread of {s2}, which should \
         agree. OpenQuake and pelicun take one IM per curve: `fragility.xml` holds the \
         curves in {s1}; docs/surface.md says what takes a surface.\n\n\
         | case | limit state | b1 ± SE | b2 ± SE | {s1} at median {s2}{} | β at fixed {s2} | \
         β alone → implied | LR χ² | reading |\n|---|---|---|---|---|---|---|---|---|\n",
        im1.description(),
        im2.description(),
        im1.unit_suffix()
    );
    let pm = |r: &SurfaceRow, i: usize| match (r.coefficients, r.se) {
        (Some(c), Some(e)) => format!("{} ± {}", sig3(c[i]), sig3(e[i])),
        _ => "—".to_string(),
    };
    let or_dash = |x: Option<f64>| x.map_or("—".to_string(), sig3);
    for r in rows {
        let at_median = match (r.median_im1_at_im2_median, r.im2_median) {
            (Some(m), Some(x2)) => format!("{} (at {})", sig3(m), sig3(x2)),
            _ => "—".to_string(),
        };
        let betas = match (r.alone, r.equivalent) {
            (Some(a), Some(e)) => format!("{} → {}", sig3(a.1), sig3(e.1)),
            (Some(a), None) => format!("{} → —", sig3(a.1)),
            _ => "—".to_string(),
        };
        let reading = match r.status.as_str() {
            "ok" => format!("both matter: use the surface, or {s1} with {s2} as a second axis"),
            status => format!("**{}**", surface_words(status, &s1, &s2)),
        };
        let _ = writeln!(
            s,
            "| `{}` {} | {} | {} | {} | {at_median} | {} | {betas} | {} | {reading} |",
            r.case.id(),
            r.case,
            r.limit_state,
            pm(r, 1),
            pm(r, 2),
            or_dash(r.beta_im1_given_im2),
            or_dash(r.lr_chi2)
        );
    }
    let unread = rows.iter().filter(|r| r.status != "ok").count();
    if unread > 0 {
        let _ = writeln!(
            s,
            "\n{unread} of {} surfaces cannot be read as a surface in both IMs (the reading \
             column says why; their status in `{SURFACE_FILE}`).",
            rows.len()
        );
    }
    s
}
