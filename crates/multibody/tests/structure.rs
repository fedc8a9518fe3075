//! The structure assembly gives a model, checked on small models whose
//! answers are counted by hand (links, owners of orientation, loop cuts,
//! states), and the forward dynamics checked against the equations of
//! motion written with the joint-space mass matrix.

#[path = "common/chain.rs"]
mod chain;
#[path = "common/four_bar.rs"]
mod shared;

use multibody::{Error, Mechanism, Model, OrientationState, SimulationOptions};

// ------------------------------------------------------------------ helpers

/// A Body with a mass and an off-origin centre of mass, so that every joint
/// moving it sees inertia.
fn body(model: &mut Model, name: &str) {
    model.add(name, "Body").set("m", 1.0).set("r_cm", [0.3, 0.1, 0.0]);
}

/// The shared four-bar (crank started at 5 rad/s, a light damper on `j1`),
/// with `cut` marked `iscut = true`.
fn four_bar(cut: Option<&str>) -> Model {
    let mut model = shared::four_bar(0.05, 1.0, 5.0);
    if let Some(j) = cut {
        model.component_mut(j).expect("a joint of the four-bar").set("iscut", true);
    }
    model
}

/// A lone Body in a world, with the given orientation states (`None` leaves
/// the parameter at its default).
fn lone_body(state: Option<OrientationState>) -> Model {
    let mut model = Model::new(format!("lone_body_{state:?}"));
    model.add("world", "World");
    let b = model.add("body", "Body").set("m", 2.0).set("I_22", 0.02);
    if let Some(s) = state {
        b.set("orientation_state", s);
    }
    model
}

fn names(mechanism: &Mechanism) -> Vec<&str> {
    mechanism.states().names.iter().map(String::as_str).collect()
}

// ----------------------------------------------------- A. frames to links

/// World - Revolute - FixedTranslation - Body: everything after the
/// revolute is one rigid group, so one link with one angle and one speed.
#[test]
fn revolute_then_rigid_rod_and_body_is_one_link() {
    let mut model = Model::new("rod_pendulum");
    model.add("world", "World");
    model.add("rev", "Revolute");
    model.add("rod", "FixedTranslation").set("r", [1.0, 0.0, 0.0]);
    body(&mut model, "body");
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "rod.frame_a"]);
    model.connect(["rod.frame_b", "body.frame_a"]);
    let mechanism = model.assemble().unwrap();
    assert_eq!(mechanism.link_count(), 1);
    assert_eq!(mechanism.degrees_of_freedom(), 1);
    assert_eq!(names(&mechanism), ["rev.phi", "rev.w"]);
}

/// Two bodies welded by a FixedTranslation move as one: one link whether
/// a revolute carries them or they float (then one owner, one 6-DOF joint).
#[test]
fn bodies_joined_by_a_fixed_translation_are_one_link() {
    let mut hinged = Model::new("hinged_pair");
    hinged.add("world", "World");
    hinged.add("rev", "Revolute").set("n", [0.0, 1.0, 0.0]);
    body(&mut hinged, "b1");
    hinged.add("rod", "FixedTranslation").set("r", [0.0, 0.0, 1.0]);
    body(&mut hinged, "b2");
    hinged.connect(["world.frame_b", "rev.frame_a"]);
    hinged.connect(["rev.frame_b", "b1.frame_a", "rod.frame_a"]);
    hinged.connect(["rod.frame_b", "b2.frame_a"]);
    let hinged = hinged.assemble().unwrap();
    assert_eq!((hinged.link_count(), hinged.degrees_of_freedom()), (1, 1));

    let mut floating = Model::new("floating_pair");
    floating.add("world", "World");
    floating.add("b1", "Body").set("m", 1.0).set("orientation_state", OrientationState::Quaternion);
    floating.add("rod", "FixedTranslation").set("r", [0.0, 0.0, 1.0]);
    body(&mut floating, "b2");
    floating.connect(["b1.frame_a", "rod.frame_a"]);
    floating.connect(["rod.frame_b", "b2.frame_a"]);
    let floating = floating.assemble().unwrap();
    assert_eq!((floating.link_count(), floating.degrees_of_freedom()), (1, 6));
    let owners = floating.orientation_owners();
    assert_eq!(owners.len(), 1, "{owners:?}");
    assert_eq!(owners[0].0, "b1");
}

