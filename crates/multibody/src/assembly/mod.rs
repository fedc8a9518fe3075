//! Assembly: turns a [`Model`] into a [`Mechanism`].
//!
//! 1. `instances`: find the World, check each component's kind and
//!    parameters, build the components.
//! 2. `connections`: check each `connect`, merge connectors into nodes.
//! 3. `links`: merge nodes joined by rigid parts into rigid groups; grow a
//!    tree of joints from the World, and from the one orientation owner of
//!    each floating group; groups without mass held only by force elements
//!    become massless groups.
//! 4. masses into link inertias, point-gravity masses, 1-D elements
//!    (`axis`), signals (`signals`), force elements (`forces`), states and
//!    start values (`states`).
//! 5. `checks`: every degree of freedom has inertia behind it.
//! 6. `flows`: the tree along which cut forces are computed for outputs.

mod axis;
mod balance;
mod checks;
mod connections;
mod drives;
mod equations;
mod flows;
mod forces;
mod friction;
mod initial;
mod instances;
mod links;
mod loops;
mod mechanism;
mod servos;
mod signals;
mod states;

use crate::components::Part;
use crate::math::{Mat3, Transform, Vec3};
use crate::system::joint::JointMotion;
use crate::system::{Anchor, Attachment, LineMass, LineSpan, Link, PointGravityMass, System, GROUND};

use crate::{Error, Model};

pub(crate) use mechanism::{CompiledComponent, JointRef, SignalTable};
pub use mechanism::{LoopInfo, Mechanism};

impl Model {
    /// Validates the model and compiles it into a mechanism.
    pub fn assemble(&self) -> Result<Mechanism, Error> {
        assemble(self)
    }
}

