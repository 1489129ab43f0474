//! The runtime's error type, with the detail it carries of its own: [`CalibrationProblem`], what
//! is wrong with a calibration's channel ([`DisplayError`] comes from the math crate). The
//! channel selectors its variants name are in `channel`, below it, so that the modules that
//! return an `Error` import this one and nothing here imports them.

#![forbid(unsafe_code)]

use core::fmt;

pub use spectral_quadrature_math::DisplayError;

/// What went wrong in a runtime call. Runtime functions return this instead of panicking.
///
/// It implements `core::error::Error` (and so `std::error::Error`) without any feature.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Error {
    /// Two lengths that must agree do not: an output against its input, a plane against the
    /// others, samples against a set's wavelengths, a rule's nodes against its order. Every
    /// call that returns it has written nothing.
    LengthMismatch {
        /// What was compared, and so what the two lengths count.
        what: LengthOf,
        /// The length it must have.
        expected: usize,
        /// The length it has.
        got: usize,
    },
    /// A run-time set would need more wavelengths than its capacity.
    Capacity {
        /// The capacity of the set.
        capacity: usize,
    },
    /// A rule that is not `Defined` was asked to contribute to a set.
    UndefinedRule {
        /// The rule's channel.
        channel: crate::Channel,
        /// The rule's order.
        order: u8,
    },
    /// A lookup table is too short, not finite, outside 0..=1 or decreasing.
    InvalidLut {
        /// The offending channel.
        channel: crate::Rgb,
    },
    /// [`Display::new`](crate::Display::new) refuses the display: the details (which
    /// chromaticity, the primaries' condition number, the white's drives, the γ) in the
    /// [`DisplayError`] that the build-time generator reports for its displays too.
    Display(DisplayError),
    /// A [`Calibration`](crate::Calibration) or [`CountCalibration`](crate::CountCalibration)
    /// cannot be formed for a channel.
    Calibration {
        /// The sensor channel's index, counted from 0 in the sensor's order.
        channel_index: usize,
        /// What is wrong with it.
        problem: CalibrationProblem,
    },
    /// A set's or rule's constructor ([`WavelengthSet::new`](crate::WavelengthSet::new),
    /// [`FoldedSet::new`](crate::FoldedSet::new), [`GaussRule::new`](crate::GaussRule::new)) got
    /// a wavelength that is not finite and positive, or not above the one before (sensor
    /// readings excepted, whose channel peaks may come in any order).
    InvalidWavelength {
        /// The first such wavelength's index.
        index: usize,
    },
    /// A set's or rule's constructor got a weight that is not finite: `weights[row][index]`
    /// (a [`LightGroupSet`](crate::LightGroupSet)'s is [`Error::LightGroup`] with
    /// [`LightGroupProblem::InvalidWeight`], which names the light).
    InvalidWeight {
        /// The weight's row: the channel, A, C1, C2 (a [`WavelengthSet`](crate::WavelengthSet)
        /// or [`GaussRule`](crate::GaussRule)) or R, G, B (a
        /// [`FoldedSet`](crate::FoldedSet)), from 0.
        row: usize,
        /// Its index in the row.
        index: usize,
    },
    /// [`Upsampling::new`](crate::Upsampling::new) got a table that is not `grid³` entries, or
    /// a grid below 2.
    UpsamplingTable {
        /// Points per axis given.
        grid: usize,
        /// Entries in the table.
        entries: usize,
    },
    /// [`Upsampling::new`](crate::Upsampling::new) got a set for a sensor's readings
    /// ([`Samples::Readings`](crate::Samples::Readings)): its samples are channel readings,
    /// not values at wavelengths, so there are no node reflectances to upsample to.
    UpsamplingReadings,
    /// [`Upsampling::new`](crate::Upsampling::new) got a [`RoundTrip`](crate::RoundTrip) whose
    /// RGB → XYZ is not the set's display's, bit for bit: the round trip would measure colours
    /// in another display's space than the one whose RGB the upsampling takes.
    UpsamplingRoundTrip,
    /// [`Upsampling::with_measured`](crate::Upsampling::with_measured) got a figure that is not
    /// finite and non-negative, or a reachable share above 1.
    UpsamplingFigures,
    /// [`PlanckianLocus::new`](crate::PlanckianLocus::new) got a node whose values are not a
    /// locus table's: see there for each check.
    InvalidLocus {
        /// The first such node's index.
        node: usize,
    },
    /// [`IntegerSet::new`](crate::IntegerSet::new) got a weight that is not finite, a sample
    /// unit that is not finite and positive, or weights too large for 32-bit sums of u16
    /// counts.
    IntegerRange,
    /// [`IntegerSet::new`](crate::IntegerSet::new) got a display whose transfer function has no
    /// integer encoder: a lookup table, or a γ that no baked display has.
    IntegerTransfer,
    /// [`LuxScale::new`](crate::LuxScale::new) got a scale that is not finite and positive, or
    /// [`LuxScale::from_reading`](crate::LuxScale::from_reading) a Y or an illuminance that is
    /// not (or whose ratio overflows).
    InvalidLuxScale,
    /// [`LightGroupSet::new`](crate::LightGroupSet::new) or
    /// [`LightGroupSet::from_members`](crate::LightGroupSet::from_members) cannot form a set
    /// from its lights.
    LightGroup {
        /// The light's index (the member's, for `from_members`), from 0; 0 where there are no
        /// lights.
        light: usize,
        /// What is wrong with it.
        problem: LightGroupProblem,
    },
}

