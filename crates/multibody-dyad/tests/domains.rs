//! Domains beyond the mechanics: connectors declared in Dyad (the
//! library's `Pin` and `HeatPort`, and a user's own), the connection
//! equations they imply, and the electrical and thermal components written
//! on them. Each model is checked against its linear closed form, and
//! prints its worst error as a fraction of the tolerance.

mod common;

use common::{error_of, report, simulate, worst_against};
use multibody_reference::expm2;

/// A capacitor charged through a resistor from a constant voltage:
/// `v = V (1 - exp(-t / (R C)))`.
#[test]
fn an_rc_circuit_charges_as_its_closed_form() {
    let solution = simulate(
        r#"
example component RC
  source = ElectricalComponents.VoltageSource()
  level = BlockComponents.Constant(k = 10)
  resistor = ElectricalComponents.Resistor(R = 100)
  capacitor = ElectricalComponents.Capacitor(C = 1e-3, v(initial = 0))
  ground = ElectricalComponents.Ground()
relations
  connect(level.y, source.V)
  connect(source.p, resistor.p)
  connect(resistor.n, capacitor.p)
  connect(capacitor.n, source.n, ground.g)
end

analysis RCRun
  extends TransientAnalysis(stop = 0.5, saveat = 0.005, abstol = 1e-10, reltol = 1e-10)
  model = RC()
end
"#,
    );
    let tau = 100.0 * 1e-3;
    let worst = worst_against(&solution, "capacitor.v", |t| 10.0 * (1.0 - (-t / tau).exp()));
    report("RC circuit, capacitor voltage", worst, 1e-6);
    let worst = worst_against(&solution, "resistor.i", |t| 10.0 / 100.0 * (-t / tau).exp());
    report("RC circuit, current", worst, 1e-8);
    // The currents of a node balance: the loop's current leaves the
    // capacitor at n and enters the source there; the ground takes none.
    let worst = worst_against(&solution, "capacitor.n.i", |t| -10.0 / 100.0 * (-t / tau).exp());
    report("RC circuit, current into the capacitor's pin n", worst, 1e-8);
    let worst = worst_against(&solution, "ground.g.i", |_| 0.0);
    report("RC circuit, current into the ground", worst, 1e-12);
}

/// A series RLC circuit switched onto a constant voltage:
/// `i = V / (L w_d) exp(-a t) sin(w_d t)`, `a = R / 2L`.
#[test]
fn a_series_rlc_circuit_rings_as_its_closed_form() {
    let solution = simulate(
        r#"
example component RLC
  source = ElectricalComponents.VoltageSource()
  level = BlockComponents.Constant(k = 5)
  resistor = ElectricalComponents.Resistor(R = 2)
  inductor = ElectricalComponents.Inductor(L = 0.1, i(initial = 0))
  capacitor = ElectricalComponents.Capacitor(C = 0.01, v(initial = 0))
  ground = ElectricalComponents.Ground()
relations
  connect(level.y, source.V)
  connect(source.p, resistor.p)
  connect(resistor.n, inductor.p)
  connect(inductor.n, capacitor.p)
  connect(capacitor.n, source.n, ground.g)
end

analysis RLCRun
  extends TransientAnalysis(stop = 1, saveat = 0.002, abstol = 1e-10, reltol = 1e-10)
  model = RLC()
end
"#,
    );
    let (r, l, c, v): (f64, f64, f64, f64) = (2.0, 0.1, 0.01, 5.0);
    let a = r / (2.0 * l);
    let wd = (1.0 / (l * c) - a * a).sqrt();
    let worst = worst_against(&solution, "inductor.i", |t| v / (l * wd) * (-a * t).exp() * (wd * t).sin());
    report("series RLC, current", worst, 1e-6);
    let worst = worst_against(&solution, "capacitor.v", |t| {
        v * (1.0 - (-a * t).exp() * ((wd * t).cos() + a / wd * (wd * t).sin()))
    });
    report("series RLC, capacitor voltage", worst, 1e-6);
}

