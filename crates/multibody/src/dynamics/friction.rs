//! Friction elements with modes in the dynamics (see
//! [`crate::system::friction`]): their sliding forces among the 1-D loads,
//! their constraint rows while locked, and after the accelerations what
//! they hold, their indicators, and at events their next modes.

use super::Workspace;
use crate::system::friction::{
    stop_tolerance, FrictionFlags, FrictionMode, FrictionValues, FRICTION_DISCRETE, FRICTION_INDICATORS, ONE_WAY_EPS,
};
use crate::system::System;

impl System {
    /// Whether the accelerations at this moment need the mass matrix: as
    /// [`System::uses_mass_matrix`], except that friction elements that
    /// slide plainly add no row (their forces are loads, and the
    /// articulated-body recursion serves, linear in the links). Stuck,
    /// breaking away or in no mode yet, they keep the constrained solve.
    pub(crate) fn needs_mass_matrix(&self, ws: &Workspace) -> bool {
        if !self.uses_mass_matrix() {
            return false;
        }
        !self.line_masses.is_empty() || self.constraint_rows > self.frictions.len() || self.friction_holds(ws)
    }

    /// Whether a friction element holds (stuck, breaking away, or in no
    /// mode yet) in the workspace's discrete state.
    pub(crate) fn friction_holds(&self, ws: &Workspace) -> bool {
        self.frictions.iter().any(|f| {
            let flags = FrictionFlags::read(&ws.discrete[f.discrete..f.discrete + FRICTION_DISCRETE]);
            let sliding = matches!(flags.mode, FrictionMode::Forward | FrictionMode::Backward)
                && !flags.start_forward
                && !flags.start_backward;
            !(sliding || flags.free)
        })
    }

    /// The normal force `cgeo fn` of friction element `k` (the law's scale
    /// without a normal-force input).
    fn friction_normal(&self, ws: &Workspace, k: usize) -> f64 {
        let f = &self.frictions[k];
        // A one-way clutch is not pressed by a negative signal (Modelica's `free`).
        let floor = if f.law.one_way { 0.0 } else { f64::NEG_INFINITY };
        f.normal.map_or(f.law.scale, |slot| (f.law.scale * ws.signals[slot]).max(floor))
    }

    /// The sliding forces on the coordinates, as the modes have them.
    pub(crate) fn friction_forces(&self, ws: &mut Workspace, q: &[f64], u: &[f64]) {
        for (k, f) in self.frictions.iter().enumerate() {
            let flags = FrictionFlags::read(&ws.discrete[f.discrete..f.discrete + FRICTION_DISCRETE]);
            let v_rel = f.b.motion(q, u, &ws.lines).1 - f.a.motion(q, u, &ws.lines).1;
            let force = flags.force(&f.law, self.friction_normal(ws, k), v_rel);
            f.b.push(&mut ws.tau, &mut ws.lines, -force);
            f.a.push(&mut ws.tau, &mut ws.lines, force);
        }
    }

    /// The rows of the friction elements: `a_rel = 0` while locked (on
    /// velocities only: a locked element keeps the relative speed it stuck
    /// with), empty otherwise.
    pub(crate) fn friction_terms(&self, ws: &mut Workspace, with_jacobian: bool) {
        let nv = self.states.nv;
        for f in &self.frictions {
            ws.residual[f.row] = 0.0;
            if !with_jacobian {
                continue;
            }
            ws.bias[f.row] = 0.0;
            let flags = FrictionFlags::read(&ws.discrete[f.discrete..f.discrete + FRICTION_DISCRETE]);
            if flags.locked() {
                for (end, sign) in [(&f.b, 1.0), (&f.a, -1.0)] {
                    for (_, v, k) in end.coordinates() {
                        ws.jac[f.row * nv + v] += sign * k;
                    }
                }
            }
        }
    }

