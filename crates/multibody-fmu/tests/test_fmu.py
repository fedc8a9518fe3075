"""FMUs written by `multibody fmu`, FMI 2.0 and 3.0, checked by an
independent importer: FMPy (PyPI) validates them and simulates them in
model exchange (its own CVode integrates, calling our derivatives and event
indicators) and in co-simulation (our integrator steps), against `multibody
run` of the same files. scripts/test-python.sh installs FMPy; without it
these tests skip with a message."""

import os
import shutil
import subprocess
import zipfile
from pathlib import Path

import numpy as np
import pandas
import pytest

fmpy = pytest.importorskip("fmpy", reason="FMPy (pip install fmpy) is needed to check the FMUs")
from fmpy.fmi2 import FMU2Slave  # noqa: E402
from fmpy.fmi3 import FMU3Slave  # noqa: E402
from fmpy.model_description import read_model_description  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402

ROOT = Path(__file__).resolve().parents[3]
EXAMPLES = ROOT / "examples"
COMMAND = os.environ.get("MULTIBODY_COMMAND", str(ROOT / "target" / "release" / "multibody"))


def multibody(*args, check=True):
    done = subprocess.run([COMMAND, *map(str, args)], capture_output=True, text=True)
    if check and done.returncode != 0:
        raise AssertionError(f"multibody {' '.join(map(str, args))} failed:\n{done.stderr}")
    return done


def export(tmp_path, model, name, *options, fmi="2"):
    fmu = tmp_path / f"{name}.fmu"
    multibody("fmu", model, "-o", fmu, "--fmi", fmi, *options)
    return fmu


VERSIONS = pytest.mark.parametrize("fmi", ["2", "3"])
# Where each version keeps the binary for this platform.
PLATFORM = {"2": "linux64", "3": "x86_64-linux"}


def run(tmp_path, model, name, *options):
    csv = tmp_path / f"{name}.csv"
    multibody("run", model, "-o", csv, *options)
    table = pandas.read_csv(csv)
    return {name: table[name].to_numpy() for name in table.columns}


def worst(result, reference, names, time=None):
    """The largest difference over `names`, the FMU's samples read at the
    reference's times (model exchange adds samples at events)."""
    t = reference["time"] if time is None else time
    out = 0.0
    for name in names:
        got = np.interp(t, result["time"], result[name])
        want = np.interp(t, reference["time"], reference[name])
        out = max(out, float(np.max(np.abs(got - want))))
    return out


DOUBLE_PENDULUM = EXAMPLES / "double_pendulum.dyad"
CONTROLLED = EXAMPLES / "controlled_pendulum.dyad"
BOUNCING = EXAMPLES / "equations" / "bouncing_ball.dyad"
ANGLES = ["link1.joint.phi", "link2.joint.phi", "link1.joint.w", "link2.joint.w"]


@VERSIONS
def test_the_fmus_validate_and_their_zip_is_as_fmi_says(tmp_path, fmi):
    for model, name in [(DOUBLE_PENDULUM, "dp"), (CONTROLLED, "cp"), (BOUNCING, "bb")]:
        fmu = export(tmp_path, model, name, fmi=fmi)
        assert validate_fmu(str(fmu)) == [], name
        with zipfile.ZipFile(fmu) as z:
            names = z.namelist()
            assert all("\\" not in n for n in names), names
            assert all(i.compress_type == zipfile.ZIP_DEFLATED for i in z.infolist())
            md = read_model_description(str(fmu))
            assert md.fmiVersion == f"{fmi}.0"
            identifier = md.modelExchange.modelIdentifier
            assert identifier == md.coSimulation.modelIdentifier
            assert f"binaries/{PLATFORM[fmi]}/{identifier}.so" in names
            assert "modelDescription.xml" in names and "resources/fmu.json" in names
    # Variable names are the result table's columns (plus der(x) and parameters).
    reference = run(tmp_path, DOUBLE_PENDULUM, "dp", "--stop", "0.1")
    md = read_model_description(str(tmp_path / "dp.fmu"))
    columns = set(reference)
    for v in md.modelVariables:
        if v.causality == "local":
            assert v.name in columns or v.name.startswith(("der(", "event_indicator[")), v.name
    parameters = {v.name: v.start for v in md.modelVariables if v.causality == "parameter"}
    assert parameters["link2.length"] == "0.5" or float(parameters["link2.length"]) > 0


