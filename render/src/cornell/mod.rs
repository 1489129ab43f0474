//! The Cornell box rendered by radiosity, once per spectral method (`cornell`,
//! `docs/cornell-box.md`).
//!
//! A renderer author judges a method by images of a scene they know. The box's measured data
//! (`data/cornell_box_*.csv`: three paints, the light, 16 quads and the camera) are rendered by
//! radiosity: the quads meshed into patches ([`geometry`]), the form factors computed once with
//! visibility, one linear solve per wavelength, node or RGB channel ([`radiosity`]), then one
//! camera view ([`camera`]). Radiosity is deterministic and its spatial part (mesh, form
//! factors, view) is the same for every method, so two images differ only in their spectral
//! part: no noise to average away, nothing to cancel. The methods ([`methods`]) are compared
//! per pixel in CIEDE2000 against the reference, and drawn side by side ([`picture`]).
//!
//! **The spectral range.** Every spectrum is integrated over 400-700 nm only, where the paints
//! are measured: each light is taken as 0 outside it ([`window`]), so the images are the colour
//! of the 400-700 nm part of every spectrum, and the paints' unknown values outside it never
//! enter. The data are interpolated linearly from their grids to 1 nm.

pub mod camera;
pub mod geometry;
pub mod methods;
pub mod picture;
pub mod radiosity;

use std::path::Path;

use spectral_quadrature_spectra::{builtin_illuminant, read_data_text, Curve, Spectra};

use crate::Error;

/// The range integrated, nm: the paints' measured range.
pub const RANGE_NM: [f64; 2] = [400.0, 700.0];

/// The lights the box can be rendered under.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Light {
    /// The box's own light (`cornell_box_light.csv`).
    Box,
    /// CIE F11, three narrow lines.
    F11,
    /// CIE LED-B2, a narrow blue pump beside a phosphor.
    LedB2,
}

impl Light {
    /// Every light, in the order the tools render them.
    pub const ALL: [Light; 3] = [Light::Box, Light::F11, Light::LedB2];

    /// The light whose [`name`](Self::name) is `name`.
    pub fn from_name(name: &str) -> Option<Light> {
        Light::ALL.into_iter().find(|l| l.name() == name)
    }

    /// The name in tables, and the `<light>` of its `KQ_<light>_<n>` sets.
    pub fn name(self) -> &'static str {
        match self {
            Light::Box => "box",
            Light::F11 => "F11",
            Light::LedB2 => "LED_B2",
        }
    }
}

/// The box's measured data.
#[derive(Debug, Clone)]
pub struct BoxData {
    /// The quads of the open box (as the camera sees it).
    pub quads: Vec<crate::cornell::geometry::Quad>,
    /// The quads with a front wall closing the box.
    pub closed_quads: Vec<crate::cornell::geometry::Quad>,
    /// The white, red and green paints' reflectances, 400-700 nm.
    pub paints: [Curve; 3],
    /// The box's light, as measured (four values).
    pub box_light: Curve,
}

/// Reads `cornell_box_{geometry,reflectance,light}.csv` from `data_dir` (the crate's `data/`).
pub fn read_data(data_dir: &Path) -> Result<BoxData, Error> {
    let geometry = read_data_text(data_dir, "data/cornell_box_geometry.csv")?;
    let quads = geometry::read_quads(&geometry, false)?;
    let closed_quads = geometry::read_quads(&geometry, true)?;
    let refl = Spectra::parse(
        "data/cornell_box_reflectance.csv",
        &read_data_text(data_dir, "data/cornell_box_reflectance.csv")?,
    )?;
    let paints = [0, 1, 2]
        .map(|k| refl.curve(k, RANGE_NM))
        .into_iter()
        .collect::<Result<Vec<_>, _>>()?;
    let light = Spectra::parse(
        "data/cornell_box_light.csv",
        &read_data_text(data_dir, "data/cornell_box_light.csv")?,
    )?;
    let mut box_light = light.curve(0, RANGE_NM)?;
    box_light.name = "box".into();
    let [w, r, g]: [Curve; 3] = paints.try_into().expect("three paints");
    Ok(BoxData {
        quads,
        closed_quads,
        paints: [w, r, g],
        box_light,
    })
}

/// `light` on 400-700 nm and 0 outside: its values every 1 nm from 400 to 700 nm (linear
/// between its data), and 0 at 399 and 701 nm, so that on the 1 nm grid it is the light inside
/// the range and nothing outside.
pub fn window(light: &Curve) -> Curve {
    let mut wavelengths = vec![RANGE_NM[0] - 1.0];
    let mut values = vec![0.0];
    let mut nm = RANGE_NM[0];
    while nm <= RANGE_NM[1] + 1e-9 {
        wavelengths.push(nm);
        values.push(light.at(nm));
        nm += 1.0;
    }
    wavelengths.push(RANGE_NM[1] + 1.0);
    values.push(0.0);
    Curve {
        name: light.name.clone(),
        wavelengths,
        values,
    }
}

/// The light `which`, windowed to 400-700 nm ([`window`]).
pub fn light_curve(
    data: &BoxData,
    d: &spectral_quadrature_generator::Derivation,
    which: Light,
) -> Result<Curve, Error> {
    let raw = match which {
        Light::Box => data.box_light.clone(),
        other => builtin_illuminant(&d.settings.data_dir, other.name(), d.settings.range_nm)?,
    };
    let mut c = window(&raw);
    c.name = which.name().to_string();
    Ok(c)
}
