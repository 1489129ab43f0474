//! What only people at a desk need, on top of `spectral-quadrature-generator`: the analysis behind
//! the report and the planner. The programs are `report` (error against run time, the crate's
//! main job), `plan` (a scene for an error budget) and `tables` (the derived tables beside the
//! paper's). The Cornell box renderers, `cornell` and `render`, are the package
//! `spectral-quadrature-render`, built on this library.
//!
//! - [`budget`]: every method at each wavelength budget (report section 5).
//! - [`cli`]: the command-line arguments the programs share.
//! - [`csv_table`]: every CSV the programs write, through the `csv` crate's writer.
//! - [`evaluate`]: the sets the report builds to measure beside the crate's (every combination
//!   of per-channel rules, a shared set on radiances).
//! - [`interreflection`]: light that bounces, the forms of reflectance a path carries after
//!   several surfaces and the fixed sets judged on them (section 10).
//! - [`light_groups`]: light groups judged on reflectances no fit saw, by five-fold
//!   cross-validation (section 9).
//! - [`node_cache`]: the nodes the report's node searches find on its default inputs, kept in
//!   a file with a fingerprint of each search's inputs (sections 4, 5, 9, 10).
//! - [`paper`]: the numbers the paper prints, which `tables` and the tests compare with.
//! - [`prefilter`]: spiky lamps, band-averaged and exact-line pre-filtering (section 6d).
//! - [`stability`]: unstable alternatives to the crate's quadrature (section 6b).
//! - [`sensitivity`]: how rules move with the grid, the range and the observer (section 6c).
//! - [`random_wavelengths`]: what renderers do instead, random wavelengths per sample (section 7).
//! - [`scene_file`]: the scene file `plan` writes for the set it chose.
//! - [`upsampling`]: RGB materials under another light, the crate's upsampling beside
//!   Jakob-Hanika, Mallett-Yuksel and Smits (section 8).
#![deny(missing_docs)]

use spectral_quadrature_spectra::{DataError, Negatives, ZeroedNegatives};
use std::path::PathBuf;

pub mod budget;
pub mod cli;
pub mod csv_table;
pub mod evaluate;
pub mod interreflection;
pub mod light_groups;
pub mod node_cache;
pub mod paper;
pub mod prefilter;
pub mod random_wavelengths;
pub mod scene_file;
pub mod sensitivity;
pub mod stability;
pub mod upsampling;

/// The runtime package's `data/`: the CIE tables, illuminants and reflectances the derivation
/// reads ([`spectral_quadrature_generator::Settings::data_dir`]). The runtime's build script names
/// it (build.rs): the workspace's `data/` in a checkout (`cargo run`, `cargo install --path
/// tools`), Cargo's unpacked copy of the published `spectral-quadrature` package for
/// `cargo install spectral-quadrature-tools`. An absolute path: the tools run from any folder.
pub const DATA_DIR: &str = env!("SPECTRAL_QUADRATURE_TOOLS_DATA_DIR");

/// The runtime package's root (see [`DATA_DIR`]): where its build script finds `data/` and
/// resolves a relative `SPECTRAL_QUADRATURE_SCENE`.
pub const CRATE_DIR: &str = env!("SPECTRAL_QUADRATURE_TOOLS_CRATE_DIR");

/// `items.iter().map(f).collect()`, with the items shared among as many threads as the machine
/// has cores (each thread takes the next item when it is done with one, so uneven items balance),
/// and the results in the items' order. A panic in `f` is resumed on the calling thread.
pub fn par_map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(items.len());
    if threads <= 1 {
        return items.iter().map(f).collect();
    }
    let next = AtomicUsize::new(0);
    let mut done: Vec<(usize, R)> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads)
            .map(|_| {
                s.spawn(|| {
                    let mut mine = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        let Some(item) = items.get(i) else {
                            return mine;
                        };
                        mine.push((i, f(item)));
                    }
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
            .collect()
    });
    done.sort_by_key(|d| d.0);
    done.into_iter().map(|d| d.1).collect()
}

/// The paper's settings on the workspace's data ([`DATA_DIR`]).
pub fn settings() -> spectral_quadrature_generator::Settings {
    spectral_quadrature_generator::Settings::new(DATA_DIR)
}

/// Prints, on standard error, one warning per file whose negative values were read as 0
/// ([`ZeroedNegatives`]: how many, where the first is, the
/// tolerance or the clamping), as `<program>: warning: <file>:<line>: ...`.
pub fn warn_zeroed<'a>(program: &str, zeroed: impl IntoIterator<Item = &'a ZeroedNegatives>) {
    for z in zeroed {
        eprintln!("{program}: warning: {z}");
    }
}

/// The rule for negative values the tools apply to the spectra files given on their command
/// line: [`Negatives::Clamp`] with `--clamp-negatives`, otherwise the readers' default
/// (rounding noise read as 0, anything more negative an error naming file, line and column).
pub fn negatives(clamp: bool) -> Negatives {
    if clamp {
        Negatives::Clamp
    } else {
        Negatives::Refuse
    }
}

/// An error of the tools: the derivation's ([`spectral_quadrature_generator::Error`], which names
/// the file and line where a file is at fault), or one of the tools' own.
#[derive(Debug)]
#[non_exhaustive]
pub enum Error {
    /// From the derivation: data, settings, sets, lights, scenes, the planner.
    Derive(spectral_quadrature_generator::Error),
    /// A light with no power at a node where an interval set divides by it.
    NoPower {
        /// The light.
        light: String,
        /// The node, nm.
        nm: f64,
    },
    /// A comparison method that is not in [`budget::METHODS`].
    UnknownMethod(String),
    /// A set size the report has no timing path for.
    NoTimingPath(usize),
    /// A file or directory that could not be written.
    Write {
        /// The path.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A plot that could not be drawn: the plotting library's error.
    Plot(String),
    /// A random-wavelength study asked for something it cannot measure (a sampler that misses
    /// part of the integrand, no samples), in words.
    Sampling(String),
}

impl std::fmt::Display for Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Error::Derive(e) => e.fmt(f),
            Error::NoPower { light, nm } => {
                write!(
                    f,
                    "{light}: no power at {nm} nm to fold into an interval set"
                )
            }
            Error::UnknownMethod(m) => write!(f, "unknown method {m}"),
            Error::NoTimingPath(n) => write!(f, "no timing path for a set of {n} wavelengths"),
            Error::Write { path, source } => write!(f, "cannot write {}: {source}", path.display()),
            Error::Plot(message) => write!(f, "plotting failed: {message}"),
            Error::Sampling(message) => write!(f, "random wavelengths: {message}"),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Write { source, .. } => Some(source),
            _ => None,
        }
    }
}

impl From<spectral_quadrature_generator::Error> for Error {
    fn from(e: spectral_quadrature_generator::Error) -> Self {
        Error::Derive(e)
    }
}

impl From<DataError> for Error {
    fn from(e: DataError) -> Self {
        Error::Derive(e.into())
    }
}

impl From<spectral_quadrature_generator::plan::PlanError> for Error {
    fn from(e: spectral_quadrature_generator::plan::PlanError) -> Self {
        Error::Derive(e.into())
    }
}