@VERSIONS
def test_double_pendulum_in_both_modes_matches_the_command(tmp_path, fmi):
    fmu = export(tmp_path, DOUBLE_PENDULUM, "dp", fmi=fmi)
    options = ["--stop", "3", "--saveat", "0.01"]
    same = run(tmp_path, DOUBLE_PENDULUM, "same", *options, "--reltol", "1e-8", "--abstol", "1e-8")
    exact = run(tmp_path, DOUBLE_PENDULUM, "exact", *options, "--reltol", "1e-12", "--abstol", "1e-12")
    cs = fmpy.simulate_fmu(str(fmu), fmi_type="CoSimulation", stop_time=3, output_interval=0.01,
                           relative_tolerance=1e-8, output=ANGLES)
    # Co-simulation steps with the command's integrator: the same run.
    cs_error = worst(cs, same, ANGLES)
    # Model exchange is integrated by FMPy's CVode, whose global error on
    # this swinging pendulum is about 40 times its tolerance after 3 s
    # (4e-5 at 1e-8; the command's own run at 1e-8 is 6.5e-6 from the
    # exact solution): at 1e-10 it must be within 1e-6 of the exact one.
    me_error = {}
    for tol in [1e-8, 1e-10]:
        me = fmpy.simulate_fmu(str(fmu), fmi_type="ModelExchange", stop_time=3, output_interval=0.01,
                               relative_tolerance=tol, output=ANGLES)
        me_error[tol] = worst(me, exact, ANGLES)
    run_error = worst(same, exact, ANGLES)
    print(f"FMI {fmi}, double pendulum, 3 s: co-simulation vs run {cs_error:.2e}; model exchange vs exact {me_error} "
          f"(the run at 1e-8 vs exact: {run_error:.2e})")
    assert cs_error < 1e-6
    assert me_error[1e-10] < 1e-6


def torque_tables(tmp_path):
    """2 N.m until 1 s, then -1.5 N.m: FMPy's table has the jump at one
    time; the command's table jumps within 1e-9 s."""
    table = tmp_path / "torque.csv"
    table.write_text("time,tau\n0,2\n1,2\n1.000000001,-1.5\n5,-1.5\n")
    fmpy_input = np.array([(0.0, 2.0), (1.0, 2.0), (1.0, -1.5), (5.0, -1.5)], dtype=[("time", float), ("tau", float)])
    return table, fmpy_input


@VERSIONS
def test_a_torque_input_fed_from_a_table_in_both_modes(tmp_path, fmi):
    fmu = export(tmp_path, CONTROLLED, "cp", fmi=fmi)
    md = read_model_description(str(fmu))
    inputs = [v.name for v in md.modelVariables if v.causality == "input"]
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    # The model's input `tau = RealInput()` is `tau`, as an importer given
    # the input by that name expects.
    assert inputs == ["tau"]
    assert sorted(outputs) == ["angle", "speed"], outputs
    table, signal = torque_tables(tmp_path)
    exact = run(tmp_path, CONTROLLED, "exact", "--stop", "3", "--saveat", "0.01", "--reltol", "1e-12",
                "--abstol", "1e-12", "--input", f"tau={table}")
    names = ["rev.phi", "rev.w", "angle", "speed"]
    errors = {}
    # Co-simulation at 1e-8 (our integrator); model exchange at 1e-10
    # (CVode's, see the double pendulum).
    for kind, tol in [("CoSimulation", 1e-8), ("ModelExchange", 1e-10)]:
        result = fmpy.simulate_fmu(str(fmu), fmi_type=kind, stop_time=3, output_interval=0.01,
                                   relative_tolerance=tol, input=signal, output=names)
        errors[kind] = worst(result, exact, names)
        assert abs(result["angle"][-1] - exact["angle"][-1]) < 1e-6
    print(f"FMI {fmi}, pendulum with a torque table, 3 s: {errors}")
    assert max(errors.values()) < 1e-6


