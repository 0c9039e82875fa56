//! The compiled core of the `rockfrag` Python package (module
//! `rockfrag._rockfrag`). The Python layer (`python/rockfrag/__init__.py`)
//! gives the functions their keyword arguments, defaults and docstrings;
//! this layer converts arrays and runs the library with the GIL released.
//!
//! Every function calls the same library functions as the CLI, so a result
//! here is the CLI's result on the same input, bit for bit.

use numpy::{IntoPyArray, PyReadonlyArray1};
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList, PyString};
use rayon::prelude::*;
use rockfrag::fragility::{Observation, fit_lognormal};
use rockfrag::motion::{
    Floor, Mode, Pair, Record, SynthesisSettings, Synthesizer, floor_record, integrate_linear,
};
use rockfrag::solver::{
    Analysis, Block, Friction, History, ImpactLaw, Initial, Integrator, Model, RockImpact,
    SolverSettings, simulate,
};
use rockfrag::spec::Study;
use rockfrag::study::{RunOptions, Shard};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// A library error as a Python exception: `OSError` for files that cannot
/// be read or written, `ValueError` for everything else (bad input), with
/// the message the CLI prints.
fn py_err(e: rockfrag::Error) -> PyErr {
    match e {
        rockfrag::Error::Io { .. } => PyOSError::new_err(e.to_string()),
        _ => PyValueError::new_err(e.to_string()),
    }
}

/// A JSON value as the Python object `json.loads` would give.
fn json_to_py<'py>(py: Python<'py>, v: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    use serde_json::Value;
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Number(n) => match (n.as_u64(), n.as_i64()) {
            (Some(u), _) if !n.is_f64() => u.into_pyobject(py)?.into_any(),
            (_, Some(i)) if !n.is_f64() => i.into_pyobject(py)?.into_any(),
            _ => n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any(),
        },
        Value::String(s) => PyString::new(py, s).into_any(),
        Value::Array(a) => {
            let items = a
                .iter()
                .map(|x| json_to_py(py, x))
                .collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any()
        }
        Value::Object(m) => {
            let d = PyDict::new(py);
            for (k, x) in m {
                d.set_item(k, json_to_py(py, x)?)?;
            }
            d.into_any()
        }
    })
}

/// A named setting (`model`, `integrator`, …) from its name, by the
/// library's one table of names; a bad name is the library's message.
fn choice<T: std::str::FromStr<Err = rockfrag::Error>>(given: &str) -> PyResult<T> {
    given.parse::<T>().map_err(py_err)
}

/// One block and the solver settings: everything an analysis needs besides
/// the record, checked once (build it with `rockfrag.simulate`'s keywords).
#[pyclass(frozen, module = "rockfrag._rockfrag")]
struct Setup {
    analysis: Analysis,
    settings: SolverSettings,
}

#[pymethods]
impl Setup {
    #[new]
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (width, aspect, restitution, mu_s, mu_k, theta0, theta_dot0, rtol,
        settle_tol, follow_cascades, model, integrator, impact, rock_impact, g, audit_energy))]
    fn new(
        width: f64,
        aspect: f64,
        restitution: f64,
        mu_s: Option<f64>,
        mu_k: Option<f64>,
        theta0: f64,
        theta_dot0: f64,
        rtol: Option<f64>,
        settle_tol: Option<f64>,
        follow_cascades: bool,
        model: &str,
        integrator: &str,
        impact: &str,
        rock_impact: &str,
        g: f64,
        audit_energy: bool,
    ) -> PyResult<Setup> {
        if let (None, Some(_)) = (mu_s, mu_k) {
            return Err(PyValueError::new_err(
                "mu_k needs mu_s: give mu_s for Coulomb friction (mu_k defaults to mu_s)",
            ));
        }
        if let (Some(s), Some(k)) = (mu_s, mu_k)
            && k > s
        {
            return Err(PyValueError::new_err(format!(
                "mu_k {k} is larger than mu_s {s}: the kinetic friction coefficient \
                 cannot exceed the static one (give mu_k ≤ {s}, or leave it out for μk = μs)"
            )));
        }
        let block = Block::new(width, aspect, g).map_err(py_err)?;
        let mut analysis = Analysis::new(block, restitution);
        if let Some(mu_s) = mu_s {
            analysis.friction = Friction::Coulomb {
                mu_s,
                mu_k: mu_k.unwrap_or(mu_s),
            };
        }
        analysis.initial = Initial {
            theta: theta0,
            theta_dot: theta_dot0,
            ..Initial::default()
        };
        let defaults = SolverSettings::default();
        let settings = SolverSettings {
            model: choice::<Model>(model)?,
            integrator: choice::<Integrator>(integrator)?,
            impact: choice::<ImpactLaw>(impact)?,
            rock_impact: choice::<RockImpact>(rock_impact)?,
            rtol: rtol.unwrap_or(defaults.rtol),
            settle_tol: settle_tol.unwrap_or(defaults.settle_tol),
            settle_cascades: !follow_cascades,
            audit_energy,
            ..defaults
        };
        analysis.validate().map_err(py_err)?;
        settings.validate().map_err(py_err)?;
        Ok(Setup { analysis, settings })
    }

    /// θc = atan(B/H) of the block (rad).
    #[getter]
    fn theta_c(&self) -> f64 {
        self.analysis.block.theta_c
    }
}

