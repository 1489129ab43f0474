//! Displays: primaries, white point and transfer function; gamut mapping and encoding.

use crate::Error;

/// One of a display's three channels. Lookup tables and transfer functions take it instead of a
/// bare index, so an index out of range cannot be written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Rgb {
    /// Red.
    R,
    /// Green.
    G,
    /// Blue.
    B,
}

impl Rgb {
    /// The channels in order.
    pub const ALL: [Rgb; 3] = [Rgb::R, Rgb::G, Rgb::B];

    /// 0, 1 or 2.
    pub const fn index(self) -> usize {
        match self {
            Rgb::R => 0,
            Rgb::G => 1,
            Rgb::B => 2,
        }
    }

    /// `"R"`, `"G"` or `"B"`.
    pub const fn name(self) -> &'static str {
        match self {
            Rgb::R => "R",
            Rgb::G => "G",
            Rgb::B => "B",
        }
    }
}

/// Per-channel lookup tables for a measured display: `tables[c][i]` is the encoded drive
/// (0..=1) that produces the linear light `i / (len − 1)` on channel c (R, G, B). Values
/// between entries are interpolated linearly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChannelLuts {
    tables: [&'static [f32]; 3],
}

impl ChannelLuts {
    /// Checks the tables: each needs at least 2 entries, all finite, in 0..=1 and
    /// non-decreasing. Usable in consts:
    ///
    /// ```
    /// use spectral_quadrature::ChannelLuts;
    /// const LUTS: ChannelLuts = match ChannelLuts::new([&[0.0, 0.7, 1.0], &[0.0, 0.6, 1.0], &[0.0, 0.5, 1.0]]) {
    ///     Ok(l) => l,
    ///     Err(_) => panic!("bad table"),
    /// };
    /// assert_eq!(LUTS.table(spectral_quadrature::Rgb::G).len(), 3);
    /// ```
    pub const fn new(tables: [&'static [f32]; 3]) -> Result<ChannelLuts, Error> {
        let mut c = 0;
        while c < 3 {
            let t = tables[c];
            if t.len() < 2 {
                return Err(Error::InvalidLut {
                    channel: Rgb::ALL[c],
                });
            }
            let mut i = 0;
            while i < t.len() {
                let v = t[i];
                if !v.is_finite() || v < 0.0 || v > 1.0 || (i > 0 && v < t[i - 1]) {
                    return Err(Error::InvalidLut {
                        channel: Rgb::ALL[c],
                    });
                }
                i += 1;
            }
            c += 1;
        }
        Ok(ChannelLuts { tables })
    }

    /// Channel c's table.
    pub const fn table(&self, c: Rgb) -> &'static [f32] {
        self.tables[c.index()]
    }
}

/// How linear light in 0..=1 becomes the value sent to the display.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TransferFunction {
    /// No encoding: the output is linear.
    Linear,
    /// The sRGB curve (IEC 61966-2-1): linear segment below 0.0031308, then 1.055·x^(1/2.4) − 0.055.
    Srgb,
    /// A pure power law: encoded = linear^(1/γ). A γ that is not finite and positive encodes as
    /// [`Linear`](Self::Linear).
    Gamma(f32),
    /// Measured per-channel tables.
    Lut(ChannelLuts),
}

