//! The joint assemblies (JointRRR, JointRRP, JointUSR, JointUSP, JointSSR,
//! JointSSP, UniversalSpherical) close a loop as the same loop built from
//! elementary joints does: the same motion, to integration tolerance.

use multibody::{Model, SimulationOptions, Solution};

fn options() -> SimulationOptions {
    SimulationOptions { stop: 2.0, saveat: 0.01, abstol: 1e-10, reltol: 1e-10, ..Default::default() }
}

/// Largest difference of `name` between two runs.
fn difference(a: &Solution, b: &Solution, name: &str) -> f64 {
    let (x, y) = (a.get(name).unwrap(), b.get(name).unwrap());
    x.iter().zip(y).fold(0.0f64, |m, (p, q)| m.max((p - q).abs()))
}

/// Both runs agree to 1e-7: each integrates to 1e-10, and the chaos-free
/// loop amplifies that little over 2 s.
fn assert_same_motion(label: &str, a: &Model, b: &Model, names: &[&str]) {
    let (sa, sb) =
        (a.assemble().unwrap().simulate(&options()).unwrap(), b.assemble().unwrap().simulate(&options()).unwrap());
    for name in names {
        let d = difference(&sa, &sb, name);
        eprintln!("{label}: {name} differs by {d:.1e} (tolerance 1e-7)");
        assert!(d < 1e-7, "{label}: {name} differs by {d:e}");
    }
    // And it moves: the comparison is not of two resting mechanisms.
    let moved = sa.get(names[0]).unwrap().iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(moved > 0.1, "{label}: {} hardly moves", names[0]);
}

/// Fourbar's crank, slider and bodies; the coupler is added by `close`.
fn spatial_four_bar(name: &str) -> Model {
    let mut m = Model::new(name);
    m.add("world", "World");
    m.add("j1", "Revolute").set("n", [1.0, 0.0, 0.0]).initial("phi", 0.0).initial("w", 5.235987755983);
    m.add("b1", "BodyCylinder").set("r", [0.0, 0.5, 0.1]).set("diameter", 0.05);
    m.add("b0", "FixedTranslation").set("r", [1.2, 0.0, 0.0]);
    m.add("b2", "BodyCylinder").set("r", [0.0, 0.2, 0.0]).set("diameter", 0.05);
    m.connect(["world.frame_b", "j1.frame_a"]);
    m.connect(["j1.frame_b", "b1.frame_a"]);
    m.connect(["world.frame_b", "b0.frame_a"]);
    m
}

/// The slider and the massless coupler from elementary joints: a prismatic
/// joint, a universal pair of revolutes at the slider and three at the crank.
fn spatial_elementary() -> Model {
    let mut m = spatial_four_bar("elementary");
    m.add("j2", "Prismatic").set("n", [1.0, 0.0, 0.0]).guess("s", -0.2);
    m.add("rev", "Revolute").set("n", [0.0, 1.0, 0.0]);
    m.add("rev1", "Revolute").set("n", [0.0, 0.0, 1.0]);
    m.add("rod", "FixedTranslation").set("r", [-1.0, 0.3, 0.1]);
    for (name, n) in [("j3", [1.0, 0.0, 0.0]), ("j4", [0.0, 1.0, 0.0]), ("j5", [0.0, 0.0, 1.0])] {
        m.add(name, "Revolute").set("n", n);
    }
    m.connect(["b0.frame_b", "j2.frame_a"]);
    m.connect(["j2.frame_b", "b2.frame_a"]);
    m.connect(["b2.frame_b", "rev.frame_a"]);
    m.connect(["rev.frame_b", "rev1.frame_a"]);
    m.connect(["rev1.frame_b", "rod.frame_a"]);
    m.connect(["b1.frame_b", "j3.frame_a"]);
    m.connect(["j3.frame_b", "j4.frame_a"]);
    m.connect(["j4.frame_b", "j5.frame_a"]);
    m.connect(["j5.frame_b", "rod.frame_b"]);
    m
}

