//! Output variables at one time: the motion of every frame, the cut force at
//! every connector (a recursive Newton-Euler pass over the flow tree), and
//! every component's own variables.

use crate::assembly::JointRef;
use crate::assembly::Mechanism;
use crate::assembly::SignalTable;
use crate::components::{
    ConnectorType, Element1DState, EvalContext, FlangeState, FrameState, FrictionState, JointState, Part,
};
use crate::dynamics::{DynamicsError, Workspace};
use crate::math::rotation::planar_angle;
use crate::math::Transform;
use crate::math::{Motion, Vec3};
use crate::system::JointMotion;
use crate::system::{Anchor, FlangeRef, GROUND};
use std::sync::Arc;

/// The name, unit and description of one scalar output signal.
#[derive(Clone, Debug, PartialEq)]
pub struct Signal {
    pub name: String,
    pub unit: &'static str,
}

/// Reusable buffers for evaluating outputs.
#[derive(Debug, Default)]
pub(crate) struct OutputScratch {
    frames: Vec<FrameState>,
    signals: Vec<f64>,
    flanges: Vec<FlangeState>,
    node_wrench: Vec<(Vec3, Vec3)>,
    flows: Vec<(Vec3, Vec3)>,
    dy: Vec<f64>,
    /// Coordinates of cut joints, computed from their frames.
    cut_q: Vec<f64>,
    cut_qdot: Vec<f64>,
    cut_u: Vec<f64>,
    cut_udot: Vec<f64>,
    cut_tau: Vec<f64>,
    /// The torque (force) each joint coordinate gets through its axis:
    /// the drive train's, less what accelerates the inertias geared to it
    /// (their armature, which the dynamics keeps in the mass matrix).
    axis_tau: Vec<f64>,
    /// Accelerations of the lines' lengths.
    line_a: Vec<f64>,
    /// One component's output values.
    values: Vec<f64>,
    /// With Euler-angle joints in charts: the state and its derivative in
    /// the library's coordinates, and per link the angles last reported
    /// (whose branch the next continue).
    library: Vec<f64>,
    library_dy: Vec<f64>,
    euler_guess: Vec<Option<Vec3>>,
}

const FRAME_SIGNALS: [(&str, usize, &str); 4] = [("r_0", 3, "m"), ("R", 9, ""), ("f", 3, "N"), ("tau", 3, "N.m")];
/// A planar frame's signals, all scalars in world coordinates.
const FRAME_2D_SIGNALS: [(&str, &str); 6] =
    [("x", "m"), ("y", "m"), ("phi", "rad"), ("fx", "N"), ("fy", "N"), ("tau", "N.m")];

impl Mechanism {
    /// Every output signal, in the order of a [`crate::Solution`]'s columns:
    /// per component, its variables, then `r_0`, `R`, `f` and `tau` of each
    /// of its frame connectors.
    pub fn signals(&self) -> Vec<Signal> {
        let table = self.signal_table();
        table.names().iter().zip(table.units()).map(|(name, &unit)| Signal { name: name.clone(), unit }).collect()
    }

    /// The names and units of every output signal, named at the first call.
    pub(crate) fn signal_table(&self) -> &Arc<SignalTable> {
        self.signal_table.get_or_init(|| Arc::new(self.name_signals()))
    }