/// The solver's default relative tolerance and settle threshold.
#[pyfunction]
fn solver_defaults() -> (f64, f64) {
    let d = SolverSettings::default();
    (d.rtol, d.settle_tol)
}

/// A record from arrays: velocity and displacement integrated from rest by
/// the linear-acceleration rule unless both are given.
fn record(
    name: String,
    dt: f64,
    acc: Vec<f64>,
    vel: Option<Vec<f64>>,
    disp: Option<Vec<f64>>,
) -> rockfrag::Result<Record> {
    let (vel, disp) = match (vel, disp) {
        (Some(v), Some(d)) => (v, d),
        (None, None) => integrate_linear(dt, &acc, 0.0, 0.0),
        _ => {
            return Err(rockfrag::Error::InvalidRecord {
                name,
                message: "give both vel and disp, or neither (they are then integrated from acc)"
                    .into(),
            });
        }
    };
    Record::new(name, dt, acc, vel, disp)
}

fn vec_of(a: Option<PyReadonlyArray1<'_, f64>>) -> Option<Vec<f64>> {
    a.map(|a| a.as_array().iter().copied().collect())
}

/// One analysis: the CLI's `simulate` on the record, with its context on error.
fn solve(
    setup: &Setup,
    r: &Record,
    history: Option<&mut History>,
) -> PyResult<rockfrag::outcome::Outcome> {
    simulate(&setup.analysis, r, &setup.settings, history).map_err(|e| {
        let text = e.to_string();
        let msg = if text.contains(&r.name) {
            format!(
                "solving record {}: {}",
                r.name,
                text.replace(&format!("invalid record {}: ", r.name), "")
            )
        } else {
            format!("solving record {}: {text}", r.name)
        };
        match e {
            rockfrag::Error::Solver { .. } => PyRuntimeError::new_err(msg),
            _ => PyValueError::new_err(msg),
        }
    })
}

/// The outcome as `simulate --json` gives it: with `sensitivity`, the
/// analysis solved again under the record scaled by 1 + 1e-9 and compared
/// (`simulate --sensitivity --json`'s `sensitivity` object).
fn outcome_json(
    setup: &Setup,
    r: &Record,
    outcome: &rockfrag::outcome::Outcome,
    sensitivity: bool,
) -> PyResult<serde_json::Value> {
    let mut v = outcome.to_json();
    if sensitivity {
        let s = rockfrag::solver::sensitivity(&setup.analysis, r, &setup.settings, outcome)
            .map_err(|e| {
                PyRuntimeError::new_err(format!(
                    "solving record {} scaled by 1 + 1e-9: {e}",
                    r.name
                ))
            })?;
        v["sensitivity"] = serde_json::to_value(s).expect("a sensitivity serialises");
    }
    Ok(v)
}

