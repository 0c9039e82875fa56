//! The case of a row: one block configuration, keyed by the case columns.

use std::cmp::Ordering;

use crate::solver::Friction;

/// One block configuration, as the case columns of `outcomes.csv` give it:
/// what a fragility curve is fitted for and a figure's series is drawn for.
///
/// A parameter drawn per analysis (a spec's `[uncertainty]`) is NaN in the
/// key of a case, which pools the analyses over its draws (see
/// [`CaseKey::pooled`]); keys compare NaN equal to NaN, so pooled cases
/// group like any other.
#[derive(Clone, Copy, Debug)]
pub struct CaseKey {
    /// Aspect ratio H/B.
    pub aspect: f64,
    /// Base width 2B (m).
    pub width: f64,
    /// Coefficient of restitution e.
    pub restitution: f64,
    /// Friction model.
    pub friction: Friction,
}

/// Which case parameters a study draws per analysis (its `[uncertainty]`):
/// their columns vary from row to row, and a case pools the analyses over
/// them. `friction` stands for μs and μk together.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Pooled {
    /// Base width 2B.
    pub width: bool,
    /// Aspect ratio H/B.
    pub aspect: bool,
    /// Coefficient of restitution e.
    pub restitution: bool,
    /// Friction coefficients μs, μk.
    pub friction: bool,
}

impl Pooled {
    /// Whether any parameter is pooled.
    pub fn any(&self) -> bool {
        self.width || self.aspect || self.restitution || self.friction
    }

    /// The pooled parameters' column names (`mu_s` for friction), in
    /// column order.
    pub fn names(&self) -> Vec<&'static str> {
        [
            (self.aspect, "aspect"),
            (self.width, "width"),
            (self.restitution, "restitution"),
            (self.friction, "mu_s, mu_k"),
        ]
        .into_iter()
        .filter_map(|(p, n)| p.then_some(n))
        .collect()
    }
}

/// Equal as `f64`, or both NaN: how case parameters compare, NaN being the
/// placeholder of a parameter drawn per analysis (pooled).
pub fn same(a: f64, b: f64) -> bool {
    a == b || (a.is_nan() && b.is_nan())
}

/// Friction models equal, NaN coefficients (drawn) equal to NaN.
pub fn same_friction(a: &Friction, b: &Friction) -> bool {
    match (a, b) {
        (Friction::Infinite, Friction::Infinite) => true,
        (Friction::Coulomb { mu_s, mu_k }, Friction::Coulomb { mu_s: s2, mu_k: k2 }) => {
            same(*mu_s, *s2) && same(*mu_k, *k2)
        }
        _ => false,
    }
}

impl PartialEq for CaseKey {
    fn eq(&self, other: &CaseKey) -> bool {
        same(self.aspect, other.aspect)
            && same(self.width, other.width)
            && same(self.restitution, other.restitution)
            && same_friction(&self.friction, &other.friction)
    }
}

impl CaseKey {
    /// This key with the `pooled` parameters set to NaN: the case that
    /// the analysis belongs to when those parameters are drawn. Pooled
    /// friction stays Coulomb, with NaN coefficients.
    pub fn pooled(mut self, pooled: Pooled) -> CaseKey {
        if pooled.aspect {
            self.aspect = f64::NAN;
        }
        if pooled.width {
            self.width = f64::NAN;
        }
        if pooled.restitution {
            self.restitution = f64::NAN;
        }
        if pooled.friction && matches!(self.friction, Friction::Coulomb { .. }) {
            self.friction = Friction::Coulomb {
                mu_s: f64::NAN,
                mu_k: f64::NAN,
            };
        }
        self
    }

    /// The `friction` column's value: `inf` or `coulomb`.
    pub fn friction_name(&self) -> &'static str {
        match self.friction {
            Friction::Infinite => "inf",
            Friction::Coulomb { .. } => "coulomb",
        }
    }

    /// Static friction coefficient μs (`None` under infinite friction).
    pub fn mu_s(&self) -> Option<f64> {
        match self.friction {
            Friction::Infinite => None,
            Friction::Coulomb { mu_s, .. } => Some(mu_s),
        }
    }

    /// Kinetic friction coefficient μk (`None` under infinite friction).
    pub fn mu_k(&self) -> Option<f64> {
        match self.friction {
            Friction::Infinite => None,
            Friction::Coulomb { mu_k, .. } => Some(mu_k),
        }
    }

    /// Total order: aspect, width, restitution, then friction (see
    /// [`cmp_friction`]).
    pub fn total_cmp(&self, other: &CaseKey) -> Ordering {
        self.aspect
            .total_cmp(&other.aspect)
            .then(self.width.total_cmp(&other.width))
            .then(self.restitution.total_cmp(&other.restitution))
            .then(cmp_friction(&self.friction, &other.friction))
    }
}

/// A case parameter as text: its value, or `drawn` for the NaN of a
/// parameter drawn per analysis (pooled).
pub fn param_text(x: f64) -> String {
    if x.is_nan() {
        "drawn".to_string()
    } else {
        x.to_string()
    }
}

impl std::fmt::Display for CaseKey {
    /// `H/B=4 2B=0.5 e=0 inf`, or `… coulomb μs=0.7 μk=0.6`; a pooled
    /// parameter reads `drawn` (`e=drawn`).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "H/B={} 2B={} e={} {}",
            param_text(self.aspect),
            param_text(self.width),
            param_text(self.restitution),
            self.friction_name()
        )?;
        if let Friction::Coulomb { mu_s, mu_k } = self.friction {
            write!(f, " μs={} μk={}", param_text(mu_s), param_text(mu_k))?;
        }
        Ok(())
    }
}

/// Total order on friction models: infinite first, then Coulomb by (μs, μk).
pub fn cmp_friction(a: &Friction, b: &Friction) -> Ordering {
    let key = |f: &Friction| match *f {
        Friction::Infinite => (0, 0.0, 0.0),
        Friction::Coulomb { mu_s, mu_k } => (1, mu_s, mu_k),
    };
    let (ka, kb) = (key(a), key(b));
    ka.0.cmp(&kb.0)
        .then(ka.1.total_cmp(&kb.1))
        .then(ka.2.total_cmp(&kb.2))
}
