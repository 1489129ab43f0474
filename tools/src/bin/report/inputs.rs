//! What the report measures on: the spectra files of the command line (`--reflectances`,
//! `--illuminants`, `--emission`) or the built-in ones, as stimuli.

use std::path::Path;

use spectral_quadrature_spectra::{
    builtin_illuminant, emissions, surfaces_under_lights, Curve, Spectra, Stimulus,
};

use crate::tools::{self, cli::SpectraArgs};
use crate::Error;

/// The lights the surfaces are under when the user gives none.
pub const DEFAULT_ILLUMINANTS: [&str; 6] = ["C", "D65", "A", "F2", "F11", "LED_B2"];

/// What the report measures on.
pub struct Inputs {
    /// Every stimulus: surfaces under lights, or lights seen directly.
    pub stimuli: Vec<Stimulus>,
    /// The surfaces (the user's, or the ColorChecker and the CIE test colours).
    pub surfaces: Vec<Curve>,
    /// Where the surfaces come from, in words.
    pub surfaces_from: String,
    /// The lights of --illuminants (empty without it).
    pub user_lights: Vec<Curve>,
    /// The lights the surfaces are under: the user's or the default ones (empty for
    /// --emission).
    pub lights: Vec<Curve>,
}

/// Reads the spectra files of the command line (each one's curves on `range`), or takes the
/// built-in spectra where none is given.
pub fn load(spectra: &SpectraArgs, range: [f64; 2]) -> Result<Inputs, Error> {
    let read = |p: &Path| {
        let file = Spectra::read_with(p, tools::negatives(spectra.clamp_negatives))?;
        tools::warn_zeroed("report", file.zeroed());
        file.curves(range)
    };
    let (surfaces, surfaces_from) = match &spectra.reflectances {
        Some(p) => (read(p)?, p.display().to_string()),
        None => (
            tools::prefilter::default_surfaces(range)?,
            "the ColorChecker and CIE TCS 1-14".to_string(),
        ),
    };
    let user_lights = match &spectra.illuminants {
        Some(p) => read(p)?,
        None => Vec::new(),
    };
    let (stimuli, lights) = if let Some(path) = &spectra.emission {
        (emissions(&read(path)?), Vec::new())
    } else if user_lights.is_empty() {
        let lights: Vec<Curve> = DEFAULT_ILLUMINANTS
            .iter()
            .map(|n| builtin_illuminant(Path::new(tools::DATA_DIR), n, range))
            .collect::<Result<_, _>>()?;
        (surfaces_under_lights(&surfaces, &lights), lights)
    } else {
        (
            surfaces_under_lights(&surfaces, &user_lights),
            user_lights.clone(),
        )
    };
    Ok(Inputs {
        stimuli,
        surfaces,
        surfaces_from,
        user_lights,
        lights,
    })
}
