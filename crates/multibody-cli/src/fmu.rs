//! `multibody fmu`: the model as an FMI 2.0 or 3.0 FMU (model exchange,
//! co-simulation or both). Nothing is compiled: the prebuilt runtime
//! library, the model files and their description are zipped.

use crate::exit::Failure;
use crate::load::{assemble, choose, lower, read_package};
use crate::output::{self, bytes};
use crate::FmuArgs;
use multibody_fmu::model::Causality;
use multibody_fmu::{Export, Kinds, Version};
use std::path::{Path, PathBuf};

/// The runtime's file name, as cargo builds it.
const RUNTIME: &str = if cfg!(target_os = "windows") {
    "multibody_fmu.dll"
} else if cfg!(target_os = "macos") {
    "libmultibody_fmu.dylib"
} else {
    "libmultibody_fmu.so"
};

pub fn fmu(args: &FmuArgs) -> Result<(), Failure> {
    let started = std::time::Instant::now();
    let kinds = match args.kind.as_deref() {
        None => None,
        Some("me") => Some(Kinds { model_exchange: true, co_simulation: false }),
        Some("cs") => Some(Kinds { model_exchange: false, co_simulation: true }),
        Some("both") => Some(Kinds { model_exchange: true, co_simulation: true }),
        Some(other) => {
            return Err(Failure::Usage(format!(
                "`--kind {other}`: write me (model exchange), cs (co-simulation) or both"
            )))
        }
    };
    // The model is checked (its errors shown at their place) before any file is written.
    let package = read_package(&args.selection.files)?;
    let target = choose(&package, &args.selection)?;
    let lowered = lower(&package, &target, &[])?;
    let version = match args.fmi.as_deref() {
        None => None,
        Some("2" | "2.0") => Some(Version::Fmi2),
        Some("3" | "3.0") => Some(Version::Fmi3),
        Some(other) => return Err(Failure::Usage(format!("`--fmi {other}`: write 2 or 3"))),
    };
    let mechanism = assemble(&package, &target, &[], &lowered)?;
    let out = args.out.clone().unwrap_or_else(|| PathBuf::from(format!("{}.fmu", lowered.name)));
    output::outputs_are_safe(&args.selection.files, &[("--out", Some(&out))])?;
    let runtime_path = runtime_path(args.runtime.as_deref())?;
    let runtime = std::fs::read(&runtime_path)
        .map_err(|e| Failure::Io(format!("cannot read the FMU runtime {}: {e}", runtime_path.display())))?;
    if !runtime.starts_with(b"\x7fELF") && !runtime.starts_with(b"MZ") && !runtime.starts_with(&[0xcf, 0xfa]) {
        return Err(Failure::Usage(format!(
            "{} is not a shared library; build the runtime with `cargo build --release -p multibody-fmu`",
            runtime_path.display()
        )));
    }
    for w in mechanism.warnings() {
        say!("warning: {w}");
    }
    let export = Export::prepare(
        &package.user_files(),
        args.selection.analysis.clone(),
        args.selection.model.clone(),
        args.outputs.clone(),
        kinds,
        version,
    )
    .map_err(Failure::Usage)?;
    for w in &export.loaded.warnings {
        say!("warning: {w}");
    }
    let archive = export.archive(&runtime).map_err(Failure::Io)?;
    output::write_atomically(&out, |w| w.write_all(&archive))?;
    let interface = &export.loaded.interface;
    let count = |c: Causality| interface.variables.iter().filter(|v| v.causality == c).count();
    say!(
        "FMU (FMI {}, {}) of {}: {} variables: {} states, {} inputs, {} outputs, {} parameters, {} event \
         indicators → {} ({}, {:.0} ms)",
        if export.version == Version::Fmi3 { "3.0" } else { "2.0" },
        match (export.kinds.model_exchange, export.kinds.co_simulation) {
            (true, true) => "model exchange and co-simulation",
            (true, false) => "model exchange",
            _ => "co-simulation",
        },
        lowered.name,
        interface.variables.len(),
        interface.states.len(),
        count(Causality::Input),
        count(Causality::Output),
        count(Causality::Parameter),
        interface.indicators.len(),
        out.display(),
        bytes(archive.len() as f64),
        started.elapsed().as_secs_f64() * 1e3
    );
    Ok(())
}

/// Where the runtime library is: `--runtime`, else `$MULTIBODY_FMU_RUNTIME`,
/// else beside this command (cargo builds both into one folder).
fn runtime_path(given: Option<&Path>) -> Result<PathBuf, Failure> {
    if let Some(path) =
        given.map(Path::to_path_buf).or_else(|| std::env::var_os("MULTIBODY_FMU_RUNTIME").map(PathBuf::from))
    {
        return if path.is_file() {
            Ok(path)
        } else {
            Err(Failure::Usage(format!("the FMU runtime {} does not exist", path.display())))
        };
    }
    let exe = std::env::current_exe().ok();
    let beside = exe.as_deref().and_then(Path::parent).map(|dir| dir.join(RUNTIME));
    beside.filter(|p| p.is_file()).ok_or_else(|| {
        Failure::Usage(format!(
            "an FMU carries the runtime library {RUNTIME}, which is not built beside this command: run `cargo \
             build --release -p multibody-fmu`, or give its path with --runtime FILE or MULTIBODY_FMU_RUNTIME"
        ))
    })
}
