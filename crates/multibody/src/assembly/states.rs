//! The state vector: names, and start values from the model's `initial`
//! (and, where no initial value is given, `guess`) modifiers.

use super::links::{LoopJoint, Tree};
use super::mechanism::{CompiledComponent, JointRef};
use crate::components::{Part, StateNames};
use crate::error::{closest, list, list_or};
use crate::system::{FlangeRef, StateLayout};
use crate::{Error, Model, Value};

/// `geared`: for 1-D bodies that turn with another coordinate, their
/// centre's place and state names, so that their start values set it.
pub fn layout(
    model: &Model,
    components: &[CompiledComponent],
    tree: &Tree,
    geared: &[(usize, FlangeRef, StateNames)],
) -> Result<StateLayout, Error> {
    let nq: usize = tree.links.iter().skip(1).map(|l| l.joint.nq()).sum();
    let nv: usize = tree.links.iter().skip(1).map(|l| l.joint.nv()).sum();
    let mut names = vec![String::new(); nq + nv];
    let mut start = vec![0.0; nq + nv];
    let mut fixed = vec![false; nq + nv];
    for (k, link) in tree.links.iter().enumerate().skip(1) {
        let component = &components[link.states_of].name;
        let sn = &tree.state_names[k];
        for (offset, entries) in [(link.q_offset, sn.q), (nq + link.v_offset, sn.u)] {
            let mut i = offset;
            for &(name, size) in entries {
                for j in 0..size {
                    names[i] = if size == 1 {
                        format!("{component}.{name}")
                    } else {
                        format!("{component}.{name}[{}]", j + 1)
                    };
                    i += 1;
                }
            }
        }
        link.joint.neutral(&mut start[link.q_offset..link.q_offset + link.joint.nq()]);
    }

    // The components' own defaults, where they have the states.
    for c in components {
        for (variable, values) in c.component.default_starts() {
            if let Some((index, size)) = locate(c, tree, nq, variable) {
                start[index..index + size.min(values.len())].copy_from_slice(&values[..size.min(values.len())]);
            }
        }
    }
    for (ci, instance) in model.components.iter().enumerate() {
        let c = &components[ci];
        // Initial values hold; guesses fill in where no initial value is given.
        let guesses = instance.guess.iter().filter(|(g, _)| !instance.initial.iter().any(|(i, _)| i == g));
        let given = instance.initial.iter().map(|e| (e, true)).chain(guesses.map(|e| (e, false)));
        for ((variable, value), holds) in given {
            if super::initial::is_initial_equation(c, variable) {
                continue;
            }
            if let Some((index, scale, offset)) = through_gear(ci, geared, nq, variable) {
                let x = numbers(&c.name, variable, value, 1)?[0];
                start[index] = (x - offset) / scale;
                fixed[index] = holds;
                continue;
            }
            let (index, size) =
                locate(c, tree, nq, variable).ok_or_else(|| not_a_state(ci, components, tree, variable))?;
            let values = numbers(&c.name, variable, value, size)?;
            start[index..index + size].copy_from_slice(&values);
            fixed[index..index + size].fill(holds);
        }
    }
    for link in tree.links.iter().skip(1) {
        if let crate::system::joint::JointModel::Free(crate::system::joint::RotationCoordinates::Quaternion {
            ..
        }) = link.joint
        {
            let q = &start[link.q_offset + 3..link.q_offset + 7];
            if q.iter().map(|x| x * x).sum::<f64>() < 1e-20 {
                return Err(Error::InvalidValue {
                    component: components[link.source.0].name.clone(),
                    name: "Q_hat".into(),
                    value: Value::Array(q.to_vec()).to_string(),
                    reason: "a quaternion must not be zero; [1, 0, 0, 0] is the identity".into(),
                });
            }
        }
    }
    Ok(StateLayout { nq, nv, nx: 0, names, start, fixed })
}

/// For a 1-D body `c` that turns with another coordinate: the state its
/// `variable` (position or speed) sets, and how (`x = offset + scale * y`).
fn through_gear(
    c: usize,
    geared: &[(usize, FlangeRef, StateNames)],
    nq: usize,
    variable: &str,
) -> Option<(usize, f64, f64)> {
    let (_, centre, names) = geared.iter().find(|g| g.0 == c)?;
    let (q, v) = centre.coordinate()?;
    if names.q.iter().any(|n| n.0 == variable) {
        Some((q, centre.scale, centre.offset))
    } else if names.u.iter().any(|n| n.0 == variable) {
        Some((nq + v, centre.scale, 0.0))
    } else {
        None
    }
}

/// Where the state `variable` of component `c` sits in the state vector.
fn locate(c: &CompiledComponent, tree: &Tree, nq: usize, variable: &str) -> Option<(usize, usize)> {
    for &joint in &c.joints {
        let JointRef::Link(link) = joint else { continue };
        let l = &tree.links[link];
        let sn = &tree.state_names[link];
        for (offset, entries) in [(l.q_offset, sn.q), (nq + l.v_offset, sn.u)] {
            let mut i = offset;
            for &(name, size) in entries {
                if name == variable {
                    return Some((i, size));
                }
                i += size;
            }
        }
    }
    None
}

