//! Checks on the assembled tree that need its mass distribution.

use super::connections::Connectors;
use super::links::Tree;
use super::mechanism::CompiledComponent;
use crate::math::RigidInertia;
use crate::system::joint::{JointModel, JointMotion, RotationCoordinates};
use crate::system::{Coupling, GROUND};
use crate::Error;

/// Every degree of freedom must move some inertia: `S' Ic S` must be
/// positive definite for each joint, with `Ic` the composite inertia of
/// what the joint moves, at the start configuration. Joints whose subtree
/// reaches a constraint, and coordinates that couplings hold, are left to
/// the check of the constrained system (a loop, or an in-line sensor's
/// constraint, may determine the motion of massless links).
pub fn inertia_behind_every_joint(
    components: &[CompiledComponent],
    conn: &Connectors,
    tree: &Tree,
    couplings: &[Coupling],
    q: &[f64],
) -> Result<(), Error> {
    let links = &tree.links;
    let n = links.len();
    let mut x_up = vec![crate::math::Transform::IDENTITY; n];
    let zeros = vec![0.0; q.len().max(1) * 6];
    let mut motions = vec![JointMotion::default(); n];
    for k in 1..n {
        links[k].motion(q, &zeros, &mut motions[k]);
        x_up[k] = links[k].x_tree.then(&motions[k].x);
    }
    let mut composite: Vec<RigidInertia> = links.iter().map(|l| l.inertia).collect();
    for k in (1..n).rev() {
        let p = links[k].parent;
        if p != GROUND {
            let c = composite[k].expressed_in_parent(&x_up[k]);
            composite[p] += c;
        }
    }
    let mut constrained = vec![false; n];
    for cut in &tree.cuts {
        for node in [cut.a, cut.b] {
            let mut k = tree.nodes[node].link();
            while k != GROUND && !constrained[k] {
                constrained[k] = true;
                k = links[k].parent;
            }
        }
    }
    for c in couplings {
        for &(_, v, _) in &c.terms {
            if let Some(k) = links.iter().position(|l| l.v_offset == v && l.joint.nv() == 1) {
                constrained[k] = true;
            }
        }
    }
    for k in 1..n {
        let l = &links[k];
        if let (Some(_), Some((_, RotationCoordinates::Euler { sequence }))) =
            (l.joint.singularity(l.q(q)), l.joint.rotation_coordinates())
        {
            return Err(Error::EulerSingularStart { component: components[l.states_of].name.clone(), sequence });
        }
        let m = &motions[k];
        let ic = &composite[k];
        let scale = ic.mass.max(ic.rot.norm()).max(l.armature).max(f64::MIN_POSITIVE);
        let nv = l.joint.nv();
        let mut d = nalgebra::DMatrix::<f64>::zeros(nv, nv);
        for i in 0..nv {
            let f = ic.apply(&m.s[i]);
            for j in 0..nv {
                d[(j, i)] = m.s[j].dot(&f);
            }
        }
        if nv == 1 {
            d[(0, 0)] += l.armature;
        }
        let singular = (0..nv).any(|i| d[(i, i)] <= 1e-12 * scale) || d.clone().cholesky().is_none();
        if singular && !constrained[k] && l.driven == 0 {
            let component = &components[l.source.0];
            let dof = match l.joint {
                JointModel::Revolute { .. } => "rotation about the axis",
                JointModel::Prismatic { .. } => "translation along the axis",
                JointModel::Free(_) => "free motion",
                JointModel::Translation => "translation",
                JointModel::Spherical(_) => "rotation",
                JointModel::Universal { .. } => "rotation about its two axes",
                JointModel::Cylindrical { .. } => "motion along and about its axis",
                JointModel::Planar { .. } => "motion in its plane",
            };
            return Err(Error::NoInertia {
                joint: component.name.clone(),
                dof: dof.into(),
                moved: moved_by(components, conn, tree, k),
            });
        }
    }
    Ok(())
}

/// Names of the components with frames on link `k` or its descendants.
fn moved_by(components: &[CompiledComponent], conn: &Connectors, tree: &Tree, k: usize) -> Vec<String> {
    let in_subtree = |mut l: usize| loop {
        if l == k {
            return true;
        }
        if l == GROUND {
            return false;
        }
        l = tree.links[l].parent;
    };
    let mut names: Vec<String> = Vec::new();
    for node in &tree.nodes {
        if in_subtree(node.link()) {
            for &c in &node.connectors {
                let name = &components[conn.infos[c].component].name;
                if !names.contains(name) && *name != components[tree.links[k].states_of].name {
                    names.push(name.clone());
                }
            }
        }
    }
    names
}
