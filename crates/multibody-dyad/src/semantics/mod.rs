//! Semantics: what the names of a package mean. The definitions by name
//! and what each declares (with what it extends), parameter scopes and
//! constant evaluation, types, and how modifiers from different levels
//! combine.

pub mod catalog;
pub mod connectors;
pub mod eval;
pub(crate) mod extends;
pub(crate) mod index;
pub(crate) mod modifiers;
pub(crate) mod scope;
pub(crate) mod types;
