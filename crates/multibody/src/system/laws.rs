//! The laws that components hand to the dynamics: 1-D force laws, frame
//! force laws and signal sources. Plain data, evaluated in the hot loop.

use crate::math::{Mat3, Vec3};

/// The force law of a 1-D element between two flanges, with the relative
/// position `s_rel = s_b - s_a` and its rate `v_rel`. `force` is the
/// element's internal force (or torque): it pushes flange_b back by `force`
/// and flange_a forward by `force`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Law1D {
    /// `force = c (s_rel - s_rel0)`.
    Spring { c: f64, s_rel0: f64 },
    /// `force = d v_rel`.
    Damper { d: f64 },
    /// `force = c (s_rel - s_rel0) + d v_rel`.
    SpringDamper { c: f64, d: f64, s_rel0: f64 },
    /// A source driving flange_b forward by `value` (reaction on flange_a).
    Source { value: f64 },
    /// A source driving flange_b forward by the value of a signal: a
    /// component's input connector, which assembly turns into a signal slot.
    Input { signal: usize },
    /// The flow (torque or force) that the model's equations give a
    /// component at flange_b, from a signal: flange_b receives its opposite.
    Flow { signal: usize },
    /// A spring and damper that act only in contact (ElastoGap,
    /// ElastoBacklash): with `x = s_rel - s_rel0`, in contact above `hi`
    /// with `f_c = c (x - hi)^n` and below `lo` with `f_c = -c (lo - x)^n`,
    /// free between. The damping force is bounded by the spring force,
    /// `f = f_c + clamp(d v_rel, -|f_c|, |f_c|)`, so the contact force never
    /// pulls and starts from zero. Entering and leaving contact are events
    /// (see [`Law1D::indicators`]).
    Contact { c: f64, d: f64, s_rel0: f64, lo: f64, hi: f64, n: f64 },
}

impl Law1D {
    /// The internal force at relative position `s_rel` and speed `v_rel`,
    /// with the current `signals` for driven sources.
    #[inline]
    pub fn force(&self, s_rel: f64, v_rel: f64, signals: &[f64]) -> f64 {
        match *self {
            Law1D::Spring { c, s_rel0 } => c * (s_rel - s_rel0),
            Law1D::Damper { d } => d * v_rel,
            Law1D::SpringDamper { c, d, s_rel0 } => c * (s_rel - s_rel0) + d * v_rel,
            Law1D::Source { value } => -value,
            Law1D::Input { signal } => -signals[signal],
            Law1D::Flow { signal } => signals[signal],
            Law1D::Contact { .. } => {
                let (f_c, f_d) = self.contact_parts(s_rel, v_rel);
                f_c + f_d
            }
        }
    }

    /// The force of a law that does not depend on the motion (a source),
    /// without computing the motion; `None` for the others.
    #[inline]
    pub fn source_force(&self, signals: &[f64]) -> Option<f64> {
        match *self {
            Law1D::Source { value } => Some(-value),
            Law1D::Input { signal } => Some(-signals[signal]),
            Law1D::Flow { signal } => Some(signals[signal]),
            _ => None,
        }
    }

    /// A contact law's spring force and its bounded damping force (zero
    /// out of contact and for the other laws).
    #[inline]
    pub fn contact_parts(&self, s_rel: f64, v_rel: f64) -> (f64, f64) {
        let Law1D::Contact { c, d, s_rel0, lo, hi, n } = *self else { return (0.0, 0.0) };
        let x = s_rel - s_rel0;
        let power = |depth: f64| if n == 1.0 { depth } else { depth.powf(n) };
        let f_c = if x > hi {
            c * power(x - hi)
        } else if x < lo {
            -c * power(lo - x)
        } else {
            return (0.0, 0.0);
        };
        let bound = f_c.abs();
        (f_c, (d * v_rel).clamp(-bound, bound))
    }

    /// How many event indicators the law watches (contact laws: two).
    pub fn indicator_count(&self) -> usize {
        match self {
            Law1D::Contact { .. } => 2,
            _ => 0,
        }
    }

