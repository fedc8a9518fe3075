//! Kinematic loops: the constraints from cut joints and constraint
//! components, the loops they close (for reports), and start values that
//! satisfy them.

use super::connections::Connectors;
use super::links::Tree;
use super::mechanism::{CompiledComponent, JointRef, LoopInfo};
use crate::dynamics::Workspace;
use crate::system::{Attachment, Constraint, CutJoint, GROUND};
use crate::{Error, Mechanism};

/// Start residuals below this (m or rad) count as closed.
const CLOSED: f64 = 1e-10;
const NEWTON_ITERATIONS: usize = 60;
/// Newton steps that hardly shrink the residual before the start is bent.
const STALLED: usize = 4;
/// How often, and by how much (rad per free coordinate, growing), it is
/// bent; a loop of many joints is bent by as much in all (a bend per joint
/// that does not shrink with their number curls a long cable into rings it
/// cannot unwind from).
const BENDS: usize = 3;
const BEND: f64 = 0.05;
const BEND_IN_ALL: f64 = 3.0;

/// The constraints, in the order of `tree.cuts`, and each cut joint's place
/// in its component's joint list.
pub fn constraints(components: &mut [CompiledComponent], tree: &Tree) -> (Vec<Constraint>, usize, usize, usize) {
    let mut constraints = Vec::new();
    let (mut row, mut cut_nq, mut cut_nv) = (0, 0, 0);
    for (index, cut) in tree.cuts.iter().enumerate() {
        let attach = |node: usize| Attachment { anchor: tree.nodes[node].anchor, pose: tree.nodes[node].pose };
        let c = &components[cut.component];
        let (a_local, b_local) = match c.parts[cut.part] {
            crate::components::Part::Joint { a, b, .. } | crate::components::Part::Constraint { a, b, .. } => (a, b),
            _ => unreachable!("cuts are joints or constraints"),
        };
        let connectors =
            (Connectors::id(components, cut.component, a_local), Connectors::id(components, cut.component, b_local));
        let joint = cut.joint.map(|model| {
            let j = CutJoint { model, q_offset: cut_nq, v_offset: cut_nv };
            cut_nq += model.nq();
            cut_nv += model.nv();
            j
        });
        let rows = cut.kind.rows();
        constraints.push(Constraint {
            component: cut.component,
            a: attach(cut.a),
            b: attach(cut.b),
            connectors,
            kind: cut.kind.with_road_base(super::road_base(components, cut.component)),
            row,
            rows,
            joint,
        });
        row += rows;
        if cut.joint.is_some() {
            // The cut joint's coordinates: its slot among the component's joints.
            let position = components[cut.component].parts[..cut.part]
                .iter()
                .filter(|p| matches!(p, crate::components::Part::Joint { .. } | crate::components::Part::Owner { .. }))
                .count();
            let joints = &mut components[cut.component].joints;
            if joints.len() <= position {
                joints.resize(position + 1, JointRef::Cut(usize::MAX));
            }
            joints[position] = JointRef::Cut(index);
        }
    }
    (constraints, row, cut_nq, cut_nv)
}

/// Each constraint's loop: the tree joints between its two ends, and how
/// many of its equations are redundant at the start.
pub fn loop_reports(mechanism: &Mechanism, ws: &mut Workspace) -> Vec<LoopInfo> {
    let nv = mechanism.system.states.nv;
    let mut reports = Vec::new();
    for (index, c) in mechanism.system.constraints.iter().enumerate() {
        let ends = [c.a.anchor, c.b.anchor].map(|a| match a {
            crate::system::Anchor::Link(k) => k,
            crate::system::Anchor::Massless(_) => GROUND,
        });
        let path = |mut k: usize| {
            let mut links = vec![k];
            while k != GROUND {
                k = mechanism.system.links[k].parent;
                links.push(k);
            }
            links
        };
        let (pa, pb) = (path(ends[0]), path(ends[1]));
        let mut joints: Vec<String> = Vec::new();
        for &k in pa.iter().chain(pb.iter()) {
            if k != GROUND && !(pa.contains(&k) && pb.contains(&k)) {
                let name = &mechanism.components[mechanism.system.links[k].source.0].name;
                if !joints.contains(name) {
                    joints.push(name.clone());
                }
            }
        }
        let cut = mechanism.components[c.component].name.clone();
        joints.push(cut.clone());
        // Rank of this constraint's rows alone.
        let rows = &ws.jac[c.row * nv..(c.row + c.rows) * nv];
        let mut gram = vec![0.0; c.rows * c.rows];
        for r in 0..c.rows {
            for s in 0..c.rows {
                gram[r * c.rows + s] = (0..nv).map(|i| rows[r * nv + i] * rows[s * nv + i]).sum();
            }
        }
        let mut perm = vec![0; c.rows];
        let rank = crate::math::dense::ldlt_pivoted(&mut gram, c.rows, &mut perm, 1e-10);
        let wheel_contact = matches!(c.kind, crate::system::ConstraintKind::Wheel { .. })
            .then(|| (0..c.rows).filter(|&i| c.kind.is_velocity_row(i)).count());
        let prescribed = mechanism.system.servos.iter().any(|s| s.constraint == index);
        reports.push(LoopInfo { cut, joints, equations: c.rows, redundant: c.rows - rank, wheel_contact, prescribed });
    }
    reports
}

