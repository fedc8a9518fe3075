//! Reading model files into a package, and choosing what to run.

use crate::exit::{color, Failure};
use crate::Selection;
use multibody_dyad::{diagnostics::did_you_mean, DefinitionKind, Diagnostic, Lowered, Override, Package};
use std::path::{Path, PathBuf};
use std::time::Duration;

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
    let mut package = Package::new();
    let mut errors = Vec::new();
    for file in &files {
        let bytes = read_model_file(file)?;
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

/// How long a FIFO (a named pipe, `/dev/stdin` from a pipe, `<(...)`) may
/// wait for the program that writes to it.
const FIFO_WAIT: Duration = Duration::from_secs(5);
/// The most a FIFO may give: a model file is text, far smaller.
const FIFO_MAX_BYTES: u64 = 256 << 20;

/// The bytes of a model file. A regular file is read; a FIFO is read once
/// something writes to it, within `FIFO_WAIT` (with no writer, opening it
/// blocks for ever) and up to `FIFO_MAX_BYTES`; a device (`/dev/zero`, a
/// terminal) or a socket is refused, for it would block or never end.
fn read_model_file(path: &Path) -> Result<Vec<u8>, Failure> {
    let cannot = |e: std::io::Error| Failure::Io(format!("cannot read {}: {e}", path.display()));
    let meta = std::fs::metadata(path).map_err(cannot)?;
    if meta.is_file() {
        return std::fs::read(path).map_err(cannot);
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let ty = meta.file_type();
        if ty.is_fifo() {
            return read_fifo(path);
        }
        let what = if ty.is_char_device() || ty.is_block_device() {
            "a device"
        } else if ty.is_socket() {
            "a socket"
        } else {
            "not a file"
        };
        Err(Failure::Usage(format!("{} is {what}, not a model file; give the path of a .dyad file", path.display())))
    }
    #[cfg(not(unix))]
    std::fs::read(path).map_err(cannot)
}

/// Reads a FIFO on a thread of its own, so that a FIFO nobody writes to
/// is given up after `FIFO_WAIT` instead of blocking the command for ever.
fn read_fifo(path: &Path) -> Result<Vec<u8>, Failure> {
    use std::io::Read;
    use std::sync::mpsc;
    let (opened, opened_here) = mpsc::channel();
    let (read, read_here) = mpsc::channel();
    let reading = path.to_path_buf();
    std::thread::spawn(move || {
        let file = std::fs::File::open(&reading);
        let _ = opened.send(());
        let bytes = file.and_then(|f| {
            let mut bytes = Vec::new();
            f.take(FIFO_MAX_BYTES + 1).read_to_end(&mut bytes).map(|_| bytes)
        });
        let _ = read.send(bytes);
    });
    if opened_here.recv_timeout(FIFO_WAIT).is_err() {
        // The thread stays blocked in open(); it ends with the command.
        return Err(Failure::Io(format!(
            "nothing writes to the FIFO {} (waited {} s); start the program that writes the model first, or give \
             the path of a .dyad file",
            path.display(),
            FIFO_WAIT.as_secs()
        )));
    }
    let bytes = read_here
        .recv()
        .unwrap_or_else(|_| Err(std::io::Error::other("the reading thread ended")))
        .map_err(|e| Failure::Io(format!("cannot read {}: {e}", path.display())))?;
    if bytes.len() as u64 > FIFO_MAX_BYTES {
        return Err(Failure::Usage(format!(
            "{} gave more than {} MB, far more than a model file; give the path of a .dyad file",
            path.display(),
            FIFO_MAX_BYTES >> 20
        )));
    }
    Ok(bytes)
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
    let definitions = package.definitions();
    let analyses: Vec<&str> =
        definitions.iter().filter(|d| d.kind == DefinitionKind::Analysis).map(|d| d.name.as_str()).collect();
    let components: Vec<&str> = definitions
        .iter()
        .filter(|d| matches!(d.kind, DefinitionKind::Component(_)))
        .map(|d| d.name.as_str())
        .collect();
    let missing = |what: &str, name: &str, names: &[&str]| {
        let mut message = format!("there is no {what} `{name}` in the files");
        if let Some(s) = did_you_mean(name, names.iter().copied()) {
            message.push_str(&format!("; {s}"));
        } else if !names.is_empty() {
            message.push_str(&format!(" (they define: {})", names.join(", ")));
        }
        Failure::Usage(message)
    };
    if let Some(name) = &selection.analysis {
        return if analyses.contains(&name.as_str()) {
            Ok(Target::Analysis(name.clone()))
        } else {
            Err(missing("analysis", name, &analyses))
        };
    }
    if let Some(name) = &selection.model {
        return if components.contains(&name.as_str()) {
            Ok(Target::Component(name.clone()))
        } else {
            Err(missing("component", name, &components))
        };
    }
    match analyses.as_slice() {
        [one] => return Ok(Target::Analysis(one.to_string())),
        [] => {}
        many => {
            return Err(Failure::Usage(format!(
                "the files have {} analyses ({}); choose one with --analysis NAME",
                many.len(),
                many.join(", ")
            )))
        }
    }
    let top: Vec<String> = package.top_components().into_iter().map(|d| d.name).collect();
    match top.as_slice() {
        [one] => Ok(Target::Component(one.clone())),
        [] => Err(Failure::Usage("the files define no analysis and no component to simulate".into())),
        many => Err(Failure::Usage(format!(
            "the files have no analysis; choose a component with --model NAME ({})",
            many.join(", ")
        ))),
    }
}

/// Lowers the target with `overrides`, printing the warnings; errors are
/// printed too.
pub fn lower(package: &Package, target: &Target, overrides: &[Override]) -> Result<Lowered, Failure> {
    let lowered = package.lower_target(target, overrides);
    match lowered {
        Ok(l) => {
            print_diagnostics(package, &l.warnings);
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

/// When the model lowers without the command line's values and not with
/// one of them, that value is the mistake: it is reported as the option
/// the user typed (`--param rev.phi=1`), not at a line of the files that
/// the user did not write it in.
pub fn blame_an_override(package: &Package, target: &Target, overrides: &[Override]) -> Option<Failure> {
    let assembled = |overrides: &[Override]| package.lower_target(target, overrides)?.assemble().map(|_| ());
    if overrides.is_empty() || assembled(&[]).is_err() {
        return None;
    }
    overrides.iter().find_map(|o| {
        let d = assembled(std::slice::from_ref(o)).err()?;
        let option = if o.initial { "--initial" } else { "--param" };
        let value = match &o.value {
            multibody_dyad::eval::Val::Number(x) => crate::run::number(*x),
            other => other.describe(),
        };
        // One line: the message, then what to do and the facts, each after `; `.
        let mut message = format!("`{option} {}={value}`: {}", o.path, d.message.trim_end_matches('.'));
        for more in d.help.iter().chain(&d.notes) {
            let more = more.trim_end_matches('.');
            let mut chars = more.chars();
            let lower = chars.next().map(|c| c.to_lowercase().chain(chars).collect::<String>()).unwrap_or_default();
            message.push_str(if message.ends_with('?') { " " } else { "; " });
            message.push_str(&lower);
        }
        Some(Failure::Usage(message))
    })
}

/// `--param NAME=VALUE` and `--initial NAME=VALUE` as overrides, each value
/// a single number (for `run`).
pub fn overrides(params: &[String], initials: &[String]) -> Result<Vec<Override>, Failure> {
    let mut out = Vec::new();
    for (option, given, initial) in [("--param", params, false), ("--initial", initials, true)] {
        for text in given {
            let (path, value) = assignment(option, text)?;
            let value: f64 = value.trim().parse().map_err(|_| {
                Failure::Usage(format!("`{option} {text}`: `{value}` is not a number (write {option} {path}=2.5)"))
            })?;
            out.push(if initial { Override::initial(path, value) } else { Override::parameter(path, value) });
        }
    }
    Ok(out)
}

/// `body.m=2` as (`body.m`, `2`).
pub fn assignment<'t>(option: &str, text: &'t str) -> Result<(&'t str, &'t str), Failure> {
    match text.split_once('=') {
        Some((path, value)) if !path.trim().is_empty() => Ok((path.trim(), value)),
        _ => Err(Failure::Usage(format!("`{option} {text}`: write NAME=VALUE, e.g. {option} body.m=2"))),
    }
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
