//! Display matrices from primaries and a white point, and the folding of AC1C2 → XYZ → RGB into a
//! wavelength set's weights.

use std::string::String;
use std::vec::Vec;

use crate::base::error::Error;

/// How a display encodes linear light.
#[derive(Debug, Clone, PartialEq)]
pub enum Transfer {
    /// No encoding.
    Linear,
    /// The sRGB piecewise curve (IEC 61966-2-1).
    Srgb,
    /// A pure power law: encoded = linear^(1/γ).
    Gamma(f64),
}

/// A display: three primaries and a white point (CIE 1931 xy), and a transfer function.
///
/// The standard displays (`SRGB`, `DISPLAY_P3`, `REC2020`, `MEYER_1987`) have one description
/// each, here (`standard_displays`): the derivation derives their matrices once ([`crate::Derivation::displays`]), and code generation, shaders,
/// scenes and the tools take name, label, primaries, white and transfer from there.
#[derive(Debug, Clone, PartialEq)]
pub struct DisplaySpec {
    /// The const name in generated code (upper snake case), and the name scenes and tools use.
    pub name: String,
    /// The human name (`"Display P3"`), baked as the runtime `Display`'s `name`.
    pub label: String,
    /// One line for the doc comment.
    pub doc: String,
    /// Chromaticities of red, green and blue.
    pub primaries_xy: [[f64; 2]; 3],
    /// Chromaticity of the white point (the colour of RGB = 1, 1, 1 at Y = 1).
    pub white_xy: [f64; 2],
    /// The transfer function.
    pub transfer: Transfer,
}

/// D65 as the displays' standards give it.
pub(crate) const D65_XY: [f64; 2] = [0.3127, 0.3290];

/// A display is refused when the 2-norm condition number of its primaries' XYZ matrix exceeds
/// this: the one definition of "nearly collinear" the runtime's `Display::new` uses too
/// (`spectral_quadrature_math::MAX_PRIMARIES_CONDITION`).
pub use spectral_quadrature_math::MAX_PRIMARIES_CONDITION as MAX_CONDITION;

/// A display's matrices, derived in f64 by `spectral-quadrature-math` (the runtime derives the
/// matrices of displays made at run time with the same code).
pub use spectral_quadrature_math::DisplayMatrices;

/// The displays the crate bakes by default.
pub(crate) fn standard_displays() -> Vec<DisplaySpec> {
    std::vec![
        DisplaySpec {
            name: "SRGB".into(),
            label: "sRGB".into(),
            doc: "sRGB / Rec. 709 primaries, D65 white, the sRGB transfer curve.".into(),
            primaries_xy: [[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]],
            white_xy: D65_XY,
            transfer: Transfer::Srgb,
        },
        DisplaySpec {
            name: "DISPLAY_P3".into(),
            label: "Display P3".into(),
            doc: "Display P3: DCI-P3 primaries, D65 white, the sRGB transfer curve.".into(),
            primaries_xy: [[0.680, 0.320], [0.265, 0.690], [0.150, 0.060]],
            white_xy: D65_XY,
            transfer: Transfer::Srgb,
        },
        DisplaySpec {
            name: "REC2020".into(),
            label: "Rec. 2020".into(),
            doc: "Rec. 2020 primaries, D65 white, a pure 2.4 gamma (BT.1886 with zero black level).".into(),
            primaries_xy: [[0.708, 0.292], [0.170, 0.797], [0.131, 0.046]],
            white_xy: D65_XY,
            transfer: Transfer::Gamma(2.4),
        },
        DisplaySpec {
            name: "MEYER_1987".into(),
            label: "Meyer 1987 monitor".into(),
            doc: "The paper's monitor: Eq. 18 phosphors, D65 white; white balance derived from them (Eq. 19 as transcribed is wrong). Its guns' measured curves are not published: a 2.2 gamma stands in; use a per-channel lookup table for a measured display.".into(),
            primaries_xy: [[0.64, 0.33], [0.29, 0.60], [0.15, 0.06]],
            white_xy: D65_XY,
            transfer: Transfer::Gamma(2.2),
        },
    ]
}

/// Derives RGB ↔ XYZ with `spectral_quadrature_math::display_matrices`: the primaries' XYZ
/// columns scaled so that RGB = (1, 1, 1) is the white at Y = 1. Errors ([`Error::Display`],
/// naming the display) when a chromaticity is invalid, when the primaries are nearly collinear
/// (condition number above [`MAX_CONDITION`]) or when the white point lies on or outside the
/// primaries' triangle (a gun drive of zero or less would be needed for white).
pub(crate) fn display_matrices(spec: &DisplaySpec) -> Result<DisplayMatrices, Error> {
    spectral_quadrature_math::display_matrices(spec.primaries_xy, spec.white_xy).map_err(
        |problem| Error::Display {
            name: spec.name.clone(),
            problem,
        },
    )
}

/// The standard display called `name` ([`DisplaySpec::name`]), or [`Error::UnknownDisplay`]
/// listing the valid names.
pub(crate) fn standard_display(name: &str) -> Result<DisplaySpec, Error> {
    let all = standard_displays();
    match all.iter().position(|d| d.name == name) {
        Some(i) => Ok(all[i].clone()),
        None => Err(Error::UnknownDisplay {
            name: name.into(),
            valid: all.into_iter().map(|d| d.name).collect(),
        }),
    }
}

/// `a · b` for 3×3 row-major matrices.
pub(crate) fn mul3(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

/// Folds `matrix` (3×3, from the space of the weights' rows to another) and a `scale` into a
/// set's 3×N weights: `out[r][i] = scale · Σ_k matrix[r][k] · weights[k][i]`.
pub(crate) fn fold(matrix: &[[f64; 3]; 3], weights: &[Vec<f64>; 3], scale: f64) -> [Vec<f64>; 3] {
    let n = weights[0].len();
    [0, 1, 2].map(|r| {
        (0..n)
            .map(|i| scale * (0..3).map(|k| matrix[r][k] * weights[k][i]).sum::<f64>())
            .collect()
    })
}