impl TransferFunction {
    /// Encodes linear light on channel `c` (only lookup tables differ per channel).
    ///
    /// Input handling, for every variant: NaN gives exactly 0; values ≤ 0 (negative, −0, −Inf)
    /// give exactly 0; values ≥ 1 (huge, +Inf) give exactly 1 (also for a lookup table whose
    /// ends are not 0 and 1: zero drive is black, full drive is the brightest). Subnormal inputs
    /// are the tiny positive numbers they are: sRGB gives 12.92·x, `Gamma(γ)` gives x^(1/γ)
    /// (4e-21 for 1e-45 at γ = 2.2). The output is always in 0..=1. Never panics.
    ///
    /// This is the reference encoder: sRGB and `Gamma(γ)` compute their power in f64 and round
    /// once, so the curve is monotone between neighbouring f32. On a microcontroller without a
    /// double-precision FPU that is soft-float, about 5 800 instructions per value on a
    /// Cortex-M4F (the README's "On a microcontroller" has the measurement). The per-pixel
    /// encoders of displays and sets ([`encode_u8`](Self::encode_u8),
    /// [`encode_u16`](Self::encode_u16), [`Display::encode_u8`],
    /// [`FoldedSet::encode_u8`](crate::FoldedSet::encode_u8) and their batch forms) do not use
    /// it and have no f64 arithmetic.
    pub fn encode(&self, c: Rgb, linear: f32) -> f32 {
        let x = clamp01(linear);
        if x == 0.0 || x == 1.0 {
            return x;
        }
        let e = match *self {
            TransferFunction::Linear => x,
            TransferFunction::Srgb => {
                if x <= SRGB_LINEAR_MAX {
                    12.92 * x
                } else {
                    // The standard's rounded constants leave the power branch about 2e-8 below
                    // the linear one at the join: hold it at the join's value there, so the
                    // curve never decreases.
                    let p = 1.055 * libm::pow(f64::from(x), 1.0 / 2.4) - 0.055;
                    (p as f32).max(12.92 * SRGB_LINEAR_MAX)
                }
            }
            // Powers in f64, rounded once: libm's f32 power is not correctly rounded and could
            // step back by one unit in the last place between neighbouring inputs.
            TransferFunction::Gamma(g) => {
                if g.is_finite() && g > 0.0 {
                    libm::pow(f64::from(x), 1.0 / f64::from(g)) as f32
                } else {
                    x
                }
            }
            TransferFunction::Lut(l) => interpolate(l.table(c), x),
        };
        clamp01(e)
    }

    /// Encodes linear light on channel `c` to 8 bits, without f64 arithmetic. Input handling
    /// as [`encode`](Self::encode): NaN, ≤ 0 → 0; ≥ 1 → 255. Never panics.
    ///
    /// - [`Srgb`](Self::Srgb): [`srgb8_from_linear`](crate::srgb8_from_linear), the exact curve
    ///   (f64) times 255 rounded to nearest for every f32: a table lookup.
    /// - `Gamma(γ)` with the γ of a baked display (`Gamma(2.4)` and `Gamma(2.2)` in the default
    ///   scene): the same, correctly rounded, from thresholds the build script computed (8
    ///   comparisons). Any other γ: f32 `powf` (libm), then [`quantize_u8`]; within 1 step of
    ///   the correctly rounded value (f32 rounding near a step's half).
    /// - [`Linear`](Self::Linear) and [`Lut`](Self::Lut): the f32 value quantized with
    ///   [`quantize_u8`].
    #[inline]
    pub fn encode_u8(&self, c: Rgb, linear: f32) -> u8 {
        match *self {
            TransferFunction::Linear => quantize_u8(linear),
            TransferFunction::Srgb => crate::srgb8_from_linear(linear),
            TransferFunction::Gamma(g) => match crate::encode::gamma_encoder(g) {
                Some(e) => e.encode(linear),
                None => quantize_u8(gamma_f32(g, linear)),
            },
            TransferFunction::Lut(l) => quantize_u8(lut_encode(l.table(c), linear)),
        }
    }

    /// Encodes linear light on channel `c` to 16 bits, without f64 arithmetic: the curve in f32
    /// (libm's f32 `powf` for sRGB and `Gamma(γ)`), then [`quantize_u16`]. Input handling as
    /// [`encode`](Self::encode): NaN, ≤ 0 → 0; ≥ 1 → 65535. Never panics.
    ///
    /// Within [`U16_MAX_STEP_ERROR`] (1 step) of the exact curve (f64) times 65 535 rounded to
    /// nearest; tests/transfer.rs measures it at every 8- and 16-bit code boundary of sRGB,
    /// `Gamma(2.2)` and `Gamma(2.4)`.
    #[inline]
    pub fn encode_u16(&self, c: Rgb, linear: f32) -> u16 {
        let e = match *self {
            TransferFunction::Linear => linear,
            TransferFunction::Srgb => srgb_f32(linear),
            TransferFunction::Gamma(g) => gamma_f32(g, linear),
            TransferFunction::Lut(l) => lut_encode(l.table(c), linear),
        };
        quantize_u16(e)
    }

