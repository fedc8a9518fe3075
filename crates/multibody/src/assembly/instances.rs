//! Finds the World, checks every component's kind and parameters, and builds
//! the components.

use super::equations::Extra;
use super::mechanism::CompiledComponent;
use crate::components::planar_mechanics::world as planar_world;
use crate::components::{lookup, registry, world, ComponentSpec, ParamSet, WorldSettings};
use crate::error::closest;
use crate::{Error, Model};
use std::collections::HashSet;

/// The settings of the model's one World: a 3-D one, a planar one, or one
/// of each that agree on gravity.
pub fn world_settings(model: &Model) -> Result<WorldSettings, Error> {
    let of_kind = |spec: &ComponentSpec| -> Vec<_> {
        model.components.iter().filter(|c| lookup(&c.kind).is_some_and(|s| std::ptr::eq(s, spec))).collect()
    };
    let (worlds, planar) = (of_kind(&world::SPEC), of_kind(&planar_world::SPEC));
    for many in [&worlds, &planar] {
        if many.len() > 1 {
            return Err(Error::SeveralWorlds { names: many.iter().map(|c| c.name.clone()).collect() });
        }
    }
    match (worlds.first(), planar.first()) {
        // A model of 1-D parts alone needs no World.
        (None, None) if !model.components.iter().any(has_frames) => Ok(WorldSettings::default()),
        (None, None) => Err(Error::NoWorld),
        (Some(world), None) => WorldSettings::from_instance(world),
        (None, Some(planar)) => planar_world::settings(planar),
        (Some(world), Some(planar)) => {
            let (spatial, plane) = (WorldSettings::from_instance(world)?, planar_world::settings(planar)?);
            if (spatial.uniform_gravity() - plane.uniform_gravity()).norm() > 1e-12 * (1.0 + spatial.g.abs()) {
                return Err(Error::InvalidValue {
                    component: planar.name.clone(),
                    name: "g".into(),
                    value: format!("{} along {}", plane.g, plane.n.transpose()),
                    reason: format!(
                        "the planar World's gravity{} differs from the 3-D World `{}`'s ({} along {}): both act on every body, so they must agree",
                        if plane.plane.rot == crate::math::Mat3::identity() { "" } else { " (in world coordinates, turned with the plane by rot_3d)" },
                        world.name, spatial.g, spatial.n.transpose()
                    ),
                });
            }
            Ok(spatial.with_plane(plane.plane))
        }
    }
}

/// Every component, built from validated parameters, in model order.
pub fn build(model: &Model, world: &WorldSettings, extras: &[Extra]) -> Result<Vec<CompiledComponent>, Error> {
    let mut names = HashSet::new();
    let mut built = Vec::with_capacity(model.components.len());
    let mut first_connector = 0;
    for instance in &model.components {
        if !names.insert(instance.name.as_str()) {
            return Err(Error::DuplicateName { name: instance.name.clone() });
        }
        let spec = lookup(&instance.kind).ok_or_else(|| Error::UnknownKind {
            component: instance.name.clone(),
            kind: instance.kind.clone(),
            suggestions: closest(&crate::components::canonical_kind(&instance.kind), registry().iter().map(|s| s.kind)),
        })?;
        let params = ParamSet::resolve(instance, spec, world)?;
        let component = (spec.build)(&params)?;
        let parts = component.parts();
        let variables = component.variables();
        let plane = if spec.is_planar() { world.plane } else { crate::math::Transform::IDENTITY };
        let shapes = (spec.shapes)(&params)
            .into_iter()
            .map(|s| crate::components::shapes::Shape { plane, ..s.named(&instance.name) })
            .collect();
        built.push(CompiledComponent {
            name: instance.name.clone(),
            spec,
            component: component.into(),
            parts,
            first_connector,
            joints: Vec::new(),
            elements: Vec::new(),
            frictions: Vec::new(),
            variables,
            shapes,
            hidden: false,
        });
        first_connector += spec.connectors.len();
    }
    // The hidden pieces of the model's equations come after the model's
    // components (whose numbers stay those of the model).
    for extra in extras {
        let spec = extra.part.spec(extra.rotational);
        let component: std::sync::Arc<dyn crate::components::Component> = std::sync::Arc::new(extra.part.clone());
        built.push(CompiledComponent {
            name: extra.name.clone(),
            spec,
            parts: component.parts(),
            component,
            first_connector,
            joints: Vec::new(),
            elements: Vec::new(),
            frictions: Vec::new(),
            variables: Vec::new(),
            shapes: Vec::new(),
            hidden: true,
        });
        first_connector += spec.connectors.len();
    }
    Ok(built)
}

/// Whether the component has 3-D frames (unknown kinds count as having
/// them; their own error comes later).
fn has_frames(instance: &crate::ComponentInstance) -> bool {
    match lookup(&instance.kind) {
        Some(spec) => spec.connectors.iter().any(|c| c.ty.is_frame()),
        None => true,
    }
}
