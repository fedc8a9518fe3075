//! The animation page in headless Chromium: it renders, moves, shows no
//! errors, hides what `render = false` hides, and copes with 100 bodies.
//!
//! Needs `/usr/bin/chromium`: run `scripts/install-test-deps.sh` first.
//! WebGL runs on SwiftShader (see `common/browser.rs` for the flags).

mod common;

use common::browser::screenshot;
use common::models::{self, Block};
use common::pixels::{is_green, is_magenta, is_purple, is_red};
use multibody::Solution;
use multibody_view::{write_animation, AnimationOptions};
use std::path::PathBuf;

fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("pages");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

const VIEW: (u32, u32) = (640, 480);

/// The double pendulum at t = 0 (both boxes along +x) and at t = 0.5 s
/// (swung down): the picture is drawn, y is up, the boxes moved down, and
/// the full page (controls and plots) logs no error.
#[test]
fn double_pendulum_page_renders_moves_and_logs_no_errors() {
    let mechanism = models::double_pendulum();
    let solution = models::simulate(&mechanism, 2.0);
    let page = scratch("double_pendulum.html");
    let summary =
        write_animation(&page, "Double pendulum", &mechanism.shapes(), &solution, &AnimationOptions::default())
            .unwrap();
    assert_eq!(summary.signals, ["revolute1.phi", "revolute2.phi", "revolute1.w", "revolute2.w"]);

    let start = screenshot(&page, "t=0&panel=0", VIEW, "double_pendulum_t0");
    let later = screenshot(&page, "t=0.5&panel=0", VIEW, "double_pendulum_t05");
    for shot in [&start, &later] {
        shot.assert_clean();
        assert_eq!((shot.image.width, shot.image.height), VIEW);
        let drawn = shot.image.drawn_fraction();
        assert!(drawn > 0.01, "the view is blank: {:.2}% drawn", drawn * 100.0);
        assert!(shot.image.colours() > 50, "too few colours for a lit scene: {}", shot.image.colours());
    }
    let changed = start.image.changed_fraction(&later.image);
    assert!(changed > 0.003, "the picture did not change between t = 0 and 0.5 s: {:.3}%", changed * 100.0);

    // y is up: the world's green y arrow is above its red x arrow.
    let (greens, _, green_y) = start.image.find(is_green);
    let (reds, _, red_y) = start.image.find(is_red);
    assert!(greens > 50 && reds > 50, "world axes missing: {greens} green, {reds} red pixels");
    assert!(green_y < red_y - 20.0, "the y axis is not drawn upwards: green at row {green_y}, red at {red_y}");
    // The purple boxes swing down (rows grow downwards).
    let (p0, _, y0) = start.image.find(is_purple);
    let (p1, _, y1) = later.image.find(is_purple);
    assert!(p0 > 100 && p1 > 100, "the boxes are missing: {p0} and {p1} purple pixels");
    assert!(y1 > y0 + 40.0, "the boxes did not swing down: mean row {y0} at t = 0, {y1} at t = 0.5 s");

    let full = screenshot(&page, "t=0.5", (1200, 700), "double_pendulum_full");
    full.assert_clean();
    assert!(full.image.drawn_fraction() > 0.05);
}

/// `render = false` on a pure magenta body takes it out of the picture; a
/// control run with `render = true` shows it.
#[test]
fn render_false_hides_the_body() {
    let mut counts = Vec::new();
    for render in [true, false] {
        let mechanism = models::magenta_double_pendulum(render);
        let solution = models::simulate(&mechanism, 1.0);
        let page = scratch(&format!("magenta_{render}.html"));
        write_animation(&page, "magenta", &mechanism.shapes(), &solution, &AnimationOptions::default()).unwrap();
        let shot = screenshot(&page, "t=0.3&panel=0", VIEW, &format!("magenta_{render}"));
        shot.assert_clean();
        assert!(shot.image.drawn_fraction() > 0.005, "the view is blank (render = {render})");
        counts.push(shot.image.find(is_magenta).0);
        eprintln!("render = {render}: {} magenta pixels", counts.last().unwrap());
    }
    assert!(counts[0] > 300, "the magenta body is not drawn with render = true: {} pixels", counts[0]);
    assert_eq!(counts[1], 0, "the magenta body is drawn although render = false");
}

