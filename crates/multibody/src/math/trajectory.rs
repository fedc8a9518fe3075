//! The math of the trajectory sources (Kinematic5, KinematicPTP,
//! KinematicPTPBoundedJerk and BlockComponents.KinematicPTP): position,
//! speed and acceleration as closed-form functions of time.
//!
//! Two shapes cover them all:
//! - [`Quintic`]: the fifth-order polynomial between two boundary states;
//! - [`Piecewise`]: a chain of segments of constant jerk, each starting with
//!   a given acceleration (so an acceleration may jump between segments, as
//!   in the bang-coast-bang profile of a point-to-point move, or run
//!   continuously, as in a jerk-limited move). Position and speed are
//!   continuous; within a segment they are the cubic and quadratic of the
//!   segment's jerk.
//!
//! [`Trajectory::jet`] gives the value and its derivatives up to the fourth
//! at any time; `value_and_derivatives` picks three consecutive ones, which
//! is what a signal source needs for its output (`q`, `qd` or `qdd`).

/// A trajectory of one axis.
#[derive(Clone, Debug, PartialEq)]
pub enum Trajectory {
    Quintic(Quintic),
    Piecewise(Piecewise),
}

impl Trajectory {
    /// Position and its first four time derivatives at `t`.
    pub fn jet(&self, t: f64) -> [f64; 5] {
        match self {
            Trajectory::Quintic(p) => p.jet(t),
            Trajectory::Piecewise(p) => p.jet(t),
        }
    }

    /// The derivative of order `order` (0: position, 1: speed, 2:
    /// acceleration, 3: jerk) and the next two: the value of a source that
    /// outputs that derivative, with its own first and second derivative.
    pub fn value_and_derivatives(&self, t: f64, order: usize) -> [f64; 3] {
        let j = self.jet(t);
        let at = |k: usize| j.get(k).copied().unwrap_or(0.0);
        [at(order), at(order + 1), at(order + 2)]
    }

    /// When the motion ends.
    pub fn end_time(&self) -> f64 {
        match self {
            Trajectory::Quintic(p) => p.tf,
            Trajectory::Piecewise(p) => p.end_time(),
        }
    }
}

/// The fifth-order polynomial on `0 <= t <= tf` that meets the position,
/// speed and acceleration given at both ends (Kinematic5). Before 0 and
/// after `tf` the axis moves on at its boundary speed (it rests there with
/// the default zero boundary speeds).
#[derive(Clone, Debug, PartialEq)]
pub struct Quintic {
    pub tf: f64,
    /// Coefficients of `t^0 .. t^5`.
    pub c: [f64; 6],
    pub start: [f64; 2],
    pub end: [f64; 2],
}

impl Quintic {
    /// Boundary states `[q, qd, qdd]` at 0 and at `tf > 0`.
    pub fn new(tf: f64, start: [f64; 3], end: [f64; 3]) -> Self {
        let [q0, v0, a0] = start;
        let [q1, v1, a1] = end;
        let (t2, t3) = (tf * tf, tf * tf * tf);
        let (t4, t5) = (t3 * tf, t3 * t2);
        // The first three coefficients come from the start; the last three
        // solve the end conditions (the classic closed form).
        let h = q1 - q0;
        let c3 = (20.0 * h - (8.0 * v1 + 12.0 * v0) * tf - (3.0 * a0 - a1) * t2) / (2.0 * t3);
        let c4 = (-30.0 * h + (14.0 * v1 + 16.0 * v0) * tf + (3.0 * a0 - 2.0 * a1) * t2) / (2.0 * t4);
        let c5 = (12.0 * h - 6.0 * (v1 + v0) * tf - (a0 - a1) * t2) / (2.0 * t5);
        Self { tf, c: [q0, v0, a0 / 2.0, c3, c4, c5], start: [q0, v0], end: [q1, v1] }
    }

