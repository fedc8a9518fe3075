//! Friction elements with modes in the dynamics (see
//! [`crate::system::friction`]): their sliding forces among the 1-D loads,
//! their constraint rows while locked, and after the accelerations what
//! they hold, their indicators, and at events their next modes.

use super::Workspace;
use crate::system::friction::{FrictionFlags, FrictionValues, FRICTION_DISCRETE, FRICTION_INDICATORS};
use crate::system::System;

impl System {
    /// The normal force `cgeo fn` of friction element `k` (the law's scale
    /// without a normal-force input).
    fn friction_normal(&self, ws: &Workspace, k: usize) -> f64 {
        let f = &self.frictions[k];
        f.normal.map_or(f.law.scale, |slot| f.law.scale * ws.signals[slot])
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
                    if let Some((_, v)) = end.coordinate() {
                        ws.jac[f.row * nv + v] += sign * end.scale;
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
            let f0 = f.law.mu(0.0) * normal;
            let f0_max = f.law.peak * f0;
            let locked = flags.locked();
            let forward = flags.start_forward || flags.mode == crate::system::friction::FrictionMode::Forward;
            // Modelica's path parameter: the holding force while locked,
            // else defined by the acceleration.
            let sa = if locked {
                -ws.lambda[f.row]
            } else if flags.free {
                a_rel
            } else if forward {
                a_rel + f0_max
            } else {
                a_rel - f0_max
            };
            let force = if locked { sa } else { flags.force(&f.law, normal, v_rel) };
            let values =
                FrictionValues { s_rel, v_rel, a_rel, force, normal, f0, f0_max, sa, locked, free: flags.free };
            ws.friction[k] = values;
            flags.indicators(&values, &mut ws.indicators[f.indicator..f.indicator + FRICTION_INDICATORS]);
            if ws.at_event {
                let free = f.normal.is_some() && normal <= 0.0;
                let next = FrictionFlags::next(&flags, &values, f.law.v_small, free, ws.initial);
                next.write(&mut ws.discrete[slots]);
            }
        }
    }
}
