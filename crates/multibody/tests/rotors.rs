//! 3-D effects of rotating parts: rotors whose axes are fixed in a moving
//! carrier, a bevel gear whose housing is that carrier, and the drive
//! trains that cannot be mounted on a moving body. The reference models
//! (GearConstraint, BevelGear1D, ActuatedDrive, GyroscopicEffects) are in
//! the command's reference tests; here, the conservation law they rest on.

use multibody::{Error, Model, OrientationState, SimulationOptions};

const JA: f64 = 0.3;
const JB: f64 = 0.7;
const RATIO: f64 = 3.0;
const CARRIER: [f64; 3] = [2.0, 3.0, 4.0];

/// A carrier body on a spherical joint at the origin (no gravity), with a
/// rotor about its x-axis and one about its y-axis, coupled by a bevel gear
/// whose housing is the carrier; `extra` adds to it.
fn tumbling_gearbox(extra: &dyn Fn(&mut Model)) -> Model {
    let mut model = Model::new("gearbox");
    model.add("world", "World").set("g", 0.0);
    model
        .add("joint", "Spherical")
        .set("orientation_state", OrientationState::Quaternion)
        .initial("w_rel", [0.4, -0.3, 0.9]);
    model.add("carrier", "Body").set("m", 1.0).set("I_11", CARRIER[0]).set("I_22", CARRIER[1]).set("I_33", CARRIER[2]);
    model.add("rotor_a", "Rotor1D").set("J", JA).set("n", [1.0, 0.0, 0.0]).initial("w", 12.0);
    model.add("rotor_b", "Rotor1D").set("J", JB).set("n", [0.0, 1.0, 0.0]);
    model.add("gear", "BevelGear1D").set("ratio", RATIO).set("n_a", [1.0, 0.0, 0.0]).set("n_b", [0.0, 1.0, 0.0]);
    model.connect(["world.frame_b", "joint.frame_a"]);
    model.connect(["joint.frame_b", "carrier.frame_a", "rotor_a.frame_a", "rotor_b.frame_a", "gear.frame_a"]);
    model.connect(["rotor_a.flange_b", "gear.flange_a"]);
    model.connect(["gear.flange_b", "rotor_b.flange_a"]);
    extra(&mut model);
    model
}

/// The kinetic energy the Rotor1D model has: the carrier's, less the
/// rotors' axial inertia locked to it, plus each rotor's absolute spin.
fn kinetic_energy(w: [f64; 3], spin_a: f64, spin_b: f64) -> f64 {
    let carrier: f64 = (0..3).map(|i| 0.5 * CARRIER[i] * w[i] * w[i]).sum();
    let locked = 0.5 * JA * w[0] * w[0] + 0.5 * JB * w[1] * w[1];
    carrier - locked + 0.5 * JA * (spin_a + w[0]).powi(2) + 0.5 * JB * (spin_b + w[1]).powi(2)
}

/// Nothing drives the tumbling gearbox: if the bevel gear (with its housing
/// reaction through the rotors' bearings) did any net work, the energy
/// would drift. It keeps it to 1e-9, while the spin passes from rotor to
/// rotor and the carrier tumbles.
#[test]
fn a_bevel_gear_on_a_tumbling_carrier_transmits_no_net_power() {
    let mechanism = tumbling_gearbox(&|_| {}).assemble().unwrap();
    let options = SimulationOptions { stop: 3.0, saveat: 0.01, abstol: 1e-12, reltol: 1e-12, ..Default::default() };
    let s = mechanism.simulate(&options).unwrap();
    let col = |n: &str| s.get(n).unwrap_or_else(|| panic!("no {n}")).to_vec();
    let w: Vec<Vec<f64>> = (1..=3).map(|i| col(&format!("carrier.w_a[{i}]"))).collect();
    let (wa, wb) = (col("rotor_a.w"), col("rotor_b.w"));
    let energy: Vec<f64> = (0..wa.len()).map(|k| kinetic_energy([w[0][k], w[1][k], w[2][k]], wa[k], wb[k])).collect();
    let drift = energy.iter().fold(0.0f64, |m, e| m.max((e - energy[0]).abs())) / energy[0];
    eprintln!("tumbling gearbox: relative energy drift {drift:e} over 3 s");
    assert!(drift < 1e-9, "the energy drifts by {drift:e} (relative)");
    // The gear holds: rotor a turns RATIO times rotor b, relative to the carrier.
    let (pa, pb) = (col("rotor_a.phi"), col("rotor_b.phi"));
    assert!(pa.iter().zip(&pb).all(|(a, b)| (a - RATIO * b).abs() < 1e-8));
    // And the test is not of a still system: the carrier tumbles, the spin changes.
    let spread = |v: &[f64]| v.iter().fold(f64::MIN, |m, x| m.max(*x)) - v.iter().fold(f64::MAX, |m, x| m.min(*x));
    assert!(spread(&w[0]) > 0.1 && spread(&wb) > 0.1, "{} {}", spread(&w[0]), spread(&wb));
}

