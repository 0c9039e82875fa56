//! The validation stage: [`SpecFile::validate`] checks a raw spec once, one
//! function per table, and builds the [`Study`]. The tables are checked in a
//! fixed order (top level, `[motion]` or `record_files`, `[uncertainty]`,
//! `[grid]`, `[solver]`, `[fragility]`), so a spec with several faults always reports the same one
//! first. `[output]` holds only switches and needs no check.

use super::adaptive::adaptive;
use super::locate::Origin;
use super::raw::{
    FrictionEntry, GridFile, LevelRange, Levels, MotionFile, OutputFile, RecordEntry, SpecFile,
    SupportFile, UncertaintyFile,
};
use super::study::{
    Intensity, Motions, Orientation, RecordFile, Study, Uncertainty, friction_label,
};
use super::uncertainty::uncertainty;
use crate::case::Param;
use crate::error::{Error, Result, number};
use crate::fragility::FragilityOptions;
use crate::im::{At, Im};
use crate::motion::{Floor, G_STANDARD, PRESETS, SynthesisSettings, preset};
use crate::outcome::Slot;
use crate::outcomes_csv::{Column, STATS, TIME_IN_MODE};
use crate::solver::{
    ASPECT_RANGE, Block, Friction, SolverSettings, WIDTH_RANGE, aspect_expected, width_expected,
};
use crate::uncertainty::{Property, Value};
use std::path::Path;

/// The most records at one level of an adaptive run unless `records` says
/// otherwise (a synthetic ensemble has as many as asked).
const ADAPTIVE_RECORDS: usize = 1000;
/// Largest ensemble size accepted.
const MAX_RECORDS: usize = 10_000_000;
/// Largest PGA accepted, g: above any recorded motion (about 4 g), so a
/// value given in cm/s² or m/s² by mistake is refused, in the spec and the CLI.
pub const MAX_PGA_G: f64 = 10.0;
/// Largest PGV accepted, m/s (recorded motions stay below about 4 m/s).
pub const MAX_PGV: f64 = 20.0;

