"""Model.linearize: the linear model of examples/controlled_pendulum.dyad at
a steady state, fed to python-control, against the closed form and against
the nonlinear model's response to a small torque step.

python-control is installed by scripts/test-python.sh; without it the test
that needs it is skipped with a message."""

from pathlib import Path

import numpy as np
import pytest

import multibody

ROOT = Path(__file__).resolve().parents[3]
PENDULUM = ROOT / "examples" / "controlled_pendulum.dyad"

# (m r^2 + I_33) phi'' = -m g r cos(phi) + tau: held at rest by a torque tau0
# at cos(phi0) = tau0 / (m g r), it oscillates at w^2 = m g r sin(-phi0) / J.
M, R, I33, G = 1.0, 0.5, 0.02, 9.80665
J = M * R * R + I33
TAU0 = 1.5


def steady_simulator():
    sim = multibody.Simulator(PENDULUM)
    sim.set_input("tau", TAU0)
    found = sim.steady_state()
    assert found["residual"] < 1e-12, found
    return sim


def test_linear_model_at_a_steady_state_has_the_closed_form():
    sim = steady_simulator()
    phi0 = -np.arccos(TAU0 / (M * G * R))
    assert abs(sim.get("rev.phi") - phi0) < 1e-12
    lin = sim.linearize(outputs=["angle", "speed"])
    assert lin.states == ["rev.phi", "rev.w"]
    assert lin.inputs == ["tau"] and lin.outputs == ["angle", "speed"]
    a = np.array([[0.0, 1.0], [M * G * R * np.sin(phi0) / J, 0.0]])
    b = np.array([[0.0], [1.0 / J]])
    assert np.max(np.abs(lin.A - a)) < 1e-9 * np.max(np.abs(a))
    assert np.max(np.abs(lin.B - b)) < 1e-9 * np.max(np.abs(b))
    np.testing.assert_allclose(lin.C, np.eye(2), atol=1e-10)
    w = np.sqrt(-a[1, 0])
    np.testing.assert_allclose(sorted(lin.poles().imag), [-w, w], rtol=1e-9)


def test_python_control_step_response_matches_the_nonlinear_model_to_second_order():
    control = pytest.importorskip("control", reason="python-control is not installed (scripts/test-python.sh installs it)")
    lin = steady_simulator().linearize(outputs=["angle"])
    sys = lin.to_control()
    assert list(sys.input_labels) == ["tau"] and list(sys.output_labels) == ["angle"]
    assert list(sys.state_labels) == ["rev.phi", "rev.w"]
    w = np.sqrt(M * G * R * np.sin(np.arccos(TAU0 / (M * G * R))) / J)
    np.testing.assert_allclose(sorted(np.asarray(control.poles(sys)).imag), [-w, w], rtol=1e-9)

    times = np.linspace(0.0, 2.0, 201)
    errors = []
    for step in (1e-3, 2e-3):
        # The nonlinear model from the steady state, its torque stepped.
        sim = steady_simulator()
        phi0 = sim.get("angle")
        t0 = sim.time
        sim.set_input("tau", TAU0 + step)
        nonlinear = []
        for t in times:
            sim.step_until(t0 + t)
            nonlinear.append(sim.get("angle") - phi0)
        response = control.forced_response(sys, T=times, U=np.full(times.shape, step))
        linear = np.asarray(response.outputs).ravel()
        errors.append(np.max(np.abs(np.array(nonlinear) - linear)))
        # The response itself is of the order of the step.
        assert np.max(np.abs(linear)) > 0.1 * step / (J * w * w)
    # The difference is second order in the step: doubling it quadruples the error.
    ratio = errors[1] / errors[0]
    print(f"linear vs nonlinear step response: errors {errors[0]:.3e}, {errors[1]:.3e} (ratio {ratio:.2f}, 4 expected)")
    assert 3.5 < ratio < 4.5, errors
    assert errors[0] < 1e-2 * 1e-3


def test_bad_names_and_no_steady_state_say_why():
    model = multibody.load(PENDULUM)
    with pytest.raises(ValueError, match="did you mean `tau`"):
        model.linearize(inputs=["tao"])
    with pytest.raises(ValueError, match="no variable `angel`"):
        model.linearize(outputs=["angel"])
    # A torque larger than the weight's largest moment holds the pendulum nowhere.
    sim = multibody.Simulator(PENDULUM)
    sim.set_input("tau", 10.0)
    with pytest.raises(multibody.LinearizationError, match="no steady state") as e:
        sim.steady_state()
    assert "der(rev.w)" in str(e.value)