/// Three revolutes in series, a body after each: three links, three
/// degrees of freedom, angles first and speeds after, in chain order.
#[test]
fn chain_of_three_revolutes_has_three_links_and_named_states() {
    let mut model = Model::new("triple");
    model.add("world", "World");
    let mut previous = "world.frame_b".to_string();
    for k in 1..=3 {
        let axis = if k == 2 { [0.0, 1.0, 0.0] } else { [0.0, 0.0, 1.0] };
        model.add(format!("j{k}"), "Revolute").set("n", axis);
        body(&mut model, &format!("b{k}"));
        model.add(format!("r{k}"), "FixedTranslation").set("r", [1.0, 0.0, 0.0]);
        model.connect([previous.clone(), format!("j{k}.frame_a")]);
        model.connect([format!("j{k}.frame_b"), format!("b{k}.frame_a"), format!("r{k}.frame_a")]);
        previous = format!("r{k}.frame_b");
    }
    let mechanism = model.assemble().unwrap();
    assert_eq!(mechanism.link_count(), 3);
    assert_eq!(mechanism.degrees_of_freedom(), 3);
    assert!(mechanism.loops().is_empty());
    assert_eq!((mechanism.states().nq, mechanism.states().nv), (3, 3));
    assert_eq!(names(&mechanism), ["j1.phi", "j2.phi", "j3.phi", "j1.w", "j2.w", "j3.w"]);
    assert!(mechanism.orientation_owners().is_empty());
}

// ------------------------------------------------ A. orientation owners

/// A Body on its own that carries orientation states owns its group: it
/// is listed, with 6 degrees of freedom. Quaternion: r_0 (3) and Q_hat (4)
/// positions, v_0 and w_a (3 + 3) velocities; Euler: r_0 and phi, v_0 and
/// phid (3 + 3 each).
#[test]
fn free_body_owns_its_orientation() {
    for (state, kind, nq) in [(OrientationState::Quaternion, "quaternion", 7), (OrientationState::Euler, "Euler", 6)] {
        let mechanism = lone_body(Some(state)).assemble().unwrap();
        let owners = mechanism.orientation_owners();
        println!("{state:?}: owners {owners:?}, states {:?}", names(&mechanism));
        assert_eq!(owners.len(), 1);
        assert_eq!(owners[0].0, "body");
        assert!(owners[0].1.contains(kind), "{state:?}: {owners:?}");
        assert_eq!(mechanism.link_count(), 1);
        assert_eq!(mechanism.degrees_of_freedom(), 6);
        assert_eq!((mechanism.states().nq, mechanism.states().nv), (nq, 6));
        assert!(names(&mechanism).iter().all(|n| n.starts_with("body.")), "{:?}", names(&mechanism));
    }
}

/// A Body hinged to the world gets its orientation through the joint: no
/// owner, whatever its own parameter would allow.
#[test]
fn body_on_a_joint_has_no_owner() {
    let mut model = Model::new("hinged");
    model.add("world", "World");
    model.add("rev", "Revolute");
    body(&mut model, "body");
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    let mechanism = model.assemble().unwrap();
    assert!(mechanism.orientation_owners().is_empty(), "{:?}", mechanism.orientation_owners());
}

/// A floating Body whose orientation_state is None has nothing that gives
/// it an orientation: assembly fails and names it. None is also the
/// default, so leaving the parameter out fails alike.
#[test]
fn floating_body_without_orientation_states_is_an_error() {
    for state in [Some(OrientationState::None), None] {
        let err = lone_body(state).assemble().unwrap_err();
        println!("{state:?}: {err}");
        let Error::NoOrientationOwner { components } = &err else {
            panic!("{state:?}: expected NoOrientationOwner, got {err:?}")
        };
        assert!(components.iter().any(|c| c == "body"), "{components:?}");
    }
}

// ----------------------------------------------------------- A. loop cuts

/// The planar four-bar: 4 revolutes (4 coordinates), one loop, one degree
/// of freedom; 5 equations at the cut revolute, of which a planar loop
/// repeats 3. The damper pins j1 in the tree, so it is never the cut.
#[test]
fn four_bar_has_one_loop_and_one_degree_of_freedom() {
    let mechanism = four_bar(None).assemble().unwrap();
    let loops = mechanism.loops();
    println!("four-bar loops {loops:?}");
    assert_eq!(loops.len(), 1);
    assert_eq!(mechanism.degrees_of_freedom(), 1);
    assert_eq!(mechanism.link_count(), 3, "the cut leaves three moving bars in the tree");
    assert_eq!((loops[0].equations, loops[0].redundant), (5, 3));
    let mut joints = loops[0].joints.clone();
    joints.sort();
    assert_eq!(joints, ["j1", "j2", "j3", "j4"]);
    assert_ne!(loops[0].cut, "j1");
}