    pub fn jet(&self, t: f64) -> [f64; 5] {
        if t < 0.0 {
            let [q, v] = self.start;
            return [q + v * t, v, 0.0, 0.0, 0.0];
        }
        if t > self.tf {
            let [q, v] = self.end;
            return [q + v * (t - self.tf), v, 0.0, 0.0, 0.0];
        }
        let c = &self.c;
        let q = c[0] + t * (c[1] + t * (c[2] + t * (c[3] + t * (c[4] + t * c[5]))));
        let qd = c[1] + t * (2.0 * c[2] + t * (3.0 * c[3] + t * (4.0 * c[4] + t * 5.0 * c[5])));
        let qdd = 2.0 * c[2] + t * (6.0 * c[3] + t * (12.0 * c[4] + t * 20.0 * c[5]));
        let qddd = 6.0 * c[3] + t * (24.0 * c[4] + t * 60.0 * c[5]);
        let qdddd = 24.0 * c[4] + t * 120.0 * c[5];
        [q, qd, qdd, qddd, qdddd]
    }
}

/// One piece of a [`Piecewise`] trajectory.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// When it starts.
    pub t: f64,
    /// Position, speed and acceleration at its start.
    pub q: f64,
    pub v: f64,
    pub a: f64,
    /// Its constant jerk.
    pub j: f64,
}

/// Segments of constant jerk from rest at `q_start` (before the first
/// segment) to rest at `q_end` (after `t_end`).
#[derive(Clone, Debug, PartialEq)]
pub struct Piecewise {
    pub segments: Vec<Segment>,
    pub t_start: f64,
    pub q_start: f64,
    pub t_end: f64,
    pub q_end: f64,
}

impl Piecewise {
    /// Chains pieces `(duration, acceleration at start, jerk)` from rest at
    /// `q` at time `t0`. The end position is where the chain arrives.
    pub fn chain(t0: f64, q: f64, pieces: &[(f64, f64, f64)]) -> Self {
        let mut segments = Vec::with_capacity(pieces.len());
        let (mut t, mut pos, mut vel) = (t0, q, 0.0);
        for &(d, a, j) in pieces.iter().filter(|p| p.0 > 0.0) {
            segments.push(Segment { t, q: pos, v: vel, a, j });
            pos += vel * d + a * d * d / 2.0 + j * d * d * d / 6.0;
            vel += a * d + j * d * d / 2.0;
            t += d;
        }
        Self { segments, t_start: t0, q_start: q, t_end: t, q_end: pos }
    }

    pub fn end_time(&self) -> f64 {
        self.t_end
    }

    pub fn jet(&self, t: f64) -> [f64; 5] {
        if self.segments.is_empty() || t < self.t_start {
            return [self.q_start, 0.0, 0.0, 0.0, 0.0];
        }
        if t >= self.t_end {
            return [self.q_end, 0.0, 0.0, 0.0, 0.0];
        }
        let k = self.segments.partition_point(|s| s.t <= t).max(1) - 1;
        let s = &self.segments[k];
        let d = t - s.t;
        [
            s.q + s.v * d + s.a * d * d / 2.0 + s.j * d * d * d / 6.0,
            s.v + s.a * d + s.j * d * d / 2.0,
            s.a + s.j * d,
            s.j,
            0.0,
        ]
    }
}

/// The fastest move from rest at `q0` to rest at `q1` starting at
/// `start_time` with speed at most `qd_max` and acceleration at most
/// `qdd_max` (both positive): accelerate at the limit, coast at the
/// speed limit if the distance allows it, brake at the limit. The
/// velocity is a trapezoid, or a triangle for short moves.
pub fn point_to_point(start_time: f64, q0: f64, q1: f64, qd_max: f64, qdd_max: f64) -> Piecewise {
    let distance = (q1 - q0).abs();
    let sign = if q1 >= q0 { 1.0 } else { -1.0 };
    let (v, a) = (qd_max.abs(), qdd_max.abs());
    if distance == 0.0 || v == 0.0 || a == 0.0 {
        return Piecewise::chain(start_time, q0, &[]);
    }
    let (t_acc, t_coast) =
        if distance >= v * v / a { (v / a, distance / v - v / a) } else { ((distance / a).sqrt(), 0.0) };
    let mut p =
        Piecewise::chain(start_time, q0, &[(t_acc, sign * a, 0.0), (t_coast, 0.0, 0.0), (t_acc, -sign * a, 0.0)]);
    // The chain lands on q1 up to rounding; make the rest exact.
    p.q_end = q1;
    p
}

/// The duration of the move of [`point_to_point`]: `d/v + v/a` when the
/// speed limit is reached (`d >= v^2/a`), `2 sqrt(d/a)` otherwise.
#[cfg(test)]
pub fn point_to_point_duration(distance: f64, qd_max: f64, qdd_max: f64) -> f64 {
    let (d, v, a) = (distance.abs(), qd_max.abs(), qdd_max.abs());
    if d >= v * v / a {
        d / v + v / a
    } else {
        2.0 * (d / a).sqrt()
    }
}

