//! Wheels: rolling without slipping (constraints on velocities) and
//! slipping (force laws), checked against closed forms and conservation
//! laws, never against numbers the engine produced.

use multibody::{Model, SimulationOptions, Solution};

const G: f64 = 9.80665;
// The library's RollingWheel defaults.
const R: f64 = 0.3;
const M: f64 = 1.0;
const I_AXIS: f64 = 0.06;
const I_LONG: f64 = 0.12;

fn tight(stop: f64, saveat: f64) -> SimulationOptions {
    SimulationOptions { stop, saveat, abstol: 1e-11, reltol: 1e-11, ..Default::default() }
}

/// A RollingWheel alone on the plane (the World for gravity), started at
/// `angles` turning at `der_angles`, of the library's default sequence
/// [2, 3, 1]: at zero angles, a rotation about y, z (the spin axis), x.
fn rolling_wheel(angles: [f64; 3], der_angles: [f64; 3]) -> Model {
    let mut model = Model::new("wheel");
    model.add("world", "World");
    model
        .add("wheel", "RollingWheel")
        .set("radius", R)
        .set("m", M)
        .set("I_axis", I_AXIS)
        .set("I_long", I_LONG)
        .initial("x", 0.0)
        .initial("z", 0.0)
        .initial("angles", angles.to_vec())
        .initial("der_angles", der_angles.to_vec());
    model
}

fn column<'a>(s: &'a Solution, name: &str) -> &'a [f64] {
    s.get(name).unwrap_or_else(|| panic!("no signal {name}"))
}

fn vector(s: &Solution, name: &str, k: usize) -> [f64; 3] {
    [1, 2, 3].map(|i| column(s, &format!("{name}[{i}]"))[k])
}

/// Kinetic plus potential energy of the wheel at sample `k`: translation of
/// the centre, rotation with the inertia diag(I_long, I_long, I_axis) in
/// frame_a, and height in gravity.
fn energy(s: &Solution, k: usize) -> f64 {
    let v = vector(s, "wheel.v_0", k);
    let w0 = vector(s, "wheel.w_0", k);
    // The angular velocity in frame_a: R w_0 (R maps world to frame).
    let rot = |i: usize, j: usize| column(s, &format!("wheel.frame_a.R[{i},{j}]"))[k];
    let w: Vec<f64> = (1..=3).map(|i| (1..=3).map(|j| rot(i, j) * w0[j - 1]).sum()).collect();
    let y = column(s, "wheel.y")[k];
    0.5 * M * v.iter().map(|x| x * x).sum::<f64>()
        + 0.5 * (I_LONG * (w[0] * w[0] + w[1] * w[1]) + I_AXIS * w[2] * w[2])
        + M * G * y
}

#[test]
fn an_upright_wheel_started_straight_rolls_in_a_straight_line() {
    // Spinning at 10 rad/s about +z (its axis along the world's z), the
    // contact point stays: the centre moves at -R * 10 along x, at height R.
    let spin = 10.0;
    let mechanism = rolling_wheel([0.0; 3], [0.0, spin, 0.0]).assemble().unwrap();
    let s = mechanism.simulate(&tight(5.0, 0.01)).unwrap();
    let mut worst = 0.0f64;
    for (k, &t) in s.time().iter().enumerate() {
        let expected = [-R * spin * t, R, 0.0];
        for (i, name) in ["wheel.x", "wheel.y", "wheel.z"].iter().enumerate() {
            worst = worst.max((column(&s, name)[k] - expected[i]).abs());
        }
    }
    // Tolerance 1e-9 m: the integrator runs at 1e-11 and this motion is
    // uniform (no error grows along it).
    println!("straight rolling: worst deviation {worst:.2e} m = {:.3} of the 1e-9 tolerance", worst / 1e-9);
    assert!(worst < 1e-9);
}

