//! `multibody import robot.urdf`: a URDF robot as a Dyad model file whose
//! component names are the URDF's link and joint names; and the reading of
//! `.urdf` files that `run`, `check` and the other commands share.

use crate::exit::Failure;
use crate::output;
use crate::ImportArgs;
use multibody_dyad::urdf::{self, ImportOptions, Robot};
use std::path::{Path, PathBuf};

/// Whether `path` names a URDF file (by its extension).
pub fn is_urdf(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("urdf"))
}

/// The robot of a URDF file as Dyad text, the elements it did not map
/// said once each (with file:line:col) on stderr.
pub fn urdf_as_dyad(path: &Path, bytes: Vec<u8>, options: &ImportOptions) -> Result<(Robot, String), Failure> {
    let file = path.display().to_string();
    let text = String::from_utf8(bytes)
        .map_err(|e| Failure::Usage(format!("{file} is not UTF-8 text (byte {})", e.utf8_error().valid_up_to())))?;
    let robot = urdf::parse(&text).map_err(|e| {
        eprintln!("{}", e.render(&file));
        Failure::Model
    })?;
    for s in &robot.skipped {
        let times = if s.count > 1 { format!(" ({} of them)", s.count) } else { String::new() };
        say!(
            "{file}:{}:{}: note: `<{}>` is not mapped{times}: {}",
            s.at.line,
            s.at.col,
            s.tag,
            urdf::skipped_effect(&s.tag)
        );
    }
    let dyad = urdf::to_dyad(&robot, &file, options);
    Ok((robot, dyad))
}

pub fn import(args: &ImportArgs) -> Result<(), Failure> {
    if !is_urdf(&args.file) {
        return Err(Failure::Usage(format!("{} is not a .urdf file", args.file.display())));
    }
    let out = args.out.clone().unwrap_or_else(|| {
        PathBuf::from(format!("{}.dyad", args.file.file_stem().map_or("robot".into(), |s| s.to_string_lossy())))
    });
    output::outputs_are_safe(std::slice::from_ref(&args.file), &[("--out", Some(&out))])?;
    let bytes =
        std::fs::read(&args.file).map_err(|e| Failure::Io(format!("cannot read {}: {e}", args.file.display())))?;
    let (robot, dyad) =
        urdf_as_dyad(&args.file, bytes, &ImportOptions { floating: args.floating, ..Default::default() })?;
    // The file must be a model that assembles before it is written.
    let mut package = multibody_dyad::Package::new();
    let name = out.display().to_string();
    if let Err(d) = package.add_source(name.clone(), dyad.clone()) {
        return Err(Failure::Usage(format!(
            "the import made a file that does not parse (a bug): {}",
            package.render(&[d])
        )));
    }
    let target = package.choose_target(None, None).map_err(Failure::Usage)?;
    // The diagnostic is rendered as the checks of a model file are.
    let refused = |d| {
        eprint!("{}", package.render(&[d]));
        say!("the imported model was not written: {} does not assemble as it is", args.file.display());
        Failure::Model
    };
    let lowered = package.lower_target(&target, &[]).map_err(refused)?;
    let mechanism = lowered.assemble().map_err(refused)?;
    output::write_atomically(&out, |w| w.write_all(dyad.as_bytes()))?;
    say!(
        "{}: {} links, {} joints → {} ({} degrees of freedom; gravity along -z, URDF's up being z)",
        robot.name,
        robot.links.len(),
        robot.joints.len(),
        out.display(),
        mechanism.degrees_of_freedom()
    );
    Ok(())
}
