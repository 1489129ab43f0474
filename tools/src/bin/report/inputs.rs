//! What the report measures on: the spectra files of the command line (`--reflectances`,
//! `--illuminants`, `--emission`) or the built-in ones, as stimuli.

use std::path::Path;

use spectral_quadrature_spectra::{
    builtin_illuminant, emissions, surfaces_under_lights, Curve, Spectra, Stimulus,
};

use crate::tools::{self, cli::SpectraArgs};
use crate::{Error, Sample};

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

/// The reflectances sections 9 and 10 judge: every one, or a seeded sample of `--sample` of
/// them (those sections refit on each fold's others, which costs time with their number).
pub struct Reflectances {
    /// The reflectances judged.
    pub curves: Vec<Curve>,
    /// Where they come from, in words.
    pub from: String,
    /// How many there are in all (more than `curves.len()` when sampled).
    pub of: usize,
    /// The seed of the sample.
    pub seed: u64,
}

impl Reflectances {
    /// `all` (from `from`), sampled to at most `sample`'s number with `seed`.
    pub fn new(all: Vec<Curve>, from: String, sample: Sample, seed: u64) -> Reflectances {
        let of = all.len();
        let curves = match sample {
            Sample::Most(n) => tools::light_groups::sample(&all, n, seed),
            Sample::All => all,
        };
        Reflectances {
            curves,
            from,
            of,
            seed,
        }
    }

    /// Whether the reflectances are a sample of fewer than all.
    pub fn sampled(&self) -> bool {
        self.curves.len() < self.of
    }

    /// The standard error a sample adds to a mean of `sd`'s spread over its reflectances
    /// (zero when every reflectance is judged).
    pub fn standard_error(&self, sd: f64) -> f64 {
        tools::light_groups::standard_error(sd, self.curves.len(), self.of)
    }

    /// For a sampled section's text: what was sampled and the largest standard error it adds
    /// to the section's means, `worst` (ΔE00) and `worst_relative` (of the mean it is on).
    pub fn statement(&self, worst: f64, worst_relative: f64) -> String {
        format!(
            "   Sampled: {} of the {} reflectances (--sample {}, seed {}; --sample all judges every one). A mean\n   below stands for the mean over all {} within a standard error of at most {worst:.3} ΔE00 ({:.1} % of it;\n   the spread of the sample's errors, finite-population correction included).",
            self.curves.len(),
            self.of,
            self.curves.len(),
            self.seed,
            self.of,
            100.0 * worst_relative
        )
    }
}
