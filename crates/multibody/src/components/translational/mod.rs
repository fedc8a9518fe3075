//! Dyad's TranslationalComponents: 1-D translational elements between flanges.

pub mod constant_force;
pub mod damper;
pub mod spring;
pub mod spring_damper;
