//! Independent helpers for the physics tests: small vector and rotation
//! algebra written from the library's documented conventions (DESIGN.md),
//! not taken from the engine, plus reading signals out of a `Solution`,
//! finite differences and a checker that prints the worst error against
//! its tolerance.
//!
//! Include it with `#[path = "common/physics.rs"] mod physics;`.
#![allow(dead_code)]

use multibody::{Model, SimulationOptions, Solution};

pub type V3 = [f64; 3];
pub type M3 = [[f64; 3]; 3];

pub const G: f64 = 9.80665;
pub const MU: f64 = 3.986004418e14;

// ---------------------------------------------------------------- vectors

pub fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
pub fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub fn scale(s: f64, a: V3) -> V3 {
    [s * a[0], s * a[1], s * a[2]]
}
pub fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub fn cross(a: V3, b: V3) -> V3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}
pub fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}
pub fn normalize(a: V3) -> V3 {
    scale(1.0 / norm(a), a)
}
/// Largest absolute component of `a - b`.
pub fn dist(a: V3, b: V3) -> f64 {
    (0..3).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max)
}

// --------------------------------------------------------------- matrices

pub const IDENTITY: M3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

pub fn mat_vec(m: &M3, v: V3) -> V3 {
    [dot(m[0], v), dot(m[1], v), dot(m[2], v)]
}
/// `m' * v`
pub fn mat_t_vec(m: &M3, v: V3) -> V3 {
    let mut out = [0.0; 3];
    for i in 0..3 {
        for j in 0..3 {
            out[j] += m[i][j] * v[i];
        }
    }
    out
}
pub fn mat_mul(a: &M3, b: &M3) -> M3 {
    let mut out = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            out[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    out
}
pub fn transpose(a: &M3) -> M3 {
    let mut out = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            out[i][j] = a[j][i];
        }
    }
    out
}
/// Largest absolute entry of `a - b`.
pub fn mat_dist(a: &M3, b: &M3) -> f64 {
    let mut worst = 0.0f64;
    for i in 0..3 {
        for j in 0..3 {
            worst = worst.max((a[i][j] - b[i][j]).abs());
        }
    }
    worst
}
/// The skew matrix `[v]x` with `[v]x u = v x u`.
pub fn skew(v: V3) -> M3 {
    [[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]]
}

// -------------------------------------------------------------- rotations
// All rotation matrices map world coordinates to frame coordinates
// (`v_frame = R v_world`), as in DESIGN.md.

/// `A_x(a) = [1 0 0; 0 c s; 0 -s c]`.
pub fn a_x(a: f64) -> M3 {
    let (s, c) = a.sin_cos();
    [[1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c]]
}
/// `A_y(a) = [c 0 -s; 0 1 0; s 0 c]` (A_x's pattern on the axes z, x).
pub fn a_y(a: f64) -> M3 {
    let (s, c) = a.sin_cos();
    [[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]]
}
/// `A_z(a) = [c s 0; -s c 0; 0 0 1]` (A_x's pattern on the axes x, y).
pub fn a_z(a: f64) -> M3 {
    let (s, c) = a.sin_cos();
    [[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]]
}
/// `A_1`, `A_2`, `A_3` by 1-based axis number.
pub fn a_axis(axis: usize, a: f64) -> M3 {
    match axis {
        1 => a_x(a),
        2 => a_y(a),
        3 => a_z(a),
        _ => panic!("axis {axis}"),
    }
}
pub fn e(axis: usize) -> V3 {
    let mut v = [0.0; 3];
    v[axis - 1] = 1.0;
    v
}

/// Rotation by `angle` about the unit axis `n` (Modelica's planarRotation):
/// `n n' + (I - n n') cos(angle) - [n]x sin(angle)`. About a coordinate
/// axis it is `A_x`, `A_y`, `A_z`.
pub fn planar(n: V3, angle: f64) -> M3 {
    let n = normalize(n);
    let (s, c) = angle.sin_cos();
    let k = skew(n);
    let mut r = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            let nn = n[i] * n[j];
            r[i][j] = nn + (IDENTITY[i][j] - nn) * c - k[i][j] * s;
        }
    }
    r
}

/// `R = A_k(phi3) A_j(phi2) A_i(phi1)` for `sequence = [i, j, k]`.
pub fn euler_r(sequence: [usize; 3], phi: V3) -> M3 {
    let [i, j, k] = sequence;
    mat_mul(&a_axis(k, phi[2]), &mat_mul(&a_axis(j, phi[1]), &a_axis(i, phi[0])))
}

