//! Helpers shared by the CLI tests: run the built binary, capture its output.
#![allow(dead_code)] // each test binary uses a different subset of the helpers

use std::process::{Command, Output};

/// Runs `rockfrag` with the given arguments.
pub fn rockfrag(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rockfrag"))
        .args(args)
        .output()
        .expect("run rockfrag")
}

/// Standard error as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Standard output as text.
pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}