pub fn assemble(model: &Model) -> Result<Mechanism, Error> {
    // The model's equations: hidden components joined to what they drive.
    let plan = equations::plan(model)?;
    let with_equations;
    let model = if plan.extras.is_empty() {
        model
    } else {
        let mut m = model.clone();
        for extra in &plan.extras {
            for (local, theirs) in &extra.joins {
                m.connect([format!("{}.{local}", extra.name), theirs.clone()]);
            }
        }
        with_equations = m;
        &with_equations
    };
    let world = instances::world_settings(model)?;
    // Parameters given that change nothing here, said once each.
    let mut without_effect = Vec::new();
    let mut components = instances::build(model, &world, &plan.extras, &mut without_effect)?;
    let conn = connections::resolve(model, &components)?;
    let groups = links::rigid_groups(&components, &conn, world.plane)?;
    let fixed: Vec<bool> = model.components.iter().map(|c| !c.initial.is_empty()).collect();
    let mut tree = links::spanning_tree(&components, &conn, &groups, &fixed)?;
    for (n, node) in tree.nodes.iter_mut().enumerate() {
        node.connectors = conn.frame_nodes[n].clone();
    }
    let mut warnings = without_effect;
    warnings.extend(groups.warnings.iter().cloned());

    // Which links each component's joints and owners move (in part order),
    // or whose states it names; cut joints come with the constraints.
    for (k, link) in tree.links.iter().enumerate().skip(1) {
        let (ci, pi) = link.source;
        if link.states_of != ci {
            components[link.states_of].joints.push(JointRef::Link(k));
            continue;
        }
        let position =
            components[ci].parts[..pi].iter().filter(|p| matches!(p, Part::Joint { .. } | Part::Owner { .. })).count();
        let joints = &mut components[ci].joints;
        if joints.len() <= position {
            joints.resize(position + 1, JointRef::Link(usize::MAX));
        }
        joints[position] = JointRef::Link(k);
    }
    let (constraints, constraint_rows, cut_nq, cut_nv) = loops::constraints(&mut components, &tree);
    // 1-D drive trains: may add links (free inertias) at the end of the tree.
    let drive = axis::place(&mut components, &conn, &mut tree)?;

    // Masses into link inertias.
    let uniform_gravity = world.uniform_gravity();
    let mut point_masses = Vec::new();
    for c in &components {
        for part in &c.parts {
            if let Part::Mass { frame, inertia, point_gravity } = part {
                let node = &tree.nodes[conn.node(c.first_connector + frame)];
                let Anchor::Link(link) = node.anchor else { continue };
                if link == GROUND {
                    continue;
                }
                let in_link = inertia.expressed_in_parent(&node.pose);
                tree.links[link].inertia += in_link;
                if (*point_gravity || world.point_gravity) && in_link.mass > 0.0 {
                    point_masses.push(PointGravityMass { link, mass: in_link.mass, com: in_link.com() });
                }
            }
        }
    }

    for link in &mut tree.links {
        link.articulated = (&link.inertia).into();
    }
    let (line_masses, lines) = lines(&components, &conn, &tree)?;

    let mut signals = signals::resolve(&components, &conn, &tree, &drive.places, &world.plane)?;
    warnings.extend(std::mem::take(&mut signals.warnings));
    let mut events = crate::system::EventLayout { inputs: std::mem::take(&mut signals.inputs), ..Default::default() };
    let axis_elements = axis::elements(&mut components, &conn, &drive.places, &signals.of_connector, &mut events)?;
    let couplings = axis::couplings(&components, &conn, &drive, constraint_rows)?;
    let constraint_rows = constraint_rows + couplings.len();
    let frictions =
        friction::elements(&mut components, &conn, &drive.places, &signals.of_connector, constraint_rows, &mut events)?;
    let constraint_rows = constraint_rows + frictions.len();
    let zero_slot = signals.slots - 1;
    let force_elements =
        forces::elements(&components, &conn, &mut tree, &drive.places, &signals.of_connector, zero_slot, &world.plane)?;
    let servos = servos::attach(
        &components,
        &conn,
        &constraints,
        &axis_elements,
        &force_elements,
        &signals,
        tree.links.iter().skip(1).map(|l| l.v_offset + l.joint.nv()).max().unwrap_or(0),
    )?;
    let (mut drives, drive_starts, source_states) =
        drives::attach(&components, &conn, &mut tree, &drive.places, &signals)?;
    let (balances, balance_drives) =
        balance::nodes(&components, &mut tree, &drive.balance_links, &axis_elements, &couplings, &frictions, &signals)?;
    drives.extend(balance_drives);
    let geared: Vec<_> = drive.geared.iter().cloned().chain(source_states).collect();
    let mut states = states::layout(model, &components, &tree, &geared)?;
    drives::apply_starts(&drive_starts, &tree, &mut states);
    balance::check_starts(&components, &tree, &drive.balance_links, &balances, &states)?;
    let free_coordinates = drives::free_coordinates(&tree, states.nv);
    let context = equations::Context {
        components: &components,
        conn: &conn,
        tree: &tree,
        places: &drive.places,
        links: &tree.links,
        couplings: &couplings,
        constraints: &constraints,
    };
    let (program, initial_of_equations) = plan.compile(&context, &mut signals, &mut states, &mut events)?;
    warnings.extend(program.notes.iter().cloned());
    checks::inertia_behind_every_joint(&components, &conn, &tree, &couplings, &states.start[..states.nq])?;

    // Start each massless group at the centre of the frames that hold it.
    let poses = link_poses(&tree.links, &states.start[..states.nq]);
    for (m, group) in tree.massless.iter_mut().enumerate() {
        let ends: Vec<Vec3> = group
            .elements
            .iter()
            .flat_map(|&e| force_elements[e].a.iter().chain([&force_elements[e].b]).copied().collect::<Vec<_>>())
            .filter(|end| end.anchor != Anchor::Massless(m))
            .map(|end| position(&poses, &end))
            .collect();
        if !ends.is_empty() {
            group.guess = ends.iter().sum::<Vec3>() / ends.len() as f64;
        }
    }
    let initial_equations = initial::collect(model, &components, &conn, &tree, &drive.places)?;
    let flow_tree = flows::flow_tree(&components, &conn, &tree);

    let flange_of_connector = axis::of_connectors(&conn, &drive.places);
    let dof = free_coordinates.iter().filter(|free| **free).count();
    let system = System {
        links: tree.links,
        axis_elements,
        axis_forces: drive.axis_forces.clone(),
        signals_read_frames: signals.blocks.iter().any(|b| b.law.reads_frames()),
        signal_slots: signals.slots,
        time_signals: signals.time_signals,
        drives,
        free_coordinates,
        signals: signals.blocks,
        couplings,
        balances,
        frictions,
        force_elements,
        massless: tree.massless,
        constraints,
        servos,
        roads: components
            .iter()
            .flat_map(|c| c.parts.iter())
            .filter_map(|p| match p {
                Part::Road { surface } => Some((**surface).clone()),
                _ => None,
            })
            .collect(),
        constraint_rows,
        line_masses,
        lines,
        equations: program,
        cut_nq,
        cut_nv,
        point_masses,
        uniform_gravity,
        mu: world.mu,
        plane: world.plane,
        states,
        dof,
        events,
    };
    let mut mechanism = Mechanism {
        name: model.name.clone(),
        world,
        system,
        components,
        connectors: conn.infos,
        nodes: tree.nodes,
        signal_of_connector: signals.of_connector,
        flange_of_connector,
        flow_tree,
        warnings,
        outputs: model.outputs.clone(),
        loops: Vec::new(),
        signal_table: Default::default(),
    };
    if mechanism.system.constraint_rows > 0 {
        loops::close(&mut mechanism)?;
    }
    initial::solve(&mut mechanism, &initial_equations)?;
    if let Some(init) = initial_of_equations {
        equations::initialize(&mut mechanism, &init)?;
    }
    Ok(mechanism)
}