/// Simulates one record; returns the outcome as `simulate --json` gives it
/// (with `sensitivity`, as `simulate --sensitivity --json` does), and the
/// time history as arrays when `history` is true.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
#[pyo3(signature = (setup, acc, dt, vel, disp, name, history, sensitivity))]
fn simulate_one<'py>(
    py: Python<'py>,
    setup: &Setup,
    acc: PyReadonlyArray1<'py, f64>,
    dt: f64,
    vel: Option<PyReadonlyArray1<'py, f64>>,
    disp: Option<PyReadonlyArray1<'py, f64>>,
    name: String,
    history: bool,
    sensitivity: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let acc: Vec<f64> = acc.as_array().iter().copied().collect();
    let r = record(name, dt, acc, vec_of(vel), vec_of(disp)).map_err(py_err)?;
    let mut h = history.then(History::default);
    let json = py.detach(|| {
        solve(setup, &r, h.as_mut()).and_then(|o| outcome_json(setup, &r, &o, sensitivity))
    })?;
    let d = json_to_py(py, &json)?.cast_into::<PyDict>()?;
    if let Some(h) = h {
        let hd = PyDict::new(py);
        let col = |f: fn(&rockfrag::solver::HistoryRow) -> f64| -> Vec<f64> {
            h.rows.iter().map(f).collect()
        };
        hd.set_item("t", col(|r| r.t).into_pyarray(py))?;
        hd.set_item(
            "mode",
            PyList::new(py, h.rows.iter().map(|r| r.mode.name()))?,
        )?;
        hd.set_item("theta", col(|r| r.theta).into_pyarray(py))?;
        hd.set_item("theta_dot", col(|r| r.theta_dot).into_pyarray(py))?;
        hd.set_item("x", col(|r| r.x).into_pyarray(py))?;
        hd.set_item("x_dot", col(|r| r.x_dot).into_pyarray(py))?;
        hd.set_item("y", col(|r| r.y).into_pyarray(py))?;
        hd.set_item("y_dot", col(|r| r.y_dot).into_pyarray(py))?;
        hd.set_item("N", col(|r| r.n).into_pyarray(py))?;
        hd.set_item("F", col(|r| r.f).into_pyarray(py))?;
        let events: Vec<bool> = h.rows.iter().map(|r| r.event).collect();
        hd.set_item("event", events.into_pyarray(py))?;
        d.set_item("history", hd)?;
    }
    Ok(d)
}

/// A record as `simulate_many` takes it: (acc, dt, vel, disp, name).
type RecordArgs<'py> = (
    PyReadonlyArray1<'py, f64>,
    f64,
    Option<PyReadonlyArray1<'py, f64>>,
    Option<PyReadonlyArray1<'py, f64>>,
    String,
);

/// Simulates many records on rayon's threads (`threads` = 0: one per core),
/// the GIL released; each record is `(acc, dt, vel, disp, name)`; with
/// `sensitivity`, each outcome carries its `sensitivity` as in
/// [`simulate_one`].
/// One stack of blocks (bottom first) under one record: the outcome of
/// `rockfrag simulate --stack … --json` as a dict (`failure` names why an
/// analysis that left the modes the stack solver models did not finish).
#[pyfunction]
#[allow(clippy::too_many_arguments)]
#[pyo3(signature = (bodies, masses, offsets, restitution, friction, tilts, acc, dt, name, rtol, g))]
fn simulate_stack<'py>(
    py: Python<'py>,
    bodies: Vec<(f64, f64)>,
    masses: Option<Vec<f64>>,
    offsets: Option<Vec<f64>>,
    restitution: Vec<f64>,
    friction: Vec<Option<(f64, f64)>>,
    tilts: Option<Vec<f64>>,
    acc: PyReadonlyArray1<'py, f64>,
    dt: f64,
    name: String,
    rtol: f64,
    g: f64,
) -> PyResult<Bound<'py, PyDict>> {
    use rockfrag::solver::stack::{Stack, StackBody, StackInterface, simulate_stack};
    let n = bodies.len();
    let per_body = |what: &str, k: usize| -> PyResult<()> {
        if k == n {
            Ok(())
        } else {
            Err(PyValueError::new_err(format!(
                "{what}: {k} values for {n} bodies (one per body, bottom first)"
            )))
        }
    };
    per_body("restitution", restitution.len())?;
    per_body("friction", friction.len())?;
    let mut stack = Stack::new(
        bodies.iter().map(|&(w, h)| StackBody::new(w, h)).collect(),
        0.0,
        g,
    );
    if let Some(m) = masses {
        per_body("masses", m.len())?;
        for (b, m) in stack.bodies.iter_mut().zip(m) {
            b.mass = m;
        }
    }
    if let Some(x) = offsets {
        per_body("offsets", x.len())?;
        for (b, x) in stack.bodies.iter_mut().zip(x) {
            b.offset = x;
        }
    }
    stack.interfaces = restitution
        .iter()
        .zip(&friction)
        .map(|(&e, f)| StackInterface {
            restitution: e,
            friction: match *f {
                None => Friction::Infinite,
                Some((mu_s, mu_k)) => Friction::Coulomb { mu_s, mu_k },
            },
        })
        .collect();
    if let Some(t) = tilts {
        per_body("tilts", t.len())?;
        stack.initial_tilt = t;
    }
    let acc: Vec<f64> = acc.as_array().iter().copied().collect();
    let r = record(name, dt, acc, None, None).map_err(py_err)?;
    let settings = SolverSettings {
        rtol,
        ..SolverSettings::default()
    };
    let json = py
        .detach(|| simulate_stack(&stack, &r, &settings, None))
        .map_err(py_err)?
        .to_json();
    json_to_py(py, &json)?
        .cast_into::<PyDict>()
        .map_err(Into::into)
}