    fn name_signals(&self) -> SignalTable {
        let mut out = Vec::new();
        let mut owners = Vec::new();
        for (k, c) in self.components.iter().enumerate().filter(|(_, c)| !c.hidden) {
            for v in &c.variables {
                for suffix in v.shape.suffixes() {
                    // A variable without a name is the component's own value.
                    let name = if v.name.is_empty() {
                        format!("{}{}", c.name, suffix)
                    } else {
                        format!("{}.{}{}", c.name, v.name, suffix)
                    };
                    out.push(Signal { name, unit: v.unit });
                }
            }
            for conn in c.spec.public_connectors().filter(|k| k.ty == ConnectorType::Frame2D) {
                for (name, unit) in FRAME_2D_SIGNALS {
                    out.push(Signal { name: format!("{}.{}.{}", c.name, conn.name, name), unit });
                }
            }
            for conn in c.spec.public_connectors().filter(|k| k.ty == ConnectorType::Frame) {
                for (name, size, unit) in FRAME_SIGNALS {
                    let shape = if size == 9 {
                        crate::components::Shape::Matrix(3, 3)
                    } else {
                        crate::components::Shape::Vector(3)
                    };
                    for suffix in shape.suffixes() {
                        out.push(Signal { name: format!("{}.{}.{}{}", c.name, conn.name, name, suffix), unit });
                    }
                }
            }
            owners.resize(out.len(), Some(k));
        }
        // The variables of the model's own equations.
        for (name, _) in &self.system.equations.outputs {
            out.push(Signal { name: name.clone(), unit: "" });
        }
        owners.resize(out.len(), None);
        for constraint in &self.system.constraints {
            let name = &self.components[constraint.component].name;
            for k in 1..=constraint.rows {
                out.push(Signal { name: format!("{name}.constraint_residual[{k}]"), unit: "" });
            }
        }
        // The couplings' rows follow those of the constraints, one each.
        for coupling in &self.system.couplings {
            let name = &self.components[coupling.component].name;
            out.push(Signal { name: format!("{name}.constraint_residual[1]"), unit: "" });
        }
        owners.resize(out.len(), None);
        let (names, units) = out.into_iter().map(|s| (s.name, s.unit)).unzip();
        SignalTable::with_owners(names, units, owners)
    }

    /// The state `y` and its derivative (in `scratch.dy`) with the joints
    /// that a simulator moved to a chart (near the singular configuration
    /// of their Euler angles) in the library's coordinates: their angles
    /// from the orientation, in the branch of the last ones reported, their
    /// rates from the angular velocity, and a free joint's position and
    /// velocity resolved in its own frame_a again.
    fn library_coordinates(&self, y: &[f64], scratch: &mut OutputScratch) {
        use crate::system::joint::RotationCoordinates;
        let nq = self.system.states.nq;
        scratch.library.clear();
        scratch.library.extend_from_slice(y);
        scratch.library_dy.clear();
        scratch.library_dy.extend_from_slice(&scratch.dy);
        scratch.euler_guess.resize(self.system.links.len(), None);
        let v3 = |s: &[f64], i: usize| Vec3::new(s[i], s[i + 1], s[i + 2]);
        for (k, link) in self.system.links.iter().enumerate() {
            let (Some(chart), Some((offset, RotationCoordinates::Euler { sequence }))) =
                (link.chart, link.joint.rotation_coordinates())
            else {
                continue;
            };
            let (qa, ua) = (link.q_offset + offset, nq + link.v_offset + offset);
            let guess = scratch.euler_guess[k].unwrap_or(chart.phi);
            let psi = (&v3(y, qa), &v3(y, ua), &v3(&scratch.dy, ua));
            let (phi, phid, phidd) = crate::dynamics::chart::library_coordinates(sequence, &chart, psi, &guess);
            if phi.iter().all(|x| x.is_finite()) {
                scratch.euler_guess[k] = Some(phi);
            }
            scratch.library[qa..qa + 3].copy_from_slice(phi.as_slice());
            scratch.library[ua..ua + 3].copy_from_slice(phid.as_slice());
            scratch.library_dy[qa..qa + 3].copy_from_slice(phid.as_slice());
            scratch.library_dy[ua..ua + 3].copy_from_slice(phidd.as_slice());
            if offset == 3 {
                // A free joint: position and velocity were resolved in the turned frame_a.
                for at in [link.q_offset, nq + link.v_offset] {
                    let back = chart.base.tr_mul(&v3(y, at));
                    scratch.library[at..at + 3].copy_from_slice(back.as_slice());
                    let back = chart.base.tr_mul(&v3(&scratch.dy, at));
                    scratch.library_dy[at..at + 3].copy_from_slice(back.as_slice());
                }
            }
        }
    }

