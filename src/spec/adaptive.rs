//! The adaptive part of a spec (docs/adaptive.md): `grid.pga = { min, max }`
//! and `[fragility] precision`, `max_analyses`, checked together.

use super::locate::Origin;
use super::raw::LevelRange;
use super::study::Adaptive;
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
    range: Option<LevelRange>,
    fragility: Option<&FragilityOptions>,
) -> Result<Option<Adaptive>> {
    let precision = fragility.and_then(|f| f.precision);
    let max_analyses = fragility.and_then(|f| f.max_analyses);
    let Some(range) = range else {
        if let Some(p) = precision {
            return Err(spec.bad(
                "fragility.precision",
                &format!("{{ median = {}, beta = {} }}", p.median, p.beta),
                "a PGA range in [grid] (pga = { min = …, max = … }) for the run to place its levels in; a list of levels is a fixed grid",
            ));
        }
        if let Some(n) = max_analyses {
            return Err(spec.bad(
                "fragility.max_analyses",
                &n,
                "to be left out without an adaptive run (grid.pga = { min = …, max = … } and [fragility] precision)",
            ));
        }
        return Ok(None);
    };
    let shown = format!("{{ min = {}, max = {} }}", range.min, range.max);
    let Some(options) = fragility else {
        return Err(spec.bad(
            "grid.pga",
            &shown,
            "a list of levels, or with a range a [fragility] table with precision = { median = …, beta = … }: the run places levels until the fit's band is that narrow",
        ));
    };
    let Some(precision) = precision else {
        return Err(spec.bad(
            "grid.pga",
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
            "one IM: an adaptive run fits curves against PGA, not a surface (refit the \
             finished folder with `rockfrag fragility DIR --im pga,pgv`)",
        ));
    }
    // unset: the levels' own IM (PGA, or its RotD50 for pairs)
    if let Some(im) = options
        .im
        .filter(|im| ![Im::PGA, Im::PGA_ROTD50].contains(im))
    {
        return Err(spec.bad(
            "fragility.im",
            &format!("\"{}\"", im.name()),
            "\"pga\" (an adaptive run places PGA levels and judges the fit on them)",
        ));
    }
    Ok(Some(Adaptive {
        range,
        precision,
        max_analyses,
    }))
}
