//! The ensemble primitive: the analyses of a run, of `rockfrag infer` and of
//! `rockfrag paper` are all made and solved here, one way.
//!
//! An ensemble is a list of work units (an intensity level and a record)
//! and a list of analysis jobs on them (a scene under a unit's motion):
//!
//! 1. [`motions`]: each unit's motion made once, the units in parallel,
//!    each worker with its own copy of the [`Source`] (and its caches);
//! 2. [`analyses`]: the jobs in parallel, their results in the jobs' order
//!    whatever the thread count (rayon's indexed collect), so that what is
//!    written or summed from them is the same bits on any machine;
//! 3. [`solve`]: each analysis by the solver made for its scene, guarded: a
//!    solver error, a panic, or a stack's motion that left the modes the
//!    stack solver models is an outcome of its own (a message), never a
//!    crash of the run nor a silent answer.
//!
//! What a job is and what it gives back are the caller's: a row of
//! `outcomes.csv` ([`crate::study::run`]), a kind's class (`rockfrag
//! infer`), a cell of the paper's tables (`rockfrag paper`).

use super::source::Source;
use crate::case::Scene;
use crate::motion::Record;
use crate::outcome::Outcome;
use crate::solver::stack::simulate_stack;
use crate::solver::{History, SolverSettings, simulate};
use rayon::prelude::*;

/// The motions of `units`, in their order, made in parallel by `make`
/// (each worker with its own copy of `source`, whose caches it fills).
pub fn motions<U, M, F>(source: &Source, units: &[U], make: F) -> Vec<M>
where
    U: Sync,
    M: Send,
    F: Fn(&mut Source, &U) -> M + Sync + Send,
{
    units
        .par_iter()
        .map_init(|| source.clone(), |src, u| make(src, u))
        .collect()
}

/// The results of `analyse` on every job, in parallel, in the jobs' order.
pub fn analyses<J, T, F>(jobs: &[J], analyse: F) -> Vec<T>
where
    J: Sync,
    T: Send,
    F: Fn(&J) -> T + Sync + Send,
{
    jobs.par_iter().map(analyse).collect()
}

/// One analysis, by the solver made for its scene: the single block's, or
/// the stack's; a solver error or panic becomes a message, and so does a
/// stack's motion that left the modes the stack solver models (its numbers
/// up to then are not the run's response). With `history`, a block's time
/// history is recorded too.
pub fn solve(
    scene: &Scene,
    record: &Record,
    solver: &SolverSettings,
    history: Option<&mut History>,
) -> std::result::Result<Outcome, String> {
    let attempt = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| match scene {
        Scene::Block(a) => simulate(a, record, solver, history).map(Ok),
        Scene::Stack(stack) => {
            simulate_stack(stack, record, solver, None).map(|o| match &o.failure {
                Some(why) => Err(format!("stack solver: {why} (not modelled)")),
                None => Ok(o.summary()),
            })
        }
    }));
    match attempt {
        Ok(Ok(o)) => o,
        Ok(Err(e)) => Err(e.to_string()),
        Err(panic) => Err(format!(
            "solver panicked: {}",
            panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_default()
        )),
    }
}
