//! Worker threads: how many a study, an inference or the paper check runs
//! on, and their pool.
//!
//! Results never depend on the thread count (every analysis is seeded by
//! its place in the study and rows are written in canonical order), so the
//! count only decides the speed. Asking for more threads than
//! [`MAX_THREADS_PER_CORE`] per available core gains nothing and, in the
//! thousands, spends minutes creating them (`--threads 10000` took 80 s,
//! `--threads 1000000` ran the machine out of process ids): such a count is
//! capped there and the cap is reported.

use crate::error::{Error, Result};

/// The most threads used per available core (the cores the process may
/// run on: its CPU affinity and cgroup quota, as `nproc` counts them).
pub const MAX_THREADS_PER_CORE: usize = 4;

/// The cores this process may run on (1 if that cannot be known).
pub fn available_cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The threads to run on for a request of `requested` (0: one per
/// available core), capped at [`MAX_THREADS_PER_CORE`] per core.
pub fn effective(requested: usize) -> usize {
    let cores = available_cores();
    match requested {
        0 => cores,
        n => n.min(MAX_THREADS_PER_CORE * cores),
    }
}

/// Why `requested` threads became `used`, if it was capped: a note for the
/// user, `None` otherwise.
pub fn cap_note(requested: usize, used: usize) -> Option<String> {
    (requested > used).then(|| {
        format!(
            "{requested} threads asked for, {used} used: at most {MAX_THREADS_PER_CORE} per \
             available core ({} here); more only cost time to start (results do not depend \
             on the thread count)",
            available_cores()
        )
    })
}

/// A rayon pool of [`effective`]`(requested)` threads, and that count.
///
/// Errors: [`Error::InvalidParameter`] (`threads`) if the system refuses
/// to start them.
pub fn pool(requested: usize) -> Result<(rayon::ThreadPool, usize)> {
    let threads = effective(requested);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::invalid("threads", threads, &format!("a usable thread count ({e})")))?;
    Ok((pool, threads))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A request within the cap is kept, 0 means one per core, and a
    /// request beyond it is capped and said so.
    #[test]
    fn threads_are_capped_per_core() {
        let cores = available_cores();
        assert_eq!(effective(0), cores);
        assert_eq!(effective(1), 1);
        assert_eq!(effective(1_000_000), MAX_THREADS_PER_CORE * cores);
        assert!(cap_note(1_000_000, effective(1_000_000)).is_some());
        assert!(cap_note(1, 1).is_none());
    }
}
