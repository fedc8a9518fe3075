//! Reading model files into a package, and choosing what to run.

use crate::exit::{color, Failure};
use crate::Selection;
use multibody::files::{self, Fifo, OpenError, FIFO_WAIT};
use multibody_dyad::{Diagnostic, Lowered, Override, Package};
use std::path::{Path, PathBuf};

pub use multibody_dyad::Target;

/// Reads every file (folders: every `.dyad` file directly in them, sorted). Syntax
/// errors of all files are printed before failing.
pub fn read_package(paths: &[PathBuf]) -> Result<Package, Failure> {
    let mut files = Vec::new();
    for path in paths {
        if path.is_dir() {
            let before = files.len();
            collect_dyad_files(path, &mut files)?;
            if files.len() == before {
                return Err(Failure::Usage(format!("the folder {} has no .dyad files", path.display())));
            }
        } else {
            files.push(path.clone());
        }
    }
    // A file named twice (or through a folder and by itself) is one file.
    let mut seen = std::collections::HashSet::new();
    files.retain(|file| seen.insert(std::fs::canonicalize(file).unwrap_or_else(|_| file.clone())));
    let mut package = Package::new();
    let mut errors = Vec::new();
    for file in &files {
        let bytes = read_model_file(file)?;
        if crate::import::is_urdf(file) {
            // A robot: read as the model file `multibody import` writes.
            // Meshes are named from the URDF's folder, where the model is.
            let options = multibody_dyad::urdf::ImportOptions {
                mesh_base: file.parent().map(Path::to_path_buf),
                ..Default::default()
            };
            let meshes = crate::import::Meshes { package_dirs: &[], required: false, leave_out: false };
            let (_, dyad) = crate::import::urdf_as_dyad(file, bytes, &options, &meshes)?;
            if let Err(d) = package.add_source(format!("{}.dyad", named_folder(file).display()), dyad) {
                errors.push(d);
            }
            continue;
        }
        // Bytes that are not UTF-8 text are reported at their place, like syntax errors.
        if let Err(d) = package.add_source_bytes(named_folder(file).display().to_string(), bytes) {
            errors.push(d);
        }
    }
    if !errors.is_empty() {
        print_diagnostics(&package, &errors);
        return Err(Failure::Model);
    }
    Ok(package)
}

/// The path under which a file is added to the package: as typed, unless
/// it does not name the folder the file is in (`X.dyad`, `./X.dyad`,
/// `../X.dyad`, which `run .` gives too), then the full path. The folder's
/// name decides the library package (a file in `PlanarMechanics/` reads
/// short names as planar components), so it must be visible.
fn named_folder(file: &Path) -> PathBuf {
    let named = file.parent().and_then(Path::file_name).is_some();
    if named {
        return file.to_path_buf();
    }
    std::fs::canonicalize(file).unwrap_or_else(|_| file.to_path_buf())
}

/// The most a model file may hold: a model file is text, far smaller.
const MODEL_MAX_BYTES: u64 = 256 << 20;

/// The bytes of a model file, through [`multibody::files::read`]: a FIFO
/// is read once something writes to it, within `FIFO_WAIT` (with no
/// writer, opening it blocks for ever); a device (`/dev/zero`, a terminal)
/// or a socket is refused, for it would block or never end.
fn read_model_file(path: &Path) -> Result<Vec<u8>, Failure> {
    files::read(path, Fifo::Wait(FIFO_WAIT), MODEL_MAX_BYTES).map_err(|e| match e {
        OpenError::Io(e) => Failure::Io(format!("cannot read {}: {e}", path.display())),
        OpenError::NotAFile(kind) => Failure::Usage(format!(
            "{} is {}, not a model file; give the path of a .dyad file",
            path.display(),
            kind.describe()
        )),
        OpenError::NoWriter { waited } => Failure::Io(format!(
            "nothing writes to the FIFO {} (waited {} s); start the program that writes the model first, or give \
             the path of a .dyad file",
            path.display(),
            waited.as_secs()
        )),
        OpenError::TooLarge { .. } => Failure::Usage(format!(
            "{} holds more than {} MB, far more than a model file; give the path of a .dyad file",
            path.display(),
            MODEL_MAX_BYTES >> 20
        )),
    })
}