    /// The law's indicators at relative position `s_rel`: a contact law's
    /// change sign where contact above `hi` and below `lo` begins or ends,
    /// so the integrator stops there rather than stepping over the kink.
    #[inline]
    pub fn indicators(&self, s_rel: f64, out: &mut [f64]) {
        if let Law1D::Contact { s_rel0, lo, hi, .. } = *self {
            let x = s_rel - s_rel0;
            out[0] = x - hi;
            out[1] = lo - x;
        }
    }
}

/// The frame in which a force or torque input vector is resolved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Resolve {
    World,
    FrameA,
    FrameB,
}

impl Resolve {
    pub const VARIANTS: &'static [&'static str] = &["World", "FrameA", "FrameB"];

    pub fn from_variant(v: &str) -> Self {
        match v {
            "World" => Resolve::World,
            "FrameA" => Resolve::FrameA,
            _ => Resolve::FrameB,
        }
    }
}

/// An input vector resolved in `resolve` expressed in world coordinates,
/// given the world-to-frame rotations of frame_a (if any) and frame_b.
#[inline]
pub fn resolve_input(u: Vec3, resolve: Resolve, rot_a: Option<&Mat3>, rot_b: &Mat3) -> Vec3 {
    match (resolve, rot_a) {
        (Resolve::FrameA, Some(a)) => a.tr_mul(&u),
        (Resolve::FrameB, _) => rot_b.tr_mul(&u),
        _ => u,
    }
}

/// How a force element acts. Its attachments are the element's, not the
/// law's: frame_b and the reaction frame_a (or the world), up to six input
/// signals `u[0..6]` and two 1-D flanges (see `Part::Force`), so a new law
/// is one arm here and one in the dynamics' `applied`, whatever it acts on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ForceLaw {
    /// Along the line from frame_a to frame_b with
    /// `f = c (s - s_unstretched) + d ds/dt`, where `s = max(|r_ab|, s_small)`;
    /// `f > 0` pulls the frames together. No torques.
    Line { c: f64, d: f64, s_unstretched: f64, s_small: f64 },
    /// A force `u[0..3]` at frame_b's origin, resolved in `resolve`; the
    /// reaction acts on frame_a.
    Force { resolve: Resolve },
    /// A torque `u[0..3]` on frame_b; the reaction acts on frame_a.
    Torque { resolve: Resolve },
    /// The flows (force `u[0..3]`, then torque `u[3..6]`, resolved in
    /// frame_b, or in the world with `world`) that the model's equations
    /// give a component at frame_b: frame_b receives their opposite. No
    /// frame_a.
    Flow { world: bool },
    /// A planar spring and damper per world axis (PlanarMechanics): with
    /// `dx`, `dy` from frame_a's origin to frame_b's and `dphi` the angle
    /// from frame_a to frame_b, frame_b is pulled back by
    /// `c[k] (d_k - rel0[k]) + d[k] der(d_k)` along x, y and about z, and
    /// frame_a the other way.
    PlanarAxes { c: [f64; 3], d: [f64; 3], rel0: [f64; 3] },
    /// A slipping wheel's elastic contact with the ground plane y = 0
    /// (frame_b at the wheel's centre, spin axis z; the reaction on the
    /// world): where the rim's lowest point is `pen` below the plane, the
    /// normal force is `f_n = max(0, c_z pen + d_z der(pen))`, and friction
    /// `f_n` times the coefficients of `law`, at the contact point. On the
    /// component's road number `road` (its `Part::Road`s) if given.
    Tyre { radius: f64, law: SlipLaw, c_z: f64, d_z: f64, road: Option<usize> },
    /// A planar wheel's slip force (PlanarMechanics' SlipBasedWheelJoint):
    /// frame_b is the wheel's steering frame, flange_b its rolling axis,
    /// which turns it along `axis` (unit, in frame_b) at `radius` times
    /// its speed. The ground pushes frame_b against the contact's slip
    /// with the normal force `max(0, n + u[0])` times the coefficients of
    /// `law`, and the flange back by the longitudinal force at the radius.
    PlanarSlip { radius: f64, axis: Vec3, n: f64, law: SlipLaw },
}

