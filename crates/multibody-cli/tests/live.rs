//! `multibody live`: the page runs the model in headless Chromium with the
//! engine compiled to WebAssembly, and must give what `multibody run`
//! gives for the same values: the same final state (to 1e-12), the same
//! picture, the same message for a bad value, and the last good run kept.
//!
//! The module is built by `scripts/build-web.sh` (run by
//! `scripts/install-test-deps.sh`).

#[path = "../../multibody-view/tests/common/browser.rs"]
mod browser;
mod common;
#[allow(dead_code)]
#[path = "../../multibody-view/tests/common/pixels.rs"]
mod pixels;

use common::{code, crate_path, example, multibody, scratch, stderr, Table};
use std::path::{Path, PathBuf};
use std::time::SystemTime;

/// The module `multibody live` embeds, checked to be built from the
/// sources as they are (a stale one would test old code).
fn module() -> PathBuf {
    let exe = PathBuf::from(env!("CARGO_BIN_EXE_multibody"));
    let module = exe.parent().unwrap().parent().unwrap().join("wasm32-unknown-unknown/web/multibody_web.wasm");
    let built = std::fs::metadata(&module).and_then(|m| m.modified()).unwrap_or_else(|_| {
        panic!("the live page tests need the WebAssembly module {}: run scripts/build-web.sh", module.display())
    });
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let newest = [
        "crates/multibody/src",
        "crates/multibody-dyad/src",
        "crates/multibody-dyad/stdlib",
        "crates/multibody-view/src",
        "crates/multibody-web/src",
    ]
    .iter()
    .map(|d| newest_file(&root.join(d)))
    .max()
    .unwrap();
    assert!(
        built >= newest,
        "the WebAssembly module {} is older than the engine's sources: run scripts/build-web.sh",
        module.display()
    );
    module
}

fn newest_file(dir: &Path) -> SystemTime {
    let mut newest = SystemTime::UNIX_EPOCH;
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let path = entry.path();
        let time = if path.is_dir() { newest_file(&path) } else { entry.metadata().unwrap().modified().unwrap() };
        newest = newest.max(time);
    }
    newest
}

/// The page's console lines that start with `multibody-live: {what}`.
fn logged<'a>(shot: &'a browser::Shot, what: &str) -> Vec<&'a str> {
    let marker = format!("multibody-live: {what}");
    shot.console()
        .into_iter()
        .filter_map(|l| l.find(&marker).map(|k| l[k + marker.len()..].split("\", source:").next().unwrap()))
        .collect()
}

/// `name=value` pairs of a logged line, by name.
fn pairs(line: &str) -> Vec<(String, f64)> {
    line.split_whitespace()
        .filter_map(|w| w.split_once('=').map(|(n, v)| (n.to_string(), v.parse().unwrap())))
        .collect()
}

