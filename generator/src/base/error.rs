//! The derivation's errors, as types: what went wrong, and in which file and at which line when a
//! file is involved.
//!
//! Every fallible function of this crate returns [`Error`]. Its `Display` gives the one-line
//! message the build script and the tools print (`scene.toml:2: TABLE9_ROW1: not a set name
//! (forms: …)`); callers that want to react match on the variant instead of reading the text.

use std::boxed::Box;
use std::fmt;
use std::string::String;
use std::vec::Vec;

use super::plan::PlanError;
use super::sets::CHANNELS;
use super::table::DataError;

/// An error of the derivation, of code generation, of a scene or of the planner.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// A file is malformed or cannot be read: data files, scenes, user spectra, the node cache.
    /// Names the file and the line.
    Data(DataError),
    /// A well-formed entry of a file that cannot be honoured (a scene's unknown set, a display
    /// that cannot be derived, a plan that cannot be met): the file, the line, and why.
    At {
        /// The file.
        file: String,
        /// 1-based line, or 0 for the file as a whole.
        line: u64,
        /// What went wrong there.
        error: Box<Error>,
        /// The valid choices, where the entry names one.
        hint: Option<String>,
    },
    /// Settings (grid, range, order, covariance input) the derivation cannot honour.
    Settings(String),
    /// A set name that does not name a set the crate can build.
    SetName {
        /// The name as given.
        name: String,
        /// Why it names no set.
        problem: SetNameProblem,
    },
    /// Building the named set failed.
    InSet {
        /// The set's name.
        name: String,
        /// What failed.
        error: Box<Error>,
    },
    /// A display whose primaries and white point give no usable matrices.
    Display {
        /// The display's const name.
        name: String,
        /// What is wrong with it.
        problem: DisplayProblem,
    },
    /// A display name that is not one of the crate's displays.
    UnknownDisplay {
        /// The name as given.
        name: String,
        /// The displays there are.
        valid: Vec<String>,
    },
    /// A transfer function that is not `srgb`, `linear` or `gamma <γ>` with a finite γ > 0.
    Transfer(String),
    /// A planner metric that is not `mean` or `max`.
    Metric(String),
    /// A light that cannot be folded into a set.
    Light {
        /// The light's name.
        name: String,
        /// What is wrong with it.
        problem: LightProblem,
    },
    /// A numerical step failed (a singular matrix, no rule at the optimised nodes).
    Numerical(String),
    /// A value that no literal of the target language reproduces as a finite f32.
    Literal {
        /// The value.
        value: f64,
        /// The language: `"Rust"`, `"WGSL"` or `"GLSL"`.
        language: &'static str,
    },
    /// Generated shader text that is not ASCII (a set, display or scene name that is not).
    NotAscii {
        /// The language: `"WGSL"` or `"GLSL"`.
        language: &'static str,
    },
    /// The planner found no set for the budget.
    Plan(PlanError),
    /// A worker thread measuring sets panicked.
    Panicked(&'static str),
}

/// Why a name names no set ([`crate::catalog::resolve`]).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum SetNameProblem {
    /// None of the forms in [`crate::catalog::NAME_FORMS`].
    UnknownForm,
    /// The form is known but its parts are not (`expected` shows the form).
    Malformed {
        /// The form expected.
        expected: &'static str,
    },
    /// A part that should be an order or a size is not a number.
    NotAnOrder(String),
    /// The channel's order is beyond what the derivation computed.
    OrderNotDerived {
        /// 0 = A, 1 = C1, 2 = C2.
        channel: usize,
        /// The order asked for.
        order: usize,
        /// The highest order derived.
        max: usize,
    },
    /// The channel's Gauss rule of that order is undefined.
    RuleUndefined {
        /// 0 = A, 1 = C1, 2 = C2.
        channel: usize,
        /// The order.
        order: usize,
        /// The rule's status.
        status: &'static str,
        /// Why, as the quadrature found it.
        reason: String,
    },
    /// The family has no set of that size.
    Size {
        /// The family (`"uniform"`, `"shared"`).
        family: &'static str,
        /// The size asked for.
        size: usize,
        /// The sizes there are.
        sizes: core::ops::RangeInclusive<usize>,
    },
    /// `KQ_<light>_<n>` names a light that is not built in.
    UnknownLight {
        /// The light.
        light: String,
        /// The built-in lights.
        valid: Vec<String>,
    },
}

/// Why a display cannot be derived ([`crate::display::display_matrices`]).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum DisplayProblem {
    /// A chromaticity outside x ≥ 0, y > 0, x + y ≤ 1, or not finite.
    Chromaticity {
        /// `"red primary"`, `"green primary"`, `"blue primary"` or `"white"`.
        which: &'static str,
        /// The chromaticity.
        xy: [f64; 2],
    },
    /// The primaries are nearly collinear: the condition number exceeds
    /// [`crate::display::MAX_CONDITION`].
    Collinear {
        /// The 2-norm condition number.
        condition: f64,
    },
    /// The white point lies outside the primaries' triangle.
    WhiteOutside {
        /// The white.
        white_xy: [f64; 2],
        /// The gun drives white would need.
        drives: [f64; 3],
    },
    /// A matrix that should be invertible is singular.
    Singular(&'static str),
}

