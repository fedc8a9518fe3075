//! 1-D friction with modes, after Modelica's `PartialFriction`: an element
//! between two flanges (a clutch between two shafts, a brake or bearing
//! between a flange and its support) that slides with a force given by
//! its law, sticks when the relative speed reaches zero, holds as a
//! constraint while the force that keeps it stuck stays within its limit,
//! and breaks away beyond it. The mode is discrete state that changes only
//! at events; the indicators say when to look again.

use super::FlangeRef;

/// The mode of a friction element, as Modelica numbers it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrictionMode {
    Backward = -1,
    Stuck = 0,
    Forward = 1,
    Free = 2,
    /// Before the first event iteration.
    Unknown = 3,
}

impl FrictionMode {
    pub fn from_value(x: f64) -> Self {
        match x as i32 {
            -1 => FrictionMode::Backward,
            0 => FrictionMode::Stuck,
            1 => FrictionMode::Forward,
            2 => FrictionMode::Free,
            _ => FrictionMode::Unknown,
        }
    }
}

/// How much force the element transmits: `scale * mu(v)` while sliding at
/// relative speed `v >= 0` (mirrored below zero), where `scale` is
/// `cgeo fn_max` times the normal-force signal (or 1 without one), and up
/// to `peak` times the sliding force at zero speed while stuck.
#[derive(Clone, Debug, PartialEq)]
pub struct FrictionLaw {
    /// `(v, mu)` rows, `v >= 0` ascending: interpolated linearly and
    /// extrapolated linearly beyond the ends (one row: a constant).
    pub table: Vec<(f64, f64)>,
    /// Stribeck's curve in place of the table (MassWithStopAndFriction).
    pub stribeck: Option<Stribeck>,
    pub peak: f64,
    /// `cgeo fn_max`: the normal-force signal's scale (1 without one).
    pub scale: f64,
    /// A sliding element whose speed passes `-v_small` (or `+v_small`)
    /// reverses without sticking (Modelica's `v_small`, `w_small`).
    pub v_small: f64,
    /// A one-way clutch (Modelica's OneWayClutch: a clutch in parallel with
    /// a freewheel): it slides forward only; at `v <= 0` it is stuck, and
    /// held without limit against backward motion, up to `peak` times the
    /// sliding force against forward motion.
    pub one_way: bool,
    /// Hard stops `(lo, hi)` of the relative position (a mass with stops):
    /// the element does not slide beyond them, its speed is set to zero
    /// where it reaches one, and it stays there while pushed against it.
    pub stops: Option<(f64, f64)>,
}

/// How near a stop counts as on it: a flange placed on a stop by the
/// state's affine map may land a rounding error off it.
pub(crate) fn stop_tolerance(stop: f64) -> f64 {
    1e-12 * (1.0 + stop.abs())
}

/// Stribeck's friction curve: `F_prop v + F_Coulomb + F_Stribeck
/// exp(-fexp v)` at speeds `v >= 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stribeck {
    pub f_prop: f64,
    pub f_coulomb: f64,
    pub f_stribeck: f64,
    pub fexp: f64,
}

/// A one-way clutch without normal force still holds up to this fraction
/// of its largest sliding force at rest (Modelica's `eps0`), and a pressed
/// one at least `1 + ONE_WAY_EPS` times its sliding force: the holding
/// limit stays above the sliding force, so that breaking away is decided.
pub(crate) const ONE_WAY_EPS: f64 = 1e-4;

impl FrictionLaw {
    /// A law from a table, without Stribeck's curve, one-way action or stops.
    pub fn from_table(table: Vec<(f64, f64)>, peak: f64, scale: f64, v_small: f64) -> Self {
        FrictionLaw { table, stribeck: None, peak, scale, v_small, one_way: false, stops: None }
    }

    /// `mu(v)` for `v >= 0`.
    pub fn mu(&self, v: f64) -> f64 {
        if let Some(Stribeck { f_prop, f_coulomb, f_stribeck, fexp }) = self.stribeck {
            return f_prop * v + f_coulomb + f_stribeck * (-fexp * v).exp();
        }
        let t = &self.table;
        match t.len() {
            0 => 0.0,
            1 => t[0].1,
            n => {
                let k = t.partition_point(|p| p.0 <= v).clamp(1, n - 1);
                let ((v0, m0), (v1, m1)) = (t[k - 1], t[k]);
                if v1 > v0 {
                    m0 + (m1 - m0) * (v - v0) / (v1 - v0)
                } else {
                    m1
                }
            }
        }
    }
}