/// Which relative rotations of frame_b a constraint locks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RotationLock {
    Free,
    /// All but the rotation about the unit axis `n` (resolved in frame_a).
    AllBut(Vec3),
    All,
    /// Rotation about `n_a` (fixed in frame_a) and `n_b` (fixed in
    /// frame_b) only: the axes keep their angle.
    Universal {
        n_a: Vec3,
        n_b: Vec3,
    },
    /// The rotations about the marked axes of frame_a (CutMount).
    Axes([bool; 3]),
}

/// What a constraint (a joint without states, or the cut of a loop)
/// keeps between its frames.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ConstraintKind {
    /// Locked rotations, and locked translations of frame_b's origin along
    /// the first `count` of `directions` (unit, resolved in frame_a).
    Locks { rotation: RotationLock, directions: [Vec3; 3], count: usize },
    /// The origins keep the distance `length` (a rod with spherical ends).
    Distance { length: f64 },
    /// A wheel of `radius` rolling on the ground plane y = 0: frame_b is
    /// the wheel's centre and turns with it, its z axis is the spin axis;
    /// frame_a is the ground. The contact point's material velocity has no
    /// component along the ground (rows on velocities only: nonholonomic),
    /// and with `Contact::Rolling` the wheel touches the plane (a row on
    /// positions).
    Wheel { radius: f64, contact: WheelContact },
}

/// Which rows a wheel's rolling contact keeps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WheelContact {
    /// An upright wheel (RollingConstraintVerticalWheel): the contact point
    /// is `radius` straight below the centre; no slip along the wheel, and
    /// with `lateral` none across it. Two velocity rows, or one.
    Vertical { lateral: bool },
    /// A wheel that may lean (RollingWheelJoint): the lowest point of its
    /// rim stays on the plane (a position row) and does not slip in either
    /// direction (two velocity rows). On the component's road number `road`
    /// (its `Part::Road`s; assembly numbers them among all roads), else on
    /// the plane y = 0.
    Rolling { road: Option<usize> },
    /// A wheel that may lean and slip (SlipWheelJoint, PacejkaWheelJoint):
    /// the lowest point of its rim stays on the plane (a position row, whose
    /// multiplier is the normal force `f_n`), and the ground pushes the
    /// contact point against its slip with `f_n` times the friction
    /// coefficients of `law`. On the component's road number `road` (its
    /// `Part::Road`s; assembly numbers them among all roads), else on the
    /// plane y = 0.
    Slipping { law: SlipLaw, road: Option<usize> },
}

/// How a slipping wheel's friction depends on the slip velocity `v_slip`
/// of its contact point (the velocity of the wheel's material point there,
/// along the road: `v_slip_long` along the wheel's path, `v_slip_lat`
/// across it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SlipLaw {
    /// The library's slip law: `mu = limit_S_triple(vAdhesion, vSlide, mu_A,
    /// mu_S, |v_slip| + v_small)` along the slip, with `vAdhesion =
    /// max(vAdhesion_min, sAdhesion |radius w_roll|)` and `vSlide =
    /// max(vSlide_min, sSlide |radius w_roll|)` (`w_roll`: the spin rate).
    Triple { v_adhesion_min: f64, v_slide_min: f64, s_adhesion: f64, s_slide: f64, mu_a: f64, mu_s: f64, v_small: f64 },
    /// Pacejka's magic formula with the factors `[B, C, D, E]` along the
    /// path (`x`) and across it (`y`). With `ellipse`, both curves are taken
    /// at the slip speed `|v_slip| + v_small` and shared along the slip's
    /// direction (grip is shared); otherwise each is taken at its own slip
    /// component.
    Pacejka { x: [f64; 4], y: [f64; 4], v_small: f64, ellipse: bool },
}