    /// Decodes a display value on channel `c` back to linear light: the inverse of
    /// [`encode`](Self::encode). Same input handling: NaN → 0, ≤ 0 → exactly 0, ≥ 1 →
    /// exactly 1; output in 0..=1. For a table with flat stretches, the lowest linear value of
    /// the stretch.
    pub fn decode(&self, c: Rgb, encoded: f32) -> f32 {
        let e = clamp01(encoded);
        if e == 0.0 || e == 1.0 {
            return e;
        }
        let x = match *self {
            TransferFunction::Linear => e,
            TransferFunction::Srgb => {
                if e <= SRGB_ENCODED_LINEAR_MAX {
                    e / 12.92
                } else {
                    let p = libm::pow((f64::from(e) + 0.055) / 1.055, 2.4);
                    (p as f32).max(SRGB_ENCODED_LINEAR_MAX / 12.92)
                }
            }
            TransferFunction::Gamma(g) => {
                if g.is_finite() && g > 0.0 {
                    libm::pow(f64::from(e), f64::from(g)) as f32
                } else {
                    e
                }
            }
            TransferFunction::Lut(l) => inverse_interpolate(l.table(c), e),
        };
        clamp01(x)
    }
}

/// The largest difference, in 16-bit steps, between
/// [`TransferFunction::encode_u16`] (and so [`Display::encode_u16`] and the sets' `encode_u16`)
/// and the exact curve (f64) times 65 535 rounded to nearest, for sRGB and power laws: the f32
/// curve is within a few units in the last place, so it can only land on the other side of a
/// step's half. tests/transfer.rs checks every 8- and 16-bit code boundary.
pub const U16_MAX_STEP_ERROR: u16 = 1;

/// The sRGB curve in f32 (libm's `powf`), held at the join's value above it so it never drops
/// below the linear segment; clamped input, output in 0..=1.
#[inline]
fn srgb_f32(linear: f32) -> f32 {
    let x = clamp01(linear);
    if x == 0.0 || x == 1.0 {
        return x;
    }
    let e = if x <= SRGB_LINEAR_MAX {
        12.92 * x
    } else {
        (1.055 * libm::powf(x, 1.0 / 2.4) - 0.055).max(12.92 * SRGB_LINEAR_MAX)
    };
    clamp01(e)
}

/// x^(1/γ) in f32 (libm's `powf`); a γ that is not finite and positive is linear. Clamped
/// input, output in 0..=1.
#[inline]
fn gamma_f32(g: f32, linear: f32) -> f32 {
    let x = clamp01(linear);
    if x == 0.0 || x == 1.0 || !(g.is_finite() && g > 0.0) {
        return x;
    }
    clamp01(libm::powf(x, 1.0 / g))
}

/// A lookup table's encoding of clamped input, as [`TransferFunction::encode`].
#[inline]
fn lut_encode(t: &[f32], linear: f32) -> f32 {
    let x = clamp01(linear);
    if x == 0.0 || x == 1.0 {
        return x;
    }
    clamp01(interpolate(t, x))
}

/// The end of the sRGB curve's linear segment, in linear light.
const SRGB_LINEAR_MAX: f32 = 0.003_130_8;
/// The end of the linear segment in encoded values.
const SRGB_ENCODED_LINEAR_MAX: f32 = 0.040_45;

/// Clamps to 0..=1 with NaN → 0.
#[inline]
pub(crate) fn clamp01(x: f32) -> f32 {
    if x > 0.0 {
        if x < 1.0 {
            x
        } else {
            1.0
        }
    } else {
        0.0
    }
}