#[test]
fn spatial_assemblies_move_as_elementary_joints() {
    let reference = spatial_elementary();
    let names = ["j1.phi", "j1.w", "b2.frame_a.r_0[1]"];

    let mut ssp = spatial_four_bar("ssp");
    ssp.add("a", "JointSSP")
        .set("rod1_length", 1.1f64.sqrt())
        .set("n_b", [1.0, 0.0, 0.0])
        .set("s_offset", -0.2)
        .set("rRod2_ib", [0.0, 0.2, 0.0]);
    ssp.connect(["b1.frame_b", "a.frame_a"]);
    ssp.connect(["b0.frame_b", "a.frame_b"]);
    ssp.connect(["a.frame_ib", "b2.frame_a"]);
    assert_same_motion("JointSSP", &reference, &ssp, &names);

    // The universal joint at the crank's tip, its rod to the slider.
    let mut usp = spatial_four_bar("usp");
    usp.add("a", "JointUSP")
        .set("n1_a", [0.0, 1.0, 0.0])
        .set("rRod1_ia", [1.0, -0.3, -0.1])
        .set("n_b", [1.0, 0.0, 0.0])
        .set("s_offset", -0.2)
        .set("rRod2_ib", [0.0, 0.2, 0.0]);
    usp.connect(["b1.frame_b", "a.frame_a"]);
    usp.connect(["b0.frame_b", "a.frame_b"]);
    usp.connect(["a.frame_ib", "b2.frame_a"]);
    assert_same_motion("JointUSP", &reference, &usp, &names);

    let mut us = spatial_four_bar("universal_spherical");
    us.add("j2", "Prismatic").set("n", [1.0, 0.0, 0.0]).guess("s", -0.2);
    us.add("a", "UniversalSpherical").set("n1_a", [0.0, 1.0, 0.0]).set("rRod_ia", [-1.0, 0.3, 0.1]);
    us.connect(["b0.frame_b", "j2.frame_a"]);
    us.connect(["j2.frame_b", "b2.frame_a"]);
    us.connect(["b2.frame_b", "a.frame_a"]);
    us.connect(["a.frame_b", "b1.frame_b"]);
    assert_same_motion("UniversalSpherical", &reference, &us, &names);
}

/// A planar four-bar swinging under gravity: crank at the origin (to A =
/// (0, 0.5)), the ground pivot B = (1, 0); a body on the crank. The
/// four-bars add a rocker from B to M = (1.1, 0.6) with a body, and a
/// massless coupler from A to M.
fn planar_four_bar(name: &str) -> Model {
    let mut m = Model::new(name);
    m.add("world", "World");
    m.add("crank", "Revolute").set("n", [0.0, 0.0, 1.0]).initial("phi", 0.0).initial("w", 2.0);
    m.add("crank_rod", "FixedTranslation").set("r", [0.0, 0.5, 0.0]);
    m.add("crank_mass", "Body").set("m", 1.0).set("r_cm", [0.0, 0.25, 0.0]);
    m.add("ground", "FixedTranslation").set("r", [1.0, 0.0, 0.0]);
    m.connect(["world.frame_b", "crank.frame_a", "ground.frame_a"]);
    m.connect(["crank.frame_b", "crank_rod.frame_a", "crank_mass.frame_a"]);
    m
}

fn with_rocker_mass(mut m: Model) -> Model {
    m.add("rocker_mass", "Body").set("m", 2.0).set("r_cm", [0.05, 0.3, 0.0]);
    m
}

fn planar_elementary() -> Model {
    let mut m = with_rocker_mass(planar_four_bar("elementary"));
    m.add("rev_a", "Revolute").set("n", [0.0, 0.0, 1.0]);
    m.add("coupler", "FixedTranslation").set("r", [1.1, 0.1, 0.0]);
    m.add("rev_m", "Revolute").set("n", [0.0, 0.0, 1.0]);
    m.add("rev_b", "Revolute").set("n", [0.0, 0.0, 1.0]);
    m.add("rocker", "FixedTranslation").set("r", [0.1, 0.6, 0.0]);
    m.connect(["crank_rod.frame_b", "rev_a.frame_a"]);
    m.connect(["rev_a.frame_b", "coupler.frame_a"]);
    m.connect(["coupler.frame_b", "rev_m.frame_a"]);
    m.connect(["ground.frame_b", "rev_b.frame_a"]);
    m.connect(["rev_b.frame_b", "rocker.frame_a", "rocker_mass.frame_a"]);
    m.connect(["rocker.frame_b", "rev_m.frame_b"]);
    m
}

#[test]
fn planar_assemblies_move_as_elementary_joints() {
    let reference = planar_elementary();
    let names = ["crank.phi", "crank.w", "rocker_mass.frame_a.R[1,2]"];
    let coupler = [1.1, 0.1, 0.0];
    let rocker = [0.1, 0.6, 0.0];
    for kind in ["JointRRR", "JointUSR", "JointSSR"] {
        let mut m = with_rocker_mass(planar_four_bar(kind));
        let a = m.add("a", kind).set("rRod2_ib", rocker);
        match kind {
            "JointRRR" => a.set("rRod1_ia", coupler),
            "JointUSR" => a.set("n1_a", [0.0, 0.0, 1.0]).set("rRod1_ia", coupler),
            _ => a.set("rod1_length", (1.1f64 * 1.1 + 0.1 * 0.1).sqrt()),
        };
        m.connect(["crank_rod.frame_b", "a.frame_a"]);
        m.connect(["ground.frame_b", "a.frame_b"]);
        m.connect(["a.frame_ib", "rocker_mass.frame_a"]);
        assert_same_motion(kind, &reference, &m, &names);
    }
}