/// A friction element in the compiled model.
#[derive(Clone, Debug)]
pub(crate) struct Friction {
    /// The relative motion is `b - a`; the element's force pushes `b` back
    /// and `a` forward while it slides forward (`b` faster).
    pub a: FlangeRef,
    pub b: FlangeRef,
    pub law: FrictionLaw,
    /// The signal slot of the normalized normal force, if any.
    pub normal: Option<usize>,
    /// Its constraint row (used while locked).
    pub row: usize,
    /// Its first discrete slot: mode, startForward, startBackward, free.
    pub discrete: usize,
    /// Its first indicator (three).
    pub indicator: usize,
    /// With stops, the first of two more: past the upper stop, past the lower.
    pub stop_indicator: Option<usize>,
}

/// Indicators per friction element.
pub(crate) const FRICTION_INDICATORS: usize = 3;
/// Discrete slots per friction element: mode, startForward, startBackward, free.
pub(crate) const FRICTION_DISCRETE: usize = 4;

/// What a friction element computed in the last evaluation.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrictionValues {
    pub s_rel: f64,
    pub v_rel: f64,
    pub a_rel: f64,
    /// The element's force (Law1D's sign: it pushes `b` back).
    pub force: f64,
    /// The normal force `scale * signal`, and the limits of a stuck element.
    pub normal: f64,
    pub f0: f64,
    pub f0_max: f64,
    /// Modelica's path parameter: the holding force while locked.
    pub sa: f64,
    pub locked: bool,
    pub free: bool,
}

/// The discrete state of a friction element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FrictionFlags {
    pub mode: FrictionMode,
    pub start_forward: bool,
    pub start_backward: bool,
    /// No normal force: decided at events like the rest (between them the
    /// normal force may cross zero only where an indicator says so).
    pub free: bool,
}

impl FrictionFlags {
    pub fn read(d: &[f64]) -> Self {
        FrictionFlags {
            mode: FrictionMode::from_value(d[0]),
            start_forward: d[1] != 0.0,
            start_backward: d[2] != 0.0,
            free: d[3] != 0.0,
        }
    }

    pub fn write(&self, d: &mut [f64]) {
        d[0] = self.mode as i32 as f64;
        d[1] = self.start_forward as i32 as f64;
        d[2] = self.start_backward as i32 as f64;
        d[3] = self.free as i32 as f64;
    }

    /// Before the first event iteration.
    pub const START: [f64; FRICTION_DISCRETE] = [3.0, 0.0, 0.0, 0.0];

    /// Whether the element is a constraint: stuck (or just engaged from
    /// free), not breaking away, and pressed.
    pub fn locked(&self) -> bool {
        use FrictionMode::*;
        !(self.free || matches!(self.mode, Forward | Backward | Unknown) || self.start_forward || self.start_backward)
    }

    /// The sliding force at relative speed `v` (zero when free or locked).
    pub fn force(&self, law: &FrictionLaw, normal: f64, v: f64) -> f64 {
        if self.free || self.locked() || self.mode == FrictionMode::Unknown {
            return 0.0;
        }
        let forward = self.start_forward || (self.mode == FrictionMode::Forward && !self.start_backward);
        if forward {
            normal * law.mu(v.max(0.0))
        } else {
            -normal * law.mu((-v).max(0.0))
        }
    }

    /// The next discrete state from `pre` (the last pass's), as Modelica's
    /// PartialFriction (or OneWayClutch, or PartialFrictionWithStop)
    /// decides it, given the relative position and speed and the path
    /// parameter `sa` of the pass evaluated with `pre`.
    pub fn next(pre: &FrictionFlags, values: &FrictionValues, law: &FrictionLaw, free: bool, initial: bool) -> Self {
        use FrictionMode::*;
        let FrictionValues { s_rel, v_rel: v, sa, f0, f0_max, .. } = *values;
        let v_small = law.v_small;
        if law.one_way {
            // Stuck at v <= 0 (locked, or breaking away forward); sliding
            // forward otherwise. Held without limit backwards: no start
            // backward.
            let was_stuck = pre.mode == Stuck;
            let start_forward =
                was_stuck && (sa > f0_max || pre.start_forward && sa > f0 || v > v_small) || initial && v > 0.0;
            let locked = was_stuck && !start_forward;
            let mode = if locked || v <= 0.0 { Stuck } else { Forward };
            return FrictionFlags { mode, start_forward, start_backward: false, free: false };
        }
        // With stops, no sliding into a stop that is reached.
        let (below_top, above_bottom) = law
            .stops
            .map_or((true, true), |(lo, hi)| (s_rel < hi - stop_tolerance(hi), s_rel > lo + stop_tolerance(lo)));
        let start_forward = pre.mode == Stuck && (sa > f0_max || pre.start_forward && sa > f0) && below_top
            || pre.mode == Backward && v > v_small
            || initial && v > 0.0;
        let start_backward = pre.mode == Stuck && (sa < -f0_max || pre.start_backward && sa < -f0) && above_bottom
            || pre.mode == Forward && v < -v_small
            || initial && v < 0.0;
        let mode = if free {
            Free
        } else if (matches!(pre.mode, Forward | Free) || start_forward) && v > 0.0 && below_top {
            Forward
        } else if (matches!(pre.mode, Backward | Free) || start_backward) && v < 0.0 && above_bottom {
            Backward
        } else {
            Stuck
        };
        FrictionFlags { mode, start_forward, start_backward, free }
    }

