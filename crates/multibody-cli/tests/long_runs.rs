//! Long runs: memory stays bounded (results stream to disk), and Ctrl-C
//! stops a run cleanly, keeping what it computed.
//!
//! One test, so that no other test's processes run meanwhile: the peak
//! memory is read from the kernel's account of this process's children.

mod common;

use common::{crate_path, scratch, Table};
use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Command, Stdio};

/// The largest peak resident memory of the children waited for so far, in bytes.
fn children_peak_memory() -> f64 {
    // SAFETY: getrusage only writes into the struct it is given.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let status = unsafe { libc::getrusage(libc::RUSAGE_CHILDREN, &mut usage) };
    assert_eq!(status, 0);
    usage.ru_maxrss as f64 * 1024.0 // kilobytes on Linux
}

fn run(dir: &Path, args: &[&str]) -> std::process::Output {
    let o = Command::new(env!("CARGO_BIN_EXE_multibody")).args(args).current_dir(dir).output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
    o
}

/// Runs `command` in `dir`, expecting it to refuse before it starts
/// (exit 2); what it said.
fn refused(dir: &Path, mut command: Command) -> String {
    let o = command.current_dir(dir).env("NO_COLOR", "1").output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(2), "{err}");
    err
}

/// A chain of `n` revolute links with small bodies, written as a model file.
fn chain(dir: &Path, n: usize) -> String {
    let mut text = String::from("component Chain\n  world = World()\n");
    for i in 0..n {
        text += &format!("  j{i} = Revolute(n = [0, 0, 1])\n  b{i} = BodyShape(r = [0.01, 0, 0], m = 0.01)\n");
    }
    text += "relations\n  connect(world.frame_b, j0.frame_a)\n";
    for i in 0..n {
        text += &format!("  connect(j{i}.frame_b, b{i}.frame_a)\n");
        if i + 1 < n {
            text += &format!("  connect(b{i}.frame_b, j{}.frame_a)\n", i + 1);
        }
    }
    text += "end\n";
    let path = dir.join(format!("chain{n}.dyad"));
    std::fs::write(&path, text).unwrap();
    path.display().to_string()
}

