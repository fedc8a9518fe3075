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
            SignalLaw::FramePosition { .. } | SignalLaw::FrameVelocity { .. } | SignalLaw::AngularVelocity { .. }
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
}