#[pyfunction]
#[pyo3(signature = (setup, records, threads, sensitivity))]
fn simulate_many<'py>(
    py: Python<'py>,
    setup: &Setup,
    records: Vec<RecordArgs<'py>>,
    threads: usize,
    sensitivity: bool,
) -> PyResult<Bound<'py, PyList>> {
    let records: Vec<Record> = records
        .into_iter()
        .map(|(acc, dt, vel, disp, name)| {
            let acc: Vec<f64> = acc.as_array().iter().copied().collect();
            record(name, dt, acc, vec_of(vel), vec_of(disp)).map_err(py_err)
        })
        .collect::<PyResult<_>>()?;
    let outcomes = py.detach(|| -> PyResult<Vec<_>> {
        let work = || -> PyResult<Vec<_>> {
            records
                .par_iter()
                .map(|r| {
                    solve(setup, r, None).and_then(|o| outcome_json(setup, r, &o, sensitivity))
                })
                .collect()
        };
        if threads == 0 {
            work()
        } else {
            rockfrag::threads::pool(threads)
                .map_err(py_err)?
                .0
                .install(work)
        }
    })?;
    let items = outcomes
        .iter()
        .map(|o| json_to_py(py, o))
        .collect::<PyResult<Vec<_>>>()?;
    PyList::new(py, items)
}

/// Record `index` of ensemble `seed` at PGA `pga` (g): the record
/// `rockfrag motion` writes, as (dt, t, acc, vel, disp, name).
#[pyfunction]
#[pyo3(signature = (seed, pga, index, dt, duration, highpass))]
fn motion<'py>(
    py: Python<'py>,
    seed: u64,
    pga: f64,
    index: u64,
    dt: Option<f64>,
    duration: Option<f64>,
    highpass: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    if !(pga.is_finite() && pga > 0.0 && pga <= rockfrag::spec::MAX_PGA_G) {
        // 300 meant in cm/s² is refused, as by the spec and the CLI.
        return Err(py_err(rockfrag::Error::invalid(
            "pga",
            pga,
            &format!(
                "a peak ground acceleration in g, in (0, {}]",
                rockfrag::spec::MAX_PGA_G
            ),
        )));
    }
    let mut settings = SynthesisSettings::default();
    if let Some(dt) = dt {
        settings.dt = dt;
    }
    if let Some(duration) = duration {
        settings.duration = duration;
    }
    if let Some(hz) = highpass {
        settings.baseline.highpass_hz = hz;
    }
    if let Some(message) = dt.and_then(|_| settings.dt_misfit("dt")) {
        return Err(PyValueError::new_err(message));
    }
    let record = py.detach(|| -> rockfrag::Result<Record> {
        // The synthesiser of the last settings is kept: building one (the
        // spectrum, the envelope, the FFT plan) costs more than a record.
        static LAST: Mutex<Option<Synthesizer>> = Mutex::new(None);
        let mut last = LAST.lock().unwrap_or_else(|e| e.into_inner());
        if last.as_ref().is_none_or(|s| *s.settings() != settings) {
            *last = Some(Synthesizer::new(&settings)?);
        }
        let synth = last.as_mut().expect("set above");
        synth.generate(seed, index, settings.pga_from_g(pga))
    });
    record_dict(py, record.map_err(py_err)?)
}

/// A record as Python gets it: `t`, `acc`, `vel`, `disp` (numpy arrays),
/// `dt` and `name`.
fn record_dict(py: Python<'_>, record: Record) -> PyResult<Bound<'_, PyDict>> {
    let t: Vec<f64> = (0..record.len()).map(|k| k as f64 * record.dt).collect();
    let d = PyDict::new(py);
    d.set_item("t", t.into_pyarray(py))?;
    d.set_item("acc", record.acc.into_pyarray(py))?;
    d.set_item("vel", record.vel.into_pyarray(py))?;
    d.set_item("disp", record.disp.into_pyarray(py))?;
    d.set_item("dt", record.dt)?;
    d.set_item("name", record.name)?;
    Ok(d)
}

/// The absolute motion of a floor of a linear building, modes (T, ζ, Γφ),
/// under a ground record: `rockfrag floor`'s record, as (t, acc, vel, disp,
/// dt, name).
#[pyfunction]
#[pyo3(signature = (acc, dt, vel, disp, name, modes))]
fn floor<'py>(
    py: Python<'py>,
    acc: PyReadonlyArray1<'py, f64>,
    dt: f64,
    vel: Option<PyReadonlyArray1<'py, f64>>,
    disp: Option<PyReadonlyArray1<'py, f64>>,
    name: String,
    modes: Vec<(f64, f64, f64)>,
) -> PyResult<Bound<'py, PyDict>> {
    let acc: Vec<f64> = acc.as_array().iter().copied().collect();
    let ground = record(name, dt, acc, vec_of(vel), vec_of(disp)).map_err(py_err)?;
    let floor = Floor {
        modes: modes
            .into_iter()
            .map(|(period, damping, participation)| Mode {
                period,
                damping,
                participation,
            })
            .collect(),
    };
    let out = py
        .detach(|| floor_record(&ground, &floor))
        .map_err(py_err)?;
    record_dict(py, out)
}