    /// After the accelerations: what each element holds or slides with,
    /// its indicators, and during an event iteration its next modes.
    pub(crate) fn friction_modes(&self, ws: &mut Workspace, q: &[f64], u: &[f64], ud: &[f64]) {
        for (k, f) in self.frictions.iter().enumerate() {
            let slots = f.discrete..f.discrete + FRICTION_DISCRETE;
            let flags = FrictionFlags::read(&ws.discrete[slots.clone()]);
            let (s_a, v_a) = f.a.motion(q, u, &ws.lines);
            let (s_b, v_b) = f.b.motion(q, u, &ws.lines);
            let (s_rel, v_rel) = (s_b - s_a, v_b - v_a);
            let a_rel = f.b.acceleration(ud, &[]) - f.a.acceleration(ud, &[]);
            let normal = self.friction_normal(ws, k);
            let law = &f.law;
            let f0 = law.mu(0.0) * normal;
            let f0_max = if !law.one_way {
                law.peak * f0
            } else if normal <= 0.0 {
                ONE_WAY_EPS * law.mu(0.0) * law.scale
            } else {
                law.peak.max(1.0 + ONE_WAY_EPS) * f0
            };
            let locked = flags.locked();
            let forward = flags.start_forward || flags.mode == FrictionMode::Forward;
            // Modelica's path parameter: the holding force while locked,
            // else defined by the acceleration.
            let sa = if locked {
                -ws.lambda[f.row]
            } else if law.one_way {
                a_rel + f0
            } else if flags.free {
                a_rel
            } else if forward {
                a_rel + f0_max
            } else {
                a_rel - f0_max
            };
            let force = if locked { sa } else { flags.force(law, normal, v_rel) };
            let values =
                FrictionValues { s_rel, v_rel, a_rel, force, normal, f0, f0_max, sa, locked, free: flags.free };
            ws.friction[k] = values;
            let own = &mut ws.indicators[f.indicator..f.indicator + FRICTION_INDICATORS];
            if law.one_way {
                flags.one_way_indicators(&values, own);
            } else {
                flags.indicators(&values, own);
            }
            if let (Some(slot), Some((lo, hi))) = (f.stop_indicator, law.stops) {
                ws.indicators[slot] = s_rel - hi;
                ws.indicators[slot + 1] = lo - s_rel;
            }
            if ws.at_event {
                let free = match (law.stops, law.stribeck) {
                    // Without any friction, free between the stops (held at them).
                    (Some((lo, hi)), stribeck) => {
                        f0 <= 0.0 && stribeck.is_none_or(|c| c.f_prop <= 0.0) && s_rel > lo && s_rel < hi
                    }
                    _ => f.normal.is_some() && normal <= 0.0 && !law.one_way,
                };
                let next = FrictionFlags::next(&flags, &values, law, free, ws.initial);
                next.write(&mut ws.discrete[slots]);
                if let Some(stops) = law.stops {
                    self.stop_at(ws, k, stops, (q, u), (s_a, v_a), (s_rel, v_rel));
                }
            }
        }
    }

    /// At an event, an element past one of its `stops`, or on it and
    /// moving into it, is put on it at rest relative to its flange a
    /// (Modelica's `reinit(s, ...)` and `reinit(v, 0)`): a hard stop that
    /// takes the speed. Its flange b is a coordinate's (assembly checks).
    fn stop_at(
        &self,
        ws: &mut Workspace,
        k: usize,
        (lo, hi): (f64, f64),
        (q, u): (&[f64], &[f64]),
        (s_a, v_a): (f64, f64),
        (s_rel, v_rel): (f64, f64),
    ) {
        let b = &self.frictions[k].b;
        let (tol_hi, tol_lo) = (stop_tolerance(hi), stop_tolerance(lo));
        let target = if s_rel > hi + tol_hi || s_rel >= hi - tol_hi && v_rel > 0.0 {
            hi
        } else if s_rel < lo - tol_lo || s_rel <= lo + tol_lo && v_rel < 0.0 {
            lo
        } else {
            return;
        };
        let Some((qi, vi)) = b.coordinate() else { return };
        let (q_on, u_on) = ((s_a + target - b.offset) / b.scale, v_a / b.scale);
        // Once there, the next pass finds nothing to do (the iteration settles).
        if q[qi] != q_on || u[vi] != u_on {
            ws.reinits.push((qi, q_on));
            ws.reinits.push((self.states.nq + vi, u_on));
        }
    }
}
