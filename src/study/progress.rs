//! What a run says about its progress on standard error: the number of
//! analyses before it starts; an estimate of the time from a pilot (one
//! record per intensity level, solved first and kept, so each level is
//! weighed by its own cost: the lowest stripes, where nothing rocks, are
//! far cheaper than the highest); and then either a progress bar (a
//! terminal) or, in a batch log, a line every [`LINE_EVERY_PERCENT`] % or
//! [`LINE_EVERY`], whichever comes first, but not within [`LINE_GAP`] of the
//! last, with count, rate and ETA. A run expected to take less than
//! [`LINE_MIN_RUN`] prints no progress line.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// A progress line at least this often (percent of the analyses) off a
/// terminal.
pub const LINE_EVERY_PERCENT: u64 = 5;
/// ... and at least this often in time.
pub const LINE_EVERY: Duration = Duration::from_secs(60);
/// ... but never more often than this.
pub const LINE_GAP: Duration = Duration::from_secs(1);
/// No progress lines for a run expected to be shorter than this.
pub const LINE_MIN_RUN: Duration = Duration::from_secs(10);

/// The units of the pilot among `left` (the units still to run, in
/// order): for each intensity level, the middle one of its units, so the
/// pilot spreads over the records too; and how many units each level has
/// left (the [`Forecast`]'s start). `level_of` gives a unit's level.
pub fn pilot_units(
    left: &[usize],
    level_of: impl Fn(usize) -> usize,
    levels: usize,
) -> (Vec<usize>, Vec<u64>) {
    let mut per_level: Vec<Vec<usize>> = vec![Vec::new(); levels];
    for &u in left {
        per_level[level_of(u)].push(u);
    }
    let pilot = per_level
        .iter()
        .filter(|l| !l.is_empty())
        .map(|l| l[l.len() / 2])
        .collect();
    (pilot, per_level.iter().map(|l| l.len() as u64).collect())
}

/// What the units of each intensity level cost, s of thread time (record
/// and analyses), learnt from the pilot and then from every unit solved,
/// and how many units of each level are left and were solved here.
#[derive(Clone, Debug)]
pub struct Forecast {
    sum: Vec<f64>,
    measured: Vec<u64>,
    left: Vec<u64>,
    here: Vec<u64>,
}

impl Forecast {
    /// A forecast over `levels` levels with `left` units still to solve at
    /// each; nothing measured yet.
    pub fn new(left: Vec<u64>) -> Forecast {
        let levels = left.len();
        Forecast {
            sum: vec![0.0; levels],
            measured: vec![0; levels],
            left,
            here: vec![0; levels],
        }
    }

    /// Records a unit at `level` solved in `seconds` of thread time.
    pub fn solved(&mut self, level: usize, seconds: f64) {
        self.sum[level] += seconds;
        self.measured[level] += 1;
        self.left[level] = self.left[level].saturating_sub(1);
        self.here[level] += 1;
    }

    /// The mean cost of a unit at `level`; a level not measured yet costs
    /// the mean of those that were.
    pub fn unit(&self, level: usize) -> f64 {
        if self.measured[level] > 0 {
            return self.sum[level] / self.measured[level] as f64;
        }
        let seen: Vec<usize> = (0..self.sum.len())
            .filter(|&l| self.measured[l] > 0)
            .collect();
        seen.iter()
            .map(|&l| self.sum[l] / self.measured[l] as f64)
            .sum::<f64>()
            / seen.len().max(1) as f64
    }

    /// The cost of the units left against that of those solved here, by
    /// today's costs per level.
    pub fn left_over_here(&self) -> f64 {
        let work = |counts: &[u64]| -> f64 {
            counts
                .iter()
                .enumerate()
                .map(|(l, &n)| n as f64 * self.unit(l))
                .sum()
        };
        work(&self.left) / work(&self.here).max(1e-300)
    }
}

