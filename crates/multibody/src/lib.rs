//! Multibody dynamics with the components and conventions of Dyad's
//! MultibodyComponents library.

pub mod math;
