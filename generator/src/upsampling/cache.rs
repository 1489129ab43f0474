//! The upsampling cache: the codes of the default scene's baked upsamplings, in a data file, each
//! with a fingerprint of everything its fit read. A build takes a table from it while the
//! fingerprint matches and fits only the others, because fitting the default scene's 28 maps
//! takes seconds at Cargo's default build-script opt-level 0 (`docs/build-cost.md` measures
//! both), as the node cache ([`crate::shared::CACHE_FILE`]) does for the node search.

use std::string::String;
use std::vec::Vec;

use super::bake::{
    group_encodings, Baked, CODE_ONE, GRID_SIZES, GROUP_COLOUR_WEIGHT, LOCAL_BANDWIDTH,
    LOCAL_PRIOR, RADIANCE_REFERENCE_LIGHT, REACHABLE_DELTA_E00,
};
use super::qp;
use super::training::TRAINING_FILES;
use crate::base::error::Error;
use crate::base::files::{cache_rows, read_data, read_optional_text, sha256_hex};
use crate::derivation::derive::Derivation;
use crate::derivation::display::DisplayMatrices;
use crate::derivation::sets::WavelengthSet;
use spectral_quadrature_spectra::{Curve, DataError};

/// The upsampling cache, a file in the data directory: the codes of every upsampling the default
/// scene bakes, with a fingerprint of everything the fit depends on.
/// `cargo run --release -p spectral-quadrature-tools --bin tables -- --upsampling-cache > data/upsampling_codes.csv`
/// writes it, and a test fits every map afresh and requires the same codes.
pub(crate) const CACHE_FILE: &str = "data/upsampling_codes.csv";

/// The version of the fit's code, part of every [`FitInputs::fingerprint`]: raise it whenever a
/// change to the fit (the map, the projection, the rounding to codes) may change a code, so that
/// every cached table is fitted again until the cache is regenerated.
pub(crate) const FIT_VERSION: u32 = 1;

/// The header line of [`CACHE_FILE`].
const HEADER: &str = "set,display,grid,fingerprint,lipschitz,max_round_trip_de00,reachable,codes";

/// One line of `CACHE_FILE`: one baked upsampling.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct CacheEntry {
    /// The set's name.
    pub set: String,
    /// The display's name (`SRGB`).
    pub display: String,
    /// Grid points per axis.
    pub grid: usize,
    /// `FitInputs::fingerprint` of the inputs the table was fitted from.
    pub fingerprint: String,
    /// [`Baked::lipschitz`].
    pub lipschitz: f64,
    /// [`Baked::max_round_trip_de00`].
    pub max_round_trip_de00: f64,
    /// [`Baked::reachable`].
    pub reachable: Vec<bool>,
    /// [`Baked::codes`]: grid³ entries of N codes.
    pub codes: Vec<Vec<u16>>,
    /// The line in the file.
    pub line: u64,
}

impl CacheEntry {
    /// The entry for a fitted upsampling whose inputs have `fingerprint`.
    pub(crate) fn new(baked: &Baked, fingerprint: String) -> CacheEntry {
        CacheEntry {
            set: baked.set.clone(),
            display: baked.display.clone(),
            grid: baked.grid,
            fingerprint,
            lipschitz: baked.lipschitz,
            max_round_trip_de00: baked.max_round_trip_de00,
            reachable: baked.reachable.clone(),
            codes: baked.codes.clone(),
            line: 0,
        }
    }

    /// The upsampling this entry caches, for `set` under the reference light `light` (its
    /// name), with the set's `encoding` ([`super::encoding`]): everything a fit gives but the fit
    /// itself ([`Baked::fit`] is `None`).
    pub(crate) fn baked(&self, set: &WavelengthSet, light: &str, encoding: [Vec<f64>; 3]) -> Baked {
        Baked {
            light: light.into(),
            wavelengths_nm: set.wavelengths_nm.clone(),
            ..self.baked_with(encoding)
        }
    }