/// The default sequence is the library's [2, 3, 1]: a turn about the
/// world's y (heading), then about z (the spin axis), then about x. Started
/// at angles [h, s, 0] turning at der_angles [0, w, 0] with no `sequence`
/// given, a wheel stands upright with its axis along (sin h, 0, cos h),
/// spins at w about it and rolls at R w along (-cos h, 0, sin h); its angles
/// stay [h, s + w t, 0]. (Read as [2, 1, 3], the same numbers lean it by s
/// and it falls.)
#[test]
fn the_default_angles_are_the_library_s_heading_spin_and_tumble() {
    let (h, s0, w) = (0.7f64, 1.2f64, 8.0f64);
    let mechanism = rolling_wheel([h, s0, 0.0], [0.0, w, 0.0]).assemble().unwrap();
    let s = mechanism.simulate(&tight(2.0, 0.01)).unwrap();
    let (mut worst, mut angle_error) = (0.0f64, 0.0f64);
    for (k, &t) in s.time().iter().enumerate() {
        let expected = [-R * w * h.cos() * t, R, R * w * h.sin() * t];
        for (i, name) in ["wheel.x", "wheel.y", "wheel.z"].iter().enumerate() {
            worst = worst.max((column(&s, name)[k] - expected[i]).abs());
        }
        // The spin passes the sequence's singular values (pi/2 + n pi), where
        // the angles are ill-determined from the orientation: compare them
        // where the spin is more than 0.1 rad from those.
        let spin = s0 + w * t;
        if spin.cos().abs() > 0.1f64.sin() {
            let angles = vector(&s, "wheel.angles", k);
            for (a, e) in angles.iter().zip([h, spin, 0.0]) {
                angle_error = angle_error.max((a - e).abs());
            }
        }
    }
    // As for straight rolling: uniform motion at the integrator's 1e-11.
    println!(
        "default sequence: worst deviation {worst:.2e} m = {:.3} of 1e-9, angles {angle_error:.2e} rad = {:.3} of 1e-9",
        worst / 1e-9,
        angle_error / 1e-9
    );
    assert!(worst < 1e-9 && angle_error < 1e-9);
}

/// Two RollingWheels on an axle 1 m long (each on a revolute about z), the
/// second marked `iscut`: its coordinates are computed from the motion, not
/// integrated. Started with the first at der_angles [Omega, w1, 0], the axle
/// turns steadily at Omega about the vertical, the first wheel's centre on a
/// circle of radius rho1 = R w1 / Omega, the second's of rho2 = rho1 - 1,
/// both about (0, 0, rho1 - 0.5); the second spins at w2 = Omega rho2 / R,
/// so its angles are [Omega t, w2 t, 0]: reported continuously as its spin
/// passes the sequence's singular values.
#[test]
fn a_cut_wheel_on_an_axle_reports_the_library_s_angles() {
    let (omega, w1) = (0.3f64, 8.0f64);
    let mut model = Model::new("axle");
    model.add("world", "World");
    model.add("axle", "Body").set("m", 2.0).set("I_11", 0.1).set("I_22", 0.1).set("I_33", 0.1);
    for (k, z) in [(1, -0.5), (2, 0.5)] {
        model.add(format!("t{k}"), "FixedTranslation").set("r", vec![0.0, 0.0, z]);
        model.add(format!("rev{k}"), "Revolute").set("n", vec![0.0, 0.0, 1.0]);
        model
            .add(format!("w{k}"), "RollingWheel")
            .set("radius", R)
            .set("m", M)
            .set("I_axis", I_AXIS)
            .set("I_long", I_LONG);
        model.connect(["axle.frame_a".to_string(), format!("t{k}.frame_a")]);
        model.connect([format!("t{k}.frame_b"), format!("rev{k}.frame_a")]);
        model.connect([format!("rev{k}.frame_b"), format!("w{k}.frame_a")]);
    }
    model
        .component_mut("w1")
        .unwrap()
        .initial("x", 0.0)
        .initial("z", -0.5)
        .initial("angles", vec![0.0; 3])
        .initial("der_angles", vec![omega, w1, 0.0]);
    model.component_mut("w2").unwrap().set("iscut", true);
    let s = model.assemble().unwrap().simulate(&tight(3.0, 0.01)).unwrap();
    let rho1 = R * w1 / omega;
    let rho2 = rho1 - 1.0;
    let w2 = omega * rho2 / R;
    let centre_z = rho1 - 0.5;
    let (mut path, mut angle_error) = (0.0f64, 0.0f64);
    for (k, &t) in s.time().iter().enumerate() {
        let (x, z) = (column(&s, "w2.x")[k], column(&s, "w2.z")[k]);
        path = path.max(((x * x + (z - centre_z).powi(2)).sqrt() - rho2).abs());
        // Away from the singular values of the spin, as for the wheel on its own.
        if (w2 * t).cos().abs() > 0.1f64.sin() {
            let angles = vector(&s, "w2.angles", k);
            for (a, e) in angles.iter().zip([omega * t, w2 * t, 0.0]) {
                angle_error = angle_error.max((a - e).abs());
            }
        }
    }
    // Steady motion integrated at 1e-11: 1e-9 as for the wheel on its own.
    println!(
        "cut wheel on an axle: path error {path:.2e} m = {:.3} of 1e-9, angles {angle_error:.2e} rad = {:.3} of 1e-9",
        path / 1e-9,
        angle_error / 1e-9
    );
    assert!(path < 1e-9 && angle_error < 1e-9);
}

