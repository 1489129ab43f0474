//! Spectral data for `spectral-quadrature`, in f64: measured spectra read from CSV, curves and
//! the stimuli they make, and the measuring of wavelength sets in CIELAB.
//!
//! The build-time generator (`spectral-quadrature-generator`) reads its observers, lights, sensors
//! and scene spectra with this crate, and the desk tools (report, planner, Cornell box) measure
//! sets with it; users read their own measured files with it:
//!
//! ```
//! use spectral_quadrature_spectra::{surfaces_under_lights, Curve, EvalSet, Reference, Spectra};
//!
//! let text = "wavelength_nm,grey,red\n380,0.5,0.1\n580,0.5,0.2\n780,0.5,0.9\n";
//! let surfaces = Spectra::parse("mine.csv", text).unwrap().curves([380.0, 780.0]).unwrap();
//! let light = Curve::constant("E", 1.0, [380.0, 780.0]);
//! let stimuli = surfaces_under_lights(&surfaces, &[light]);
//! assert_eq!(stimuli[1].name, "red under E");
//!
//! // Two sets with made-up XYZ weights, one of them the reference.
//! let dense = EvalSet::from_weights(
//!     "dense", "example", None, &[450.0, 550.0, 650.0],
//!     &[vec![0.3, 0.4, 0.3], vec![0.1, 0.7, 0.2], vec![0.8, 0.2, 0.0]],
//!     &[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
//! );
//! let reference = Reference::new(dense.clone(), &stimuli);
//! let errors = reference.errors(&dense, &stimuli);
//! assert_eq!(errors.max_de00(), 0.0); // a set measured against itself
//! ```
//!
//! - Reading: [`Spectra`] (CSV with one header row, the wavelength in nm first, any strictly
//!   increasing spacing), over the lower-level [`parse_table`]; every malformed input is a
//!   [`DataError`] naming the file and the line, and nothing is skipped. Negative values follow
//!   one rule, [`Negatives`]: rounding noise is read as 0 and reported ([`ZeroedNegatives`]),
//!   anything more negative is an error unless the caller asks to clamp.
//! - Curves and stimuli: [`Curve`] (linear interpolation), [`Stimulus`] (a light, possibly
//!   reflected by a surface, and the white of CIELAB), [`surfaces_under_lights`], [`emissions`],
//!   and the illuminants the runtime crate ships in its `data/` ([`builtin_lights`],
//!   [`builtin_illuminant`], [`Spectra::builtin`]).
//! - Measuring: an [`EvalSet`] (a set's wavelengths and XYZ weights) against a [`Reference`]
//!   integration gives [`Errors`], ΔE*ab and CIEDE2000 per stimulus (from
//!   `spectral-quadrature-math`, the runtime's copy).
//!
//! The generator builds the reference and the sets of a derivation (`Observer::full_integration`,
//! `Derivation::eval_set`); this crate knows no observer and no derivation.

#![deny(missing_docs)]
#![forbid(unsafe_code)]

mod curves;
mod error;
mod files;
mod measure;
mod table;

pub use curves::{
    builtin_illuminant, builtin_lights, emissions, surfaces_under_lights, Curve, Spectra, Stimulus,
    BUILTIN_FILES,
};
pub use error::DataError;
pub use files::{data_path, read_data_text, read_error};
pub use measure::{Errors, EvalSet, Reference};
pub use table::{
    parse_table, parse_table_with, read_table, read_table_with, read_text, Negatives, Spacing,
    Table, ValueAt, ZeroedNegatives, NEGATIVE_TOLERANCE,
};