/// A slider-crank: the crank as above, a slider along x through B = (1, 0)
/// (the prismatic joint at frame_b), the coupler from A to the slider.
#[test]
fn slider_crank_assemblies_move_as_elementary_joints() {
    let slider = |name: &str| {
        let mut m = planar_four_bar(name);
        m.add("slider_mass", "Body").set("m", 2.0);
        m
    };
    let mut reference = slider("elementary");
    reference.add("rev_a", "Revolute").set("n", [0.0, 0.0, 1.0]);
    reference.add("coupler", "FixedTranslation").set("r", [1.0, -0.5, 0.0]);
    reference.add("rev_m", "Revolute").set("n", [0.0, 0.0, 1.0]);
    reference.add("slide", "Prismatic").set("n", [1.0, 0.0, 0.0]);
    reference.connect(["crank_rod.frame_b", "rev_a.frame_a"]);
    reference.connect(["rev_a.frame_b", "coupler.frame_a"]);
    reference.connect(["coupler.frame_b", "rev_m.frame_a"]);
    reference.connect(["ground.frame_b", "slide.frame_a"]);
    reference.connect(["slide.frame_b", "rev_m.frame_b", "slider_mass.frame_a"]);
    let names = ["crank.phi", "crank.w", "slider_mass.frame_a.r_0[1]"];
    for kind in ["JointRRP", "JointUSP", "JointSSP"] {
        let mut m = slider(kind);
        let a = m.add("a", kind).set("n_b", [1.0, 0.0, 0.0]).set("rRod2_ib", [0.0, 0.0, 0.0]);
        match kind {
            "JointRRP" => a.set("rRod1_ia", [1.0, -0.5, 0.0]),
            "JointUSP" => a.set("n1_a", [0.0, 0.0, 1.0]).set("rRod1_ia", [1.0, -0.5, 0.0]),
            _ => a.set("rod1_length", 1.25f64.sqrt()),
        };
        m.connect(["crank_rod.frame_b", "a.frame_a"]);
        m.connect(["ground.frame_b", "a.frame_b"]);
        m.connect(["a.frame_ib", "slider_mass.frame_a"]);
        assert_same_motion(kind, &reference, &m, &names);
    }
}

/// CutMount releasing a planar loop's redundant directions (translation
/// along z, rotations about x, y and z) closes it as
/// RevolutePlanarLoopConstraint does.
#[test]
fn a_cut_mount_releasing_the_redundant_directions_closes_a_planar_loop() {
    let close = |kind: &str| {
        let mut m = with_rocker_mass(planar_four_bar(kind));
        m.add("rev_a", "Revolute").set("n", [0.0, 0.0, 1.0]);
        m.add("coupler", "FixedTranslation").set("r", [1.1, 0.1, 0.0]);
        m.add("rev_b", "Revolute").set("n", [0.0, 0.0, 1.0]);
        m.add("rocker", "FixedTranslation").set("r", [0.1, 0.6, 0.0]);
        let c = m.add("cut", kind);
        if kind == "CutMount" {
            c.set("z_locked", false).set("rx_locked", false).set("ry_locked", false).set("rz_locked", false);
        } else {
            c.set("n", [0.0, 0.0, 1.0]);
        }
        m.connect(["crank_rod.frame_b", "rev_a.frame_a"]);
        m.connect(["rev_a.frame_b", "coupler.frame_a"]);
        m.connect(["coupler.frame_b", "cut.frame_a"]);
        m.connect(["ground.frame_b", "rev_b.frame_a"]);
        m.connect(["rev_b.frame_b", "rocker.frame_a", "rocker_mass.frame_a"]);
        m.connect(["rocker.frame_b", "cut.frame_b"]);
        m
    };
    let names = ["crank.phi", "crank.w", "rocker_mass.frame_a.R[1,2]"];
    assert_same_motion("CutMount", &close("RevolutePlanarLoopConstraint"), &close("CutMount"), &names);
    assert_same_motion("CutMount", &planar_elementary(), &close("CutMount"), &names);
}