impl SlipLaw {
    /// The friction coefficients `(mu_long, mu_lat)` at the slip velocity
    /// components and the rolling speed `v_roll = radius w_roll`: the ground
    /// pushes the wheel by `-f_n (mu_long e_long + mu_lat e_lat)`.
    #[inline]
    pub fn coefficients(&self, v_long: f64, v_lat: f64, v_roll: f64) -> (f64, f64) {
        use crate::math::wheel::{limit_s_triple, pacejka_magic};
        match *self {
            SlipLaw::Triple { v_adhesion_min, v_slide_min, s_adhesion, s_slide, mu_a, mu_s, v_small } => {
                let v_slip = (v_long * v_long + v_lat * v_lat).sqrt() + v_small;
                let v_adhesion = v_adhesion_min.max(s_adhesion * v_roll.abs());
                let v_slide = v_slide_min.max(s_slide * v_roll.abs());
                let mu = limit_s_triple(v_adhesion, v_slide, mu_a, mu_s, v_slip);
                (mu * v_long / v_slip, mu * v_lat / v_slip)
            }
            SlipLaw::Pacejka { x, y, v_small, ellipse } => {
                let magic = |v: f64, [b, c, d, e]: [f64; 4]| pacejka_magic(v, b, c, d, e);
                if ellipse {
                    let v_slip = (v_long * v_long + v_lat * v_lat).sqrt() + v_small;
                    (magic(v_slip, x) * v_long / v_slip, magic(v_slip, y) * v_lat / v_slip)
                } else {
                    (magic(v_long, x), magic(v_lat, y))
                }
            }
        }
    }
}

impl ConstraintKind {
    /// Locks of the translations along frame_a's axes that are `locked`,
    /// with the given rotation lock.
    pub fn locking_axes(rotation: RotationLock, locked: [bool; 3]) -> Self {
        let mut directions = [Vec3::zeros(); 3];
        let mut count = 0;
        for (k, &l) in locked.iter().enumerate() {
            if l {
                directions[count] = crate::math::unit(k);
                count += 1;
            }
        }
        ConstraintKind::Locks { rotation, directions, count }
    }

    /// Number of scalar constraint equations.
    pub fn rows(&self) -> usize {
        match *self {
            ConstraintKind::Locks { rotation, count, .. } => {
                count
                    + match rotation {
                        RotationLock::Free => 0,
                        RotationLock::AllBut(_) => 2,
                        RotationLock::All => 3,
                        RotationLock::Universal { .. } => 1,
                        RotationLock::Axes(locked) => locked.iter().filter(|l| **l).count(),
                    }
            }
            ConstraintKind::Distance { .. } => 1,
            ConstraintKind::Wheel { contact: WheelContact::Vertical { lateral }, .. } => 1 + lateral as usize,
            ConstraintKind::Wheel { contact: WheelContact::Rolling { .. }, .. } => 3,
            ConstraintKind::Wheel { contact: WheelContact::Slipping { .. }, .. } => 1,
        }
    }

    /// The same relation with the component's road numbers moved by
    /// `base` (assembly numbers all the mechanism's roads).
    pub fn with_road_base(mut self, base: usize) -> Self {
        if let ConstraintKind::Wheel {
            contact: WheelContact::Slipping { road: Some(r), .. } | WheelContact::Rolling { road: Some(r) },
            ..
        } = &mut self
        {
            *r += base;
        }
        self
    }

    /// The friction law of a slipping wheel (its one row's multiplier is
    /// the normal force, and friction forces follow it).
    pub fn slip_law(&self) -> Option<SlipLaw> {
        match *self {
            ConstraintKind::Wheel { contact: WheelContact::Slipping { law, .. }, .. } => Some(law),
            _ => None,
        }
    }

    /// Whether row `i` of this constraint is on velocities only
    /// (nonholonomic): it has no position residual, and moving positions
    /// onto the constraints leaves it alone.
    pub fn is_velocity_row(&self, i: usize) -> bool {
        match *self {
            ConstraintKind::Wheel { contact: WheelContact::Vertical { .. }, .. } => true,
            // Row 0 keeps the wheel on the plane; rows 1 and 2 are the rolling.
            ConstraintKind::Wheel { contact: WheelContact::Rolling { .. }, .. } => i > 0,
            _ => false,
        }
    }
}

