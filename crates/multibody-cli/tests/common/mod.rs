//! Test support: running the built `multibody` command; the reference data
//! and its tube comparison come from the `multibody-reference` crate.
#![allow(dead_code)]

pub mod examples;

use std::path::{Path, PathBuf};

use std::process::{Command, Output};

/// Runs `multibody` with `args` in `dir`.
pub fn multibody(dir: &Path, args: &[&str]) -> Output {
    std::fs::create_dir_all(dir).unwrap();
    Command::new(env!("CARGO_BIN_EXE_multibody"))
        .args(args)
        .current_dir(dir)
        .env("NO_COLOR", "1")
        .output()
        .expect("the multibody binary runs")
}

/// A fresh scratch folder for one test.
pub fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// What a run printed on stderr and stdout, and its exit code.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

pub fn code(o: &Output) -> i32 {
    o.status.code().expect("exited normally")
}

/// The path of an example model, `examples/NAME`.
pub fn example(name: &str) -> String {
    crate_path(&format!("../../examples/{name}"))
}

/// A file of this crate's tests, or of the repository's examples, by path from the crate.
pub fn crate_path(relative: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(relative).display().to_string()
}

pub use multibody_reference::Table;

/// Compares a CSV of ours with the reference for signals of the same name.
pub fn assert_within_tube(reference: &Table, ours: &Table, signals: &[&str]) {
    multibody_reference::assert_within_tube(reference, ours, &multibody_reference::same(signals));
}

/// Compares a CSV of ours with the reference, pairing `(reference name, our name)`.
pub fn assert_pairs_within_tube(reference: &Table, ours: &Table, pairs: &[(&str, &str)]) {
    multibody_reference::assert_within_tube(reference, ours, pairs);
}
