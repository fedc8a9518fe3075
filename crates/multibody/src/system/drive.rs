//! Imposed motion: joint coordinates that follow signals instead of the
//! equations of motion (prescribed positions and poses, position, speed
//! and acceleration sources on a joint's axis).
//!
//! A driven coordinate keeps its place in the state, so that outputs and
//! start values work as for any other; but where the drive knows the
//! position (or speed) exactly, every evaluation overwrites the integrated
//! value with the exact one, and the acceleration is the drive's, not the
//! dynamics'. The dynamics then carries the driven link like a rigid one
//! moving along a known path: its joint transmits whatever force that
//! takes (a rheonomic joint, not a stiff spring).

/// What a drive knows about its coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DriveLevel {
    /// Position from the signals (with their first and second derivatives).
    Position,
    /// Speed from the signals (with their derivative); the position integrates it.
    Speed,
    /// Acceleration from the signals; position and speed integrate it.
    Acceleration,
    /// The position follows the signal through a critically damped
    /// second-order filter of cut-off `w_crit` (Modelica's inexact Position
    /// source): `a = ((ref - x) w_crit - af v) w_crit / bf`.
    PositionFilter { w_crit: f64 },
    /// The speed follows the signal through a first-order filter:
    /// `a = (ref - v) w_crit`.
    SpeedFilter { w_crit: f64 },
    /// A 1-D node without mass (`System::balances[node]`): the balance of
    /// the forces on it gives its speed (and without damping its position);
    /// its acceleration follows after the dynamics.
    Balance { node: usize },
}

/// The `s` coefficient of the filter of [`DriveLevel::PositionFilter`]
/// (a Bessel filter, as Modelica's Position source).
pub const FILTER_AF: f64 = 1.3617;
/// Its `s^2` coefficient.
pub const FILTER_BF: f64 = 0.6180;

impl DriveLevel {
    /// Whether the drive sets positions and speeds exactly, so that it
    /// needs the signals' derivatives.
    pub fn needs_derivatives(&self) -> bool {
        matches!(self, DriveLevel::Position | DriveLevel::Speed)
    }
}

/// How the drive's signals map to the joint coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DriveMap {
    /// Velocity coordinate `first + k` (and its position `q_first + k`)
    /// follows `(signal_k - offset) / scale` for `k < count`; the joint's
    /// positions of those coordinates are their integrals.
    Linear { first: usize, count: usize, scale: f64, offset: f64 },
    /// A free joint's position `r` from the first three signals and its
    /// orientation from the quaternion `[w, i, j, k]` of the next four
    /// (world to frame_b); the angular velocity follows from the
    /// quaternion's rates.
    Pose,
}

/// One driven joint.
#[derive(Clone, Debug, PartialEq)]
pub struct Drive {
    /// The link whose joint it drives.
    pub link: usize,
    pub level: DriveLevel,
    pub map: DriveMap,
    /// The signal slots it reads (unused entries read the zero slot).
    pub slots: [usize; 7],
    /// The component that drives (for messages).
    pub component: usize,
}
