//! The adaptive part of a spec (docs/adaptive.md): `grid.pga = { min, max }`
//! and `[fragility] precision`, `max_analyses`, checked together.

use super::locate::Origin;
use super::raw::LevelRange;
use super::study::{Adaptive, Intensity};
use crate::error::Result;
use crate::fragility::FragilityOptions;
use crate::im::Im;

/// The most analyses per case an adaptive study may ask for.
const MAX_ANALYSES: usize = 10_000_000;

/// The adaptive part of a spec: a PGA range needs `[fragility] precision`
/// and the precision needs a range; `max_analyses` needs both. The run
/// judges its band by the bootstrap of the fit, so one is required.
pub(super) fn adaptive(
    spec: &Origin,
    range: Option<(Im, LevelRange)>,
    fragility: Option<&FragilityOptions>,
) -> Result<Option<Adaptive>> {
    let precision = fragility.and_then(|f| f.precision);
    let max_analyses = fragility.and_then(|f| f.max_analyses);
    let Some(range) = range else {
        if let Some(p) = precision {
            return Err(spec.bad(
                "fragility.precision",
                &format!("{{ median = {}, beta = {} }}", p.median, p.beta),
                "a range in [grid] (pga = { min = …, max = … }, or pgv) for the run to place its levels in; a list of levels is a fixed grid",
            ));
        }
        if let Some(n) = max_analyses {
            return Err(spec.bad(
                "fragility.max_analyses",
                &n,
                "to be left out without an adaptive run (grid.pga or grid.pgv = { min = …, max = … } and [fragility] precision)",
            ));
        }
        return Ok(None);
    };
    let (level_im, range) = range;
    let field = if level_im == Im::PGV {
        "grid.pgv"
    } else {
        "grid.pga"
    };
    let shown = format!("{{ min = {}, max = {} }}", range.min, range.max);
    let Some(options) = fragility else {
        return Err(spec.bad(
            field,
            &shown,
            "a list of levels, or with a range a [fragility] table with precision = { median = …, beta = … }: the run places levels until the fit's band is that narrow",
        ));
    };
    let Some(precision) = precision else {
        return Err(spec.bad(
            field,
            &shown,
            "a list of levels, or with a range [fragility] precision = { median = …, beta = … }: the run places levels until the fit's band is that narrow",
        ));
    };
    precision.validate().map_err(|e| spec.nested("", e))?;
    let max_analyses = max_analyses.unwrap_or(crate::fragility::DEFAULT_MAX_ANALYSES);
    if !(crate::fragility::MIN_ANALYSES..=MAX_ANALYSES).contains(&max_analyses) {
        return Err(spec.bad(
            "fragility.max_analyses",
            &max_analyses,
            &format!(
                "a number of analyses per case from {} (an adaptive run's least) to {MAX_ANALYSES}",
                crate::fragility::MIN_ANALYSES
            ),
        ));
    }
    if options.bootstrap < 200 {
        return Err(spec.bad(
            "fragility.bootstrap",
            &options.bootstrap,
            "at least 200 replicates: an adaptive run judges its band by the bootstrap",
        ));
    }
    if let (Some(im), Some(second)) = (options.im, options.surface) {
        return Err(spec.bad(
            "fragility.im",
            &format!("[\"{im}\", \"{second}\"]"),
            "one IM: an adaptive run fits curves against its levels' IM, not a surface (refit \
             the finished folder with `rockfrag fragility DIR --im pga,pgv`)",
        ));
    }
    // unset: the levels' own IM (PGA or PGV, or its RotD50 for pairs)
    let own = [
        level_im,
        level_im.taken(crate::im::At::RotD50).unwrap_or(level_im),
    ];
    if let Some(im) = options.im.filter(|im| !own.contains(im)) {
        return Err(spec.bad(
            "fragility.im",
            &format!("\"{}\"", im.name()),
            &format!(
                "\"{}\" (an adaptive run places {} levels and judges the fit on them)",
                level_im.name(),
                level_im.short()
            ),
        ));
    }
    Ok(Some(Adaptive {
        im: level_im,
        range,
        precision,
        max_analyses,
    }))
}

/// `grid.pga = { min, max }` (g) or `grid.pgv = { min, max }` (m/s):
/// 0 < min, 1.5·min ≤ max ≤ `top` (the field's largest level), the other field left
/// out (`other`); the levels are the lattice an adaptive run chooses from.
pub(super) fn level_range(
    spec: &Origin,
    im: Im,
    r: LevelRange,
    other: bool,
    top: f64,
) -> Result<Intensity> {
    let (name, other_name, what) = if im == Im::PGV {
        ("pgv", "pga", "a peak ground velocity")
    } else {
        ("pga", "pgv", "a peak ground acceleration")
    };
    let unit = im.unit();
    if other {
        return Err(spec.bad(
            &format!("grid.{other_name}"),
            &"(given)",
            &format!("to be left out when grid.{name} is given (one intensity measure per study)"),
        ));
    }
    let ok = |v: f64| v.is_finite() && v > 0.0 && v <= top;
    if !ok(r.min) {
        return Err(spec.bad(
            &format!("grid.{name}.min"),
            &r.min,
            &format!("{what} in (0, {top}] {unit}"),
        ));
    }
    if !(ok(r.max) && r.max >= 1.5 * r.min) {
        return Err(spec.bad(
            &format!("grid.{name}.max"),
            &r.max,
            &format!(
                "{what} in (0, {top}] {unit} at least 1.5 times grid.{name}.min ({}): the range \
                 an adaptive run places its levels in",
                r.min
            ),
        ));
    }
    let lattice = crate::fragility::lattice(r.min, r.max);
    Ok(if im == Im::PGV {
        Intensity::Pgv(lattice)
    } else {
        Intensity::Pga(lattice)
    })
}
