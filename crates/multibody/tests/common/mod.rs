//! Shared test support: the reference data (outside the repository, found
//! through `MULTIBODY_REFERENCE`) and the tube comparison of its README.
#![allow(dead_code)]

use multibody::Solution;
use std::path::PathBuf;

/// The reference folder: `$MULTIBODY_REFERENCE`, or `../shared/reference`
/// next to the repository. Panics with instructions when it is missing.
pub fn reference_dir() -> PathBuf {
    let dir = match std::env::var_os("MULTIBODY_REFERENCE") {
        Some(d) => PathBuf::from(d),
        None => PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/reference"),
    };
    assert!(
        dir.join("msl").is_dir(),
        "reference data not found at {}: set MULTIBODY_REFERENCE to the folder holding msl/, analytic/ and chain_reference_ddq.json",
        dir.display()
    );
    dir
}

/// A reference CSV: times (duplicates removed, keeping the last row of
/// each time) and named columns.
pub struct Reference {
    pub name: String,
    pub names: Vec<String>,
    pub time: Vec<f64>,
    pub columns: Vec<Vec<f64>>,
}

impl Reference {
    pub fn load(name: &str) -> Self {
        let path = reference_dir().join("msl").join(format!("{name}.csv"));
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
        let mut lines = text.lines();
        let header: Vec<String> = lines.next().unwrap().split(',').map(|s| s.trim_matches('"').to_string()).collect();
        let mut time: Vec<f64> = Vec::new();
        let mut columns = vec![Vec::new(); header.len() - 1];
        for line in lines.filter(|l| !l.trim().is_empty()) {
            let values: Vec<f64> = line.split(',').map(|s| s.trim().parse().unwrap()).collect();
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
        Self { name: name.into(), names: header[1..].to_vec(), time, columns }
    }

    pub fn column(&self, name: &str) -> &[f64] {
        let i =
            self.names.iter().position(|n| n == name).unwrap_or_else(|| panic!("{} has no column {name}", self.name));
        &self.columns[i]
    }

    pub fn stop(&self) -> f64 {
        *self.time.last().unwrap()
    }

    /// The output interval of the reference.
    pub fn interval(&self) -> f64 {
        self.time[1] - self.time[0]
    }
}

/// The tube half-height for signals that are zero up to rounding noise.
pub const ZERO_SIGNAL_HALF_HEIGHT: f64 = 1e-9;

/// How one signal compared.
pub struct SignalReport {
    pub name: String,
    /// Largest deviation outside the reference's time window, over the tube half-height (pass: <= 1).
    pub tube_fraction: f64,
    /// Largest plain difference at equal times, over the tube half-height.
    pub pointwise_fraction: f64,
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

/// Compares `ours` with the reference signal by signal, with the tube of
/// the reference README: half-height 0.2 % of the signal's range
/// `max(y_max - y_min, |y_min|)`, half-width 0.2 % of the time span. Prints
/// the worst fractions; panics if any sample leaves its tube.
pub fn assert_within_tube(reference: &Reference, ours: &Solution, pairs: &[(&str, &str)]) -> Vec<SignalReport> {
    let span = reference.stop() - reference.time[0];
    let half_width = 2e-3 * span;
    let mut reports = Vec::new();
    for &(ref_name, our_name) in pairs {
        let y_ref = reference.column(ref_name);
        let y_ours = ours.get(our_name).unwrap_or_else(|| panic!("our solution has no signal {our_name}"));
        let (lo, hi) = y_ref.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &y| (a.min(y), b.max(y)));
        // A signal that is zero by symmetry (range and value ~1e-16 or exactly 0)
        // gets a zero-height tube by the formula; it must then stay below an
        // absolute 1e-9, far stricter than any real tube here.
        let half_height = (2e-3 * (hi - lo).max(lo.abs())).max(ZERO_SIGNAL_HALF_HEIGHT);
        let (mut tube, mut pointwise) = (0.0f64, 0.0f64);
        let mut k0 = 0;
        for (i, &t) in reference.time.iter().enumerate() {
            let y = interp(ours.time(), y_ours, t);
            pointwise = pointwise.max((y - y_ref[i]).abs() / half_height);
            // The reference's extent over [t - w, t + w].
            while reference.time[k0] < t - half_width {
                k0 += 1;
            }
            let (mut wlo, mut whi) =
                (interp(&reference.time, y_ref, t - half_width), interp(&reference.time, y_ref, t + half_width));
            if wlo > whi {
                std::mem::swap(&mut wlo, &mut whi);
            }
            let mut k = k0;
            while k < reference.time.len() && reference.time[k] <= t + half_width {
                wlo = wlo.min(y_ref[k]);
                whi = whi.max(y_ref[k]);
                k += 1;
            }
            let outside = (wlo - y).max(y - whi).max(0.0);
            tube = tube.max(outside / half_height);
        }
        reports.push(SignalReport { name: ref_name.into(), tube_fraction: tube, pointwise_fraction: pointwise });
    }
    println!("{}: worst error as a fraction of the tube (pass <= 1); pointwise = at equal times", reference.name);
    for r in &reports {
        println!("  {:40} tube {:8.4}   pointwise {:8.4}", r.name, r.tube_fraction, r.pointwise_fraction);
    }
    let failed: Vec<&SignalReport> = reports.iter().filter(|r| r.tube_fraction > 1.0).collect();
    assert!(
        failed.is_empty(),
        "{}: signals left the tube: {:?}",
        reference.name,
        failed.iter().map(|r| &r.name).collect::<Vec<_>>()
    );
    reports
}
