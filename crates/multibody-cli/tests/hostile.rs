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

/// `multibody` with `args` in `dir`, its output captured.
fn multibody(dir: &Path, args: &[&str]) -> Output {
    multibody_with(dir, args, Stdio::piped(), Stdio::piped())
}

/// A model file `r.partial.dyad` and `--out r.dyad`: a failing run would
/// keep its partial CSV as `r.partial.dyad`, over the model. Refused before
/// the run; the model file stays.
#[test]
fn a_partial_name_never_replaces_a_model_file() {
    let dir = scratch("partial-collision");
    let model = dir.join("r.partial.dyad");
    std::fs::copy(crate_path("tests/models/EulerSingularity.dyad"), &model).unwrap();
    let text = std::fs::read_to_string(&model).unwrap();
    let o = multibody(&dir, &["run", "r.partial.dyad", "--out", "r.dyad"]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("`--out r.dyad`: a run that stops part way would keep its results as r.partial.dyad"),
        "{err}"
    );
    assert!(err.contains("is the model file r.partial.dyad"), "{err}");
    assert!(!err.contains("Simulating"), "refused before the run: {err}");
    assert_eq!(std::fs::read_to_string(&model).unwrap(), text, "the model file is untouched");
    // The views' partial names count too, and so do a sweep's.
    let o = multibody(&dir, &["run", "r.partial.dyad", "--plot", "r.svg", "--out", "r.partial.svg"]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert!(stderr(&o).contains("may both write r.partial.svg"), "{}", stderr(&o));
    let o = multibody(&dir, &["sweep", "r.partial.dyad", "--param", "body.m=1,2", "--out", "r.dyad"]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&model).unwrap(), text);
}

