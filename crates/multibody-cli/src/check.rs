//! `multibody check`: assemble and describe the mechanism without simulating.

use crate::exit::Failure;
use crate::load::{choose, file_of, lower, print_diagnostics, read_package, Target};
use crate::run::number;
use crate::Selection;

pub fn check(selection: &Selection) -> Result<(), Failure> {
    let package = read_package(&selection.files)?;
    let target = choose(&package, selection)?;
    let lowered = lower(&package, &target, &[])?;
    let mechanism = lowered.assemble().map_err(|d| {
        print_diagnostics(&package, &[d]);
        Failure::Model
    })?;
    let what = match &target {
        Target::Analysis(name) => format!("analysis {name}, model {}", lowered.model.name),
        Target::Component(name) => format!("component {name}"),
    };
    println!("{what} ({})", file_of(&package, &lowered.name));
    println!("  components: {}", lowered.model.components.len());
    let dof = mechanism.degrees_of_freedom();
    println!("  degrees of freedom: {dof}");
    let states = mechanism.states();
    if states.names.is_empty() {
        println!("  states: none");
    } else {
        println!("  states, with start values:");
        let width = states.names.iter().map(|n| n.chars().count()).max().unwrap_or(0);
        for (name, start) in states.names.iter().zip(&states.start) {
            println!("    {name:width$}  {}", number(*start));
        }
    }
    let loops = mechanism.loops();
    if !loops.is_empty() {
        let contacts = loops.iter().filter(|l| l.wheel_contact.is_some()).count();
        if contacts < loops.len() {
            println!("  kinematic loops: {}", loops.len() - contacts);
        }
        for l in loops.iter().filter(|l| l.wheel_contact.is_none()) {
            println!(
                "    through {}: cut at {}, {} constraint equations, {} of them redundant",
                l.joints.join(", "),
                l.cut,
                l.equations,
                l.redundant
            );
        }
        if contacts > 0 {
            println!("  wheel contacts: {contacts}");
        }
        for l in loops.iter().filter(|l| l.wheel_contact.is_some()) {
            let on_velocities = l.wheel_contact.unwrap_or(0);
            println!(
                "    {} on the ground: {} constraint equations ({} of them on velocities), {} of them redundant",
                l.cut, l.equations, on_velocities, l.redundant
            );
        }
    }
    let owners = mechanism.orientation_owners();
    if owners.is_empty() {
        println!("  orientation: every part is positioned from the World through joints and fixed parts");
    } else {
        println!("  orientation owners (free parts):");
        for (owner, how) in owners {
            println!("    {owner}: {how}");
        }
    }
    let warnings = mechanism.warnings();
    if warnings.is_empty() && lowered.warnings.is_empty() {
        println!("  warnings: none");
    } else {
        println!("  warnings: {}", warnings.len() + lowered.warnings.len());
        for w in &lowered.warnings {
            println!("    {}", w.message);
        }
        for w in warnings {
            println!("    {w}");
        }
    }
    Ok(())
}