/// One component of a pair as Rust reads it: (name, dt, acc, vel, disp).
type Component<'py> = (
    String,
    f64,
    PyReadonlyArray1<'py, f64>,
    Option<PyReadonlyArray1<'py, f64>>,
    Option<PyReadonlyArray1<'py, f64>>,
);

/// The pair (H1, H2) of two components, checked as `rockfrag simulate
/// --motion2` checks it.
fn pair_of(h1: Component<'_>, h2: Component<'_>) -> rockfrag::Result<Pair> {
    let one = |(name, dt, acc, vel, disp): Component<'_>| {
        record(
            name,
            dt,
            acc.as_array().iter().copied().collect(),
            vec_of(vel),
            vec_of(disp),
        )
    };
    Pair::new(one(h1)?, one(h2)?)
}

/// The motion along the direction `orientation` degrees from H1 towards
/// H2: cos φ·H1 + sin φ·H2, as a study of record pairs turns a pair.
#[pyfunction]
#[pyo3(signature = (h1, h2, orientation))]
fn rotate<'py>(
    py: Python<'py>,
    h1: Component<'py>,
    h2: Component<'py>,
    orientation: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let pair = pair_of(h1, h2).map_err(py_err)?;
    let out = py.detach(|| pair.rotated(orientation)).map_err(py_err)?;
    record_dict(py, out)
}

/// RotDnn of a pair (Boore 2010): the `percentile` over 0°, 1°, …, 179° of
/// the peak of the rotated acceleration (m/s²) or, with `velocity`, of the
/// rotated velocity (m/s).
#[pyfunction]
#[pyo3(signature = (h1, h2, percentile, velocity))]
fn rotd(h1: Component<'_>, h2: Component<'_>, percentile: f64, velocity: bool) -> PyResult<f64> {
    let pair = pair_of(h1, h2).map_err(py_err)?;
    if velocity {
        rockfrag::motion::rotd_series(&pair.h1.vel, &pair.h2.vel, percentile)
    } else {
        rockfrag::motion::rotd(&pair, percentile)
    }
    .map_err(py_err)
}

/// A study from a file, or from a JSON object of the spec's fields (turned
/// into TOML and read as a file in the working directory would be).
fn load_study(path: Option<&str>, json: Option<&str>) -> PyResult<(Study, String)> {
    match (path, json) {
        (Some(p), _) => Ok((Study::load(Path::new(p)).map_err(py_err)?, p.to_string())),
        (None, Some(j)) => {
            let value: serde_json::Value =
                serde_json::from_str(j).map_err(|e| PyValueError::new_err(e.to_string()))?;
            let table = toml::Value::try_from(&value).map_err(|e| {
                PyValueError::new_err(format!("the spec dict is not a TOML table: {e}"))
            })?;
            let text = toml::to_string(&table).map_err(|e| {
                PyValueError::new_err(format!("the spec dict is not a TOML table: {e}"))
            })?;
            let origin = std::env::current_dir()
                .unwrap_or_default()
                .join("spec-dict.toml");
            let study = Study::from_toml(&text, &origin).map_err(|e| {
                PyValueError::new_err(format!("{e}\n(the spec dict as TOML:)\n{text}"))
            })?;
            Ok((study, "<dict>".to_string()))
        }
        (None, None) => Ok((
            Study::shenton_jones(),
            rockfrag::spec::SHENTON_JONES_ORIGIN.to_string(),
        )),
    }
}

