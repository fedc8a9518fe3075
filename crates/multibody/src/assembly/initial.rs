//! Initial equations besides the start values of states: on the motion of
//! one frame relative to another (FreeMotionScalarInit), and on the
//! relative position and speed of a 1-D element (`spring.phi_rel(initial =
//! 0)`, `damper.w_rel(initial = 0)`), which are not states. The start
//! values the model does not fix are solved so that they hold, with the
//! loops kept closed: positions by Newton steps of least change, then
//! velocities (linear in the joint speeds) likewise.

use super::axis::{self, Places};
use super::connections::Connectors;
use super::links::Tree;
use super::mechanism::CompiledComponent;
use super::Mechanism;
use crate::components::Part;
use crate::math::Vec3;
use crate::system::{Attachment, FlangeRef, SignalLaw};
use crate::{Error, Model, Value};
use nalgebra::{DMatrix, DVector};

/// Residuals below this (m, m/s) count as met.
const MET: f64 = 1e-12;
const NEWTON_ITERATIONS: usize = 50;
/// Step of the finite differences of the position Jacobian.
const STEP: f64 = 1e-7;

/// What an initial equation relates.
#[derive(Clone, Copy)]
enum Ends {
    /// Frame b relative to frame a, resolved in a (three components).
    Frames { a: Attachment, b: Attachment },
    /// Flange b relative to flange a (one component).
    Flanges { a: FlangeRef, b: FlangeRef },
}

/// The initial equations one component states.
pub struct InitialMotion {
    component: usize,
    ends: Ends,
    /// `(k, value, variable)`: component k of the relative position, of
    /// the velocity, the value it starts at, and the variable that says so.
    positions: Vec<(usize, f64, String)>,
    velocities: Vec<(usize, f64, String)>,
}

/// Whether `variable` of component `c` is an initial equation rather than a state.
pub fn is_initial_equation(c: &CompiledComponent, variable: &str) -> bool {
    let frames = c.parts.iter().any(|p| matches!(p, Part::InitialMotion { .. })) && relative(variable).is_some();
    frames || element_relative(c, variable).is_some()
}

/// For a variable that is the position or speed of one 1-D connector
/// relative to another (a compliant element's `phi_rel`, `s_rel`, `w_rel`,
/// `v_rel`; a 1-D sensor's output, relative or absolute): whether it is a
/// position, and the connectors (`None`: the fixed ground).
fn element_relative(c: &CompiledComponent, variable: &str) -> Option<(bool, Option<usize>, usize)> {
    if !c.spec.variables.iter().any(|v| v.name == variable) {
        return None;
    }
    let mut found = None;
    for part in &c.parts {
        let this = match *part {
            Part::Element1D { a, b, .. } => match variable {
                "phi_rel" | "s_rel" => Some((true, Some(a), b)),
                "w_rel" | "v_rel" => Some((false, Some(a), b)),
                _ => None,
            },
            Part::Signal { output, ref law, flanges: [a, Some(b)], .. }
                if c.spec.connectors[output].name == variable =>
            {
                match law {
                    SignalLaw::FlangePosition => Some((true, a, b)),
                    SignalLaw::FlangeSpeed => Some((false, a, b)),
                    _ => None,
                }
            }
            _ => None,
        };
        if this.is_some() {
            if found.is_some() {
                return None;
            }
            found = this;
        }
    }
    found
}

/// `("r_rel_a_2")` -> position component 1; `("v_rel_a_3")` -> velocity component 2.
fn relative(variable: &str) -> Option<(bool, usize)> {
    let (position, k) = if let Some(k) = variable.strip_prefix("r_rel_a_") {
        (true, k)
    } else {
        (false, variable.strip_prefix("v_rel_a_")?)
    };
    let k: usize = k.parse().ok()?;
    // `then`, not `then_some`: `k - 1` must not be computed for k = 0.
    (1..=3).contains(&k).then(|| (position, k - 1))
}