#[test]
fn a_rolling_wheel_keeps_its_energy_and_its_contact_point_still() {
    // Leaning, heading turning and spinning: a general rolling motion. The
    // lean is -0.3 about x; the angular velocity in frame_a is
    // (0.2, 0.8 cos 0.3, 0.8 sin 0.3 - 6): heading rate 0.8 about the world's
    // y, falling rate 0.2, spin -6. In [2, 3, 1] at [0, 0, -0.3] that is
    // der_angles = [0.8 - 6 sin 0.3, -6 cos 0.3, 0.2].
    let lean = 0.3f64;
    let der_angles = [0.8 - 6.0 * lean.sin(), -6.0 * lean.cos(), 0.2];
    let mechanism = rolling_wheel([0.0, 0.0, -lean], der_angles).assemble().unwrap();
    assert_eq!(mechanism.degrees_of_freedom(), 3, "5 positional and 3 velocity degrees of freedom");
    let s = mechanism.simulate(&tight(10.0, 0.01)).unwrap();
    let e0 = energy(&s, 0);
    let (mut drift, mut slip) = (0.0f64, 0.0f64);
    for k in 0..s.time().len() {
        drift = drift.max((energy(&s, k) - e0).abs() / e0.abs());
        let v = vector(&s, "wheel.v_contact_0", k);
        slip = slip.max(v.iter().map(|x| x * x).sum::<f64>().sqrt());
    }
    // Rolling constraints do no work and nothing else dissipates: energy is
    // conserved exactly; 1e-8 (relative) over 10 s leaves room for the
    // integrator's 1e-11 per step and the drift projection.
    println!("energy drift {drift:.2e} (relative) = {:.3} of 1e-8", drift / 1e-8);
    // The contact point's velocity is zero: 1e-9 m/s is the projection's reach.
    println!("contact velocity {slip:.2e} m/s = {:.3} of 1e-9", slip / 1e-9);
    assert!(drift < 1e-8);
    assert!(slip < 1e-9);
    // The wheel did move (the check is not of a wheel at rest).
    assert!(column(&s, "wheel.x").iter().any(|x| x.abs() > 0.5));
}

/// A thin axisymmetric disk (mass m, radius R, inertia A about its axis, B
/// across) rolling steadily with lean theta (its axis tilted theta up from
/// the horizontal), heading rate Omega, and spin component w_a = w . axis:
/// Newton-Euler about the centre gives
/// `(A + m R^2) w_a Omega cos(theta) - B Omega^2 sin(theta) cos(theta) + m g R sin(theta) = 0`,
/// and the centre moves at `V = -R w_a` on a circle of radius `rho = V / Omega`
/// about a point on the side the wheel leans to. For a chosen rho and theta:
/// `Omega^2 = m g R sin(theta) / ((A + m R^2) rho cos(theta) / R + B sin(theta) cos(theta))`.
#[test]
fn a_leaning_wheel_traces_the_circle_of_the_steady_rolling_disk() {
    let (theta, rho) = (0.2f64, 7.7f64);
    let omega = (M * G * R * theta.sin()
        / ((I_AXIS + M * R * R) * rho * theta.cos() / R + I_LONG * theta.sin() * theta.cos()))
    .sqrt();
    let w_a = -rho * omega / R;
    // Sequence [2, 1, 3] (given: its first rate is the heading rate here):
    // angles [heading, lean, spin]; a lean of -theta about x gives the axis
    // (0, sin theta, cos theta). The angular velocity is Omega y + spin_rate
    // axis, so w_a = Omega sin(theta) + spin_rate.
    let spin_rate = w_a - omega * theta.sin();
    let mut model = rolling_wheel([0.0, -theta, 0.0], [omega, 0.0, spin_rate]);
    model.component_mut("wheel").unwrap().set("sequence", [2.0, 1.0, 3.0]);
    let mechanism = model.assemble().unwrap();
    let lap = 2.0 * std::f64::consts::PI / omega;
    let s = mechanism.simulate(&tight(lap, 0.01)).unwrap();
    // The axis (0, sin theta, cos theta) tilts up towards +z: the wheel
    // leans towards -z, and so does its path. The centre starts at the
    // origin moving along +x at V = rho Omega, turning (Omega about +y)
    // towards -z: the circle's centre is at z = -rho.
    let (x, z) = (column(&s, "wheel.x"), column(&s, "wheel.z"));
    let centre_z = -rho;
    let mut worst = 0.0f64;
    for k in 0..s.time().len() {
        let r = (x[k] * x[k] + (z[k] - centre_z).powi(2)).sqrt();
        worst = worst.max((r - rho).abs());
    }
    let heading_rate = column(&s, "wheel.der_angles[1]");
    let rate_error = heading_rate.iter().fold(0.0f64, |a, w| a.max((w - omega).abs()));
    // One lap at 3 m/s, fast enough for the steady motion to be stable
    // (at 1.3 m/s on a 1 m circle with a 0.3 rad lean it is not: errors grow
    // e-fold in 0.6 s), so errors do not grow along it. Integrated at
    // 1e-11, 1e-9 m on a 7.7 m circle is a thousand steps' worth of local error.
    println!(
        "steady rolling disk: rho {rho} m, Omega {omega:.6} rad/s; radius error {worst:.2e} m = {:.4} of 1e-9, heading rate error {rate_error:.2e} rad/s = {:.4} of 1e-9",
        worst / 1e-9,
        rate_error / 1e-9
    );
    assert!(worst < 1e-9);
    assert!(rate_error < 1e-9);
}