/// UniversalSpherical's rod frame frame_ia carries mass as the rod of an
/// elementary universal joint does: the same axes (n1_a, then n1_a x rod),
/// the same body on the rod, the same motion.
#[test]
fn a_body_on_the_universal_spherical_rod_frame_moves_as_on_elementary_joints() {
    let rod = [-1.0, 0.3, 0.1];
    let n1 = [0.0, 1.0, 0.0];
    let across = [0.1 / 1.01f64.sqrt(), 0.0, 1.0 / 1.01f64.sqrt()];
    let rod_body = |m: &mut Model| {
        m.add("rod_mass", "Body")
            .set("m", 0.7)
            .set("r_cm", [-0.5, 0.15, 0.05])
            .set("I_11", 0.02)
            .set("I_22", 0.03)
            .set("I_33", 0.04);
    };

    let mut elementary = spatial_four_bar("elementary_rod_mass");
    elementary.add("j2", "Prismatic").set("n", [1.0, 0.0, 0.0]).guess("s", -0.2);
    elementary.add("rev", "Revolute").set("n", n1);
    elementary.add("rev1", "Revolute").set("n", across);
    elementary.add("rod", "FixedTranslation").set("r", rod);
    elementary.add("ball", "Spherical");
    rod_body(&mut elementary);
    elementary.connect(["b0.frame_b", "j2.frame_a"]);
    elementary.connect(["j2.frame_b", "b2.frame_a"]);
    elementary.connect(["b2.frame_b", "rev.frame_a"]);
    elementary.connect(["rev.frame_b", "rev1.frame_a"]);
    elementary.connect(["rev1.frame_b", "rod.frame_a", "rod_mass.frame_a"]);
    elementary.connect(["rod.frame_b", "ball.frame_a"]);
    elementary.connect(["ball.frame_b", "b1.frame_b"]);

    let mut us = spatial_four_bar("universal_spherical_rod_mass");
    us.add("j2", "Prismatic").set("n", [1.0, 0.0, 0.0]).guess("s", -0.2);
    us.add("a", "UniversalSpherical").set("n1_a", n1).set("rRod_ia", rod);
    rod_body(&mut us);
    us.connect(["b0.frame_b", "j2.frame_a"]);
    us.connect(["j2.frame_b", "b2.frame_a"]);
    us.connect(["b2.frame_b", "a.frame_a"]);
    us.connect(["a.frame_b", "b1.frame_b"]);
    us.connect(["a.frame_ia", "rod_mass.frame_a"]);

    let names = ["j1.phi", "j1.w", "j2.s", "rod_mass.w_a[1]", "rod_mass.w_a[3]"];
    assert_same_motion("UniversalSpherical with a body on frame_ia", &elementary, &us, &names);

    // The rod's mass changes the motion: without it the crank moves otherwise.
    let without = spatial_elementary().assemble().unwrap().simulate(&options()).unwrap();
    let with = us.assemble().unwrap().simulate(&options()).unwrap();
    assert!(difference(&with, &without, "j1.phi") > 1e-3, "the rod's body made no difference");
}

/// JointRRP starts on the branch `positive_branch` names, as the library's
/// closed form `d = -k1 +- sqrt(k1^2 - |w|^2 + L^2)` (Modelica's
/// PrismaticWithLengthConstraint). The slider-crank above: the crank pin
/// at A = 0.5 (-sin phi, cos phi), the slider along x through B = (1, 0),
/// rod 1 of length L = sqrt(1.25). The slider is at
/// `x = A_x + sqrt(L^2 - A_y^2)` on the positive branch and at
/// `A_x - sqrt(L^2 - A_y^2)` on the other, at the start (1 and -1) and at
/// every sample after.
#[test]
fn joint_rrp_starts_on_the_branch_it_is_given() {
    for positive in [true, false] {
        let mut m = planar_four_bar("rrp_branch");
        m.add("slider_mass", "Body").set("m", 2.0);
        m.add("a", "JointRRP")
            .set("n_b", [1.0, 0.0, 0.0])
            .set("rRod2_ib", [0.0, 0.0, 0.0])
            .set("rRod1_ia", [1.0, -0.5, 0.0])
            .set("positive_branch", positive);
        m.connect(["crank_rod.frame_b", "a.frame_a"]);
        m.connect(["ground.frame_b", "a.frame_b"]);
        m.connect(["a.frame_ib", "slider_mass.frame_a"]);
        let options = SimulationOptions { stop: 1.0, ..options() };
        let s = m.assemble().unwrap().simulate(&options).unwrap();
        let (phi, x) = (s.get("crank.phi").unwrap(), s.get("slider_mass.frame_a.r_0[1]").unwrap());
        let sign = if positive { 1.0 } else { -1.0 };
        let mut worst = 0.0f64;
        for k in 0..phi.len() {
            let (ax, ay) = (-0.5 * phi[k].sin(), 0.5 * phi[k].cos());
            worst = worst.max((x[k] - (ax + sign * (1.25 - ay * ay).sqrt())).abs());
        }
        eprintln!("JointRRP positive_branch = {positive}: slider starts at {:.12}, worst error {worst:.1e}", x[0]);
        assert!((x[0] - sign).abs() < 1e-9, "positive_branch = {positive}: the slider starts at {}", x[0]);
        assert!(worst < 1e-7, "positive_branch = {positive}: the slider is off its closed form by {worst:e}");
    }
}