/// `w = e_k phid3 + A_k e_j phid2 + A_k A_j e_i phid1` (resolved in the frame).
pub fn euler_w(sequence: [usize; 3], phi: V3, phid: V3) -> V3 {
    let [i, j, k] = sequence;
    let ak = a_axis(k, phi[2]);
    let akaj = mat_mul(&ak, &a_axis(j, phi[1]));
    add(add(scale(phid[2], e(k)), scale(phid[1], mat_vec(&ak, e(j)))), scale(phid[0], mat_vec(&akaj, e(i))))
}

/// `R = (2 p0^2 - 1) I + 2 (p p' - p0 [p]x)` of a unit quaternion `[w, i, j, k]`.
pub fn r_from_quat(q: [f64; 4]) -> M3 {
    let p0 = q[0];
    let p = [q[1], q[2], q[3]];
    let k = skew(p);
    let mut r = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            r[i][j] = (2.0 * p0 * p0 - 1.0) * IDENTITY[i][j] + 2.0 * (p[i] * p[j] - p0 * k[i][j]);
        }
    }
    r
}

/// The quaternion (with `w > 0`) of `R` in the convention of `r_from_quat`:
/// `trace R = 4 p0^2 - 1` and `R - R' = -4 p0 [p]x`. Checked by rebuilding
/// `R` (valid away from rotations by pi, which the tests avoid).
pub fn quat_from_r(r: &M3) -> [f64; 4] {
    let trace = r[0][0] + r[1][1] + r[2][2];
    let p0 = (1.0 + trace).sqrt() / 2.0;
    assert!(p0 > 0.1, "quat_from_r is only used away from rotations by pi");
    let q = [p0, (r[1][2] - r[2][1]) / (4.0 * p0), (r[2][0] - r[0][2]) / (4.0 * p0), (r[0][1] - r[1][0]) / (4.0 * p0)];
    assert!(mat_dist(&r_from_quat(q), r) < 1e-14, "quat_from_r does not invert r_from_quat");
    q
}

/// The angular velocity resolved in the frame from `R` and `dR/dt`:
/// `dR/dt = -[w]x R`, so `[w]x = -dR/dt R'`.
pub fn w_from_rdot(r: &M3, rdot: &M3) -> V3 {
    let wx = mat_mul(rdot, &transpose(r));
    // [w]x = -wx
    [-wx[2][1] * 0.5 + wx[1][2] * 0.5, -wx[0][2] * 0.5 + wx[2][0] * 0.5, -wx[1][0] * 0.5 + wx[0][1] * 0.5]
}

// ------------------------------------------------------------- solutions

/// The samples of a signal; panics with the signals of that component when
/// the name is wrong.
pub fn sig<'a>(sol: &'a Solution, name: &str) -> &'a [f64] {
    sol.get(name).unwrap_or_else(|| {
        let component = name.split('.').next().unwrap_or(name);
        let names: Vec<&String> = sol.names().iter().filter(|n| n.starts_with(component)).collect();
        panic!("no signal {name}; the signals of {component} are {names:?}")
    })
}

/// `prefix[1..3]` at sample `k`, e.g. `v3(sol, "body.r_0", k)`.
pub fn v3(sol: &Solution, prefix: &str, k: usize) -> V3 {
    [sig(sol, &format!("{prefix}[1]"))[k], sig(sol, &format!("{prefix}[2]"))[k], sig(sol, &format!("{prefix}[3]"))[k]]
}

/// `prefix[i,j]` at sample `k` (row-major, 1-based names).
pub fn m3(sol: &Solution, prefix: &str, k: usize) -> M3 {
    let mut r = [[0.0; 3]; 3];
    for (i, row) in r.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = sig(sol, &format!("{prefix}[{},{}]", i + 1, j + 1))[k];
        }
    }
    r
}

/// `prefix[1..4]` at sample `k`.
pub fn v4(sol: &Solution, prefix: &str, k: usize) -> [f64; 4] {
    let mut q = [0.0; 4];
    for (i, x) in q.iter_mut().enumerate() {
        *x = sig(sol, &format!("{prefix}[{}]", i + 1))[k];
    }
    q
}

/// Simulation options: `abstol`, `reltol` and an output grid.
pub fn options(stop: f64, saveat: f64, abstol: f64, reltol: f64) -> SimulationOptions {
    SimulationOptions { stop, saveat, abstol, reltol, ..SimulationOptions::default() }
}