/// A DC motor (resistance, inductance, EMF) turns a revolute joint through
/// its axis, its housing on the joint's support; the body sits on the
/// axis, so gravity gives no torque. `L di/dt = V - R i - k w` and
/// `J dw/dt = k i` is linear, with the closed form `x = x_ss + exp(A t)
/// (x_0 - x_ss)`.
#[test]
fn a_dc_motor_turns_a_revolute_as_its_linear_closed_form() {
    let solution = simulate(
        r#"
example component MotorOnJoint
  world = MultibodyComponents.World()
  joint = MultibodyComponents.Revolute(n = [0, 0, 1], phi(initial = 0), w(initial = 0))
  rotor = MultibodyComponents.Body(m = 2, r_cm = [0, 0, 0], I_11 = 0.1, I_22 = 0.1, I_33 = 0.05)
  source = ElectricalComponents.VoltageSource()
  level = BlockComponents.Constant(k = 12)
  winding = ElectricalComponents.Resistor(R = 1.5)
  coil = ElectricalComponents.Inductor(L = 0.02, i(initial = 0))
  emf = ElectricalComponents.RotationalEMF(k = 0.4)
  ground = ElectricalComponents.Ground()
relations
  connect(world.frame_b, joint.frame_a)
  connect(joint.frame_b, rotor.frame_a)
  connect(level.y, source.V)
  connect(source.p, winding.p)
  connect(winding.n, coil.p)
  connect(coil.n, emf.p)
  connect(emf.n, source.n, ground.g)
  connect(emf.rotor, joint.axis)
  connect(emf.housing, joint.support)
end

analysis MotorRun
  extends TransientAnalysis(stop = 1, saveat = 0.005, abstol = 1e-11, reltol = 1e-11)
  model = MotorOnJoint()
end
"#,
    );
    let (r, l, k, j, v) = (1.5, 0.02, 0.4, 0.05, 12.0);
    // x = [i, w]: dx/dt = A x + b.
    let a = [[-r / l, -k / l], [k / j, 0.0]];
    // Steady state: no current, w = V / k.
    let steady = [0.0, v / k];
    let closed = |t: f64| {
        let e = expm2(a, t);
        let d = [-steady[0], -steady[1]];
        [steady[0] + e[0][0] * d[0] + e[0][1] * d[1], steady[1] + e[1][0] * d[0] + e[1][1] * d[1]]
    };
    let worst_i = worst_against(&solution, "coil.i", |t| closed(t)[0]);
    let worst_w = worst_against(&solution, "joint.w", |t| closed(t)[1]);
    // The scale of each: the peak current is below V / R = 8 A, the speed V / k = 30 rad/s.
    report("DC motor on a revolute, current / (V / R)", worst_i / (v / r), 1e-6);
    report("DC motor on a revolute, speed / (V / k)", worst_w / (v / k), 1e-6);
    // The angle: the integral of the speed. With A invertible, the
    // integral of exp(A s) from 0 to t is A^-1 (exp(A t) - I).
    let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    let inv = [[a[1][1] / det, -a[0][1] / det], [-a[1][0] / det, a[0][0] / det]];
    let angle = |t: f64| {
        let e = expm2(a, t);
        let m = [[e[0][0] - 1.0, e[0][1]], [e[1][0], e[1][1] - 1.0]];
        let d = [-steady[0], -steady[1]];
        let md = [m[0][0] * d[0] + m[0][1] * d[1], m[1][0] * d[0] + m[1][1] * d[1]];
        steady[1] * t + inv[1][0] * md[0] + inv[1][1] * md[1]
    };
    let worst_phi = worst_against(&solution, "joint.phi", angle);
    report("DC motor on a revolute, angle / 30 rad", worst_phi / 30.0, 1e-6);
    // The EMF's torque on the rotor is k i.
    let tau = solution.get("emf.tau").unwrap();
    let i = solution.get("coil.i").unwrap();
    let worst = tau.iter().zip(i).map(|(tau, i)| (tau + k * i).abs()).fold(0.0, f64::max);
    report("RotationalEMF torque = -k i", worst, 1e-9);
}