/// A source between rotor a and a Mounting1D on the carrier: its power,
/// `tau * phi_a'`, is the rate of change of that energy.
#[test]
fn a_mounted_source_powers_the_gearbox() {
    let mechanism = tumbling_gearbox(&|m| {
        m.add("tau", "BlockComponents.Sine").set("amplitude", 5.0).set("frequency", 2.0).set("offset", 1.0);
        m.add("source", "RotationalComponents.Torque");
        m.add("mounting", "Mounting1D");
        m.connect(["tau.y", "source.tau"]);
        m.connect(["source.spline", "rotor_a.flange_a"]);
        m.connect(["source.support", "mounting.flange_b"]);
        m.connect(["joint.frame_b", "mounting.frame_a"]);
    })
    .assemble()
    .unwrap();
    let options = SimulationOptions { stop: 1.0, saveat: 0.001, abstol: 1e-12, reltol: 1e-12, ..Default::default() };
    let s = mechanism.simulate(&options).unwrap();
    let col = |n: &str| s.get(n).unwrap_or_else(|| panic!("no {n}")).to_vec();
    let w: Vec<Vec<f64>> = (1..=3).map(|i| col(&format!("carrier.w_a[{i}]"))).collect();
    let (wa, wb, t) = (col("rotor_a.w"), col("rotor_b.w"), s.time().to_vec());
    let energy: Vec<f64> = (0..wa.len()).map(|k| kinetic_energy([w[0][k], w[1][k], w[2][k]], wa[k], wb[k])).collect();
    // Central differences of the energy against the power at the same sample.
    let mut worst = 0.0f64;
    let mut scale = 0.0f64;
    for k in 1..t.len() - 1 {
        let rate = (energy[k + 1] - energy[k - 1]) / (t[k + 1] - t[k - 1]);
        let power = (1.0 + 5.0 * (2.0 * std::f64::consts::TAU * t[k]).sin()) * wa[k];
        worst = worst.max((rate - power).abs());
        scale = scale.max(power.abs());
    }
    eprintln!("mounted source: power balance off by {:e} of the peak power", worst / scale);
    assert!(worst < 1e-4 * scale, "power balance off by {worst:e} of {scale:e}");
}

/// What a drive train mounted on a moving body cannot hold is refused with
/// a message that names the part and what to use instead.
#[test]
fn worldly_parts_in_a_mounted_drive_train_are_refused() {
    let with = |kind: &str| {
        tumbling_gearbox(&|m| {
            m.add("extra", kind).set("J", 1.0);
            m.connect(["rotor_b.flange_b", "extra.spline_a"]);
        })
    };
    match with("RotationalComponents.Inertia").assemble() {
        Err(Error::Unsupported { component, what, fix }) => {
            assert_eq!(component, "extra");
            assert!(fix.contains("Rotor1D") && what.contains("`gear`"), "{what}; {fix}");
        }
        other => panic!("expected an error naming the inertia, got {other:?}"),
    }
    // A source whose support is left to the world.
    let open_support = tumbling_gearbox(&|m| {
        m.add("source", "RotationalComponents.ConstantTorque").set("tau_constant", 1.0);
        m.connect(["source.spline", "rotor_a.flange_a"]);
    });
    match open_support.assemble() {
        Err(Error::Unsupported { component, what, fix }) => {
            assert_eq!(component, "source");
            assert!(
                what.contains("drive train") && fix.contains("support") && fix.contains("Mounting1D"),
                "{what}; {fix}"
            );
        }
        other => panic!("expected an error naming the source, got {other:?}"),
    }
}

/// GearConstraint's inner joints and their axes are its own: a model
/// cannot connect to them, and the error lists only the public connectors.
#[test]
fn a_gear_constraint_keeps_its_inner_connectors_to_itself() {
    let mut model = Model::new("inner");
    model.add("world", "World");
    model.add("gear", "GearConstraint").set("ratio", 2.0);
    model.add("damper", "RotationalComponents.Damper").set("d", 1.0);
    model.connect(["world.frame_b", "gear.bearing"]);
    model.connect(["gear.axis_a", "damper.spline_a"]);
    match model.assemble() {
        Err(Error::UnknownConnector { connector, valid, .. }) => {
            assert_eq!(connector, "axis_a");
            assert_eq!(valid, ["frame_a", "frame_b", "bearing"]);
        }
        other => panic!("expected an unknown connector, got {other:?}"),
    }
}