/// What a length was compared with, in [`Error::LengthMismatch`]: says what its `expected`
/// and `got` count.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum LengthOf {
    /// The output of a `_batch` call, or the interleaved output of a `_planar_to_interleaved`
    /// call: its pixels (`got`) against the input's (`expected`).
    Output,
    /// An input plane of a `_planar` or `_planar_to_interleaved` call: its values (`got`)
    /// against the first input plane's (`expected`).
    InputPlane,
    /// An output plane of a `_planar` or `_interleaved_to_planar` call: its values (`got`)
    /// against the input's pixels (`expected`; with no input planes, N = 0, the first output
    /// plane's length).
    OutputPlane,
    /// The samples given to [`DynamicSet::ac1c2`](crate::DynamicSet::ac1c2) (`got`) against
    /// the set's wavelengths (`expected`).
    Samples,
    /// The wavelengths given to [`GaussRule::new`](crate::GaussRule::new) (`got`) against its
    /// order (`expected`; 0 for a rule that is not `Defined`).
    RuleWavelengths,
    /// The weights given to [`GaussRule::new`](crate::GaussRule::new) (`got`) against its order
    /// (`expected`; 0 for a rule that is not `Defined`).
    RuleWeights,
}

impl LengthOf {
    /// The identifier, `"output"`, `"input-plane"`, `"output-plane"`, `"samples"`,
    /// `"rule-wavelengths"` or `"rule-weights"` (kebab-case, stable across versions). Its
    /// [`Display`](fmt::Display) is the sentence for messages.
    pub const fn name(self) -> &'static str {
        match self {
            LengthOf::Output => "output",
            LengthOf::InputPlane => "input-plane",
            LengthOf::OutputPlane => "output-plane",
            LengthOf::Samples => "samples",
            LengthOf::RuleWavelengths => "rule-wavelengths",
            LengthOf::RuleWeights => "rule-weights",
        }
    }
}

impl fmt::Display for LengthOf {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            LengthOf::Output => "an output's pixels against its input's",
            LengthOf::InputPlane => "an input plane against the first",
            LengthOf::OutputPlane => "an output plane against the input's pixels",
            LengthOf::Samples => "the samples against the set's wavelengths",
            LengthOf::RuleWavelengths => "a rule's wavelengths against its order",
            LengthOf::RuleWeights => "a rule's weights against its order",
        })
    }
}

/// `Ok` where `got == expected`, else [`Error::LengthMismatch`] naming `what`: the runtime's one
/// length check, which every layout and constructor calls (usable in consts).
#[inline]
pub(crate) const fn check_length(what: LengthOf, expected: usize, got: usize) -> Result<(), Error> {
    if got == expected {
        Ok(())
    } else {
        Err(Error::LengthMismatch {
            what,
            expected,
            got,
        })
    }
}

