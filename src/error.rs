//! The runtime's error type.

#![forbid(unsafe_code)]

use core::fmt;

/// What went wrong in a runtime call. Runtime functions return this instead of panicking.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Error {
    /// A batch call got input and output slices of different lengths.
    LengthMismatch {
        /// Number of pixels in the input.
        inputs: usize,
        /// Number of pixels in the output.
        outputs: usize,
    },
    /// A run-time set would need more wavelengths than its capacity.
    Capacity {
        /// The capacity of the set.
        capacity: usize,
    },
    /// A rule that is not `Defined` was asked to contribute to a set.
    UndefinedRule {
        /// The rule's channel row (0 = A, 1 = C1, 2 = C2).
        channel: u8,
        /// The rule's order.
        order: u8,
    },
    /// A lookup table is too short, not finite, outside 0..=1 or decreasing.
    InvalidLut {
        /// The offending channel.
        channel: crate::Rgb,
    },
    /// A chromaticity given to [`Display::new`](crate::Display::new) is not finite, is
    /// negative, or has y = 0 or x + y > 1.
    InvalidChromaticity,
    /// The primaries given to [`Display::new`](crate::Display::new) are collinear or nearly
    /// so (see [`MAX_PRIMARIES_CONDITION`](crate::MAX_PRIMARIES_CONDITION)).
    SingularPrimaries,
    /// The white point given to [`Display::new`](crate::Display::new) is not a positive mix
    /// of the primaries (it lies outside their triangle).
    WhiteOutsideGamut,
    /// A `Gamma(γ)` transfer function given to [`Display::new`](crate::Display::new) has a γ
    /// that is not finite and positive.
    InvalidGamma,
    /// A [`Calibration`](crate::Calibration) or [`CountCalibration`](crate::CountCalibration)
    /// cannot be formed for a channel.
    Calibration {
        /// The channel, counted from 0 in the sensor's order.
        channel: usize,
        /// What is wrong with it.
        problem: crate::CalibrationProblem,
    },
    /// [`IntegerSet::new`](crate::IntegerSet::new) got a weight that is not finite, a sample
    /// unit that is not finite and positive, or weights too large for 32-bit sums of u16
    /// counts.
    IntegerRange,
    /// [`IntegerSet::new`](crate::IntegerSet::new) got a display whose transfer function has no
    /// integer encoder: a lookup table, or a γ that no baked display has.
    IntegerTransfer,
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::LengthMismatch { inputs, outputs } => write!(
                f,
                "batch length mismatch: {inputs} input pixels, {outputs} output pixels"
            ),
            Error::Capacity { capacity } => {
                write!(f, "the set would need more than its {capacity} wavelengths")
            }
            Error::UndefinedRule { channel, order } => write!(
                f,
                "channel {} order {order} is not a defined rule",
                ["A", "C1", "C2"].get(channel as usize).unwrap_or(&"?")
            ),
            Error::InvalidLut { channel } => write!(
                f,
                "lookup table for channel {} needs 2 or more finite, non-decreasing entries in 0..=1",
                channel.name()
            ),
            Error::InvalidChromaticity => f.write_str(
                "a chromaticity is not finite, is negative, or has y = 0 or x + y > 1",
            ),
            Error::SingularPrimaries => f.write_str("the primaries are (nearly) collinear"),
            Error::WhiteOutsideGamut => {
                f.write_str("the white point lies outside the primaries' triangle")
            }
            Error::InvalidGamma => f.write_str("gamma must be finite and positive"),
            Error::Calibration { channel, problem } => {
                write!(f, "calibration of channel {channel}: {}", problem.as_str())
            }
            Error::IntegerRange => f.write_str(
                "the weights or the sample unit have no fixed-point form for u16 counts",
            ),
            Error::IntegerTransfer => f.write_str("the transfer function has no integer encoder"),
        }
    }
}

impl core::error::Error for Error {}