/// A wheel of `kind` standing upright, spinning at `spin` about +z with its
/// centre at rest.
fn spinning_wheel(kind: &str, spin: f64, elastic: bool) -> Model {
    let mut model = Model::new("spin_up");
    model.add("world", "World");
    let wheel = model
        .add("wheel", kind)
        .set("radius", R)
        .set("m", M)
        .set("I_axis", I_AXIS)
        .set("I_long", I_LONG)
        .initial("x", 0.0)
        .initial("z", 0.0)
        .initial("angles", vec![0.0; 3])
        .initial("v_0", vec![0.0; 3])
        .initial("der_angles", vec![0.0, spin, 0.0]);
    if elastic {
        // Start resting on the spring: the weight's compression.
        wheel.set("elastic_contact", true).initial("y", R - M * G / 250000.0);
    }
    model
}

/// Started spinning with its centre at rest, a slipping wheel is pushed
/// forward by friction until its contact point stops slipping; then it
/// rolls. Friction and the normal force act at the contact point, and the
/// normal force balances the weight, so the angular momentum about the
/// ground line the wheel runs on is conserved: `I_axis w0 = I_axis w + m R^2 w`,
/// and rolling means `v = -R w` (a spin about +z runs towards -x).
#[test]
fn a_slipping_wheel_spins_up_until_it_rolls() {
    let spin = 25.0;
    let w_final = I_AXIS * spin / (I_AXIS + M * R * R);
    let v_final = -R * w_final;
    for (kind, elastic) in [("SlippingWheel", false), ("SlippingWheel", true), ("PacejkaSlippingWheel", false)] {
        let mechanism = spinning_wheel(kind, spin, elastic).assemble().unwrap();
        let s = mechanism.simulate(&SimulationOptions { stop: 3.0, saveat: 0.01, ..tight(3.0, 0.01) }).unwrap();
        let slip = column(&s, "wheel.v_slip_long");
        assert!(slip[1].abs() > 1.0, "{kind}: the wheel slips at first ({})", slip[1]);
        let last = s.time().len() - 1;
        let v = column(&s, "wheel.v_0[1]")[last];
        let w = column(&s, "wheel.w_roll")[last];
        let (dv, dw) = ((v - v_final).abs(), (w - w_final).abs());
        // The slip decays with a time constant of a few ms (the slip law's
        // slope near zero slip): after 3 s it is gone to rounding. 1e-6
        // relative on the final speeds: the angular momentum balance holds
        // to the integrator's 1e-11 per step (the elastic contact's settling
        // at the start moves the wheel by micrometres, below that).
        println!(
            "{kind} (elastic {elastic}): final slip {:.1e} m/s; speed {v:.9} vs {v_final:.9} m/s ({:.1e} of 1e-6 relative), spin {w:.9} vs {w_final:.9} rad/s ({:.1e} of 1e-6); f_n {:.6} N vs m g {:.6} N",
            slip[last],
            dv / v_final.abs() / 1e-6,
            dw / w_final.abs() / 1e-6,
            column(&s, "wheel.f_n")[last],
            M * G
        );
        // The normal force carries the weight (rigid: exactly; elastic: once settled).
        assert!((column(&s, "wheel.f_n")[last] - M * G).abs() < 1e-6 * M * G);
        assert!(slip[last].abs() < 1e-9, "{kind}: still slipping at {}", slip[last]);
        assert!(dv < 1e-6 * v_final.abs() && dw < 1e-6 * w_final.abs());
        // And it goes straight on.
        assert!(column(&s, "wheel.z").iter().all(|z| z.abs() < 1e-9));
    }
}

