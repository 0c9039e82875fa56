//! `rockfrag export pelicun`: the fitted curves as a pelicun (FEMA P-58)
//! damage database, `<name>.csv` and `<name>.json`, that pelicun loads
//! unmodified.
//!
//! One component per case, its `ID` the case id ([`crate::case::Case::id`]:
//! letters, digits and `_`; pelicun splits its random-variable names on
//! `-`, so an id with `-` fails deep inside pandas). LS1 … LSn are the
//! study's limit states in order of severity, each `lognormal` with
//! `Theta_0` the median θ in the demand's unit and `Theta_1` the β. The
//! demand is the IM the curves were fitted against: `Peak Ground
//! Acceleration` in `g`, `Peak Ground Velocity` in `mps`, with
//! `Demand-Directional = 1` (with 0, pelicun multiplies the demand by 1.2,
//! FEMA P-58's factor for a non-directional demand: the PGA here is already
//! the demand on the object) and `Demand-Offset = 0`.
//!
//! A case with a limit state that could not be fitted is left out and
//! named in the JSON's `_GeneralInformation.Omitted`: pelicun needs every
//! limit state (a blank one is skipped and silently renumbers the damage
//! states above it; `Incomplete = 1` drops the component without a word).
//! One exception: when the limit states that could not be fitted are the
//! last ones and none of them was exceeded at any stripe (the pedestal of a
//! statue that never overturns), the case is written with the limit states
//! before them, whose damage states keep their numbers, and named in
//! `_GeneralInformation.Partial` and its own `Comments`: pelicun then never
//! predicts the higher damage states, which the study supports only up to
//! its highest stripe.
//! pelicun 3.10 reads only the CSV; the JSON describes the components and
//! their damage states for people and SimCenter tools.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::fragility::{
    Caveat, FitStatus, FragilityRow, LimitState, UnfitKind, read_fragility_csv,
};
use crate::im::Im;
use crate::io_util::write_atomic;

/// What [`export_pelicun`] wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct PelicunDatabase {
    /// The damage database, `<name>.csv`.
    pub csv: PathBuf,
    /// Its description, `<name>.json`.
    pub json: PathBuf,
    /// Components (cases) written.
    pub components: usize,
    /// Cases left out: id and the limit states that could not be fitted.
    pub omitted: Vec<String>,
    /// Cases written without their last limit states, none of which was
    /// exceeded at any stripe: id and those limit states.
    pub partial: Vec<String>,
}

/// pelicun's demand type and unit for curves fitted against `im`.
pub fn demand(im: Im) -> Result<(String, &'static str)> {
    im.pelicun().ok_or_else(|| {
        Error::invalid(
            "fragility.im",
            im,
            "an IM pelicun has a demand type for: pga, pgv, sa(T) (or their RotD50), \
             pfa or pfv (refit with --im pga)",
        )
    })
}

