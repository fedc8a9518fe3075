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

/// How a URDF file's meshes are found and what a missing one does.
pub struct Meshes<'a> {
    /// Folders that hold ROS packages (`--package-dir`); `ROS_PACKAGE_PATH`
    /// is searched after them.
    pub package_dirs: &'a [PathBuf],
    /// A missing mesh stops the import (else it is noted and left out).
    pub required: bool,
    /// Mesh visuals are left out (`--no-meshes`).
    pub leave_out: bool,
}

/// The robot of a URDF file as Dyad text, the elements it did not map
/// said once each (with file:line:col) on stderr.
pub fn urdf_as_dyad(
    path: &Path,
    bytes: Vec<u8>,
    options: &ImportOptions,
    meshes: &Meshes,
) -> Result<(Robot, String), Failure> {
    let file = path.display().to_string();
    let text = String::from_utf8(bytes)
        .map_err(|e| Failure::Usage(format!("{file} is not UTF-8 text (byte {})", e.utf8_error().valid_up_to())))?;
    let mut robot = urdf::parse(&text).map_err(|e| {
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
    for w in &robot.warnings {
        say!("{}", w.render(&file));
    }
    if meshes.leave_out {
        for link in &mut robot.links {
            link.visuals.retain(|v| !matches!(v.geometry, urdf::Geometry::Mesh { .. }));
        }
    }
    let mut package_dirs = meshes.package_dirs.to_vec();
    if let Some(ros) = std::env::var_os("ROS_PACKAGE_PATH") {
        package_dirs.extend(std::env::split_paths(&ros).filter(|p| !p.as_os_str().is_empty()));
    }
    let folder = path
        .parent()
        .map_or_else(|| PathBuf::from("."), |p| if p.as_os_str().is_empty() { ".".into() } else { p.into() });
    let missing = urdf::resolve_meshes(&mut robot, &urdf::MeshSearch { urdf_folder: folder, package_dirs });
    for m in &missing {
        if meshes.required {
            eprintln!("{}", m.render(&file, "error"));
        } else {
            say!("{}; the link is drawn without it", m.render(&file, "note"));
        }
    }
    if meshes.required && !missing.is_empty() {
        if missing.iter().all(|m| m.not_a_file.is_some()) {
            // Found, but not files: no folder to name.
            say!("help: name mesh files in the URDF, or import without meshes with --no-meshes");
        } else {
            say!(
                "help: name the folder that holds the package with --package-dir (or ROS_PACKAGE_PATH), or import \
                 without meshes with --no-meshes"
            );
        }
        return Err(Failure::Model);
    }
    // Too large a robot is said about the URDF, before its model is made.
    urdf::check_size(&robot, options).map_err(|e| {
        eprintln!("{}", e.render(&file));
        Failure::Model
    })?;
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
    // Mesh files are named from the model file's folder.
    let base = out
        .parent()
        .map_or_else(|| PathBuf::from("."), |p| if p.as_os_str().is_empty() { ".".into() } else { p.into() });
    let options = ImportOptions { floating: args.floating, mesh_base: Some(base), ..Default::default() };
    let meshes = Meshes { package_dirs: &args.package_dir, required: true, leave_out: args.no_meshes };
    let (robot, dyad) = urdf_as_dyad(&args.file, bytes, &options, &meshes)?;
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
        "{}: {} links, {} joints → {} ({} degree{} of freedom; gravity along -z, URDF's up being z)",
        robot.name,
        robot.links.len(),
        robot.joints.len(),
        out.display(),
        mechanism.degrees_of_freedom(),
        if mechanism.degrees_of_freedom() == 1 { "" } else { "s" }
    );
    Ok(())
}
