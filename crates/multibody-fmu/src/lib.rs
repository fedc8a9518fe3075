//! FMI 2.0 and 3.0 export of Dyad models, model exchange and co-simulation.
//!
//! One runtime library serves every FMU: built once as this crate's
//! `cdylib`, it is copied into the FMU as `binaries/<platform>/<model>.so`
//! beside the model files (`resources/model/`) and a settings file. At
//! instantiation it reads the files, checks them against the FMU's token,
//! lowers and assembles the model (milliseconds), and runs it with the
//! engine's [`multibody::Simulator`]: its own integrator and events for
//! co-simulation, or the host's integrator with the simulator's
//! derivatives, indicators and event handling for model exchange.
//! Exporting compiles nothing: it describes and zips.
//!
//! - [`model`]: the files, the variables and their value references (the
//!   export and the runtime share it, so they agree);
//! - [`description`]: the `modelDescription.xml`;
//! - [`export`]: the zip;
//! - [`instance`]: one instance in safe Rust; [`fmi2`] and [`fmi3`]: the C
//!   functions, sharing their guard and logging (`host`).

pub mod description;
pub mod export;
pub mod fmi2;
pub mod fmi3;
mod host;
pub mod instance;
pub mod model;

pub use description::{Kinds, Version};
pub use export::Export;
