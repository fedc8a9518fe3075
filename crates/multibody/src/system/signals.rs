//! The signal graph: blocks that compute a signal from time, from other
//! signals, or from the motion (sensors), evaluated inside every right-hand
//! side in dependency order.
//!
//! Every block writes one slot of the workspace's signal values; its
//! inputs read slots. The slot after the last block always reads zero (an
//! input connected to nothing).

use super::laws::{Resolve, SignalSource};
use super::{Attachment, FlangeRef};

/// How a block computes its output.
#[derive(Clone, Debug, PartialEq)]
pub enum SignalLaw {
    /// A function of time.
    Source(SignalSource),
    /// `y = bias + gains . u`: gains, sums and feedback differences.
    Affine { gains: [f64; 3], bias: f64 },
    /// `y = u1 * u2`.
    Product,
    /// `y = u1 / u2`.
    Division,
    /// Position of flange b relative to flange a (angle or displacement).
    FlangePosition,
    /// Speed of flange b relative to flange a.
    FlangeSpeed,
    /// Component `index` of the position of frame b's origin relative to
    /// frame a's (the world's without frame a), resolved in `resolve`.
    FramePosition { index: usize, resolve: Resolve },
    /// Component `index` of the velocity of frame b's origin relative to
    /// frame a's, as seen from the world, resolved in `resolve`.
    FrameVelocity { index: usize, resolve: Resolve },
    /// Component `index` of the angular velocity of frame b relative to
    /// frame a, resolved in `resolve`.
    AngularVelocity { index: usize, resolve: Resolve },
    /// Component `index` of the velocity of frame b's origin relative to
    /// frame a's as an observer fixed in `seen_from` sees it (the time
    /// derivative of the relative position resolved in that frame; the
    /// world's for `World`), resolved in `resolve`.
    RelativeVelocity { index: usize, seen_from: Resolve, resolve: Resolve },
    /// Angle `index` of the rotation from frame a (the world without one)
    /// to frame b about the axes of `sequence` (1-based), the first angle
    /// the one of its two solutions nearest `guess`.
    FrameAngles { index: usize, sequence: [usize; 3], guess: f64 },
    /// Distance between the origins of frames a and b, smoothed below
    /// `s_small`.
    FrameDistance { s_small: f64 },
    /// Component `index` of the vector of the three inputs, given in frame
    /// a's coordinates (the world's without frame a), resolved in frame b
    /// (the world without one).
    ResolveVector { index: usize },
    /// An output the signal graph cannot compute before the accelerations
    /// (it depends on them or on cut forces), or that the component's
    /// parameters switch off: assembly refuses a model that reads it, and
    /// it reads NaN. `reason` says why, for that error.
    Unavailable { reason: &'static str },
    /// A slot the model's own equations write (they run in its place).
    Written,
    /// Input number `index` of the model, which the host sets
    /// (`Workspace::inputs`, holding `start` until then).
    Input { index: usize, start: f64 },
}

impl SignalLaw {
    /// Whether the output depends on the inputs at the same instant (so a
    /// loop of such blocks is an algebraic loop).
    pub fn feeds_through(&self) -> bool {
        matches!(self, SignalLaw::Affine { .. } | SignalLaw::Product | SignalLaw::Division)
    }

    /// Whether the block reads frame poses, which the kinematics then
    /// computes.
    pub fn reads_frames(&self) -> bool {
        matches!(
            self,
            SignalLaw::FramePosition { .. }
                | SignalLaw::FrameVelocity { .. }
                | SignalLaw::AngularVelocity { .. }
                | SignalLaw::RelativeVelocity { .. }
                | SignalLaw::FrameAngles { .. }
                | SignalLaw::FrameDistance { .. }
                | SignalLaw::ResolveVector { .. }
        )
    }
}

/// A block with its inputs resolved to slots and its frames and flanges to
/// where they sit.
#[derive(Clone, Debug)]
pub(crate) struct SignalBlock {
    pub law: SignalLaw,
    /// The slot it writes.
    pub output: usize,
    /// The slots it reads (the zero slot where unused).
    pub inputs: [usize; 3],
    /// Frame a (None: the world) and frame b of a frame sensor.
    pub frames: [Option<Attachment>; 2],
    /// Flange a and flange b of a 1-D sensor.
    pub flanges: [FlangeRef; 2],
    /// A planar sensor in a plane placed away from the x-y plane: it
    /// measures in the plane's coordinates (its "world" is the plane).
    pub in_plane: bool,
}