/// Moves the start positions and velocities that the model did not fix
/// onto the constraints (least change), and counts the degrees of freedom.
pub fn close(mechanism: &mut Mechanism) -> Result<(), Error> {
    let mut ws = mechanism.workspace();
    let (nq, nv) = (mechanism.system.states.nq, mechanism.system.states.nv);
    let mut y = mechanism.system.states.start.clone();
    // Driven coordinates start where their drives put them at t = 0, and stay.
    mechanism.impose_drives(&mut ws, 0.0, &mut y);
    let free = free_velocity_coordinates(mechanism);
    let fixed_values = |range: std::ops::Range<usize>| -> Vec<String> {
        range
            .filter(|&i| mechanism.system.states.fixed[i])
            .map(|i| format!("{} = {}", mechanism.system.states.names[i], mechanism.system.states.start[i]))
            .collect()
    };
    let as_error = |e: crate::DynamicsError| Error::Unsupported {
        component: mechanism.name.clone(),
        what: format!("a start state where {}", mechanism.describe(&e)),
        fix: String::new(),
    };
    let mut free = free;
    let mut best = newton(mechanism, &mut ws, &mut y, &free).map_err(as_error)?;
    // Loop assemblies start on the branch they are given: where the
    // closure found is the other one, their slider is put at the other
    // root and held there while the rest of the loop closes again.
    let flips = branch_flips(mechanism, &mut ws, &y).map_err(as_error)?;
    if !flips.is_empty() {
        let held: Vec<(usize, bool)> = flips.iter().filter(|f| f.3).map(|&(_, v, _, _)| (v, free[v])).collect();
        for &(q, v, value, hold) in &flips {
            y[q] = value;
            if hold {
                free[v] = false;
            }
        }
        best = newton(mechanism, &mut ws, &mut y, &free).map_err(as_error)?;
        for (v, was) in held {
            free[v] = was;
        }
    }
    mechanism.system.constraint_state(&mut ws, &y).map_err(as_error)?;
    let (worst, size) =
        ws.residual
            .iter()
            .enumerate()
            .fold((0, 0.0f64), |acc, (i, r)| if r.abs() > acc.1 { (i, r.abs()) } else { acc });
    if size > CLOSED {
        let reports = loop_reports(mechanism, &mut ws);
        let system = &mechanism.system;
        let joints = match system.constraints.iter().position(|c| c.row <= worst && worst < c.row + c.rows) {
            Some(c) => reports[c].joints.clone(),
            // A coupling's row: the joints it couples cannot be placed.
            None => system
                .couplings
                .iter()
                .filter(|c| c.row == worst)
                .map(|c| mechanism.components[c.component].name.clone())
                .collect(),
        };
        return Err(Error::LoopCannotClose { joints, residual: best, fixed: fixed_values(0..nq) });
    }
    // Velocities: remove the part that violates the constraints, keeping the fixed ones.
    mechanism.system.velocity_residual(&mut ws, &y).map_err(as_error)?;
    mechanism.system.least_norm_step(&mut ws, Some(&free[nv..]), false);
    for i in 0..nv {
        y[nq + i] += ws.du[i];
    }
    mechanism.system.velocity_residual(&mut ws, &y).map_err(as_error)?;
    let violation = ws.lambda.iter().fold(0.0f64, |a, r| a.max(r.abs()));
    let scale = 1.0 + y[nq..].iter().fold(0.0f64, |a, v| a.max(v.abs()));
    if violation > 1e-9 * scale {
        let reports = loop_reports(mechanism, &mut ws);
        let joints = reports.iter().flat_map(|r| r.joints.clone()).collect();
        return Err(Error::LoopCannotMove { joints, violation, fixed: fixed_values(nq..nq + nv) });
    }
    mechanism.system.constraint_state(&mut ws, &y).map_err(as_error)?;
    // What has no inertia must be determined by the constraints.
    let mut dy = vec![0.0; y.len()];
    let weak = match mechanism.rhs(&mut ws, 0.0, &y, &mut dy) {
        Err(crate::DynamicsError::SingularInertia { link }) => {
            Some(mechanism.owner_of_link(link).unwrap_or("the mechanism").to_string())
        }
        // A velocity coordinate (`housing.w`, `sensor.spline_1.w`) belongs
        // to the component its name starts with.
        Err(crate::DynamicsError::SingularMotion { dof }) => {
            Some(mechanism.velocity_name(dof).split('.').next().unwrap_or("the mechanism").to_string())
        }
        _ => None,
    };
    if let Some(joint) = weak {
        return Err(Error::NoInertia {
            joint,
            dof: "motion".into(),
            moved: vec!["(nothing the loops determine)".into()],
        });
    }
    mechanism.system.constraint_state(&mut ws, &y).map_err(as_error)?;
    mechanism.system.states.start = y;
    mechanism.loops = loop_reports(mechanism, &mut ws);
    mechanism.system.dof = mechanism.system.free_degrees_of_freedom(&mut ws);
    if let Some(warning) = singular_start(mechanism, &mut ws) {
        mechanism.warnings.push(warning);
    }
    Ok(())
}