/// The motion of a 100-link chain for 10 s, prescribed by forward
/// kinematics (the engine takes minutes for this run in a debug build; the
/// view only reads frames' `r_0` and `R`, which this fills exactly as a
/// simulation would). Shapes come from the real assembled model.
fn chain_solution(n: usize, stop: f64, dt: f64) -> Solution {
    let mut names = Vec::new();
    let mut units = Vec::new();
    let frame = |names: &mut Vec<String>, units: &mut Vec<&'static str>, f: &str| {
        for i in 1..=3 {
            names.push(format!("{f}.r_0[{i}]"));
            units.push("m");
        }
        for i in 1..=3 {
            for j in 1..=3 {
                names.push(format!("{f}.R[{i},{j}]"));
                units.push("");
            }
        }
    };
    frame(&mut names, &mut units, "world.frame_b");
    for k in 1..=n {
        for f in [format!("rev{k}.frame_a"), format!("body{k}.frame_a"), format!("rod{k}.frame_a")] {
            frame(&mut names, &mut units, &f);
        }
        names.push(format!("rev{k}.phi"));
        units.push("rad");
    }
    let mut solution = Solution::new(names, units);
    let steps = (stop / dt).round() as usize;
    let pose = |row: &mut Vec<f64>, p: [f64; 3], theta: f64| {
        let (s, c) = theta.sin_cos();
        row.extend_from_slice(&p);
        row.extend_from_slice(&[c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0]);
    };
    for step in 0..=steps {
        let t = step as f64 * dt;
        let mut row = Vec::new();
        pose(&mut row, [0.0; 3], 0.0);
        let (mut p, mut theta) = ([0.0; 3], 0.0);
        for k in 1..=n {
            let phi = if k == 1 {
                -std::f64::consts::FRAC_PI_2 + 0.8 * (1.5 * t).sin()
            } else {
                0.06 * (2.0 * t - 0.2 * k as f64).sin()
            };
            pose(&mut row, p, theta);
            theta += phi;
            pose(&mut row, p, theta);
            pose(&mut row, p, theta);
            row.push(phi);
            p = [p[0] + 0.05 * theta.cos(), p[1] + 0.05 * theta.sin(), 0.0];
        }
        solution.push(t, &row);
    }
    solution
}

/// A 100-body chain over 10 s: the page stays small enough, loads without
/// errors and draws a frame fast enough to play (measured in the page over
/// 20 frames; software rendering here, a GPU is far faster).
#[test]
fn hundred_body_page_loads_and_draws_quickly() {
    let mechanism = models::chain(100);
    let solution = chain_solution(100, 10.0, 0.01);
    let page = scratch("chain100.html");
    let summary =
        write_animation(&page, "100-link chain", &mechanism.shapes(), &solution, &AnimationOptions::default()).unwrap();
    eprintln!(
        "100-body page: {:.2} MB, {} frames, {} poses, {} shapes",
        summary.bytes as f64 / 1e6,
        summary.frames,
        summary.poses,
        summary.shapes
    );
    assert!(summary.left_out.is_empty(), "{:?}", summary.left_out);
    assert_eq!(summary.frames, 301);
    assert!(summary.bytes < 8_000_000, "the page is {} bytes", summary.bytes);

    let shot = screenshot(&page, "t=5&panel=0&bench=20", VIEW, "chain100");
    shot.assert_clean();
    assert!(shot.image.drawn_fraction() > 0.01, "the view is blank");
    let bench = shot
        .console()
        .iter()
        .find_map(|l| l.split("ms_per_frame=").nth(1).and_then(|s| s.split_whitespace().next()?.parse::<f64>().ok()))
        .expect("the page logged its frame time");
    eprintln!("100-body page: {bench:.1} ms per frame (software WebGL)");
    assert!(bench < 1000.0, "a frame takes {bench} ms");
}

