//! Drives: which links' motion signals impose, and from which slots.

use super::axis::{self, Places};
use super::connections::Connectors;
use super::links::Tree;
use super::mechanism::{CompiledComponent, JointRef};
use super::signals::Signals;
use crate::components::{Part, StateNames};
use crate::system::{Drive, DriveLevel, DriveMap, FlangeRef};
use crate::Error;

/// Start positions and speeds a drive gives its link's first coordinates.
pub struct DriveStart {
    pub link: usize,
    pub count: usize,
    pub q: [f64; 3],
    pub u: [f64; 3],
}

/// A motion source's own position and speed (its flange relative to its
/// support) at the coordinate it drives, with the names the source gives
/// them, for the start values set on the source: the coordinates a drive
/// integrates (through a filter, from a speed or an acceleration) are
/// states, and `source.w(initial = ...)` starts them.
pub type SourceStates = Vec<(usize, FlangeRef, StateNames)>;

/// The states a motion source of `level` integrates, by the names of its
/// variables (`phi`, `w` or `s`, `v`): none where it sets both exactly.
fn integrated(level: DriveLevel, position: &str) -> Option<StateNames> {
    const ANGLE: &[(&str, usize)] = &[("phi", 1)];
    const SPEED: &[(&str, usize)] = &[("w", 1)];
    const DISTANCE: &[(&str, usize)] = &[("s", 1)];
    const VELOCITY: &[(&str, usize)] = &[("v", 1)];
    let (q, u) = if position == "phi" { (ANGLE, SPEED) } else { (DISTANCE, VELOCITY) };
    match level {
        DriveLevel::Position | DriveLevel::Balance { .. } => None,
        DriveLevel::Speed => Some(StateNames { q, u: &[] }),
        DriveLevel::Acceleration | DriveLevel::PositionFilter { .. } | DriveLevel::SpeedFilter { .. } => {
            Some(StateNames { q, u })
        }
    }
}

/// The drives of every component, with the driven coordinates marked on
/// their links, the start values they give, and the states of the motion
/// sources.
pub fn attach(
    components: &[CompiledComponent],
    conn: &Connectors,
    tree: &mut Tree,
    places: &Places,
    signals: &Signals,
) -> Result<(Vec<Drive>, Vec<DriveStart>, SourceStates), Error> {
    let mut drives = Vec::new();
    let mut starts = Vec::new();
    let mut source_states = Vec::new();
    let zero = signals.blocks.len();
    for (ci, c) in components.iter().enumerate() {
        let id = |local: usize| Connectors::id(components, ci, local);
        let slot = |local: Option<usize>| local.map_or(zero, |l| signals.of_connector[id(l)]);
        let fail = |what: String, fix: &str| Error::Unsupported { component: c.name.clone(), what, fix: fix.into() };
        for part in &c.parts {
            let (link, level, map, locals) = match *part {
                Part::Drive { part, level, map, inputs, start } => {
                    let position =
                        c.parts[..part].iter().filter(|p| matches!(p, Part::Joint { .. } | Part::Owner { .. })).count();
                    let Some(&JointRef::Link(link)) = c.joints.get(position) else {
                        return Err(fail(
                            "prescribed motion of a joint that closes a kinematic loop".into(),
                            "prescribe the motion of a joint of the tree, or open the loop elsewhere",
                        ));
                    };
                    if let (Some((q, u)), DriveMap::Linear { count, .. }) = (start, map) {
                        starts.push(DriveStart { link, count, q, u });
                    }
                    (link, level, map, inputs)
                }
                Part::AxisDrive { flange, support, input, level } => {
                    let on = axis::flange(components, conn, places, id(flange))?;
                    let base = axis::flange(components, conn, places, id(support))?;
                    if base.mover.is_some() {
                        return Err(fail(
                            "a motion source whose support moves".into(),
                            "mount the source's support on something fixed (or leave use_support off)",
                        ));
                    }
                    if on.on_line() {
                        return Err(fail(
                            "imposing motion on the flange of a line force (the line's length places it)".into(),
                            "move the frames the line joins instead",
                        ));
                    }
                    let Some((_, v)) = on.coordinate() else {
                        return Err(fail(
                            format!("imposing motion on `{}`, which is fixed", conn.name(components, id(flange))),
                            "connect the flange to a joint's axis or to an inertia",
                        ));
                    };
                    let Some(link) = tree.links.iter().position(|l| l.v_offset == v && l.joint.nv() == 1) else {
                        return Err(fail(
                            "imposing motion on a coordinate of a loop".into(),
                            "drive a joint of the tree",
                        ));
                    };
                    let map = DriveMap::Linear { first: 0, count: 1, scale: on.scale, offset: on.offset - base.offset };
                    if let Some(names) = c.spec.variables.first().and_then(|v| integrated(level, v.name)) {
                        source_states.push((ci, on.affine(1.0, -base.offset), names));
                    }
                    let mut locals = [None; 7];
                    locals[0] = Some(input);
                    (link, level, map, locals)
                }
                _ => continue,
            };
            let slots = locals.map(slot);
            let used = match map {
                DriveMap::Linear { count, .. } => count,
                DriveMap::Pose => 7,
            };
            if level.needs_derivatives() {
                if let Some(k) = (0..used).find(|&k| !signals.of_time[slots[k]]) {
                    let name = locals[k].map_or_else(String::new, |l| format!(" `{}`", conn.name(components, id(l))));
                    return Err(fail(
                        format!("a prescribed position or speed whose input{name} depends on the motion"),
                        "drive it with sources of time (and gains, sums, products of them), \
                         or prescribe the acceleration instead",
                    ));
                }
            }
            let bits = match map {
                DriveMap::Linear { first, count, .. } => ((1u8 << count) - 1) << first,
                DriveMap::Pose => 0b11_1111,
            };
            let l = &mut tree.links[link];
            if l.driven & bits != 0 {
                return Err(fail(
                    "imposing the motion of a joint that another source already drives".into(),
                    "keep one source per joint",
                ));
            }
            l.driven |= bits;
            drives.push(Drive { link, level, map, slots, component: ci });
        }
    }
    Ok((drives, starts, source_states))
}

/// Sets the start values the drives give, where the model gives none.
pub fn apply_starts(starts: &[DriveStart], tree: &Tree, states: &mut crate::system::StateLayout) {
    let nq = states.nq;
    for s in starts {
        let link = &tree.links[s.link];
        for k in 0..s.count {
            for (index, value) in [(link.q_offset + k, s.q[k]), (nq + link.v_offset + k, s.u[k])] {
                if !states.fixed[index] {
                    states.start[index] = value;
                }
            }
        }
    }
}

/// Per velocity coordinate, whether no drive imposes it.
pub fn free_coordinates(tree: &Tree, nv: usize) -> Vec<bool> {
    let mut free = vec![true; nv];
    for l in &tree.links[1..] {
        for i in 0..l.joint.nv() {
            if l.driven & (1 << i) != 0 {
                free[l.v_offset + i] = false;
            }
        }
    }
    free
}