/// A heat network on a connector the model declares itself: two bodies
/// exchange heat through a conductance. Their difference decays at the
/// rate `G (1/C1 + 1/C2)` and their heat content stays.
#[test]
fn a_connector_the_user_declares_carries_a_heat_network() {
    let solution = simulate(
        r#"
"A thermal port of this model's own."
connector Warmth
  potential temperature::Real
  flow heat::Real
end

component Lump
  port = Warmth()
  parameter C::Real
  variable T::Real
relations
  T = port.temperature
  C * der(T) = port.heat
end

component Bridge
  a = Warmth()
  b = Warmth()
  parameter G::Real
relations
  a.heat = G * (a.temperature - b.temperature)
  a.heat + b.heat = 0
end

example component TwoBodies
  hot = Lump(C = 2, T(initial = 400))
  cold = Lump(C = 6, T(initial = 300))
  link = Bridge(G = 3)
relations
  connect(hot.port, link.a)
  connect(link.b, cold.port)
end

analysis TwoBodiesRun
  extends TransientAnalysis(stop = 3, saveat = 0.01, abstol = 1e-10, reltol = 1e-10)
  model = TwoBodies()
end
"#,
    );
    let rate = 3.0 * (1.0 / 2.0 + 1.0 / 6.0);
    let mean = (2.0 * 400.0 + 6.0 * 300.0) / 8.0;
    // T_hot - mean = (400 - mean) exp(-rate t).
    let worst = worst_against(&solution, "hot.T", |t| mean + (400.0 - mean) * (-rate * t).exp());
    report("user connector, hot body", worst, 1e-6);
    let worst = worst_against(&solution, "cold.T", |t| mean + (300.0 - mean) * (-rate * t).exp());
    report("user connector, cold body", worst, 1e-6);
}

/// The library's thermal parts: a body cooling through a conductor to a
/// fixed temperature, `T = T_s + (T_0 - T_s) exp(-G t / C)`, and a second
/// body heated at a prescribed rate, `T = T_0 + Q t / C`.
#[test]
fn a_body_cools_through_a_thermal_conductor_as_its_closed_form() {
    let solution = simulate(
        r#"
example component Cooling
  body = ThermalComponents.HeatCapacitor(C = 50, T0 = 350)
  wall = ThermalComponents.ThermalConductor(G = 10)
  room = ThermalComponents.FixedTemperature(T = 290)
  heated = ThermalComponents.HeatCapacitor(C = 20, T0 = 300)
  heater = ThermalComponents.PrescribedHeatFlow()
  power = BlockComponents.Constant(k = 40)
relations
  connect(body.port, wall.port_a)
  connect(wall.port_b, room.port)
  connect(power.y, heater.Q_flow)
  connect(heater.port, heated.port)
end

analysis CoolingRun
  extends TransientAnalysis(stop = 10, saveat = 0.05, abstol = 1e-10, reltol = 1e-10)
  model = Cooling()
end
"#,
    );
    let worst = worst_against(&solution, "body.T", |t| 290.0 + 60.0 * (-10.0 * t / 50.0).exp());
    report("heat capacitor cooling to a fixed temperature", worst, 1e-6);
    let worst = worst_against(&solution, "wall.Q_flow", |t| 10.0 * 60.0 * (-10.0 * t / 50.0).exp());
    report("heat flow through the conductor", worst, 1e-6);
    let worst = worst_against(&solution, "heated.T", |t| 300.0 + 40.0 * t / 20.0);
    report("heat capacitor under a prescribed heat flow", worst, 1e-6);
}

