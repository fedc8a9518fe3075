//! Multibody dynamics with the components and conventions of Dyad's
//! MultibodyComponents library (a port of Multibody.jl, which follows
//! Modelica.Mechanics.MultiBody).
//!
//! Build a [`Model`] of components joined at frames, assemble it into a
//! [`Mechanism`], and simulate it into a [`Solution`] that holds every
//! variable of every component by name:
//!
//! ```
//! use multibody::{Model, SimulationOptions};
//!
//! let mut model = Model::new("pendulum");
//! model.add("world", "World");
//! model.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]);
//! model.add("body", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]);
//! model.connect(["world.frame_b", "rev.frame_a"]);
//! model.connect(["rev.frame_b", "body.frame_a"]);
//!
//! let mechanism = model.assemble()?;
//! let solution = mechanism.simulate(&SimulationOptions { stop: 1.0, saveat: 0.01, ..Default::default() })?;
//! let phi = solution.last("rev.phi").unwrap();
//! assert!(phi < 0.0); // released horizontally, it swings down
//! println!("body at {:?}", solution.last("body.frame_a.r_0[2]"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

// The layers, from the bottom: math; error and model; system (the compiled
// numeric model); dynamics; components; assembly; outputs; simulate;
// linear (linear models and steady states of a simulator). Each
// imports only from its own layer and those below (`tests/layers.rs`).
// `files` (opening the files a user names, safely) stands apart: it
// uses no other module.
pub mod assembly;
pub mod components;
pub mod dynamics;
mod error;
pub mod files;
pub mod linear;
pub mod math;
mod model;
pub mod outputs;
pub mod simulate;
pub mod system;

pub use assembly::{LoopInfo, Mechanism};
pub use dynamics::{DynamicsError, Workspace};
pub use error::{closest, Error};
pub use linear::{
    Derivatives, JointSpace, Linearization, LinearizeError, LinearizeOptions, Pole, SteadyState, SteadyStateOptions,
};
pub use math::expr::{Cmp, Expr, Func, Func2, TimeExpr};
pub use model::{
    ComponentInstance, Connection, Equation, Equations, Flow, Model, OrientationState, Value, Variable, When,
    WhenAction,
};
pub use simulate::{
    EventUpdate, Method, OptionError, Rows, RunReport, SampleSink, SimulationError, SimulationOptions, Simulator,
    Solution, Stopped,
};
pub use system::{StateLayout, System};
