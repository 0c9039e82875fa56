//! The `rockfrag` command-line tool: a thin shell over the library.

mod cli;

/// A write to a closed pipe (`rockfrag simulate … | head -1`) ends the
/// program quietly with status 141, as a Unix tool killed by SIGPIPE does,
/// instead of a panic message and status 101 (Rust ignores SIGPIPE, so
/// `println!` panics when the reader has gone).
fn quiet_on_broken_pipe() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let payload = info.payload();
        let text = payload
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| payload.downcast_ref::<&str>().copied())
            .unwrap_or("");
        if text.starts_with("failed printing to stdout") && text.contains("Broken pipe") {
            std::process::exit(141);
        }
        default(info);
    }));
}

/// Sets two thresholds of glibc's allocator (other C libraries, musl, have
/// neither):
///
/// - the threshold for serving a block by mmap(2) stays at its default
///   (128 KiB) instead of rising to the largest block freed (up to 32 MiB).
///   A run frees its synthetic members (`Source::prepare`, 7.5 MB in
///   `studies/fragility-100k.toml`) before the fit; with the raised
///   threshold the fit's vectors of a few MB come from the heap and stay
///   resident after they are freed, under the figures' rows: that run's
///   peak was 38 MiB, with the threshold kept 27 MiB, at the same CPU.
/// - the free memory at the top of a heap that is given back to the system
///   is raised from 128 KiB to 4 MiB. At 128 KiB each worker's heap was cut
///   back (madvise) after almost every chunk of analyses and its pages
///   faulted in again by the next: 129,000 page faults in that study,
///   12,500 with 4 MiB, for 1.6 MB more at the peak (31.3 → 32.9 MiB).
fn set_allocator_thresholds() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt(3) only sets parameters of glibc's allocator; called
    // before any other thread exists.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 128 * 1024);
        libc::mallopt(libc::M_TRIM_THRESHOLD, 4 * 1024 * 1024);
    }
}

fn main() {
    set_allocator_thresholds();
    quiet_on_broken_pipe();
    let args = match cli::parse() {
        Ok(args) => args,
        Err(err) => cli::exit_on_parse_error(err),
    };
    if let Err(err) = cli::check(&args) {
        cli::exit_on_parse_error(err);
    }
    interrupt::install(&args.command);
    if let Err(err) = cli::run(args) {
        // One line: the context chain, skipping causes already quoted by their parent.
        let mut line = String::new();
        for cause in err.chain() {
            let text = cause.to_string();
            if !line.contains(&text) {
                if !line.is_empty() {
                    line.push_str(": ");
                }
                line.push_str(&text);
            }
        }
        eprintln!("error: {line}");
        std::process::exit(1);
    }
}

/// Ctrl-C (SIGINT). `run` stops at the end of the chunk of analyses under
/// way, saves and checkpoints it, says so and how to resume, and exits with
/// status 130 (its own message, `cli::run`); a second Ctrl-C stops at once
/// (a run killed so resumes too: the checkpoint is written after each
/// chunk). Every other command stops at once with a line saying what was
/// kept: files are written whole or not at all, and `infer` keeps its
/// simulations level by level.
#[cfg(unix)]
mod interrupt {
    use std::sync::OnceLock;
    use std::sync::atomic::{AtomicBool, Ordering};

    /// What an interrupted command prints as it stops at once.
    static MESSAGE: OnceLock<String> = OnceLock::new();
    /// Whether the first Ctrl-C asks the run to stop after its chunk.
    static GRACEFUL: AtomicBool = AtomicBool::new(false);

    pub fn install(command: &crate::cli::Command) {
        use crate::cli::Command;
        let (graceful, kept) = match command {
            Command::Run(_) => (
                true,
                "the analyses saved at the last checkpoint are kept; run the same command again \
                 to resume where it stopped",
            ),
            Command::Infer(_) => (
                false,
                "the simulations of the intensity levels finished so far are kept; run the same \
                 command again to resume where it stopped",
            ),
            _ => (
                false,
                "no file was left half-written (each is written whole or not at all); run the \
                 command again",
            ),
        };
        let _ = MESSAGE.set(format!("\ninterrupted: {kept}\n"));
        GRACEFUL.store(graceful, Ordering::SeqCst);
        let handler = on_interrupt as extern "C" fn(libc::c_int);
        // SAFETY: the handler does only what a signal handler may: atomic
        // loads and stores, write(2) and _exit(2).
        unsafe {
            libc::signal(libc::SIGINT, handler as libc::sighandler_t);
        }
    }

    extern "C" fn on_interrupt(_: libc::c_int) {
        let first = !rockfrag::study::INTERRUPT.swap(true, Ordering::SeqCst);
        if first && GRACEFUL.load(Ordering::SeqCst) {
            say(
                "\ninterrupted: finishing the chunk of analyses under way and saving it \
                 (Ctrl-C again to stop at once)\n",
            );
            return;
        }
        if let Some(message) = MESSAGE.get() {
            say(message);
        }
        // SAFETY: _exit is async-signal-safe.
        unsafe { libc::_exit(130) }
    }

    fn say(text: &str) {
        // SAFETY: write(2) on standard error, from a live buffer.
        unsafe {
            libc::write(2, text.as_ptr().cast(), text.len());
        }
    }
}

/// Elsewhere Ctrl-C keeps the platform's default.
#[cfg(not(unix))]
mod interrupt {
    pub fn install(_: &crate::cli::Command) {}
}
