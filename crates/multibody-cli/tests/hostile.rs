//! Hostile surroundings, third round (issue 26): closed and full consoles,
//! outputs that are not files, huge thread counts, signals, and the
//! messages of the mistakes a new user makes. Each case failed once.

mod common;

use common::{crate_path, scratch};
use std::path::Path;
use std::process::{Command, Output, Stdio};

fn example(name: &str) -> String {
    crate_path(&format!("../../examples/{name}"))
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn code(o: &Output) -> i32 {
    o.status.code().expect("exited normally")
}

/// `multibody` with `args` in `dir`, its stdout and stderr as given.
fn multibody_with(dir: &Path, args: &[&str], stdout: Stdio, stderr: Stdio) -> Output {
    Command::new(env!("CARGO_BIN_EXE_multibody"))
        .args(args)
        .current_dir(dir)
        .env("NO_COLOR", "1")
        .stdin(Stdio::null())
        .stdout(stdout)
        .stderr(stderr)
        .output()
        .expect("the multibody binary runs")
}

/// The write end of a pipe whose reader has gone (`| head -1` after its
/// line, `| true`): every write to it fails.
fn closed_pipe() -> Stdio {
    let (reader, writer) = std::io::pipe().expect("a pipe");
    drop(reader);
    writer.into()
}

/// A stream on which every write fails with "no space left on device".
fn full_device() -> Stdio {
    std::fs::OpenOptions::new().write(true).open("/dev/full").expect("/dev/full").into()
}

/// `list | head -1`, `check model | head -1`: the reader went away, the
/// command ends quietly with success (it used to panic, exit 101).
#[test]
fn a_closed_stdout_ends_the_command_quietly() {
    let dir = scratch("closed-stdout");
    let pendulum = example("pendulum.dyad");
    let cases: [&[&str]; 3] = [&["list"], &["check", &pendulum], &["describe", "Body"]];
    for args in cases {
        let o = multibody_with(&dir, args, closed_pipe(), Stdio::piped());
        assert_eq!(code(&o), 0, "{args:?}: {}", stderr(&o));
        assert!(!stderr(&o).contains("panicked"), "{args:?}: {}", stderr(&o));
    }
}

/// `list > /dev/full`: an input/output error that says so, not a panic.
#[test]
fn a_full_stdout_is_an_io_error() {
    let dir = scratch("full-stdout");
    let o = multibody_with(&dir, &["list"], full_device(), Stdio::piped());
    assert_eq!(code(&o), 4, "{}", stderr(&o));
    assert!(stderr(&o).contains("cannot write to standard output"), "{}", stderr(&o));
    assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
}

/// `run model 2> /dev/full` and `run model 2>&1 | true`: the console is
/// commentary; the run ends normally and its CSV is written.
#[test]
fn a_run_writes_its_results_whatever_happens_to_its_console() {
    let pendulum = example("pendulum.dyad");
    let args = ["run", pendulum.as_str(), "--stop", "0.5", "--out", "r.csv"];
    type Console = fn() -> Stdio;
    let consoles: [(&str, Console, Console); 3] = [
        ("stderr full", Stdio::null, full_device),
        ("both closed", closed_pipe, closed_pipe),
        ("stdout full, stderr closed", full_device, closed_pipe),
    ];
    for (name, out, err) in consoles {
        let dir = scratch(&format!("console-{}", name.replace([' ', ','], "-")));
        let o = multibody_with(&dir, &args, out(), err());
        assert_eq!(code(&o), 0, "{name}");
        let csv = std::fs::read_to_string(dir.join("r.csv")).expect("the CSV is written");
        assert_eq!(csv.lines().count(), 52, "{name}: a header and 51 samples");
    }
    // A failing run keeps its partial result too, and says so by its exit code.
    let dir = scratch("console-failing");
    let model = crate_path("tests/models/EulerSingularity.dyad");
    let o = multibody_with(&dir, &["run", &model, "--out", "r.csv"], closed_pipe(), closed_pipe());
    assert_eq!(code(&o), 3);
    assert!(dir.join("r.partial.csv").exists());
}
