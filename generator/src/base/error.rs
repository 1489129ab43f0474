//! The crate's errors, as types: what went wrong, and in which file and at which line when a
//! file is involved.
//!
//! Every fallible function of this crate returns [`Error`]. Its `Display` gives the one-line
//! message the build script and the tools print (`scene.toml:2: TABLE9_ROW1: not a set name
//! (forms: …)`); callers that want to react match on the variant instead of reading the text.
//!
//! The errors sit below everything that returns them, so what they carry is defined here too:
//! the planner's [`PlanError`] reports the best [`Candidate`] for a [`Metric`]. Two messages quote
//! constants of the layers above and are written there, beside them: [`SetNameProblem`]'s
//! `Display` is in the catalogue (the set-name forms, the channel names). A display's problem is
//! `spectral_quadrature_math::DisplayError`, the one type the runtime reports too.

use std::boxed::Box;
use std::fmt;
use std::string::String;
use std::vec::Vec;

use spectral_quadrature_spectra::DataError;

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
        problem: spectral_quadrature_math::DisplayError,
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
    /// A device's readings to which no calibration fits ([`crate::calibration::fit`]).
    Calibration {
        /// The sensor's channel, counted from 1.
        channel: usize,
        /// Why none fits.
        problem: CalibrationProblem,
    },
}

/// Why a device's readings give no calibration in a channel ([`Error::Calibration`]).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum CalibrationProblem {
    /// The golden device reads every reflectance the same: no slope to fit.
    GoldenFlat,
    /// The device's readings do not grow with the golden device's (a wrong channel order or a
    /// dead channel).
    NotGrowing {
        /// The fitted slope, not positive (or not finite).
        slope: f64,
    },
}

/// Why a name names no set ([`crate::catalog::resolve`]).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum SetNameProblem {
    /// None of the catalogue's forms (the message lists them).
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
        /// The lights of the scene's `[lights]` (empty outside a scene).
        scene: Vec<String>,
    },
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
            Error::Calibration { channel, problem } => match problem {
                CalibrationProblem::GoldenFlat => write!(
                    f,
                    "channel {channel}: the golden device reads every reflectance the same; nothing to fit"
                ),
                CalibrationProblem::NotGrowing { slope } => write!(
                    f,
                    "channel {channel}: the readings do not grow with what the golden device reads (slope {slope:.3e}); are the columns in the sensor's order?"
                ),
            },
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

/// Why no set could be chosen.
#[derive(Debug, Clone, PartialEq)]
pub enum PlanError {
    /// The budget is not a finite number greater than 0.
    BadBudget(f64),
    /// There were no candidates to choose from.
    NoCandidates,
    /// There were no stimuli to measure the sets on.
    NoStimuli,
    /// A stimulus whose reference colour is not finite (a light that is zero everywhere).
    NoReference {
        /// The stimulus.
        stimulus: String,
        /// Its CIELAB under the full integration.
        lab: [f64; 3],
    },
    /// Neither emission, nor both reflectances and illuminants, were given.
    NoSpectra,
    /// No candidate meets the budget; `best` has the lowest error of all (ties: fewer
    /// wavelengths, then name).
    Unreachable {
        /// The budget on ΔE00.
        budget: f64,
        /// Which statistic the budget bounds.
        metric: Metric,
        /// The set with the lowest error.
        best: Candidate,
        /// How many sets were measured.
        evaluated: usize,
    },
}

impl fmt::Display for PlanError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PlanError::BadBudget(b) => write!(
                f,
                "bad budget: {b}: the ΔE00 budget must be a finite number greater than 0"
            ),
            PlanError::NoCandidates => f.write_str("no sets to choose from"),
            PlanError::NoStimuli => f.write_str("no stimuli to measure the sets on"),
            PlanError::NoReference { stimulus, lab } => write!(
                f,
                "stimulus {stimulus:?}: its reference colour is not finite (CIELAB {lab:?}); is the light zero?"
            ),
            PlanError::NoSpectra => {
                f.write_str("give reflectances and illuminants, or emission")
            }
            PlanError::Unreachable {
                budget,
                metric,
                best,
                evaluated,
            } => write!(
                f,
                "no set meets {metric} ΔE00 <= {budget}: the best achievable is {metric} ΔE00 {} by {} with {} wavelengths ({evaluated} sets evaluated)",
                fmt_de(best.error(*metric)),
                best.name,
                best.wavelengths
            ),
        }
    }
}

impl std::error::Error for PlanError {}

/// Which statistic of ΔE00 over the stimuli the budget bounds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Metric {
    /// The mean ΔE00 over the stimuli.
    Mean,
    /// The largest ΔE00 over the stimuli.
    Max,
}

impl Metric {
    /// `"mean"` or `"max"`.
    pub(crate) fn as_str(self) -> &'static str {
        match self {
            Metric::Mean => "mean",
            Metric::Max => "max",
        }
    }
}

impl fmt::Display for Metric {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl core::str::FromStr for Metric {
    type Err = Error;

    /// `mean` or `max` (any case); otherwise [`Error::Metric`].
    fn from_str(s: &str) -> Result<Metric, Error> {
        match s.to_ascii_lowercase().as_str() {
            "mean" => Ok(Metric::Mean),
            "max" => Ok(Metric::Max),
            _ => Err(Error::Metric(s.into())),
        }
    }
}

/// One set the crate can build, measured on the stimuli.
#[derive(Debug, Clone, PartialEq)]
pub struct Candidate {
    /// The set's name ([`crate::catalog::resolve`] builds it).
    pub name: String,
    /// Its number of distinct wavelengths (the samples a renderer takes per pixel).
    pub wavelengths: usize,
    /// Mean ΔE00 over the stimuli.
    pub mean_de00: f64,
    /// Largest ΔE00 over the stimuli.
    pub max_de00: f64,
    /// Mean ΔE*ab over the stimuli.
    pub mean_de76: f64,
    /// Largest ΔE*ab over the stimuli.
    pub max_de76: f64,
}

impl Candidate {
    /// The ΔE00 statistic the budget bounds.
    pub fn error(&self, metric: Metric) -> f64 {
        match metric {
            Metric::Mean => self.mean_de00,
            Metric::Max => self.max_de00,
        }
    }

    /// Whether the set meets the budget (`error <= budget`; a NaN error never does).
    pub fn meets(&self, budget: f64, metric: Metric) -> bool {
        self.error(metric) <= budget
    }
}

/// A ΔE for messages: three decimals, or three significant digits below 0.01.
pub fn fmt_de(x: f64) -> String {
    if x.is_finite() && x != 0.0 && x.abs() < 0.01 {
        std::format!("{x:.3e}")
    } else {
        std::format!("{x:.3}")
    }
}