/// `--out /dev/null` used to replace the device node by a regular file
/// (as root, the real `/dev/null`). Devices, FIFOs and folders are refused
/// before anything runs, under their own name or a link to them. The test
/// names devices only through links and copies in its own folder: should
/// the refusal ever break, a link or a copy is replaced, never /dev/null.
#[test]
fn outputs_must_be_regular_files_or_new_paths() {
    let dir = scratch("special-outputs");
    let pendulum = example("pendulum.dyad");
    let fifo = dir.join("fifo.csv");
    let made = Command::new("mkfifo").arg(&fifo).status().expect("mkfifo runs");
    assert!(made.success());
    std::os::unix::fs::symlink("/dev/null", dir.join("null-link.csv")).unwrap();
    std::os::unix::fs::symlink("/dev/full", dir.join("full-link.svg")).unwrap();
    std::os::unix::fs::symlink("/dev/zero", dir.join("zero-link.html")).unwrap();
    std::fs::create_dir(dir.join("folder.csv")).unwrap();
    let mut cases: Vec<(&[&str], &str)> = vec![
        (&["--out", "null-link.csv"], "`--out null-link.csv`: it is a device, not a regular file"),
        (&["--out", "fifo.csv"], "it is a FIFO (named pipe)"),
        (&["--out", "folder.csv"], "it is a folder"),
        (&["--plot", "full-link.svg"], "`--plot full-link.svg`: it is a device"),
        (&["--animate", "zero-link.html"], "`--animate zero-link.html`: it is a device"),
    ];
    // A copy of /dev/null (a device node of its own) where the test may make one (as root).
    let copied = Command::new("mknod").arg(dir.join("null-copy.csv")).args(["c", "1", "3"]).status();
    if copied.is_ok_and(|s| s.success()) {
        cases.push((&["--out", "null-copy.csv"], "`--out null-copy.csv`: it is a device"));
    }
    for (options, message) in cases {
        let mut args = vec!["run", pendulum.as_str(), "--stop", "0.1"];
        args.extend_from_slice(options);
        let o = multibody(&dir, &args);
        assert_eq!(code(&o), 2, "{options:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(message), "{options:?}: {}", stderr(&o));
        assert!(!stderr(&o).contains("Simulating"), "{options:?}: refused before the run");
    }
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo(), "the FIFO stays");
    assert!(std::fs::symlink_metadata(dir.join("null-link.csv")).unwrap().file_type().is_symlink());
    // The partial name is checked too: a FIFO there would be replaced by a failing run.
    let made = Command::new("mkfifo").arg(dir.join("r.partial.csv")).status().expect("mkfifo runs");
    assert!(made.success());
    let o = multibody(&dir, &["run", &pendulum, "--stop", "0.1", "--out", "r.csv"]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert!(stderr(&o).contains("would keep its results as r.partial.csv, which is a FIFO"), "{}", stderr(&o));
    // A sweep's output too.
    let o = multibody(&dir, &["sweep", &pendulum, "--param", "body.m=1,2", "--out", "null-link.csv"]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert!(stderr(&o).contains("it is a device"), "{}", stderr(&o));
}

/// `--reltol 1` was accepted without a word (a damped pendulum ended at
/// 69 rad instead of -1.68); `--abstol 1e-300` too. Both run, with a
/// warning that says what they do to the result; `check` warns about an
/// analysis's own.
#[test]
fn tolerances_that_spoil_the_result_are_warned_about() {
    let dir = scratch("tolerance-warnings");
    let pendulum = example("pendulum.dyad");
    let o = multibody(&dir, &["run", &pendulum, "--stop", "0.5", "--reltol", "1"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("warning: --reltol 1: `reltol` = 1 lets each step err by 100% of the state"), "{err}");
    assert!(err.contains("far from the true motion"), "{err}");
    let o = multibody(&dir, &["run", &pendulum, "--stop", "0.2", "--abstol", "1e-300", "--reltol", "1e-14"]);
    let err = stderr(&o);
    assert!(
        err.contains("warning: --abstol 1e-300: `abstol` = 1e-300 is below what double precision resolves"),
        "{err}"
    );
    if code(&o) == 3 {
        assert!(err.contains("the tolerances warned about above may be why"), "{err}");
    }
    // The defaults and ordinary choices say nothing.
    let o = multibody(&dir, &["run", &pendulum, "--stop", "0.2", "--reltol", "1e-3", "--abstol", "1e-10"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(!stderr(&o).contains("warning"), "{}", stderr(&o));
    // An analysis's own loose tolerance, in `check`.
    let text = std::fs::read_to_string(&pendulum).unwrap().replace("stop = 5", "stop = 5, reltol = 0.1");
    std::fs::write(dir.join("loose.dyad"), text).unwrap();
    let o = multibody(&dir, &["check", "loose.dyad"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("`reltol` = 0.1 lets each step err by 10% of the state"), "{out}");
}

/// A model "file" that is a FIFO nobody writes to blocked for ever; a
/// device (`/dev/zero`) was read without end. The FIFO is given up after a
/// few seconds with a message, the device refused; a FIFO that is written
/// (`<(...)`, a pipe) still reads.
#[test]
fn a_model_from_a_fifo_without_writer_or_a_device_is_refused() {
    let dir = scratch("fifo-input");
    let fifo = dir.join("model.dyad");
    assert!(Command::new("mkfifo").arg(&fifo).status().expect("mkfifo runs").success());
    let started = std::time::Instant::now();
    let o = multibody(&dir, &["check", "model.dyad"]);
    assert_eq!(code(&o), 4, "{}", stderr(&o));
    assert!(stderr(&o).contains("nothing writes to the FIFO model.dyad (waited 5 s)"), "{}", stderr(&o));
    assert!(started.elapsed().as_secs() < 60, "gave up in {:?}", started.elapsed());
    for device in ["/dev/zero", "/dev/urandom"] {
        let o = multibody(&dir, &["run", device]);
        assert_eq!(code(&o), 2, "{}", stderr(&o));
        assert!(stderr(&o).contains(&format!("{device} is a device, not a model file")), "{}", stderr(&o));
    }
    // A writer: the model reads as from a file.
    let text = std::fs::read(example("pendulum.dyad")).unwrap();
    let writer = std::thread::spawn(move || std::fs::write(fifo, text));
    let o = multibody(&dir, &["check", "model.dyad"]);
    writer.join().unwrap().unwrap();
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("analysis PendulumSimulation"));
}