    /// The map of a light group for the display `m` that this entry caches: `members` the
    /// group's members as sets ([`super::bake_group`]), `lights` the curves of their lights.
    /// Under the first light, with member 0's encoding ([`group_encodings`]).
    pub(crate) fn baked_group(
        &self,
        d: &Derivation,
        members: &[WavelengthSet],
        m: &DisplayMatrices,
        lights: &[Curve],
    ) -> Result<Baked, Error> {
        let encoding = group_encodings(d, members, m)?.swap_remove(0);
        Ok(Baked {
            light: lights.first().map_or(String::new(), |l| l.name.clone()),
            wavelengths_nm: members[0].wavelengths_nm.clone(),
            group_lights: Some(lights.iter().map(|l| l.name.clone()).collect()),
            ..self.baked_with(encoding)
        })
    }

    /// The parts of [`CacheEntry::baked`] and [`CacheEntry::baked_group`] that the entry holds.
    fn baked_with(&self, encoding: [Vec<f64>; 3]) -> Baked {
        Baked {
            set: self.set.clone(),
            display: self.display.clone(),
            light: String::new(),
            wavelengths_nm: Vec::new(),
            grid: self.grid,
            encoding,
            fit: None,
            reachable: self.reachable.clone(),
            codes: self.codes.clone(),
            max_round_trip_de00: self.max_round_trip_de00,
            lipschitz: self.lipschitz,
            group_lights: None,
        }
    }
}

/// What every upsampling's fit reads besides its set, display and light: the observer, the range,
/// the training reflectances (their files' checksums), the fit's constants and [`FIT_VERSION`].
/// Computed once per scene; [`FitInputs::fingerprint`] adds the rest for each map.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FitInputs {
    common: String,
}

impl FitInputs {
    /// Reads the training files' checksums from the derivation's data directory.
    pub(crate) fn new(d: &Derivation) -> Result<FitInputs, Error> {
        let mut common = std::format!(
            "upsampling fit {FIT_VERSION}\nobserver {} {}\nrange {:?}\nconstants bandwidth {LOCAL_BANDWIDTH:?} prior {LOCAL_PRIOR:?} reachable {REACHABLE_DELTA_E00:?} code {CODE_ONE:?} qp {:?} {:?} {} radiance light {RADIANCE_REFERENCE_LIGHT}\n",
            d.observer.file,
            d.observer.sha256,
            d.settings.range_nm,
            qp::EPSILON,
            qp::TOLERANCE,
            qp::MAX_STEPS,
        );
        for file in TRAINING_FILES {
            let bytes = read_data(&d.settings.data_dir, file)?;
            common += &std::format!("training {file} {}\n", sha256_hex(&bytes));
        }
        Ok(FitInputs { common })
    }

    /// A SHA-256 over everything the fit of `set` for `display` under `light` depends on besides
    /// its code: [`FitInputs::new`]'s inputs, the set's name, wavelengths and encoding weights
    /// ([`super::encoding`], which hold its quadrature weights and the display), whether its light
    /// is folded in, the display's matrices, the light's samples and the grid. A cached table is
    /// used only while its fingerprint matches.
    pub(crate) fn fingerprint(
        &self,
        set: &WavelengthSet,
        display: (&str, &DisplayMatrices),
        light: &Curve,
        folded: bool,
        encoding: &[Vec<f64>; 3],
        grid: usize,
    ) -> String {
        let (name, m) = display;
        let text = std::format!(
            "{}set {} folded {folded} nodes {:?}\nencoding {:?}\ndisplay {name} {:?} {:?}\nlight {} {:?} {:?}\ngrid {grid}\n",
            self.common,
            set.name,
            set.wavelengths_nm,
            encoding,
            m.rgb_to_xyz,
            m.xyz_to_rgb,
            light.name,
            light.wavelengths,
            light.values,
        );
        sha256_hex(text.as_bytes())
    }