#[test]
fn memory_stays_bounded_and_ctrl_c_keeps_the_results() {
    let dir = scratch("long-runs");
    let pendulum = crate_path("../../examples/pendulum.dyad");

    // Every signal, streamed: 20 times longer costs no more memory.
    run(&dir, &["run", &pendulum, "--stop", "1", "--saveat", "1e-3", "--out", "short.csv"]);
    let short = children_peak_memory();
    run(&dir, &["run", &pendulum, "--stop", "20", "--saveat", "1e-3", "--out", "long.csv"]);
    let long = children_peak_memory();
    let table = Table::load(&dir.join("long.csv"));
    assert_eq!(table.time.len(), 20001);
    // Kept in memory, the long run's samples alone would take 16 MB.
    let held = 20001.0 * (table.names.len() + 1) as f64 * 8.0;
    println!(
        "pendulum, all {} signals: peak {:.1} MB for 1 s, {:.1} MB for 20 s (holding them: +{:.1} MB)",
        table.names.len(),
        short / 1e6,
        long / 1e6,
        held / 1e6
    );
    assert!(long - short < 0.25 * held, "memory grew with the run: {short} -> {long} bytes");

    // A sweep streams its table run by run (issue 26: a sweep of 1000 runs
    // kept every run's samples and died under 2 GB). 100 runs of 100001
    // samples of the states, held, would take 240 MB.
    let o = run(
        &dir,
        &["sweep", &pendulum, "--param", "body.m=0.1:0.1:10", "--stop", "10", "--saveat", "1e-4", "--out", "sweep.csv"],
    );
    let peak = children_peak_memory();
    println!("sweep of 100 runs × 100001 samples: peak {:.1} MB", peak / 1e6);
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("100 runs of 100 ran"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(peak < 100e6, "peak memory {peak} bytes");

    // The hostile review's run: 2000 bodies, 1 s, 10001 samples of one signal.
    let model = chain(&dir, 2000);
    let o = run(&dir, &["run", &model, "--stop", "1", "--saveat", "1e-4", "--signals", "j0.phi", "--out", "chain.csv"]);
    let peak = children_peak_memory();
    println!("2000-body chain, 1 s, --saveat 1e-4 --signals j0.phi: peak {:.1} MB", peak / 1e6);
    assert!(String::from_utf8_lossy(&o.stderr).contains("10001 samples × 1 signal"));
    assert!(peak < 200e6, "peak memory {peak} bytes");

    // Every signal of a 1000-body chain (99018 and time) as Parquet: the
    // columns are encoded one at a time. With an encoder per column the
    // writer's state alone took 6.5 kB a column: a peak of 664 MB, where
    // the same run to CSV peaks at 66 MB.
    let wide = chain(&dir, 1000);
    let o = run(&dir, &["run", &wide, "--stop", "0.01", "--saveat", "1e-3", "--out", "wide.parquet"]);
    let peak = children_peak_memory();
    println!("1000-body chain, every signal to Parquet: peak {:.1} MB", peak / 1e6);
    assert!(String::from_utf8_lossy(&o.stderr).contains("11 samples × 99018 signals"));
    assert!(peak < 300e6, "peak memory {peak} bytes");

    // The same table over 1001 samples, where the process may have 1 GB of
    // address space (`ulimit -v`): the footer the writer keeps grows with
    // every row group, and the run was killed halfway (issue 26, a 2000-body
    // chain under 2 GB). It is refused before it starts, with the estimate
    // and the budget, which counts the limit.
    let mut limited = Command::new("sh");
    limited.args(["-c", "ulimit -v 1000000 && exec \"$0\" \"$@\"", env!("CARGO_BIN_EXE_multibody")]).args([
        "run",
        &wide,
        "--stop",
        "0.1",
        "--saveat",
        "1e-4",
        "--out",
        "limited.parquet",
    ]);
    let err = refused(&dir, limited);
    assert!(err.contains("writing Parquet of 99019 columns would hold about 1.0 GB in memory (1001 samples)"), "{err}");
    assert!(err.contains("more than the 512.0 MB this run may use"), "{err}");
    assert!(!dir.join("limited.parquet").exists());

    // A run the views cannot hold is refused before it starts, naming the budget.
    let mut views = Command::new(env!("CARGO_BIN_EXE_multibody"));
    views.args(["run", &model, "--stop", "1", "--saveat", "1e-9", "--animate", "chain.html", "--out", "never.csv"]);
    let err = refused(&dir, views);
    assert!(err.contains("the animation and plot need every signal in memory"), "{err}");
    assert!(!dir.join("never.csv").exists());

    // Ctrl-C: stops after the current step, writes what was computed as partial, exits 130.
    let mut child = Command::new(env!("CARGO_BIN_EXE_multibody"))
        .args(["run", &pendulum, "--stop", "1e9", "--saveat", "0", "--signals", "rev.phi", "--out", "endless.csv"])
        .current_dir(&dir)
        .env("NO_COLOR", "1")
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stderr = BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    while !line.contains("degree") {
        line.clear();
        assert!(stderr.read_line(&mut line).unwrap() > 0, "the run ended before it started");
    }
    std::thread::sleep(std::time::Duration::from_millis(500));
    let killed = Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap();
    assert!(killed.success());
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut stderr, &mut rest).unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130), "{rest}");
    assert!(rest.contains("interrupted (Ctrl-C"), "{rest}");
    assert!(rest.contains("endless.partial.csv"), "{rest}");
    let table = Table::load(&dir.join("endless.partial.csv"));
    assert!(table.time.len() > 100, "{} samples kept", table.time.len());
    assert!(!dir.join("endless.csv").exists());
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect();
    assert!(left.is_empty(), "temporary files left: {left:?}");
}