/// How many roads the components before `ci` give: where its own are
/// numbered among the mechanism's.
pub(crate) fn road_base(components: &[CompiledComponent], ci: usize) -> usize {
    components[..ci].iter().flat_map(|c| c.parts.iter()).filter(|p| matches!(p, Part::Road { .. })).count()
}

/// World pose (world-to-link rotation, origin) of every link at `q`.
fn link_poses(links: &[Link], q: &[f64]) -> Vec<(Mat3, Vec3)> {
    let zeros = vec![0.0; q.len() * 2 + 6];
    let mut poses = vec![(Mat3::identity(), Vec3::zeros()); links.len()];
    let mut m = JointMotion::default();
    for k in 1..links.len() {
        links[k].motion(q, &zeros, &mut m);
        let x: Transform = links[k].x_tree.then(&m.x);
        let (rot_p, pos_p) = poses[links[k].parent];
        poses[k] = (x.rot * rot_p, pos_p + rot_p.tr_mul(&x.trans));
    }
    poses
}

/// World position of an attachment on a link (massless groups: their start guess is unknown, use the origin).
fn position(poses: &[(Mat3, Vec3)], end: &Attachment) -> Vec3 {
    match end.anchor {
        Anchor::Link(k) => poses[k].1 + poses[k].0.tr_mul(&end.pose.trans),
        Anchor::Massless(_) => Vec3::zeros(),
    }
}

/// The point masses of line forces, and the lines whose lengths place
/// 1-D flanges, between the frames their ends are on.
fn lines(
    components: &[CompiledComponent],
    conn: &connections::Connectors,
    tree: &links::Tree,
) -> Result<(Vec<LineMass>, Vec<LineSpan>), Error> {
    let (mut masses, mut spans) = (Vec::new(), Vec::new());
    for c in components {
        for part in &c.parts {
            let (a, b, what) = match *part {
                Part::LineMass { a, b, .. } => (a, b, "a line force with mass (hasmass = true)"),
                Part::LineFlanges { a, b, .. } => (a, b, "a line force with 1-D flanges"),
                _ => continue,
            };
            let connectors = (c.first_connector + a, c.first_connector + b);
            let attach = |id: usize| {
                let node = &tree.nodes[conn.node(id)];
                match node.anchor {
                    Anchor::Massless(_) => Err(Error::Unsupported {
                        component: c.name.clone(),
                        what: format!("{what} ending at frames without mass"),
                        fix: "give those frames mass, or put a PointMass between two massless springs".into(),
                    }),
                    anchor => Ok(Attachment { anchor, pose: node.pose }),
                }
            };
            let (a, b) = (attach(connectors.0)?, attach(connectors.1)?);
            match *part {
                Part::LineMass { m, h, point_gravity, .. } => {
                    masses.push(LineMass { a, b, connectors, m, h, point_gravity })
                }
                Part::LineFlanges { s_small, .. } => spans.push(LineSpan { a, b, connectors, s_small }),
                _ => unreachable!("only line parts get here"),
            }
        }
    }
    Ok((masses, spans))
}