/// Runs a study as `rockfrag run` does (the fragility fit and the figures
/// too when the spec asks), returning the output folder.
#[pyfunction]
#[pyo3(signature = (path, json, out, threads))]
fn run(
    py: Python<'_>,
    path: Option<String>,
    json: Option<String>,
    out: Option<String>,
    threads: usize,
) -> PyResult<(String, Vec<String>)> {
    let (study, spec_file) = load_study(path.as_deref(), json.as_deref())?;
    let out = out.map_or_else(|| PathBuf::from("results").join(&study.name), PathBuf::from);
    let opts = RunOptions {
        threads,
        shard: Shard::WHOLE,
        spec_file,
        ..RunOptions::new(&out)
    };
    // The CLI's run sequence: analyses, summary, fit, figures.
    let report = py
        .detach(|| rockfrag::pipeline::run(&study, &opts))
        .map_err(py_err)?;
    if let Some(message) = report.failure() {
        return Err(PyRuntimeError::new_err(message));
    }
    // The curves that could not be fitted, with advice, for Python's warnings.
    let unfitted = report
        .finish
        .as_ref()
        .and_then(|f| f.fit.as_ref())
        .map_or_else(Vec::new, |fit| fit.unfitted.clone());
    Ok((out.display().to_string(), unfitted))
}

/// `rockfrag fragility DIR`: fits the curves of a finished study folder
/// with `options` (the spec's `[fragility]` table as JSON) into `out`
/// (default DIR, whose summary.md then gets the new curves); returns the
/// fragility.csv path, the table, the curves not fitted with advice, and a
/// warning when the fit replaces one of more bootstrap replicates. Without
/// `bootstrap` in `options`, the study's own `[fragility] bootstrap`.
#[pyfunction]
#[pyo3(signature = (dir, options, out))]
fn fragility(
    py: Python<'_>,
    dir: String,
    options: String,
    out: Option<String>,
) -> PyResult<(String, String, Vec<String>, Option<String>)> {
    let dir = PathBuf::from(dir);
    let given: rockfrag::fragility::FragilityOptions = serde_json::from_str(&options)
        .map_err(|e| PyValueError::new_err(format!("invalid fragility options: {e}")))?;
    // bootstrap not given: the study's own, as `rockfrag fragility`
    let bootstrap_given = serde_json::from_str::<serde_json::Value>(&options)
        .is_ok_and(|v| v.get("bootstrap").is_some());
    let out = out.map_or_else(|| dir.clone(), PathBuf::from);
    let (report, fewer) = py
        .detach(|| -> rockfrag::Result<_> {
            rockfrag::study::require_finished(&dir)?;
            let mut options = rockfrag::pipeline::folder_fit_options(&dir, &given)?;
            if !bootstrap_given {
                options.bootstrap = rockfrag::pipeline::study_bootstrap(&dir)?;
            }
            options.validate()?;
            let fewer = rockfrag::pipeline::fewer_replicates(&out, options.bootstrap);
            Ok((rockfrag::pipeline::refit(&dir, &out, &options)?, fewer))
        })
        .map_err(py_err)?;
    Ok((
        report.fragility_csv.display().to_string(),
        report.table.clone(),
        report.unfitted.clone(),
        fewer,
    ))
}

/// `rockfrag risk DIR --hazard FILE`: the annual rate of each fitted curve
/// of `dir` over the hazard curve `hazard` (site `site` of an OpenQuake
/// file), written to `out/risk.csv` (default DIR); returns its path.
#[pyfunction]
#[pyo3(signature = (dir, hazard, site, years, out))]
fn risk(
    py: Python<'_>,
    dir: String,
    hazard: String,
    site: Option<usize>,
    years: f64,
    out: Option<String>,
) -> PyResult<String> {
    let options = rockfrag::risk::RiskOptions {
        years,
        ..rockfrag::risk::RiskOptions::default()
    };
    py.detach(|| {
        rockfrag::pipeline::risk(
            Path::new(&dir),
            Path::new(&hazard),
            site,
            &options,
            out.as_deref().map(Path::new),
        )
    })
    .map(|report| report.written[0].display().to_string())
    .map_err(py_err)
}

/// The columns of a study's `outcomes.csv`, read by the library's reader
/// into its one row type, each field as the file holds it
/// ([`OutcomeRow::write_field`](rockfrag::outcomes_csv::OutcomeRow::write_field)):
/// a list of (name, kind, values) in the file's order, kind `flag`,
/// `count`, `number` or `text` ([`ValueKind`](rockfrag::outcomes_csv::ValueKind)),
/// values as text (empty where absent), typed by the Python layer.
#[pyfunction]
fn read_outcomes(py: Python<'_>, path: &str) -> PyResult<Vec<(String, &'static str, Vec<String>)>> {
    use rockfrag::outcomes_csv::{OutcomesFile, ValueKind};
    let path = Path::new(path);
    py.detach(|| -> rockfrag::Result<_> {
        let mut file = OutcomesFile::open(path, &[], "read_outcomes")?;
        let columns = file.columns();
        let mut values: Vec<Vec<String>> = vec![Vec::new(); columns.len()];
        while let Some((_, row)) = file.next_row()? {
            for (column, v) in columns.iter().zip(&mut values) {
                let mut field = String::new();
                row.write_field(*column, &mut field);
                // As the CSV reader would give it: unquoted.
                if field.starts_with('"') {
                    field = field[1..field.len() - 1].replace("\"\"", "\"");
                }
                v.push(field);
            }
        }
        Ok(columns
            .into_iter()
            .zip(values)
            .map(|(c, v)| {
                let kind = match c.value_kind() {
                    ValueKind::Flag => "flag",
                    ValueKind::Count => "count",
                    ValueKind::Number => "number",
                    ValueKind::Text => "text",
                };
                (c.name().into_owned(), kind, v)
            })
            .collect())
    })
    .map_err(py_err)
}