    /// [`FitInputs::fingerprint`] for the map of the light group called `name` on `display`
    /// ([`super::bake_group`]: `members` its members as sets, `lights` the curves of their
    /// lights): [`FitInputs::new`]'s inputs, the group's name and nodes, every member's encoding
    /// ([`group_encodings`]) and light's samples, the display's matrices,
    /// [`GROUP_COLOUR_WEIGHT`] and the grid.
    pub(crate) fn group_fingerprint(
        &self,
        d: &Derivation,
        name: &str,
        members: &[WavelengthSet],
        display: (&str, &DisplayMatrices),
        lights: &[Curve],
        grid: usize,
    ) -> Result<String, Error> {
        let (display_name, m) = display;
        let encodings = group_encodings(d, members, m)?;
        let mut text = std::format!(
            "{}light group {name} colour weight {GROUP_COLOUR_WEIGHT:?} nodes {:?}\ndisplay {display_name} {:?} {:?}\ngrid {grid}\n",
            self.common, members[0].wavelengths_nm, m.rgb_to_xyz, m.xyz_to_rgb,
        );
        for (w, l) in encodings.iter().zip(lights) {
            text += &std::format!(
                "light {} {:?} {:?}\nencoding {w:?}\n",
                l.name,
                l.wavelengths,
                l.values
            );
        }
        Ok(sha256_hex(text.as_bytes()))
    }
}

/// Reads [`CACHE_FILE`] from `data_dir`: no file is an empty cache; a malformed one is an error
/// naming the file and line.
pub(crate) fn read_cache(data_dir: &std::path::Path) -> Result<Vec<CacheEntry>, DataError> {
    match read_optional_text(data_dir, CACHE_FILE)? {
        Some(text) => parse_cache(CACHE_FILE, &text),
        None => Ok(Vec::new()),
    }
}

/// The value of one hex digit, or `None`.
fn hex_digit(c: u8) -> Option<u16> {
    match c {
        b'0'..=b'9' => Some(u16::from(c - b'0')),
        b'a'..=b'f' => Some(u16::from(c - b'a' + 10)),
        _ => None,
    }
}

