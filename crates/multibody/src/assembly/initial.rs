//! Initial equations on the motion of one frame relative to another
//! (FreeMotionScalarInit): the start values the model does not fix are
//! solved so that they hold, positions by Newton steps of least change,
//! then velocities (linear in the joint speeds) likewise.

use super::connections::Connectors;
use super::links::Tree;
use super::mechanism::CompiledComponent;
use super::Mechanism;
use crate::components::Part;
use crate::math::Vec3;
use crate::system::Attachment;
use crate::{Error, Model, Value};
use nalgebra::{DMatrix, DVector};

/// Residuals below this (m, m/s) count as met.
const MET: f64 = 1e-12;
const NEWTON_ITERATIONS: usize = 50;
/// Step of the finite differences of the position Jacobian.
const STEP: f64 = 1e-7;

/// The initial equations one component states.
pub struct InitialMotion {
    component: usize,
    a: Attachment,
    b: Attachment,
    /// `(k, value)`: component k of the relative position, of the velocity.
    positions: Vec<(usize, f64)>,
    velocities: Vec<(usize, f64)>,
}

/// Whether `variable` of component `c` is an initial equation rather than a state.
pub fn is_initial_equation(c: &CompiledComponent, variable: &str) -> bool {
    c.parts.iter().any(|p| matches!(p, Part::InitialMotion { .. })) && relative(variable).is_some()
}

/// `("r_rel_a_2")` -> position component 1; `("v_rel_a_3")` -> velocity component 2.
fn relative(variable: &str) -> Option<(bool, usize)> {
    let (position, k) = if let Some(k) = variable.strip_prefix("r_rel_a_") {
        (true, k)
    } else {
        (false, variable.strip_prefix("v_rel_a_")?)
    };
    let k: usize = k.parse().ok()?;
    (1..=3).contains(&k).then_some((position, k - 1))
}

/// Every component's initial equations.
pub fn collect(
    model: &Model,
    components: &[CompiledComponent],
    conn: &Connectors,
    tree: &Tree,
) -> Result<Vec<InitialMotion>, Error> {
    let mut out = Vec::new();
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
        let mut motion =
            InitialMotion { component: ci, a: attach(a), b: attach(b), positions: Vec::new(), velocities: Vec::new() };
        for (variable, value) in &model.components[ci].initial {
            let Some((is_position, k)) = relative(variable) else { continue };
            let Value::Number(x) = value else {
                return Err(Error::InvalidValue {
                    component: c.name.clone(),
                    name: variable.clone(),
                    value: value.to_string(),
                    reason: "an initial value here is one number".into(),
                });
            };
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
            list.push((k, *x));
        }
        if !(motion.positions.is_empty() && motion.velocities.is_empty()) {
            out.push(motion);
        }
    }
    Ok(out)
}

/// Solves the start state for the initial equations (after the loops are closed).
pub fn solve(mechanism: &mut Mechanism, equations: &[InitialMotion]) -> Result<(), Error> {
    if equations.is_empty() {
        return Ok(());
    }
    let name = |m: &Mechanism| m.components[equations[0].component].name.clone();
    if mechanism.system.constraint_rows > 0 {
        return Err(Error::Unsupported {
            component: name(mechanism),
            what: "initial equations on relative motion in a mechanism with kinematic loops".into(),
            fix: "give the joints' start values instead".into(),
        });
    }
    let (nq, nv) = (mechanism.system.states.nq, mechanism.system.states.nv);
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
            let mut out = DVector::zeros(count);
            let mut i = 0;
            for (e, r) in equations.iter().zip(&r) {
                for &(k, x) in &e.positions {
                    out[i] = r[k] - x;
                    i += 1;
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
            let mut jac = DMatrix::zeros(count, free_positions.len());
            for (col, &i) in free_positions.iter().enumerate() {
                let mut moved = y.clone();
                let mut du = vec![0.0; nv];
                du[i] = STEP;
                retract(system, &mut ws, &mut moved, du);
                jac.set_column(col, &((residual(&mut ws, &moved)? - &res) / STEP));
            }
            let step = jac.pseudo_inverse(1e-12).map_err(|_| cannot(mechanism, equations))? * -res;
            let mut du = vec![0.0; nv];
            for (col, &i) in free_positions.iter().enumerate() {
                du[i] = step[col];
            }
            retract(system, &mut ws, &mut y, du);
        }
        if !met {
            return Err(cannot(mechanism, equations));
        }
    }

    let count = equations.iter().map(|e| e.velocities.len()).sum::<usize>();
    if count > 0 {
        // The relative velocities are linear in the joint speeds: columns
        // from unit speeds, at the solved positions.
        let speeds = |ws: &mut crate::Workspace, y: &[f64]| -> Result<DVector<f64>, Error> {
            let (_, v) = relative_motion(mechanism, ws, y, equations)?;
            let mut out = DVector::zeros(count);
            let mut i = 0;
            for (e, v) in equations.iter().zip(&v) {
                for &(k, x) in &e.velocities {
                    out[i] = v[k] - x;
                    i += 1;
                }
            }
            Ok(out)
        };
        let mut at_rest = y.clone();
        at_rest[nq..].fill(0.0);
        let offset = speeds(&mut ws, &at_rest)?;
        let mut map = DMatrix::zeros(count, free_speeds.len());
        for (col, &i) in free_speeds.iter().enumerate() {
            let mut unit = at_rest.clone();
            unit[nq + i] = 1.0;
            map.set_column(col, &(speeds(&mut ws, &unit)? - &offset));
        }
        let res = speeds(&mut ws, &y)?;
        let step = map.pseudo_inverse(1e-12).map_err(|_| cannot(mechanism, equations))? * -&res;
        for (col, &i) in free_speeds.iter().enumerate() {
            y[nq + i] += step[col];
        }
        if speeds(&mut ws, &y)?.amax() > 1e-9 {
            return Err(cannot(mechanism, equations));
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
    system.kinematics_and_bias(ws, q, u).map_err(|e| Error::Unsupported {
        component: mechanism.name.clone(),
        what: format!("a start state where {}", mechanism.describe(&e)),
        fix: String::new(),
    })?;
    system.world_poses(ws);
    let mut positions = Vec::with_capacity(equations.len());
    let mut velocities = Vec::with_capacity(equations.len());
    for e in equations {
        let (a, b) = (system.point_state(ws, &e.a), system.point_state(ws, &e.b));
        let w_a = match e.a.anchor {
            crate::system::Anchor::Link(k) => e.a.pose.rot * ws.links[k].v.ang,
            crate::system::Anchor::Massless(_) => Vec3::zeros(),
        };
        let r_rel = a.rot * (b.r - a.r);
        positions.push(r_rel);
        velocities.push(a.rot * (b.v - a.v) - w_a.cross(&r_rel));
    }
    Ok((positions, velocities))
}

fn cannot(mechanism: &Mechanism, equations: &[InitialMotion]) -> Error {
    let names: Vec<String> = equations.iter().map(|e| mechanism.components[e.component].name.clone()).collect();
    Error::Unsupported {
        component: names.join(", "),
        what: "initial values of relative motion that no start of the free joints meets".into(),
        fix: "check that the values are reachable, give guesses closer to them, or fix fewer joint start values".into(),
    }
}