    /// Evaluates the output signals at `(t, y)` into `row` (one value per
    /// signal): those of every component, or with `wanted` only those of
    /// the components it marks (the other values are left as they were).
    pub(crate) fn outputs_into(
        &self,
        ws: &mut Workspace,
        scratch: &mut OutputScratch,
        t: f64,
        y: &[f64],
        row: &mut Vec<f64>,
        wanted: Option<&[bool]>,
    ) -> Result<(), DynamicsError> {
        let nq = self.system.states.nq;
        scratch.dy.resize(y.len(), 0.0);
        // Driven coordinates read their exact values, as the dynamics did.
        let exact;
        let y = if self.system.drives.is_empty() {
            y
        } else {
            let mut y_exact = y.to_vec();
            self.impose_drives(ws, t, &mut y_exact);
            exact = y_exact;
            &exact[..]
        };
        self.rhs(ws, t, y, &mut scratch.dy)?;
        self.system.run_output_equations(ws);
        self.system.world_poses(ws);
        // True link accelerations: the ABA ran in a frame falling with gravity.
        for w in ws.links.iter_mut() {
            w.a += Motion::new(Vec3::zeros(), w.rot * self.system.uniform_gravity);
        }
        self.frame_states(ws, scratch);
        self.cut_forces(ws, scratch, y);
        self.cut_joint_coordinates(scratch);
        scratch.signals.clear();
        scratch.signals.extend(self.signal_of_connector.iter().map(|&slot| ws.signals[slot]));
        let charted = self.system.links.iter().any(|l| l.chart.is_some());
        if charted {
            self.library_coordinates(y, scratch);
        }
        let (q, u) = y.split_at(nq);
        let (qd, ud) = scratch.dy.split_at(nq);
        // What the components see of their joints: the library's coordinates.
        let (jq, ju, jqd, jud) = if charted {
            let (a, b) = scratch.library.split_at(nq);
            let (c, d) = scratch.library_dy.split_at(nq);
            (a, b, c, d)
        } else {
            (q, u, qd, ud)
        };
        scratch.axis_tau.clear();
        scratch.axis_tau.extend_from_slice(&ws.tau);
        for link in self.system.links.iter().filter(|l| l.armature != 0.0) {
            scratch.axis_tau[link.v_offset] -= link.armature * ud[link.v_offset];
        }
        // A line's length accelerates as s'' = e . a_rel + (|v_rel|^2 - s'^2) / s.
        scratch.line_a.clear();
        for (line, state) in self.system.lines.iter().zip(&ws.lines) {
            let (a, b) = (&scratch.frames[line.connectors.0], &scratch.frames[line.connectors.1]);
            let v_rel = b.v_0 - a.v_0;
            scratch.line_a.push(state.e.dot(&(b.a_0 - a.a_0)) + (v_rel.norm_squared() - state.v * state.v) / state.s);
        }
        self.planar_frames_in_plane(&mut scratch.frames);
        scratch.flanges.clear();
        scratch.flanges.extend(self.flange_of_connector.iter().map(|f| {
            let (s, v) = f.motion(q, u, &ws.lines);
            FlangeState { s, v, a: f.acceleration(ud, &scratch.line_a) }
        }));

        row.resize(self.signal_table().names().len(), 0.0);
        let mut column = 0;
        let mut joints: Vec<JointState> = Vec::new();
        let mut elements: Vec<Element1DState> = Vec::new();
        let mut frictions: Vec<FrictionState> = Vec::new();
        for (k, c) in self.components.iter().enumerate() {
            let width = self.output_width(c);
            if c.hidden || wanted.is_some_and(|w| !w[k]) {
                column += width;
                continue;
            }
            joints.clear();
            for &joint in &c.joints {
                joints.push(match joint {
                    JointRef::Link(k) => {
                        let l = &self.system.links[k];
                        let (qr, vr) = (l.q_offset..l.q_offset + l.joint.nq(), l.v_offset..l.v_offset + l.joint.nv());
                        JointState {
                            q: &jq[qr.clone()],
                            u: &ju[vr.clone()],
                            qdot: &jqd[qr],
                            udot: &jud[vr.clone()],
                            tau: &scratch.axis_tau[vr],
                        }
                    }
                    JointRef::Cut(k) => {
                        let cut = self.system.constraints[k].joint.expect("cut joints carry their model");
                        let (qr, vr) =
                            (cut.q_offset..cut.q_offset + cut.model.nq(), cut.v_offset..cut.v_offset + cut.model.nv());
                        JointState {
                            q: &scratch.cut_q[qr.clone()],
                            u: &scratch.cut_u[vr.clone()],
                            qdot: &scratch.cut_qdot[qr],
                            udot: &scratch.cut_udot[vr.clone()],
                            tau: &scratch.cut_tau[vr],
                        }
                    }
                });
            }
            elements.clear();
            for &e in &c.elements {
                let el = &self.system.axis_elements[e];
                let at = |f: FlangeRef| {
                    let (s, v) = f.motion(q, u, &ws.lines);
                    (s, v, f.acceleration(ud, &scratch.line_a))
                };
                let (a, b) = (at(el.a), at(el.b));
                let s_rel = b.0 - a.0;
                let v_rel = b.1 - a.1;
                elements.push(Element1DState {
                    s_rel,
                    v_rel,
                    a_rel: b.2 - a.2,
                    force: el.law.force(s_rel, v_rel, &ws.signals),
                });
            }
            frictions.clear();
            for &f in &c.frictions {
                let friction = &self.system.frictions[f];
                let flags = crate::system::friction::FrictionFlags::read(&ws.discrete[friction.discrete..]);
                frictions.push(FrictionState {
                    values: ws.friction[f],
                    mode: flags.mode as i32 as f64,
                    start_forward: flags.start_forward,
                    start_backward: flags.start_backward,
                });
            }
            let own = c.first_connector..c.first_connector + c.spec.connectors.len();
            let frames = &scratch.frames[own.clone()];
            let signals = &scratch.signals[own.clone()];
            let flanges = &scratch.flanges[own];
            let ctx = EvalContext {
                time: t,
                world: &self.world,
                frames,
                joints: &joints,
                elements: &elements,
                frictions: &frictions,
                signals,
                flanges,
            };
            let values = &mut scratch.values;
            values.clear();
            c.component.evaluate(&ctx, values);
            debug_assert_eq!(
                values.len(),
                c.variables.iter().map(|v| v.shape.len()).sum::<usize>(),
                "{} pushed the wrong number of values",
                c.name
            );
            for (local, conn) in c.spec.connectors.iter().enumerate() {
                if conn.ty == ConnectorType::Frame2D && !conn.internal {
                    let f = &frames[local];
                    let (force, torque) = (f.rot.tr_mul(&f.f), f.rot.tr_mul(&f.tau));
                    values.extend([f.r_0.x, f.r_0.y, planar_angle(&f.rot), force.x, force.y, torque.z]);
                }
            }
            for (local, conn) in c.spec.connectors.iter().enumerate() {
                if conn.ty == ConnectorType::Frame && !conn.internal {
                    let f = &frames[local];
                    values.extend_from_slice(f.r_0.as_slice());
                    values.extend(f.rot.transpose().iter()); // row-major R[i,j]
                    values.extend_from_slice(f.f.as_slice());
                    values.extend_from_slice(f.tau.as_slice());
                }
            }
            row[column..column + width].copy_from_slice(values);
            column += width;
        }
        for (_, reg) in &self.system.equations.outputs {
            row[column] = ws.registers[*reg as usize];
            column += 1;
        }
        // Friction rows (after the couplings') have no residual to report.
        let reported = ws.residual.len() - self.system.frictions.len();
        row[column..].copy_from_slice(&ws.residual[..reported]);
        Ok(())
    }

