//! Helpers shared by the view tests.
#![allow(dead_code)]

pub mod browser;
pub mod models;
pub mod pixels;