impl SpecFile {
    /// Checks every value and builds the [`Study`]. `text` is the spec's text
    /// (to locate fields in errors), `origin` its path; record files are
    /// checked for existence when `check_files` is set.
    pub fn validate(self, text: &str, origin: &Path, check_files: bool) -> Result<Study> {
        let spec = Origin { text, origin };
        let name = name(&spec, self.name)?;
        let g = gravity(&spec, self.g)?;
        // The direction the blocks face belongs to the motions, not to the
        // block: taken out of [grid] and [uncertainty] here.
        let mut grid_file = self.grid;
        let grid_orientation = grid_file.orientation.take();
        let mut uncertainty_file = self.uncertainty;
        let drawn_orientation = uncertainty_file.as_mut().and_then(|u| u.orientation.take());
        // the default seed of every [uncertainty] draw: the study's seed (1
        // with record files, which leave `seed` out)
        let orientation_seed = uncertainty_file
            .as_ref()
            .and_then(|u| u.seed)
            .or(self.seed)
            .unwrap_or(1);
        if drawn_orientation.is_some() && uncertainty_file.as_ref().is_some_and(only_seed) {
            uncertainty_file = None;
        }
        let motions = if self.record_files.is_empty() {
            // an adaptive run adds records as it needs them: `records` caps
            // those of one level
            let range = matches!(grid_file.pga, Some(Levels::Range(_)))
                || matches!(grid_file.pgv, Some(Levels::Range(_)));
            let records = self.records.or(range.then_some(ADAPTIVE_RECORDS));
            let mut motions = synthetic(&spec, self.motion, self.seed, records, g)?;
            match self.components {
                None | Some(1) => no_orientation(&spec, &grid_orientation, &drawn_orientation)?,
                Some(2) => {
                    if let Motions::Synthetic { pairs, .. } = &mut motions {
                        *pairs = Some(orientation(
                            &spec,
                            grid_orientation,
                            drawn_orientation,
                            orientation_seed,
                        )?);
                    }
                }
                Some(n) => {
                    return Err(spec.bad(
                        "components",
                        &n,
                        "1 or 2 horizontal components per synthetic record",
                    ));
                }
            }
            motions
        } else {
            no_ensemble(&spec, self.seed, self.records, self.motion.is_some())?;
            if let Some(n) = self.components {
                return Err(spec.bad(
                    "components",
                    &n,
                    "to be left out when record_files is given (give the files as pairs \
                     [\"a-H1.AT2\", \"a-H2.AT2\"] for two components)",
                ));
            }
            match record_files(&spec, &self.record_files, check_files)? {
                Recorded::Files(files) => {
                    no_orientation(&spec, &grid_orientation, &drawn_orientation)?;
                    Motions::Files(files)
                }
                Recorded::Pairs(pairs) => Motions::Pairs {
                    pairs,
                    orientation: orientation(
                        &spec,
                        grid_orientation,
                        drawn_orientation,
                        orientation_seed,
                    )?,
                },
            }
        };
        let floor = support(&spec, self.support)?;
        let recorded = !matches!(motions, Motions::Synthetic { .. });
        let seed = match &motions {
            Motions::Synthetic { seed, .. } => *seed,
            Motions::Files(_) | Motions::Pairs { .. } => 1,
        };
        let stacks = super::stack::stacks(&spec, &grid_file.stack, g)?;
        // with stacks, the block lists make cases only when a block is named
        // (on the grid, or drawn)
        let drawn_block = uncertainty_file
            .as_ref()
            .is_some_and(|u| u.width.is_some() || u.aspect.is_some());
        let blocks = stacks.is_empty()
            || grid_file.width.is_some()
            || grid_file.aspect.is_some()
            || drawn_block;
        if !stacks.is_empty() {
            super::stack::settings(&spec, &self.solver, &grid_file)?;
        }
        if !blocks {
            super::uncertainty::no_block_draws(&spec, uncertainty_file.as_ref())?;
        }
        let uncertainty = uncertainty(&spec, uncertainty_file, &grid_file, seed, &stacks)?;
        let mut grid = grid(&spec, grid_file, g, recorded, uncertainty.as_ref())?;
        if !blocks {
            grid.widths.clear();
            grid.aspects.clear();
            grid.restitutions.clear();
            grid.frictions.clear();
        }
        solver(&spec, &self.solver)?;
        fragility(&spec, self.fragility.as_ref(), &self.output, &stacks)?;
        let adaptive = adaptive(&spec, grid.range, self.fragility.as_ref())?;
        let mut fragility_options = self.fragility;
        // A study of record pairs is fitted against the pair's RotD50 PGA
        // (what hazard models give) unless the spec names a measure; any
        // other against PGA.
        if let Some(options) = &mut fragility_options
            && options.im.is_none()
        {
            // an adaptive run's levels are its fit's IM (PGA or PGV)
            let levels = adaptive.map_or(Im::PGA, |a| a.im);
            options.im = Some(if motions.orientation().is_some() {
                levels.taken(At::RotD50).unwrap_or(levels)
            } else {
                levels
            });
        }
        // An IM the study's motions will not have is refused now, not
        // after every analysis has run.
        let ims = fragility_options
            .as_ref()
            .map_or_else(Vec::new, |o| o.im.into_iter().chain(o.surface).collect());
        for im in ims {
            let missing = match im.at() {
                At::Floor if floor.is_ground() => Some("a study on a floor ([support] floor)"),
                At::RotD50 if motions.orientation().is_none() => {
                    Some("a study of record pairs (components = 2, or record pairs)")
                }
                _ => None,
            };
            if let Some(needs) = missing {
                return Err(spec.bad(
                    "fragility.im",
                    &im,
                    &format!("an IM of this study's motions: {im} needs {needs}"),
                ));
            }
        }
        if let Some(infer) = &self.infer {
            infer.validate().map_err(|e| spec.nested("", e))?;
        }
        if let (Some(options), Some(u)) = (&mut fragility_options, &uncertainty) {
            options.pool = u.drawn();
        }

        Ok(Study {
            name,
            description: self.description,
            g,
            motions,
            floor,
            intensity: grid.intensity,
            widths: grid.widths,
            aspects: grid.aspects,
            restitutions: grid.restitutions,
            frictions: grid.frictions,
            stacks,
            uncertainty,
            solver: self.solver,
            output: self.output,
            fragility: fragility_options,
            infer: self.infer,
            adaptive,
        })
    }
}

// ───────────────────────────── top level ─────────────────────────────