/// Why a light cannot be folded into a set.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum LightProblem {
    /// Not one of the built-in illuminants.
    NotBuiltIn {
        /// The built-in illuminants.
        valid: Vec<String>,
    },
    /// A negative or non-finite value on the derivation's grid.
    Negative,
    /// Its luminance is zero.
    NoLuminance,
}

impl Error {
    /// The file and line the error names, if it names one.
    pub fn location(&self) -> Option<(&str, u64)> {
        match self {
            Error::Data(e) => Some((&e.file, e.line)),
            Error::At { file, line, .. } => Some((file, *line)),
            _ => None,
        }
    }

    /// `self`, found at `line` of `file` (0: the file as a whole). An error that already names
    /// a file is returned as it is.
    pub fn at(self, file: &str, line: u64) -> Error {
        if self.location().is_some() {
            return self;
        }
        Error::At {
            file: file.into(),
            line,
            error: Box::new(self),
            hint: None,
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Data(e) => e.fmt(f),
            Error::At {
                file,
                line,
                error,
                hint,
            } => {
                if *line == 0 {
                    write!(f, "{file}: {error}")?;
                } else {
                    write!(f, "{file}:{line}: {error}")?;
                }
                match hint {
                    Some(h) => write!(f, "; {h}"),
                    None => Ok(()),
                }
            }
            Error::Settings(s) | Error::Numerical(s) => f.write_str(s),
            Error::SetName { name, problem } => write!(f, "{name}: {problem}"),
            Error::InSet { name, error } => write!(f, "{name}: {error}"),
            Error::Display { name, problem } => write!(f, "display {name}: {problem}"),
            Error::UnknownDisplay { name, valid } => {
                write!(f, "unknown display {name:?}; valid: {}", valid.join(", "))
            }
            Error::Transfer(s) => write!(
                f,
                "unknown transfer function {s:?}; valid: \"srgb\", \"linear\", \"gamma <γ>\" with γ > 0"
            ),
            Error::Metric(s) => write!(f, "unknown metric {s:?}; valid: mean, max"),
            Error::Light { name, problem } => write!(f, "light {name}: {problem}"),
            Error::Literal { value, language } => {
                write!(f, "no {language} literal reproduces {value} as a finite f32")
            }
            Error::NotAscii { language } => write!(f, "{language} text is not ASCII"),
            Error::Plan(e) => e.fmt(f),
            Error::Panicked(what) => write!(f, "{what} panicked"),
        }
    }
}

impl fmt::Display for SetNameProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SetNameProblem::UnknownForm => {
                write!(f, "not a set name (forms: {})", super::catalog::NAME_FORMS)
            }
            SetNameProblem::Malformed { expected } => write!(f, "expected {expected}"),
            SetNameProblem::NotAnOrder(s) => write!(f, "{s:?} is not an order"),
            SetNameProblem::OrderNotDerived {
                channel,
                order,
                max,
            } => write!(
                f,
                "{} order {order} is not among the derived orders 1..={max}",
                CHANNELS[*channel]
            ),
            SetNameProblem::RuleUndefined {
                channel,
                order,
                status,
                reason,
            } => write!(
                f,
                "{} order {order} is undefined ({status}: {reason})",
                CHANNELS[*channel]
            ),
            SetNameProblem::Size {
                family,
                size,
                sizes,
            } => write!(
                f,
                "{family} sets have {} to {} wavelengths, not {size}",
                sizes.start(),
                sizes.end()
            ),
            SetNameProblem::UnknownLight { light, valid } => write!(
                f,
                "{light} is not a built-in illuminant (data/illuminant_<light>.csv: {})",
                valid.join(", ")
            ),
        }
    }
}

impl fmt::Display for DisplayProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DisplayProblem::Chromaticity { which, xy } => write!(
                f,
                "{which} chromaticity ({}, {}) is not a valid colour",
                xy[0], xy[1]
            ),
            DisplayProblem::Collinear { condition } => write!(
                f,
                "primaries are nearly collinear (condition number {condition:.3e} > threshold {:e})",
                super::display::MAX_CONDITION
            ),
            DisplayProblem::WhiteOutside { white_xy, drives } => write!(
                f,
                "white point ({}, {}) lies outside the primaries' triangle (gun drives for white {drives:?})",
                white_xy[0], white_xy[1]
            ),
            DisplayProblem::Singular(what) => write!(f, "{what} matrix is singular"),
        }
    }
}

impl fmt::Display for LightProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LightProblem::NotBuiltIn { valid } => write!(
                f,
                "not a built-in illuminant (data/illuminant_<light>.csv: {})",
                valid.join(", ")
            ),
            LightProblem::Negative => {
                f.write_str("a negative or non-finite value on the derivation's grid")
            }
            LightProblem::NoLuminance => f.write_str("no luminance"),
        }
    }
}

impl std::error::Error for Error {}

impl From<DataError> for Error {
    fn from(e: DataError) -> Self {
        Error::Data(e)
    }
}

impl From<PlanError> for Error {
    fn from(e: PlanError) -> Self {
        Error::Plan(e)
    }
}