    /// How many output columns a component has: its variables' values,
    /// then 24 per public frame connector.
    fn output_width(&self, c: &crate::assembly::CompiledComponent) -> usize {
        if c.hidden {
            return 0;
        }
        let frames = c.spec.public_connectors().filter(|k| k.ty == ConnectorType::Frame).count();
        let planar = c.spec.public_connectors().filter(|k| k.ty == ConnectorType::Frame2D).count();
        let per_frame: usize = FRAME_SIGNALS.iter().map(|(_, size, _)| size).sum();
        c.variables.iter().map(|v| v.shape.len()).sum::<usize>() + frames * per_frame + planar * FRAME_2D_SIGNALS.len()
    }

    /// Planar frames in a placed plane read in its coordinates, as their
    /// components and the `x`, `y`, `phi` of Frame2D connectors say them
    /// (after the cut forces and cut joints, which work in the world's).
    fn planar_frames_in_plane(&self, frames: &mut [FrameState]) {
        let plane = &self.world.plane;
        if *plane == Transform::IDENTITY {
            return;
        }
        for c in &self.components {
            for (local, connector) in c.spec.connectors.iter().enumerate() {
                if connector.ty == ConnectorType::Frame2D {
                    let frame = &mut frames[c.first_connector + local];
                    *frame = frame.in_plane(plane);
                }
            }
        }
    }