/// Whichever free joint is marked `iscut` becomes the cut; the counts stay.
#[test]
fn iscut_chooses_the_cut_joint() {
    for j in ["j2", "j3", "j4"] {
        let mechanism = four_bar(Some(j)).assemble().unwrap();
        let loops = mechanism.loops();
        assert_eq!(loops.len(), 1);
        assert_eq!(loops[0].cut, j, "iscut on {j}: {loops:?}");
        assert_eq!(mechanism.degrees_of_freedom(), 1);
        // The cut joint's coordinates are no states.
        assert!(!names(&mechanism).iter().any(|n| n.starts_with(&format!("{j}."))), "{:?}", names(&mechanism));
    }
}

// ------------------------------------------- B. ABA against M ud = f
//
// `forward_dynamics` on a tree runs the articulated-body algorithm: it
// never forms the mass matrix, but propagates articulated inertias from
// the leaves inwards and accelerations outwards. `mass_matrix_and_bias`
// forms M column by column with composite rigid bodies (CRBA) and
// f = tau - C(q, u) with a Newton-Euler pass at zero acceleration (RNEA).
// The two share only the joint kinematics, so an error in the ABA's
// articulated inertias, bias forces or projections shows up as
// M ud != f. With loops, forward_dynamics itself solves with CRBA and RNEA
// (the tree may hold links without mass), so there the identity checks the
// constraint solve (augmented factorisation, Schur complement, multipliers)
// and J and -Jdot u are checked against finite differences of J.

/// Deterministic pseudo-random numbers (Knuth's 64-bit LCG, top 53 bits).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// `M x` with `M` row-major `n x n`.
fn mat_vec(m: &[f64], x: &[f64]) -> Vec<f64> {
    let n = x.len();
    (0..n).map(|i| (0..n).map(|j| m[i * n + j] * x[j]).sum()).collect()
}

/// `M x` in absolute values: the size of the terms summed in each row, the
/// scale against which a rounding-level residual is measured.
fn abs_mat_vec(m: &[f64], x: &[f64]) -> Vec<f64> {
    let n = x.len();
    (0..n).map(|i| (0..n).map(|j| (m[i * n + j] * x[j]).abs()).sum()).collect()
}

/// `J' l` with `J` row-major `rows x n`, and its absolute version.
fn jt_vec(j: &[f64], l: &[f64], n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut out = vec![0.0; n];
    let mut abs = vec![0.0; n];
    for (r, lr) in l.iter().enumerate() {
        for i in 0..n {
            out[i] += j[r * n + i] * lr;
            abs[i] += (j[r * n + i] * lr).abs();
        }
    }
    (out, abs)
}

/// The benchmark chain with rotational spring-dampers on every third joint
/// (j0, j3, ...), so that the joint torques tau are not zero.
fn sprung_chain(n: usize) -> (Model, Vec<usize>) {
    let mut model = chain::benchmark_chain(n);
    let sprung: Vec<usize> = (0..n).step_by(3).collect();
    for &k in &sprung {
        model.component_mut(&format!("j{k}")).unwrap().set("axisflange", true);
        model
            .add(format!("sd{k}"), "RotationalComponents.SpringDamper")
            .set("c", SPRING_C)
            .set("d", SPRING_D)
            .set("phi_rel0", SPRING_REST);
        model.connect([format!("sd{k}.spline_a"), format!("j{k}.support")]);
        model.connect([format!("sd{k}.spline_b"), format!("j{k}.axis")]);
    }
    (model, sprung)
}

const SPRING_C: f64 = 40.0;
const SPRING_D: f64 = 3.0;
const SPRING_REST: f64 = 0.2;