fn collect_dyad_files(dir: &Path, out: &mut Vec<PathBuf>) -> Result<(), Failure> {
    let entries = std::fs::read_dir(dir).map_err(|e| Failure::Io(format!("cannot read {}: {e}", dir.display())))?;
    let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    // Subfolders are separate packages (examples/msl holds models of the same names as examples).
    out.extend(paths.into_iter().filter(|p| p.is_file() && p.extension().is_some_and(|e| e == "dyad")));
    Ok(())
}

/// The analysis or component the selection names, or the only candidate.
pub fn choose(package: &Package, selection: &Selection) -> Result<Target, Failure> {
    package.choose_target(selection.analysis.as_deref(), selection.model.as_deref()).map_err(Failure::Usage)
}

/// Lowers the target with `overrides`, printing the warnings; errors are
/// printed too.
pub fn lower(package: &Package, target: &Target, overrides: &[Override]) -> Result<Lowered, Failure> {
    let lowered = package.lower_target(target, overrides);
    match lowered {
        Ok(l) => {
            let warnings: Vec<Diagnostic> =
                l.warnings.iter().filter(|d| !said_about_the_urdf(package, d)).cloned().collect();
            print_diagnostics(package, &warnings);
            Ok(l)
        }
        Err(d) => {
            if let Some(failure) = blame_an_override(package, target, overrides) {
                return Err(failure);
            }
            print_diagnostics(package, &[d]);
            Err(Failure::Model)
        }
    }
}

/// A warning about the model made of a URDF file that reading the URDF
/// gave already, at the link (an inertia no rigid body has).
fn said_about_the_urdf(package: &Package, d: &Diagnostic) -> bool {
    let made_of_urdf = |span: multibody_dyad::Span| {
        package.sources().name(span.file).strip_suffix(".dyad").is_some_and(|f| crate::import::is_urdf(Path::new(f)))
    };
    d.primary_span().is_some_and(made_of_urdf) && d.message.starts_with("no rigid mass distribution has the inertia")
}

/// Assembles the lowered model; a failure is blamed on a command-line
/// value where one caused it, else shown at its place in the files.
pub fn assemble(
    package: &Package,
    target: &Target,
    overrides: &[Override],
    lowered: &multibody_dyad::Lowered,
) -> Result<multibody::Mechanism, Failure> {
    lowered.assemble().map_err(|d| {
        if let Some(failure) = blame_an_override(package, target, overrides) {
            return failure;
        }
        print_diagnostics(package, &[d]);
        Failure::Model
    })
}

/// The failure of the one command-line value that spoils the model, if one does.
pub fn blame_an_override(package: &Package, target: &Target, overrides: &[Override]) -> Option<Failure> {
    package.blame_override(target, overrides).map(Failure::Usage)
}

/// `--param NAME=VALUE` and `--initial NAME=VALUE` as overrides, each value
/// a single number (for `run`).
pub fn overrides(params: &[String], initials: &[String]) -> Result<Vec<Override>, Failure> {
    multibody_dyad::study::parse_overrides(params, initials).map_err(Failure::Usage)
}

/// `body.m=2` as (`body.m`, `2`).
pub fn assignment<'t>(option: &str, text: &'t str) -> Result<(&'t str, &'t str), Failure> {
    multibody_dyad::study::split_assignment(option, text).map_err(Failure::Usage)
}

pub fn print_diagnostics(package: &Package, diagnostics: &[Diagnostic]) {
    for d in diagnostics {
        crate::console::say_text(&d.render(package.sources(), color()));
    }
}

/// The file a target is defined in, for the summary.
pub fn file_of(package: &Package, name: &str) -> String {
    package
        .definitions()
        .into_iter()
        .find(|d| d.name == name)
        .map(|d| package.sources().name(d.span.file).to_string())
        .unwrap_or_default()
}