/// Parses the text of an upsampling cache (see [`CACHE_FILE`]); `file` labels errors, which name
/// the line and the field.
pub(crate) fn parse_cache(file: &str, text: &str) -> Result<Vec<CacheEntry>, DataError> {
    let err = |line: u64, message: String| DataError {
        file: file.into(),
        line,
        message,
    };
    let mut out: Vec<CacheEntry> = Vec::new();
    for (line, l) in cache_rows(file, text, HEADER)? {
        let fields: Vec<&str> = l.split(',').collect();
        let [set, display, grid, fingerprint, lipschitz, round_trip, reachable, codes] = fields[..]
        else {
            return Err(err(
                line,
                std::format!("expected 8 fields ({HEADER}), found {}", fields.len()),
            ));
        };
        let what = std::format!("{set} {display}");
        let grid = grid
            .parse::<usize>()
            .ok()
            .filter(|g| GRID_SIZES.contains(g))
            .ok_or_else(|| {
                err(
                    line,
                    std::format!(
                        "{what}: grid {grid:?} is not {} to {} points per axis",
                        GRID_SIZES.start(),
                        GRID_SIZES.end()
                    ),
                )
            })?;
        if fingerprint.len() != 64 || fingerprint.bytes().any(|c| hex_digit(c).is_none()) {
            return Err(err(
                line,
                std::format!("{what}: the fingerprint is not 64 lower-case hex digits"),
            ));
        }
        let figure = |name: &str, v: &str| match v.parse::<f64>() {
            Ok(x) if x.is_finite() && x >= 0.0 => Ok(x),
            _ => Err(err(
                line,
                std::format!("{what}: {name} {v:?} is not a finite number ≥ 0"),
            )),
        };
        let lipschitz = figure("lipschitz", lipschitz)?;
        let max_round_trip_de00 = figure("max_round_trip_de00", round_trip)?;
        let points = grid * grid * grid;
        let bad_digit = |field: &str, at: usize| {
            err(
                line,
                std::format!(
                    "{what}: {field}: character {} is not a lower-case hex digit",
                    at + 1
                ),
            )
        };
        // One hex digit per four grid points, the first point in the lowest bit.
        if reachable.len() != points.div_ceil(4) {
            return Err(err(
                line,
                std::format!(
                    "{what}: reachable has {} hex digits; a {grid}³ grid needs {}",
                    reachable.len(),
                    points.div_ceil(4)
                ),
            ));
        }
        let mut reach = Vec::with_capacity(points);
        for (k, c) in reachable.bytes().enumerate() {
            let v = hex_digit(c).ok_or_else(|| bad_digit("reachable", k))?;
            for b in 0..4 {
                let idx = 4 * k + b;
                let bit = (v >> b) & 1 == 1;
                if idx < points {
                    reach.push(bit);
                } else if bit {
                    return Err(err(
                        line,
                        std::format!(
                            "{what}: reachable sets a bit past the grid's {points} points"
                        ),
                    ));
                }
            }
        }
        // Four hex digits per code, N codes per grid point.
        let digits = codes.len();
        if digits == 0 || digits % (4 * points) != 0 {
            return Err(err(
                line,
                std::format!(
                    "{what}: codes has {digits} hex digits, not a positive multiple of 4 × {points} (four per code, N codes per point of the {grid}³ grid)"
                ),
            ));
        }
        let n = digits / (4 * points);
        let bytes = codes.as_bytes();
        let mut table = Vec::with_capacity(points);
        for p in 0..points {
            let mut entry = Vec::with_capacity(n);
            for node in 0..n {
                let at = 4 * (p * n + node);
                let mut v = 0u16;
                for (k, &c) in bytes.iter().enumerate().skip(at).take(4) {
                    v = (v << 4) | hex_digit(c).ok_or_else(|| bad_digit("codes", k))?;
                }
                entry.push(v);
            }
            table.push(entry);
        }
        if out.iter().any(|e| e.set == set && e.display == display) {
            return Err(err(line, std::format!("{what} appears twice")));
        }
        out.push(CacheEntry {
            set: set.into(),
            display: display.into(),
            grid,
            fingerprint: fingerprint.into(),
            lipschitz,
            max_round_trip_de00,
            reachable: reach,
            codes: table,
            line,
        });
    }
    Ok(out)
}

/// The text of `CACHE_FILE` for `entries`.
pub(crate) fn write_cache(entries: &[CacheEntry]) -> String {
    use std::fmt::Write as _;
    let rows: Vec<Vec<String>> = entries
        .iter()
        .map(|e| {
            let mut reachable = String::with_capacity(e.reachable.len().div_ceil(4));
            for chunk in e.reachable.chunks(4) {
                let v = chunk
                    .iter()
                    .enumerate()
                    .fold(0u8, |v, (b, &r)| v | (u8::from(r) << b));
                write!(reachable, "{v:x}").ok();
            }
            let mut codes =
                String::with_capacity(4 * e.codes.len() * e.codes.first().map_or(0, Vec::len));
            for c in e.codes.iter().flatten() {
                write!(codes, "{c:04x}").ok();
            }
            std::vec![
                e.set.clone(),
                e.display.clone(),
                e.grid.to_string(),
                e.fingerprint.clone(),
                std::format!("{:?}", e.lipschitz),
                std::format!("{:?}", e.max_round_trip_de00),
                reachable,
                codes,
            ]
        })
        .collect();
    let generated = std::format!(
        "Generated by `cargo run --release -p spectral-quadrature-tools --bin tables -- --upsampling-cache > {CACHE_FILE}`."
    );
    crate::base::files::write_csv(
        &[
            &generated,
            "The default scene's upsamplings, fitted; the build reuses an entry while its fingerprint matches the inputs.",
            "reachable: one hex digit per 4 grid points (index (r·grid + g)·grid + b), the first in the lowest bit.",
            "codes: 4 hex digits per 16-bit code (node value × 65535), N codes per grid point, the points in that order.",
        ],
        HEADER,
        &rows,
    )
}
