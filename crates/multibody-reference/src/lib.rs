//! Test support shared by the crates' tests: where the reference data is
//! (outside the repository, found through `MULTIBODY_REFERENCE`), reading
//! its CSV files, and the tube comparison its README describes.

use multibody::Solution;
use std::path::{Path, PathBuf};

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

/// Signals over time, from a CSV file or a simulation.
pub trait Signals {
    fn times(&self) -> &[f64];
    fn signal(&self, name: &str) -> Option<&[f64]>;
    fn label(&self) -> &str;
}

/// A CSV table: quoted names (they may contain commas), times with
/// duplicates removed (the last row of each time is kept, as the reference
/// README asks).
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
        let header = split_header(lines.next().unwrap_or_default());
        let mut time: Vec<f64> = Vec::new();
        let mut columns = vec![Vec::new(); header.len().saturating_sub(1)];
        for line in lines.filter(|l| !l.trim().is_empty()) {
            let values: Vec<f64> = line
                .split(',')
                .map(|s| s.trim().parse().unwrap_or_else(|_| panic!("{}: not a number in {line}", path.display())))
                .collect();
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
        let name = path.file_stem().map_or_else(String::new, |s| s.to_string_lossy().into_owned());
        Self { name, names: header.into_iter().skip(1).collect(), time, columns }
    }

    /// `msl/NAME.csv` of the reference folder.
    pub fn reference(name: &str) -> Self {
        Self::load(&reference_dir().join("msl").join(format!("{name}.csv")))
    }

    pub fn column(&self, name: &str) -> &[f64] {
        self.signal(name).unwrap_or_else(|| panic!("{} has no column {name}", self.name))
    }

    pub fn stop(&self) -> f64 {
        *self.time.last().expect("an empty table")
    }

    /// The rows up to time `stop`.
    pub fn until(&self, stop: f64) -> Table {
        let n = self.time.partition_point(|&t| t <= stop);
        Table {
            name: self.name.clone(),
            names: self.names.clone(),
            time: self.time[..n].to_vec(),
            columns: self.columns.iter().map(|c| c[..n].to_vec()).collect(),
        }
    }

    /// The output interval.
    pub fn interval(&self) -> f64 {
        self.time[1] - self.time[0]
    }
}

impl Signals for Table {
    fn times(&self) -> &[f64] {
        &self.time
    }
    fn signal(&self, name: &str) -> Option<&[f64]> {
        self.names.iter().position(|n| n == name).map(|i| self.columns[i].as_slice())
    }
    fn label(&self) -> &str {
        &self.name
    }
}

impl Signals for Solution {
    fn times(&self) -> &[f64] {
        self.time()
    }
    fn signal(&self, name: &str) -> Option<&[f64]> {
        self.get(name)
    }
    fn label(&self) -> &str {
        "simulation"
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

/// The tube half-height for signals that are zero up to rounding noise
/// (the formula gives them a zero-height tube): they must stay below an
/// absolute 1e-9, far stricter than any real tube here.
pub const ZERO_SIGNAL_HALF_HEIGHT: f64 = 1e-9;

/// How one signal compared.
pub struct SignalReport {
    pub name: String,
    /// Largest deviation outside the reference's time window, over the tube
    /// half-height (pass: <= 1).
    pub tube_fraction: f64,
    /// Largest plain difference at equal times, over the tube half-height.
    pub pointwise_fraction: f64,
}

/// Compares `ours` with the reference signal by signal, pairing
/// `(reference name, our name)`, with the tube of the reference README:
/// half-height 0.2 % of the signal's range `max(y_max - y_min, |y_min|)`,
/// half-width 0.2 % of the time span. Prints the worst fractions; panics if
/// any sample leaves its tube or our run does not cover the reference's.
pub fn assert_within_tube(reference: &Table, ours: &impl Signals, pairs: &[(&str, &str)]) -> Vec<SignalReport> {
    let span = reference.stop() - reference.time[0];
    let half_width = 2e-3 * span;
    let our_stop = ours.times().last().copied().unwrap_or(f64::NEG_INFINITY);
    assert!(
        (our_stop - reference.stop()).abs() <= half_width,
        "{}: our run ends at {our_stop}, the reference at {}",
        reference.name,
        reference.stop()
    );
    let mut reports = Vec::new();
    for &(ref_name, our_name) in pairs {
        let y_ref = reference.column(ref_name);
        let y_ours = ours.signal(our_name).unwrap_or_else(|| panic!("{} has no signal {our_name}", ours.label()));
        let (lo, hi) = y_ref.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &y| (a.min(y), b.max(y)));
        let half_height = (2e-3 * (hi - lo).max(lo.abs())).max(ZERO_SIGNAL_HALF_HEIGHT);
        let (mut tube, mut pointwise) = (0.0f64, 0.0f64);
        let mut k0 = 0;
        for (i, &t) in reference.time.iter().enumerate() {
            let y = interp(ours.times(), y_ours, t);
            pointwise = pointwise.max((y - y_ref[i]).abs() / half_height);
            // The reference's extent over [t - w, t + w].
            while reference.time[k0] < t - half_width {
                k0 += 1;
            }
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
            tube = tube.max((lo_w - y).max(y - hi_w).max(0.0) / half_height);
        }
        reports.push(SignalReport { name: ref_name.into(), tube_fraction: tube, pointwise_fraction: pointwise });
    }
    println!("{}: worst error as a fraction of the tube (pass <= 1); pointwise = at equal times", reference.name);
    for r in &reports {
        println!("  {:40} tube {:8.4}   pointwise {:8.4}", r.name, r.tube_fraction, r.pointwise_fraction);
    }
    let failed: Vec<&str> = reports.iter().filter(|r| r.tube_fraction > 1.0).map(|r| r.name.as_str()).collect();
    assert!(failed.is_empty(), "{}: signals left the tube: {failed:?}", reference.name);
    reports
}

/// Pairs of equal names.
pub fn same<'a>(names: &[&'a str]) -> Vec<(&'a str, &'a str)> {
    names.iter().map(|n| (*n, *n)).collect()
}

