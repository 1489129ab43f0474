//! Transfer functions: how linear light on a display's channel becomes the value sent to it
//! (f32, 8 and 16 bits), and back.

#![forbid(unsafe_code)]

use super::bits::same_f32_bits;
use crate::encode::{clamp01, GammaEncoder8};
use crate::{Error, Rgb};

/// Per-channel lookup tables for a measured display: `tables[c][i]` is the encoded drive
/// (0..=1) that produces the linear light `i / (len − 1)` on channel c (R, G, B). Values
/// between entries are interpolated linearly.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
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
    /// double-precision FPU that is soft-float, many times the cost of the 8-bit encoders
    /// (docs/performance.md has the measurement and its command). The per-pixel
    /// encoders of displays and sets ([`encode_u8`](Self::encode_u8),
    /// [`encode_u16`](Self::encode_u16), [`Display::encode_u8`](crate::Display::encode_u8),
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
            TransferFunction::Gamma(g) => match gamma_encoder(g) {
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
    /// Within [`U16_MAX_ERROR`] (1 step) of the exact curve (f64) times 65 535 rounded to
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

    /// Whether `other` is the same variant with the same bits (a γ, or every entry of the three
    /// tables): `PartialEq` in a const fn.
    pub(crate) const fn same_bits(&self, other: &TransferFunction) -> bool {
        match (self, other) {
            (TransferFunction::Linear, TransferFunction::Linear)
            | (TransferFunction::Srgb, TransferFunction::Srgb) => true,
            (TransferFunction::Gamma(x), TransferFunction::Gamma(y)) => x.to_bits() == y.to_bits(),
            (TransferFunction::Lut(x), TransferFunction::Lut(y)) => {
                let mut k = 0;
                while k < 3 {
                    let c = Rgb::ALL[k];
                    if !same_f32_bits(x.table(c), y.table(c)) {
                        return false;
                    }
                    k += 1;
                }
                true
            }
            _ => false,
        }
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

/// The largest difference, in 16-bit steps, between [`TransferFunction::encode_u16`] (and so
/// [`Display::encode_u16`](crate::Display::encode_u16) and the sets' `encode_u16`) and the exact
/// curve (f64) times 65 535 rounded to nearest, for sRGB and power laws: the f32 curve is within a
/// few units in the last place, so it can only land on the other side of a step's half.
/// tests/transfer.rs checks every 8- and 16-bit code boundary.
pub const U16_MAX_ERROR: u16 = 1;

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
pub(crate) fn gamma_f32(g: f32, linear: f32) -> f32 {
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

/// The baked encoder for `Gamma(gamma)`, if a baked display has that γ.
#[inline]
pub(crate) fn gamma_encoder(gamma: f32) -> Option<&'static GammaEncoder8> {
    crate::tables::GAMMA_ENCODERS
        .iter()
        .find(|e| e.gamma.to_bits() == gamma.to_bits())
}
