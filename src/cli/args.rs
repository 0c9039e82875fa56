//! Value parsers shared by the subcommands: each says what it accepts.

use rockfrag::error::{fixed, number as shown};
use rockfrag::spec::{MAX_PGA_G, MAX_PGV};

/// A finite number > 0.
pub fn positive(s: &str) -> Result<f64, String> {
    let x = number(s)?;
    if x > 0.0 {
        Ok(x)
    } else {
        Err("expected a number > 0".into())
    }
}

/// A peak ground acceleration in g: in (0, [`MAX_PGA_G`]], so a value in
/// cm/s² or m/s² (`300`) is refused with the unit named.
pub fn pga_g(s: &str) -> Result<f64, String> {
    let x = positive(s)?;
    if x <= MAX_PGA_G {
        Ok(x)
    } else {
        Err(format!(
            "expected a peak ground acceleration in g, in (0, {MAX_PGA_G}]: {x} g is beyond any \
             recorded motion (in cm/s², {x} is {} g)",
            fixed(x / 981.0, 3),
            x = shown(x)
        ))
    }
}

/// A peak ground velocity in m/s: in (0, [`MAX_PGV`]], so a value in cm/s
/// is refused.
pub fn pgv_m_s(s: &str) -> Result<f64, String> {
    let x = positive(s)?;
    if x <= MAX_PGV {
        Ok(x)
    } else {
        Err(format!(
            "expected a peak ground velocity in m/s, in (0, {MAX_PGV}]: {x} m/s is beyond any \
             recorded motion (in cm/s, {x} is {} m/s)",
            fixed(x / 100.0, 3),
            x = shown(x)
        ))
    }
}

/// A finite number ≥ 0.
pub fn non_negative(s: &str) -> Result<f64, String> {
    let x = number(s)?;
    if x >= 0.0 {
        Ok(x)
    } else {
        Err("expected a number ≥ 0".into())
    }
}

/// A cap on the free motion followed after the record's end, s: the
/// range the spec's `solver.free_motion_max` accepts (its check, one place).
pub fn free_motion_s(s: &str) -> Result<f64, String> {
    let x = s
        .trim()
        .parse::<f64>()
        .map_err(|_| "expected a time in s".to_string())?;
    let settings = rockfrag::solver::SolverSettings {
        free_motion_max: x,
        ..rockfrag::solver::SolverSettings::default()
    };
    match settings.validate() {
        Err(rockfrag::error::Error::InvalidParameter { expected, .. }) => {
            Err(format!("expected {expected}"))
        }
        Err(e) => Err(e.to_string()),
        Ok(()) => Ok(x),
    }
}

/// A number in [0, 1].
pub fn unit_interval(s: &str) -> Result<f64, String> {
    let x = number(s)?;
    if (0.0..=1.0).contains(&x) {
        Ok(x)
    } else {
        Err("expected a number in [0, 1]".into())
    }
}

/// A number in (0, 1).
pub fn open_unit_interval(s: &str) -> Result<f64, String> {
    let x = number(s)?;
    if x > 0.0 && x < 1.0 {
        Ok(x)
    } else {
        Err("expected a number in (0, 1)".into())
    }
}

fn number(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err("expected a finite number".into()),
    }
}

/// A thread count ≥ 1.
pub fn threads(s: &str) -> Result<usize, String> {
    match s.trim().parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err("expected a whole number of threads ≥ 1".into()),
    }
}

/// A shard `K/N` with 1 ≤ K ≤ N.
pub fn shard(s: &str) -> Result<rockfrag::study::Shard, String> {
    s.parse()
        .map_err(|_| "expected K/N with 1 ≤ K ≤ N, e.g. 2/8".to_string())
}

/// A parser for a named choice of the library (a setting such as the solver
/// model): clap lists the names and suggests the nearest for a typo, and the
/// name is turned into the value by the library's one table of names.
pub fn choice<T>(names: Vec<&'static str>) -> impl clap::builder::TypedValueParser<Value = T>
where
    T: std::str::FromStr + Clone + Send + Sync + 'static,
    T::Err: std::fmt::Debug,
{
    use clap::builder::TypedValueParser;
    clap::builder::PossibleValuesParser::new(names).map(|s| {
        s.parse::<T>()
            .expect("a name clap accepted is a listed name")
    })
}

/// A damping ratio ζ in [0, 1) (an underdamped mode).
pub fn damping_ratio(s: &str) -> Result<f64, String> {
    let x = number(s)?;
    if (0.0..1.0).contains(&x) {
        Ok(x)
    } else {
        Err("expected a damping ratio in [0, 1), e.g. 0.05".into())
    }
}

/// Any finite number.
pub fn finite(s: &str) -> Result<f64, String> {
    number(s)
}
