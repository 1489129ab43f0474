//! Displays: primaries, white point and transfer function; gamut mapping and encoding.

#![forbid(unsafe_code)]

use spectral_quadrature_math::{display_matrices, DisplayError, DisplayMatrices, Point};

use super::bits::{same_f32_bits, same_str};
use super::transfer::{gamma_encoder, gamma_f32, quantize_u8, TransferFunction};
use crate::encode::{clamp01, srgb8_not_nan};
use crate::{Error, Rgb};

/// What to do with colours the display cannot show (a linear channel below 0 or above 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum GamutMapping {
    /// Clamp each channel to 0..=1. Hue and luminance may shift.
    #[default]
    Clip,
    /// Keep the achromatic coordinate A and move the colour straight toward the display's white
    /// axis (same A, C1 and C2 shrunk by one common factor relative to the white of that A) until
    /// it fits. The AC1C2 opponent axes make this a one-parameter problem. Only a colour whose A
    /// lies between black and the display's white can keep its A: brighter colours become white,
    /// colours with A ≤ 0 become black.
    PreserveA,
}

impl GamutMapping {
    /// The mapping's identifier, `"clip"` or `"preserve-a"` (kebab-case, stable across
    /// versions): for CSV columns, logs and settings. Its [`Display`](core::fmt::Display) is
    /// the sentence for messages.
    pub const fn name(self) -> &'static str {
        match self {
            GamutMapping::Clip => "clip",
            GamutMapping::PreserveA => "preserve-a",
        }
    }
}

impl core::fmt::Display for GamutMapping {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            GamutMapping::Clip => "each channel clamped to 0..=1",
            GamutMapping::PreserveA => {
                "the achromatic coordinate A kept, the colour moved toward the white axis"
            }
        })
    }
}

/// How far [`Display::from_matrices`] lets each entry of `rgb_to_xyz · xyz_to_rgb`, computed in
/// f32, lie from the identity's, in units of the sum of its three products' magnitudes: 6 · 2⁻²⁴.
/// Two matrices that are exact inverses in f64, each rounded to f32 (2⁻²⁴ relative per entry,
/// 2 · 2⁻²⁴ per product), give a product within (2 + 3) · 2⁻²⁴ of the identity times that sum
/// once the three-term f32 sum adds its own rounding (3 · 2⁻²⁴); the sixth unit covers the
/// second-order terms and the f64 inverse's own error (its condition number times 2⁻⁵³, below
/// 2⁻⁴⁰ for every display [`Display::new`] accepts). A singular matrix's product misses the
/// identity by a whole unit on some entry.
const MATRIX_ROUNDING: f32 = 6.0 / 16_777_216.0;

/// A display: primaries, white point (CIE 1931 xy), the matrices between linear RGB and XYZ
/// (white at Y = 1), and a transfer function.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Display {
    // Private: a display is made by `new`, which derives the matrices so that they always agree
    // with the chromaticities, or (the baked ones) by `from_matrices`, which checks them.
    name: &'static str,
    primaries_xy: [[f32; 2]; 3],
    white_xy: [f32; 2],
    rgb_to_xyz: [[f32; 3]; 3],
    xyz_to_rgb: [[f32; 3]; 3],
    a_from_rgb: [f32; 3],
    transfer: TransferFunction,
}

