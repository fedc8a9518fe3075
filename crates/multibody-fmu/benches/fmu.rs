//! What an FMU of the double pendulum costs: exporting it (describing and
//! zipping, with the runtime library cargo built), and 5 s of
//! co-simulation through the C functions in steps of 10 ms reading four
//! variables each, beside the same run as `multibody run` computes it.

use criterion::{criterion_group, criterion_main, Criterion};
use multibody_fmu::fmi2::*;
use multibody_fmu::model::{MODEL_FOLDER, SETTINGS_FILE};
use multibody_fmu::Export;
use std::ffi::{c_uint, CString};
use std::path::PathBuf;

fn model() -> Vec<(String, String)> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/double_pendulum.dyad");
    vec![("double_pendulum.dyad".into(), std::fs::read_to_string(path).unwrap())]
}

fn export() -> Export {
    Export::prepare(&model(), None, None, Vec::new(), None, None).unwrap()
}

fn benches(c: &mut Criterion) {
    // The runtime cargo built beside the benchmark (target/release).
    let exe = std::env::current_exe().unwrap();
    let runtime = exe.parent().and_then(|d| d.parent()).map(|d| d.join("libmultibody_fmu.so"));
    let runtime = runtime.and_then(|p| std::fs::read(p).ok()).unwrap_or_else(|| vec![0; 24 << 20]);
    c.bench_function("fmu/export/double_pendulum", |b| b.iter(|| export().archive(&runtime).unwrap().len()));

    let e = export();
    let dir = std::env::temp_dir().join(format!("multibody-fmu-bench-{}", std::process::id()));
    let resources = dir.join("resources");
    std::fs::create_dir_all(resources.join(MODEL_FOLDER)).unwrap();
    std::fs::write(resources.join(SETTINGS_FILE), &e.settings_json).unwrap();
    for (name, text) in &e.files {
        std::fs::write(resources.join(MODEL_FOLDER).join(name), text).unwrap();
    }
    let vr: Vec<c_uint> = ["link1.joint.phi", "link2.joint.phi", "link1.joint.w", "link2.joint.w"]
        .iter()
        .map(|n| e.loaded.interface.variables.iter().position(|v| &v.name == n).unwrap() as c_uint)
        .collect();
    let (name, guid) = (CString::new("bench").unwrap(), CString::new(e.token.clone()).unwrap());
    let uri = CString::new(format!("file://{}", resources.display())).unwrap();
    c.bench_function("fmu/cosimulation/double_pendulum_5s", |b| {
        b.iter(|| unsafe {
            let fmu = fmi2Instantiate(name.as_ptr(), 1, guid.as_ptr(), uri.as_ptr(), std::ptr::null(), 0, 0);
            assert_eq!(fmi2SetupExperiment(fmu, 0, 0.0, 0.0, 1, 5.0), OK);
            assert_eq!(fmi2EnterInitializationMode(fmu), OK);
            assert_eq!(fmi2ExitInitializationMode(fmu), OK);
            let mut y = [0.0; 4];
            for k in 0..500 {
                assert_eq!(fmi2DoStep(fmu, k as f64 * 0.01, 0.01, 1), OK);
                assert_eq!(fmi2GetReal(fmu, vr.as_ptr(), 4, y.as_mut_ptr()), OK);
            }
            fmi2FreeInstance(fmu);
            y[0]
        })
    });
    let mechanism = e.loaded.mechanism.clone();
    let options = multibody::SimulationOptions { stop: 5.0, saveat: 0.01, ..e.loaded.options.clone() };
    c.bench_function("fmu/run/double_pendulum_5s", |b| b.iter(|| mechanism.simulate(&options).unwrap().len()));
    let _ = std::fs::remove_dir_all(dir);
}

criterion_group!(fmu, benches);
criterion_main!(fmu);