/// The number of pixels of a planar call, checked with [`check_length`] before anything is
/// written: the length of the first of `inputs` (its planes' lengths, or the interleaved input's
/// pixels), which every other input ([`LengthOf::InputPlane`]) and every one of `outputs`
/// (`output`: [`LengthOf::OutputPlane`] for planes, [`LengthOf::Output`] for interleaved pixels)
/// must have. With no inputs (N = 0) the first output's length is the number of pixels, and no
/// outputs, no pixels.
pub(crate) fn planar_pixels(
    inputs: impl IntoIterator<Item = usize>,
    output: LengthOf,
    outputs: &[usize],
) -> Result<usize, Error> {
    let mut inputs = inputs.into_iter();
    let pixels = match inputs.next() {
        Some(len) => len,
        None => outputs.first().copied().unwrap_or(0),
    };
    for len in inputs {
        check_length(LengthOf::InputPlane, pixels, len)?;
    }
    for &len in outputs {
        check_length(output, pixels, len)?;
    }
    Ok(pixels)
}

/// Why a [`LightGroupSet`](crate::LightGroupSet) cannot be formed, in
/// [`Error::LightGroup`] (which names the light).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum LightGroupProblem {
    /// The set has no lights (L = 0): it would give black for every pixel.
    NoLights,
    /// A member is not a set for reflectances under a light folded into its weights
    /// ([`Samples::Reflectance`](crate::Samples::Reflectance)): radiances or a sensor's
    /// readings have no light to group by.
    NotReflectance,
    /// A member's wavelengths are not member 0's, bit for bit: the lights must share the nodes
    /// the renderer samples at.
    Wavelengths,
    /// A member's display is not member 0's (every field the same bits): one set encodes with
    /// one display.
    Display,
    /// A weight of the light's matrix is not finite
    /// ([`LightGroupSet::new`](crate::LightGroupSet::new)): `weights[light][channel][index]`.
    InvalidWeight {
        /// The weight's channel (its row in the light's matrix).
        channel: crate::Rgb,
        /// Its index in the row: the node.
        index: usize,
    },
}

impl LightGroupProblem {
    /// The problem's identifier, `"no-lights"`, `"not-reflectance"`, `"wavelengths"`,
    /// `"display"` or `"invalid-weight"` (kebab-case, stable across versions). Its [`Display`](fmt::Display) is the
    /// sentence for messages.
    pub const fn name(self) -> &'static str {
        match self {
            LightGroupProblem::NoLights => "no-lights",
            LightGroupProblem::NotReflectance => "not-reflectance",
            LightGroupProblem::Wavelengths => "wavelengths",
            LightGroupProblem::Display => "display",
            LightGroupProblem::InvalidWeight { .. } => "invalid-weight",
        }
    }
}

impl fmt::Display for LightGroupProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            LightGroupProblem::NoLights => "a light-group set needs at least one light",
            LightGroupProblem::NotReflectance => {
                "the member is not a set for reflectances under a folded light"
            }
            LightGroupProblem::Wavelengths => "the member's wavelengths are not member 0's",
            LightGroupProblem::Display => "the member's display is not member 0's",
            LightGroupProblem::InvalidWeight { channel, index } => {
                return write!(
                    f,
                    "weight {index} of channel {} is not finite",
                    channel.name()
                );
            }
        })
    }
}

