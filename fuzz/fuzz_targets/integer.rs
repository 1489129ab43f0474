//! The integer path on arbitrary counts: `IntegerSet::encode_u8` and `encode_u8_batch` of the
//! baked integer sets (N = 4, 6 and 8, the default scene's displays), and of sets made at run
//! time by `IntegerSet::new` from a baked folded set whose weights and sample unit the bytes
//! scale (any f32: NaN, ±Inf, subnormal, huge, negative).
//!
//! Checked: no panic; each byte is what `encode_u8`'s documentation defines, independently of
//! its coarse sums and tables of limits: the number of the display's f32 thresholds at or below
//! the exact value `F / 2^P` of `linear_fixed`, that is `Display::encode_u8` (clipping) of the
//! largest f32 at or below it; the batch gives the per-pixel bytes, and refuses a length
//! mismatch without writing; `IntegerSet::new` either refuses or gives a set whose weights
//! are within 2³¹.
#![no_main]

use common::{step_ulps, Bytes};
use libfuzzer_sys::fuzz_target;
use spectral_quadrature::tables::{folded, integer};
use spectral_quadrature::{FoldedSet, GamutMapping, IntegerSet};

/// At most this many pixels per input (longer inputs are truncated).
const MAX_PIXELS: usize = 24;

/// The largest f32 at or below `v` (finite `v`).
fn f32_at_or_below(v: f64) -> f32 {
    let x = v as f32;
    if f64::from(x) <= v {
        x
    } else {
        // Rounded up: one step toward −∞. Never from +0.0 (a negative `v` rounds to −0.0 at
        // most), where `step_ulps` would give −0.0 instead of the smallest negative f32.
        step_ulps(x, -1)
    }
}

/// The bytes `encode_u8` is defined to give for `counts`.
fn expected<const N: usize>(set: &IntegerSet<N>, counts: &[u16; N]) -> [u8; 3] {
    let f = set.linear_fixed(counts);
    // |F| < 2³¹ · 65535 · N < 2⁵³: exact in f64, and so is the division by 2^P.
    let scale = (-(set.frac_bits() as i32) as f64).exp2();
    let rgb = f.map(|v| f32_at_or_below(v as f64 * scale));
    set.display().encode_u8(GamutMapping::Clip, rgb)
}

fn check<const N: usize>(set: &IntegerSet<N>, bytes: &mut Bytes) {
    let mut px = Vec::new();
    while !bytes.is_empty() && px.len() < MAX_PIXELS {
        px.push(std::array::from_fn::<u16, N, _>(|_| {
            u16::from_le_bytes([bytes.u8(), bytes.u8()])
        }));
    }
    for counts in &px {
        let got = set.encode_u8(counts);
        let want = expected(set, counts);
        assert_eq!(
            got,
            want,
            "P = {}, counts {counts:?}, F {:?}",
            set.frac_bits(),
            set.linear_fixed(counts)
        );
    }
    let mut out = vec![[7u8; 3]; px.len()];
    set.encode_u8_batch(&px, &mut out).unwrap();
    for (p, counts) in px.iter().enumerate() {
        assert_eq!(out[p], set.encode_u8(counts), "batch pixel {p}: {counts:?}");
    }
    // A length mismatch is refused and nothing is written.
    let mut short = vec![[7u8; 3]; px.len().saturating_sub(1)];
    if !px.is_empty() {
        assert!(set.encode_u8_batch(&px, &mut short).is_err());
        assert!(short.iter().all(|b| *b == [7; 3]));
    }
}

/// A set made at run time: `folded`'s weights times a factor, with a sample unit, both from the
/// bytes.
fn made<const N: usize>(set: &FoldedSet<N>, bytes: &mut Bytes) -> Option<IntegerSet<N>> {
    let factor = bytes.value();
    let unit = match bytes.u8() % 4 {
        0 => 1.0 / 65535.0,
        _ => bytes.value(),
    };
    let weights = set.weights().map(|row| row.map(|w| w * factor));
    let f = FoldedSet::new(set.wavelengths_nm(), weights, set.samples(), set.display()).ok()?;
    let made = IntegerSet::new(&f, unit).ok()?;
    assert!(made
        .weights()
        .iter()
        .flatten()
        .all(|v| v.unsigned_abs() < 1 << 31));
    Some(made)
}

fuzz_target!(|data: &[u8]| {
    let mut bytes = Bytes::new(data);
    match bytes.u8() % 8 {
        0 => check(&integer::TABLE2_ROW2_SRGB, &mut bytes),
        1 => check(&integer::KQ_C_4_REC2020, &mut bytes),
        2 => check(&integer::TABLE2_ROW1_DISPLAY_P3, &mut bytes),
        3 => check(&integer::KQ_F11_6_MEYER_1987, &mut bytes),
        4 => check(&integer::KQ_C_8_SRGB, &mut bytes),
        5 => {
            if let Some(set) = made(&folded::KQ_C_4_SRGB, &mut bytes) {
                check(&set, &mut bytes);
            }
        }
        6 => {
            if let Some(set) = made(&folded::TABLE2_ROW1_REC2020, &mut bytes) {
                check(&set, &mut bytes);
            }
        }
        _ => {
            if let Some(set) = made(&folded::KQ_C_8_DISPLAY_P3, &mut bytes) {
                check(&set, &mut bytes);
            }
        }
    }
});