    /// The coordinates, rates and accelerations of cut joints, from the
    /// motion of their frames (they are not states).
    fn cut_joint_coordinates(&self, scratch: &mut OutputScratch) {
        scratch.cut_q.resize(self.system.cut_nq, 0.0);
        scratch.cut_qdot.resize(self.system.cut_nq, 0.0);
        scratch.cut_u.resize(self.system.cut_nv, 0.0);
        scratch.cut_udot.resize(self.system.cut_nv, 0.0);
        scratch.cut_tau.resize(self.system.cut_nv, 0.0);
        for c in &self.system.constraints {
            let Some(cut) = c.joint else { continue };
            let (a, b) = (scratch.frames[c.connectors.0], scratch.frames[c.connectors.1]);
            let (nq, nv) = (cut.model.nq(), cut.model.nv());
            let qr = cut.q_offset..cut.q_offset + nq;
            // Relative pose, and the relative motion in frame_b as the joint would move it.
            let x = Transform::new(b.rot * a.rot.transpose(), a.rot * (b.r_0 - a.r_0));
            let mut guess = [0.0; 7];
            guess[..nq].copy_from_slice(&scratch.cut_q[qr.clone()]);
            if guess[..nq].iter().all(|g| *g == 0.0) {
                cut.model.neutral(&mut guess[..nq]);
            }
            cut.model.coordinates_of(&x, &guess[..nq], &mut scratch.cut_q[qr.clone()]);
            let (w_a, w_b) = (a.rot.tr_mul(&a.w), b.rot.tr_mul(&b.w));
            let (alpha_a, alpha_b) = (a.rot.tr_mul(&a.z), b.rot.tr_mul(&b.z));
            let r = b.r_0 - a.r_0;
            let dv = b.v_0 - a.v_0;
            let v_j = Motion::new(b.rot * (w_b - w_a), b.rot * (dv - w_a.cross(&r)));
            let rate = Motion::new(alpha_b - alpha_a, b.a_0 - a.a_0 - alpha_a.cross(&r) - w_a.cross(&dv));
            // The derivative of v_j as seen from frame_b.
            let a_j =
                Motion::new(b.rot * rate.ang, b.rot * rate.lin) - Motion::new(b.w, Vec3::zeros()).cross_motion(&v_j);
            let mut m = JointMotion::default();
            cut.model.motion(&scratch.cut_q[qr.clone()], &[0.0; 6][..nv], &mut m);
            let (u, ud) = (least_squares(&m.s[..nv], &v_j), least_squares(&m.s[..nv], &(a_j - m.cj)));
            scratch.cut_u[cut.v_offset..cut.v_offset + nv].copy_from_slice(&u[..nv]);
            scratch.cut_udot[cut.v_offset..cut.v_offset + nv].copy_from_slice(&ud[..nv]);
            let mut q = [0.0; 7];
            q[..nq].copy_from_slice(&scratch.cut_q[qr.clone()]);
            cut.model.qdot(&q[..nq], &u[..nv], &mut scratch.cut_qdot[qr]);
        }
    }