/// A component that wraps two resistors behind its own pins and reads the
/// current through its pin `p`: the flows count from inside and outside
/// as Modelica counts them, so the reading is the current of the divider.
#[test]
fn flows_through_a_component_boundary_keep_their_sign() {
    let solution = simulate(
        r#"
component Divider
  p = Pin()
  n = Pin()
  middle = Pin()
  upper = ElectricalComponents.Resistor(R = 30)
  lower = ElectricalComponents.Resistor(R = 10)
  variable i_in::Current
relations
  connect(p, upper.p)
  connect(upper.n, lower.p, middle)
  connect(lower.n, n)
  i_in = p.i
end

example component Supply
  source = ElectricalComponents.VoltageSource()
  level = BlockComponents.Constant(k = 8)
  divider = Divider()
  meter = ElectricalComponents.VoltageSensor()
  ground = ElectricalComponents.Ground()
relations
  connect(level.y, source.V)
  connect(source.p, divider.p)
  connect(divider.n, source.n, ground.g)
  connect(divider.middle, meter.p)
  connect(meter.n, ground.g)
end

analysis SupplyRun
  extends TransientAnalysis(stop = 0.1, saveat = 0.05)
  model = Supply()
end
"#,
    );
    let worst = worst_against(&solution, "divider.i_in", |_| 8.0 / 40.0);
    report("current into a component through its own pin", worst, 1e-12);
    let worst = worst_against(&solution, "meter.v", |_| 8.0 * 10.0 / 40.0);
    report("voltage sensor at the divider's middle", worst, 1e-12);
    let worst = worst_against(&solution, "source.i", |_| -8.0 / 40.0);
    report("the source's current (p to n through it)", worst, 1e-12);
}

/// Connectors of different types do not connect: the message names both
/// types and points at both ends.
#[test]
fn connecting_a_pin_to_a_heat_port_names_both_types() {
    let message = error_of(
        r#"
example component Mixed
  resistor = ElectricalComponents.Resistor(R = 1)
  body = ThermalComponents.HeatCapacitor(C = 1, T0 = 300)
relations
  connect(resistor.p, body.port)
end

analysis MixedRun
  extends TransientAnalysis(stop = 1)
  model = Mixed()
end
"#,
    );
    assert!(message.contains("(Pin) cannot be connected to"), "{message}");
    assert!(message.contains("(HeatPort)"), "{message}");
    assert!(message.contains("a Pin connector") && message.contains("a HeatPort connector"), "{message}");
}

/// A pin cannot meet a mechanical connector of the engine either.
#[test]
fn connecting_a_pin_to_a_joint_axis_names_both_types() {
    let message = error_of(
        r#"
example component Wrong
  world = MultibodyComponents.World()
  joint = MultibodyComponents.Revolute()
  resistor = ElectricalComponents.Resistor(R = 1)
relations
  connect(world.frame_b, joint.frame_a)
  connect(resistor.p, joint.axis)
end

analysis WrongRun
  extends TransientAnalysis(stop = 1)
  model = Wrong()
end
"#,
    );
    assert!(message.contains("(Pin) cannot be connected to `joint.axis` (Spline)"), "{message}");
}

/// A connector with flows and no potential says what is missing.
#[test]
fn a_connector_without_a_potential_is_refused() {
    let message = error_of(
        r#"
connector OnlyFlow
  flow q::Real
end

example component M
  parameter x::Real = 1
end

analysis R
  extends TransientAnalysis(stop = 1)
  model = M()
end
"#,
    );
    assert!(message.contains("has flows but no potential"), "{message}");
}