/// Every control, driven through DOM events in the page (play, pause,
/// slider, speed, loop, arrow key, seeking in a plot, pan, orbit, zoom,
/// reset), does what it should without an error; and a page that throws is
/// caught by these checks.
#[test]
fn controls_work_and_errors_are_caught() {
    let mechanism = models::pendulum();
    let solution = models::simulate(&mechanism, 2.0);
    let page = scratch("pendulum.html");
    write_animation(&page, "Pendulum", &mechanism.shapes(), &solution, &AnimationOptions::default()).unwrap();
    let shot = screenshot(&page, "t=0.5&exercise=1", (1000, 600), "pendulum_exercise");
    shot.assert_clean();
    let line = shot.console().into_iter().find(|l| l.contains("multibody-view: exercised")).map(str::to_string);
    let line = line.unwrap_or_else(|| panic!("the controls were not exercised:\n{}", shot.log));
    for check in ["play", "pause", "slider", "speed", "loop", "key", "plotSeek", "pan", "rotate", "zoom", "reset"] {
        assert!(line.contains(check), "`{check}` was not exercised: {line}");
    }
    assert!(line.contains("all ok"), "{line}");

    let html = std::fs::read_to_string(&page).unwrap();
    let broken = scratch("broken.html");
    let marker = "window.requestAnimationFrame(tick);\n})();";
    assert!(html.contains(marker));
    std::fs::write(&broken, html.replace(marker, "window.requestAnimationFrame(tick);\n  null.boom;\n})();")).unwrap();
    let shot = screenshot(&broken, "t=0.5", (800, 500), "broken");
    let caught = std::panic::catch_unwind(|| shot.assert_clean()).is_err();
    assert!(caught, "an uncaught exception went unnoticed:\n{}", shot.log);
}

/// A mesh file drawn by a ShapefileVisualizer (read from a relative path in
/// the page's mesh folder, scaled and turned by its parameters, on a moving
/// frame) covers the same pixels as the BoxShape primitive of the block the
/// file's geometry makes; with `render = false` it is not drawn.
#[test]
fn mesh_file_is_drawn_where_its_geometry_puts_it() {
    let dir = scratch("mesh_block");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("box.stl"), models::box_stl(0.5, 0.15, 0.15)).unwrap();
    let options = AnimationOptions { mesh_folder: Some(dir.clone()), ..Default::default() };
    let mut found = Vec::new();
    for block in [Block::Primitive, Block::Mesh { render: true }, Block::Mesh { render: false }] {
        let mechanism = models::mesh_or_box(block);
        let solution = models::simulate(&mechanism, 0.2);
        let name = format!("{block:?}").replace([' ', '{', '}', ':'], "");
        let page = dir.join(format!("{name}.html"));
        let summary = write_animation(&page, "mesh", &mechanism.shapes(), &solution, &options).unwrap();
        assert!(summary.left_out.is_empty(), "{:?}", summary.left_out);
        let shot = screenshot(&page, "t=0&panel=0", VIEW, &format!("mesh_{name}"));
        shot.assert_clean();
        assert!(shot.image.drawn_fraction() > 0.005, "the view is blank ({block:?})");
        let (n, x, y) = shot.image.find(is_magenta);
        eprintln!("{block:?}: {n} magenta pixels around ({x:.1}, {y:.1})");
        found.push((n, x, y));
    }
    let [(n_box, x_box, y_box), (n_mesh, x_mesh, y_mesh), (n_hidden, _, _)] = found[..] else { unreachable!() };
    assert!(n_box > 500, "the reference box is too small to compare: {n_box} pixels");
    let ratio = n_mesh as f64 / n_box as f64;
    assert!((0.93..1.07).contains(&ratio), "the mesh covers {n_mesh} pixels, the box {n_box}");
    assert!(
        (x_mesh - x_box).abs() < 2.0 && (y_mesh - y_box).abs() < 2.0,
        "the mesh is around ({x_mesh:.1}, {y_mesh:.1}), the box around ({x_box:.1}, {y_box:.1})"
    );
    assert_eq!(n_hidden, 0, "the mesh is drawn although render = false");
}