/// The time-optimal move from rest at `q0` to rest at `q1` starting at
/// `start_time` with speed, acceleration and jerk at most `qd_max`,
/// `qdd_max`, `qddd_max` (positive): the seven-phase double-S profile
/// (jerk up, hold acceleration, jerk down, coast, and the mirror image),
/// phases dropping out when a limit is not reached.
pub fn point_to_point_bounded_jerk(
    start_time: f64,
    q0: f64,
    q1: f64,
    qd_max: f64,
    qdd_max: f64,
    qddd_max: f64,
) -> Piecewise {
    let distance = (q1 - q0).abs();
    let sign = if q1 >= q0 { 1.0 } else { -1.0 };
    let (v, a, j) = (qd_max.abs(), qdd_max.abs(), qddd_max.abs());
    if distance == 0.0 || v == 0.0 || a == 0.0 || j == 0.0 {
        return Piecewise::chain(start_time, q0, &[]);
    }
    let [tj, ta, tv] = double_s_phases(distance, v, a, j);
    let peak = j * tj; // the acceleration reached
    let pieces = [
        (tj, 0.0, sign * j),
        (ta - 2.0 * tj, sign * peak, 0.0),
        (tj, sign * peak, -sign * j),
        (tv, 0.0, 0.0),
        (tj, 0.0, -sign * j),
        (ta - 2.0 * tj, -sign * peak, 0.0),
        (tj, -sign * peak, sign * j),
    ];
    let mut p = Piecewise::chain(start_time, q0, &pieces);
    p.q_end = q1;
    p
}

/// Durations `[jerk phase, acceleration phase, coasting]` of the rest to
/// rest double-S move over `d > 0`. The acceleration phase (of length
/// `ta`, jerk phases included) mirrors the braking phase.
fn double_s_phases(d: f64, v: f64, a: f64, j: f64) -> [f64; 3] {
    // Reaching the speed limit: the acceleration limit is reached on the way
    // when v j >= a^2.
    let (tj, ta) = if v * j >= a * a { (a / j, a / j + v / a) } else { ((v / j).sqrt(), 2.0 * (v / j).sqrt()) };
    let tv = d / v - ta;
    if tv >= 0.0 {
        return [tj, ta, tv];
    }
    // The speed limit is not reached: the move is two mirrored phases with
    // d = v_peak ta. With the acceleration limit reached, v_peak = a (ta - tj).
    let tj = a / j;
    let ta = (tj + (tj * tj + 4.0 * d / a).sqrt()) / 2.0;
    if ta >= 2.0 * tj {
        return [tj, ta, 0.0];
    }
    // Neither: v_peak = j tj^2 and ta = 2 tj, so d = 2 j tj^3.
    let tj = (d / (2.0 * j)).cbrt();
    [tj, 2.0 * tj, 0.0]
}