/// On the 7- and 30-link chains at random states, the ABA's accelerations
/// solve M ud = f to 1e-9 of the size of the terms. The spring-dampers'
/// share of f is also checked by hand: the joint feels
/// -c (phi - phi_rel0) - d w, the reaction of the element's torque.
#[test]
fn aba_accelerations_solve_the_mass_matrix_equations_on_the_chain() {
    let mut rng = Lcg(0x5eed_1234_abcd_0001);
    for n in [7, 30] {
        let (model, sprung) = sprung_chain(n);
        let mechanism = model.assemble().unwrap();
        let bare = chain::benchmark_chain(n).assemble().unwrap();
        assert_eq!(mechanism.states().names, bare.states().names, "the springs changed the states");
        let (nq, nv) = (mechanism.states().nq, mechanism.states().nv);
        assert_eq!((nq, nv), (n, n));
        let system = mechanism.system();
        let (mut ws_aba, mut ws_crba, mut ws_bare) = (mechanism.workspace(), mechanism.workspace(), bare.workspace());
        let mut worst = 0.0f64;
        let mut worst_tau = 0.0f64;
        for sample in 0..5 {
            let t = 0.1 * sample as f64;
            let q: Vec<f64> = (0..nq).map(|_| rng.uniform(-3.0, 3.0)).collect();
            let u: Vec<f64> = (0..nv).map(|_| rng.uniform(-2.0, 2.0)).collect();
            let mut ud = vec![0.0; nv];
            mechanism.forward_dynamics(&mut ws_aba, t, &q, &u, &mut ud).unwrap();
            let (mut m, mut f) = (vec![0.0; nv * nv], vec![0.0; nv]);
            system.mass_matrix_and_bias(&mut ws_crba, t, &q, &u, &mut m, &mut f).unwrap();
            for i in 0..nv {
                for j in 0..i {
                    assert_eq!(m[i * nv + j], m[j * nv + i], "M is not symmetric");
                }
                assert!(m[i * nv + i] > 0.0, "M[{i},{i}] = {}", m[i * nv + i]);
            }
            let (mu, scale) = (mat_vec(&m, &ud), abs_mat_vec(&m, &ud));
            let scale = (0..nv).map(|i| scale[i] + f[i].abs()).fold(0.0, f64::max);
            let residual = (0..nv).map(|i| (mu[i] - f[i]).abs()).fold(0.0, f64::max);
            worst = worst.max(residual / scale);

            // The springs' torques, from the difference to the chain without them.
            let (mut m0, mut f0) = (vec![0.0; nv * nv], vec![0.0; nv]);
            bare.system().mass_matrix_and_bias(&mut ws_bare, t, &q, &u, &mut m0, &mut f0).unwrap();
            assert_eq!(m, m0, "the springs changed the mass matrix");
            for k in 0..n {
                let expected =
                    if sprung.contains(&k) { -SPRING_C * (q[k] - SPRING_REST) - SPRING_D * u[k] } else { 0.0 };
                let err = (f[k] - f0[k] - expected).abs() / (1.0 + f[k].abs() + f0[k].abs());
                worst_tau = worst_tau.max(err);
            }
        }
        println!(
            "chain of {n}: worst |M ud - f| = {worst:.2e} of the terms' size (limit 1e-9); worst spring torque error {worst_tau:.2e}"
        );
        assert!(worst < 1e-9);
        assert!(worst_tau < 1e-12);
    }
}

/// The full state `y = [q, u]` at sample `k` of a solution, by state name.
fn state_at(mechanism: &Mechanism, solution: &multibody::Solution, k: usize) -> Vec<f64> {
    mechanism.states().names.iter().map(|n| solution.get(n).unwrap_or_else(|| panic!("no signal {n}"))[k]).collect()
}