/// Every component's initial equations.
pub fn collect(
    model: &Model,
    components: &[CompiledComponent],
    conn: &Connectors,
    tree: &Tree,
    places: &Places,
) -> Result<Vec<InitialMotion>, Error> {
    let mut out = Vec::new();
    // Hidden components (of the equations) come after the model's, with no start values.
    for (ci, (c, instance)) in components.iter().zip(&model.components).enumerate() {
        for (variable, value) in &instance.initial {
            let Some((position, a, b)) = element_relative(c, variable) else { continue };
            let x = one_number(c, variable, value)?;
            let flange = |local: usize| axis::flange(components, conn, places, Connectors::id(components, ci, local));
            let a = a.map_or(Ok(FlangeRef::FIXED), flange)?;
            let ends = Ends::Flanges { a, b: flange(b)? };
            let goal = vec![(0, x, variable.clone())];
            let (positions, velocities) = if position { (goal, vec![]) } else { (vec![], goal) };
            out.push(InitialMotion { component: ci, ends, positions, velocities });
        }
    }
    for (ci, c) in components.iter().enumerate() {
        let Some(&Part::InitialMotion { a, b, position, velocity }) =
            c.parts.iter().find(|p| matches!(p, Part::InitialMotion { .. }))
        else {
            continue;
        };
        let attach = |local: usize| {
            let node = &tree.nodes[conn.node(Connectors::id(components, ci, local))];
            Attachment { anchor: node.anchor, pose: node.pose }
        };
        let ends = Ends::Frames { a: attach(a), b: attach(b) };
        let mut motion = InitialMotion { component: ci, ends, positions: Vec::new(), velocities: Vec::new() };
        for (variable, value) in &model.components[ci].initial {
            let Some((is_position, k)) = relative(variable) else { continue };
            let x = one_number(c, variable, value)?;
            let (allowed, switch, list) = if is_position {
                (position, "use_r", &mut motion.positions)
            } else {
                (velocity, "use_v", &mut motion.velocities)
            };
            if !allowed {
                return Err(Error::NotAState {
                    component: c.name.clone(),
                    variable: variable.clone(),
                    reason: format!("it is an initial equation only with `{switch} = true`; set it"),
                });
            }
            list.push((k, x, variable.clone()));
        }
        if !(motion.positions.is_empty() && motion.velocities.is_empty()) {
            out.push(motion);
        }
    }
    Ok(out)
}

/// The value of an initial equation: one number.
fn one_number(c: &CompiledComponent, variable: &str, value: &Value) -> Result<f64, Error> {
    match value {
        Value::Number(x) => Ok(*x),
        _ => Err(Error::InvalidValue {
            component: c.name.clone(),
            name: variable.to_string(),
            value: value.to_string(),
            reason: "an initial value here is one number".into(),
        }),
    }
}