/// A ladder of `n` stages (series resistor 1, capacitor to ground and a
/// shunt resistor 10 at each node) from a 1 V source, every capacitor
/// started at rest (`initial der(c[i].v) = 0`).
fn ladder_at_rest(n: usize) -> String {
    format!(
        r#"
example component Ladder
  source = ElectricalComponents.VoltageSource()
  level = BlockComponents.Constant(k = 1)
  ground = ElectricalComponents.Ground()
  r = [ElectricalComponents.Resistor(R = 1) for i in 1:{n}]
  shunt = [ElectricalComponents.Resistor(R = 10) for i in 1:{n}]
  c = [ElectricalComponents.Capacitor(C = 1e-3) for i in 1:{n}]
relations
  connect(level.y, source.V)
  connect(source.n, ground.g)
  connect(source.p, r[1].p)
  for i in 1:{n}
    connect(r[i].n, c[i].p, shunt[i].p)
    connect(c[i].n, shunt[i].n, ground.g)
    initial der(c[i].v) = 0
  end
  for i in 1:{m}
    connect(r[i].n, r[i + 1].p)
  end
end

analysis LadderRun
  extends TransientAnalysis(stop = 0.01, saveat = 0.005, abstol = 1e-10, reltol = 1e-10)
  model = Ladder()
end
"#,
        m = n - 1
    )
}

/// 300 capacitors started at rest: 300 initial equations over 300 free
/// start values, one sparse Newton system (each equation reads three
/// neighbouring voltages, so three evaluations give its Jacobian). At rest
/// no current flows into the capacitors: the node voltages solve the
/// resistive ladder, `(v[k-1] - v[k]) / 1 = v[k] / 10 + (v[k] - v[k+1]) / 1`,
/// which the test solves by elimination; the ladder then stays there.
#[test]
fn a_ladder_of_300_capacitors_started_at_rest_holds_the_resistive_divider() {
    let n = 300;
    let solution = simulate(&ladder_at_rest(n));
    // Tridiagonal elimination (Thomas) of the node equations.
    let (a, b, c) = (-1.0, 2.0 + 0.1, -1.0);
    let mut d = vec![0.0; n];
    d[0] = 1.0; // the source's 1 V through r[1]
    let (mut cp, mut dp) = (vec![0.0; n], vec![0.0; n]);
    let last = |k: usize| if k == n - 1 { 1.0 + 0.1 } else { b };
    cp[0] = c / last(0);
    dp[0] = d[0] / last(0);
    for k in 1..n {
        let m = last(k) - a * cp[k - 1];
        cp[k] = c / m;
        dp[k] = (d[k] - a * dp[k - 1]) / m;
    }
    let mut v = vec![0.0; n];
    v[n - 1] = dp[n - 1];
    for k in (0..n - 1).rev() {
        v[k] = dp[k] - cp[k] * v[k + 1];
    }
    let mut worst = 0.0f64;
    for (k, expected) in v.iter().enumerate() {
        let column = solution.get(&format!("c[{}].v", k + 1)).unwrap_or_else(|| panic!("no c[{}].v", k + 1));
        worst = column.iter().fold(worst, |w, x| w.max((x - expected).abs()));
    }
    report("300-stage ladder started at rest, node voltages", worst, 1e-9);
    assert!(v[0] > 0.5 && v[n - 1] > 0.0, "the divider should carry voltage down the ladder");
}

/// An inverting amplifier on an IdealOpAmp: a SineVoltage (1 V, 2 Hz)
/// through 1 kOhm into the inverting input, 3 kOhm from there to the
/// output, a 2 kOhm load. The output is `-3 sin(4 pi t)` (the gain
/// `-R2 / R1`), which a PotentialSensor reads, and a PowerSensor reads the
/// load's `v^2 / R`.
#[test]
fn an_inverting_amplifier_gains_minus_r2_over_r1() {
    let solution = simulate(
        r#"
example component Inverting
  source = ElectricalComponents.SineVoltage(V = 1, f = 2)
  r1 = ElectricalComponents.Resistor(R = 1000)
  r2 = ElectricalComponents.Resistor(R = 3000)
  load = ElectricalComponents.Resistor(R = 2000)
  amp = ElectricalComponents.IdealOpAmp()
  out = ElectricalComponents.PotentialSensor()
  meter = ElectricalComponents.PowerSensor()
  ground = ElectricalComponents.Ground()
relations
  connect(source.p, r1.p)
  connect(r1.n, r2.p, amp.n1)
  connect(r2.n, amp.p2, out.p, meter.pc, meter.pv)
  connect(meter.nc, load.p)
  connect(load.n, meter.nv, amp.p1, amp.n2, source.n, ground.g)
end

analysis InvertingRun
  extends TransientAnalysis(stop = 1, saveat = 0.01, abstol = 1e-10, reltol = 1e-10)
  model = Inverting()
end
"#,
    );
    let out = |t: f64| -3.0 * (4.0 * std::f64::consts::PI * t).sin();
    report("inverting amplifier, output voltage", worst_against(&solution, "out.phi", out), 1e-9);
    report(
        "inverting amplifier, load power",
        worst_against(&solution, "meter.power", |t| out(t).powi(2) / 2000.0),
        1e-12,
    );
    report("inverting amplifier, no input current", worst_against(&solution, "amp.i1", |_| 0.0), 1e-15);
}

