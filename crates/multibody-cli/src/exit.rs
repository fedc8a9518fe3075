//! How the command fails, and the exit code for each way.

use std::io::IsTerminal;
use std::process::ExitCode;

/// Why the command stopped. What went wrong has been printed (or is in
/// the message) when this is returned.
#[derive(Debug)]
pub enum Failure {
    /// The model files have errors; the diagnostics were printed.
    Model,
    /// Bad arguments, or names that do not exist.
    Usage(String),
    /// The simulation stopped part way; partial results were written.
    Simulation,
    /// A file could not be read or written.
    Io(String),
    /// Ctrl-C stopped the simulation; what it computed was written.
    Interrupted,
}

/// The exit code after Ctrl-C, as shells report a process ended by SIGINT.
pub const INTERRUPTED: u8 = 130;

impl Failure {
    pub fn code(&self) -> u8 {
        match self {
            Failure::Model => 1,
            Failure::Usage(_) => 2,
            Failure::Simulation => 3,
            Failure::Io(_) => 4,
            Failure::Interrupted => INTERRUPTED,
        }
    }

    /// What went wrong, for a message of one run (a sweep's).
    pub fn message(&self) -> String {
        match self {
            Failure::Usage(message) | Failure::Io(message) => message.clone(),
            Failure::Model => "the model files have errors".into(),
            Failure::Simulation => "the simulation failed".into(),
            Failure::Interrupted => "interrupted".into(),
        }
    }

    /// Prints the message (if not printed yet) and gives the exit code.
    pub fn report(self) -> ExitCode {
        match &self {
            Failure::Usage(message) | Failure::Io(message) => say!("{}: {message}", error_word()),
            Failure::Model | Failure::Simulation | Failure::Interrupted => {}
        }
        ExitCode::from(self.code())
    }
}

/// Whether to colour what goes to stderr.
pub fn color() -> bool {
    std::io::stderr().is_terminal() && std::env::var_os("NO_COLOR").is_none()
}

/// "error" in red on a terminal.
pub fn error_word() -> &'static str {
    if color() {
        "\x1b[1;31merror\x1b[0m"
    } else {
        "error"
    }
}
