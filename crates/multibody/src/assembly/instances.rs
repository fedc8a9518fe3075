//! Finds the World, checks every component's kind and parameters, and builds
//! the components.

use super::equations::Extra;
use super::mechanism::CompiledComponent;
use crate::components::planar_mechanics::world as planar_world;
use crate::components::{lookup, registry, without_effect, world, ComponentSpec, ParamSet, WorldSettings};
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
pub fn build(
    model: &Model,
    world: &WorldSettings,
    extras: &[Extra],
    notes: &mut Vec<String>,
) -> Result<Vec<CompiledComponent>, Error> {
    let mut names = HashSet::new();
    let mut built = Vec::with_capacity(model.components.len());
    let world_defaults_read = world_defaults_read(model, world);
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
        let shapes: Vec<_> = (spec.shapes)(&params)
            .into_iter()
            .map(|s| crate::components::shapes::Shape { plane, ..s.named(&instance.name) })
            .collect();
        for param in spec.params {
            if !without_effect::changed_from_default(&params, param.name) {
                continue;
            }
            let context = without_effect::Context {
                draws: !shapes.is_empty(),
                // (Only `render` asks; it costs the shapes once more.)
                draws_when_rendered: param.name != "render" || draws_when_rendered(instance, spec, world),
                world_defaults_read: &world_defaults_read,
            };
            if let Some(why) = without_effect::reason(&params, param.name, &context) {
                notes.push(format!("`{}.{}` has no effect: {why}", instance.name, param.name));
            }
        }
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

/// The World parameters that a component of the model takes a default
/// from and uses (a parameter it does not give whose default is the
/// World's, where it draws it). Looked at only when the World gives one of
/// its `default_*` parameters: that is what the answer is for.
fn world_defaults_read(model: &Model, world: &WorldSettings) -> Vec<&'static str> {
    let gives_defaults = model.components.iter().any(|c| {
        matches!(c.kind.as_str(), "World" | "PlanarMechanics.World")
            && c.params.iter().any(|(n, _)| n.starts_with("default_"))
    });
    let mut read = Vec::new();
    if !gives_defaults {
        return read;
    }
    for instance in &model.components {
        let Some(spec) = lookup(&instance.kind) else { continue };
        let draws = ParamSet::resolve(instance, spec, world).is_ok_and(|p| !(spec.shapes)(&p).is_empty());
        for p in spec.params {
            if instance.params.iter().any(|(n, _)| n == p.name) || without_effect::not_drawn(spec.kind, p.name) {
                continue;
            }
            match p.default {
                crate::components::Default::World(name, _) if draws && !read.contains(&name) => read.push(name),
                // A default computed from the World's (`length / world.default_width_fraction`).
                crate::components::Default::Derived(how) => {
                    for word in how.split(|c: char| !(c.is_alphanumeric() || c == '_')) {
                        if let Some(known) = crate::components::world::SPEC.params.iter().find(|q| q.name == word) {
                            if !read.contains(&known.name) {
                                read.push(known.name);
                            }
                        }
                    }
                }
                _ => {}
            }
        }
        // Read in the code: a BodyShape's width without one given.
        if spec.kind == "BodyShape"
            && !instance.params.iter().any(|(n, _)| n == "width")
            && !read.contains(&"default_width_fraction")
        {
            read.push("default_width_fraction");
        }
    }
    read
}

/// Whether the component draws anything in the animation when it is
/// rendered (whatever its `render` says).
fn draws_when_rendered(
    instance: &crate::ComponentInstance,
    spec: &'static ComponentSpec,
    world: &WorldSettings,
) -> bool {
    let mut rendered = instance.clone();
    if spec.param("render").is_some() {
        rendered.set("render", true);
    }
    ParamSet::resolve(&rendered, spec, world).is_ok_and(|p| !(spec.shapes)(&p).is_empty())
}

/// Whether the component has 3-D frames (unknown kinds count as having
/// them; their own error comes later).
fn has_frames(instance: &crate::ComponentInstance) -> bool {
    match lookup(&instance.kind) {
        Some(spec) => spec.connectors.iter().any(|c| c.ty.is_frame()),
        None => true,
    }
}