/// Bad wheel parameters are refused with a message that names the
/// component and the parameter and says what is wrong, never a panic.
#[test]
fn bad_wheel_parameters_are_named() {
    let cases: [(&str, &str, f64, &str); 6] = [
        ("RollingWheel", "radius", 0.0, "positive"),
        ("RollingWheelSet", "track", -1.0, "positive"),
        ("RollingConstraintVerticalWheel", "radius", -0.3, "positive"),
        ("SlippingWheel", "m", -2.0, "zero or more"),
        ("SlipWheelJoint", "vSlide_min", 0.01, "sliding must start beyond the adhesion peak"),
        ("PacejkaSlippingWheel", "radius", f64::NAN, "finite"),
    ];
    for (kind, param, value, words) in cases {
        let mut model = Model::new("bad");
        model.add("world", "World");
        model.add("w", kind).set(param, value);
        let message = match model.assemble() {
            Ok(_) => panic!("{kind} with {param} = {value} should be refused"),
            Err(e) => e.to_string(),
        };
        println!("{kind}.{param} = {value}: {message}");
        for w in ["w", param, words] {
            assert!(message.contains(w), "{kind}: the message should mention {w:?}: {message}");
        }
    }
}

/// Start velocities that contradict rolling are refused at the start, with
/// the fixed values named (not silently changed).
#[test]
fn start_velocities_that_slip_are_refused() {
    let mut model = rolling_wheel([0.0; 3], [0.0, 10.0, 0.0]);
    model.component_mut("wheel").unwrap().initial("v_0", vec![0.0; 3]);
    let message = match model.assemble() {
        Ok(_) => panic!("a spinning wheel whose centre is held still cannot roll"),
        Err(e) => e.to_string(),
    };
    println!("{message}");
    assert!(message.contains("wheel.v_0[1] = 0") && message.contains("wheel.der_angles[2] = 10"), "{message}");
}

/// A Pacejka wheel (grip along its path only: friction_ellipse = false) on
/// `road`, starting at rest at x = `x0`, its spin axis along z.
fn wheel_on_road(road: multibody::Expr, x0: f64) -> Model {
    let mut model = Model::new("road");
    model.add("world", "World");
    model
        .add("wheel", "PacejkaSlippingWheel")
        .set("radius", R)
        .set("m", M)
        .set("I_axis", I_AXIS)
        .set("I_long", I_LONG)
        .set("friction_ellipse", false)
        .initial("x", x0)
        .initial("z", 0.0)
        .initial("angles", vec![0.0; 3])
        .initial("v_0", vec![0.0; 3])
        .initial("der_angles", vec![0.0; 3])
        .surface(road);
    model
}

