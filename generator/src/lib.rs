//! The host-side derivation behind `spectral-quadrature`, in f64: Meyer's method from CIE data
//! to Gauss rules, the shared (kernel-quadrature) sets, scenes, and the code generation of the
//! runtime's `const` tables and shader snippets.
//!
//! The runtime's `build.rs` calls [`build::generate`] with the path of its `data/` directory (as
//! chrono-tz's build script calls chrono-tz-build); the tests compare the baked tables with a
//! fresh derivation; the desk tools (report, planner) build on it; and users can run it with
//! their own settings or data:
//!
//! ```
//! use spectral_quadrature_build::{derive, Settings};
//! # let data_dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../data");
//! // data_dir: a directory laid out like the runtime crate's data/ (CIE tables as CSV).
//! let d = derive(&Settings::new(data_dir)).unwrap();
//! let a3 = &d.rules[0][2]; // channel A, order 3
//! assert_eq!(a3.nodes_nm.len(), 3);
//! ```
//!
//! # What lives here and why
//!
//! Everything a baked table needs, and nothing else: a downstream build runs this crate at
//! Cargo's default build-script opt-level 0. [`evaluate`] (spectra, exact integration, CIELAB)
//! and [`plan`] stay here because a scene with a `[plan]` section is resolved at build time by
//! measuring sets against the scene's spectra; the report, the stability and sensitivity studies
//! and the pre-filtering analysis live in the `spectral-quadrature-tools` crate.
//!
//! The steps, named after the paper: [`observer`] loads x̄ȳz̄; [`opponent`] forms the cone
//! fundamentals (Eq. 1), the covariance (Eq. 4-5) and the KL transform (Eq. 9-10);
//! [`quadrature`] runs the recurrence (Eq. 16) and forms each order's rule; [`sets`] merges rules
//! into wavelength sets (Table 2); [`codegen`] writes the tables the runtime includes.
//! [`shared`] finds the shared sets by kernel quadrature, and [`user`] fits sets to what a
//! scene brings: a light by file, fixed wavelengths, a sensor's channels. Every fallible
//! function returns [`Error`].

#![deny(missing_docs)]

pub mod build;
pub mod catalog;
pub mod codegen;
pub mod display;
pub mod error;
pub mod evaluate;
pub mod lab;
pub mod observer;
pub mod opponent;
pub mod plan;
pub mod quadrature;
pub mod scene;
pub mod sets;
pub mod shader;
pub mod shared;
pub mod table;
pub mod transfer_tables;
pub mod user;

use std::path::{Path, PathBuf};
use std::string::String;
use std::vec::Vec;

pub use error::{DisplayProblem, Error, LightProblem, SetNameProblem};
pub use observer::{Observer, ObserverId};
pub use opponent::{Covariance, Opponent};
pub use quadrature::{Measure, Recurrence, Rule, Status};
pub use sets::WavelengthSet;
pub use table::DataError;

/// What the derivation starts from. [`Settings::new`] gives the paper's: CIE 1931 2°,
/// 380-770 nm every 5 nm, δ covariance, orders 1 to 16.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    /// The directory the data files are read from, laid out like the runtime crate's `data/`
    /// (`cmf_cie1931_2deg_1nm.csv`, `illuminant_C.csv`, ...). Files are named in headers and
    /// errors as `data/<file>`, whatever this path is, so generated text does not depend on
    /// where the crate lives.
    pub data_dir: PathBuf,
    /// The colour-matching functions.
    pub observer: ObserverId,
    /// The spectrum's limits in nm (Eq. 2): the grid's first and last wavelength.
    pub range_nm: [f64; 2],
    /// Grid step in nm: a whole multiple of the observer table's 1 nm.
    pub step_nm: f64,
    /// Rules are formed for orders 1..=max_order in each channel.
    pub max_order: usize,
    /// K(λ, μ) of Eq. 5.
    pub covariance: Covariance,
    /// XYZ → SML (Eq. 1 by default).
    pub cone_matrix: [[f64; 3]; 3],
    /// Round the observer's x̄, ȳ, z̄ to this many decimals before deriving (`None`: as
    /// published). The paper's Table 1a is reproduced most closely with `Some(5)` (see
    /// [`Settings::paper`]).
    pub observer_decimals: Option<u32>,
}

impl Settings {
    /// The paper's settings, reading data from `data_dir` (see [`Settings::data_dir`]).
    pub fn new(data_dir: impl Into<PathBuf>) -> Settings {
        Settings {
            data_dir: data_dir.into(),
            observer: ObserverId::Cie1931_2deg,
            range_nm: [380.0, 770.0],
            step_nm: 5.0,
            max_order: 16,
            covariance: Covariance::Delta,
            cone_matrix: opponent::MEYER_EQ1_XYZ_TO_SML,
            observer_decimals: None,
        }
    }