/// The progress of one invocation of a run.
pub struct Progress {
    show: bool,
    bar: Option<ProgressBar>,
    total: u64,
    done: u64,
    /// Analyses done (written) by this invocation.
    run_here: u64,
    /// When this invocation started running analyses (the pilot's start).
    t0: Instant,
    last_line: Instant,
    last_percent: u64,
    /// Per-level costs and counts (`None`: no pilot, no ETA lines).
    forecast: Option<Forecast>,
    /// Whether the run is expected to last [`LINE_MIN_RUN`] or more.
    lines: bool,
}

/// `1:02:03`, `2:03` or `4.2 s`.
pub fn duration_text(seconds: f64) -> String {
    if !seconds.is_finite() {
        return "?".to_string();
    }
    if seconds < 60.0 {
        return format!("{seconds:.1} s");
    }
    let s = seconds.round() as u64;
    if s < 3600 {
        format!("{}:{:02} min", s / 60, s % 60)
    } else {
        format!("{}:{:02}:{:02} h", s / 3600, s / 60 % 60, s % 60)
    }
}

/// Whether a progress line is due off a terminal: [`LINE_EVERY_PERCENT`] %
/// more done than at the last line, or [`LINE_EVERY`] since it, but not
/// within [`LINE_GAP`] of it.
fn line_due(percent: u64, last_percent: u64, since: Duration) -> bool {
    (percent >= last_percent + LINE_EVERY_PERCENT || since >= LINE_EVERY) && since >= LINE_GAP
}