/// Fits a lognormal fragility to counts: `overturned[i]` of `trials[i]`
/// analyses at intensity `im[i]`.
#[pyfunction]
fn fit<'py>(
    py: Python<'py>,
    im: Vec<f64>,
    trials: Vec<u64>,
    overturned: Vec<u64>,
) -> PyResult<Bound<'py, PyDict>> {
    if im.len() != trials.len() || im.len() != overturned.len() {
        return Err(PyValueError::new_err(format!(
            "im, trials and overturned have different lengths ({}, {}, {})",
            im.len(),
            trials.len(),
            overturned.len()
        )));
    }
    let mut obs = Vec::with_capacity(im.len());
    for ((&x, &n), &z) in im.iter().zip(&trials).zip(&overturned) {
        if !(x.is_finite() && x > 0.0) {
            return Err(py_err(rockfrag::Error::invalid(
                "im",
                x,
                "a positive finite intensity",
            )));
        }
        if z > n {
            return Err(PyValueError::new_err(format!(
                "{z} overturned of {n} analyses at im = {x}: cannot exceed the analyses"
            )));
        }
        obs.push(Observation {
            im: x,
            trials: n,
            overturned: z,
        });
    }
    let d = PyDict::new(py);
    match fit_lognormal(&obs) {
        Ok(f) => {
            // As fragility.csv's status: a median beyond the stripes is flagged.
            let range = obs
                .iter()
                .filter(|o| o.trials > 0)
                .map(|o| o.im)
                .fold(None, |r: Option<(f64, f64)>, x| {
                    Some(r.map_or((x, x), |(a, b)| (a.min(x), b.max(x))))
                });
            let caveat = rockfrag::fragility::Caveat::of_median(f.median(), range);
            d.set_item("status", caveat.map_or("ok", |c| c.status()))?;
            d.set_item("median", f.median())?;
            d.set_item("beta", f.beta())?;
            d.set_item("se_median", f.se_median())?;
            d.set_item("se_ln_median", f.se_ln_median())?;
            d.set_item("se_beta", f.se_beta())?;
            d.set_item("a", f.a)?;
            d.set_item("b", f.b)?;
            d.set_item("cov", f.cov.to_vec())?;
            d.set_item("loglik", f.loglik)?;
            d.set_item("iterations", f.iterations)?;
            // the caveat in the words the console and the summary use (the
            // intensities' unit is the caller's, so none is named)
            let message = caveat.map_or(String::new(), |c| {
                rockfrag::fragility::caveat_words(c, range, None, "1")
            });
            d.set_item("message", message)?;
        }
        Err(u) => {
            d.set_item("status", u.status())?;
            for k in [
                "median",
                "beta",
                "se_median",
                "se_ln_median",
                "se_beta",
                "a",
                "b",
            ] {
                d.set_item(k, f64::NAN)?;
            }
            d.set_item("cov", py.None())?;
            d.set_item("loglik", f64::NAN)?;
            d.set_item("iterations", 0)?;
            d.set_item("message", u.to_string())?;
        }
    }
    Ok(d)
}

/// Infers the intensity a site felt from a survey, as `rockfrag infer`
/// does (the same run: simulations kept and reused in `out`, the same
/// files written), returning `inference.json`'s text (`inference_json`),
/// the columns of `posterior.csv` (`posterior`) and the folder (`out`). The survey
/// is a file (`observations_path`) or CSV text (`observations_csv`, named
/// `<observations>` in errors, its first row on line 2).
#[pyfunction]
#[allow(clippy::too_many_arguments)]
#[pyo3(signature = (observations_path, observations_csv, spec_path, spec_json, out, prior, im,
    threads, figure))]
