"""multibody.Simulator: a model stepped from Python while Python sets its
inputs, against the same sampled loop integrated independently with scipy.

Run by scripts/test-python.sh (which installs scipy in its environment)."""

from pathlib import Path

import numpy as np
import pytest

import multibody

ROOT = Path(__file__).resolve().parents[3]
PENDULUM = ROOT / "examples" / "controlled_pendulum.dyad"

# The pendulum of examples/controlled_pendulum.dyad: (m r^2 + I_33) phi'' = -m g r cos(phi) + tau.
M, R, I33, G = 1.0, 0.5, 0.02, 9.80665
J = M * R * R + I33
# The PD law, sampled every DT with its torque held in between (a zero-order hold).
KP, KD, SETPOINT, DT, STOP = 20.0, 2.0, 1.0, 1e-3, 5.0


def pd(angle, speed):
    return KP * (SETPOINT - angle) - KD * speed


def scipy_loop(steps):
    """The sampled loop integrated by scipy: the pendulum's own equation of
    motion between samples, the torque held."""
    from scipy.integrate import solve_ivp

    y = np.zeros(2)
    out = [y.copy()]
    for k in range(steps):
        tau = pd(y[0], y[1])

        def f(t, y):
            return [y[1], (-M * G * R * np.cos(y[0]) + tau) / J]

        sol = solve_ivp(f, (k * DT, (k + 1) * DT), y, method="DOP853", rtol=1e-12, atol=1e-12)
        assert sol.success, sol.message
        y = sol.y[:, -1]
        out.append(y.copy())
    return np.array(out)


def test_a_pd_law_in_python_closes_the_loop_as_scipy_integrates_it():
    sim = multibody.Simulator(PENDULUM, stop=STOP, saveat=DT, reltol=1e-10, abstol=1e-10)
    assert sim.inputs == {"tau": 0.0}
    assert set(sim.outputs) == {"angle", "speed"}
    steps = round(STOP / DT)
    ours = [sim.state.copy()]
    for k in range(steps):
        out = sim.outputs
        sim.set_input("tau", pd(out["angle"], out["speed"]))
        sim.step_until((k + 1) * DT)
        ours.append(sim.state.copy())
    assert sim.time == STOP
    assert sim.state_names == ["rev.phi", "rev.w"]
    ours = np.array(ours)
    theirs = scipy_loop(steps)
    worst = np.max(np.abs(ours - theirs))
    print("\nPD loop every 1 ms for 5 s, 5000 step_until calls against scipy DOP853 (1e-12):")
    print(f"  worst difference in (phi, w): {worst:.3e} = {worst / 1e-8:.2e} of the tolerance 1e-8")
    assert worst < 1e-8
    # The loop settles at the setpoint; the recorded samples are the states reached.
    assert abs(ours[-1, 0] - SETPOINT) < 0.2
    result = sim.result()
    assert len(result) == steps + 1
    assert np.array_equal(result["rev.phi"], ours[:, 0])
    assert np.allclose(sim.result("tau")["tau"][1:], [pd(a, w) for a, w in ours[:-1]], rtol=0, atol=1e-12)


def test_inputs_outputs_state_and_reset():
    model = multibody.load(PENDULUM)
    sim = model.simulator(stop=1.0, saveat=0.01)
    sim.set_input("tau", 2.0)
    assert sim.inputs == {"tau": 2.0}
    sim.step_until(0.5)
    assert sim.time == 0.5
    assert sim.outputs["angle"] == pytest.approx(sim.get("rev.phi"), abs=1e-15)
    assert sim.get("tau") == 2.0
    # Set the state, by array and by name.
    sim.set_state(np.array([0.1, 0.0]))
    assert list(sim.state) == [0.1, 0.0]
    sim.set_state({"rev.w": 1.5})
    assert list(sim.state) == [0.1, 1.5]
    sim.step_until(1.0)
    assert len(sim.result()) == 101
    assert sim.event_count == 0
    # Back in time: refused, and the simulator stays at 1.0 (it did nothing, silently).
    with pytest.raises(multibody.SimulationError, match="steps forward only"):
        sim.step_until(0.2)
    assert sim.time == 1.0 and len(sim.result()) == 101
    # Far ahead: what it would record cannot fit in memory, refused before
    # any step (it grew until the allocator aborted the process).
    with pytest.raises(ValueError, match=r"step_until\(1e\+?300\) would record .* samples"):
        sim.step_until(1e300)
    assert sim.time == 1.0 and len(sim.result()) == 101
    sim.reset()
    assert sim.time == 0.0 and list(sim.state) == [0.0, 0.0] and sim.inputs == {"tau": 0.0}
    assert len(sim.result()) == 0