/// A signal as a function of time.
#[derive(Clone, Debug, PartialEq)]
pub enum SignalSource {
    Constant {
        k: f64,
    },
    Step {
        height: f64,
        offset: f64,
        start_time: f64,
    },
    Ramp {
        height: f64,
        duration: f64,
        offset: f64,
        start_time: f64,
    },
    Sine {
        amplitude: f64,
        frequency: f64,
        phase: f64,
        offset: f64,
        start_time: f64,
    },
    /// Linear interpolation in a table of `(time, value)` rows, held
    /// constant outside it.
    Table {
        points: Vec<(f64, f64)>,
    },
    /// A formula of time from the model's equations.
    Formula(crate::math::expr::TimeFunction),
    /// The derivative of order `order` (0 position, 1 speed, 2
    /// acceleration, 3 jerk) of a trajectory (Kinematic5, KinematicPTP, ...).
    Trajectory {
        path: crate::math::trajectory::Trajectory,
        order: usize,
    },
}

impl SignalSource {
    pub fn value(&self, t: f64) -> f64 {
        match *self {
            SignalSource::Constant { k } => k,
            SignalSource::Step { height, offset, start_time } => offset + if t >= start_time { height } else { 0.0 },
            SignalSource::Ramp { height, duration, offset, start_time } => {
                if t < start_time {
                    offset
                } else if t < start_time + duration {
                    offset + (t - start_time) * height / duration
                } else {
                    offset + height
                }
            }
            SignalSource::Sine { amplitude, frequency, phase, offset, start_time } => {
                if t < start_time {
                    offset
                } else {
                    offset + amplitude * (2.0 * std::f64::consts::PI * frequency * (t - start_time) + phase).sin()
                }
            }
            SignalSource::Formula(ref f) => f.value(t),
            SignalSource::Table { ref points } => {
                let k = points.partition_point(|p| p.0 <= t);
                match k {
                    0 => points.first().map_or(0.0, |p| p.1),
                    k if k >= points.len() => points.last().map_or(0.0, |p| p.1),
                    k => {
                        let ((t0, y0), (t1, y1)) = (points[k - 1], points[k]);
                        if t1 > t0 {
                            y0 + (y1 - y0) * (t - t0) / (t1 - t0)
                        } else {
                            y1
                        }
                    }
                }
            }
            SignalSource::Trajectory { ref path, order } => path.value_and_derivatives(t, order)[0],
        }
    }
}

impl SignalSource {
    /// The first time after `t` at which the signal jumps or kinks (a time
    /// event), or infinity.
    pub fn next_switch(&self, t: f64) -> f64 {
        let after = |times: &mut dyn Iterator<Item = f64>| times.filter(|&s| s > t).fold(f64::INFINITY, f64::min);
        match *self {
            SignalSource::Step { start_time, .. } | SignalSource::Sine { start_time, .. } => {
                after(&mut [start_time].into_iter())
            }
            SignalSource::Ramp { duration, start_time, .. } => {
                after(&mut [start_time, start_time + duration].into_iter())
            }
            // The times increase (the component checks): the first row after
            // `t`, by bisection. A scan of every row at every event cost a
            // table of n rows n^2 (10^5 rows: 25 s).
            SignalSource::Table { ref points } => {
                points.get(points.partition_point(|p| p.0 <= t)).map_or(f64::INFINITY, |p| p.0)
            }
            _ => f64::INFINITY,
        }
    }

    /// The value just before `t` (its left limit): where the signal jumps
    /// at `t`, the value it jumps from.
    pub fn value_before(&self, t: f64) -> f64 {
        match *self {
            SignalSource::Step { height, offset, start_time } => offset + if t > start_time { height } else { 0.0 },
            SignalSource::Sine { offset, start_time, .. } if t <= start_time => offset,
            SignalSource::Table { ref points } => {
                // Coming from before, the first row at `t` is reached (rows
                // at the same time are a jump).
                let k = points.partition_point(|p| p.0 < t);
                match points.get(k) {
                    Some(&(tk, yk)) if tk == t && k > 0 => yk,
                    _ => self.value(t),
                }
            }
            _ => self.value(t),
        }
    }

