//! Compliant contact against closed forms: a mass between two ElastoGap
//! walls and an inertia in an ElastoBacklash fly freely across the gap and
//! bounce off the springs for half a period of sqrt(c/m); without damping
//! the energy is conserved and every contact begins and ends at the time
//! the closed form gives (events, not stepped over). With damping the
//! contact force starts from zero and never pulls.

use multibody::{Model, SimulationOptions, Simulator};
use std::f64::consts::PI;

/// The integration tolerance; the errors below grow with it, by a contact's
/// worth of phase per bounce.
const TOL: f64 = 1e-10;

fn options(stop: f64) -> SimulationOptions {
    SimulationOptions { stop, abstol: TOL, reltol: TOL, saveat: 0.005, ..Default::default() }
}

/// Position and speed of a body starting at 0 with speed `v0 > 0` between
/// contacts at `+-h`, where a spring of natural frequency `w` pushes it
/// back (no damping); and the times contact begins and ends.
fn bounce(h: f64, v0: f64, w: f64, t: f64) -> (f64, f64) {
    let (fly, press) = (2.0 * h / v0, PI / w);
    let period = 2.0 * (fly + press);
    let mut t = (t + h / v0).rem_euclid(period); // from the left contact's end
                                                 // Right-going flight, right contact, left-going flight, left contact.
    if t < fly {
        return (-h + v0 * t, v0);
    }
    t -= fly;
    if t < press {
        return (h + v0 / w * (w * t).sin(), v0 * (w * t).cos());
    }
    t -= press;
    if t < fly {
        return (h - v0 * t, -v0);
    }
    t -= fly;
    (-h - v0 / w * (w * t).sin(), -v0 * (w * t).cos())
}

/// The times contacts begin and end over `[0, stop]`.
fn contact_times(h: f64, v0: f64, w: f64, stop: f64) -> Vec<f64> {
    let (fly, press) = (2.0 * h / v0, PI / w);
    let mut times = vec![h / v0];
    while *times.last().unwrap() < stop {
        let last = *times.last().unwrap();
        times.push(last + if times.len() % 2 == 1 { press } else { fly });
    }
    times.pop();
    times
}

/// Steps to each expected event and compares the time it happened.
fn event_errors(sim: &mut Simulator, times: &[f64]) -> f64 {
    let mut worst: f64 = 0.0;
    for &t in times {
        sim.step_until(t + 1e-3).unwrap();
        let (t_event, _) = sim.last_event().expect("an event");
        worst = worst.max((t_event - t).abs());
    }
    worst
}

/// A mass `m` at 0 moving at `v0` between walls at -1 and 1, each an
/// ElastoGap of stiffness `c` and damping `d`.
fn walls(m: f64, v0: f64, c: f64, d: f64) -> Model {
    let mut model = Model::new("walls");
    model.add("mass", "TranslationalComponents.Mass").set("m", m).initial("s", 0.0).initial("v", v0);
    model.add("left_wall", "TranslationalComponents.Fixed").set("s0", -1.0);
    model.add("right_wall", "TranslationalComponents.Fixed").set("s0", 1.0);
    model.add("left", "TranslationalComponents.ElastoGap").set("c", c).set("d", d);
    model.add("right", "TranslationalComponents.ElastoGap").set("c", c).set("d", d);
    // Contact where s_rel = flange_b - flange_a < 0.
    model.connect(["left_wall.flange", "left.flange_a"]);
    model.connect(["left.flange_b", "mass.flange_a"]);
    model.connect(["mass.flange_b", "right.flange_a"]);
    model.connect(["right.flange_b", "right_wall.flange"]);
    model
}

#[test]
fn a_mass_bounces_between_elasto_gaps_for_half_periods_and_keeps_its_energy() {
    let (m, v0, c, stop): (f64, f64, f64, f64) = (2.0, 1.0, 800.0, 12.0);
    let w = (c / m).sqrt();
    let mechanism = walls(m, v0, c, 0.0).assemble().unwrap();
    let mut sim = Simulator::new(&mechanism, &options(stop)).unwrap();
    let times = contact_times(1.0, v0, w, stop);
    let event_error = event_errors(&mut sim, &times);
    sim.step_until(stop).unwrap();
    let solution = sim.solution();
    let (mut worst, mut energy): (f64, f64) = (0.0, 0.0);
    let e0 = 0.5 * m * v0 * v0;
    for (k, &t) in solution.time().iter().enumerate() {
        let g = |name: &str| solution.get(name).unwrap()[k];
        let (s, v) = bounce(1.0, v0, w, t);
        worst = worst.max((g("mass.s") - s).abs()).max((g("mass.v") - v).abs());
        let springs = (g("left.f").powi(2) + g("right.f").powi(2)) / (2.0 * c);
        energy = energy.max((0.5 * m * g("mass.v").powi(2) + springs - e0).abs() / e0);
        // Walls only push: the left pushes the mass forward, the right back.
        assert!(g("left.f") <= 0.0 && g("right.f") <= 0.0, "t = {t}");
    }
    println!(
        "{} contact events: worst time error {event_error:.2e} (tolerance 2e-7); worst state error {worst:.2e} \
         (tolerance 4e-6); worst relative energy error {energy:.2e} (tolerance 1e-7)",
        times.len()
    );
    assert_eq!(sim.event_count(), times.len(), "one event per contact change");
    // Over 6 bounces in 12 s at the tolerance 1e-10: the first contact
    // starts within 1e-15 s of its time and lasts its half period to 1e-12
    // s; each bounce leaves with a speed error of a few 1e-9 (the state at
    // an event is read on the dense output of the step across it, a lower
    // order than the step, which saw the contact's kink), so the contacts'
    // times drift by about 1e-8 s per bounce, and the speed error is
    // omega v0 times that. Shorter steps (or a tighter tolerance) shrink it.
    assert!(event_error < 2e-7);
    assert!(worst < 4e-6);
    assert!(energy < 1e-7);
}

