//! Servo constraints: positions the model's equations prescribe as
//! formulas of time, held by efforts (signals driving 1-D sources) that
//! nothing else decides. Each becomes a [`Servo`]: its constraint's rows,
//! their targets, the efforts' signal slots and the generalised forces a
//! unit effort applies (constant: a 1-D source pushes its flanges'
//! coordinates by a fixed ratio).

use super::connections::Connectors;
use super::mechanism::CompiledComponent;
use super::signals::Signals;
use crate::components::ConnectorType;
use crate::components::Part;
use crate::system::Law1D;
use crate::system::{AxisElement, Constraint, ForceElement, LineState, Mover, Servo};
use crate::Error;

pub(crate) fn attach(
    components: &[CompiledComponent],
    conn: &Connectors,
    constraints: &[Constraint],
    axis_elements: &[AxisElement],
    force_elements: &[ForceElement],
    signals: &Signals,
    nv: usize,
) -> Result<Vec<Servo>, Error> {
    let (blocks, of_connector) = (&signals.blocks, &signals.of_connector);
    let mut servos = Vec::new();
    for (ci, c) in components.iter().enumerate() {
        for part in &c.parts {
            let Part::Servo { targets, efforts } = part else { continue };
            let constraint =
                constraints.iter().position(|k| k.component == ci).expect("a servo's component holds its constraint");
            let slots: Vec<usize> = efforts.iter().map(|&k| of_connector[c.first_connector + k]).collect();
            let mut forces = vec![0.0; slots.len() * nv];
            let mut lines: Vec<LineState> = Vec::new();
            for (i, &slot) in slots.iter().enumerate() {
                let refuse = |what: &str| {
                    // The effort by the input it drives (`motor.tau`).
                    let input = (0..conn.types.len())
                        .find(|&k| conn.types[k] == ConnectorType::RealInput && of_connector[k] == slot)
                        .map_or(format!("number {}", i + 1), |k| format!("`{}`", conn.name(components, k)));
                    Err(Error::Equations {
                        problem: format!(
                            "the motion that equations prescribe at `{}` is held by unknown efforts, and the effort \
                             {input} {what}",
                            c.name.trim_end_matches(" (servo)"),
                        ),
                        equations: Vec::new(),
                        variables: Vec::new(),
                        fix: "let the unknown efforts drive 1-D sources (RotationalComponents.Torque, \
                              TranslationalComponents.Force) on the joints' axes, and read them nowhere else"
                            .into(),
                    })
                };
                let column = &mut forces[i * nv..(i + 1) * nv];
                for e in axis_elements {
                    // What a unit signal pushes flange_b with (flange_a takes the reaction).
                    let push = match e.law {
                        Law1D::Input { signal } if signal == slot => 1.0,
                        Law1D::Flow { signal } if signal == slot => -1.0,
                        _ => continue,
                    };
                    if [e.a, e.b].iter().any(|f| matches!(f.mover, Some(Mover::Line(_)))) {
                        return refuse("drives a flange that a line force places");
                    }
                    e.b.push(column, &mut lines, push);
                    e.a.push(column, &mut lines, -push);
                }
                if force_elements.iter().any(|f| f.inputs.contains(&slot)) {
                    return refuse("drives a force between frames, which depends on the motion");
                }
                if blocks.iter().any(|b| b.inputs.contains(&slot)) {
                    return refuse("is read by a signal block, before the motion decides it");
                }
                if column.iter().all(|&x| x == 0.0) {
                    return refuse("acts on no joint");
                }
            }
            servos.push(Servo { constraint, targets: targets.clone(), slots, forces });
        }
    }
    Ok(servos)
}