/// `[support]`: the ground (absent, or no modes) or a floor whose every
/// mode has 0 < T < ∞, 0 ≤ ζ < 1 and a finite Γφ; errors name
/// `support.floor[i].period` (0-based i) and the value.
fn support(spec: &Origin, support: Option<SupportFile>) -> Result<Floor> {
    let floor = Floor {
        modes: support.map_or_else(Vec::new, |s| s.floor),
    };
    floor.validate().map_err(|e| spec.nested("support.", e))?;
    Ok(floor)
}

/// `name`: given, or derived from the first word of the spec file's stem
/// (accents dropped, other characters not allowed in a name become `_`:
/// `stüdy 2.toml` is `study`).
fn name(spec: &Origin, name: Option<String>) -> Result<String> {
    const ALLOWED: &str =
        "a non-empty name of letters, digits, '.', '_' or '-' (not starting with '.')";
    let valid = |n: &str| {
        !n.is_empty()
            && !n.starts_with('.')
            && n.chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-'))
    };
    let name = match name {
        Some(n) => n,
        None => {
            let stem = spec
                .origin
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            let word = stem.split_whitespace().next().unwrap_or_default();
            let derived = ascii_name(word);
            if !valid(&derived) {
                return Err(spec.bad(
                    "name",
                    &format!("(none; the file name '{stem}' gives \"{derived}\")"),
                    &format!("{ALLOWED}: add name = \"...\" to the spec"),
                ));
            }
            derived
        }
    };
    if !valid(&name) {
        return Err(spec.bad("name", &format!("\"{name}\""), ALLOWED));
    }
    Ok(name)
}

/// A file-name word as a study name: Latin letters lose their accents
/// (`ü` → `u`, `ß` → `ss`), any other character not allowed in a name
/// becomes `_`, and leading dots go.
fn ascii_name(word: &str) -> String {
    let mut out = String::new();
    for c in word.chars() {
        let plain = match c {
            'à'..='å' => "a",
            'À'..='Å' => "A",
            'ç' => "c",
            'Ç' => "C",
            'è'..='ë' => "e",
            'È'..='Ë' => "E",
            'ì'..='ï' => "i",
            'Ì'..='Ï' => "I",
            'ñ' => "n",
            'Ñ' => "N",
            'ò'..='ö' | 'ø' => "o",
            'Ò'..='Ö' | 'Ø' => "O",
            'ù'..='ü' => "u",
            'Ù'..='Ü' => "U",
            'ý' | 'ÿ' => "y",
            'Ý' => "Y",
            'ß' => "ss",
            'æ' => "ae",
            'Æ' => "AE",
            'œ' => "oe",
            'Œ' => "OE",
            c if c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-') => {
                out.push(c);
                continue;
            }
            _ => "_",
        };
        out.push_str(plain);
    }
    out.trim_start_matches('.').to_string()
}

/// `g`, m/s² (default: standard gravity).
fn gravity(spec: &Origin, g: Option<f64>) -> Result<f64> {
    let g = g.unwrap_or(G_STANDARD);
    if !(g.is_finite() && g > 0.0) {
        return Err(spec.bad("g", &g, "a positive gravity in m/s²"));
    }
    Ok(g)
}

// ─────────────────────── [motion], seed, records ───────────────────────