/// The moving four-bar (crank started at 5 rad/s), at states along its
/// motion put back on the constraints: the accelerations and multipliers
/// satisfy M ud = f + J' lambda and J ud = -Jdot u to 1e-8 of the terms'
/// size. J and -Jdot u are the derivatives of the constraints: J u = 0 on
/// the constraint, and the central difference of J along qdot, times u,
/// gives Jdot u.
#[test]
fn loop_accelerations_satisfy_the_constrained_equations() {
    let mechanism = four_bar(None).assemble().unwrap();
    let system = mechanism.system();
    let (nq, nv) = (mechanism.states().nq, mechanism.states().nv);
    let solution = mechanism
        .simulate(&SimulationOptions { stop: 2.0, saveat: 0.25, abstol: 1e-9, reltol: 1e-9, ..Default::default() })
        .unwrap();
    let mut ws = mechanism.workspace();
    let mut ws_crba = mechanism.workspace();
    let (mut worst_dyn, mut worst_con, mut worst_vel, mut worst_jdot) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let mut samples = 0;
    for k in 1..solution.len() {
        let t = solution.time()[k];
        let mut y = state_at(&mechanism, &solution, k);
        mechanism.project(&mut ws, t, &mut y).unwrap();
        let (q, u) = y.split_at(nq);
        let mut ud = vec![0.0; nv];
        mechanism.forward_dynamics(&mut ws, t, q, u, &mut ud).unwrap();
        let jac = ws.constraint_jacobian().to_vec();
        let lambda = ws.multipliers().to_vec();
        // What J ud must equal: -Jdot u.
        let gamma: Vec<f64> = ws.constraint_velocity_product().iter().map(|b| -b).collect();
        let rows = lambda.len();
        assert_eq!(jac.len(), rows * nv);
        assert_eq!(rows, 5, "one cut revolute: 5 rows");

        let (mut m, mut f) = (vec![0.0; nv * nv], vec![0.0; nv]);
        system.mass_matrix_and_bias(&mut ws_crba, t, q, u, &mut m, &mut f).unwrap();
        let (mu, mu_abs) = (mat_vec(&m, &ud), abs_mat_vec(&m, &ud));
        let (jl, jl_abs) = jt_vec(&jac, &lambda, nv);
        let scale = (0..nv).map(|i| mu_abs[i] + f[i].abs() + jl_abs[i]).fold(0.0, f64::max);
        let residual = (0..nv).map(|i| (mu[i] - f[i] - jl[i]).abs()).fold(0.0, f64::max);
        worst_dyn = worst_dyn.max(residual / scale);

        let row = |r: usize, x: &[f64]| -> (f64, f64) {
            let terms = (0..nv).map(|i| jac[r * nv + i] * x[i]);
            (terms.clone().sum(), terms.map(f64::abs).sum())
        };
        let scale = (0..rows).map(|r| row(r, &ud).1 + gamma[r].abs()).fold(0.0, f64::max);
        let residual = (0..rows).map(|r| (row(r, &ud).0 - gamma[r]).abs()).fold(0.0, f64::max);
        worst_con = worst_con.max(residual / scale);
        // On the constraint the velocities keep the loop closed.
        let u_scale = (0..rows).map(|r| row(r, u).1).fold(0.0, f64::max);
        worst_vel = worst_vel.max((0..rows).map(|r| row(r, u).0.abs()).fold(0.0, f64::max) / u_scale);

        // Jdot u from J at q -/+ h qdot (u held), central difference.
        let mut dy = vec![0.0; nq + nv];
        mechanism.rhs(&mut ws, t, &y, &mut dy).unwrap();
        let h = 1e-5;
        let mut jacs = Vec::new();
        for s in [-h, h] {
            let qs: Vec<f64> = (0..nq).map(|i| q[i] + s * dy[i]).collect();
            let mut scratch = vec![0.0; nv];
            mechanism.forward_dynamics(&mut ws, t, &qs, u, &mut scratch).unwrap();
            jacs.push(ws.constraint_jacobian().to_vec());
        }
        let jdot_u: Vec<f64> = (0..rows)
            .map(|r| (0..nv).map(|i| (jacs[1][r * nv + i] - jacs[0][r * nv + i]) / (2.0 * h) * u[i]).sum())
            .collect();
        let scale = gamma.iter().chain(&jdot_u).fold(1e-3, |a: f64, x| a.max(x.abs()));
        let err = (0..rows).map(|r| (jdot_u[r] + gamma[r]).abs()).fold(0.0, f64::max);
        worst_jdot = worst_jdot.max(err / scale);
        samples += 1;
    }
    println!(
        "four-bar over {samples} states: |M ud - f - J' lambda| {worst_dyn:.2e}, |J ud + Jdot u| {worst_con:.2e} \
         (limits 1e-8); |J u| {worst_vel:.2e}; finite-difference Jdot u against -gamma {worst_jdot:.2e} (limit 1e-6)"
    );
    assert!(samples >= 8);
    assert!(worst_dyn < 1e-8);
    assert!(worst_con < 1e-8);
    assert!(worst_vel < 1e-8);
    assert!(worst_jdot < 1e-6);
}
