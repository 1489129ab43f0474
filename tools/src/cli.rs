//! The command-line arguments the programs share: the user's spectra files and how their
//! negative values are read (`report` and `plan` flatten [`SpectraArgs`] into their own).

use std::path::PathBuf;

/// The spectra a program judges sets on: surfaces under lights, or lights seen directly.
#[derive(clap::Args, Debug, Clone)]
pub struct SpectraArgs {
    /// Reflectances (CSV: wavelength_nm, one column per surface). Default: the ColorChecker
    /// (Ohta) and the CIE test colour samples 1-14.
    #[arg(long, value_name = "FILE")]
    pub reflectances: Option<PathBuf>,
    /// Illuminants (CSV: wavelength_nm, one column per light). Default: each program's own (the
    /// report: CIE C, D65, A, F2, F11 and LED-B2; the planner: C).
    #[arg(long, value_name = "FILE")]
    pub illuminants: Option<PathBuf>,
    /// Light spectra seen directly (CSV), instead of surfaces under illuminants.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["reflectances", "illuminants"])]
    pub emission: Option<PathBuf>,
    /// Read every negative value of the spectra files given here as 0 (each file's count is
    /// printed as a warning), for measured data whose noise exceeds the tolerance (1e-6 of the
    /// file's largest value; within it, values are read as 0 without this flag). A scene sets
    /// its own files' rule with `clamp_negatives = true`.
    #[arg(long)]
    pub clamp_negatives: bool,
}

impl SpectraArgs {
    /// Whether any spectra file was given (the built-in data serve otherwise).
    pub fn any(&self) -> bool {
        self.reflectances.is_some() || self.illuminants.is_some() || self.emission.is_some()
    }
}