/// An integrator on an IdealOpAmp3Pin: 2 V through 1 Ohm into the
/// inverting input, a 0.5 F capacitor from it to the output, which then
/// falls as `-V t / (R C) = -4 t`.
#[test]
fn an_op_amp_integrator_ramps_at_minus_v_over_rc() {
    let solution = simulate(
        r#"
example component Integrator
  source = ElectricalComponents.ConstantVoltage(V = 2)
  r = ElectricalComponents.Resistor(R = 1)
  c = ElectricalComponents.Capacitor(C = 0.5, v(initial = 0))
  amp = ElectricalComponents.IdealOpAmp3Pin()
  out = ElectricalComponents.PotentialSensor()
  ground = ElectricalComponents.Ground()
relations
  connect(source.p, r.p)
  connect(r.n, c.p, amp.in_n)
  connect(c.n, amp.out, out.p)
  connect(amp.in_p, source.n, ground.g)
end

analysis IntegratorRun
  extends TransientAnalysis(stop = 1, saveat = 0.01, abstol = 1e-10, reltol = 1e-10)
  model = Integrator()
end
"#,
    );
    report("op-amp integrator, output voltage", worst_against(&solution, "out.phi", |t| -4.0 * t), 1e-9);
}

/// A linear motor: 10 V through 2 Ohm into a TranslationalEMF (k = 5 N/A)
/// whose flange pushes a 1 kg mass: `m dv/dt = k (V - k v) / R`, so
/// `v = (V / k) (1 - exp(-k^2 t / (m R)))`.
#[test]
fn a_translational_emf_drives_a_mass_to_v_over_k() {
    let solution = simulate(
        r#"
example component LinearMotor
  source = ElectricalComponents.ConstantVoltage(V = 10)
  r = ElectricalComponents.Resistor(R = 2)
  emf = ElectricalComponents.TranslationalEMF(k = 5)
  ground = ElectricalComponents.Ground()
  slider = TranslationalComponents.Mass(m = 1, s(initial = 0), v(initial = 0))
  rail = TranslationalComponents.Fixed()
relations
  connect(source.p, r.p)
  connect(r.n, emf.p)
  connect(emf.n, source.n, ground.g)
  connect(emf.flange, slider.flange_a)
  connect(emf.support, rail.flange)
end

analysis LinearMotorRun
  extends TransientAnalysis(stop = 1, saveat = 0.01, abstol = 1e-10, reltol = 1e-10)
  model = LinearMotor()
end
"#,
    );
    let v = |t: f64| 2.0 * (1.0 - (-12.5 * t).exp());
    report("linear motor, slider speed", worst_against(&solution, "slider.v", v), 1e-6);
    report("linear motor, current", worst_against(&solution, "r.i", |t| (10.0 - 5.0 * v(t)) / 2.0), 1e-6);
}