@VERSIONS
def test_events_of_a_bouncing_ball_in_both_modes(tmp_path, fmi):
    fmu = export(tmp_path, BOUNCING, "bb", fmi=fmi)
    reference = run(tmp_path, BOUNCING, "bb")
    # The impacts the command found: where the count steps up.
    steps = np.nonzero(np.diff(reference["impacts"]))[0]
    impact_times = reference["last_impact"][steps + 1]
    assert len(impact_times) == 10
    for kind in ["ModelExchange", "CoSimulation"]:
        result = fmpy.simulate_fmu(str(fmu), fmi_type=kind, stop_time=3.65, output_interval=0.01,
                                   relative_tolerance=1e-10, output=["h", "v", "impacts", "last_impact"])
        got = np.unique(result["last_impact"][result["impacts"] > 0])
        assert len(got) == 10, (kind, got)
        print(f"FMI {fmi}, bouncing ball, {kind}: impact times differ by at most {np.max(np.abs(got - impact_times)):.2e} s")
        assert np.max(np.abs(got - impact_times)) < 1e-7
        assert abs(result["h"][-1] - reference["h"][-1]) < 1e-6


@VERSIONS
def test_two_instances_in_one_process_give_what_one_gives(tmp_path, fmi):
    fmu = export(tmp_path, DOUBLE_PENDULUM, "dp", fmi=fmi)
    folder = fmpy.extract(str(fmu))
    md = read_model_description(folder)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    phi = [vr["link1.joint.phi"], vr["link2.joint.phi"]]

    def instance(name, length=None):
        if fmi == "2":
            slave = FMU2Slave(guid=md.guid, unzipDirectory=folder, modelIdentifier=md.coSimulation.modelIdentifier,
                              instanceName=name)
            slave.instantiate()
            slave.setupExperiment(tolerance=1e-8, startTime=0.0)
            slave.enterInitializationMode()
        else:
            slave = FMU3Slave(guid=md.guid, unzipDirectory=folder, modelIdentifier=md.coSimulation.modelIdentifier,
                              instanceName=name)
            slave.instantiate()
            slave.enterInitializationMode(tolerance=1e-8, startTime=0.0)
        if length is not None:
            (slave.setReal if fmi == "2" else slave.setFloat64)([vr["link2.length"]], [length])
        slave.exitInitializationMode()
        return slave

    def read(slave):
        return (slave.getReal if fmi == "2" else slave.getFloat64)(phi)

    alone = instance("alone")
    alone_values = []
    for k in range(100):
        alone.doStep(k * 0.01, 0.01)
        alone_values.append(read(alone))
    alone.terminate()
    alone.freeInstance()

    a, b = instance("a"), instance("b", length=0.7)
    a_values, b_values = [], []
    for k in range(100):
        a.doStep(k * 0.01, 0.01)
        b.doStep(k * 0.01, 0.01)
        a_values.append(read(a))
        b_values.append(read(b))
    for s in (a, b):
        s.terminate()
        s.freeInstance()
    assert np.array_equal(np.array(a_values), np.array(alone_values))
    # The other instance's parameter is its own: it moved differently, as
    # the command runs it with that value.
    other = run(tmp_path, DOUBLE_PENDULUM, "other", "--stop", "1", "--saveat", "0.01", "--reltol", "1e-8",
                "--abstol", "1e-8", "--param", "link2.length=0.7")
    assert abs(b_values[-1][1] - other["link2.joint.phi"][-1]) < 1e-6
    assert abs(b_values[-1][1] - a_values[-1][1]) > 1e-3
    shutil.rmtree(folder, ignore_errors=True)


