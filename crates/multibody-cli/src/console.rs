//! Writing to the console without ever panicking.
//!
//! `println!` and `eprintln!` panic when their stream is closed or full
//! (`multibody list | head -1`, `2> /dev/full`). What the command prints
//! on stderr is commentary: a run's result files matter more, so a stderr
//! that cannot be written is ignored. What it prints on stdout is its
//! answer (`list`, `describe`, `check`): a reader that went away ends the
//! command quietly, as it asked no more; any other failure (a full disk)
//! is an input/output error.

use crate::exit::Failure;
use std::io::Write;

/// A line on stderr, like `eprintln!`, ignoring a closed or full stderr.
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::console::say_text(&format!("{}\n", format_args!($($arg)*)))
    };
}

/// A line into a `String`, like `writeln!` without a result to handle.
macro_rules! put {
    ($out:ident, $($arg:tt)*) => {
        $out.push_str(&format!("{}\n", format_args!($($arg)*)))
    };
}

/// Text on stderr, as it is; a stderr that cannot be written is ignored.
pub fn say_text(text: &str) {
    let mut stderr = std::io::stderr().lock();
    let _ = stderr.write_all(text.as_bytes()).and_then(|()| stderr.flush());
}

/// The command's answer on stdout. A closed pipe (`| head -1`) is not an
/// error: the reader has what it wanted, and the command ends with success.
pub fn answer(text: &str) -> Result<(), Failure> {
    let mut stdout = std::io::stdout().lock();
    match stdout.write_all(text.as_bytes()).and_then(|()| stdout.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(Failure::Io(format!("cannot write to standard output: {e}"))),
    }
}
