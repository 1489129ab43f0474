//! `defmt::Format` for the public types (feature `defmt`).

#![forbid(unsafe_code)]

use defmt::{write, Format, Formatter};

use crate::{Channel, Error, GamutMapping, RuleStatus, Samples, TransferFunction};

impl Format for crate::Rgb {
    fn format(&self, f: Formatter<'_>) {
        write!(f, "{=str}", self.name())
    }
}

impl Format for Channel {
    fn format(&self, f: Formatter<'_>) {
        write!(f, "{=str}", self.name())
    }
}

impl Format for Samples {
    fn format(&self, f: Formatter<'_>) {
        match self {
            Samples::Radiance => write!(f, "radiance"),
            Samples::Reflectance { light } => write!(f, "reflectance under {=str}", light),
            Samples::Readings {
                sensor,
                light: Some(light),
            } => write!(
                f,
                "readings of sensor {=str}, fitted under {=str}",
                sensor, light
            ),
            Samples::Readings {
                sensor,
                light: None,
            } => write!(f, "readings of sensor {=str}, fitted for radiances", sensor),
        }
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
            Error::InvalidLut { channel } => {
                write!(f, "InvalidLut {{ channel: {=str} }}", channel.name())
            }
            Error::InvalidChromaticity => write!(f, "InvalidChromaticity"),
            Error::SingularPrimaries => write!(f, "SingularPrimaries"),
            Error::WhiteOutsideGamut => write!(f, "WhiteOutsideGamut"),
            Error::InvalidGamma => write!(f, "InvalidGamma"),
            Error::Calibration { channel, problem } => write!(
                f,
                "Calibration {{ channel: {=usize}, problem: {=str} }}",
                channel,
                problem.as_str()
            ),
            Error::IntegerRange => write!(f, "IntegerRange"),
            Error::IntegerTransfer => write!(f, "IntegerTransfer"),
        }
    }
}

impl Format for crate::GaussRule {
    fn format(&self, f: Formatter<'_>) {
        write!(
            f,
            "GaussRule {{ channel: {}, order: {=u8}, status: {}, wavelengths_nm: {=[?]}, weights: {=[?]} }}",
            self.channel,
            self.order,
            self.status,
            self.wavelengths_nm,
            self.weights
        )
    }
}

impl<const N: usize> Format for crate::WavelengthSet<N> {
    fn format(&self, f: Formatter<'_>) {
        write!(
            f,
            "WavelengthSet {{ samples: {}, wavelengths_nm: {=[?]}, weights: [{=[?]}, {=[?]}, {=[?]}] }}",
            self.samples,
            &self.wavelengths_nm[..],
            &self.weights[0][..],
            &self.weights[1][..],
            &self.weights[2][..]
        )
    }
}

impl<const N: usize> Format for crate::FoldedSet<N> {
    fn format(&self, f: Formatter<'_>) {
        write!(
            f,
            "FoldedSet {{ samples: {}, display: {=str}, wavelengths_nm: {=[?]}, weights: [{=[?]}, {=[?]}, {=[?]}] }}",
            self.samples,
            self.display.name,
            &self.wavelengths_nm[..],
            &self.weights[0][..],
            &self.weights[1][..],
            &self.weights[2][..]
        )
    }
}

impl<const N: usize> Format for crate::IntegerSet<N> {
    fn format(&self, f: Formatter<'_>) {
        let w = self.weights();
        write!(
            f,
            "IntegerSet {{ samples: {}, display: {=str}, sample_unit: {=f32}, frac_bits: {=u32}, weights: [{=[?]}, {=[?]}, {=[?]}] }}",
            self.samples(),
            self.display().name,
            self.sample_unit(),
            self.frac_bits(),
            &w[0][..],
            &w[1][..],
            &w[2][..]
        )
    }
}

impl Format for crate::ChannelLuts {
    fn format(&self, f: Formatter<'_>) {
        write!(
            f,
            "ChannelLuts {{ entries: [{=usize}, {=usize}, {=usize}] }}",
            self.table(crate::Rgb::R).len(),
            self.table(crate::Rgb::G).len(),
            self.table(crate::Rgb::B).len()
        )
    }
}

impl Format for crate::Display {
    fn format(&self, f: Formatter<'_>) {
        write!(
            f,
            "Display {{ name: {=str}, white_xy: {=[?]}, transfer: {} }}",
            self.name,
            &self.white_xy[..],
            self.transfer
        )
    }
}

impl<const CAP: usize> Format for crate::DynamicSet<CAP> {
    fn format(&self, f: Formatter<'_>) {
        write!(
            f,
            "DynamicSet {{ wavelengths_nm: {=[?]}, weights: [{=[?]}, {=[?]}, {=[?]}] }}",
            self.wavelengths_nm(),
            self.weights(0),
            self.weights(1),
            self.weights(2)
        )
    }
}

impl Format for crate::Cct {
    fn format(&self, f: Formatter<'_>) {
        write!(
            f,
            "Cct {{ kelvin: {=f32}, duv: {=f32} }}",
            self.kelvin, self.duv
        )
    }
}

impl<const K: usize> Format for crate::PlanckianLocus<K> {
    fn format(&self, f: Formatter<'_>) {
        let [lo, hi] = self.kelvin_range();
        write!(
            f,
            "PlanckianLocus {{ nodes: {=usize}, kelvin: {=f32}-{=f32} }}",
            K, lo, hi
        )
    }
}

impl Format for crate::LuxScale {
    fn format(&self, f: Formatter<'_>) {
        write!(f, "LuxScale {{ lux_per_y: {=f32} }}", self.lux_per_y)
    }
}

impl Format for crate::CalibrationProblem {
    fn format(&self, f: Formatter<'_>) {
        write!(f, "{=str}", self.as_str())
    }
}

impl<const N: usize> Format for crate::Calibration<N> {
    fn format(&self, f: Formatter<'_>) {
        write!(
            f,
            "Calibration {{ dark: {=[?]}, gain: {=[?]} }}",
            &self.dark[..],
            &self.gain[..]
        )
    }
}

impl<const N: usize> Format for crate::CountCalibration<N> {
    fn format(&self, f: Formatter<'_>) {
        write!(
            f,
            "CountCalibration {{ dark: {=[?]}, gain_q16: {=[?]} }}",
            &self.dark[..],
            &self.gain_q16[..]
        )
    }
}
