//! The `multibody` command as a user meets it: exit codes, what `run`,
//! `check`, `describe` and `list` print, and partial output on failure.

mod common;

use common::{code, crate_path, example, multibody, scratch, stderr, stdout, Table};

#[test]
fn run_writes_a_csv_named_after_the_analysis_and_summarises() {
    let dir = scratch("run-default");
    let o = multibody(&dir, &["run", &example("pendulum.dyad")]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let table = Table::load(&dir.join("PendulumSimulation.csv"));
    assert_eq!(table.time.len(), 501);
    assert_eq!(table.stop(), 5.0);
    assert!(table.names.iter().any(|n| n == "rev.phi"));
    assert!(table.names.iter().any(|n| n == "body.frame_a.R[1,2]"), "matrix signals keep their names");
    let err = stderr(&o);
    assert!(err.contains("Simulating analysis PendulumSimulation (model Pendulum)"), "{err}");
    assert!(err.contains("501 samples"), "{err}");
    assert!(err.contains("PendulumSimulation.csv"), "{err}");
    assert!(err.contains("rev.phi = "), "{err}");
    assert!(stdout(&o).is_empty());
}

#[test]
fn run_selects_signals_and_overrides_options() {
    let dir = scratch("run-signals");
    let o = multibody(
        &dir,
        &[
            "run",
            &example("pendulum.dyad"),
            "--signals",
            "rev.?",
            "rev.phi",
            "body.r_0[?]",
            "--stop",
            "1",
            "--saveat",
            "0.1",
            "--out",
            "short.csv",
        ],
    );
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let table = Table::load(&dir.join("short.csv"));
    assert_eq!(table.time.len(), 11);
    let mut names = table.names.clone();
    names.sort();
    assert_eq!(names, ["body.r_0[1]", "body.r_0[2]", "body.r_0[3]", "rev.a", "rev.phi", "rev.w"]);
}

#[test]
fn run_a_component_of_a_folder_with_default_options() {
    let dir = scratch("run-model");
    let examples = crate_path("../../examples");
    let o = multibody(&dir, &["run", &examples, "--model", "FreeBody", "--stop", "0.5"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stderr(&o).contains("component FreeBody with default options"), "{}", stderr(&o));
    let table = Table::load(&dir.join("FreeBody.csv"));
    assert_eq!(table.stop(), 0.5);
}

#[test]
fn usage_errors_exit_with_2() {
    let dir = scratch("usage");
    let examples = crate_path("../../examples");
    // Several analyses and none chosen.
    let o = multibody(&dir, &["run", &examples]);
    assert_eq!(code(&o), 2);
    assert!(stderr(&o).contains("choose one with --analysis"), "{}", stderr(&o));
    // A misspelt analysis.
    let o = multibody(&dir, &["run", &examples, "--analysis", "PendulumSimulaton"]);
    assert_eq!(code(&o), 2);
    assert!(stderr(&o).contains("did you mean `PendulumSimulation`?"), "{}", stderr(&o));
    // A pattern that matches nothing, caught before simulating.
    let o = multibody(&dir, &["run", &example("pendulum.dyad"), "--signals", "rev.ph"]);
    assert_eq!(code(&o), 2);
    assert!(stderr(&o).contains("matches no signal"), "{}", stderr(&o));
    assert!(!dir.join("PendulumSimulation.csv").exists());
    // clap's own errors.
    assert_eq!(code(&multibody(&dir, &["run"])), 2);
    assert_eq!(code(&multibody(&dir, &["frobnicate"])), 2);
    let o = multibody(&dir, &["describe", "Revolut"]);
    assert_eq!(code(&o), 2);
    assert!(stderr(&o).contains("did you mean Revolute?"), "{}", stderr(&o));
}

#[test]
fn model_errors_exit_with_1_and_point_at_the_source() {
    let dir = scratch("model-error");
    let bad = crate_path("../multibody-dyad/tests/bad/unknown_parameter_of_user_component.dyad");
    let o = multibody(&dir, &["run", &bad]);
    assert_eq!(code(&o), 1);
    let err = stderr(&o);
    assert!(err.contains("unknown_parameter_of_user_component.dyad:3:13"), "{err}");
    assert!(err.contains("did you mean `length`?"), "{err}");
    assert!(!err.contains("\x1b["), "no colours when stderr is not a terminal");
    // Bytes that are not text are pointed at like a syntax error.
    std::fs::write(dir.join("binary.dyad"), b"component A\n  x = \xff\xfe\n").unwrap();
    let o = multibody(&dir, &["check", "binary.dyad"]);
    assert_eq!(code(&o), 1);
    assert!(stderr(&o).contains("not UTF-8 text") && stderr(&o).contains("binary.dyad:2:7"), "{}", stderr(&o));
    // Every file's syntax errors are reported, not only the first file's.
    let other = crate_path("../multibody-dyad/tests/bad/syntax_si_suffix.dyad");
    let third = crate_path("../multibody-dyad/tests/bad/syntax_missing_end.dyad");
    let o = multibody(&dir, &["check", &other, &third]);
    assert_eq!(code(&o), 1);
    assert!(stderr(&o).contains("syntax_si_suffix.dyad:3:41"), "{}", stderr(&o));
    assert!(stderr(&o).contains("syntax_missing_end.dyad:4:39"), "{}", stderr(&o));
    // Assembly errors too.
    let owner = crate_path("../multibody-dyad/tests/bad/no_owner_of_orientation.dyad");
    let o = multibody(&dir, &["check", &owner]);
    assert_eq!(code(&o), 1);
    assert!(stderr(&o).contains("nothing owns the orientation"), "{}", stderr(&o));
}

#[test]
fn io_errors_exit_with_4() {
    let dir = scratch("io");
    let o = multibody(&dir, &["run", "no/such/file.dyad"]);
    assert_eq!(code(&o), 4);
    assert!(stderr(&o).contains("cannot read no/such/file.dyad"), "{}", stderr(&o));
    // A folder for the output cannot be made where a file is; found before simulating.
    std::fs::write(dir.join("a-file"), "").unwrap();
    let o = multibody(&dir, &["run", &example("pendulum.dyad"), "--stop", "0.1", "--out", "a-file/out.csv"]);
    assert_eq!(code(&o), 4);
    assert!(stderr(&o).contains("cannot write a-file/out.csv"), "{}", stderr(&o));
    assert!(!stderr(&o).contains("Simulating"), "{}", stderr(&o));
    // A missing folder is made, as for the views.
    let o = multibody(&dir, &["run", &example("pendulum.dyad"), "--stop", "0.1", "--out", "new-folder/out.csv"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(dir.join("new-folder/out.csv").exists());
}

/// A free body whose Euler angles meet their singular configuration runs
/// to its stop, and the command says once that it went on in a chart; the
/// angles it reports are the library's, in the branch they were in:
/// phi[2] = t on through pi/2 (R = A_y(t), phi[1] = phi[3] = 0).
#[test]
fn an_euler_body_runs_through_its_singularity_with_a_note() {
    let dir = scratch("euler-singularity");
    let model = crate_path("tests/models/EulerSingularity.dyad");
    let o = multibody(&dir, &["run", &model, "--out", "result.csv"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let err = stderr(&o);
    assert_eq!(err.matches("singular configuration").count(), 1, "one note: {err}");
    assert!(err.contains("warning: `body` came near the singular configuration"), "{err}");
    let table = Table::load(&dir.join("result.csv"));
    assert!((table.stop() - 3.0).abs() < 1e-9, "ran to {}", table.stop());
    let (t, phi2) = (&table.time, table.column("body.phi[2]"));
    for (&t, &phi2) in t.iter().zip(phi2) {
        assert!((phi2 - t).abs() < 1e-9, "phi[2] = {phi2} at t = {t}, not t");
    }
}

/// A warning of the run about a relation names the equation as written
/// and where it is (it named an internal `#0`).
#[test]
fn a_warning_about_a_relation_shows_the_equation_and_its_place() {
    let dir = scratch("relation_warning");
    std::fs::write(
        dir.join("square.dyad"),
        "component SquareTorque\n  inertia = RotationalComponents.Inertia(J = 1)\n  torque = \
         RotationalComponents.Sources.Torque()\n  u = RealOutput()\nrelations\n  u = if sin(2 * pi * 1000 * time) \
         > 0 then 1 else -1\n  connect(u, torque.tau)\n  connect(torque.spline, inertia.spline_a)\nend\nanalysis \
         SquareRun\n  extends TransientAnalysis(stop = 0.01)\n  model = SquareTorque()\nend\n",
    )
    .unwrap();
    let o = multibody(&dir, &["run", "square.dyad", "--out", "result.csv"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let all = format!("{}{}", stdout(&o), stderr(&o));
    assert!(all.contains("the relation in `u = if sin(2 * pi * 1000 * time) > 0 then 1 else -1` ("), "{all}");
    assert!(all.contains("square.dyad:6:3)"), "{all}");
    assert!(!all.contains("#0"), "{all}");
}

#[test]
fn a_failed_simulation_keeps_what_it_computed_as_partial_and_exits_with_3() {
    let dir = scratch("partial");
    let model = crate_path("tests/models/PilingUp.dyad");
    std::fs::write(dir.join("result.csv"), "an earlier complete result").unwrap();
    let o = multibody(&dir, &["run", &model, "--out", "result.csv", "--plot", "result.svg"]);
    assert_eq!(code(&o), 3, "{}", stderr(&o));
    let err = stderr(&o);
    // The bounces pile up at sqrt(2 / 9.81) (1 + 2 e / (1 - e)) = 4.0637 s.
    let t_zeno = (2.0f64 / 9.81).sqrt() * (1.0 + 2.0 * 0.8 / 0.2);
    let stopped: f64 = err
        .split("the simulation stopped at t = ")
        .nth(1)
        .and_then(|rest| rest.split(':').next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("no stop time in: {err}"));
    assert!((stopped - t_zeno).abs() < 1e-3, "stopped at {stopped}, not near {t_zeno}: {err}");
    assert!(err.contains("pile up"), "the message says why: {err}");
    assert!(err.contains("wrote what was computed"), "{err}");
    assert!(err.contains("result.partial.csv"), "{err}");
    let table = Table::load(&dir.join("result.partial.csv"));
    let last = table.stop();
    assert!(last > 4.0 && last <= stopped + 1e-9, "kept up to {last}");
    let h = table.column("h");
    assert!(h.iter().all(|&h| h > -1e-6 && h <= 1.0 + 1e-9), "the ball stays between the ground and its start");
    // The earlier result stays; the views of the partial run are named partial too.
    assert_eq!(std::fs::read_to_string(dir.join("result.csv")).unwrap(), "an earlier complete result");
    assert!(dir.join("result.partial.svg").exists());
    assert!(!dir.join("result.svg").exists());
    assert_no_temporary_files(&dir);
}

/// Nothing of the temporary files that results are written through stays.
fn assert_no_temporary_files(dir: &std::path::Path) {
    let left: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect();
    assert!(left.is_empty(), "temporary files left: {left:?}");
}

/// Options are checked before any work, from the command line (naming the
/// option, negative numbers typed as such) and from the analysis (with its
/// place); a refused run leaves earlier results as they were.
#[test]
fn options_are_checked_before_anything_is_written() {
    let dir = scratch("options");
    let pendulum = example("pendulum.dyad");
    std::fs::write(dir.join("PendulumSimulation.csv"), "earlier results").unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["--stop", "-1"], "--stop -1: `stop` (-1) must be after `start` (0)"),
        (&["--stop", "nan"], "--stop NaN: `stop` must be a finite number"),
        (&["--stop", "inf"], "--stop inf: `stop` must be a finite number"),
        (&["--saveat", "-0.5"], "--saveat -0.5: `saveat` must not be negative"),
        (&["--reltol", "0"], "--reltol 0: `reltol` must be positive"),
        (&["--reltol", "1e-20"], "below what double precision can resolve"),
        (&["--abstol", "-1e-6"], "--abstol -0.000001: `abstol` must be positive"),
        (&["--alg", "Euler"], "--alg Euler: no such method"),
        (&["--plot", "plot.jpg"], "cannot tell the plot format; name the file .png or .svg"),
    ];
    for (options, message) in cases {
        let mut args = vec!["run", pendulum.as_str()];
        args.extend_from_slice(options);
        let o = multibody(&dir, &args);
        assert_eq!(code(&o), 2, "{options:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(message), "{options:?}: {}", stderr(&o));
        assert!(!stderr(&o).contains("Simulating"), "{options:?}: refused before simulating");
    }
    assert_eq!(std::fs::read_to_string(dir.join("PendulumSimulation.csv")).unwrap(), "earlier results");
    assert_no_temporary_files(&dir);
    // The analysis's own values, in `check` too, with their place.
    std::fs::write(
        dir.join("bad_analysis.dyad"),
        std::fs::read_to_string(&pendulum).unwrap().replace("stop = 5", "stop = 5, reltol = -1e-6"),
    )
    .unwrap();
    for command in ["check", "run"] {
        let o = multibody(&dir, &[command, "bad_analysis.dyad"]);
        assert_eq!(code(&o), 1, "{command}: {}", stderr(&o));
        assert!(stderr(&o).contains("`reltol` must be positive"), "{command}: {}", stderr(&o));
        assert!(stderr(&o).contains("bad_analysis.dyad:"), "{command}: {}", stderr(&o));
    }
}

/// No output may write over a model file or over another output; the
/// refusal comes before anything is computed and leaves the files as they were.
#[test]
fn outputs_never_write_over_inputs_or_each_other() {
    let dir = scratch("overwrite");
    let model = dir.join("pendulum.dyad");
    std::fs::copy(example("pendulum.dyad"), &model).unwrap();
    let text = std::fs::read_to_string(&model).unwrap();
    let o = multibody(&dir, &["run", "pendulum.dyad", "--out", "./pendulum.dyad"]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert!(stderr(&o).contains("would write over the model file"), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&model).unwrap(), text, "the model file is untouched");
    // A folder's model files count as inputs too.
    let o = multibody(&dir, &["run", ".", "--plot", "pendulum.dyad"]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&model).unwrap(), text);
    // Earlier results beside the models are outputs, not inputs: a rerun replaces them.
    std::fs::write(dir.join("earlier.csv"), "earlier results").unwrap();
    let o = multibody(&dir, &["run", ".", "--out", "earlier.csv", "--stop", "0.1"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(std::fs::read_to_string(dir.join("earlier.csv")).unwrap().contains("rev.phi"));

    std::fs::write(dir.join("out.csv"), "earlier results").unwrap();
    let o = multibody(&dir, &["run", "pendulum.dyad", "--out", "out.csv", "--animate", "out.csv"]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert!(stderr(&o).contains("`--out` and `--animate` both name"), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(dir.join("out.csv")).unwrap(), "earlier results");
}

#[test]
fn check_prints_the_states_and_orientation_owners() {
    let dir = scratch("check");
    let o = multibody(&dir, &["check", &example("pendulum.dyad")]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.contains("analysis PendulumSimulation, model Pendulum"), "{out}");
    assert!(out.contains("degrees of freedom: 1"), "{out}");
    assert!(out.contains("rev.phi  0") && out.contains("rev.w    0"), "{out}");
    assert!(out.contains("every part is positioned from the World"), "{out}");
    assert!(out.contains("warnings: none"), "{out}");

    let o = multibody(&dir, &["check", &example("free_body.dyad")]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.contains("degrees of freedom: 6"), "{out}");
    let w2 = out.lines().find(|l| l.trim_start().starts_with("body.w_a[2] ")).expect("w_a[2] is a state");
    assert_eq!(w2.split_whitespace().last(), Some("2"), "{out}");
    assert!(out.contains("orientation owners") && out.contains("body: quaternion"), "{out}");
}

/// The loop is found and reported without the user marking anything.
#[test]
fn check_reports_a_loop_its_degrees_of_freedom_and_redundant_equations() {
    let dir = scratch("check-loop");
    let o = multibody(&dir, &["check", &example("four_bar.dyad")]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.contains("degrees of freedom: 1\n"), "{out}");
    assert!(out.contains("kinematic loops: 1\n"), "{out}");
    assert!(out.contains("5 constraint equations, 3 of them redundant"), "{out}");
    for joint in ["j1", "j2", "j3", "j4"] {
        assert!(out.contains(joint), "{out}");
    }
}

#[test]
fn describe_shows_parameters_connectors_and_variables() {
    let dir = scratch("describe");
    let o = multibody(&dir, &["describe", "MultibodyComponents.Body"]);
    assert_eq!(code(&o), 0);
    let out = stdout(&o);
    assert!(out.starts_with("Body\n"), "{out}");
    for line in
        ["m ", "= 1 ", "kg", "r_cm", "= [0, 0, 0]", "frame_a", "Frame3D", "w_a[3]", "rad/s", "orientation_state"]
    {
        assert!(out.contains(line), "describe Body lacks `{line}`:\n{out}");
    }
    let o = multibody(&dir, &["describe", "RotationalComponents.Components.Damper"]);
    assert_eq!(code(&o), 0);
    assert!(stdout(&o).contains("(required)"), "{}", stdout(&o));
    // A component of the library written in Dyad, by its longer name:
    // inherited connectors and its variables are shown.
    let o = multibody(&dir, &["describe", "BlockComponents.Continuous.Derivative"]);
    assert_eq!(code(&o), 0);
    let out = stdout(&o);
    assert!(out.starts_with("BlockComponents.Derivative (written in Dyad)"), "{out}");
    for line in ["T ", "(required)", "x0", "= 0", "u ", "RealInput", "y ", "RealOutput", "Variables", "x "] {
        assert!(out.contains(line), "describe Derivative lacks `{line}`:\n{out}");
    }
}

#[test]
fn list_shows_every_kind_once() {
    let dir = scratch("list");
    let o = multibody(&dir, &["list"]);
    assert_eq!(code(&o), 0);
    let out = stdout(&o);
    let kinds = multibody::components::registry();
    let written = multibody_dyad::catalog::components();
    assert_eq!(out.lines().count(), kinds.len() + written.len());
    for name in kinds.iter().map(|s| s.kind).chain(written.iter().map(|(n, _)| n.as_str())) {
        assert!(out.lines().any(|l| l.split_whitespace().next() == Some(name)), "{name} missing");
    }
}

#[test]
fn help_documents_the_exit_codes() {
    let o = multibody(&scratch("help"), &["--help"]);
    assert_eq!(code(&o), 0);
    let out = stdout(&o);
    for line in [
        "0  success",
        "1  the model files have errors",
        "2  usage error",
        "3  the simulation failed",
        "4  input/output error",
        "130  stopped by Ctrl-C",
    ] {
        assert!(out.contains(line), "--help lacks `{line}`:\n{out}");
    }
}

/// A sweep runs every combination of the values into one long table: each
/// run's rows are those of `run` with the same values; a run that fails is
/// reported with its values and the others are kept.
#[test]
fn a_sweep_runs_the_grid_into_one_table() {
    let dir = scratch("sweep");
    let pendulum = example("pendulum.dyad");
    let o = multibody(
        &dir,
        &["run", &pendulum, "--param", "body.m=2", "--initial", "rev.phi=0.5", "--stop", "1", "--out", "one.csv"],
    );
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let one = Table::load(&dir.join("one.csv"));
    let o = multibody(
        &dir,
        &[
            "sweep",
            &pendulum,
            "--param",
            "body.m=-1,1:1:2",
            "--initial",
            "rev.phi=0.5",
            "--stop",
            "1",
            "--signals",
            "rev.phi",
            "rev.w",
            "--out",
            "sweep.csv",
        ],
    );
    assert_eq!(code(&o), 3, "one run of three fails: {}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("run 1 (body.m = -1, rev.phi = 0.5)"), "{err}");
    assert!(err.contains("2 runs of 3 ran"), "{err}");
    let text = std::fs::read_to_string(dir.join("sweep.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next().unwrap(), "\"run\",\"body.m\",\"rev.phi\",\"time\",\"rev.phi\",\"rev.w\"");
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let run3: Vec<&Vec<&str>> = rows.iter().filter(|r| r[0] == "3").collect();
    assert_eq!(run3.len(), one.time.len());
    assert!(rows.iter().all(|r| r[0] != "1"), "the failed run has no rows");
    for (k, row) in run3.iter().enumerate() {
        assert_eq!(row[1..3], ["2", "0.5"]);
        let (t, phi, w): (f64, f64, f64) = (row[3].parse().unwrap(), row[4].parse().unwrap(), row[5].parse().unwrap());
        assert_eq!(t, one.time[k]);
        assert_eq!(phi.to_bits(), one.column("rev.phi")[k].to_bits(), "the same numbers as `run`");
        assert_eq!(w.to_bits(), one.column("rev.w")[k].to_bits());
    }
    let o = multibody(&dir, &["sweep", &pendulum, "--param", "body.m=1:0:2"]);
    assert_eq!(code(&o), 2);
    assert!(stderr(&o).contains("non-zero step"), "{}", stderr(&o));
}

/// A file in a folder named `PlanarMechanics` reads short names as planar
/// components, also when it is named from inside that folder (`run
/// fall.dyad`, `run .`): a planar Body, free, falls as
/// `y = 2 + 3 t - g t^2 / 2` and drifts as `x = 1 + 0.5 t`.
#[test]
fn a_file_run_from_inside_its_planar_mechanics_folder_reads_planar_names() {
    let dir = scratch("planar-folder").join("PlanarMechanics");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("fall.dyad"),
        "component Fall
  world = World()
  body = Body(m = 2, I = 1, r(initial = [1, 2]), v(initial = [0.5, 3]))
end

analysis FallSimulation
  extends TransientAnalysis(stop = 1, saveat = 0.1)
  model = Fall()
end
",
    )
    .unwrap();
    for path in ["fall.dyad", ".", "./fall.dyad"] {
        let o = multibody(&dir, &["run", path]);
        assert_eq!(code(&o), 0, "run {path}: {}", stderr(&o));
        let table = Table::load(&dir.join("FallSimulation.csv"));
        let (x, y) = (table.column("body.r[1]"), table.column("body.r[2]"));
        let g = 9.80665;
        for (k, t) in table.time.iter().enumerate() {
            let (ex, ey) = (1.0 + 0.5 * t, 2.0 + 3.0 * t - g * t * t / 2.0);
            assert!((x[k] - ex).abs() < 1e-6 && (y[k] - ey).abs() < 1e-6, "run {path}: at {t} ({}, {})", x[k], y[k]);
        }
        std::fs::remove_file(dir.join("FallSimulation.csv")).unwrap();
    }
}

/// The scene JSON an animation page embeds.
fn page_scene(page: &std::path::Path) -> serde_json::Value {
    let html = std::fs::read_to_string(page).unwrap();
    let start = html.find("id=\"mb-scene\">").expect("the page has a scene") + "id=\"mb-scene\">".len();
    let end = start + html[start..].find("</script>").unwrap();
    serde_json::from_str(&html[start..end]).unwrap()
}

/// Standard base64 back to bytes (the page's arrays).
fn unbase64(text: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        _ => 63,
    };
    let digits: Vec<u8> = text.bytes().filter(|&c| c != b'=').map(value).collect();
    let mut out = Vec::new();
    for chunk in digits.chunks(4) {
        let n = chunk.iter().enumerate().fold(0u32, |n, (i, &d)| n | (u32::from(d) << (18 - 6 * i)));
        out.extend_from_slice(&n.to_be_bytes()[1..chunk.len()]);
    }
    out
}

/// A pendulum whose link is drawn twice from one mesh file, named by a
/// string parameter of a component of the model's own, relative to the
/// model file's folder.
const MESH_MODEL: &str = r#"
component Link
  frame_a = Frame3D()
  parameter part::String = "parts/tetra.stl"
  body = MultibodyComponents.Body(m = 1, r_cm = [0.5, 0, 0])
  look = MultibodyComponents.ShapefileVisualizer(shapefile = part, shape_scale = 0.2, color = [0.9, 0.5, 0.1, 1])
  again = MultibodyComponents.ShapefileVisualizer(shapefile = part, shape_transform = [[1, 0, 0, 0.3], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
relations
  connect(frame_a, body.frame_a, look.frame_a, again.frame_a)
end

component MeshArm
  world = MultibodyComponents.World()
  rev = MultibodyComponents.Revolute(n = [0, 0, 1])
  link = Link(part = "PART")
relations
  connect(world.frame_b, rev.frame_a)
  connect(rev.frame_b, link.frame_a)
end

analysis MeshArmSimulation
  extends TransientAnalysis(stop = 0.5, saveat = 0.05)
  model = MeshArm()
end
"#;

/// A tetrahedron with unit legs along x, y and z (ASCII STL).
const TETRA_STL: &str = "solid t\n\
    facet normal 0 0 -1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\nendfacet\n\
    facet normal 0 -1 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\n\
    facet normal -1 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\nendfacet\n\
    facet normal 1 1 1\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\nendsolid t\n";

#[test]
fn run_draws_a_mesh_file_from_the_model_folder_once() {
    let dir = scratch("mesh-run");
    std::fs::create_dir_all(dir.join("model/parts")).unwrap();
    std::fs::write(dir.join("model/parts/tetra.stl"), TETRA_STL).unwrap();
    std::fs::write(dir.join("model/arm.dyad"), MESH_MODEL.replace("PART", "parts/tetra.stl")).unwrap();
    // Run from elsewhere than the model's folder.
    let o = multibody(&dir, &["run", "model/arm.dyad", "--animate", "arm.html", "--out", "arm.csv"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(!stderr(&o).contains("warning"), "{}", stderr(&o));
    let scene = page_scene(&dir.join("arm.html"));
    let meshes = scene["meshes"].as_array().unwrap();
    assert_eq!(meshes.len(), 1, "one file, embedded once");
    assert!(meshes[0]["path"].as_str().unwrap().ends_with("model/parts/tetra.stl"), "{}", meshes[0]["path"]);
    let floats = |key: &str| -> Vec<f32> {
        unbase64(meshes[0][key].as_str().unwrap())
            .chunks(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect()
    };
    let indices = unbase64(meshes[0]["indices"].as_str().unwrap());
    assert_eq!(indices.len() / 4, 12, "the file's 4 triangles");
    let positions = floats("positions");
    assert_eq!(floats("normals").len(), positions.len());
    // The file's corners: the unit tetrahedron.
    for axis in 0..3 {
        let values: Vec<f32> = positions.iter().skip(axis).step_by(3).copied().collect();
        let (lo, hi) = values.iter().fold((f32::MAX, f32::MIN), |(lo, hi), &x| (lo.min(x), hi.max(x)));
        assert_eq!((lo, hi), (0.0, 1.0), "axis {axis}");
    }
    let shapes: Vec<&serde_json::Value> =
        scene["shapes"].as_array().unwrap().iter().filter(|s| s["kind"] == "mesh").collect();
    assert_eq!(shapes.len(), 2);
    assert_eq!(shapes[0]["component"], "link.look");
    assert!(shapes.iter().all(|s| s["mesh"] == 0));
    assert_eq!(shapes[0]["scale"], 0.2);
    assert_eq!(shapes[1]["transform"][3], 0.3);
    assert_eq!(shapes[0]["color"][1], 0.5);
}

#[test]
fn a_missing_mesh_file_is_left_out_with_a_warning_and_the_results_are_kept() {
    let dir = scratch("mesh-missing");
    std::fs::create_dir_all(dir.join("model")).unwrap();
    std::fs::write(dir.join("model/arm.dyad"), MESH_MODEL.replace("PART", "parts/nowhere.stl")).unwrap();
    let o = multibody(&dir, &["run", "model/arm.dyad", "--animate", "arm.html", "--out", "arm.csv"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let err = stderr(&o);
    for component in ["link.look", "link.again"] {
        let line =
            err.lines().find(|l| l.contains(component)).unwrap_or_else(|| panic!("no warning for {component}:\n{err}"));
        assert!(line.starts_with("warning:"), "{line}");
        assert!(line.contains("model/parts/nowhere.stl") && line.contains("no such file"), "{line}");
    }
    assert_eq!(Table::load(&dir.join("arm.csv")).time.len(), 11, "the results are kept");
    let scene = page_scene(&dir.join("arm.html"));
    assert!(scene["meshes"].as_array().unwrap().is_empty());
    assert!(scene["shapes"].as_array().unwrap().iter().all(|s| s["kind"] != "mesh"));
    assert!(!scene["shapes"].as_array().unwrap().is_empty(), "the other shapes are drawn");
}
