//! What a run says about its progress on standard error: the number of
//! analyses before it starts, an estimate of the time once the first chunk
//! has measured the rate, and then either a progress bar (a terminal) or a
//! line every [`LINE_EVERY_PERCENT`] % or [`LINE_EVERY`], whichever comes
//! first, but not within [`LINE_GAP`] of the last (a batch log), with count,
//! rate and ETA. A run shorter than [`LINE_GAP`] prints no progress line.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// A progress line at least this often (percent of the analyses) off a
/// terminal.
pub const LINE_EVERY_PERCENT: u64 = 5;
/// ... and at least this often in time.
pub const LINE_EVERY: Duration = Duration::from_secs(60);
/// ... but never more often than this.
pub const LINE_GAP: Duration = Duration::from_secs(10);

/// The progress of one invocation of a run.
pub struct Progress {
    show: bool,
    bar: Option<ProgressBar>,
    total: u64,
    done: u64,
    /// Analyses done by this invocation and when it started running them.
    run_here: u64,
    t0: Instant,
    last_line: Instant,
    last_percent: u64,
    estimated: bool,
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
                "{elapsed_precise} [{wide_bar}] {human_pos}/{human_len} analyses, {per_sec}, ETA {eta}",
            ) {
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
            estimated: false,
        }
    }

    /// Records `n` more analyses done.
    pub fn inc(&mut self, n: u64) {
        self.done += n;
        self.run_here += n;
        if !self.show {
            return;
        }
        let elapsed = self.t0.elapsed().as_secs_f64();
        let rate = self.run_here as f64 / elapsed.max(1e-9);
        let left = self.total.saturating_sub(self.done);
        let eta = left as f64 / rate;
        if !self.estimated {
            self.estimated = true;
            if left > 0 {
                let line = format!(
                    "estimate: {} more ({} analyses/s over the first {})",
                    duration_text(eta),
                    rate.round(),
                    self.run_here
                );
                match &self.bar {
                    Some(bar) => bar.println(line),
                    None => eprintln!("{line}"),
                }
            }
        }
        if let Some(bar) = &self.bar {
            bar.inc(n);
            return;
        }
        let percent = self.done * 100 / self.total.max(1);
        if line_due(percent, self.last_percent, self.last_line.elapsed()) && left > 0 {
            self.last_percent = percent - percent % LINE_EVERY_PERCENT;
            self.last_line = Instant::now();
            eprintln!(
                "progress: {}/{} analyses ({percent}%), {} analyses/s, ETA {}",
                self.done,
                self.total,
                rate.round(),
                duration_text(eta)
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

    /// A batch log gets a line every 5 % of a long run, and at least every
    /// minute of a slow one, but a short run (under 10 s) none.
    #[test]
    fn progress_lines_every_5_percent_or_minute_not_within_10_s() {
        let s = Duration::from_secs;
        assert!(line_due(10, 5, s(11)));
        assert!(!line_due(9, 5, s(59)));
        assert!(line_due(6, 5, s(60)));
        assert!(!line_due(50, 5, s(9)));
        assert_eq!(duration_text(4.25), "4.2 s");
        assert_eq!(duration_text(125.0), "2:05 min");
        assert_eq!(duration_text(3723.0), "1:02:03 h");
    }
}
