//! The `rockfrag` command-line tool: a thin shell over the library.

mod cli;

use clap::Parser;

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

fn main() {
    quiet_on_broken_pipe();
    let args = match cli::Cli::try_parse() {
        Ok(args) => args,
        Err(err) => cli::exit_on_parse_error(err),
    };
    if let Err(err) = cli::check(&args) {
        cli::exit_on_parse_error(err);
    }
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