    /// The default settings for another observer: its cone matrix
    /// ([`ObserverId::cone_matrix`], which for some observers is computed from the table, so
    /// this reads it) and range ([`ObserverId::default_range_nm`]).
    pub fn for_observer(
        observer: ObserverId,
        data_dir: impl Into<PathBuf>,
    ) -> Result<Settings, Error> {
        let data_dir = data_dir.into();
        let table = observer.load(&data_dir)?;
        Ok(Settings {
            observer,
            range_nm: observer.default_range_nm(),
            cone_matrix: observer.cone_matrix(&table),
            ..Settings::new(data_dir)
        })
    }

    /// The settings that reproduce the paper's printed tables most closely: the defaults with
    /// the observer rounded to 5 decimals. Against Table 1a this lowers the largest node
    /// difference from 0.57 to 0.39 nm and the mean from 0.090 to 0.069 nm (4 decimals is far
    /// worse, 6 no better), which suggests the paper's tables came from 5-decimal data. The
    /// crate's baked tables use the data as published ([`Settings::new`]).
    pub fn paper(data_dir: impl Into<PathBuf>) -> Settings {
        Settings {
            observer_decimals: Some(5),
            ..Settings::new(data_dir)
        }
    }

    /// One line describing the settings, for generated headers.
    pub fn describe(&self) -> String {
        let decimals = match self.observer_decimals {
            Some(k) => std::format!(" observer_decimals={k}"),
            None => String::new(),
        };
        std::format!(
            "observer={} range={}-{} nm step={} nm max_order={} covariance={}{decimals}",
            self.observer.name(),
            self.range_nm[0],
            self.range_nm[1],
            self.step_nm,
            self.max_order,
            self.covariance.describe()
        )
    }
}

/// Everything the derivation produces.
#[derive(Debug, Clone, PartialEq)]
pub struct Derivation {
    /// The settings it was run with.
    pub settings: Settings,
    /// The observer table at its native 1 nm.
    pub observer: Observer,
    /// Grid wavelengths in nm.
    pub grid_nm: Vec<f64>,
    /// x̄, ȳ, z̄ on the grid.
    pub xyz: Vec<[f64; 3]>,
    /// s̄, m̄, l̄ on the grid (Eq. 1).
    pub cones: Vec<[f64; 3]>,
    /// The covariance matrix of Eq. 4.
    pub covariance: [[f64; 3]; 3],
    /// The KL transform (Eq. 9, 10).
    pub opponent: Opponent,
    /// ā, c̄1, c̄2 on the grid.
    pub sensitivities: Vec<[f64; 3]>,
    /// The measure of each channel's weight function.
    pub measures: [Measure; 3],
    /// The recurrence of each channel.
    pub recurrences: [Recurrence; 3],
    /// `rules[c][n - 1]`: channel c's rule of order n, for n = 1..=max_order.
    pub rules: [Vec<Rule>; 3],
    /// Table 2's two sets: row 1 (A 3, C1 2, C2 1) and row 2 (A on C1's nodes).
    pub table2: [WavelengthSet; 2],
    /// ∫ ȳ dλ on the grid: the luminance Y of a spectrum of constant value 1. Folded sets divide
    /// by it, so that such a spectrum has Y = 1 (display white).
    pub unit_spectrum_y: f64,
    /// The standard displays ([`display::standard_displays`]) and their matrices, derived once
    /// here; scenes, code generation, shaders and the tools take them from here.
    pub displays: Vec<(display::DisplaySpec, display::DisplayMatrices)>,
}

impl Derivation {
    /// A set folded for a display: `rgb = weights · samples` gives linear RGB, with a constant
    /// spectrum of 1 at Y = 1 (AC1C2 → XYZ → RGB and 1 / [`unit_spectrum_y`](Self::unit_spectrum_y)
    /// multiplied into the weights in f64).
    pub fn folded(
        &self,
        set: &WavelengthSet,
        matrices: &display::DisplayMatrices,
    ) -> [Vec<f64>; 3] {
        let m = display::mul3(&matrices.xyz_to_rgb, &self.opponent.ac1c2_to_xyz);
        display::fold(&m, &set.weights, 1.0 / self.unit_spectrum_y)
    }

    /// The display called `name` and its matrices, or [`Error::UnknownDisplay`] listing the
    /// valid names.
    pub fn display(
        &self,
        name: &str,
    ) -> Result<&(display::DisplaySpec, display::DisplayMatrices), Error> {
        self.displays
            .iter()
            .find(|(s, _)| s.name == name)
            .ok_or_else(|| Error::UnknownDisplay {
                name: name.into(),
                valid: self.displays.iter().map(|(s, _)| s.name.clone()).collect(),
            })
    }
}

/// Table 2: how far (nm) an A node may move to reuse another channel's wavelength. The paper's A
/// nodes 483.0 and 632.3 nm lie 7.9 and 0.9 nm from C1's 490.9 and 631.4 nm.
pub const TABLE2_SNAP_NM: f64 = 10.0;

/// Runs the derivation with the observer's embedded table.
pub fn derive(settings: &Settings) -> Result<Derivation, Error> {
    let observer = settings.observer.load(&settings.data_dir)?;
    derive_with(settings, observer)
}