fn live_page(dir: &Path, model: &str, extra: &[&str]) -> PathBuf {
    let page = dir.join("live.html");
    let mut args =
        vec!["live", &example(model)[..], "-o", "live.html"].into_iter().map(String::from).collect::<Vec<_>>();
    args.extend(extra.iter().map(|s| s.to_string()));
    args.push("--wasm".into());
    args.push(module().display().to_string());
    let out = multibody(dir, &args.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(code(&out), 0, "{}", stderr(&out));
    page
}

#[test]
fn a_changed_length_runs_in_the_page_as_the_command_runs_it() {
    let dir = scratch("live_changed_length");
    let page = live_page(&dir, "double_pendulum.dyad", &[]);
    let bytes = std::fs::metadata(&page).unwrap().len();
    eprintln!("live page: {bytes} bytes");
    assert!(bytes < 3_000_000, "the live page has {bytes} bytes, more than 3 MB");

    // The command's run with the same values, and its own page.
    let out = multibody(
        &dir,
        &[
            "run",
            &example("double_pendulum.dyad"),
            "--param",
            "link2.length=0.7",
            "--stop",
            "5",
            "--out",
            "ref.csv",
            "--animate",
            "ref.html",
        ],
    );
    assert_eq!(code(&out), 0, "{}", stderr(&out));
    let reference = Table::load(&dir.join("ref.csv"));

    let shot =
        browser::screenshot(&page, "live=link2.length=0.7;stop=5&livebench=10&t=2&panel=0", (900, 600), "live_changed");
    shot.assert_clean();
    let finals = logged(&shot, "final ");
    assert_eq!(finals.len(), 1, "the page did not report its run:\n{}", shot.log);
    let finals = pairs(finals[0]);
    assert_eq!(finals.len(), 4, "{finals:?}");
    let mut worst: f64 = 0.0;
    for (name, value) in &finals {
        let expected = *reference.column(name).last().unwrap();
        let error = (value - expected).abs();
        eprintln!("{name}: page {value:e}, command {expected:e}, difference {error:.1e}");
        worst = worst.max(error);
    }
    eprintln!("worst difference {worst:.1e} = {:.4} of 1e-12", worst / 1e-12);
    assert!(worst <= 1e-12, "the page's final state differs from the command's by {worst:e}");

    // Re-running after a change, measured in the page (run, scene and redraw).
    let bench = logged(&shot, "bench ");
    let bench = pairs(bench.first().unwrap_or_else(|| panic!("no bench line:\n{}", shot.log)));
    let median = bench.iter().find(|(n, _)| n == "median_ms").unwrap().1;
    eprintln!("re-simulating 5 s after a change: median {median} ms, max {} ms", bench[2].1);
    assert!(median < 50.0, "re-simulating the double pendulum took {median} ms (median of 10)");

    // The picture: the command's page with the same length at the same
    // time, and not the unchanged motion.
    let same = browser::screenshot(&dir.join("ref.html"), "t=2&panel=0", (900, 600), "live_ref");
    same.assert_clean();
    let before = browser::screenshot(&page, "t=2&panel=0", (900, 600), "live_before");
    let to_same = shot.image.changed_fraction(&same.image);
    let to_before = shot.image.changed_fraction(&before.image);
    eprintln!("pixels changed: vs the command's page {to_same:.4}, vs the unchanged model {to_before:.4}");
    assert!(to_same < 0.002, "the page's picture differs from the command's: {to_same}");
    assert!(to_before > 0.01, "the change did not show: {to_before}");
}

#[test]
fn a_bad_value_shows_the_commands_message_and_keeps_the_last_run() {
    let dir = scratch("live_bad_value");
    let page = live_page(&dir, "double_pendulum.dyad", &["--stop", "2"]);
    for (value, case) in
        [("link2.width=-0.1", "negative"), ("link1.d=abc", "word"), ("link2.box.density=-7800", "negative_mass")]
    {
        let out = multibody(&dir, &["run", &example("double_pendulum.dyad"), "--param", value, "--out", "x.csv"]);
        assert_eq!(code(&out), 2, "{}", stderr(&out));
        let message = stderr(&out).trim().strip_prefix("error: ").unwrap().to_string();
        let shot =
            browser::screenshot(&page, &format!("live=link2.length=0.7;{value}&t=1.5&panel=0"), (900, 600), case);
        let refused = logged(&shot, "refused ");
        assert_eq!(refused.len(), 1, "{}", shot.log);
        // Logged as JSON text: `"` and `\` escaped.
        let shown = refused[0].trim_matches('"').replace("\\\"", "\"").replace("\\\\", "\\");
        let shown = shown.trim_end_matches("\\\"").trim_end_matches('"');
        assert_eq!(shown, message, "{case}");
        // The view still shows the good run before it (link2 0.7 m long).
        let kept = browser::screenshot(&page, "live=link2.length=0.7&t=1.5&panel=0", (900, 600), "kept");
        let changed = shot.image.changed_fraction(&kept.image);
        assert!(changed < 0.002, "{case}: the last good run was not kept ({changed})");
    }
}

/// The page steps the run (as it does in real time) and sets the model's
/// input torque between steps: 2 N.m until t = 1 s, then -1.5 N.m. The
/// command drives the same input from a table that jumps there (within
/// 1e-9 s); both runs use the analysis's tolerances of 1e-10.
#[test]
fn an_input_set_between_steps_acts_as_the_commands_input_table() {
    let dir = scratch("live_stepped_input");
    let page = live_page(&dir, "controlled_pendulum.dyad", &["--stop", "3"]);
    std::fs::write(dir.join("tau.csv"), "time,tau\n0,2\n1,2\n1.000000001,-1.5\n3,-1.5\n").unwrap();
    let model = example("controlled_pendulum.dyad");
    let out = multibody(&dir, &["run", &model, "--input", "tau=tau.csv", "--stop", "3", "--out", "ref.csv"]);
    assert_eq!(code(&out), 0, "{}", stderr(&out));
    let reference = Table::load(&dir.join("ref.csv"));
    let shot =
        browser::screenshot(&page, "livestep=0.1&liveinput=tau=2@1=-1.5&t=3&panel=0", (900, 600), "live_stepped");
    shot.assert_clean();
    let stepped = logged(&shot, "stepped ");
    assert_eq!(stepped.len(), 1, "the page did not report its steps:\n{}", shot.log);
    assert!(stepped[0].starts_with("30 final "), "{}", stepped[0]);
    let finals = pairs(stepped[0]);
    for name in ["rev.phi", "rev.w"] {
        let value = finals.iter().find(|(n, _)| n == name).unwrap().1;
        let expected = *reference.column(name).last().unwrap();
        let error = (value - expected).abs();
        eprintln!(
            "{name}: stepped in the page {value}, command {expected}, difference {error:.1e} = {:.4} of 1e-6",
            error / 1e-6
        );
        assert!(error < 1e-6, "{name}: {value} vs {expected}");
    }
    // The torque turned the pendulum away from where it hangs unforced.
    assert!(finals.iter().any(|(n, v)| n == "rev.phi" && *v < -1.0), "{finals:?}");
}

#[test]
fn the_command_refuses_before_writing() {
    let dir = scratch("live_refusals");
    let model = example("double_pendulum.dyad");
    let missing = multibody(&dir, &["live", &model, "-o", "p.html", "--wasm", "nowhere.wasm"]);
    assert_eq!(code(&missing), 2);
    assert!(stderr(&missing).contains("the WebAssembly module nowhere.wasm does not exist"), "{}", stderr(&missing));
    std::fs::write(dir.join("fake.wasm"), "not a module").unwrap();
    let fake = multibody(&dir, &["live", &model, "-o", "p.html", "--wasm", "fake.wasm"]);
    assert!(
        stderr(&fake).contains("is not a WebAssembly module; rebuild it with scripts/build-web.sh"),
        "{}",
        stderr(&fake)
    );
    let module = module().display().to_string();
    let bad = multibody(&dir, &["live", &model, "--param", "link2.width=-0.1", "-o", "p.html", "--wasm", &module]);
    assert_eq!(code(&bad), 2);
    assert!(
        stderr(&bad).contains("`--param link2.width=-0.1`: `link2.box.width` = -0.1 is not allowed"),
        "{}",
        stderr(&bad)
    );
    assert!(!dir.join("p.html").exists(), "a page was written for a model that does not run");
    let copy = dir.join("model.dyad");
    std::fs::copy(&model, &copy).unwrap();
    let over = multibody(&dir, &["live", "model.dyad", "-o", "model.dyad", "--wasm", &module]);
    assert_eq!(code(&over), 2);
    assert_eq!(std::fs::read_to_string(&copy).unwrap(), std::fs::read_to_string(&model).unwrap());
    // Nor the module it reads (it wrote the page over it).
    let own = dir.join("own.wasm");
    std::fs::copy(&module, &own).unwrap();
    let over = multibody(&dir, &["live", &model, "-o", "own.wasm", "--wasm", "./own.wasm"]);
    assert_eq!(code(&over), 2);
    assert!(stderr(&over).contains("would write over the WebAssembly module"), "{}", stderr(&over));
    assert_eq!(std::fs::read(&own).unwrap(), std::fs::read(&module).unwrap());
    // A first run whose samples cannot fit in memory is refused before it
    // starts (a 2000-body chain to --stop 1e6 grew past 11 GB).
    let far = multibody(&dir, &["live", &model, "--stop", "1e9", "-o", "far.html", "--wasm", &module]);
    assert_eq!(code(&far), 2, "{}", stderr(&far));
    assert!(stderr(&far).contains("the page holds every signal of its first run"), "{}", stderr(&far));
    assert!(stderr(&far).contains("shorten --stop"), "{}", stderr(&far));
    assert!(!dir.join("far.html").exists());
}

/// One axis of the industrial robot (a folder of model files) in the live
/// page: the controller's gains are values of its panel, and a changed
/// position gain runs in the page as the command runs it.
#[test]
fn the_robot_axis_runs_in_the_page_with_a_changed_gain() {
    let dir = scratch("live_one_axis");
    let folder = crate_path("../../examples/robot");
    let wasm = module().display().to_string();
    let args = ["live", &folder, "--analysis", "OneAxisRun", "-o", "live.html", "--wasm", &wasm];
    let out = multibody(&dir, &args);
    assert_eq!(code(&out), 0, "{}", stderr(&out));
    let out = multibody(
        &dir,
        &["run", &folder, "--analysis", "OneAxisRun", "--param", "kp=8", "--out", "ref.csv", "--signals", "*"],
    );
    assert_eq!(code(&out), 0, "{}", stderr(&out));
    let reference = Table::load(&dir.join("ref.csv"));
    let shot = browser::screenshot(&dir.join("live.html"), "live=kp=8&panel=0", (900, 600), "live_one_axis");
    // No shapes: the page shows plots, not a 3-D view.
    shot.assert_no_errors();
    let finals = logged(&shot, "final ");
    assert_eq!(finals.len(), 1, "the page did not report its run:\n{}", shot.log);
    let finals = pairs(finals[0]);
    assert!(finals.len() >= 6, "{finals:?}");
    let out =
        multibody(&dir, &["run", &folder, "--analysis", "OneAxisRun", "--out", "unchanged.csv", "--signals", "*"]);
    assert_eq!(code(&out), 0, "{}", stderr(&out));
    let unchanged = Table::load(&dir.join("unchanged.csv"));
    let (mut worst, mut change): (f64, f64) = (0.0, 0.0);
    for (name, value) in &finals {
        let scale = |x: f64| x.abs().max(1.0);
        let expected = *reference.column(name).last().unwrap();
        worst = worst.max((value - expected).abs() / scale(expected));
        let before = *unchanged.column(name).last().unwrap();
        change = change.max((value - before).abs() / scale(before));
    }
    // The WebAssembly engine's math library rounds sines and powers apart
    // from the native one's: the steps part, and the two runs agree to the
    // run's accuracy (tolerance 1e-8), not to the bit; the gain's own
    // effect is far larger.
    eprintln!("one axis with kp = 8: worst relative difference to the command {worst:.1e} (allowed 1e-5); kp = 5 -> 8 changes the end by {change:.1e}");
    assert!(worst <= 1e-5, "the page's final state differs from the command's by {worst:e}");
    assert!(change > 1e-3, "the changed gain shows: {change:e}");
}
