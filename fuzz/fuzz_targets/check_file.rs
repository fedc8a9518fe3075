//! Any bytes as a whole model file, read as `multibody check` reads one: a
//! Dyad file, or a URDF robot (text that starts with `<`) imported first;
//! then, for every analysis and component, lower, assemble, evaluate the
//! right-hand side at the start, explain a failure with its places, and
//! build what `check` prints (states, loops, orientation owners, signals)
//! and a robot's joint space. Nothing may panic, overflow or hang.
#![no_main]

mod front_end;

use libfuzzer_sys::fuzz_target;
use multibody::JointSpace;
use multibody_dyad::urdf::{self, ImportOptions};
use std::sync::Arc;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let dyad;
    let text = if text.trim_start().starts_with('<') {
        let robot = match urdf::parse(text) {
            Ok(robot) => robot,
            Err(e) => {
                let _ = e.render("fuzz.urdf");
                return;
            }
        };
        for floating in [false, true] {
            let _ = urdf::to_dyad(&robot, "fuzz.urdf", &ImportOptions { floating, ..Default::default() });
        }
        dyad = urdf::to_dyad(&robot, "fuzz.urdf", &ImportOptions::default());
        dyad.as_str()
    } else {
        text
    };
    front_end::each_lowered(text, |package, lowered| {
        let mechanism = match lowered.assemble() {
            Ok(mechanism) => mechanism,
            Err(d) => {
                let _ = d.render(package.sources(), false);
                return;
            }
        };
        let y = mechanism.states().start.clone();
        let mut dy = vec![0.0; y.len()];
        if let Err(e) = mechanism.rhs(&mut mechanism.workspace(), lowered.options.start, &y, &mut dy) {
            let _ = lowered.with_places(package.sources(), &mechanism.describe(&e));
        }
        let _ = (mechanism.loops().len(), mechanism.orientation_owners(), mechanism.warnings().len());
        let names: Vec<String> = mechanism.signals().into_iter().map(|s| s.name).collect();
        if let Ok(mut space) = JointSpace::new(Arc::new(mechanism)) {
            let nq = space.coordinates().len();
            let nv = space.velocities().len();
            let q = y[..nq].to_vec();
            let mut m = vec![0.0; nv * nv];
            let _ = space.mass_matrix(&q, &mut m);
            for name in names.iter().take(4) {
                let _ = space.frame_pose(name.split('.').next().unwrap_or(""), &q);
            }
        }
    });
});