/// A half-wave rectifier: a SineVoltage (10 V, 1 Hz) through an IdealDiode
/// into 10 Ohm. Conducting, `i = Vs / (R + Ron)`; blocking,
/// `i = Goff Vs / (1 + R Goff)`: both branches exact, switching (an event)
/// where the source changes sign.
#[test]
fn an_ideal_diode_rectifies_half_waves() {
    let solution = simulate(
        r#"
example component Rectifier
  source = ElectricalComponents.SineVoltage(V = 10, f = 1)
  diode = ElectricalComponents.IdealDiode()
  load = ElectricalComponents.Resistor(R = 10)
  ground = ElectricalComponents.Ground()
relations
  connect(source.p, diode.p)
  connect(diode.n, load.p)
  connect(load.n, source.n, ground.g)
end

analysis RectifierRun
  extends TransientAnalysis(stop = 2, saveat = 0.01, abstol = 1e-10, reltol = 1e-10)
  model = Rectifier()
end
"#,
    );
    let (r, ron, goff) = (10.0, 1e-5, 1e-5);
    let current = |t: f64| {
        let vs = 10.0 * (2.0 * std::f64::consts::PI * t).sin();
        if vs >= 0.0 {
            vs / (r + ron)
        } else {
            goff * vs / (1.0 + r * goff)
        }
    };
    report("half-wave rectifier, load current", worst_against(&solution, "load.i", current), 1e-9);
    let blocked = solution.get("load.i").unwrap().iter().fold(f64::INFINITY, |m, &i| m.min(i));
    assert!(blocked > -1e-4 && blocked < 0.0, "blocking, the current is about -Goff Vs: {blocked}");
}

/// Switches in series with 10 Ohm across 10 V: the closing switch closes
/// and the opening switch opens at t = 0.5 (their `control` set by
/// equations of time). Closed, `i = V / (R + Ron)`; open,
/// `i = Goff V / (1 + R Goff)`.
#[test]
fn ideal_switches_conduct_as_their_control_says() {
    let solution = simulate(
        r#"
example component Switches
  source = ElectricalComponents.ConstantVoltage(V = 10)
  closing = ElectricalComponents.IdealClosingSwitch()
  opening = ElectricalComponents.IdealOpeningSwitch()
  r1 = ElectricalComponents.Resistor(R = 10)
  r2 = ElectricalComponents.Resistor(R = 10)
  ground = ElectricalComponents.Ground()
relations
  closing.control = time >= 0.5
  opening.control = time >= 0.5
  connect(source.p, closing.p, opening.p)
  connect(closing.n, r1.p)
  connect(opening.n, r2.p)
  connect(r1.n, r2.n, source.n, ground.g)
end

analysis SwitchesRun
  extends TransientAnalysis(stop = 1, saveat = 0.01, abstol = 1e-10, reltol = 1e-10)
  model = Switches()
end
"#,
    );
    let (closed, open) = (10.0 / (10.0 + 1e-5), 1e-5 * 10.0 / (1.0 + 10.0 * 1e-5));
    // The sample at the event's instant is the left limit (before it).
    let closing = |t: f64| if t > 0.5 { closed } else { open };
    let opening = |t: f64| if t > 0.5 { open } else { closed };
    report("closing switch, current", worst_against(&solution, "r1.i", closing), 1e-9);
    report("opening switch, current", worst_against(&solution, "r2.i", opening), 1e-9);
}

/// A 1 mF capacitor started at 10 V discharges through a Conductor of
/// 0.01 S: `v = 10 exp(-t G / C)`.
#[test]
fn a_capacitor_discharges_through_a_conductor() {
    let solution = simulate(
        r#"
example component Discharge
  c = ElectricalComponents.Capacitor(C = 1e-3, v(initial = 10))
  g = ElectricalComponents.Conductor(G = 0.01)
  ground = ElectricalComponents.Ground()
relations
  connect(c.p, g.p)
  connect(c.n, g.n, ground.g)
end

analysis DischargeRun
  extends TransientAnalysis(stop = 0.5, saveat = 0.005, abstol = 1e-10, reltol = 1e-10)
  model = Discharge()
end
"#,
    );
    report(
        "conductor discharge, capacitor voltage",
        worst_against(&solution, "c.v", |t| 10.0 * (-10.0 * t).exp()),
        1e-6,
    );
}