def test_bad_names_are_value_errors_with_the_name_meant():
    sim = multibody.Simulator(PENDULUM, stop=1.0)
    with pytest.raises(ValueError, match="did you mean `tau`"):
        sim.set_input("tua", 1.0)
    with pytest.raises(ValueError, match="did you mean `rev.phi`"):
        sim.get("rev.ph")
    with pytest.raises(ValueError, match="did you mean `rev.w`"):
        sim.set_state({"rev.v": 1.0})
    with pytest.raises(ValueError, match="2 values"):
        sim.set_state([1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="no signal matches"):
        sim.result("nothing*")
    # Values of the wrong kind name what they were given for (they said
    # "must be real number, not str" or "'str' object has no attribute 'items'").
    with pytest.raises(TypeError, match="the input 'tau' must be a number, not str 'high'"):
        sim.set_input("tau", "high")
    with pytest.raises(TypeError, match="the state 'rev.phi' must be a number, not str 'x'"):
        sim.set_state({"rev.phi": "x"})
    with pytest.raises(TypeError, match="params maps names to numbers"):
        multibody.load(PENDULUM).simulate(params="x")
    with pytest.raises(TypeError, match=r"initial\['rev.w'\] must be a number"):
        multibody.load(PENDULUM).simulate(initial={"rev.w": None})
    with pytest.raises(ValueError, match="too large for a double"):
        sim.set_input("tau", 10**400)


def test_a_simulation_that_stops_raises_with_its_time_and_partial_result():
    sim = multibody.Simulator(PENDULUM, stop=1.0, saveat=0.01)
    sim.step_until(0.2)
    with pytest.raises(multibody.SimulationError) as caught:
        sim.step_until(float("nan"))
    assert caught.value.time == 0.2
    assert len(caught.value.partial) == 21
    # It stays where it was, and goes on.
    sim.step_until(0.3)
    assert sim.time == 0.3


def test_an_euler_body_steps_through_its_singularity_with_one_note():
    """A free body with Euler-angle states turning about y at 1 rad/s (the
    sequence [1, 2, 3] is singular at phi[2] = pi/2): stepped or simulated,
    it runs to its stop, its phi[2] = t on through pi/2, and its result
    carries one note naming the body."""
    model = multibody.load(ROOT / "crates" / "multibody-cli" / "tests" / "models" / "EulerSingularity.dyad")
    whole = model.simulate(signals="all")
    sim = model.simulator()
    for k in range(30):
        sim.step_until(0.1 * (k + 1))
    stepped = sim.result("all")
    for result in (whole, stepped):
        assert result.time[-1] == pytest.approx(3.0)
        assert np.abs(result["body.phi[2]"] - result.time).max() < 1e-9
        notes = [w for w in result.warnings if "singular" in w]
        assert len(notes) == 1 and "`body`" in notes[0], result.warnings


def test_ctrl_c_stops_step_until_and_the_simulator_goes_on(interruptible):
    """Ctrl-C during step_until() (the GIL released) stops it after its
    current step with KeyboardInterrupt, the time reached and the states
    recorded attached; the simulator stays there and steps on."""
    import os
    import signal
    import threading
    import time

    sim = multibody.load(ROOT / "examples" / "double_pendulum.dyad").simulator(saveat=1.0)
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    started = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt) as info:
            sim.step_until(1e6)
    finally:
        timer.cancel()
    assert time.monotonic() - started < 3.0
    e = info.value
    assert 0 < e.time < 1e6 and sim.time == e.time
    assert "interrupted at t = " in str(e)
    assert len(e.partial.time) > 1 and e.partial.time[-1] <= e.time
    sim.step_until(e.time + 1.0)
    assert sim.time == e.time + 1.0


def test_a_simulator_used_by_two_threads_says_so(interruptible):
    """A second thread that steps (or reads) a Simulator while another
    thread's step_until runs (the GIL released) gets a RuntimeError that
    says what to do, not pyo3's "Already borrowed"; the first run goes on.
    The main thread is stopped by Ctrl-C once the second has tried."""
    import os
    import signal
    import threading
    import time

    sim = multibody.load(ROOT / "examples" / "double_pendulum.dyad").simulator(saveat=1.0)
    refused = []

    def second():
        deadline = time.monotonic() + 20.0
        try:
            while time.monotonic() < deadline:
                try:
                    sim.time  # works until the main thread's step holds it
                except RuntimeError as e:
                    refused.append(e)
                    break
                time.sleep(0.001)
            if refused:
                try:
                    sim.step_until(1.0)
                except RuntimeError as e:
                    refused.append(e)
        finally:
            os.kill(os.getpid(), signal.SIGINT)

    helper = threading.Thread(target=second)
    helper.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            sim.step_until(1e6)
    finally:
        helper.join()
    assert len(refused) == 2, refused
    for e in refused:
        assert type(e) is RuntimeError
        assert "this Simulator is being used by another thread" in str(e), e
        assert "make one per thread" in str(e), e
        assert "borrowed" not in str(e)
    # The simulator is whole and goes on in one thread.
    t = sim.time
    sim.step_until(t + 0.5)
    assert sim.time == t + 0.5