/// A start at a singular configuration of a loop (a parallelogram at its
/// change point, a crank at a dead point): there the constraints lose a
/// rank, so the start counts more degrees of freedom than the mechanism has
/// anywhere near it. Compared with the rank a small step away.
fn singular_start(mechanism: &Mechanism, ws: &mut Workspace) -> Option<String> {
    let system = &mechanism.system;
    let nv = system.states.nv;
    if system.constraints.is_empty() || nv == 0 {
        return None;
    }
    let rank_of = |ws: &mut Workspace, y: &[f64]| -> Option<Vec<usize>> {
        system.constraint_state(ws, y).ok()?;
        let free: Vec<usize> = (0..nv).filter(|&i| system.free_coordinates.get(i).copied().unwrap_or(true)).collect();
        Some(
            system
                .constraints
                .iter()
                .map(|c| {
                    if c.rows == 0 || free.is_empty() {
                        return 0;
                    }
                    let rows =
                        nalgebra::DMatrix::from_fn(c.rows, free.len(), |r, k| ws.jac[(c.row + r) * nv + free[k]]);
                    rows.rank(1e-9 * rows.amax().max(f64::MIN_POSITIVE))
                })
                .collect(),
        )
    };
    let y = system.states.start.clone();
    let here = rank_of(ws, &y)?;
    let mut near = y.clone();
    ws.du[..nv].iter_mut().enumerate().for_each(|(i, d)| *d = 1e-4 * (1.0 + 0.37 * i as f64));
    system.retract(&mut near, ws);
    let there = rank_of(ws, &near)?;
    let lost: Vec<String> =
        here.iter().zip(&there).enumerate().filter(|(_, (h, t))| h < t).map(|(c, _)| mechanism.loop_name(c)).collect();
    (!lost.is_empty()).then(|| {
        format!(
            "the start is a singular configuration of {}: its constraints lose a rank here that they have a small \
             step away (a parallelogram at its change point, a crank at a dead point), so the start counts more \
             degrees of freedom ({}) than the mechanism has near it, and which way it moves on is not decided by \
             the loop; start a little away from it",
            lost.join(" and "),
            system.dof
        )
    })
}

/// Newton's iterations on the positions of the loops, moving the `free`
/// coordinates; the smallest residual met.
fn newton(
    mechanism: &Mechanism,
    ws: &mut Workspace,
    y: &mut [f64],
    free: &[bool],
) -> Result<f64, crate::DynamicsError> {
    let nv = mechanism.system.states.nv;
    let mut best = f64::INFINITY;
    let (mut previous, mut stalled, mut bends) = (f64::INFINITY, 0, 0);
    for _ in 0..NEWTON_ITERATIONS {
        mechanism.system.constraint_state(ws, y)?;
        let size = ws.residual.iter().fold(0.0f64, |a, r| a.max(r.abs()));
        best = best.min(size);
        if size <= CLOSED * 1e-2 {
            break;
        }
        stalled = if size > 0.99 * previous { stalled + 1 } else { 0 };
        previous = size;
        if stalled >= STALLED && bends < BENDS {
            // A stretched-out start (a straight cable between two mounts closer
            // than its length) is a singular point: no first-order motion
            // shortens it. Bend every free joint a little and start again.
            bends += 1;
            let count = free[..nv].iter().filter(|&&f| f).count().max(1) as f64;
            let bend = BEND.min(BEND_IN_ALL / count) * bends as f64;
            for (du, &is_free) in ws.du.iter_mut().zip(&free[..nv]) {
                *du = if is_free { bend } else { 0.0 };
            }
            mechanism.system.retract(y, ws);
            (previous, stalled) = (f64::INFINITY, 0);
            continue;
        }
        mechanism.system.least_norm_step(ws, Some(&free[..nv]), true);
        mechanism.system.retract(y, ws);
    }
    Ok(best)
}

