//! Lowering: a component instantiated into a [`multibody::Model`]. The
//! lowerer flattens user components (`lower`); the relations pass turns
//! their relations into scalar equations (`relations`, with expressions
//! written out by `symbolic`); connections through user components are
//! merged (`connections`); an analysis gives the simulation options
//! (`analysis`). What a user may want to change is listed as it goes
//! (`tunables`).

pub(crate) mod analysis;
pub(crate) mod connections;
pub(crate) mod lower;
pub(crate) mod relations;
pub mod symbolic;
pub(crate) mod tunables;