/// The synthetic ensemble: `[motion]` (its `g` must be the study's), `seed`
/// and `records`.
fn synthetic(
    spec: &Origin,
    motion: Option<MotionFile>,
    seed: Option<u64>,
    records: Option<usize>,
    g: f64,
) -> Result<Motions> {
    let motion = motion.unwrap_or_default();
    let base = match &motion.preset {
        None => SynthesisSettings::default(),
        Some(name) => preset(name).ok_or_else(|| {
            spec.bad(
                "motion.preset",
                &format!("\"{name}\""),
                &format!(
                    "one of {}",
                    PRESETS
                        .iter()
                        .map(|(n, _)| format!("\"{n}\""))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            )
        })?,
    };
    let mut settings = motion.resolve(SynthesisSettings { g, ..base });
    if settings.g != g {
        return Err(spec.bad(
            "motion.g",
            &settings.g,
            &format!(
                "the study's gravity g = {} (set the top-level `g` instead)",
                number(g)
            ),
        ));
    }
    settings.g = g;
    settings
        .validate()
        .map_err(|e| spec.nested("motion.", psd_path(e)))?;
    let records = records.unwrap_or(25);
    if !(1..=MAX_RECORDS).contains(&records) {
        return Err(spec.bad(
            "records",
            &records,
            &format!("a number of records in 1..={MAX_RECORDS}"),
        ));
    }
    Ok(Motions::Synthetic {
        settings,
        seed: seed.unwrap_or(1),
        records,
        pairs: None,
    })
}

/// The spectrum's own validation names its fields bare (`xi_g`); put them
/// under `psd`.
fn psd_path(err: Error) -> Error {
    match err {
        Error::InvalidParameter {
            field,
            value,
            expected,
        } if ["s0", "xi_g", "f_g", "xi_2", "f_2"].contains(&field.as_str()) => {
            Error::InvalidParameter {
                field: format!("psd.{field}"),
                value,
                expected,
            }
        }
        other => other,
    }
}

// ─────────────────────────── record_files ───────────────────────────

/// With `record_files`, the synthetic ensemble's `seed`, `records` and
/// `[motion]` must be left out.
fn no_ensemble(
    spec: &Origin,
    seed: Option<u64>,
    records: Option<usize>,
    motion: bool,
) -> Result<()> {
    for (field, given) in [
        ("seed", seed.map(|s| s.to_string())),
        ("records", records.map(|r| r.to_string())),
        ("motion", motion.then(|| "[motion]".to_string())),
    ] {
        if let Some(value) = given {
            return Err(spec.bad(
                field,
                &value,
                "to be left out when record_files is given (recorded motions replace \
                 the synthetic ensemble)",
            ));
        }
    }
    Ok(())
}

/// Whether an `[uncertainty]` table gives nothing but its seed (once the
/// orientation is taken out of it).
fn only_seed(u: &UncertaintyFile) -> bool {
    u.width.is_none()
        && u.aspect.is_none()
        && u.restitution.is_none()
        && u.mu_s.is_none()
        && u.mu_k_over_mu_s.is_none()
        && u.stack.is_empty()
}

/// What `record_files` holds: single components, or pairs of them.
enum Recorded {
    Files(Vec<RecordFile>),
    Pairs(Vec<[RecordFile; 2]>),
}

/// `record_files`: every entry a file, or every entry a pair of files
/// ([`record_file`] for each file), no file listed twice (compared as the
/// file they name, not as written).
fn record_files(spec: &Origin, given: &[RecordEntry], check_files: bool) -> Result<Recorded> {
    let pairs = matches!(given.first(), Some(RecordEntry::Pair(_)));
    let mut files: Vec<RecordFile> = Vec::with_capacity(given.len() * 2);
    let mut seen = Seen::default();
    for (i, entry) in given.iter().enumerate() {
        let field = format!("record_files[{i}]");
        match (entry, pairs) {
            (RecordEntry::One(name), false) => {
                files.push(record_file(spec, &field, name, &mut seen, check_files)?);
            }
            (RecordEntry::Pair([h1, h2]), true) => {
                let base = spec.origin.parent().unwrap_or(Path::new(""));
                if crate::io_util::same_file(&base.join(h1), &base.join(h2)) {
                    return Err(spec.bad(
                        &format!("{field}[1]"),
                        &format!("\"{h2}\""),
                        "the second horizontal component, a file other than the first",
                    ));
                }
                for (j, name) in [h1, h2].into_iter().enumerate() {
                    let field = format!("{field}[{j}]");
                    let f = record_file(spec, &field, name, &mut seen, check_files)?;
                    files.push(f);
                }
            }
            (RecordEntry::One(name), true) => {
                return Err(spec.bad(
                    &field,
                    &format!("\"{name}\""),
                    "a pair of components [\"H1\", \"H2\"] like record_files[0] (a study's \
                     records are all pairs or all single components)",
                ));
            }
            (RecordEntry::Pair([h1, h2]), false) => {
                return Err(spec.bad(
                    &field,
                    &format!("[\"{h1}\", \"{h2}\"]"),
                    "a single file like record_files[0] (a study's records are all pairs or \
                     all single components)",
                ));
            }
        }
    }
    Ok(if pairs {
        let mut it = files.into_iter();
        let mut out = Vec::with_capacity(given.len());
        while let (Some(h1), Some(h2)) = (it.next(), it.next()) {
            out.push([h1, h2]);
        }
        Recorded::Pairs(out)
    } else {
        Recorded::Files(files)
    })
}

/// Without record pairs there is no direction to face: `grid.orientation`
/// and `uncertainty.orientation` are refused.
fn no_orientation(spec: &Origin, grid: &Option<Vec<f64>>, drawn: &Option<Value>) -> Result<()> {
    let expected = "to be left out: a block faces a direction only between two horizontal \
                    components (give record_files as pairs [\"a-H1.AT2\", \"a-H2.AT2\"], \
                    or components = 2 for synthetic pairs)";
    if grid.is_some() {
        return Err(spec.bad("grid.orientation", &"(given)", expected));
    }
    if drawn.is_some() {
        return Err(spec.bad("uncertainty.orientation", &"(given)", expected));
    }
    Ok(())
}

/// The directions of a study of record pairs: `grid.orientation` (angles in
/// [0°, 360°), none repeated) or `uncertainty.orientation` (a number, or a
/// distribution within [−360°, 360°]), not both; neither: φ uniform on
/// [0°, 180°). Draws use `seed`.
fn orientation(
    spec: &Origin,
    grid: Option<Vec<f64>>,
    drawn: Option<Value>,
    seed: u64,
) -> Result<Orientation> {
    const ANGLE: &str = crate::motion::ORIENTATION_EXPECTED;
    let in_turn = crate::motion::is_orientation;
    match (grid, drawn) {
        (Some(_), Some(_)) => Err(spec.bad(
            "uncertainty.orientation",
            &"(given)",
            "to be left out when grid.orientation is given (the direction is on the grid or \
             drawn, not both)",
        )),
        (Some(angles), None) => Ok(Orientation::Grid(grid_list(
            spec,
            "orientation",
            &angles,
            in_turn,
            ANGLE,
        )?)),
        (None, Some(Value::Fixed(x))) => {
            if !in_turn(x) {
                return Err(spec.bad("uncertainty.orientation", &x, ANGLE));
            }
            Ok(Orientation::Grid(vec![x]))
        }
        (None, Some(Value::Drawn(dist))) => {
            dist.validate(
                "uncertainty.orientation",
                -360.0,
                360.0,
                "an angle in degrees within [-360, 360]",
            )
            .map_err(|e| spec.nested("", e))?;
            Ok(Orientation::Drawn { dist, seed })
        }
        (None, None) => Ok(Orientation::unknown(seed)),
    }
}

/// The files of `record_files` listed so far: the file each names (its
/// canonical path when it exists, else its path with `.` and `..` resolved
/// as written) and the entry that named it.
#[derive(Default)]
struct Seen(std::collections::HashMap<std::path::PathBuf, (String, String)>);

/// `path` with `.` components dropped and `..` resolved against the one
/// before it, without looking at the file system.
fn lexical(path: &Path) -> std::path::PathBuf {
    use std::path::Component;
    let mut out = std::path::PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir
                if matches!(out.components().next_back(), Some(Component::Normal(_))) =>
            {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// One file of `record_files` at `field`: a `.AT2` or `.csv` path relative
/// to the spec file, not a file `seen` already lists (`"good.AT2"` and
/// `"./good.AT2"` are one file, and one record counted twice) and, when
/// `check_files` is set, existing.
fn record_file(
    spec: &Origin,
    field: &str,
    given: &str,
    seen: &mut Seen,
    check_files: bool,
) -> Result<RecordFile> {
    let base = spec.origin.parent().unwrap_or(Path::new(""));
    let path = base.join(given);
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    if !matches!(ext.as_deref(), Some("at2" | "csv")) {
        return Err(spec.bad(field, &format!("\"{given}\""), "a .AT2 or .csv file"));
    }
    if given.contains(['\n', '\r']) {
        return Err(spec.bad(field, &format!("{given:?}"), "a path without line breaks"));
    }
    if check_files && !path.is_file() {
        let found = if path.is_dir() {
            "is a folder"
        } else if path.exists() {
            "is not a regular file"
        } else {
            "not found"
        };
        return Err(spec.bad(
            field,
            &format!("\"{given}\""),
            &format!(
                "an existing record file, relative to the spec file ({}: {found})",
                path.display()
            ),
        ));
    }
    let key = std::fs::canonicalize(&path).unwrap_or_else(|_| lexical(&path));
    if let Some((first, named)) = seen.0.get(&key) {
        return Err(spec.bad(
            field,
            &format!("\"{given}\""),
            &format!(
                "no file listed twice: it is {first} (\"{named}\") again, which would count \
                 one record twice"
            ),
        ));
    }
    seen.0.insert(key, (field.to_string(), given.to_string()));
    Ok(RecordFile {
        given: given.to_string(),
        path,
    })
}

// ─────────────────────────────── [grid] ───────────────────────────────

/// The validated `[grid]`.
struct Grid {
    widths: Vec<Param<f64>>,
    aspects: Vec<Param<f64>>,
    restitutions: Vec<Param<f64>>,
    intensity: Intensity,
    frictions: Vec<Param<Friction>>,
    /// `grid.pga` or `grid.pgv` given as a range (an adaptive run), with
    /// the IM of its levels.
    range: Option<(Im, LevelRange)>,
}

/// `[grid]`: the block lists (every width–aspect pair must make a valid
/// block under gravity `g`), the intensity levels and the friction models.
/// A list left out takes its default, unless `[uncertainty]` gives the
/// parameter: then the list is the one [`Param::Drawn`] (see [`Study::widths`]).
fn grid(
    spec: &Origin,
    grid: GridFile,
    g: f64,
    recorded: bool,
    uncertain: Option<&Uncertainty>,
) -> Result<Grid> {
    let given = |p: Property| uncertain.is_some_and(|u| u.get(p).is_some());
    let list = |p: Property, values: Option<Vec<f64>>, default: &[f64]| match values {
        Some(v) => Some(v),
        None if given(p) => None,
        None => Some(default.to_vec()),
    };
    let (width_text, aspect_text) = (width_expected(), aspect_expected());
    let checked = |p: Property, values, default, ok: fn(f64) -> bool, expected| match list(
        p, values, default,
    ) {
        Some(v) => Ok(grid_list(spec, p.name(), &v, ok, expected)?
            .into_iter()
            .map(Param::Fixed)
            .collect()),
        None => Ok(vec![Param::Drawn]),
    };
    let widths = checked(
        Property::Width,
        grid.width,
        &GridFile::WIDTH,
        |v| (WIDTH_RANGE.0..=WIDTH_RANGE.1).contains(&v),
        &width_text,
    )?;
    let aspects = checked(
        Property::Aspect,
        grid.aspect,
        &GridFile::ASPECT,
        |v| (ASPECT_RANGE.0..=ASPECT_RANGE.1).contains(&v),
        &aspect_text,
    )?;
    let restitutions = checked(
        Property::Restitution,
        grid.restitution,
        &GridFile::RESTITUTION,
        |v| (0.0..=1.0).contains(&v),
        "a coefficient of restitution in [0, 1]",
    )?;
    for w in widths.iter().filter_map(|w| w.fixed()) {
        for a in aspects.iter().filter_map(|a| a.fixed()) {
            Block::new(w, a, g).map_err(|e| spec.nested("grid.", e))?;
        }
    }
    let split = |l: Option<Levels>| match l {
        Some(Levels::List(v)) => (Some(v), None),
        Some(Levels::Range(r)) => (None, Some(r)),
        None => (None, None),
    };
    let (pga, pga_range) = split(grid.pga);
    let (pgv, pgv_range) = split(grid.pgv);
    let range = match (pga_range, pgv_range) {
        (Some(r), _) => Some((Im::PGA, r)),
        (None, Some(r)) => Some((Im::PGV, r)),
        (None, None) => None,
    };
    let intensity = match (grid.scale_factors, range) {
        (Some(factors), _) => {
            let given = |v: Option<Vec<f64>>, r: Option<LevelRange>| v.or(r.map(|_| Vec::new()));
            scale_factors(
                spec,
                &factors,
                &given(pga, pga_range),
                &given(pgv, pgv_range),
                recorded,
            )?
        }
        (None, Some((im, r))) => {
            let both = pga_range.is_some() && pgv_range.is_some();
            let top = if im == Im::PGV { MAX_PGV } else { MAX_PGA_G };
            super::adaptive::level_range(spec, im, r, pga.is_some() || pgv.is_some() || both, top)?
        }
        (None, None) => intensity(spec, pga, pgv)?,
    };
    let frictions = match (grid.friction, uncertain.and_then(|u| u.get(Property::MuS))) {
        (Some(entries), _) => frictions(spec, &entries)?
            .into_iter()
            .map(Param::Fixed)
            .collect(),
        (None, None) => vec![Param::Fixed(Friction::Infinite)],
        (None, Some(mu_s)) => {
            let u = uncertain.expect("mu_s given");
            let ratio = u.get(Property::MuKOverMuS).expect("validated beside mu_s");
            match (mu_s, ratio) {
                (Value::Fixed(mu_s), Value::Fixed(r)) => vec![Param::Fixed(Friction::Coulomb {
                    mu_s: *mu_s,
                    mu_k: mu_s * r,
                })],
                _ => vec![Param::Drawn],
            }
        }
    };
    Ok(Grid {
        widths,
        aspects,
        restitutions,
        intensity,
        frictions,
        range,
    })
}

/// A list `grid.<name>`: non-empty, every value finite, `ok` and not repeated.
fn grid_list(
    spec: &Origin,
    name: &str,
    values: &[f64],
    ok: impl Fn(f64) -> bool,
    expected: &str,
) -> Result<Vec<f64>> {
    let field = format!("grid.{name}");
    if values.is_empty() {
        return Err(spec.bad(&field, &"[]", "at least one value"));
    }
    for (i, &v) in values.iter().enumerate() {
        let f = format!("grid.{name}[{i}]");
        if !(v.is_finite() && ok(v)) {
            return Err(spec.bad(&f, &v, expected));
        }
        if values[..i].contains(&v) {
            return Err(spec.bad(&f, &v, "a value not already in the list"));
        }
    }
    Ok(values.to_vec())
}

/// `grid.pga` or `grid.pgv`, not both (default: PGA 0.3, 0.6, 0.9, 1.2 g).
fn intensity(spec: &Origin, pga: Option<Vec<f64>>, pgv: Option<Vec<f64>>) -> Result<Intensity> {
    Ok(match (pga, pgv) {
        (Some(_), Some(_)) => {
            return Err(spec.bad(
                "grid.pgv",
                &"(given)",
                "to be left out when grid.pga is given (one intensity measure per study)",
            ));
        }
        (None, Some(pgv)) => Intensity::Pgv(increasing(
            spec,
            "pgv",
            grid_list(
                spec,
                "pgv",
                &pgv,
                |v| v > 0.0 && v <= MAX_PGV,
                &format!("a peak ground velocity in (0, {MAX_PGV}] m/s"),
            )?,
        )?),
        (pga, None) => Intensity::Pga(increasing(
            spec,
            "pga",
            grid_list(
                spec,
                "pga",
                &pga.unwrap_or_else(|| vec![0.3, 0.6, 0.9, 1.2]),
                |v| v > 0.0 && v <= MAX_PGA_G,
                &format!("a peak ground acceleration in (0, {MAX_PGA_G}] g"),
            )?,
        )?),
    })
}

/// The intensity levels `grid.<name>` (checked by [`grid_list`]) in
/// increasing order, or an error at the first out of order: a level's
/// number keys its analyses' `[uncertainty]` draws (and its place in
/// `outcomes.csv`), so the same levels in another order would be other
/// analyses (the results of `[0.6, 0.3]` differed from `[0.3, 0.6]`'s);
/// one order, the increasing one, keeps a set of levels one study.
fn increasing(spec: &Origin, name: &str, values: Vec<f64>) -> Result<Vec<f64>> {
    if let Some(i) = (1..values.len()).find(|&i| values[i] < values[i - 1]) {
        return Err(spec.bad(
            &format!("grid.{name}[{i}]"),
            &values[i],
            &format!(
                "a level above the one before it, {} (the levels in increasing order: a \
                 level's number keys its analyses' draws, so another order would be other \
                 analyses)",
                values[i - 1]
            ),
        ));
    }
    Ok(values)
}

/// Largest scale factor accepted (a record made 100 times stronger is a
/// typing error, not an analysis).
const MAX_SCALE: f64 = 100.0;

/// `grid.scale_factors`: only with `record_files`, instead of `pga` and
/// `pgv`; factors in (0, 100], none repeated.
fn scale_factors(
    spec: &Origin,
    factors: &[f64],
    pga: &Option<Vec<f64>>,
    pgv: &Option<Vec<f64>>,
    recorded: bool,
) -> Result<Intensity> {
    for (name, given) in [("grid.pga", pga.is_some()), ("grid.pgv", pgv.is_some())] {
        if given {
            return Err(spec.bad(
                name,
                &"(given)",
                "to be left out when grid.scale_factors is given (records are scaled by \
                 factors, or to a PGA, or to a PGV)",
            ));
        }
    }
    if !recorded {
        return Err(spec.bad(
            "grid.scale_factors",
            &format!("{factors:?}"),
            "record_files: scale factors apply to recorded motions (synthetic records are \
             made at a PGA or PGV level)",
        ));
    }
    Ok(Intensity::Scale(increasing(
        spec,
        "scale_factors",
        grid_list(
            spec,
            "scale_factors",
            factors,
            |v| v > 0.0 && v <= MAX_SCALE,
            &format!("a scale factor in (0, {MAX_SCALE}]"),
        )?,
    )?))
}

/// `grid.friction`: non-empty, 0 ≤ μk ≤ μs for Coulomb models, no model
/// repeated.
fn frictions(spec: &Origin, entries: &[FrictionEntry]) -> Result<Vec<Friction>> {
    if entries.is_empty() {
        return Err(spec.bad("grid.friction", &"[]", "at least one friction model"));
    }
    let mut frictions = Vec::with_capacity(entries.len());
    for (i, &FrictionEntry(f)) in entries.iter().enumerate() {
        if let Friction::Coulomb { mu_s, mu_k } = f {
            if !(mu_s.is_finite() && mu_s >= 0.0) {
                return Err(spec.bad(
                    &format!("grid.friction[{i}].mu_s"),
                    &mu_s,
                    "a static friction coefficient μs ≥ 0",
                ));
            }
            if !(mu_k.is_finite() && mu_k >= 0.0 && mu_k <= mu_s) {
                return Err(spec.bad(
                    &format!("grid.friction[{i}].mu_k"),
                    &mu_k,
                    &format!(
                        "a kinetic friction coefficient μk in [0, μs = {}]",
                        number(mu_s)
                    ),
                ));
            }
        }
        if frictions.contains(&f) {
            return Err(spec.bad(
                &format!("grid.friction[{i}]"),
                &friction_label(Param::Fixed(f)),
                "a friction model not already in the list",
            ));
        }
        frictions.push(f);
    }
    Ok(frictions)
}

// ─────────────────────────── [solver], [fragility] ───────────────────────────

/// `[solver]`: the settings' own checks, fields under `solver.`.
fn solver(spec: &Origin, solver: &SolverSettings) -> Result<()> {
    solver.validate().map_err(|e| spec.nested("solver.", e))
}

/// `[fragility]`, if given: the options' own checks, whose fields already
/// carry the `fragility.` prefix; and a limit state's measure must be a
/// column this study writes (time in mode and the solver's counters only
/// when `[output]` asks for them).
fn fragility(
    spec: &Origin,
    options: Option<&FragilityOptions>,
    output: &OutputFile,
    stacks: &[super::stack::StudyStack],
) -> Result<()> {
    let Some(options) = options else {
        return Ok(());
    };
    options.validate().map_err(|e| spec.nested("", e))?;
    for (i, ls) in options.limit_state.iter().enumerate() {
        let Some((column, _)) = ls.column() else {
            continue;
        };
        // a body's measure: a body the study's stacks have
        if let Column::Body(slot, _) = column {
            let three = stacks.iter().any(|s| s.stack.bodies.len() == 3);
            let have = if stacks.is_empty() {
                None
            } else if three {
                Some("base, middle, top or any")
            } else {
                Some("base, top or any")
            };
            let missing = match have {
                None => Some(
                    "a study with stacks ([[grid.stack]]); a block's own column has no body prefix",
                ),
                Some(_) if slot == Slot::Middle && !three => Some(
                    "a body of the study's stacks (base, top or any: no stack has three blocks)",
                ),
                _ => None,
            };
            if let Some(expected) = missing {
                return Err(spec.bad(
                    &format!("fragility.limit_state[{i}].measure"),
                    &format!("{:?}", ls.measure),
                    expected,
                ));
            }
        }
        let switch = if TIME_IN_MODE.contains(&column) && !output.time_in_mode {
            "time_in_mode"
        } else if STATS.contains(&column) && !output.stats {
            "stats"
        } else {
            continue;
        };
        return Err(spec.bad(
            &format!("fragility.limit_state[{i}].measure"),
            &format!("{:?}", ls.measure),
            &format!("a column outcomes.csv will have: set `[output] {switch} = true` to write it"),
        ));
    }
    Ok(())
}