/// `(reference name, our name)` for the three components of vectors, e.g.
/// `vector_pairs("body.body", "body", &["w_a"])` pairs `body.body.w_a[1]` with `body.w_a[1]`, ...
pub fn vector_pairs(theirs: &str, ours: &str, names: &[&str]) -> Vec<(String, String)> {
    names
        .iter()
        .flat_map(|n| (1..=3).map(move |i| (format!("{theirs}.{n}[{i}]"), format!("{ours}.{n}[{i}]"))))
        .collect()
}

/// Borrowed pairs, as `assert_within_tube` takes them.
pub fn as_pairs(pairs: &[(String, String)]) -> Vec<(&str, &str)> {
    pairs.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect()
}

/// `exp(A t)` of a real 2x2 matrix, in closed form (Cayley-Hamilton): with
/// `s` half the trace and `q² = s² - det`, `exp(A t) = exp(s t) (c I + g
/// (A - s I))`, where `c = cosh(q t)` and `g = sinh(q t) / q` (cos and sin
/// for `q² < 0`; `c = 1`, `g = t` for `q = 0`). The closed form of linear
/// models of two states (a DC motor's current and speed).
pub fn expm2(a: [[f64; 2]; 2], t: f64) -> [[f64; 2]; 2] {
    let s = (a[0][0] + a[1][1]) / 2.0;
    let q2 = s * s - (a[0][0] * a[1][1] - a[0][1] * a[1][0]);
    let (c, g) = if q2 > 0.0 {
        let q = q2.sqrt();
        ((q * t).cosh(), (q * t).sinh() / q)
    } else if q2 < 0.0 {
        let q = (-q2).sqrt();
        ((q * t).cos(), (q * t).sin() / q)
    } else {
        (1.0, t)
    };
    let e = (s * t).exp();
    [[e * (c + g * (a[0][0] - s)), e * g * a[0][1]], [e * g * a[1][0], e * (c + g * (a[1][1] - s))]]
}

/// Classical RK4 with a fixed step, written here independently of the
/// engine: returns the state at `t = n * dt * every` for `n` in
/// `0..samples` (`every` steps per output sample). A reference for models
/// whose closed form is an ODE of a few states.
pub fn rk4<const N: usize>(
    f: impl Fn(&[f64; N]) -> [f64; N],
    y0: [f64; N],
    dt: f64,
    samples: usize,
    every: usize,
) -> Vec<[f64; N]> {
    let mut y = y0;
    let mut out = vec![y];
    let axpy = |y: &[f64; N], a: f64, k: &[f64; N]| -> [f64; N] { std::array::from_fn(|i| y[i] + a * k[i]) };
    for _ in 1..samples {
        for _ in 0..every {
            let k1 = f(&y);
            let k2 = f(&axpy(&y, dt / 2.0, &k1));
            let k3 = f(&axpy(&y, dt / 2.0, &k2));
            let k4 = f(&axpy(&y, dt, &k3));
            for i in 0..N {
                y[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
        out.push(y);
    }
    out
}

/// The period of a pendulum of length `length` released at rest from the
/// angle `theta0`: `4 K(sin(theta0 / 2)) sqrt(length / g)`, the complete
/// elliptic integral `K(k) = pi / (2 agm(1, sqrt(1 - k^2)))` by the
/// arithmetic-geometric mean.
pub fn pendulum_period(length: f64, g: f64, theta0: f64) -> f64 {
    let k = (theta0 / 2.0).sin();
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    for _ in 0..30 {
        (a, b) = ((a + b) / 2.0, (a * b).sqrt());
    }
    2.0 * std::f64::consts::PI / a * (length / g).sqrt()
}