/// Assembles and simulates, panicking with the engine's message on failure.
pub fn run(model: &Model, opts: &SimulationOptions) -> Solution {
    let mechanism = model.assemble().unwrap_or_else(|e| panic!("{}: assembly failed: {e}", model.name));
    mechanism.simulate(opts).unwrap_or_else(|e| panic!("{}: simulation failed: {e}", model.name))
}

/// The largest error seen, and when.
#[derive(Clone, Copy, Debug)]
pub struct Worst {
    pub err: f64,
    pub t: f64,
}

impl Default for Worst {
    fn default() -> Self {
        Self { err: 0.0, t: f64::NAN }
    }
}

impl Worst {
    pub fn update(&mut self, err: f64, t: f64) {
        // A NaN error is the worst possible and stays.
        if self.err.is_nan() {
            return;
        }
        if err.is_nan() || err > self.err {
            self.err = err;
            self.t = t;
        }
    }

    /// Prints `what: worst ... (tolerance ...)` and asserts it is within.
    pub fn check(&self, what: &str, unit: &str, tolerance: f64) {
        println!("{what}: worst {:.3e} {unit} at t = {:.4} (tolerance {:.1e})", self.err, self.t, tolerance);
        assert!(
            self.err <= tolerance,
            "{what}: worst error {:e} {unit} at t = {} exceeds the tolerance {:e}",
            self.err,
            self.t,
            tolerance
        );
    }
}

/// The worst of `err(k)` over every sample `k`, with its time.
pub fn worst_over(sol: &Solution, mut err: impl FnMut(usize) -> f64) -> Worst {
    let mut w = Worst::default();
    for (k, &t) in sol.time().iter().enumerate() {
        w.update(err(k), t);
    }
    w
}

/// The fourth-order central difference of equally spaced samples at `k`
/// (needs two samples on each side): `(-x[k+2] + 8 x[k+1] - 8 x[k-1] + x[k-2]) / (12 h)`.
pub fn fd5(x: &[f64], h: f64, k: usize) -> f64 {
    (-x[k + 2] + 8.0 * x[k + 1] - 8.0 * x[k - 1] + x[k - 2]) / (12.0 * h)
}

/// The derivative at `k` of samples `h` apart, by Richardson extrapolation
/// of the 5-point stencil: `D = D(h) + (D(h) - D(2h)) / 15`, whose
/// truncation error is O(h^6) (needs four samples on each side). Returns
/// `D` and the size of the correction `|D(h) - D(2h)| / 15`, the estimated
/// truncation error of `D(h)`, which bounds that of `D` generously.
pub fn fd_richardson(x: &[f64], h: f64, k: usize) -> (f64, f64) {
    let d1 = fd5(x, h, k);
    let d2 = (-x[k + 4] + 8.0 * x[k + 2] - 8.0 * x[k - 2] + x[k - 4]) / (24.0 * h);
    (d1 + (d1 - d2) / 15.0, (d1 - d2).abs() / 15.0)
}

/// Sample errors of size `delta` change `fd_richardson` by at most
/// `FD_NOISE_GAIN * delta / h`: (16 * 18/12 + 18/24) / 15.
pub const FD_NOISE_GAIN: f64 = 1.65;

/// The samples with four neighbours on each side on a uniform grid of
/// step `h` (the last output interval may be shorter).
pub fn uniform_rows(t: &[f64], h: f64) -> Vec<usize> {
    if t.len() < 9 {
        return Vec::new();
    }
    (4..t.len() - 4).filter(|&i| (t[i + 4] - t[i - 4] - 8.0 * h).abs() < 1e-9 * h.max(1.0)).collect()
}

/// Checks that the signals `d` are the time derivatives of the signals `x`
/// (component by component), sampled `h` apart with errors up to
/// `sample_error`. The tolerance is 10 times the amplified sample error
/// plus the largest truncation estimate of the differences.
pub fn check_derivative(label: &str, unit: &str, t: &[f64], h: f64, x: &[Vec<f64>], d: &[Vec<f64>], sample_error: f64) {
    let mut worst = Worst::default();
    let mut truncation = 0.0f64;
    for i in uniform_rows(t, h) {
        for (xj, dj) in x.iter().zip(d) {
            let (fd, trunc) = fd_richardson(xj, h, i);
            truncation = truncation.max(trunc);
            worst.update((fd - dj[i]).abs(), t[i]);
        }
    }
    let noise = 10.0 * FD_NOISE_GAIN * sample_error / h;
    println!("{label}: finite-difference truncation estimate {truncation:.1e}, sample noise bound {noise:.1e}");
    worst.check(label, unit, noise + truncation);
}