impl Progress {
    /// Starts the report of a run of `total` analyses, `done` of them by
    /// earlier invocations, on `threads` threads; says nothing unless `show`.
    pub fn start(show: bool, total: u64, done: u64, threads: usize) -> Progress {
        let tty = std::io::stderr().is_terminal();
        if show {
            let left = total - done;
            let resumed = if done > 0 {
                format!(" ({done} of {total} done before)")
            } else {
                String::new()
            };
            let plural = if threads == 1 { "" } else { "s" };
            eprintln!("running {left} analyses{resumed} on {threads} thread{plural}");
        }
        let bar = (show && tty).then(|| {
            let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
            if let Ok(style) = ProgressStyle::with_template(
                "{elapsed_precise} [{wide_bar}] {human_pos}/{human_len} analyses, {rate}, ETA {eta}",
            ) {
                // indicatif's own {per_sec} prints `3,028.4567/s`.
                let style = style.with_key(
                    "rate",
                    |state: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                        let _ = write!(w, "{:.0} analyses/s", state.per_sec());
                    },
                );
                bar.set_style(style.progress_chars("=> "));
            }
            bar.set_position(done);
            bar.reset_eta();
            bar
        });
        let now = Instant::now();
        Progress {
            show,
            bar,
            total,
            done,
            run_here: 0,
            t0: now,
            last_line: now,
            last_percent: done * 100 / total.max(1),
            forecast: None,
            lines: false,
        }
    }

    /// Records the pilot (`forecast`, its units recorded as solved;
    /// `analyses` analyses in `wall`) and says how long the rest should take.
    pub fn pilot(&mut self, forecast: Forecast, analyses: usize, wall: Duration) {
        self.forecast = Some(forecast);
        self.t0 = Instant::now() - wall;
        let eta = self.eta();
        self.lines = eta >= LINE_MIN_RUN.as_secs_f64();
        if self.show && eta > 0.0 {
            let line = format!(
                "estimate: {} more (from a pilot of {analyses} analyses, one record per intensity level)",
                duration_text(eta)
            );
            match &self.bar {
                Some(bar) => bar.println(line),
                None => eprintln!("{line}"),
            }
        }
    }

    /// Says `line` on standard error (above the bar, if any), unless quiet.
    pub fn say(&self, line: &str) {
        if self.show {
            match &self.bar {
                Some(bar) => bar.println(line),
                None => eprintln!("{line}"),
            }
        }
    }

    /// Seconds left: the wall time so far in proportion to the cost of the
    /// units left against that of the units solved.
    fn eta(&self) -> f64 {
        let ratio = self.forecast.as_ref().map_or(0.0, Forecast::left_over_here);
        self.t0.elapsed().as_secs_f64() * ratio
    }

    /// Records `n` more analyses written, of which the units in `solved`
    /// (level, thread seconds) were solved now (the pilot's were before).
    pub fn inc(&mut self, n: u64, solved: &[(usize, f64)]) {
        self.done += n;
        self.run_here += n;
        if let Some(f) = &mut self.forecast {
            for &(level, seconds) in solved {
                f.solved(level, seconds);
            }
        }
        if !self.show {
            return;
        }
        if let Some(bar) = &self.bar {
            bar.inc(n);
            return;
        }
        let left = self.total.saturating_sub(self.done);
        let percent = self.done * 100 / self.total.max(1);
        if self.lines && left > 0 && line_due(percent, self.last_percent, self.last_line.elapsed())
        {
            self.last_percent = percent - percent % LINE_EVERY_PERCENT;
            self.last_line = Instant::now();
            let rate = self.run_here as f64 / self.t0.elapsed().as_secs_f64().max(1e-9);
            eprintln!(
                "progress: {}/{} analyses ({percent}%), {} analyses/s, ETA {}",
                self.done,
                self.total,
                rate.round(),
                duration_text(self.eta())
            );
        }
    }

    /// Clears the bar.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A batch log gets a line every 5 % of a run, and at least every
    /// minute of a slow one, but not two within a second (a 20-s run gets
    /// one every 5 %, about one a second; a short run none, see
    /// LINE_MIN_RUN).
    #[test]
    fn progress_lines_every_5_percent_or_minute_not_within_a_second() {
        let s = Duration::from_secs;
        let ms = Duration::from_millis;
        assert!(line_due(10, 5, ms(1000)));
        assert!(!line_due(10, 5, ms(999)));
        assert!(!line_due(9, 5, s(59)));
        assert!(line_due(6, 5, s(60)));
        assert_eq!(duration_text(4.25), "4.2 s");
        assert_eq!(duration_text(125.0), "2:05 min");
        assert_eq!(duration_text(3723.0), "1:02:03 h");
    }

    /// The pilot takes the middle unit of each level still to run, and the
    /// ETA weighs units by their level's cost. With two levels whose units
    /// cost 1 and 4 s, 50 units each, after the pilot (one of each) and 49
    /// units of the cheap level (measured at 1 s each): the cost-weighted
    /// ETA is the true remaining time, 49 × 4 = 196 s, where counting
    /// analyses alone would say 54 × 49 / 51 ≈ 52 s, almost 4× too low. A
    /// level the pilot saw too cheap is corrected by the units solved since.
    #[test]
    fn pilot_spreads_over_levels_and_weighs_them() {
        let level_of = |u: usize| u / 50;
        let units: Vec<usize> = (0..100).collect();
        assert_eq!(
            pilot_units(&units, level_of, 2),
            (vec![25, 75], vec![50, 50])
        );
        assert_eq!(
            pilot_units(&units[60..], level_of, 2),
            (vec![80], vec![0, 40])
        );
        let mut f = Forecast::new(vec![50, 50]);
        f.solved(0, 0.1); // the pilot's cheap unit happened to be cheaper
        f.solved(1, 4.0);
        for _ in 0..49 {
            f.solved(0, 1.0 + 0.9 / 49.0);
        }
        assert!((f.unit(0) - 1.0).abs() < 1e-12, "{}", f.unit(0));
        let elapsed = 0.1 + 4.0 + 49.0 * (1.0 + 0.9 / 49.0); // one thread: 54 s
        let eta = elapsed * f.left_over_here();
        assert!((eta - 196.0).abs() < 1e-9, "{eta}");
        let naive = elapsed * 49.0 / 51.0;
        assert!(naive < 0.3 * 196.0, "{naive}");
    }
}