/// Down the road `y = -0.1 x`: the wheel creeps at the constant slip the
/// magic formula needs for the grip that rolling takes, so its centre
/// accelerates as a rolling wheel's, `g sin(a) / (1 + I_axis / (m R^2))`
/// along the slope, at the height `R / cos(a)` above the road, and the road
/// carries `m g cos(a)`: on the rigid contact and on the elastic one.
#[test]
fn a_wheel_rolls_down_a_sloping_road() {
    use multibody::Expr as S;
    let slope = 0.1f64;
    let angle = slope.atan();
    let expected = G * angle.sin() / (1.0 + I_AXIS / (M * R * R));
    for elastic in [false, true] {
        let road = -slope * S::var("x");
        let mut model = wheel_on_road(road, 0.0);
        if elastic {
            model.component_mut("wheel").unwrap().set("elastic_contact", true);
        }
        let mechanism = model.assemble().unwrap();
        let s = mechanism.simulate(&tight(3.0, 0.5)).unwrap();
        let (x, y, vx) = (column(&s, "wheel.x"), column(&s, "wheel.y"), column(&s, "wheel.v_0[1]"));
        let n = x.len() - 1;
        // Speed along the slope from its x component.
        let accel = (vx[n] - vx[n - 1]) / angle.cos() / (s.time()[n] - s.time()[n - 1]);
        let height = (y[n] - (-slope * x[n] + R / angle.cos())).abs();
        let load = (column(&s, "wheel.f_n")[n] - M * G * angle.cos()).abs();
        // The creep (and the elastic contact's bounce) settle in
        // milliseconds, so the last half second is pure rolling: 1e-6
        // relative is far above the integrator's 1e-11. The rigid contact
        // keeps the height and carries the load exactly (to 1e-9, the
        // projection's reach); the elastic one sits lower by its compression,
        // m g cos(a) / c_z = 3.9e-5 m along the normal (1e-4 allows for it).
        let height_tolerance = if elastic { 1e-4 } else { 1e-9 };
        println!(
            "sloping road (elastic {elastic}): acceleration {accel:.9} vs {expected:.9} m/s2 ({:.1e} of 1e-6 relative); height error {height:.1e} m (of {height_tolerance:.0e}), load error {load:.1e} N (of 1e-6 m g)",
            (accel - expected).abs() / expected / 1e-6
        );
        assert!((accel - expected).abs() < 1e-6 * expected);
        assert!(height < height_tolerance && load < 1e-6 * M * G);
    }
}

/// In the bowl `y = x^2 / (2 rho)`, a wheel rolling about the bottom swings
/// like one on a circular track of radius rho: its centre on a circle of
/// radius rho - R, period `2 pi sqrt((rho - R) (1 + I_axis / (m R^2)) / g)`
/// for small swings.
#[test]
fn a_wheel_swings_in_a_bowl_with_the_period_of_rolling() {
    use multibody::Expr as S;
    let rho = 3.0;
    let road = S::var("x") * S::var("x") / (2.0 * rho);
    let amplitude = 0.01;
    let mechanism = wheel_on_road(road, amplitude).assemble().unwrap();
    let expected = 2.0 * std::f64::consts::PI * ((rho - R) * (1.0 + I_AXIS / (M * R * R)) / G).sqrt();
    let s = mechanism.simulate(&tight(3.0 * expected, 0.001)).unwrap();
    let (t, x) = (s.time(), column(&s, "wheel.x"));
    // Upward zero crossings of x, interpolated.
    let crossings: Vec<f64> = (1..x.len())
        .filter(|&k| x[k - 1] < 0.0 && x[k] >= 0.0)
        .map(|k| t[k - 1] + (t[k] - t[k - 1]) * (-x[k - 1]) / (x[k] - x[k - 1]))
        .collect();
    assert!(crossings.len() >= 2, "the wheel swings: {crossings:?}");
    let period = crossings[1] - crossings[0];
    // The small-swing formula's own error is of order (amplitude / rho)^2 ~
    // 1e-5 (the bowl is a parabola, not a circle, and the swing is not
    // infinitely small); the creep's damping shifts the period by less.
    // 1e-4 relative covers both.
    let error = (period - expected).abs() / expected;
    println!("bowl: period {period:.6} s vs {expected:.6} s, {error:.1e} relative = {:.3} of 1e-4", error / 1e-4);
    assert!(error < 1e-4);
}

/// A road is only for wheels that roll on one.
#[test]
fn a_road_for_a_body_is_refused() {
    let mut model = Model::new("no_road");
    model.add("world", "World");
    model.add("body", "Body").surface(multibody::Expr::Var("x".into()));
    let message = match model.assemble() {
        Ok(_) => panic!("a Body takes no road"),
        Err(e) => e.to_string(),
    };
    println!("{message}");
    assert!(message.contains("body") && message.contains("surface"), "{message}");
}

