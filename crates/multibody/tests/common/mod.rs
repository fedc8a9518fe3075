//! Shared test support: the reference data and its tube comparison live in
//! the `multibody-reference` crate, shared with the command's tests.
#![allow(dead_code, unused_imports)]

pub use multibody_reference::{as_pairs, assert_within_tube, reference_dir, same, vector_pairs, Table as Reference};