fn not_a_state(ci: usize, components: &[CompiledComponent], tree: &Tree, variable: &str) -> Error {
    let c = &components[ci];
    let links = c.joints.iter().filter_map(|j| if let JointRef::Link(l) = j { Some(*l) } else { None });
    let states: Vec<&str> =
        links.flat_map(|l| tree.state_names[l].q.iter().chain(tree.state_names[l].u)).map(|(n, _)| *n).collect();
    if c.spec.variables.iter().any(|v| v.name == variable) {
        let reason = if c.joints.iter().any(|j| matches!(j, JointRef::Cut(_))) {
            cut_joint_reason(ci, components, tree)
        } else if c.joints.is_empty() && c.parts.iter().any(|p| matches!(p, Part::Mass { .. })) {
            "its motion comes from what it is connected to. Set the start values of the joints between it and the World instead, or make it free (`orientation_state = OrientationState.Quaternion()` for a Body, `isroot = true` for an unconnected PointMass)".to_string()
        } else if states.is_empty() {
            format!("{} has no states; it is computed from the motion", c.spec.kind)
        } else {
            format!("it is computed from the states; its states are {}", states.join(", "))
        };
        return Error::NotAState { component: c.name.clone(), variable: variable.into(), reason };
    }
    Error::UnknownVariable {
        component: c.name.clone(),
        kind: c.spec.kind.into(),
        variable: variable.into(),
        suggestions: closest(variable, states.iter().copied().chain(c.spec.variables.iter().map(|v| v.name))),
        valid: states.iter().map(|s| s.to_string()).collect(),
    }
}

/// Why the cut joint `ci` has no states, and what to do: which other joint
/// of its loop could be cut instead, if any.
fn cut_joint_reason(ci: usize, components: &[CompiledComponent], tree: &Tree) -> String {
    let generic =
        "this joint closes a kinematic loop, so its coordinates follow from the other joints of the loop".to_string();
    let Some(l) = tree.cut_loops.iter().find(|l| l.component == ci) else { return generic };
    let names = |joints: &[&LoopJoint]| -> Vec<String> {
        joints.iter().map(|j| components[j.component].name.clone()).collect()
    };
    let others: Vec<&LoopJoint> = l.others.iter().collect();
    let loop_names = list(&names(&others));
    let iscut = components[ci].parts.iter().any(|p| matches!(p, Part::Joint { iscut: true, .. }));
    if others.is_empty() {
        return "its two frames are already joined rigidly, so the joint closes a loop by itself and cannot move.\nRemove the joint, or the rigid connection between its frames.".into();
    }
    if iscut {
        return format!(
            "it is marked `iscut = true`, so it is the joint cut to close the kinematic loop through {loop_names}, and its coordinates follow from theirs.\nRemove `iscut = true` so that another joint of the loop is cut instead, or give the start value to one of those joints."
        );
    }
    let free: Vec<&LoopJoint> = others.iter().copied().filter(|j| !j.elements && !j.fixed).collect();
    let fixed: Vec<&LoopJoint> = others.iter().copied().filter(|j| !j.elements && j.fixed).collect();
    if !free.is_empty() {
        format!(
            "it closes the kinematic loop through {loop_names}, so its coordinates follow from theirs.\nTo give it a start value, mark {} with `iscut = true`; that joint is then cut instead.",
            if free.len() == 1 { list(&names(&free)) } else { format!("one of {}", list_or(&names(&free))) }
        )
    } else if !fixed.is_empty() {
        format!(
            "it closes the kinematic loop through {loop_names}: one joint of a loop is cut and its coordinates follow from the others, and every joint of this loop that could be cut has start values.\nRemove the start values of one joint of the loop ({} or this one); that joint is then cut.",
            names(&fixed).iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", ")
        )
    } else {
        format!(
            "it closes the kinematic loop through {loop_names}, whose joints all have 1-D elements on their axes and cannot be cut, so this one is cut and its coordinates follow from theirs.\nRemove its start value."
        )
    }
}

/// The numbers of a start value of `size` entries.
fn numbers(component: &str, variable: &str, value: &Value, size: usize) -> Result<Vec<f64>, Error> {
    let values = match value {
        Value::Number(x) => vec![*x],
        Value::Array(v) => v.clone(),
        other => {
            return Err(Error::WrongType {
                component: component.into(),
                name: variable.into(),
                expected: if size == 1 { "a number".into() } else { format!("an array of {size} numbers") },
                got: other.describe(),
            })
        }
    };
    if values.len() != size {
        return Err(Error::WrongSize {
            component: component.into(),
            name: variable.into(),
            expected: size,
            got: values.len(),
        });
    }
    if values.iter().any(|x| !x.is_finite()) {
        return Err(Error::InvalidValue {
            component: component.into(),
            name: variable.into(),
            value: value.to_string(),
            reason: "start values must be finite numbers".into(),
        });
    }
    Ok(values)
}
