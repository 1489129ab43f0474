//! What the derivation starts from: the observer, the range and step of the grid, the highest
//! order, the covariance of Eq. 5 and the cone matrix of Eq. 1.

use std::path::PathBuf;

use super::observer::ObserverId;
use super::opponent::{self, Covariance};
use crate::base::error::Error;

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
    /// published). The paper's Table 1a is reproduced most closely with `Some(5)` (the tools'
    /// `paper::settings`).
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
    /// (`ObserverId::cone_matrix`, which for some observers is computed from the table, so
    /// this reads it) and range (`ObserverId::default_range_nm`).
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
}

/// One line describing the settings, as generated headers give them (`tables::SETTINGS`):
/// `observer=cie1931_2deg range=380-770 nm step=5 nm max_order=16 covariance=delta`, with
/// ` observer_decimals=<k>` at the end when the observer is rounded. The data directory is left
/// out, so the line does not depend on where the crate lives.
impl core::fmt::Display for Settings {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "observer={} range={}-{} nm step={} nm max_order={} covariance={}",
            self.observer.name(),
            self.range_nm[0],
            self.range_nm[1],
            self.step_nm,
            self.max_order,
            self.covariance.describe()
        )?;
        match self.observer_decimals {
            Some(k) => write!(f, " observer_decimals={k}"),
            None => Ok(()),
        }
    }
}