fn interpolate(t: &[f32], x: f32) -> f32 {
    if t.len() < 2 {
        return t.first().copied().unwrap_or(x);
    }
    let pos = x * (t.len() - 1) as f32;
    let i = (pos as usize).min(t.len() - 2);
    let f = pos - i as f32;
    t[i] + (t[i + 1] - t[i]) * f
}

fn inverse_interpolate(t: &[f32], e: f32) -> f32 {
    if t.len() < 2 {
        return e;
    }
    let last = t.len() - 1;
    if e <= t[0] {
        return 0.0;
    }
    if e >= t[last] {
        return 1.0;
    }
    // First index with t[i] ≥ e; then t[i - 1] < e ≤ t[i].
    let i = t.partition_point(|&v| v < e).clamp(1, last);
    let (a, b) = (t[i - 1], t[i]);
    let f = if b > a { (e - a) / (b - a) } else { 0.0 };
    ((i - 1) as f32 + f) / last as f32
}

/// What to do with colours the display cannot show (a linear channel below 0 or above 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
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

/// A display: primaries, white point (CIE 1931 xy), the matrices between linear RGB and XYZ
/// (white at Y = 1), and a transfer function.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Display {
    /// A short name, e.g. `"sRGB"`.
    pub name: &'static str,
    /// Chromaticities of red, green, blue.
    pub primaries_xy: [[f32; 2]; 3],
    /// Chromaticity of white (RGB = 1, 1, 1).
    pub white_xy: [f32; 2],
    /// Linear RGB → XYZ.
    pub rgb_to_xyz: [[f32; 3]; 3],
    /// XYZ → linear RGB.
    pub xyz_to_rgb: [[f32; 3]; 3],
    /// The achromatic coordinate A of one unit of linear R, G and B (used by
    /// [`GamutMapping::PreserveA`]).
    pub a_from_rgb: [f32; 3],
    /// How linear light is encoded.
    pub transfer: TransferFunction,
}