impl Error {
    /// The error's sentence without the numbers its [`Display`](fmt::Display) adds, as a
    /// `&'static str` from a `const fn`: what a constant can `panic!` with where a constructor
    /// refuses its arguments at compile time (a panic in constant evaluation prints a string,
    /// not a `Display`). The generated tables make every baked constant with its checked
    /// constructor and stop the build with this sentence where one refuses.
    ///
    /// ```
    /// use spectral_quadrature::{Error, Samples, WavelengthSet};
    /// const fn checked<T: Copy>(made: Result<T, Error>) -> T {
    ///     match made {
    ///         Ok(value) => value,
    ///         Err(e) => panic!("{}", e.summary()),
    ///     }
    /// }
    /// const MINE: WavelengthSet<1> = checked(WavelengthSet::new([550.0], [[1.0], [0.0], [0.0]], Samples::Radiance));
    /// let refused = WavelengthSet::new([550.0], [[f32::NAN], [0.0], [0.0]], Samples::Radiance);
    /// assert_eq!(refused.unwrap_err().summary(), "a set's or rule's weight is not finite");
    /// # let _ = MINE;
    /// ```
    pub const fn summary(&self) -> &'static str {
        match self {
            Error::LengthMismatch { what, .. } => match what {
                LengthOf::Output => "length mismatch: an output's pixels against its input's",
                LengthOf::InputPlane => "length mismatch: an input plane against the first",
                LengthOf::OutputPlane => {
                    "length mismatch: an output plane against the input's pixels"
                }
                LengthOf::Samples => "length mismatch: the samples against the set's wavelengths",
                LengthOf::RuleWavelengths => {
                    "length mismatch: a rule's wavelengths against its order"
                }
                LengthOf::RuleWeights => "length mismatch: a rule's weights against its order",
            },
            Error::Capacity { .. } => "the set would need more wavelengths than its capacity",
            Error::UndefinedRule { .. } => "the rule is not a defined rule",
            Error::InvalidLut { .. } => {
                "a lookup table needs 2 or more finite, non-decreasing entries in 0..=1"
            }
            Error::Display(e) => match e {
                DisplayError::Chromaticity { .. } => {
                    "display refused: a chromaticity is not finite, is negative, or has y <= 0 or x + y > 1"
                }
                DisplayError::Collinear { .. } => {
                    "display refused: the primaries are collinear, or a matrix is singular or not finite or not the other's inverse"
                }
                DisplayError::WhiteOutside { .. } => {
                    "display refused: the white is not a mix of the primaries"
                }
                DisplayError::Gamma { .. } => "display refused: gamma is not finite and positive",
                _ => "display refused",
            },
            Error::Calibration { problem, .. } => match problem {
                CalibrationProblem::NoSignal => {
                    "calibration: the white reading is not above the dark one"
                }
                CalibrationProblem::Reference => {
                    "calibration: the reference reading is not finite and positive"
                }
                CalibrationProblem::OutOfRange => {
                    "calibration: the gain or dark offset is out of range"
                }
            },
            Error::InvalidWavelength { .. } => {
                "a wavelength is not finite and positive, or not above the one before"
            }
            Error::InvalidWeight { .. } => "a set's or rule's weight is not finite",
            Error::UpsamplingTable { .. } => {
                "an upsampling table is not grid³ entries for a grid of 2 or more"
            }
            Error::UpsamplingReadings => {
                "an upsampling needs a set whose samples are at wavelengths, not a sensor's readings"
            }
            Error::UpsamplingRoundTrip => {
                "an upsampling's round trip must measure colour in the set's display's RGB → XYZ"
            }
            Error::UpsamplingFigures => {
                "an upsampling's measured figures must be finite and non-negative, the reachable share at most 1"
            }
            Error::InvalidLocus { .. } => {
                "a Planckian locus node is not finite, not ordered, or its chord or fixed-point tangent does not match its point and tangent"
            }
            Error::IntegerRange => {
                "the weights or the sample unit have no fixed-point form for u16 counts"
            }
            Error::IntegerTransfer => "the transfer function has no integer encoder",
            Error::InvalidLuxScale => "a lux scale needs a finite, positive illuminance per unit Y",
            Error::LightGroup { problem, .. } => match problem {
                LightGroupProblem::NoLights => "light group: a light-group set needs at least one light",
                LightGroupProblem::NotReflectance => {
                    "light group: a member is not a set for reflectances under a folded light"
                }
                LightGroupProblem::Wavelengths => {
                    "light group: a member's wavelengths are not member 0's"
                }
                LightGroupProblem::Display => "light group: a member's display is not member 0's",
                LightGroupProblem::InvalidWeight { .. } => {
                    "light group: a weight of a light's matrix is not finite"
                }
            },
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::LengthMismatch {
                what,
                expected,
                got,
            } => match what {
                LengthOf::Output => write!(
                    f,
                    "length mismatch: an output of {got} pixels for an input of {expected}"
                ),
                LengthOf::InputPlane => write!(
                    f,
                    "length mismatch: an input plane of {got} values where the first has {expected}"
                ),
                LengthOf::OutputPlane => write!(
                    f,
                    "length mismatch: an output plane of {got} values for {expected} pixels"
                ),
                LengthOf::Samples => write!(
                    f,
                    "length mismatch: {got} samples for a set of {expected} wavelengths"
                ),
                LengthOf::RuleWavelengths => write!(
                    f,
                    "length mismatch: {got} wavelengths for a rule of {expected} nodes"
                ),
                LengthOf::RuleWeights => write!(
                    f,
                    "length mismatch: {got} weights for a rule of {expected} nodes"
                ),
            },
            Error::Capacity { capacity } => {
                write!(f, "the set would need more than its {capacity} wavelengths")
            }
            Error::UndefinedRule { channel, order } => write!(
                f,
                "channel {} order {order} is not a defined rule",
                channel.name()
            ),
            Error::InvalidLut { channel } => write!(
                f,
                "lookup table for channel {} needs 2 or more finite, non-decreasing entries in 0..=1",
                channel.name()
            ),
            Error::Display(e) => write!(f, "display refused: {e}"),
            Error::Calibration {
                channel_index,
                problem,
            } => write!(
                f,
                "calibration of sensor channel {channel_index}: {problem}"
            ),
            Error::InvalidWavelength { index } => write!(
                f,
                "wavelength {index} is not finite and positive, or not above the one before"
            ),
            Error::InvalidWeight { row, index } => {
                write!(f, "weight {index} of row {row} is not finite")
            }
            Error::UpsamplingTable { grid, entries } => write!(
                f,
                "an upsampling table of {entries} entries is not grid³ for a grid of {grid} (≥ 2)"
            ),
            Error::UpsamplingReadings => f.write_str(
                "an upsampling needs a set whose samples are at wavelengths, not a sensor's readings",
            ),
            Error::UpsamplingRoundTrip => f.write_str(
                "an upsampling's round trip must measure colour in the set's display's RGB → XYZ",
            ),
            Error::UpsamplingFigures => f.write_str(
                "an upsampling's measured figures must be finite and non-negative, the reachable share at most 1",
            ),
            Error::InvalidLocus { node } => write!(
                f,
                "node {node} of a Planckian locus table is not finite, not ordered, or its chord or fixed-point tangent does not match its point and tangent"
            ),
            Error::IntegerRange => f.write_str(
                "the weights or the sample unit have no fixed-point form for u16 counts",
            ),
            Error::IntegerTransfer => f.write_str("the transfer function has no integer encoder"),
            Error::InvalidLuxScale => f.write_str(
                "a lux scale needs a finite, positive illuminance per unit Y (from a finite, positive Y and illuminance)",
            ),
            Error::LightGroup { light, problem } => {
                write!(f, "light group {light}: {problem}")
            }
        }
    }
}