impl Display {
    /// A short name, e.g. `"sRGB"`.
    pub const fn name(&self) -> &'static str {
        self.name
    }

    /// Chromaticities (CIE 1931 xy) of red, green, blue.
    pub const fn primaries_xy(&self) -> [[f32; 2]; 3] {
        self.primaries_xy
    }

    /// Chromaticity of white (RGB = 1, 1, 1).
    pub const fn white_xy(&self) -> [f32; 2] {
        self.white_xy
    }

    /// Linear RGB → XYZ (white at Y = 1), row-major.
    pub const fn rgb_to_xyz(&self) -> [[f32; 3]; 3] {
        self.rgb_to_xyz
    }

    /// XYZ → linear RGB, row-major.
    pub const fn xyz_to_rgb(&self) -> [[f32; 3]; 3] {
        self.xyz_to_rgb
    }

    /// The achromatic coordinate A of one unit of linear R, G and B (used by
    /// [`GamutMapping::PreserveA`]).
    pub const fn a_from_rgb(&self) -> [f32; 3] {
        self.a_from_rgb
    }

    /// How linear light is encoded.
    pub const fn transfer(&self) -> TransferFunction {
        self.transfer
    }

    /// A display made at run time from its primaries and white point (CIE 1931 xy) and a transfer
    /// function: linear RGB = (1, 1, 1) is the white at Y = 1. The matrices come from
    /// [`spectral_quadrature_math::display_matrices`] in f64, the same operations the baked
    /// displays come from, then rounded to f32.
    ///
    /// Errors, never a panic, all [`Error::Display`] with the [`DisplayError`] that says what and
    /// where: [`DisplayError::Gamma`] for a `Gamma(γ)` whose γ is not finite and positive;
    /// [`DisplayError::Chromaticity`] (naming the point) for a coordinate that is not finite,
    /// negative, or with x + y > 1 or y = 0; [`DisplayError::Collinear`] when the primaries are
    /// collinear (or nearly: the 2-norm condition number of their matrix above
    /// [`MAX_PRIMARIES_CONDITION`](crate::MAX_PRIMARIES_CONDITION)), or so extreme that the f32
    /// matrices would overflow (condition `+Inf`); [`DisplayError::WhiteOutside`] when the white
    /// is not a positive mix of the primaries (or lies on an edge of their triangle: some
    /// primary's share below [`MIN_WHITE_SHARE`](crate::MIN_WHITE_SHARE) of the largest). Lookup
    /// tables were checked by [`ChannelLuts::new`](crate::ChannelLuts::new).
    ///
    /// It computes in f64: once per display, never per pixel, and only for displays made at run
    /// time (the baked [`tables::displays`](crate::tables::displays) cost nothing). On a
    /// microcontroller without a double-precision FPU that f64 is soft-float.
    ///
    /// ```
    /// use spectral_quadrature::{tables::displays, Display, DisplayError, Error, TransferFunction};
    /// let srgb = Display::new("sRGB", [[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]], [0.3127, 0.3290], TransferFunction::Srgb).unwrap();
    /// assert!((srgb.xyz_to_rgb()[0][0] - displays::SRGB.xyz_to_rgb()[0][0]).abs() < 1e-4);
    /// let flat = Display::new("flat", [[0.2, 0.2], [0.4, 0.4], [0.3, 0.3]], [0.3127, 0.3290], TransferFunction::Srgb);
    /// assert!(matches!(flat, Err(Error::Display(DisplayError::Collinear { .. }))));
    /// ```
    pub fn new(
        name: &'static str,
        primaries_xy: [[f32; 2]; 3],
        white_xy: [f32; 2],
        transfer: TransferFunction,
    ) -> Result<Display, Error> {
        if let TransferFunction::Gamma(g) = transfer {
            if !(g.is_finite() && g > 0.0) {
                return Err(Error::Display(DisplayError::Gamma { gamma: g }));
            }
        }
        let f64s = |xy: [f32; 2]| xy.map(f64::from);
        let matrices = display_matrices(primaries_xy.map(f64s), f64s(white_xy))?;
        let DisplayMatrices {
            rgb_to_xyz,
            xyz_to_rgb,
            ..
        } = matrices;
        let to_ac1c2 = crate::tables::XYZ_TO_AC1C2;
        let a_from_rgb = [0, 1, 2].map(|c| {
            (0..3)
                .map(|k| f64::from(to_ac1c2[0][k]) * rgb_to_xyz[k][c])
                .sum::<f64>() as f32
        });
        let f32s = |m: [[f64; 3]; 3]| m.map(|row| row.map(|v| v as f32));
        let (rgb_to_xyz, xyz_to_rgb) = (f32s(rgb_to_xyz), f32s(xyz_to_rgb));
        // Extreme chromaticities (subnormal x or y) can still overflow f32.
        let all = rgb_to_xyz
            .iter()
            .chain(&xyz_to_rgb)
            .flatten()
            .chain(&a_from_rgb);
        if !all.into_iter().all(|v| v.is_finite()) {
            return Err(Error::Display(DisplayError::Collinear {
                condition: f32::INFINITY,
            }));
        }
        Ok(Display {
            name,
            primaries_xy,
            white_xy,
            rgb_to_xyz,
            xyz_to_rgb,
            a_from_rgb,
            transfer,
        })
    }

    /// A display from its matrices, as the build bakes them ([`tables::displays`](crate::tables::displays)):
    /// the chromaticities, both matrices and the A of one unit of R, G and B, as
    /// [`Display::new`] would derive them in f64 and round them to f32. Checked, never a panic,
    /// usable in consts (where [`new`](Self::new), in f64, is not), with the errors
    /// [`Display::new`] gives, all [`Error::Display`]:
    ///
    /// - [`DisplayError::Gamma`] for a `Gamma(γ)` whose γ is not finite and positive;
    /// - [`DisplayError::Chromaticity`] (naming the point, primaries first) for a coordinate
    ///   that is not finite, negative, or with x + y > 1 or y ≤ 0;
    /// - [`DisplayError::Collinear`] with an infinite condition number where a matrix entry or
    ///   an A is not finite, or where the matrices are not each other's inverse: an entry of
    ///   `rgb_to_xyz · xyz_to_rgb` (in f32) farther from the identity's than 6 · 2⁻²⁴ times
    ///   the sum of its products' magnitudes, the bound the f32 rounding of an inverse pair
    ///   computed in f64 keeps (`MATRIX_ROUNDING` in the source says where each unit comes
    ///   from). A singular matrix has no inverse, so it is refused.
    ///
    /// The chromaticities are not checked against the matrices: the matrices are the display.
    ///
    /// ```
    /// use spectral_quadrature::{tables::displays::SRGB, Display, DisplayError, Error};
    /// let same = Display::from_matrices(
    ///     SRGB.name(),
    ///     SRGB.primaries_xy(),
    ///     SRGB.white_xy(),
    ///     SRGB.rgb_to_xyz(),
    ///     SRGB.xyz_to_rgb(),
    ///     SRGB.a_from_rgb(),
    ///     SRGB.transfer(),
    /// );
    /// assert_eq!(same, Ok(SRGB));
    /// // A singular RGB → XYZ (its blue column zero) has no inverse.
    /// let mut flat = SRGB.rgb_to_xyz();
    /// flat.iter_mut().for_each(|row| row[2] = 0.0);
    /// let refused = Display::from_matrices(
    ///     "flat", SRGB.primaries_xy(), SRGB.white_xy(), flat, SRGB.xyz_to_rgb(),
    ///     SRGB.a_from_rgb(), SRGB.transfer(),
    /// );
    /// assert!(matches!(refused, Err(Error::Display(DisplayError::Collinear { .. }))));
    /// ```
    pub const fn from_matrices(
        name: &'static str,
        primaries_xy: [[f32; 2]; 3],
        white_xy: [f32; 2],
        rgb_to_xyz: [[f32; 3]; 3],
        xyz_to_rgb: [[f32; 3]; 3],
        a_from_rgb: [f32; 3],
        transfer: TransferFunction,
    ) -> Result<Display, Error> {
        if let TransferFunction::Gamma(gamma) = transfer {
            if !(gamma.is_finite() && gamma > 0.0) {
                return Err(Error::Display(DisplayError::Gamma { gamma }));
            }
        }
        let points = [Point::Red, Point::Green, Point::Blue, Point::White];
        let mut k = 0;
        while k < 4 {
            let xy = if k < 3 { primaries_xy[k] } else { white_xy };
            let [x, y] = xy;
            let valid = x.is_finite() && y.is_finite() && x >= 0.0 && y > 0.0 && x + y <= 1.0;
            if !valid {
                return Err(Error::Display(DisplayError::Chromaticity {
                    point: points[k],
                    xy,
                }));
            }
            k += 1;
        }
        let singular = Err(Error::Display(DisplayError::Collinear {
            condition: f32::INFINITY,
        }));
        let mut i = 0;
        while i < 3 {
            if !a_from_rgb[i].is_finite() {
                return singular;
            }
            let mut j = 0;
            while j < 3 {
                if !(rgb_to_xyz[i][j].is_finite() && xyz_to_rgb[i][j].is_finite()) {
                    return singular;
                }
                j += 1;
            }
            i += 1;
        }
        let mut i = 0;
        while i < 3 {
            let mut j = 0;
            while j < 3 {
                let mut product = 0.0f32;
                let mut magnitude = 0.0f32;
                let mut k = 0;
                while k < 3 {
                    let term = rgb_to_xyz[i][k] * xyz_to_rgb[k][j];
                    product += term;
                    magnitude += term.abs();
                    k += 1;
                }
                let identity = if i == j { 1.0 } else { 0.0 };
                // A product that overflows (an infinite magnitude, a NaN sum) is refused too.
                let inverse = magnitude.is_finite()
                    && (product - identity).abs() <= MATRIX_ROUNDING * magnitude;
                if !inverse {
                    return singular;
                }
                j += 1;
            }
            i += 1;
        }
        Ok(Display {
            name,
            primaries_xy,
            white_xy,
            rgb_to_xyz,
            xyz_to_rgb,
            a_from_rgb,
            transfer,
        })
    }

    /// Whether `other` is the same display, every field the same bits (name, chromaticities,
    /// matrices, transfer function and its tables): `PartialEq` in a const fn, stricter only
    /// where one field holds 0.0 and the other −0.0.
    pub(crate) const fn same_bits(&self, other: &Display) -> bool {
        let mut k = 0;
        while k < 3 {
            if !same_f32_bits(&self.primaries_xy[k], &other.primaries_xy[k])
                || !same_f32_bits(&self.rgb_to_xyz[k], &other.rgb_to_xyz[k])
                || !same_f32_bits(&self.xyz_to_rgb[k], &other.xyz_to_rgb[k])
            {
                return false;
            }
            k += 1;
        }
        same_str(self.name, other.name)
            && same_f32_bits(&self.white_xy, &other.white_xy)
            && same_f32_bits(&self.a_from_rgb, &other.a_from_rgb)
            && self.transfer.same_bits(&other.transfer)
    }

    /// The same display with another transfer function (for example measured lookup tables).
    pub const fn with_transfer(mut self, transfer: TransferFunction) -> Display {
        self.transfer = transfer;
        self
    }

    /// Linear RGB of an XYZ colour (Y = 1 is the display's white). IEEE arithmetic: NaN and
    /// ±Inf propagate, out-of-gamut colours give components below 0 or above 1.
    pub fn linear_from_xyz(&self, xyz: [f32; 3]) -> [f32; 3] {
        super::matrix::mat3_vec(&self.xyz_to_rgb, xyz)
    }

    /// XYZ of a linear RGB colour. IEEE arithmetic, as [`linear_from_xyz`](Self::linear_from_xyz).
    pub fn xyz_from_linear(&self, rgb: [f32; 3]) -> [f32; 3] {
        super::matrix::mat3_vec(&self.rgb_to_xyz, rgb)
    }

    /// Brings a linear colour into 0..=1 per channel.
    ///
    /// Any NaN channel gives black `[0, 0, 0]`. With `PreserveA`, a colour with an infinite
    /// channel is clipped as with `Clip` (+Inf → 1, −Inf → 0). Never panics; the output is
    /// always in 0..=1.
    #[inline]
    pub fn map_gamut(&self, mapping: GamutMapping, rgb: [f32; 3]) -> [f32; 3] {
        if rgb.iter().any(|v| v.is_nan()) {
            return [0.0; 3];
        }
        match mapping {
            GamutMapping::Clip => rgb.map(clamp01),
            GamutMapping::PreserveA => {
                if rgb.iter().any(|v| v.is_infinite()) {
                    return rgb.map(clamp01);
                }
                preserve_a(self.a_from_rgb, rgb)
            }
        }
    }

    /// Gamut-maps and encodes a linear colour: values in 0..=1 ready to quantize. Input handling
    /// as [`map_gamut`](Self::map_gamut) (NaN anywhere → black).
    ///
    /// The reference encoder, not a per-pixel function: each channel goes through
    /// [`TransferFunction::encode`], the exact curve in f64 rounded once (soft-float on a
    /// microcontroller without a double-precision FPU). What the per-pixel encoders
    /// ([`encode_u8`](Self::encode_u8), [`encode_u16`](Self::encode_u16), f32 and integers
    /// only) and the shaders' `<display>_encode` are measured against.
    pub fn encode(&self, mapping: GamutMapping, rgb: [f32; 3]) -> [f32; 3] {
        let m = self.map_gamut(mapping, rgb);
        [
            self.transfer.encode(Rgb::R, m[0]),
            self.transfer.encode(Rgb::G, m[1]),
            self.transfer.encode(Rgb::B, m[2]),
        ]
    }

    /// Gamut-maps and encodes to 8 bits with [`TransferFunction::encode_u8`]: for sRGB and the
    /// baked displays' power laws the exact curve rounded to nearest (which
    /// `quantize_u8(encode(..))`, rounding twice, misses by one step on a few inputs). No f64
    /// arithmetic. Input handling as [`map_gamut`](Self::map_gamut): NaN anywhere → black.
    #[inline]
    pub fn encode_u8(&self, mapping: GamutMapping, rgb: [f32; 3]) -> [u8; 3] {
        // The common case inline and without branches: the sRGB table clamps as `Clip` does,
        // and a NaN anywhere selects black afterwards.
        if self.is_srgb_clip(mapping) {
            let nan = rgb[0].is_nan() | rgb[1].is_nan() | rgb[2].is_nan();
            let px = rgb.map(srgb8_not_nan);
            return if nan { [0; 3] } else { px };
        }
        self.encode_u8_other(mapping, rgb)
    }

    /// Whether 8-bit encoding with `mapping` is the sRGB table with `Clip`: the case every fast
    /// path (per pixel, batch, planar, vector loops) takes, and the one `srgb8_from_linear`
    /// computes.
    #[inline]
    pub(crate) fn is_srgb_clip(&self, mapping: GamutMapping) -> bool {
        matches!(
            (mapping, self.transfer),
            (GamutMapping::Clip, TransferFunction::Srgb)
        )
    }

    /// [`encode_u8`](Self::encode_u8) for every transfer function and mapping but sRGB with
    /// `Clip`.
    fn encode_u8_other(&self, mapping: GamutMapping, rgb: [f32; 3]) -> [u8; 3] {
        let m = match mapping {
            // Every 8-bit encoder clamps to 0..=1 itself, exactly as `Clip` does for a colour
            // without NaN: only the NaN rule is left to apply here.
            GamutMapping::Clip => {
                if rgb[0].is_nan() | rgb[1].is_nan() | rgb[2].is_nan() {
                    return [0; 3];
                }
                rgb
            }
            GamutMapping::PreserveA => self.map_gamut(mapping, rgb),
        };
        // The transfer function is matched once per pixel, not per channel. `m` has no NaN.
        match self.transfer {
            TransferFunction::Srgb => m.map(srgb8_not_nan),
            TransferFunction::Gamma(g) => match gamma_encoder(g) {
                Some(e) => m.map(|x| e.encode(x)),
                None => m.map(|x| quantize_u8(gamma_f32(g, x))),
            },
            t => [
                t.encode_u8(Rgb::R, m[0]),
                t.encode_u8(Rgb::G, m[1]),
                t.encode_u8(Rgb::B, m[2]),
            ],
        }
    }

    /// Gamut-maps and encodes to 16 bits with [`TransferFunction::encode_u16`] (f32, within
    /// [`U16_MAX_ERROR`](crate::U16_MAX_ERROR) of the exact curve rounded). No f64
    /// arithmetic. Input handling as [`map_gamut`](Self::map_gamut): NaN anywhere → black.
    #[inline]
    pub fn encode_u16(&self, mapping: GamutMapping, rgb: [f32; 3]) -> [u16; 3] {
        let m = self.map_gamut(mapping, rgb);
        [
            self.transfer.encode_u16(Rgb::R, m[0]),
            self.transfer.encode_u16(Rgb::G, m[1]),
            self.transfer.encode_u16(Rgb::B, m[2]),
        ]
    }
}

fn preserve_a(a_rgb: [f32; 3], rgb: [f32; 3]) -> [f32; 3] {
    let a_white = a_rgb[0] + a_rgb[1] + a_rgb[2];
    let a = a_rgb[0] * rgb[0] + a_rgb[1] * rgb[1] + a_rgb[2] * rgb[2];
    let level = a / a_white;
    if level.is_nan() || level <= 0.0 {
        return [0.0; 3];
    }
    if level >= 1.0 {
        return [1.0; 3];
    }
    // rgb(t) = level·(1, 1, 1) + t·d keeps A for every t, since a_rgb · d = 0.
    let d = rgb.map(|v| v - level);
    let mut t = 1.0f32;
    for dc in d {
        if dc > 0.0 {
            t = t.min((1.0 - level) / dc);
        } else if dc < 0.0 {
            t = t.min(level / -dc);
        }
    }
    d.map(|dc| clamp01(level + t * dc))
}
