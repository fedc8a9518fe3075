//! Models shared by several physics test files (include with
//! `#[path = "common/models.rs"] mod models;` after `physics`).
#![allow(dead_code)]

use super::physics::*;
use multibody::{Model, OrientationState};

/// A free Body tumbling (asymmetric inertia with a product term) from a
/// start that the Euler and the quaternion states describe alike.
pub fn tumbling_body(state: OrientationState, r_cm: V3, g: f64) -> Model {
    let phi0 = [0.2, -0.3, 0.4];
    let phid0 = [0.5, 0.3, -0.4];
    let mut model = Model::new(format!("tumbling_{state:?}"));
    model.add("world", "World").set("g", g);
    let body = model
        .add("body", "Body")
        .set("m", 1.3)
        .set("r_cm", r_cm)
        .set("I_11", 0.05)
        .set("I_22", 0.08)
        .set("I_33", 0.1)
        .set("I_21", 0.005)
        .set("orientation_state", state)
        .initial("r_0", [0.1, 0.5, -0.2])
        .initial("v_0", [0.4, 1.0, 0.2]);
    match state {
        OrientationState::Euler => {
            body.initial("phi", phi0).initial("phid", phid0);
        }
        OrientationState::Quaternion => {
            body.initial("Q_hat", quat_from_r(&euler_r([1, 2, 3], phi0)).to_vec())
                .initial("w_a", euler_w([1, 2, 3], phi0, phid0));
        }
        OrientationState::None => unreachable!(),
    }
    model
}

/// The scalar signals of `name`: itself, or its entries `name[..]`.
pub fn entries_of(sol: &multibody::Solution, name: &str) -> Vec<String> {
    if sol.get(name).is_some() {
        return vec![name.to_string()];
    }
    let prefix = format!("{name}[");
    let entries: Vec<String> = sol.names().iter().filter(|n| n.starts_with(&prefix)).cloned().collect();
    assert!(!entries.is_empty(), "no signal {name}");
    entries
}

/// Compares signals of two runs of the same physics on the same output
/// grid. Both runs have the integrator tolerance `eps`, so each is within
/// ~100 eps of the signal's scale of the exact solution (see the headers of
/// the test files); so is their difference, with the scale
/// `max(1, max |signal|)`.
pub fn compare_runs(label: &str, a: &multibody::Solution, b: &multibody::Solution, names: &[&str], eps: f64) {
    assert_eq!(a.time(), b.time(), "{label}: the runs have different output grids");
    for name in names {
        let entries = entries_of(a, name);
        let scale = entries.iter().flat_map(|e| sig(a, e).iter()).fold(1.0f64, |s, x| s.max(x.abs()));
        let unit = a.unit(&entries[0]).unwrap_or("");
        worst_over(a, |k| entries.iter().map(|e| (sig(a, e)[k] - sig(b, e)[k]).abs()).fold(0.0, f64::max)).check(
            &format!("{label}: |{name} difference| (scale {scale:.2})"),
            unit,
            100.0 * eps * scale,
        );
    }
}