/// For each loop assembly on the other branch than it is given (see
/// [`crate::components::PrismaticBranch`]) at the closed positions `y`:
/// its slider's position coordinate, velocity coordinate, the value that
/// puts it on its branch and `true` (hold it there), and the same for the
/// revolute that turns its rod to meet the slider (`false`: the loop may
/// move it). An assembly whose slider closes the loop (a cut joint) keeps
/// the start configuration's branch.
fn branch_flips(
    mechanism: &Mechanism,
    ws: &mut Workspace,
    y: &[f64],
) -> Result<Vec<(usize, usize, f64, bool)>, crate::DynamicsError> {
    let mut flips = Vec::new();
    if mechanism.components.iter().all(|c| c.component.prismatic_branch().is_none()) {
        return Ok(flips);
    }
    mechanism.system.constraint_state(ws, y)?;
    for c in &mechanism.components {
        let Some(b) = c.component.prismatic_branch() else { continue };
        let Some(&JointRef::Link(link)) = c.joints.get(b.joint) else { continue };
        let pose = |local: usize| {
            let id = c.first_connector + local;
            let node = mechanism.nodes.iter().find(|n| n.connectors.contains(&id))?;
            if let crate::system::Anchor::Massless(_) = node.anchor {
                return None;
            }
            let lw = &ws.links[node.link()];
            Some((node.pose.rot * lw.rot, lw.pos + lw.rot.tr_mul(&node.pose.trans)))
        };
        let (Some((rot_a, r_a)), Some((rot_b, r_b))) = (pose(b.frame_a), pose(b.frame_b)) else { continue };
        let normal = rot_a.tr_mul(&b.normal);
        let across = |v: crate::math::Vec3| v - normal * normal.dot(&v);
        let e = across(rot_b.tr_mul(&b.axis));
        let w = across(r_b + rot_b.tr_mul(&b.rod2) - r_a);
        let k1 = e.dot(&w) / e.norm_squared();
        let disc = k1 * k1 - (w.norm_squared() - b.length * b.length) / e.norm_squared();
        // No closure (or the two meet): nothing to choose.
        if disc.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            continue;
        }
        let l = &mechanism.system.links[link];
        let d = y[l.q_offset] + b.offset;
        if (d + k1 >= 0.0) != b.positive {
            let target = -k1 + if b.positive { disc.sqrt() } else { -disc.sqrt() };
            flips.push((l.q_offset, l.v_offset, target - b.offset, true));
            // And the rod turned to reach the slider there (from the
            // closed loop, the turn between the two places it reaches).
            if let Some(&JointRef::Link(turn)) = c.joints.get(b.turn) {
                let t = &mechanism.system.links[turn];
                let (now, then) = (w + e * d, w + e * target);
                let angle = normal.dot(&now.cross(&then)).atan2(now.dot(&then));
                if t.joint.nq() == 1 {
                    flips.push((t.q_offset, t.v_offset, y[t.q_offset] + angle, false));
                }
            }
        }
    }
    Ok(flips)
}

/// For positions (first `nv`) and velocities (last `nv`): which velocity
/// coordinates may change to close the loops.
pub(super) fn free_velocity_coordinates(mechanism: &Mechanism) -> Vec<bool> {
    let (nq, nv) = (mechanism.system.states.nq, mechanism.system.states.nv);
    let fixed = &mechanism.system.states.fixed;
    let mut free = vec![true; 2 * nv];
    for link in &mechanism.system.links[1..] {
        for dof in 0..link.joint.nv() {
            // A joint's rotation coordinates (quaternion or angles) are fixed together.
            let position_fixed = match link.joint.rotation_coordinates() {
                Some((offset, rot)) if dof >= link.joint.nv() - 3 => {
                    (0..rot.nq()).any(|i| fixed[link.q_offset + offset + i])
                }
                _ => fixed[link.q_offset + dof.min(link.joint.nq() - 1)],
            };
            let driven = !mechanism.system.free_coordinates[link.v_offset + dof];
            free[link.v_offset + dof] = !position_fixed && !driven;
            free[nv + link.v_offset + dof] = !fixed[nq + link.v_offset + dof] && !driven;
        }
    }
    free
}