/// Solves the start state for the initial equations (after the loops are
/// closed), keeping the constraints met.
pub fn solve(mechanism: &mut Mechanism, equations: &[InitialMotion]) -> Result<(), Error> {
    if equations.is_empty() {
        return Ok(());
    }
    let (nq, nv) = (mechanism.system.states.nq, mechanism.system.states.nv);
    let rows = mechanism.system.constraint_rows;
    // Constraint rows on velocities only (rolling) say nothing about positions.
    let mut position_rows = vec![true; rows];
    for c in &mechanism.system.constraints {
        for i in (0..c.rows).filter(|&i| c.kind.is_velocity_row(i)) {
            position_rows[c.row + i] = false;
        }
    }
    let free = super::loops::free_velocity_coordinates(mechanism);
    let free_positions: Vec<usize> = (0..nv).filter(|&i| free[i]).collect();
    let free_speeds: Vec<usize> = (0..nv).filter(|&i| free[nv + i]).collect();
    let mut ws = mechanism.workspace();
    let mut y = mechanism.system.states.start.clone();
    let system = &mechanism.system;

    let count = equations.iter().map(|e| e.positions.len()).sum::<usize>();
    if count > 0 {
        let residual = |ws: &mut crate::Workspace, y: &[f64]| -> Result<DVector<f64>, Error> {
            let (r, _) = relative_motion(mechanism, ws, y, equations)?;
            let mut out = DVector::zeros(count + rows);
            let mut i = 0;
            for (e, r) in equations.iter().zip(&r) {
                for &(k, x, _) in &e.positions {
                    out[i] = r[k] - x;
                    i += 1;
                }
            }
            if rows > 0 {
                system.constraint_state(ws, y).map_err(|e| unreachable_start(mechanism, &e))?;
                for (r, &on_positions) in position_rows.iter().enumerate() {
                    out[count + r] = if on_positions { ws.residual[r] } else { 0.0 };
                }
            }
            Ok(out)
        };
        let mut met = false;
        for _ in 0..NEWTON_ITERATIONS {
            let res = residual(&mut ws, &y)?;
            if res.amax() <= MET {
                met = true;
                break;
            }
            if free_positions.is_empty() {
                break;
            }
            let mut jac = DMatrix::zeros(count + rows, free_positions.len());
            for (col, &i) in free_positions.iter().enumerate() {
                let mut moved = y.clone();
                let mut du = vec![0.0; nv];
                du[i] = STEP;
                retract(system, &mut ws, &mut moved, du);
                jac.set_column(col, &((residual(&mut ws, &moved)? - &res) / STEP));
            }
            let step = jac.pseudo_inverse(1e-12).map_err(|_| cannot(mechanism, equations, &res, true))? * -&res;
            let mut du = vec![0.0; nv];
            for (col, &i) in free_positions.iter().enumerate() {
                du[i] = step[col];
            }
            retract(system, &mut ws, &mut y, du);
        }
        if !met {
            return Err(cannot(mechanism, equations, &residual(&mut ws, &y)?, true));
        }
    }

    let count = equations.iter().map(|e| e.velocities.len()).sum::<usize>();
    if count > 0 {
        // The relative velocities are linear in the joint speeds: columns
        // from unit speeds, at the solved positions.
        let speeds = |ws: &mut crate::Workspace, y: &[f64]| -> Result<DVector<f64>, Error> {
            let (_, v) = relative_motion(mechanism, ws, y, equations)?;
            let mut out = DVector::zeros(count + rows);
            let mut i = 0;
            for (e, v) in equations.iter().zip(&v) {
                for &(k, x, _) in &e.velocities {
                    out[i] = v[k] - x;
                    i += 1;
                }
            }
            if rows > 0 {
                system.velocity_residual(ws, y).map_err(|e| unreachable_start(mechanism, &e))?;
                for r in 0..rows {
                    out[count + r] = ws.lambda[r];
                }
            }
            Ok(out)
        };
        let mut at_rest = y.clone();
        at_rest[nq..].fill(0.0);
        let offset = speeds(&mut ws, &at_rest)?;
        let mut map = DMatrix::zeros(count + rows, free_speeds.len());
        for (col, &i) in free_speeds.iter().enumerate() {
            let mut unit = at_rest.clone();
            unit[nq + i] = 1.0;
            map.set_column(col, &(speeds(&mut ws, &unit)? - &offset));
        }
        let res = speeds(&mut ws, &y)?;
        if !free_speeds.is_empty() {
            let step = map.pseudo_inverse(1e-12).map_err(|_| cannot(mechanism, equations, &res, false))? * -&res;
            for (col, &i) in free_speeds.iter().enumerate() {
                y[nq + i] += step[col];
            }
        }
        let res = speeds(&mut ws, &y)?;
        if res.amax() > 1e-9 {
            return Err(cannot(mechanism, equations, &res, false));
        }
    }
    mechanism.system.states.start = y;
    Ok(())
}