    /// The indicators that watch for the next change, given what the
    /// element computed: they change sign where the mode must be looked
    /// at again.
    pub fn indicators(&self, values: &FrictionValues, out: &mut [f64]) {
        use FrictionMode::*;
        out.fill(1.0);
        let pressed = values.normal;
        let v = values.v_rel;
        match self.mode {
            _ if values.free => out[0] = pressed,
            _ if values.locked => {
                out[0] = held(values.f0_max - values.sa);
                out[1] = held(values.sa + values.f0_max);
                out[2] = pressed;
            }
            Stuck if self.start_forward => {
                out[0] = v;
                out[1] = values.sa - values.f0;
                out[2] = pressed;
            }
            Stuck if self.start_backward => {
                out[0] = -v;
                out[1] = -values.sa - values.f0;
                out[2] = pressed;
            }
            Forward => {
                out[0] = v;
                out[2] = pressed;
            }
            Backward => {
                out[0] = -v;
                out[2] = pressed;
            }
            _ => out[2] = pressed,
        }
    }

    /// The indicators of a one-way clutch: locked, the holding torque
    /// against its limit forward (backwards it has none); breaking away or
    /// sliding, the speed (and the holding torque against the sliding one).
    pub fn one_way_indicators(&self, values: &FrictionValues, out: &mut [f64]) {
        out.fill(1.0);
        out[2] = values.normal;
        if values.locked {
            out[0] = held(values.f0_max - values.sa);
        } else if self.mode == FrictionMode::Stuck && self.start_forward {
            out[0] = values.v_rel;
            out[1] = values.sa - values.f0;
        } else if self.mode == FrictionMode::Forward {
            out[0] = values.v_rel;
        }
    }
}

/// A locked element's margin to its holding limit as an indicator: it
/// breaks away only beyond the limit (`sa > f0_max`, strictly), so the
/// margin zero still counts as held (positive). Otherwise an event located
/// where the force just reaches the limit would leave it locked with an
/// indicator of zero, read as already crossed, and its crossing would be
/// missed.
fn held(margin: f64) -> f64 {
    if margin >= 0.0 {
        margin.max(f64::MIN_POSITIVE)
    } else {
        margin
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn law() -> FrictionLaw {
        FrictionLaw::from_table(vec![(0.0, 0.5)], 1.1, 20.0, 1e10)
    }

    #[test]
    fn a_table_is_interpolated_and_extrapolated_linearly() {
        let l = FrictionLaw { table: vec![(0.0, 0.5), (1.0, 0.3)], ..law() };
        assert_eq!([l.mu(0.0), l.mu(0.5), l.mu(2.0)], [0.5, 0.4, 0.09999999999999998]);
        assert_eq!(law().mu(7.0), 0.5);
    }

    #[test]
    fn modes_follow_partial_friction() {
        use FrictionMode::*;
        let at = |v_rel, sa| FrictionValues { v_rel, sa, f0: 10.0, f0_max: 11.0, ..Default::default() };
        let flags = |mode| FrictionFlags { mode, start_forward: false, start_backward: false, free: false };
        // At the start, an engaged element slides the way it moves.
        let start = FrictionFlags::next(&flags(Unknown), &at(-10.0, 0.0), &law(), false, true);
        assert_eq!((start.mode, start.start_backward), (Backward, true));
        // Engaging from free with a speed slides; at rest it sticks.
        assert_eq!(FrictionFlags::next(&flags(Free), &at(2.0, 0.0), &law(), false, false).mode, Forward);
        assert_eq!(FrictionFlags::next(&flags(Free), &at(0.0, 0.0), &law(), false, false).mode, Stuck);
        // Sliding forward, the speed reaching zero sticks (v_small large).
        assert_eq!(FrictionFlags::next(&flags(Forward), &at(-1e-12, 0.0), &law(), false, false).mode, Stuck);
        // Stuck within the limit holds; beyond it the start flag rises.
        let held = FrictionFlags::next(&flags(Stuck), &at(0.0, 10.5), &law(), false, false);
        assert!(held.locked());
        let away = FrictionFlags::next(&flags(Stuck), &at(0.0, 11.5), &law(), false, false);
        assert_eq!((away.mode, away.start_forward, away.locked()), (Stuck, true, false));
        // ... and the mode follows once the speed has the sign.
        assert_eq!(FrictionFlags::next(&away, &at(1e-9, 10.5), &law(), false, false).mode, Forward);
        // No normal force: free.
        assert_eq!(FrictionFlags::next(&flags(Forward), &at(1.0, 0.0), &law(), true, false).mode, Free);
    }
}