    /// Motion of every frame connector (from its node); flows are zeroed.
    fn frame_states(&self, ws: &Workspace, scratch: &mut OutputScratch) {
        scratch.frames.clear();
        scratch.frames.resize(self.connectors.len(), FrameState::default());
        for node in &self.nodes {
            let x = &node.pose;
            if let Anchor::Massless(m) = node.anchor {
                let state = FrameState {
                    r_0: ws.massless_pos[m] + x.trans,
                    rot: x.rot,
                    v_0: ws.massless_vel[m],
                    ..FrameState::default()
                };
                for &c in &node.connectors {
                    scratch.frames[c] = state;
                }
                continue;
            }
            let lw = &ws.links[node.link()];
            let (v_link, a_link) = if node.link() == GROUND { (Motion::ZERO, Motion::ZERO) } else { (lw.v, lw.a) };
            let rot = x.rot * lw.rot;
            let v = x.apply_motion(&v_link);
            let a = x.apply_motion(&a_link);
            let state = FrameState {
                r_0: lw.pos + lw.rot.tr_mul(&x.trans),
                rot,
                v_0: rot.tr_mul(&v.lin),
                w: v.ang,
                a_0: rot.tr_mul(&(a.lin + v.ang.cross(&v.lin))),
                z: a.ang,
                f: Vec3::zeros(),
                tau: Vec3::zeros(),
            };
            for &c in &node.connectors {
                scratch.frames[c] = state;
            }
        }
    }

