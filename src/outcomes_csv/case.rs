//! The case of a row: one block configuration, keyed by the case columns.

use std::cmp::Ordering;

use crate::solver::Friction;

/// One block configuration, as the case columns of `outcomes.csv` give it:
/// what a fragility curve is fitted for and a figure's series is drawn for.
#[derive(Clone, Copy, Debug, PartialEq)]
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

impl CaseKey {
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

impl std::fmt::Display for CaseKey {
    /// `H/B=4 2B=0.5 e=0 inf`, or `… coulomb μs=0.7 μk=0.6`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "H/B={} 2B={} e={} {}",
            self.aspect,
            self.width,
            self.restitution,
            self.friction_name()
        )?;
        if let Friction::Coulomb { mu_s, mu_k } = self.friction {
            write!(f, " μs={mu_s} μk={mu_k}")?;
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