    /// The value and its first two time derivatives at `t`, for motion
    /// that a source prescribes (positions need their speed and
    /// acceleration). Jumps and kinks count as having zero derivative at
    /// the instant itself, as an integrator that steps over them sees it.
    pub fn jet(&self, t: f64) -> [f64; 3] {
        let value = self.value(t);
        match *self {
            SignalSource::Formula(ref f) => f.jet(t),
            SignalSource::Constant { .. } | SignalSource::Step { .. } => [value, 0.0, 0.0],
            SignalSource::Ramp { height, duration, start_time, .. } => {
                let rising = t >= start_time && t < start_time + duration;
                [value, if rising { height / duration } else { 0.0 }, 0.0]
            }
            SignalSource::Sine { amplitude, frequency, phase, start_time, .. } => {
                if t < start_time {
                    return [value, 0.0, 0.0];
                }
                let w = 2.0 * std::f64::consts::PI * frequency;
                let angle = w * (t - start_time) + phase;
                [value, amplitude * w * angle.cos(), -amplitude * w * w * angle.sin()]
            }
            SignalSource::Table { ref points } => {
                let k = points.partition_point(|p| p.0 <= t);
                let slope = if k == 0 || k >= points.len() {
                    0.0
                } else {
                    let ((t0, y0), (t1, y1)) = (points[k - 1], points[k]);
                    if t1 > t0 {
                        (y1 - y0) / (t1 - t0)
                    } else {
                        0.0
                    }
                };
                [value, slope, 0.0]
            }
            SignalSource::Trajectory { ref path, order } => path.value_and_derivatives(t, order),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sources_follow_their_definitions() {
        let ramp = SignalSource::Ramp { height: 2.0, duration: 4.0, offset: 1.0, start_time: 1.0 };
        assert_eq!([ramp.value(0.0), ramp.value(3.0), ramp.value(9.0)], [1.0, 2.0, 3.0]);
        let step = SignalSource::Step { height: 2.0, offset: -1.0, start_time: 0.5 };
        assert_eq!([step.value(0.4), step.value(0.5)], [-1.0, 1.0]);
        let sine = SignalSource::Sine { amplitude: 2.0, frequency: 0.25, phase: 0.0, offset: 1.0, start_time: 0.0 };
        assert!((sine.value(1.0) - 3.0).abs() < 1e-15);
        let table = SignalSource::Table { points: vec![(0.0, 0.0), (1.0, 10.0), (2.0, 10.0)] };
        assert_eq!([table.value(-1.0), table.value(0.25), table.value(5.0)], [0.0, 2.5, 10.0]);
    }

    #[test]
    fn a_table_switches_at_each_of_its_rows() {
        let table = SignalSource::Table { points: vec![(0.0, 0.0), (1.0, 10.0), (1.0, 5.0), (2.0, 10.0)] };
        let next: Vec<f64> = [-1.0, 0.0, 0.5, 1.0, 1.5, 2.0, 3.0].iter().map(|&t| table.next_switch(t)).collect();
        assert_eq!(next, [0.0, 1.0, 1.0, 2.0, 2.0, f64::INFINITY, f64::INFINITY]);
        assert_eq!(SignalSource::Table { points: vec![] }.next_switch(0.0), f64::INFINITY);
    }

    #[test]
    fn jets_are_the_derivatives_of_the_values() {
        let sources = [
            SignalSource::Ramp { height: 2.0, duration: 4.0, offset: 1.0, start_time: 1.0 },
            SignalSource::Sine { amplitude: 2.0, frequency: 0.3, phase: 0.4, offset: 1.0, start_time: 0.5 },
            SignalSource::Table { points: vec![(0.0, 0.0), (1.0, 10.0), (2.0, 10.0)] },
        ];
        // Central differences of step 1e-4 err by about h^2 |y'''| / 6 and
        // by rounding 1e-16 / h^2: 1e-6 covers both for these amplitudes.
        let h = 1e-4;
        for source in &sources {
            for t in [0.7, 1.3, 2.2, 3.9] {
                let [_, d1, d2] = source.jet(t);
                let fd1 = (source.value(t + h) - source.value(t - h)) / (2.0 * h);
                let fd2 = (source.jet(t + h)[1] - source.jet(t - h)[1]) / (2.0 * h);
                assert!((d1 - fd1).abs() < 1e-6, "{source:?} at {t}: {d1} vs {fd1}");
                assert!((d2 - fd2).abs() < 1e-6, "{source:?} at {t}: {d2} vs {fd2}");
            }
        }
    }
}