impl core::error::Error for Error {
    fn source(&self) -> Option<&(dyn core::error::Error + 'static)> {
        match self {
            Error::Display(e) => Some(e),
            _ => None,
        }
    }
}

impl From<DisplayError> for Error {
    fn from(e: DisplayError) -> Error {
        Error::Display(e)
    }
}

/// What is wrong with one channel of a calibration (see [`Error::Calibration`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum CalibrationProblem {
    /// The white reading is not above the dark one (or one of them is not finite): there is no
    /// signal to scale. Longer integration, more light, or a wrong channel order.
    NoSignal,
    /// The reference (what the golden device reads on the white) is not finite and positive.
    Reference,
    /// The gain or the dark offset is not finite, or does not fit the integer form (a dark
    /// offset outside 0..=65 535 counts, a gain of 65 536 or more).
    OutOfRange,
}

impl CalibrationProblem {
    /// The problem's identifier, `"no-signal"`, `"reference"` or `"out-of-range"` (kebab-case,
    /// stable across versions). Its [`Display`](fmt::Display) is the sentence for messages.
    pub const fn name(self) -> &'static str {
        match self {
            CalibrationProblem::NoSignal => "no-signal",
            CalibrationProblem::Reference => "reference",
            CalibrationProblem::OutOfRange => "out-of-range",
        }
    }
}

impl fmt::Display for CalibrationProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            CalibrationProblem::NoSignal => "the white reading is not above the dark one",
            CalibrationProblem::Reference => "the reference reading is not finite and positive",
            CalibrationProblem::OutOfRange => "the gain or dark offset is out of range",
        })
    }
}