@VERSIONS
def test_an_edited_model_file_refuses_to_instantiate(tmp_path, fmi):
    fmu = export(tmp_path, DOUBLE_PENDULUM, "dp", fmi=fmi)
    edited = tmp_path / "edited.fmu"
    with zipfile.ZipFile(fmu) as src, zipfile.ZipFile(edited, "w", zipfile.ZIP_DEFLATED) as dst:
        for item in src.infolist():
            data = src.read(item)
            if item.filename.endswith(".dyad"):
                data = data.replace(b"Length = 0.5", b"Length = 0.6", 1)
                assert b"Length = 0.6" in data
            dst.writestr(item.filename, data)
    assert_refused(edited, "token mismatch")


def assert_refused(fmu, expected):
    """Simulating `fmu` (a file or an unpacked folder) fails, and the
    FMU's log says `expected`."""
    messages = []

    def logger(*args):
        # FMI 2.0 passes the instance's name before the status; 3.0 does not.
        messages.append(args[-1].decode())

    with pytest.raises(Exception):
        fmpy.simulate_fmu(str(fmu), fmi_type="CoSimulation", stop_time=0.1, logger=logger)
    assert any(expected in m for m in messages), messages


@VERSIONS
def test_an_edited_description_refuses_to_instantiate(tmp_path, fmi):
    """A description whose value references were swapped ran with its
    variables mixed up: the token covered resources/ only. Unpacked whole
    (as the FMI standard has it), such an FMU refuses to instantiate."""
    fmu = export(tmp_path, DOUBLE_PENDULUM, "dp", fmi=fmi)
    folder = Path(fmpy.extract(str(fmu), unzipdir=str(tmp_path / "unpacked")))
    description = folder / "modelDescription.xml"
    text = description.read_text()
    swapped = (
        text.replace('valueReference="1"', 'valueReference="@"', 1)
        .replace('valueReference="2"', 'valueReference="1"', 1)
        .replace('valueReference="@"', 'valueReference="2"', 1)
    )
    assert swapped != text
    description.write_text(swapped)
    assert_refused(folder, "modelDescription.xml was edited after the export")
    # As exported, the unpacked FMU runs.
    description.write_text(text)
    result = fmpy.simulate_fmu(str(folder), fmi_type="CoSimulation", stop_time=0.1)
    assert result["time"][-1] == pytest.approx(0.1)


def test_a_model_without_inputs_or_outputs_exports_with_a_warning(tmp_path):
    done = multibody("fmu", DOUBLE_PENDULUM, "-o", tmp_path / "dp.fmu")
    assert "no inputs and no outputs" in done.stderr + done.stdout
    assert (tmp_path / "dp.fmu").is_file()


def test_a_model_that_does_not_compile_writes_nothing(tmp_path):
    bad = tmp_path / "bad.dyad"
    bad.write_text("component Bad\n  body = MultibodyComponents.Body(m = 1, r_cm = [0.5, 0])\nend\n")
    done = multibody("fmu", bad, "-o", tmp_path / "bad.fmu", check=False)
    assert done.returncode == 1, done.stderr
    assert "bad.dyad" in done.stderr
    assert not (tmp_path / "bad.fmu").exists()
    assert list(tmp_path.iterdir()) == [bad]


def test_an_fmu_analysis_in_the_model_file(tmp_path):
    model = tmp_path / "export.dyad"
    model.write_text(CONTROLLED.read_text() + """
analysis PendulumFMU
  extends DyadFMUGeneration.FMUAnalysis(version = "FMI_V3", fmu_type = "FMI_CS", n_outputs = 1, outputs = ["rev.phi"])
  model = ControlledPendulum()
end
""")
    fmu = tmp_path / "p.fmu"
    multibody("fmu", model, "--analysis", "PendulumFMU", "-o", fmu)
    md = read_model_description(str(fmu))
    assert md.fmiVersion == "3.0"
    assert md.modelExchange is None and md.coSimulation is not None
    outputs = sorted(v.name for v in md.modelVariables if v.causality == "output")
    assert outputs == ["angle", "rev.phi", "speed"]
    done = multibody("run", model, "--analysis", "PendulumFMU", check=False)
    assert done.returncode == 2 and "multibody fmu" in done.stderr
