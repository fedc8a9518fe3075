//! `multibody live`: a page that runs the model itself, with a panel of
//! its values (the engine compiled to WebAssembly, embedded).

use crate::exit::Failure;
use crate::load::{assemble, choose, lower, overrides, read_package};
use crate::output::{self, bytes};
use crate::run::{chosen_signals, command_line_options};
use crate::LiveArgs;
use std::path::{Path, PathBuf};

/// The module's file name, as `scripts/build-web.sh` builds it.
const MODULE: &str = "multibody_web.wasm";

pub fn live(args: &LiveArgs) -> Result<(), Failure> {
    output::outputs_are_safe(&args.selection.files, &[("--out", Some(&args.out))])?;
    let wasm_path = module_path(args.wasm.as_deref())?;
    if output::same_file(&args.out, &wasm_path) {
        return Err(Failure::Usage(format!(
            "`--out {}`: it would write over the WebAssembly module the page is built from; choose another path \
             for the page",
            args.out.display()
        )));
    }
    let package = read_package(&args.selection.files)?;
    let target = choose(&package, &args.selection)?;
    let overrides = overrides(&args.values.params, &args.values.initials)?;
    let lowered = lower(&package, &target, &overrides)?;
    let options = command_line_options(
        &crate::OptionArgs { stop: args.stop, saveat: None, abstol: None, reltol: None, alg: None },
        &lowered.options,
    )?;
    let mechanism = assemble(&package, &target, &overrides, &lowered)?;
    chosen_signals(&mechanism, &args.signals)?;
    // The page holds every signal of its first run: refused before the run
    // when that cannot fit (a 2000-body chain to --stop 1e6 grew past 11 GB).
    if let Some(samples) = multibody_dyad::study::grid_samples(&options) {
        let (needed, budget) =
            (samples * (mechanism.signals().len() + 1) as f64 * 8.0, output::Budget::of_this_machine());
        if needed > budget.memory {
            return Err(Failure::Usage(format!(
                "the page holds every signal of its first run: {samples:.0} samples × {} signals take {}, more than \
                 the {} this command may use (half the memory available); shorten --stop, or give the analysis a \
                 longer saveat",
                mechanism.signals().len(),
                bytes(needed),
                bytes(budget.memory)
            )));
        }
    }
    let wasm = std::fs::read(&wasm_path)
        .map_err(|e| Failure::Io(format!("cannot read the WebAssembly module {}: {e}", wasm_path.display())))?;
    if !wasm.starts_with(b"\0asm") {
        return Err(Failure::Usage(format!(
            "{} is not a WebAssembly module; rebuild it with scripts/build-web.sh",
            wasm_path.display()
        )));
    }

    // The first run, shown until the page has run the model itself; a model
    // that cannot run is refused here, before any file is written.
    say!("Running {} for the page's first view", lowered.name);
    let solution = mechanism.simulate(&options).map_err(|stopped| {
        let reason = lowered.with_places(package.sources(), &stopped.reason);
        Failure::Usage(format!("the simulation stopped at t = {}: {reason}", crate::run::number(stopped.time)))
    })?;
    let model = multibody_view::LiveModel {
        files: package.user_files(),
        analysis: args.selection.analysis.clone(),
        model: args.selection.model.clone(),
        params: args.values.params.clone(),
        initials: args.values.initials.clone(),
        stop: args.stop,
    };
    let view = multibody_view::AnimationOptions {
        signals: args.signals.clone(),
        up: multibody_view::AnimationOptions::up_of(&mechanism),
        ..Default::default()
    };
    let page = multibody_view::live_html(&lowered.name, &mechanism.shapes(), &solution, &view, &model, &wasm)
        .map_err(|e| Failure::Usage(e.to_string()))?;
    output::write_atomically(&args.out, |w| w.write_all(page.html.as_bytes()))?;
    say!(
        "  live page: {} values in the panel, {} shapes → {} ({}; open it in a browser, it works offline)",
        lowered.tunables.len(),
        page.summary.shapes,
        args.out.display(),
        bytes(page.summary.bytes as f64)
    );
    Ok(())
}

/// Where the WebAssembly module is: `--wasm`, else `$MULTIBODY_WASM`, else
/// where `scripts/build-web.sh` puts it beside this command's build
/// (`target/wasm32-unknown-unknown/web/`) or beside the command itself.
fn module_path(given: Option<&Path>) -> Result<PathBuf, Failure> {
    if let Some(path) = given.map(Path::to_path_buf).or_else(|| std::env::var_os("MULTIBODY_WASM").map(PathBuf::from)) {
        return if path.is_file() {
            Ok(path)
        } else {
            Err(Failure::Usage(format!("the WebAssembly module {} does not exist", path.display())))
        };
    }
    let exe = std::env::current_exe().ok();
    let dir = exe.as_deref().and_then(Path::parent);
    let mut candidates = Vec::new();
    if let Some(dir) = dir {
        candidates.push(dir.join(MODULE));
        if let Some(target) = dir.parent() {
            candidates.push(target.join("wasm32-unknown-unknown/web").join(MODULE));
        }
    }
    candidates.into_iter().find(|p| p.is_file()).ok_or_else(|| {
        Failure::Usage(
            "the live page needs the engine compiled to WebAssembly, which is not built: run scripts/build-web.sh \
             (it adds Rust's wasm32 target and builds it), or give its path with --wasm FILE or MULTIBODY_WASM"
                .into(),
        )
    })
}
