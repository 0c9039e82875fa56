//! The `rockfrag` command-line tool: a thin shell over the library.

mod cli;

use clap::Parser;

fn main() {
    let args = match cli::Cli::try_parse() {
        Ok(args) => args,
        Err(err) => cli::exit_on_parse_error(err),
    };
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
