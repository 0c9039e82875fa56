//! Adaptive Dormand–Prince stepping to the first event, shared by the two
//! integrated modes that use it (rock on request, and slide-rock always).

use super::{Event, Run};
use crate::error::{Error, Result};
use crate::solver::dopri::{Rhs, Step, StepCounts, Stepper, Tolerance};

impl Run<'_> {
    /// Integrates `rhs` by DOPRI5 from (t, y) to `t_end`, carrying the run's
    /// step size `h` in and out and adding the stepper's counters to the
    /// statistics. After each accepted step, `events(run, step, ta, tb)`
    /// returns the earliest event on (ta, tb], located on the step's dense
    /// output; stepping stops there. Returns the stop time, the event (if any)
    /// and the state there. `mode` names the mode in the error raised when
    /// the step size underflows.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub(super) fn dopri_to_event<const N: usize>(
        &mut self,
        mode: &str,
        mut rhs: impl Rhs<N>,
        t: f64,
        y: [f64; N],
        t_end: f64,
        tol: Tolerance<N>,
        mut events: impl FnMut(&mut Self, &Step<N>, f64, f64) -> Option<(f64, Event)>,
    ) -> Result<(f64, Option<Event>, [f64; N])> {
        let mut st = Stepper::new(&mut rhs, t, y, t_end, self.h, tol, self.given.dt);
        let mut found = None;
        loop {
            let step = match st.step(&mut rhs) {
                Ok(Some(step)) => step,
                Ok(None) => break,
                Err(time) => {
                    return Err(Error::Solver {
                        time,
                        message: format!(
                            "step size {} s too small in {mode}",
                            crate::error::number(st.h)
                        ),
                    });
                }
            };
            if let Some((te, ev)) = events(self, &step, st.t, step.t0 + step.h) {
                found = Some((te, ev, step.at(te)));
                break;
            }
            st.accept(&step);
        }
        self.h = st.h;
        self.count(&st.counts);
        Ok(match found {
            Some((te, ev, ye)) => (te, Some(ev), ye),
            None => (t_end, None, st.y),
        })
    }

    /// Error tolerances: `atol` times the given scale for each state component
    /// (θc for angles, p·θc for rates, …), and the energy scale for the
    /// audit's work component that follows them when N is one larger.
    pub(super) fn tolerance<const N: usize>(&self, scales: &[f64]) -> Tolerance<N> {
        let atol = std::array::from_fn(|i| {
            self.given.set.atol * scales.get(i).copied().unwrap_or(self.tally.audit.escale)
        });
        Tolerance {
            rtol: self.given.set.rtol,
            atol,
        }
    }

    /// Adds a stepper's counters to the run's statistics.
    fn count(&mut self, c: &StepCounts) {
        self.tally.out.stats.rhs_calls += c.rhs_calls;
        self.tally.out.stats.steps_accepted += c.accepted;
        self.tally.out.stats.steps_rejected += c.rejected;
    }
}
