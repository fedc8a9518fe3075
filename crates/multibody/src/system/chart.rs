//! The chart an Euler-angle joint is integrated in after it came near its
//! singular configuration (see `dynamics::chart`).

use crate::math::{Mat3, Vec3};

/// The chart an Euler-angle joint is integrated in: `R = A(psi) base`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EulerChart {
    pub base: Mat3,
    /// The library's angles when the joint first moved to a chart: where
    /// their branch is continued from.
    pub phi: Vec3,
}
