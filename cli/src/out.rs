//! Everything the commands print goes through here: results to stdout
//! ([`say!`], [`put!`], [`json`]), warnings and notes to stderr ([`warn`],
//! [`note`]). What a
//! failed or closed stdout means is decided in one place, [`print`]: a
//! closed stdout ends the listing quietly.

use std::fmt;
use std::io::Write;

use crate::failure::Failure;

/// Print a line to stdout.
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::out::print(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// Print to stdout without adding a newline (for text that ends in one).
macro_rules! put {
    ($($arg:tt)*) => {
        $crate::out::print(format_args!($($arg)*))
    };
}

pub(crate) use {put, say};

/// Write to stdout. Rust ignores SIGPIPE, so a reader that goes away (as
/// `head` does) shows up here as a broken pipe: the listing was cut short
/// on purpose, and the process ends quietly with success, as it would by
/// SIGPIPE. Any other failure to write is an error.
pub fn print(text: fmt::Arguments<'_>) {
    let mut stdout = std::io::stdout().lock();
    match stdout.write_fmt(text).and_then(|()| stdout.flush()) {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => {
            holo::output::remove_temporaries();
            std::process::exit(0);
        }
        Err(e) => {
            holo::output::remove_temporaries();
            eprintln!("holo: error: cannot write to standard output: {e}");
            std::process::exit(1);
        }
    }
}

/// Print `value` as pretty JSON.
pub fn json(value: &impl serde::Serialize) -> Result<(), Failure> {
    let text = serde_json::to_string_pretty(value).map_err(|e| Failure(e.to_string()))?;
    say!("{text}");
    Ok(())
}

/// A warning on stderr, `holo: warning: …`.
pub fn warn(warning: impl fmt::Display) {
    eprintln!("holo: warning: {warning}");
}

/// A note on stderr, `holo: note: …`: what a command decided for the user
/// that they may not expect, though nothing is wrong.
pub fn note(note: impl fmt::Display) {
    eprintln!("holo: note: {note}");
}