impl Display {
    /// A display made at run time from its primaries and white point (CIE 1931 xy) and a transfer
    /// function, with the matrices computed as the build script computes the baked ones: linear
    /// RGB = (1, 1, 1) is the white at Y = 1.
    ///
    /// Errors, never a panic: [`Error::InvalidChromaticity`] for a coordinate that is not finite,
    /// negative, or with x + y > 1 or y = 0; [`Error::SingularPrimaries`] when the primaries are
    /// collinear (or nearly: the matrix's condition number above
    /// [`MAX_PRIMARIES_CONDITION`]), or so extreme that the f32 matrices would overflow;
    /// [`Error::WhiteOutsideGamut`] when the white is not a positive mix of the primaries (or lies
    /// on an edge of their triangle: some primary's share below [`MIN_WHITE_SHARE`] of the
    /// largest); [`Error::InvalidGamma`] for a `Gamma(γ)` whose γ is not finite and
    /// positive. Lookup tables were checked by [`ChannelLuts::new`].
    ///
    /// It computes in f64 (once per display, not per pixel; on a microcontroller without a double
    /// FPU that is some thousands of instructions of soft-float).
    ///
    /// ```
    /// use spectral_quadrature::{tables::displays, Display, Error, TransferFunction};
    /// let srgb = Display::new("sRGB", [[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]], [0.3127, 0.3290], TransferFunction::Srgb).unwrap();
    /// assert!((srgb.xyz_to_rgb[0][0] - displays::SRGB.xyz_to_rgb[0][0]).abs() < 1e-4);
    /// let flat = Display::new("flat", [[0.2, 0.2], [0.4, 0.4], [0.3, 0.3]], [0.3127, 0.3290], TransferFunction::Srgb);
    /// assert_eq!(flat.unwrap_err(), Error::SingularPrimaries);
    /// ```
    pub fn new(
        name: &'static str,
        primaries_xy: [[f32; 2]; 3],
        white_xy: [f32; 2],
        transfer: TransferFunction,
    ) -> Result<Display, Error> {
        if let TransferFunction::Gamma(g) = transfer {
            if !(g.is_finite() && g > 0.0) {
                return Err(Error::InvalidGamma);
            }
        }
        let xyz_of = |xy: [f32; 2]| -> Result<[f64; 3], Error> {
            let (x, y) = (f64::from(xy[0]), f64::from(xy[1]));
            if !(x.is_finite() && y.is_finite() && x >= 0.0 && y > 0.0 && x + y <= 1.0) {
                return Err(Error::InvalidChromaticity);
            }
            Ok([x / y, 1.0, (1.0 - x - y) / y])
        };
        let p = [
            xyz_of(primaries_xy[0])?,
            xyz_of(primaries_xy[1])?,
            xyz_of(primaries_xy[2])?,
        ];
        let w = xyz_of(white_xy)?;
        // Columns are the primaries' XYZ at Y = 1.
        let m = [0, 1, 2].map(|r| [p[0][r], p[1][r], p[2][r]]);
        let inv = invert3(&m).ok_or(Error::SingularPrimaries)?;
        if norm_inf(&m) * norm_inf(&inv) > MAX_PRIMARIES_CONDITION {
            return Err(Error::SingularPrimaries);
        }
        // The primaries' amounts in white.
        let s = [0, 1, 2].map(|r| inv[r][0] * w[0] + inv[r][1] * w[1] + inv[r][2] * w[2]);
        // Strictly inside the triangle: a white on an edge (some primary's amount a negligible
        // fraction of the largest) would make xyz_to_rgb blow up.
        let largest = s.iter().fold(0.0f64, |m, v| m.max(*v));
        if !s
            .iter()
            .all(|&v| v.is_finite() && v > MIN_WHITE_SHARE * largest)
        {
            return Err(Error::WhiteOutsideGamut);
        }
        let rgb_to_xyz = [0, 1, 2].map(|r| [0, 1, 2].map(|c| m[r][c] * s[c]));
        let xyz_to_rgb = invert3(&rgb_to_xyz).ok_or(Error::SingularPrimaries)?;
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
            return Err(Error::SingularPrimaries);
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

    /// The same display with another transfer function (for example measured lookup tables).
    pub const fn with_transfer(mut self, transfer: TransferFunction) -> Display {
        self.transfer = transfer;
        self
    }

    /// Linear RGB of an XYZ colour (Y = 1 is the display's white). IEEE arithmetic: NaN and
    /// ±Inf propagate, out-of-gamut colours give components below 0 or above 1.
    pub fn linear_from_xyz(&self, xyz: [f32; 3]) -> [f32; 3] {
        crate::mat3_vec(&self.xyz_to_rgb, xyz)
    }

    /// XYZ of a linear RGB colour. IEEE arithmetic, as [`linear_from_xyz`](Self::linear_from_xyz).
    pub fn xyz_from_linear(&self, rgb: [f32; 3]) -> [f32; 3] {
        crate::mat3_vec(&self.rgb_to_xyz, rgb)
    }

    /// Brings a linear colour into 0..=1 per channel.
    ///
    /// Any NaN channel gives black `[0, 0, 0]`. With `PreserveA`, a colour with an infinite
    /// channel is clipped as with `Clip` (+Inf → 1, −Inf → 0). Never panics; the output is
    /// always in 0..=1.
    #[inline]
    pub fn map_gamut(&self, rgb: [f32; 3], mapping: GamutMapping) -> [f32; 3] {
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
    pub fn encode(&self, rgb: [f32; 3], mapping: GamutMapping) -> [f32; 3] {
        let m = self.map_gamut(rgb, mapping);
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
    pub fn encode_u8(&self, rgb: [f32; 3], mapping: GamutMapping) -> [u8; 3] {
        // The common case inline and without branches: the sRGB table clamps as `Clip` does,
        // and a NaN anywhere selects black afterwards.
        if self.is_srgb_clip(mapping) {
            let nan = rgb[0].is_nan() | rgb[1].is_nan() | rgb[2].is_nan();
            let px = rgb.map(crate::encode::srgb8_not_nan);
            return if nan { [0; 3] } else { px };
        }
        self.encode_u8_other(rgb, mapping)
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
    fn encode_u8_other(&self, rgb: [f32; 3], mapping: GamutMapping) -> [u8; 3] {
        let m = match mapping {
            // Every 8-bit encoder clamps to 0..=1 itself, exactly as `Clip` does for a colour
            // without NaN: only the NaN rule is left to apply here.
            GamutMapping::Clip => {
                if rgb[0].is_nan() | rgb[1].is_nan() | rgb[2].is_nan() {
                    return [0; 3];
                }
                rgb
            }
            GamutMapping::PreserveA => self.map_gamut(rgb, mapping),
        };
        // The transfer function is matched once per pixel, not per channel. `m` has no NaN.
        match self.transfer {
            TransferFunction::Srgb => m.map(crate::encode::srgb8_not_nan),
            TransferFunction::Gamma(g) => match crate::encode::gamma_encoder(g) {
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
    /// [`U16_MAX_STEP_ERROR`] of the exact curve rounded). No f64 arithmetic. Input handling as
    /// [`map_gamut`](Self::map_gamut): NaN anywhere → black.
    #[inline]
    pub fn encode_u16(&self, rgb: [f32; 3], mapping: GamutMapping) -> [u16; 3] {
        let m = self.map_gamut(rgb, mapping);
        [
            self.transfer.encode_u16(Rgb::R, m[0]),
            self.transfer.encode_u16(Rgb::G, m[1]),
            self.transfer.encode_u16(Rgb::B, m[2]),
        ]
    }
}

/// The largest condition number of the primaries' matrix (columns: the primaries' XYZ at
/// Y = 1) that [`Display::new`] accepts: beyond it the primaries are so nearly collinear that the
/// f32 matrices would lose three or more of their seven digits. The derivation refuses baked
/// displays at the same value of the 2-norm condition number; this one uses the ∞-norm, which
/// for a 3×3 matrix is within a factor of 3 of it.
pub const MAX_PRIMARIES_CONDITION: f64 = 1000.0;

/// The smallest share of a primary in the white, relative to the largest, that
/// [`Display::new`] accepts: below it the white lies on an edge of the primaries' triangle, and
/// the XYZ → RGB matrix would be dominated by one enormous column.
pub const MIN_WHITE_SHARE: f64 = 1e-6;

/// The inverse of a 3×3 matrix by cofactors, `None` when singular or not finite.
fn invert3(m: &[[f64; 3]; 3]) -> Option<[[f64; 3]; 3]> {
    let c =
        |r0: usize, r1: usize, c0: usize, c1: usize| m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0];
    let cof = [
        [c(1, 2, 1, 2), -c(1, 2, 0, 2), c(1, 2, 0, 1)],
        [-c(0, 2, 1, 2), c(0, 2, 0, 2), -c(0, 2, 0, 1)],
        [c(0, 1, 1, 2), -c(0, 1, 0, 2), c(0, 1, 0, 1)],
    ];
    let det = m[0][0] * cof[0][0] + m[0][1] * cof[0][1] + m[0][2] * cof[0][2];
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    // inverse = adjugate / det, the adjugate being the cofactors transposed.
    let inv = [0, 1, 2].map(|r| [0, 1, 2].map(|k| cof[k][r] / det));
    inv.iter().flatten().all(|v| v.is_finite()).then_some(inv)
}

/// The ∞-norm (largest absolute row sum) of a 3×3 matrix.
fn norm_inf(m: &[[f64; 3]; 3]) -> f64 {
    m.iter()
        .map(|r| r.iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// 0..=1 → 0..=255, round to nearest; NaN → 0, out of range clamped.
#[inline]
pub fn quantize_u8(e: f32) -> u8 {
    (clamp01(e) * 255.0 + 0.5) as u8
}

/// 0..=1 → 0..=65535, round to nearest; NaN → 0, out of range clamped.
#[inline]
pub fn quantize_u16(e: f32) -> u16 {
    (clamp01(e) * 65535.0 + 0.5) as u16
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