#[test]
fn a_damped_elasto_gap_never_pulls_and_its_force_starts_from_zero() {
    // Damping near critical: d v would exceed c x at the start and the end
    // of each contact; bounded by |f_c|, the force stays pushing.
    let (m, v0, c, d) = (2.0, 1.0, 800.0, 60.0);
    let mechanism = walls(m, v0, c, d).assemble().unwrap();
    let mut sim = Simulator::new(&mechanism, &options(1.5)).unwrap();
    sim.step_until(1.5).unwrap();
    let solution = sim.solution();
    let mut largest_pull: f64 = 0.0;
    let mut bounded = true;
    for k in 0..solution.time().len() {
        let g = |name: &str| solution.get(name).unwrap()[k];
        largest_pull = largest_pull.max(g("right.f"));
        bounded &= g("right.f_d").abs() <= g("right.f_c").abs();
    }
    // The rebound is slower than the approach (energy lost), but it leaves.
    let v_after = sim.state_value("mass.v").unwrap();
    println!("largest pull {largest_pull:.2e} (must be <= 0); speed after the bounce {v_after}");
    assert!(largest_pull <= 0.0 && bounded);
    assert!(v_after < 0.0 && v_after > -v0);
    // Leaving contact, the force has returned to zero: the contact's end
    // is where the spring force vanishes, and with it the bounded damping.
    assert_eq!(sim.value("right.f").unwrap(), 0.0);
    assert_eq!(sim.value("right.contact").unwrap(), 0.0);
}

#[test]
fn an_inertia_rattles_in_an_elasto_backlash_and_without_backlash_it_is_a_spring() {
    // Half the backlash b/2 = 0.1 rad each side; w0 = 1 rad/s.
    let (j, w0, c, b, stop): (f64, f64, f64, f64, f64) = (0.5, 1.0, 50.0, 0.2, 3.0);
    let omega = (c / j).sqrt();
    let rattle = |b: f64| {
        let mut model = Model::new("rattle");
        model.add("housing", "RotationalComponents.Fixed");
        model.add("backlash", "RotationalComponents.ElastoBacklash").set("c", c).set("d", 0.0).set("b", b);
        model.add("inertia", "RotationalComponents.Inertia").set("J", j).initial("phi", 0.0).initial("w", w0);
        model.connect(["housing.spline", "backlash.spline_a"]);
        model.connect(["backlash.spline_b", "inertia.spline_a"]);
        model.assemble().unwrap()
    };
    let mechanism = rattle(b);
    let mut sim = Simulator::new(&mechanism, &options(stop)).unwrap();
    let times = contact_times(b / 2.0, w0, omega, stop);
    let event_error = event_errors(&mut sim, &times);
    sim.step_until(stop).unwrap();
    let solution = sim.solution();
    let mut worst: f64 = 0.0;
    for (k, &t) in solution.time().iter().enumerate() {
        let (phi, w) = bounce(b / 2.0, w0, omega, t);
        worst = worst.max((solution.get("inertia.phi").unwrap()[k] - phi).abs());
        worst = worst.max((solution.get("inertia.w").unwrap()[k] - w).abs());
    }
    println!(
        "backlash: {} contact events, worst time error {event_error:.2e} (tolerance 5e-8); worst state error \
         {worst:.2e} (tolerance 5e-7)",
        times.len()
    );
    // As for the gap: each bounce adds a few 1e-9 s of phase.
    assert!(event_error < 5e-8 && worst < 5e-7);

    // b = 0: a spring, phi = w0 / omega sin(omega t), and no events.
    let mechanism = rattle(0.0);
    let mut sim = Simulator::new(&mechanism, &options(stop)).unwrap();
    sim.step_until(stop).unwrap();
    let error = (sim.state_value("inertia.phi").unwrap() - w0 / omega * (omega * stop).sin()).abs();
    println!("without backlash: angle error {error:.2e} (tolerance 1e-8)");
    assert!(error < 1e-8);
    assert_eq!(sim.event_count(), 0);
}