fn infer<'py>(
    py: Python<'py>,
    observations_path: Option<String>,
    observations_csv: Option<String>,
    spec_path: Option<String>,
    spec_json: Option<String>,
    out: Option<String>,
    prior: &str,
    im: Option<String>,
    threads: usize,
    figure: bool,
) -> PyResult<Bound<'py, PyDict>> {
    use rockfrag::infer::{Im, InferOptions, PriorChoice, Survey, output};
    let survey = match (&observations_path, observations_csv) {
        (Some(p), _) => Survey::read(Path::new(p)),
        (None, Some(text)) => Survey::parse(&text, Path::new("<observations>")),
        (None, None) => {
            return Err(PyValueError::new_err(
                "no observations: give a survey file or rows",
            ));
        }
    }
    .map_err(py_err)?;
    if spec_path.is_none() && spec_json.is_none() {
        return Err(PyValueError::new_err(
            "no study: give the spec file (or a dict of its fields) that infer simulates with",
        ));
    }
    let (study, spec_file) = load_study(spec_path.as_deref(), spec_json.as_deref())?;
    let prior: PriorChoice = choice(prior)?;
    // One IM, or two joined by a comma (the joint posterior's), as the CLI.
    let im = im
        .map(|s| match rockfrag::im::ImPair::parse(&s) {
            Some(pair) => pair
                .and_then(rockfrag::infer::pair::inferable_pair)
                .map(|p| (p.first(), Some(p.second())))
                .map_err(|e| py_err(rockfrag::Error::invalid("im", &s, &e))),
            None => s
                .parse::<Im>()
                .ok()
                .and_then(|im| rockfrag::infer::inferable(im).ok())
                .map(|im| (im, None))
                .ok_or_else(|| {
                    py_err(rockfrag::Error::invalid(
                        "im",
                        &s,
                        "pga (g) or pgv (m/s), or two IMs for their joint posterior \
                         ([\"pga\", \"pgv\"])",
                    ))
                }),
        })
        .transpose()?;
    let out = out.map_or_else(
        || match &observations_path {
            Some(p) => rockfrag::infer::default_out(Path::new(p)),
            None => PathBuf::from("results").join("observations"),
        },
        PathBuf::from,
    );
    let opts = InferOptions {
        prior,
        im: im.map(|i| i.0),
        second: im.and_then(|i| i.1),
        threads,
        figure: figure.then_some(rockfrag::figures::Format::Svg),
        ..InferOptions::new(&out, &spec_file)
    };
    let report = py
        .detach(|| rockfrag::infer::run(&study, &survey, &opts))
        .map_err(py_err)?;
    // What the CLI wrote, read back: the numbers are the files' numbers.
    // inference.json goes to Python as text, for `json.loads` (serde_json's
    // default float parsing may miss the last bit).
    let json_path = out.join(output::INFERENCE);
    let text = std::fs::read_to_string(&json_path)
        .map_err(|e| py_err(rockfrag::Error::io(&json_path)(e)))?;
    let d = PyDict::new(py);
    d.set_item("inference_json", text)?;
    let columns = output::read_posterior(&out.join(output::POSTERIOR)).map_err(py_err)?;
    let posterior = PyDict::new(py);
    for (name, values) in columns {
        posterior.set_item(name, values.into_pyarray(py))?;
    }
    d.set_item("posterior", posterior)?;
    if report.pair.is_some() {
        let path = out.join(rockfrag::infer::pair_output::POSTERIOR_2D);
        let columns = output::read_posterior(&path).map_err(py_err)?;
        let joint = PyDict::new(py);
        for (name, values) in columns {
            joint.set_item(name, values.into_pyarray(py))?;
        }
        d.set_item("posterior_2d", joint)?;
    }
    d.set_item("analyses_run", report.analyses_run)?;
    d.set_item("resumed_levels", report.resumed_levels)?;
    d.set_item("out", out.display().to_string())?;
    Ok(d)
}

#[pymodule]
fn _rockfrag(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Setup>()?;
    m.add_function(wrap_pyfunction!(solver_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_one, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_many, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_stack, m)?)?;
    m.add_function(wrap_pyfunction!(motion, m)?)?;
    m.add_function(wrap_pyfunction!(floor, m)?)?;
    m.add_function(wrap_pyfunction!(rotate, m)?)?;
    m.add_function(wrap_pyfunction!(rotd, m)?)?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(fragility, m)?)?;
    m.add_function(wrap_pyfunction!(risk, m)?)?;
    m.add_function(wrap_pyfunction!(read_outcomes, m)?)?;
    m.add_function(wrap_pyfunction!(fit, m)?)?;
    m.add_function(wrap_pyfunction!(infer, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
