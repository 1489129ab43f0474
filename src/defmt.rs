//! `defmt::Format` for the public types (feature `defmt`).

use defmt::{write, Format, Formatter};

use crate::{Channel, Error, GamutMapping, RuleStatus, TransferFunction};

impl Format for Channel {
    fn format(&self, f: Formatter<'_>) {
        write!(f, "{=str}", self.name())
    }
}

impl Format for RuleStatus {
    fn format(&self, f: Formatter<'_>) {
        write!(f, "{=str}", self.as_str())
    }
}

impl Format for GamutMapping {
    fn format(&self, f: Formatter<'_>) {
        match self {
            GamutMapping::Clip => write!(f, "Clip"),
            GamutMapping::PreserveA => write!(f, "PreserveA"),
        }
    }
}

impl Format for TransferFunction {
    fn format(&self, f: Formatter<'_>) {
        match self {
            TransferFunction::Linear => write!(f, "Linear"),
            TransferFunction::Srgb => write!(f, "Srgb"),
            TransferFunction::Gamma(g) => write!(f, "Gamma({=f32})", g),
            TransferFunction::Lut(_) => write!(f, "Lut"),
        }
    }
}

impl Format for Error {
    fn format(&self, f: Formatter<'_>) {
        match *self {
            Error::LengthMismatch { inputs, outputs } => write!(
                f,
                "LengthMismatch {{ inputs: {=usize}, outputs: {=usize} }}",
                inputs, outputs
            ),
            Error::Capacity { capacity } => {
                write!(f, "Capacity {{ capacity: {=usize} }}", capacity)
            }
            Error::UndefinedRule { channel, order } => write!(
                f,
                "UndefinedRule {{ channel: {=u8}, order: {=u8} }}",
                channel, order
            ),
            Error::InvalidLut { channel } => write!(f, "InvalidLut {{ channel: {=u8} }}", channel),
        }
    }
}