/// Runs the derivation on a given observer table (for example one read from a user's file).
pub fn derive_with(settings: &Settings, mut observer: Observer) -> Result<Derivation, Error> {
    if let Some(k) = settings.observer_decimals {
        let scale = 10f64.powi(k.min(15) as i32);
        for v in observer.xyz.iter_mut().flatten() {
            *v = (*v * scale).round() / scale;
        }
    }
    let [lo, hi] = settings.range_nm;
    let rows = observer.grid_rows(lo, hi, settings.step_nm)?;
    if settings.max_order == 0 {
        return Err(Error::Settings("max_order must be at least 1".into()));
    }
    if settings.max_order >= rows.len() {
        return Err(Error::Settings(std::format!(
            "max_order {} needs more than {} grid points",
            settings.max_order,
            rows.len()
        )));
    }
    let grid_nm: Vec<f64> = rows.iter().map(|&r| observer.wavelengths[r]).collect();
    let xyz: Vec<[f64; 3]> = rows.iter().map(|&r| observer.xyz[r]).collect();
    let cones = opponent::cone_fundamentals(&xyz, &settings.cone_matrix);
    let covariance =
        opponent::covariance_matrix(&cones, &grid_nm, settings.step_nm, &settings.covariance)?;
    // Peaks are read off the observer's own (finest) table inside the range.
    let fine: Vec<[f64; 3]> = observer
        .wavelengths
        .iter()
        .zip(&observer.xyz)
        .filter(|(l, _)| **l >= lo - 1e-9 && **l <= hi + 1e-9)
        .map(|(_, v)| *v)
        .collect();
    let opponent = opponent::karhunen_loeve(&covariance, &settings.cone_matrix, &fine)?;
    let sensitivities = opponent::sensitivities(&opponent, &xyz);
    let measures = [0, 1, 2].map(|c| {
        let w: Vec<f64> = sensitivities.iter().map(|s| s[c]).collect();
        Measure::new(&grid_nm, &w, settings.step_nm, settings.range_nm)
    });
    let recurrences = [0, 1, 2].map(|c| quadrature::stieltjes(&measures[c], settings.max_order));
    let rules = [0, 1, 2].map(|c| {
        (1..=settings.max_order)
            .map(|n| quadrature::gauss_rule(&measures[c], &recurrences[c], n, settings.range_nm))
            .collect::<Vec<_>>()
    });
    let row1 = WavelengthSet::merge(
        "TABLE2_ROW1",
        "Table 2, first row: Gauss rules A order 3, C1 order 2, C2 order 1 (6 wavelengths).",
        [rules[0].get(2), rules[1].get(1), rules[2].first()],
    )?;
    let row2 = row1.snap_channel(
        "TABLE2_ROW2",
        "Table 2, second row: as row 1, with A's outer nodes moved onto C1's and A's weights made interpolatory (4 wavelengths).",
        0,
        &measures[0],
        TABLE2_SNAP_NM,
    );
    let unit_spectrum_y = xyz.iter().map(|v| v[1]).sum::<f64>() * settings.step_nm;
    let displays = display::standard_displays()
        .into_iter()
        .map(|spec| display::display_matrices(&spec).map(|m| (spec, m)))
        .collect::<Result<Vec<_>, Error>>()?;
    Ok(Derivation {
        unit_spectrum_y,
        displays,
        settings: settings.clone(),
        observer,
        grid_nm,
        xyz,
        cones,
        covariance: [0, 1, 2].map(|i| [0, 1, 2].map(|j| covariance[(i, j)])),
        opponent,
        sensitivities,
        measures,
        recurrences,
        rules,
        table2: [row1, row2],
    })
}

/// Hex SHA-256 of some bytes (checksums of inputs in generated headers).
pub fn sha256_hex(bytes: &[u8]) -> String {
    use sha2::Digest;
    let digest = sha2::Sha256::digest(bytes);
    digest.iter().map(|b| std::format!("{b:02x}")).collect()
}

/// The path of a data file labelled `data/<file>` (or just `<file>`) under `data_dir`.
pub fn data_path(data_dir: &Path, label: &str) -> PathBuf {
    data_dir.join(label.strip_prefix("data/").unwrap_or(label))
}

/// Reads the data file labelled `data/<file>` under `data_dir` ([`data_path`]). The error names
/// the label, and the path it tried.
pub fn read_data(data_dir: &Path, label: &str) -> Result<Vec<u8>, DataError> {
    let path = data_path(data_dir, label);
    std::fs::read(&path).map_err(|e| read_error(label, &path, &e))
}

/// [`read_data`], as text.
pub fn read_data_text(data_dir: &Path, label: &str) -> Result<String, DataError> {
    let path = data_path(data_dir, label);
    std::fs::read_to_string(&path).map_err(|e| read_error(label, &path, &e))
}

/// The error of a data file that could not be read: it names the label and the path.
pub(crate) fn read_error(label: &str, path: &Path, e: &std::io::Error) -> DataError {
    DataError {
        file: label.into(),
        line: 0,
        message: std::format!("cannot read {}: {e}", path.display()),
    }
}
