//! Test support: running the built `multibody` command, reading CSV files,
//! and the tube comparison of shared/reference/msl/README.md (the logic of
//! the engine's tests/common, for CSV files instead of solutions).
#![allow(dead_code)]

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

/// A file of this crate's tests, or of the repository's examples, by path from the crate.
pub fn crate_path(relative: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(relative).display().to_string()
}

/// The reference folder: `$MULTIBODY_REFERENCE`, or `../shared/reference`
/// next to the repository. Panics with instructions when it is missing.
pub fn reference_dir() -> PathBuf {
    let dir = match std::env::var_os("MULTIBODY_REFERENCE") {
        Some(d) => PathBuf::from(d),
        None => PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/reference"),
    };
    assert!(
        dir.join("msl").is_dir(),
        "reference data not found at {}: set MULTIBODY_REFERENCE to the folder holding msl/ (the Modelica reference results)",
        dir.display()
    );
    dir
}

/// A CSV of signals over time: times (a repeated time keeps its last row)
/// and named columns.
pub struct Table {
    pub name: String,
    pub names: Vec<String>,
    pub time: Vec<f64>,
    pub columns: Vec<Vec<f64>>,
}

impl Table {
    pub fn load(path: &Path) -> Self {
        let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
        let mut lines = text.lines();
        let header = split_header(lines.next().expect("a header"));
        assert_eq!(header[0], "time", "{}: the first column is not time", path.display());
        let mut time: Vec<f64> = Vec::new();
        let mut columns = vec![Vec::new(); header.len() - 1];
        for line in lines.filter(|l| !l.trim().is_empty()) {
            let values: Vec<f64> = line
                .split(',')
                .map(|s| s.trim().parse().unwrap_or_else(|_| panic!("{}: not a number in `{line}`", path.display())))
                .collect();
            assert_eq!(values.len(), header.len(), "{}: a row has the wrong length", path.display());
            if time.last() == Some(&values[0]) {
                time.pop();
                columns.iter_mut().for_each(|c| {
                    c.pop();
                });
            }
            time.push(values[0]);
            for (c, v) in columns.iter_mut().zip(&values[1..]) {
                c.push(*v);
            }
        }
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        Self { name, names: header[1..].to_vec(), time, columns }
    }

    pub fn reference(name: &str) -> Self {
        Self::load(&reference_dir().join("msl").join(format!("{name}.csv")))
    }

    pub fn column(&self, name: &str) -> &[f64] {
        let i =
            self.names.iter().position(|n| n == name).unwrap_or_else(|| panic!("{} has no column {name}", self.name));
        &self.columns[i]
    }

    pub fn stop(&self) -> f64 {
        *self.time.last().unwrap()
    }
}

/// The fields of a CSV header line; quoted fields may contain commas.
fn split_header(line: &str) -> Vec<String> {
    let mut fields = vec![String::new()];
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' if quoted && chars.peek() == Some(&'"') => {
                chars.next();
                fields.last_mut().unwrap().push('"');
            }
            '"' => quoted = !quoted,
            ',' if !quoted => fields.push(String::new()),
            c => fields.last_mut().unwrap().push(c),
        }
    }
    fields
}

/// Linear interpolation of (time, values) at t.
fn interp(time: &[f64], values: &[f64], t: f64) -> f64 {
    let k = time.partition_point(|&s| s < t);
    if k == 0 {
        return values[0];
    }
    if k >= time.len() {
        return *values.last().unwrap();
    }
    let w = (t - time[k - 1]) / (time[k] - time[k - 1]);
    values[k - 1] * (1.0 - w) + values[k] * w
}

/// Compares `ours` with `reference` signal by signal with the tube of the
/// reference README: half-height 0.2 % of `max(y_max - y_min, |y_min|)`,
/// half-width 0.2 % of the time span. Prints each signal's worst error as
/// a fraction of its tube; panics if any sample leaves its tube.
pub fn assert_within_tube(reference: &Table, ours: &Table, signals: &[&str]) {
    let span = reference.stop() - reference.time[0];
    let half_width = 2e-3 * span;
    assert!(
        (ours.stop() - reference.stop()).abs() <= half_width,
        "{}: our run ends at {}, the reference at {}",
        reference.name,
        ours.stop(),
        reference.stop()
    );
    println!("{}: worst error as a fraction of the tube (pass <= 1)", reference.name);
    let mut failed = Vec::new();
    for &name in signals {
        let y_ref = reference.column(name);
        let y_ours = ours.column(name);
        let (lo, hi) = y_ref.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &y| (a.min(y), b.max(y)));
        let half_height = 2e-3 * (hi - lo).max(lo.abs()).max(1e-300);
        let mut worst = 0.0f64;
        let mut k0 = 0;
        for &t in &reference.time {
            let y = interp(&ours.time, y_ours, t);
            while reference.time[k0] < t - half_width {
                k0 += 1;
            }
            // The reference's extent over [t - w, t + w].
            let (mut lo_w, mut hi_w) =
                (interp(&reference.time, y_ref, t - half_width), interp(&reference.time, y_ref, t + half_width));
            if lo_w > hi_w {
                std::mem::swap(&mut lo_w, &mut hi_w);
            }
            let mut k = k0;
            while k < reference.time.len() && reference.time[k] <= t + half_width {
                lo_w = lo_w.min(y_ref[k]);
                hi_w = hi_w.max(y_ref[k]);
                k += 1;
            }
            let outside = (lo_w - y).max(y - hi_w).max(0.0);
            worst = worst.max(outside / half_height);
        }
        println!("  {name:30} {worst:8.4}");
        if worst > 1.0 {
            failed.push(name);
        }
    }
    assert!(failed.is_empty(), "{}: signals left the tube: {failed:?}", reference.name);
}
