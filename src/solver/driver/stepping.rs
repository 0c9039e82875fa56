//! The Dormand–Prince stepper's tolerances and counters, shared by rock and
//! slide-rock.

use super::Run;
use crate::solver::dopri::{StepCounts, Tolerance};

impl Run<'_> {
    /// Error tolerances: `atol` times the given scale for each state component
    /// (θc for angles, p·θc for rates, …), and the energy scale for the
    /// audit's work component that follows them when N is one larger.
    pub(super) fn tolerance<const N: usize>(&self, scales: &[f64]) -> Tolerance<N> {
        let atol =
            std::array::from_fn(|i| self.set.atol * scales.get(i).copied().unwrap_or(self.escale));
        Tolerance {
            rtol: self.set.rtol,
            atol,
        }
    }

    /// Adds a stepper's counters to the run's statistics.
    pub(super) fn count(&mut self, c: &StepCounts) {
        self.out.stats.rhs_calls += c.rhs_calls;
        self.out.stats.steps_accepted += c.accepted;
        self.out.stats.steps_rejected += c.rejected;
    }
}