/// Writes the damage database of the fitted study folder `dir` (its
/// `fragility.csv`) into `out` as `<name>.csv` and `<name>.json` (see the
/// [module docs](self)). `limit_states` describe the limit states in the
/// JSON (the study's, from its spec; by name alone when empty); `study`
/// names the database in the JSON.
///
/// Errors: a fit against PGA/(g tan θc); no case fitted for every limit
/// state; unreadable or unwritable files.
pub fn export_pelicun(
    dir: &Path,
    out: &Path,
    name: &str,
    study: &str,
    limit_states: &[LimitState],
) -> Result<PelicunDatabase> {
    let rows = {
        if !dir.join("fragility.csv").exists() {
            // An unfinished run or another folder: say so, not "No such file".
            crate::study::require_finished(dir)?;
        }
        crate::fragility::check_set(dir)?;
        read_fragility_csv(&dir.join("fragility.csv"))?
    };
    let im = rows.first().map_or(Im::PGA, |r| r.im);
    let (demand_type, unit) = demand(im)?;
    let mut names: Vec<String> = Vec::new();
    for r in &rows {
        if !names.contains(&r.limit_state) {
            names.push(r.limit_state.clone());
        }
    }
    // The rows of each case, in order.
    let mut cases: Vec<(String, Vec<&FragilityRow>)> = Vec::new();
    for r in &rows {
        let id = r.case.id();
        match cases.iter_mut().find(|c| c.0 == id) {
            Some(c) => c.1.push(r),
            None => cases.push((id, vec![r])),
        }
    }
    let mut csv =
        String::from("ID,Incomplete,Demand-Type,Demand-Unit,Demand-Offset,Demand-Directional");
    for k in 1..=names.len() {
        let _ = write!(csv, ",LS{k}-Family,LS{k}-Theta_0,LS{k}-Theta_1");
    }
    csv.push('\n');
    let mut components = Vec::new();
    let mut omitted = Vec::new();
    let mut partial = Vec::new();
    for (id, case_rows) in &cases {
        let fits: Vec<Option<(f64, f64)>> = names
            .iter()
            .map(|ls| {
                case_rows
                    .iter()
                    .find(|r| &r.limit_state == ls)
                    .and_then(|r| r.fit())
            })
            .collect();
        // A case whose limit states are out of order: pelicun's damage
        // state k (LSₖ exceeded, LSₖ₊₁ not) would have a negative probability.
        if let Some(r) = case_rows
            .iter()
            .find(|r| r.caveat() == Some(Caveat::OutOfOrder))
        {
            omitted.push(format!(
                "{id} ({}: out-of-order, more likely than a milder limit state)",
                r.limit_state
            ));
            continue;
        }
        // The limit states written: all, or those before trailing ones that
        // were never exceeded (their damage states keep their numbers).
        let status_of = |ls: &String| {
            case_rows
                .iter()
                .find(|r| &r.limit_state == ls)
                .map(|r| r.status)
        };
        let kept = fits.iter().take_while(|f| f.is_some()).count();
        let never_exceeded =
            |ls: &String| status_of(ls) == Some(FitStatus::Unfit(UnfitKind::NoneOverturned));
        if kept > 0 && kept < names.len() && names[kept..].iter().all(never_exceeded) {
            partial.push(format!(
                "{id} (written with {}; {} never exceeded at any stripe)",
                names[..kept].join(", "),
                names[kept..].join(", ")
            ));
        } else if fits.iter().any(Option::is_none) {
            let missing: Vec<String> = names
                .iter()
                .zip(&fits)
                .filter(|(_, f)| f.is_none())
                .map(|(ls, _)| {
                    let status = case_rows
                        .iter()
                        .find(|r| &r.limit_state == ls)
                        .map_or("no fit", |r| r.status.keyword());
                    format!("{ls}: {status}")
                })
                .collect();
            omitted.push(format!("{id} ({})", missing.join("; ")));
            continue;
        }
        let _ = write!(csv, "{id},0,{demand_type},{unit},0,1");
        for (m, b) in fits.into_iter().flatten() {
            // Rust's shortest round-trip form: the file holds the fit's θ and β.
            let _ = write!(csv, ",lognormal,{m:?},{b:?}");
        }
        // blank trailing limit states: pelicun reads the ones before them
        csv.push_str(&",,,".repeat(names.len() - kept));
        csv.push('\n');
        components.push((id.clone(), case_rows[0].case, kept));
    }
    if components.is_empty() {
        return Err(Error::Parse {
            path: dir.join("fragility.csv"),
            line: 0,
            message: format!(
                "no case is fitted for every limit state, which pelicun needs ({})",
                omitted.join(", ")
            ),
        });
    }

    // The JSON, DLML's layout.
    let describe = |k: usize, ls: &str| -> String {
        match limit_states.iter().find(|l| l.name == ls) {
            Some(l) if l.measure == "overturned" => format!("{ls}: the block overturns"),
            Some(l) => match l.exceeds {
                Some(x) => format!("{ls}: {} exceeds {x}", l.measure),
                None => format!("{ls}: {}", l.measure),
            },
            None if ls == "overturning" => format!("{ls}: the block overturns"),
            None => format!("{ls} (limit state {k})"),
        }
    };
    let mut general = serde_json::json!({
        "ShortName": format!("rockfrag {study}"),
        "Description": format!(
            "Fragility of free-standing rigid blocks from the rockfrag study {study}; \
             limit states in order of severity: {}", names.join(", ")),
        "Version": env!("CARGO_PKG_VERSION"),
    });
    if !omitted.is_empty() {
        general["Omitted"] = serde_json::json!(omitted);
    }
    if !partial.is_empty() {
        general["Partial"] = serde_json::json!(partial);
    }
    let mut json = serde_json::Map::new();
    json.insert("_GeneralInformation".into(), general);
    for (id, case, kept) in &components {
        let mut states = serde_json::Map::new();
        for (k, ls) in names.iter().enumerate().take(*kept) {
            states.insert(
                format!("LS{}", k + 1),
                serde_json::json!({ format!("DS{}", k + 1): { "Description": describe(k + 1, ls) } }),
            );
        }
        json.insert(
            id.clone(),
            serde_json::json!({
                "Description": format!("Free-standing rigid block {case}"),
                "Comments": format!(
                    "Lognormal fragility fitted by rockfrag (probit maximum likelihood over \
                     stripes of {}); Theta_0 = median in {unit}, Theta_1 = lognormal dispersion \
                     beta.{}", im.name(),
                    if *kept < names.len() {
                        let (these, were) = if names.len() - kept == 1 {
                            ("The limit state", "was")
                        } else {
                            ("The limit states", "were")
                        };
                        format!(
                            " {these} {} {were} never exceeded at any stripe of the study \
                             and left out: this component never reaches their damage \
                             states, which the study supports only up to its highest stripe.",
                            names[*kept..].join(", "))
                    } else {
                        String::new()
                    }),
                "SuggestedComponentBlockSize": "1 EA",
                "RoundUpToIntegerQuantity": "True",
                "LimitStates": states,
            }),
        );
    }
    let json_text = serde_json::to_string_pretty(&serde_json::Value::Object(json))
        .expect("a JSON value serialises")
        + "\n";
    crate::io_util::create_folder(out)?;
    let paths = (
        out.join(format!("{name}.csv")),
        out.join(format!("{name}.json")),
    );
    write_atomic(&paths.0, |w| w.write_all(csv.as_bytes())).map_err(Error::io(&paths.0))?;
    write_atomic(&paths.1, |w| w.write_all(json_text.as_bytes())).map_err(Error::io(&paths.1))?;
    Ok(PelicunDatabase {
        csv: paths.0,
        json: paths.1,
        components: components.len(),
        omitted,
        partial,
    })
}