/// The duration of [`point_to_point_bounded_jerk`]'s move.
#[cfg(test)]
pub fn bounded_jerk_duration(distance: f64, qd_max: f64, qdd_max: f64, qddd_max: f64) -> f64 {
    let [_, ta, tv] = double_s_phases(distance.abs(), qd_max.abs(), qdd_max.abs(), qddd_max.abs());
    2.0 * ta + tv
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Checks that each derivative is the time derivative of the one before
    /// by central differences. With step h the difference errs by
    /// h^2 |f'''| / 6 (plus rounding eps |f| / h); the tolerances below are
    /// that bound for the trajectories' largest third derivative, times 10.
    fn assert_derivatives(traj: &Trajectory, times: &[f64], h: f64, tol: [f64; 3]) -> [f64; 3] {
        let mut worst = [0.0f64; 3];
        for &t in times {
            let (lo, hi, mid) = (traj.jet(t - h), traj.jet(t + h), traj.jet(t));
            for k in 0..3 {
                let fd = (hi[k] - lo[k]) / (2.0 * h);
                let err = (fd - mid[k + 1]).abs();
                worst[k] = worst[k].max(err);
                assert!(err < tol[k], "order {k} at t = {t}: {fd} vs {} ({traj:?})", mid[k + 1]);
            }
        }
        worst
    }

    #[test]
    fn quintic_meets_its_boundary_conditions_and_its_derivatives_agree() {
        let start = [0.3, -0.2, 0.5];
        let end = [1.7, 0.4, -0.3];
        let p = Quintic::new(2.0, start, end);
        let j0 = p.jet(0.0);
        let j1 = p.jet(2.0);
        for k in 0..3 {
            // Evaluating a degree-5 polynomial in doubles: a few ulps of 10.
            assert!((j0[k] - start[k]).abs() < 1e-13, "start {k}: {j0:?}");
            assert!((j1[k] - end[k]).abs() < 1e-12, "end {k}: {j1:?}");
        }
        // The default rest-to-rest move from 0 to 1 in tf: the textbook
        // 10 s^3 - 15 s^4 + 6 s^5 with s = t / tf.
        let rest = Quintic::new(2.0, [0.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
        for t in [0.2, 0.7, 1.0, 1.5, 1.9] {
            let s: f64 = t / 2.0;
            let expected = 10.0 * s.powi(3) - 15.0 * s.powi(4) + 6.0 * s.powi(5);
            assert!((rest.jet(t)[0] - expected).abs() < 1e-14);
        }
        // Third derivatives are below 60 here: h = 1e-5 gives 1e-9; rounding 1e-11.
        let traj = Trajectory::Quintic(p);
        let worst = assert_derivatives(&traj, &[0.1, 0.6, 1.0, 1.4, 1.95], 1e-5, [1e-7; 3]);
        eprintln!("quintic worst derivative errors {worst:?}");
        // Past the end it moves on at the end speed.
        assert!((traj.jet(3.0)[0] - (1.7 + 0.4)).abs() < 1e-12);
    }

    #[test]
    fn point_to_point_trapezoid_and_triangle() {
        // Trapezoid: 0 -> 4 with v = 3, a = 4 (4 >= 9/4); the Modelica test case.
        // Triangle: 1 -> 2 with the same limits (1 < 9/4).
        for (q0, q1, v, a, start) in [(1.0, 5.0, 3.0, 4.0, 0.5), (1.0, 2.0, 3.0, 4.0, 0.5), (2.0, -1.0, 0.7, 0.9, 0.0)]
        {
            let p = point_to_point(start, q0, q1, v, a);
            let d: f64 = q1 - q0;
            let expected_t = if d.abs() >= v * v / a { d.abs() / v + v / a } else { 2.0 * (d.abs() / a).sqrt() };
            assert!((p.end_time() - start - expected_t).abs() < 1e-14, "duration {}", p.end_time());
            assert!((point_to_point_duration(d, v, a) - expected_t).abs() < 1e-14);
            // The chain lands on q1 before the exact end value is set.
            let last = p.segments.last().unwrap();
            let dt = p.t_end - last.t;
            let landed = last.q + last.v * dt + last.a * dt * dt / 2.0;
            assert!((landed - q1).abs() < 1e-12, "lands at {landed}");
            let duration = p.end_time() - start;
            let traj = Trajectory::Piecewise(p.clone());
            assert_eq!(traj.jet(start - 1.0), [q0, 0.0, 0.0, 0.0, 0.0]);
            assert_eq!(traj.jet(start), [q0, 0.0, p.segments[0].a, 0.0, 0.0]);
            assert_eq!(traj.jet(p.t_end + 0.1), [q1, 0.0, 0.0, 0.0, 0.0]);
            // Limits: sample densely.
            let n = 2000;
            let mut peak_v = 0.0f64;
            for i in 0..=n {
                let t = start + duration * i as f64 / n as f64;
                let [_, qd, qdd, ..] = traj.jet(t);
                assert!(qd.abs() <= v * (1.0 + 1e-12) && qdd.abs() <= a * (1.0 + 1e-12));
                peak_v = peak_v.max(qd.abs());
            }
            // The peak speed is v, or a sqrt(d / a) for a triangle.
            let expected_peak = if d.abs() >= v * v / a { v } else { a * (d.abs() / a).sqrt() };
            assert!((peak_v - expected_peak).abs() < a * duration / n as f64 + 1e-12);
            // Away from the acceleration jumps the derivatives agree; the
            // third derivative is 0, so only rounding (1e-16 * 5 / 1e-6) counts.
            let jumps: Vec<f64> = p.segments.iter().map(|s| s.t).chain([p.t_end]).collect();
            let times: Vec<f64> = (1..40)
                .map(|i| start + duration * i as f64 / 40.0)
                .filter(|t| jumps.iter().all(|j| (t - j).abs() > 1e-3))
                .collect();
            let worst = assert_derivatives(&traj, &times, 1e-6, [1e-8, 1e-8, 1e-8]);
            eprintln!("ptp {q0}->{q1}: worst derivative errors {worst:?}");
        }
    }

    #[test]
    fn bounded_jerk_respects_its_limits_and_its_closed_form_duration() {
        // Cases: every limit reached; acceleration not reached (v j < a^2);
        // speed not reached; neither speed nor acceleration reached.
        let cases = [
            (0.0, 3.0, 1.0, 1.0, 10.0),
            (0.0, 3.0, 1.0, 2.0, 1.0),
            (1.0, 1.2, 1.0, 1.0, 10.0),
            (0.0, -0.01, 1.0, 1.0, 10.0),
        ];
        for (q0, q1, v, a, j) in cases {
            let p = point_to_point_bounded_jerk(0.2, q0, q1, v, a, j);
            let d: f64 = (q1 - q0).abs();
            // Closed forms of the duration for each case.
            let expected = if v * j >= a * a && d >= v * (v / a + a / j) {
                d / v + v / a + a / j
            } else if v * j < a * a && d >= 2.0 * v * (v / j).sqrt() {
                d / v + 2.0 * (v / j).sqrt()
            } else if d >= 2.0 * a * a * a / (j * j) {
                let tj = a / j;
                tj + (tj * tj + 4.0 * d / a).sqrt()
            } else {
                4.0 * (d / (2.0 * j)).cbrt()
            };
            let duration = p.end_time() - 0.2;
            assert!((duration - expected).abs() < 1e-12, "{q0}->{q1}: {duration} vs {expected}");
            // Sums of phase durations: a few ulps.
            assert!((bounded_jerk_duration(d, v, a, j) - duration).abs() < 1e-14);
            let last = p.segments.last().unwrap();
            let dt = p.t_end - last.t;
            let landed = last.q + last.v * dt + last.a * dt * dt / 2.0 + last.j * dt * dt * dt / 6.0;
            assert!((landed - q1).abs() < 1e-12, "lands at {landed}, not {q1}");
            let traj = Trajectory::Piecewise(p.clone());
            // Rest at both ends: speed and acceleration vanish.
            let (v_end, a_end) = (last.v + last.a * dt + last.j * dt * dt / 2.0, last.a + last.j * dt);
            assert!(v_end.abs() < 1e-12 && a_end.abs() < 1e-12, "{v_end} {a_end}");
            let n = 4000;
            for i in 0..=n {
                let t = 0.2 + duration * i as f64 / n as f64;
                let [_, qd, qdd, qddd, _] = traj.jet(t);
                assert!(qd.abs() <= v * (1.0 + 1e-12), "speed {qd} at {t}");
                assert!(qdd.abs() <= a * (1.0 + 1e-12), "acceleration {qdd} at {t}");
                assert!(qddd.abs() <= j * (1.0 + 1e-12), "jerk {qddd} at {t}");
            }
            // The third derivative of q, qd, qdd is at most j, 0, 0 away
            // from the jerk switches: h = 1e-5 gives j h^2 / 6 = 2e-10.
            let switches: Vec<f64> = p.segments.iter().map(|s| s.t).chain([p.t_end]).collect();
            let times: Vec<f64> = (1..50)
                .map(|i| 0.2 + duration * i as f64 / 50.0)
                .filter(|t| switches.iter().all(|s| (t - s).abs() > 1e-4))
                .collect();
            let worst = assert_derivatives(&traj, &times, 1e-5, [1e-8, 1e-8, 1e-8]);
            eprintln!("bounded jerk {q0}->{q1}: worst derivative errors {worst:?}");
        }
    }

    #[test]
    fn value_and_derivatives_shift_by_order() {
        let traj = Trajectory::Piecewise(point_to_point(0.0, 0.0, 1.0, 1.0, 1.0));
        let j = traj.jet(0.5);
        assert_eq!(traj.value_and_derivatives(0.5, 0), [j[0], j[1], j[2]]);
        assert_eq!(traj.value_and_derivatives(0.5, 2), [j[2], j[3], j[4]]);
        assert_eq!(traj.value_and_derivatives(0.5, 3), [j[3], j[4], 0.0]);
    }
}