/// The Panda of example-robot-data (from PyPI, fetched by
/// scripts/fetch-robots.sh; skipped without it), read from its URDF with
/// its meshes (Collada files found through `package://`), painted magenta:
/// the page draws the robot from the meshes alone (nothing else of the
/// scene is magenta), and draws nothing magenta with the meshes left out.
#[test]
fn the_panda_is_drawn_with_its_meshes() {
    use multibody_dyad::urdf::{self, Geometry, ImportOptions, MeshSearch};
    let robots = std::env::var_os("MULTIBODY_ROBOTS")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/robots"));
    let path = robots.join("example-robot-data/panda_description/urdf/panda.urdf");
    let Ok(text) = std::fs::read_to_string(&path) else {
        println!("skipped: no {} (scripts/fetch-robots.sh fetches it)", path.display());
        return;
    };
    let mut found = Vec::new();
    for with_meshes in [true, false] {
        let mut robot = urdf::parse(&text).unwrap();
        let search = MeshSearch { urdf_folder: path.parent().unwrap().into(), package_dirs: Vec::new() };
        let missing = urdf::resolve_meshes(&mut robot, &search);
        assert!(
            missing.is_empty(),
            "{:?}",
            missing.iter().map(|m| m.render("panda.urdf", "error")).collect::<Vec<_>>()
        );
        let mut meshes = 0;
        for link in &mut robot.links {
            link.visuals.retain(|v| with_meshes || !matches!(v.geometry, Geometry::Mesh { .. }));
            for visual in &mut link.visuals {
                visual.color = Some([1.0, 0.0, 1.0, 1.0]);
                meshes += matches!(visual.geometry, Geometry::Mesh { .. }) as usize;
            }
        }
        assert_eq!(meshes, if with_meshes { 11 } else { 0 }, "the Panda has 11 visual meshes");
        let dyad = urdf::to_dyad(&robot, "panda.urdf", &ImportOptions::default());
        let mut package = multibody_dyad::Package::new();
        package.add_source("panda.dyad", dyad).unwrap();
        let target = package.choose_target(None, None).unwrap();
        let mechanism = package.lower_target(&target, &[]).unwrap().assemble().unwrap();
        let solution = models::simulate(&mechanism, 0.2);
        let page = scratch(&format!("panda_{with_meshes}.html"));
        // URDF's z up, drawn up.
        let options = AnimationOptions { up: AnimationOptions::up_of(&mechanism), ..Default::default() };
        assert_eq!(options.up, [0.0, 0.0, 1.0]);
        let summary = write_animation(&page, "Panda", &mechanism.shapes(), &solution, &options).unwrap();
        assert!(summary.left_out.is_empty(), "{:?}", summary.left_out);
        let shot = screenshot(&page, "t=0&panel=0", VIEW, &format!("panda_{with_meshes}"));
        shot.assert_clean();
        let (n, x, y) = shot.image.find(is_magenta);
        println!(
            "Panda {}: {n} magenta pixels around ({x:.0}, {y:.0})",
            if with_meshes { "with meshes" } else { "without" }
        );
        found.push(n);
    }
    assert!(found[0] > 3000, "the Panda's meshes cover only {} pixels of {}x{}", found[0], VIEW.0, VIEW.1);
    // Without the meshes only the shading of the bodies' default (purple)
    // spheres passes for magenta here and there.
    assert!(found[1] * 50 < found[0], "{} magenta pixels without the meshes: the count is not the meshes'", found[1]);
}