    /// Cut forces: loads at each node (masses), summed from the leaves of
    /// the flow tree towards the ground. Each transmitting part carries the
    /// sum of the loads beyond it.
    fn cut_forces(&self, ws: &Workspace, scratch: &mut OutputScratch, y: &[f64]) {
        let (q, u) = y.split_at(self.system.states.nq);
        let n = self.nodes.len();
        scratch.node_wrench.clear();
        scratch.node_wrench.resize(n, (Vec3::zeros(), Vec3::zeros()));
        scratch.flows.clear();
        scratch.flows.resize(self.connectors.len(), (Vec3::zeros(), Vec3::zeros()));

        // Loads: each mass needs the force that moves it against gravity.
        for c in &self.components {
            for part in &c.parts {
                if let Part::Mass { frame, inertia, point_gravity } = part {
                    let id = c.first_connector + frame;
                    let fs = &scratch.frames[id];
                    let r_cm = inertia.com();
                    let i_cm = inertia.inertia_com();
                    let g_0 = self.world.gravity(&(fs.r_0 + fs.rot.tr_mul(&r_cm)), *point_gravity);
                    let f =
                        (fs.rot * (fs.a_0 - g_0) + fs.z.cross(&r_cm) + fs.w.cross(&fs.w.cross(&r_cm))) * inertia.mass;
                    let tau = i_cm * fs.z + fs.w.cross(&(i_cm * fs.w)) + r_cm.cross(&f);
                    scratch.flows[id].0 += f;
                    scratch.flows[id].1 += tau;
                    let node = self.connectors[id].node;
                    scratch.node_wrench[node].0 += fs.rot.tr_mul(&f);
                    scratch.node_wrench[node].1 += fs.rot.tr_mul(&tau);
                }
            }
        }

        // Force elements and constraints: their flows are the opposite of what they apply.
        let applied = self
            .system
            .force_elements
            .iter()
            .map(|el| {
                let (on_a, on_b, _) = self.system.applied(ws, el, q, u);
                (el.connectors.0, el.connectors.1, (on_a, on_b))
            })
            .chain(
                self.system
                    .constraints
                    .iter()
                    .enumerate()
                    // A servo's multipliers act through the sources it drives, not at its frame.
                    .filter(|(i, _)| !self.system.servos.iter().any(|s| s.constraint == *i))
                    .map(|(_, c)| (Some(c.connectors.0), c.connectors.1, self.system.constraint_wrenches(ws, c))),
            )
            .chain(
                self.system
                    .line_masses
                    .iter()
                    .map(|lm| (Some(lm.connectors.0), lm.connectors.1, self.system.line_mass_wrenches(ws, lm))),
            )
            .chain(self.system.lines.iter().zip(&ws.lines).map(|(line, state)| {
                let f = state.e * state.force;
                (Some(line.connectors.0), line.connectors.1, ((-f, Vec3::zeros()), (f, Vec3::zeros())))
            }));
        for (a, b, (on_a, on_b)) in applied {
            let ends = [(a, on_a), (Some(b), on_b)];
            for (connector, (force, moment)) in ends {
                let Some(id) = connector else { continue };
                let rot = scratch.frames[id].rot;
                scratch.flows[id].0 -= rot * force;
                scratch.flows[id].1 -= rot * moment;
                let node = self.connectors[id].node;
                scratch.node_wrench[node].0 -= force;
                scratch.node_wrench[node].1 -= moment;
            }
        }

        let node_state = |node: usize, frames: &[FrameState]| frames[self.nodes[node].connectors[0]];
        for &node in self.flow_tree.order.iter().rev() {
            let Some(edge) = self.flow_tree.parent[node] else { continue };
            let (force, moment) = scratch.node_wrench[node];
            let here = node_state(node, &scratch.frames);
            if let Some(c) = edge.child_connector {
                scratch.flows[c].0 -= here.rot * force;
                scratch.flows[c].1 -= here.rot * moment;
            }
            if let Some(p) = edge.parent_node {
                if edge.child_connector.is_none() {
                    continue;
                }
                let there = node_state(p, &scratch.frames);
                let shifted = moment + (here.r_0 - there.r_0).cross(&force);
                scratch.node_wrench[p].0 += force;
                scratch.node_wrench[p].1 += shifted;
                if let Some(c) = edge.parent_connector {
                    scratch.flows[c].0 += there.rot * force;
                    scratch.flows[c].1 += there.rot * shifted;
                }
            }
        }
        for (frame, flow) in scratch.frames.iter_mut().zip(&scratch.flows) {
            frame.f = flow.0;
            frame.tau = flow.1;
        }
    }
}

/// The coordinates `u` (up to 6) with `S u` closest to `v` (least squares).
fn least_squares(s: &[Motion], v: &Motion) -> [f64; 6] {
    let as6 = |m: &Motion| nalgebra::Vector6::new(m.ang.x, m.ang.y, m.ang.z, m.lin.x, m.lin.y, m.lin.z);
    let mut normal = nalgebra::Matrix6::<f64>::identity();
    let mut rhs = nalgebra::Vector6::<f64>::zeros();
    for (i, si) in s.iter().enumerate() {
        rhs[i] = as6(si).dot(&as6(v));
        for (j, sj) in s.iter().enumerate() {
            normal[(i, j)] = as6(si).dot(&as6(sj));
        }
    }
    let x = normal.cholesky().map_or(nalgebra::Vector6::zeros(), |c| c.solve(&rhs));
    [x[0], x[1], x[2], x[3], x[4], x[5]]
}
