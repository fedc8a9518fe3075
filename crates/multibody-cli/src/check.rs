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
    // The start itself: equations that fail there (a singular system, no
    // solution) would stop the run at once. One evaluation, with no room
    // kept for a run's samples.
    let start = lowered.options.start;
    let y = &mechanism.states().start;
    let mut dy = vec![0.0; y.len()];
    if let Err(e) = mechanism.rhs(&mut mechanism.workspace(), start, y, &mut dy) {
        let title = format!("the model cannot start at t = {}: ", number(start));
        print_diagnostics(&package, &[lowered.start_failure(package.sources(), &title, &mechanism.describe(&e))]);
        return Err(Failure::Model);
    }
    let what = match &target {
        Target::Analysis(name) => format!("analysis {name}, model {}", lowered.model.name),
        Target::Component(name) => format!("component {name}"),
    };
    let mut out = String::new();
    put!(out, "{what} ({})", file_of(&package, &lowered.name));
    put!(out, "  components: {}", lowered.model.components.len());
    let dof = mechanism.degrees_of_freedom();
    put!(out, "  degrees of freedom: {dof}");
    let states = mechanism.states();
    if states.names.is_empty() {
        put!(out, "  states: none");
    } else {
        put!(out, "  states, with start values:");
        let width = states.names.iter().map(|n| n.chars().count()).max().unwrap_or(0);
        for (name, start) in states.names.iter().zip(&states.start) {
            put!(out, "    {name:width$}  {}", number(*start));
        }
    }
    let loops = mechanism.loops();
    if !loops.is_empty() {
        let contacts = loops.iter().filter(|l| l.wheel_contact.is_some()).count();
        let prescribed = loops.iter().filter(|l| l.prescribed).count();
        if contacts + prescribed < loops.len() {
            put!(out, "  kinematic loops: {}", loops.len() - contacts - prescribed);
        }
        for l in loops.iter().filter(|l| l.wheel_contact.is_none() && !l.prescribed) {
            put!(
                out,
                "    through {}: cut at {}, {} constraint equations, {} of them redundant",
                l.joints.join(", "),
                l.cut,
                l.equations,
                l.redundant
            );
        }
        for l in loops.iter().filter(|l| l.prescribed) {
            put!(
                out,
                "  motion prescribed by equations: {} ({} position coordinates, {} of them redundant), held by the \
                 unknown efforts on {}",
                l.cut.trim_end_matches(" (servo)"),
                l.equations,
                l.redundant,
                l.joints.join(", ")
            );
        }
        if contacts > 0 {
            put!(out, "  wheel contacts: {contacts}");
        }
        for l in loops.iter().filter(|l| l.wheel_contact.is_some()) {
            let on_velocities = l.wheel_contact.unwrap_or(0);
            put!(
                out,
                "    {} on the ground: {} constraint equations ({} of them on velocities), {} of them redundant",
                l.cut,
                l.equations,
                on_velocities,
                l.redundant
            );
        }
    }
    let owners = mechanism.orientation_owners();
    if owners.is_empty() {
        put!(out, "  orientation: every part is positioned from the World through joints and fixed parts");
    } else {
        put!(out, "  orientation owners (free parts):");
        for (owner, how) in owners {
            put!(out, "    {owner}: {how}");
        }
    }
    let mut warnings = mechanism.warnings().to_vec();
    warnings.extend(lowered.options.warnings().into_iter().map(|(_, w)| w));
    if warnings.is_empty() && lowered.warnings.is_empty() {
        put!(out, "  warnings: none");
    } else {
        put!(out, "  warnings: {}", warnings.len() + lowered.warnings.len());
        for w in &lowered.warnings {
            put!(out, "    {}", w.message);
        }
        for w in warnings {
            put!(out, "    {w}");
        }
    }
    crate::console::answer(&out)
}