/// Multibody.jl's WheelInWorld (the library's tests.WheelInWorld): a
/// RollingWheel (radius 0.3, m 2, I_axis 0.06, I_long 0.12) started upright
/// at (x, z) = (0.2, 0.2), spinning at -5 rad/s about its axis and falling
/// over at -1 rad/s, rolls under gravity for 4 s: the library's start,
/// der_angles = [0, -5, -1] of its (and our default) sequence [2, 3, 1], the
/// angular velocity (-1, 0, -5) in frame_a. Its spin angle passes the
/// sequence's singular values (+-pi/2, ...) a dozen times on the way.
///
/// Two references: `tests/independent/rolling_disk.py`, a separate Newton-Euler
/// integration (the contact force an unknown beside the accelerations, the
/// contact point's acceleration zero; fixed-step RK4 converged to 4e-10 m),
/// gives x(4) = 0.16300348297, z(4) = -2.23761434163; Multibody.jl's test
/// asserts x(4) = 0.162547, z(4) = -2.23778 within 1e-3.
#[test]
fn the_library_s_wheel_in_world() {
    let mut model = Model::new("WheelInWorld");
    model.add("world", "World");
    model
        .add("wheel", "RollingWheel")
        .set("radius", 0.3)
        .set("m", 2.0)
        .set("I_axis", 0.06)
        .set("I_long", 0.12)
        .initial("x", 0.2)
        .initial("z", 0.2)
        .initial("angles", vec![0.0; 3])
        .initial("der_angles", vec![0.0, -5.0, -1.0]);
    let s = model.assemble().unwrap().simulate(&tight(4.0, 0.01)).unwrap();
    let (x, z) = (s.last("wheel.x").unwrap(), s.last("wheel.z").unwrap());
    let newton_euler = (0.163_003_482_97, -2.237_614_341_63);
    let library = (0.162547, -2.23778);
    let ne = (x - newton_euler.0).abs().max((z - newton_euler.1).abs());
    let lib = (x - library.0).abs().max((z - library.1).abs());
    // 1e-7 m: both integrations converged far below it (ours at 1e-11, the
    // script's steps to 4e-10), leaving room for errors growing along 4 s of
    // leaning motion. The library's own tolerance is 1e-3.
    println!(
        "WheelInWorld at t = 4: x {x:.9}, z {z:.9}; Newton-Euler check {ne:.1e} m = {:.3} of 1e-7; Multibody.jl {lib:.1e} m = {:.3} of its 1e-3",
        ne / 1e-7,
        lib / 1e-3
    );
    assert!(ne < 1e-7);
    assert!(lib < 1e-3);
}

/// A rolling wheel (no slip at all) on the road y = x, as Multibody.jl's
/// WheelInWorldWithSurface: its centre stays R sqrt(2) above the road's
/// line (the contact moved along the 45 degree normal), it accelerates down
/// the slope at `g sin(45) / (1 + I_axis / (m R^2))`, and its energy holds.
#[test]
fn a_rolling_wheel_rolls_down_a_road() {
    let mut model = rolling_wheel([0.0; 3], [0.0; 3]);
    model.component_mut("wheel").unwrap().surface(multibody::Expr::Var("x".into()));
    let s = model.assemble().unwrap().simulate(&tight(2.0, 0.5)).unwrap();
    let (x, y, vx) = (column(&s, "wheel.x"), column(&s, "wheel.y"), column(&s, "wheel.v_0[1]"));
    let angle = std::f64::consts::FRAC_PI_4;
    let expected = G * angle.sin() / (1.0 + I_AXIS / (M * R * R));
    let n = x.len() - 1;
    // Down the slope is towards -x; speed along it from the x component.
    let accel = -(vx[n] - vx[0]) / angle.cos() / s.time()[n];
    let height = (0..=n).fold(0.0f64, |a, k| a.max((y[k] - x[k] - R * 2f64.sqrt()).abs()));
    let e0 = energy(&s, 0);
    let drift = (0..=n).fold(0.0f64, |a, k| a.max((energy(&s, k) - e0).abs() / e0.abs()));
    // Rolling from rest, the acceleration is constant from the start; the
    // integrator runs at 1e-11 (1e-6 relative is far above it), the contact
    // row is held to the projection's 1e-12 (1e-9 m) and energy as on flat
    // ground (1e-8).
    println!(
        "rolling down y = x: acceleration {accel:.9} vs {expected:.9} m/s2 ({:.1e} of 1e-6 relative), height error {height:.1e} m (of 1e-9), energy drift {drift:.1e} (of 1e-8)",
        (accel - expected).abs() / expected / 1e-6
    );
    assert!((accel - expected).abs() < 1e-6 * expected);
    assert!(height < 1e-9 && drift < 1e-8);
}
