//! Dyad's RotationalComponents: 1-D rotational elements between splines.

pub mod constant_torque;
pub mod damper;
pub mod spring;
pub mod spring_damper;