/// `q <- q (+) du` for the velocity-coordinate step `du`.
fn retract(system: &crate::system::System, ws: &mut crate::Workspace, y: &mut [f64], du: Vec<f64>) {
    ws.du.copy_from_slice(&du);
    system.retract(y, ws);
}

/// Position and velocity of each equation's frame b relative to its frame a, resolved in a.
fn relative_motion(
    mechanism: &Mechanism,
    ws: &mut crate::Workspace,
    y: &[f64],
    equations: &[InitialMotion],
) -> Result<(Vec<Vec3>, Vec<Vec3>), Error> {
    let system = &mechanism.system;
    let (q, u) = y.split_at(system.states.nq);
    system.kinematics_and_bias(ws, q, u).map_err(|e| unreachable_start(mechanism, &e))?;
    system.world_poses(ws);
    system.line_motion(ws);
    let mut positions = Vec::with_capacity(equations.len());
    let mut velocities = Vec::with_capacity(equations.len());
    for e in equations {
        match e.ends {
            Ends::Frames { a: at_a, b: at_b } => {
                let (a, b) = (system.point_state(ws, &at_a), system.point_state(ws, &at_b));
                let w_a = match at_a.anchor {
                    crate::system::Anchor::Link(k) => at_a.pose.rot * ws.links[k].v.ang,
                    crate::system::Anchor::Massless(_) => Vec3::zeros(),
                };
                let r_rel = a.rot * (b.r - a.r);
                positions.push(r_rel);
                velocities.push(a.rot * (b.v - a.v) - w_a.cross(&r_rel));
            }
            Ends::Flanges { a, b } => {
                let ((s_a, v_a), (s_b, v_b)) = (a.motion(q, u, &ws.lines), b.motion(q, u, &ws.lines));
                positions.push(Vec3::new(s_b - s_a, 0.0, 0.0));
                velocities.push(Vec3::new(v_b - v_a, 0.0, 0.0));
            }
        }
    }
    Ok((positions, velocities))
}

/// A start state the kinematics cannot evaluate.
fn unreachable_start(mechanism: &Mechanism, e: &crate::DynamicsError) -> Error {
    Error::Unsupported {
        component: mechanism.name.clone(),
        what: format!("a start state where {}", mechanism.describe(e)),
        fix: String::new(),
    }
}

/// The error for initial equations left unmet with residuals `res`
/// (positions or velocities): the first one unmet, what it reached, and the
/// start values that held.
fn cannot(mechanism: &Mechanism, equations: &[InitialMotion], res: &DVector<f64>, positions: bool) -> Error {
    let states = &mechanism.system.states;
    let fixed: Vec<String> = (0..states.nq + states.nv)
        .filter(|&i| states.fixed[i] && (i < states.nq) == positions)
        .map(|i| states.names[i].clone())
        .collect();
    let goals = equations.iter().flat_map(|e| {
        let list = if positions { &e.positions } else { &e.velocities };
        list.iter().map(move |g| (e.component, g))
    });
    for ((component, (_, value, variable)), r) in goals.zip(res.iter()) {
        if r.abs() > 1e-9 {
            return Error::StartUnmet {
                component: mechanism.components[component].name.clone(),
                variable: variable.clone(),
                value: *value,
                reached: value + r,
                fixed,
            };
        }
    }
    let names: Vec<String> = equations.iter().map(|e| mechanism.components[e.component].name.clone()).collect();
    Error::Unsupported {
        component: names.join(", "),
        what: "initial values of relative motion that keep a kinematic loop open".into(),
        fix: "check that the values are reachable, give guesses closer to them, or fix fewer start values".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::relative;

    #[test]
    fn relative_components_are_numbered_from_one() {
        assert_eq!(relative("r_rel_a_1"), Some((true, 0)));
        assert_eq!(relative("v_rel_a_3"), Some((false, 2)));
        // Found by fuzzing `check_file`: index 0 overflowed in debug builds.
        assert_eq!(relative("r_rel_a_0"), None);
        assert_eq!(relative("v_rel_a_4"), None);
    }
}
