//! The planar (structure-of-arrays) batch path and the table sRGB encoder behind it.
//!
//! 1. The encoder against the exact sRGB curve, recomputed here in f64 with `libm::pow`: equal
//!    to it rounded to nearest for every f32 from 2⁻¹³ to 1 (109 million values, exhaustively),
//!    and 0 below; against the per-pixel encoder within `SRGB8_MAX_ERROR`.
//! 2. What one step costs in colour: the largest ΔE*ab between 8-bit sRGB colours that differ by
//!    at most one step per channel, over the whole cube, below `SRGB8_MAX_ERROR_DE76`.
//! 3. Property tests (2 000 cases each, of up to 39 pixels: some 40 000 pixels per property; no
//!    regression files): the planar path equals the per-pixel path, for random lengths (0 to 39
//!    pixels: multiples of the 16-pixel chunk and not), random finite and non-finite samples,
//!    N = 4, 6 (baked sets), 8 and 16 (random weights).
//! 4. Documented input handling, and length errors that leave the outputs untouched. (That
//!    the planar paths never allocate is in tests/no_alloc.rs, with the rest of the runtime.)

// Channel loops index several parallel arrays by channel.
#![allow(clippy::needless_range_loop)]

mod common;

use common::{FOLDED_ROW1, FOLDED_ROW2, MAPPINGS};

use std::fmt::Debug;

use proptest::prelude::*;
use proptest::test_runner::TestCaseResult;
use spectral_quadrature::tables::{displays, folded};
use spectral_quadrature::{
    delta_e76, f32_budget, lab_from_xyz, quantize_u8, srgb8_from_linear, Error, FoldedSet,
    GamutMapping, LengthOf, Rgb, Samples, TransferFunction, SRGB8_MAX_ERROR, SRGB8_MAX_ERROR_DE76,
};

// ---------------------------------------------------------------------------------------------
// The exact curve, in f64
// ---------------------------------------------------------------------------------------------

/// The sRGB curve (IEC 61966-2-1) in f64, for x in 0..=1.
fn srgb64(x: f64) -> f64 {
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * libm::pow(x, 1.0 / 2.4) - 0.055
    }
}

/// The exact curve rounded to nearest (halves up) as a code value, for x in 0..=1.
fn exact8(x: f32) -> u8 {
    (255.0 * srgb64(f64::from(x)) + 0.5).floor() as u8
}

/// The per-pixel path's encoder: `TransferFunction::Srgb.encode_u8`.
fn per_pixel8(x: f32) -> u8 {
    TransferFunction::Srgb.encode_u8(Rgb::R, x)
}

/// The f32 curve quantized: `TransferFunction::Srgb` rounded twice.
fn quantized8(x: f32) -> u8 {
    quantize_u8(TransferFunction::Srgb.encode(Rgb::R, x))
}

/// For k = 1..=255, the bits of the smallest f32 in 0..=1 at which `f` reaches k, by bisection
/// over the f32 bit patterns (both encoders are non-decreasing in x; the exhaustive walk below
/// confirms it for `exact8`, and tests/properties.rs p6 for the per-pixel one).
fn thresholds(f: impl Fn(f32) -> u8) -> Vec<u32> {
    (1..=255u8)
        .map(|k| {
            let (mut lo, mut hi) = (0u32, 1.0f32.to_bits());
            assert!(f(f32::from_bits(lo)) < k && f(f32::from_bits(hi)) >= k);
            while hi - lo > 1 {
                let mid = lo + (hi - lo) / 2;
                if f(f32::from_bits(mid)) >= k {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            hi
        })
        .collect()
}

/// 2⁻¹³: the encoder's lower clamp.
const LO: f32 = f32::from_bits((127 - 13) << 23);

#[test]
fn encoder_is_the_exact_curve_rounded_for_every_f32_in_0_1() {
    let exact = thresholds(exact8);
    let pixel = thresholds(per_pixel8);
    let twice = thresholds(quantized8);
    // Below 2⁻¹³ the encoder clamps to 2⁻¹³; the exact curve is 0 there (it is 12.92·x, and
    // the first threshold lies above 2⁻¹³).
    assert!(
        exact[0] > LO.to_bits(),
        "first threshold {:e}",
        f32::from_bits(exact[0])
    );
    assert_eq!(exact8(LO), 0);
    // Every f32 from 2⁻¹³ to 1, in increasing order: the exact code value is the number of
    // thresholds passed; the encoder must equal it, and the per-pixel one differ by at most
    // SRGB8_MAX_ERROR.
    let (mut k_exact, mut k_pixel, mut k_twice) = (0usize, 0usize, 0usize);
    let (mut differ, mut worst, mut twice_differ) = (0u64, 0u8, 0u64);
    let mut bits = LO.to_bits();
    while bits <= 1.0f32.to_bits() {
        while k_exact < 255 && exact[k_exact] <= bits {
            k_exact += 1;
        }
        while k_pixel < 255 && pixel[k_pixel] <= bits {
            k_pixel += 1;
        }
        while k_twice < 255 && twice[k_twice] <= bits {
            k_twice += 1;
        }
        if k_twice != k_exact {
            twice_differ += 1;
            assert_eq!(k_twice.abs_diff(k_exact), 1);
        }
        let got = srgb8_from_linear(f32::from_bits(bits));
        if usize::from(got) != k_exact {
            let x = f32::from_bits(bits);
            panic!(
                "srgb8_from_linear({x:e} = {bits:#x}) = {got}, exact {k_exact} \
                 (255·srgb = {})",
                255.0 * srgb64(f64::from(x))
            );
        }
        if k_pixel != k_exact {
            differ += 1;
            worst = worst.max(k_pixel.abs_diff(k_exact) as u8);
        }
        bits += 1;
    }
    // Spot checks of the walk's counting against the formula itself, at each threshold.
    for (i, &t) in exact.iter().enumerate() {
        let k = i as u8 + 1;
        assert_eq!(exact8(f32::from_bits(t)), k);
        assert_eq!(exact8(f32::from_bits(t - 1)), k - 1);
    }
    eprintln!(
        "encoder: equal to the exact curve rounded on all {} f32 in 2^-13..=1; per-pixel \
         encoder differs on {differ} of them, by at most {worst} step(s) (asserted ≤ {}); \
         the f32 curve quantized differs on {twice_differ}, by 1 step",
        1.0f32.to_bits() - LO.to_bits() + 1,
        SRGB8_MAX_ERROR
    );
    assert_eq!(worst, SRGB8_MAX_ERROR);
    assert_eq!(differ, 0);
    // The count the docs of SRGB8_MAX_ERROR give for rounding twice.
    assert_eq!(twice_differ, 268);
    // Below 2⁻¹³: every 4096th f32 (the encoder clamps them all to 2⁻¹³), and the specials.
    for bits in (0..LO.to_bits()).step_by(4096) {
        let x = f32::from_bits(bits);
        assert_eq!(srgb8_from_linear(x), 0, "{x:e}");
        assert_eq!(exact8(x), 0, "{x:e}");
    }
}

#[test]
fn encoder_input_handling() {
    for x in [
        f32::NAN,
        -f32::NAN,
        f32::NEG_INFINITY,
        -f32::MAX,
        -1.0,
        -1e-45,
        -0.0,
        0.0,
    ] {
        assert_eq!(srgb8_from_linear(x), 0, "{x:?}");
    }
    for x in [1e-45, f32::MIN_POSITIVE, 1.5e-4] {
        assert_eq!(srgb8_from_linear(x), 0, "{x:?}");
    }
    for x in [1.0, 1.000_001, 2.0, 1e30, f32::MAX, f32::INFINITY] {
        assert_eq!(srgb8_from_linear(x), 255, "{x:?}");
    }
    // Every NaN payload, both signs, a few of them.
    for payload in [1u32, 0x2a, 0x40_0000, 0x7f_ffff] {
        for sign in [0u32, 0x8000_0000] {
            let x = f32::from_bits(sign | 0x7f80_0000 | payload);
            assert!(x.is_nan());
            assert_eq!(srgb8_from_linear(x), 0);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// What one step costs: ΔE*ab over the sRGB cube
// ---------------------------------------------------------------------------------------------

/// Lab (D65 white of the sRGB display, Y = 1) of every 8-bit colour with blue = b, at
/// `r * 256 + g`.
fn lab_plane(b: usize, linear: &[f64; 256], m: &[[f64; 3]; 3], white: [f64; 3]) -> Vec<[f64; 3]> {
    let mut plane = Vec::with_capacity(256 * 256);
    for r in 0..256 {
        for g in 0..256 {
            let rgb = [linear[r], linear[g], linear[b]];
            let xyz: [f64; 3] =
                std::array::from_fn(|i| m[i][0] * rgb[0] + m[i][1] * rgb[1] + m[i][2] * rgb[2]);
            plane.push(lab_from_xyz(xyz, white));
        }
    }
    plane
}

/// The largest squared ΔE*ab between `a[i]` and `b[i + offset]` over the colours `i` (as
/// `r * 256 + g`) whose red and green, moved by `(dr, dg)`, stay in 0..=255; with the pair.
fn worst_pair(a: &[[f64; 3]], b: &[[f64; 3]], dr: i32, dg: i32) -> (f64, usize, usize) {
    let mut worst = (0.0f64, 0, 0);
    for r in 0.max(-dr)..256.min(256 - dr) {
        for g in 0.max(-dg)..256.min(256 - dg) {
            let i = (r * 256 + g) as usize;
            let j = ((r + dr) * 256 + g + dg) as usize;
            let (p, q) = (a[i], b[j]);
            let d2 = (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2);
            if d2 > worst.0 {
                worst = (d2, i, j);
            }
        }
    }
    worst
}

#[test]
fn one_step_per_channel_costs_at_most_srgb8_max_delta_e() {
    // The exact decode of each code value, and the sRGB display's matrix, in f64.
    let linear: [f64; 256] = std::array::from_fn(|v| {
        let e = v as f64 / 255.0;
        if e <= 0.040_45 {
            e / 12.92
        } else {
            libm::pow((e + 0.055) / 1.055, 2.4)
        }
    });
    let m = displays::SRGB.rgb_to_xyz().map(|row| row.map(f64::from));
    let white: [f64; 3] = std::array::from_fn(|i| m[i].iter().sum());
    // Each unordered pair of colours at most one step apart in every channel, once: one step
    // down in blue (the previous plane, any red and green step), or the same blue and a step
    // up in (red, green) order. 13 of the 26 neighbours; the other 13 are the same pairs seen
    // from the other end.
    let steps: Vec<[i32; 3]> = (0..27)
        .map(|i| [i / 9 - 1, (i / 3) % 3 - 1, i % 3 - 1])
        .filter(|d| d[2] == -1 || (d[2] == 0 && [d[0], d[1]] > [0, 0]))
        .collect();
    assert_eq!(steps.len(), 13);
    // Two threads, each over half of the blue planes (the second also reads the plane before).
    let scan = |planes: std::ops::Range<usize>| {
        let (mut worst, mut single) = ((0.0f64, [0usize; 3], [0usize; 3]), 0.0f64);
        let mut prev = (planes.start > 0).then(|| lab_plane(planes.start - 1, &linear, &m, white));
        for b in planes {
            let here = lab_plane(b, &linear, &m, white);
            for d in &steps {
                let other = match d[2] {
                    0 => &here,
                    _ => match &prev {
                        Some(p) => p,
                        None => continue,
                    },
                };
                let (d2, i, j) = worst_pair(&here, other, d[0], d[1]);
                if d.iter().filter(|&&s| s != 0).count() == 1 {
                    single = single.max(d2);
                }
                if d2 > worst.0 {
                    let b2 = (b as i32 + d[2]) as usize;
                    worst = (d2, [i / 256, i % 256, b], [j / 256, j % 256, b2]);
                }
            }
            prev = Some(here);
        }
        (worst, single)
    };
    let ((w1, s1), (w2, s2)) = std::thread::scope(|s| {
        let low = s.spawn(|| scan(0..128));
        let high = scan(128..256);
        (low.join().expect("scan thread"), high)
    });
    let (worst, single) = (if w1.0 >= w2.0 { w1 } else { w2 }, s1.max(s2));
    let (de, single) = (worst.0.sqrt(), single.sqrt());
    eprintln!(
        "one step: max ΔE*ab {de:.4} between {:?} and {:?} (≤ 1 step in each channel); \
         {single:.4} for a step in one channel (asserted < {SRGB8_MAX_ERROR_DE76})",
        worst.1, worst.2
    );
    assert!(de < f64::from(SRGB8_MAX_ERROR_DE76));
    // delta_e76 agrees with the squared distance used above: the same f64 differences, summed
    // in another order, so a few units of 2⁻⁵² of a ΔE near 2, far below 1e-12.
    let lab = |c: [usize; 3]| lab_plane(c[2], &linear, &m, white)[c[0] * 256 + c[1]];
    assert!((delta_e76(lab(worst.1), lab(worst.2)) - de).abs() < 1e-12);
}

// ---------------------------------------------------------------------------------------------
// The planar path against the per-pixel path
// ---------------------------------------------------------------------------------------------

/// Runs one property for 2 000 cases, each a whole image of up to 39 pixels, with
/// [`common::check_property`].
fn check<S>(name: &str, strategy: S, test: impl Fn(S::Value) -> TestCaseResult)
where
    S: Strategy,
    S::Value: Debug,
{
    common::check_property(2_000, name, strategy, test);
}

/// One sample: mostly reflectance-like, radiance-like or signed values, sometimes any f32 at
/// all (NaN, ±Inf, subnormals, huge).
fn sample() -> impl Strategy<Value = f32> + Clone {
    prop_oneof![
        3 => 0.0f32..=1.0,
        2 => 0.0f32..=1e4,
        2 => -1e3f32..=1e3,
        1 => any::<f32>(),
    ]
}

/// Pixels as `[f32; N]`, 0 to 40 of them: no, one and two full 16-pixel chunks, with and
/// without a partial one. Drawn as one flat vector, which keeps proptest's value trees on the
/// heap.
fn pixels<const N: usize>() -> impl Strategy<Value = Vec<[f32; N]>> {
    proptest::collection::vec(sample(), 0..40 * N).prop_map(|flat| {
        flat.chunks_exact(N)
            .map(|c| std::array::from_fn(|i| c[i]))
            .collect()
    })
}

/// The same pixels as planes.
fn planes<const N: usize>(px: &[[f32; N]]) -> [Vec<f32>; N] {
    std::array::from_fn(|i| px.iter().map(|s| s[i]).collect())
}

fn plane_refs<const N: usize>(planes: &[Vec<f32>; N]) -> [&[f32]; N] {
    planes.each_ref().map(|p| &p[..])
}

fn same(a: f32, b: f32) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

/// The fast path's reference: the per-pixel product, clipped (NaN anywhere → black) and
/// encoded with `srgb8_from_linear`, whose exactness test 1 establishes.
fn reference8<const N: usize>(set: &FoldedSet<N>, s: &[f32; N]) -> [u8; 3] {
    let rgb = set.linear_rgb(s);
    if rgb.iter().any(|v| v.is_nan()) {
        [0; 3]
    } else {
        rgb.map(srgb8_from_linear)
    }
}

fn planar_case<const N: usize>(
    set: &FoldedSet<N>,
    mapping: GamutMapping,
    px: &[[f32; N]],
) -> TestCaseResult {
    let display = &set.display();
    let n = px.len();
    let pl = planes(px);
    let samples = plane_refs(&pl);

    // Linear: bit for bit the per-pixel product, hence within its f32 budget of the exact sum
    // with these f32 weights (the budget is that of `f32_budget`; for finite samples only, as
    // documented).
    let mut lin = [0, 1, 2].map(|_| vec![f32::NAN; n]);
    let [r, g, b] = &mut lin;
    prop_assert_eq!(set.linear_rgb_planar(samples, [r, g, b]), Ok(()));
    for (p, s) in px.iter().enumerate() {
        let one = set.linear_rgb(s);
        for c in 0..3 {
            prop_assert!(same(lin[c][p], one[c]), "linear pixel {} channel {}", p, c);
            if s.iter().all(|v| v.is_finite()) && lin[c][p].is_finite() {
                let (exact, abs) =
                    set.weights()[c]
                        .iter()
                        .zip(s)
                        .fold((0.0, 0.0), |(e, a), (w, v)| {
                            let t = f64::from(*w) * f64::from(*v);
                            (e + t, a + t.abs())
                        });
                // f32_budget(N, Σ|w s|) is the documented accuracy of the product; the f64
                // reference's own rounding, (N + 1)·2⁻⁵³·Σ|w s|, is added to keep it rigorous.
                let budget = f32_budget(N, abs) + (N as f64 + 1.0) * f64::EPSILON * abs;
                prop_assert!((f64::from(lin[c][p]) - exact).abs() <= budget);
            }
        }
    }

    // Encoded: the fast path (sRGB curve, Clip) equals `reference8` exactly; every display and
    // mapping equals the per-pixel `encode_u8` exactly.
    let mut out = vec![[7u8; 3]; n];
    prop_assert_eq!(
        set.encode_u8_planar_to_interleaved(mapping, samples, &mut out),
        Ok(())
    );
    let fast = display.transfer() == TransferFunction::Srgb && mapping == GamutMapping::Clip;
    for (p, s) in px.iter().enumerate() {
        let one = set.encode_u8(mapping, s);
        if fast {
            prop_assert_eq!(out[p], reference8(set, s), "pixel {}", p);
        }
        // Every path equals `encode_u8` exactly; for the fast one that is what
        // SRGB8_MAX_ERROR = 0 says.
        prop_assert_eq!(out[p], one, "pixel {}", p);
    }
    other_layouts_case(set, mapping, px)
}

/// The planar-out 8-bit encoder and both 16-bit encoders against the per-pixel functions, every
/// pixel exactly; outputs start at values no pixel is expected to keep by chance everywhere.
fn other_layouts_case<const N: usize>(
    set: &FoldedSet<N>,
    mapping: GamutMapping,
    px: &[[f32; N]],
) -> TestCaseResult {
    let n = px.len();
    let pl = planes(px);
    let samples = plane_refs(&pl);
    let mut p8 = [0, 1, 2].map(|_| vec![7u8; n]);
    let [r, g, b] = &mut p8;
    prop_assert_eq!(set.encode_u8_planar(mapping, samples, [r, g, b]), Ok(()));
    let mut i16 = vec![[7u16; 3]; n];
    prop_assert_eq!(
        set.encode_u16_planar_to_interleaved(mapping, samples, &mut i16),
        Ok(())
    );
    let mut p16 = [0, 1, 2].map(|_| vec![7u16; n]);
    let [r, g, b] = &mut p16;
    prop_assert_eq!(set.encode_u16_planar(mapping, samples, [r, g, b]), Ok(()));
    for (p, s) in px.iter().enumerate() {
        let one8 = set.encode_u8(mapping, s);
        let one16 = set.encode_u16(mapping, s);
        prop_assert_eq!(
            [p8[0][p], p8[1][p], p8[2][p]],
            one8,
            "u8 planes, pixel {}",
            p
        );
        prop_assert_eq!(i16[p], one16, "u16 interleaved, pixel {}", p);
        prop_assert_eq!(
            [p16[0][p], p16[1][p], p16[2][p]],
            one16,
            "u16 planes, pixel {}",
            p
        );
    }
    Ok(())
}

/// The planar-out 8-bit encoder runs the interleaved loops on chunks of 64 pixels: images of
/// several chunks and a partial one, with NaN, ±Inf, subnormal, huge and negative samples among
/// random ones, on every baked display and mapping, give the per-pixel bytes.
#[test]
fn planar_out_encoders_equal_per_pixel_across_chunks() {
    let specials = [
        f32::NAN,
        f32::INFINITY,
        -f32::INFINITY,
        1e-45,
        -1e-45,
        f32::MIN_POSITIVE,
        f32::MAX,
        -f32::MAX,
        -1.0,
        0.0,
        -0.0,
        1.0,
    ];
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        if state.is_multiple_of(5) {
            specials[(state >> 8) as usize % specials.len()]
        } else {
            ((state >> 40) as f32) / (1u64 << 24) as f32 * 1.2 - 0.1
        }
    };
    for n in [0, 1, 63, 64, 65, 200] {
        let px4: Vec<[f32; 4]> = (0..n).map(|_| std::array::from_fn(|_| next())).collect();
        let px6: Vec<[f32; 6]> = (0..n).map(|_| std::array::from_fn(|_| next())).collect();
        for j in 0..4 {
            for mapping in MAPPINGS {
                other_layouts_case(&FOLDED_ROW2[j], mapping, &px4).unwrap();
                other_layouts_case(&FOLDED_ROW1[j], mapping, &px6).unwrap();
            }
        }
    }
}

/// The baked sets of Table 2 folded for each display, and both mappings.
#[test]
fn planar_equals_per_pixel_for_baked_sets() {
    // The sRGB display, Clip, three times out of four: the fast path.
    let choice = prop_oneof![3 => Just((0usize, 0usize)), 1 => (0usize..4, 0usize..2)];
    check(
        "planar, baked sets",
        (pixels::<4>(), pixels::<6>(), choice),
        |(px4, px6, (j, m))| {
            let mapping = MAPPINGS[m];
            planar_case(&FOLDED_ROW2[j], mapping, &px4)?;
            planar_case(&FOLDED_ROW1[j], mapping, &px6)
        },
    );
}

/// Weights of either sign and several magnitudes, for the sets of 8 and 16 wavelengths the
/// default scene does not bake.
fn weights<const N: usize>() -> impl Strategy<Value = [[f32; N]; 3]> {
    let w = prop_oneof![-1.0f32..=1.0, -1e-3f32..=1e-3, Just(0.0)];
    proptest::collection::vec(w, 3 * N)
        .prop_map(|flat| std::array::from_fn(|c| std::array::from_fn(|i| flat[c * N + i])))
}

#[test]
fn planar_equals_per_pixel_for_8_and_16_wavelengths() {
    check(
        "planar, N = 8 and 16",
        (
            weights::<8>(),
            pixels::<8>(),
            weights::<16>(),
            pixels::<16>(),
        ),
        |(w8, px8, w16, px16)| {
            let set8 = FoldedSet::new(
                std::array::from_fn(|i| 400.0 + 40.0 * i as f32),
                w8,
                Samples::Radiance,
                displays::SRGB,
            )
            .unwrap();
            let set16 = FoldedSet::new(
                std::array::from_fn(|i| 390.0 + 20.0 * i as f32),
                w16,
                Samples::Radiance,
                displays::SRGB,
            )
            .unwrap();
            planar_case(&set8, GamutMapping::Clip, &px8)?;
            planar_case(&set16, GamutMapping::Clip, &px16)
        },
    );
}

// ---------------------------------------------------------------------------------------------
// Input handling, length errors
// ---------------------------------------------------------------------------------------------

const NAN: f32 = f32::NAN;
const INF: f32 = f32::INFINITY;

/// Every kind of awkward sample, and a few ordinary ones.
const SPECIALS: [f32; 14] = [
    NAN,
    INF,
    -INF,
    f32::MAX,
    -f32::MAX,
    1e30,
    f32::MIN_POSITIVE / 2.0,
    1e-45,
    -1e-45,
    0.0,
    -0.0,
    -1.0,
    0.5,
    1.0,
];

#[test]
fn specials_give_what_the_docs_say() {
    let set = folded::TABLE2_ROW2_SRGB;
    // Every combination of two specials in the first two samples (the others 0.5): 196 pixels,
    // more than 12 chunks with a partial one.
    let px: Vec<[f32; 4]> = SPECIALS
        .iter()
        .flat_map(|&a| SPECIALS.iter().map(move |&b| [a, b, 0.5, 0.5]))
        .collect();
    let pl = planes(&px);
    let mut out = vec![[7u8; 3]; px.len()];
    set.encode_u8_planar_to_interleaved(GamutMapping::Clip, plane_refs(&pl), &mut out)
        .unwrap();
    for (p, s) in px.iter().enumerate() {
        let rgb = set.linear_rgb(s);
        if s.iter().any(|v| v.is_nan()) || rgb.iter().any(|v| v.is_nan()) {
            // A NaN sample, or infinities meeting as ∞ − ∞: black.
            assert_eq!(out[p], [0; 3], "{s:?}");
        }
        for c in 0..3 {
            if rgb[c] == INF && !rgb.iter().any(|v| v.is_nan()) {
                assert_eq!(out[p][c], 255, "{s:?}");
            }
            if rgb[c] == -INF || (rgb[c] <= 0.0 && !rgb[c].is_nan()) {
                assert_eq!(out[p][c], 0, "{s:?}");
            }
        }
        assert_eq!(out[p], reference8(&set, s), "{s:?}");
    }
    // Linear output: IEEE, as the per-pixel product.
    let mut lin = [0, 1, 2].map(|_| vec![0.0f32; px.len()]);
    let [r, g, b] = &mut lin;
    set.linear_rgb_planar(plane_refs(&pl), [r, g, b]).unwrap();
    for (p, s) in px.iter().enumerate() {
        let one = set.linear_rgb(s);
        assert!((0..3).all(|c| same(lin[c][p], one[c])), "{s:?}");
    }
}

#[test]
fn empty_inputs_are_fine() {
    let set = folded::TABLE2_ROW1_SRGB;
    let empty: [&[f32]; 6] = [&[]; 6];
    assert_eq!(
        set.encode_u8_planar_to_interleaved(GamutMapping::Clip, empty, &mut []),
        Ok(())
    );
    assert_eq!(
        set.linear_rgb_planar(empty, [&mut [], &mut [], &mut []]),
        Ok(())
    );
}

#[test]
fn length_mismatches_are_errors_and_write_nothing() {
    let set = folded::TABLE2_ROW2_SRGB;
    let pl: [Vec<f32>; 4] = std::array::from_fn(|_| vec![0.5; 20]);
    for (what, plane, len) in [
        ("short plane", 2, 19),
        ("long plane", 3, 21),
        ("empty plane", 0, 0),
    ] {
        let mut pl = pl.clone();
        pl[plane].resize(len, 0.5);
        let samples = plane_refs(&pl);
        // Named after plane 0: the first plane that differs from it.
        let expected = Err(Error::LengthMismatch {
            what: LengthOf::InputPlane,
            expected: pl[0].len(),
            got: if plane == 0 { 20 } else { len },
        });
        let mut out = vec![[9u8; 3]; 20];
        let r = set.encode_u8_planar_to_interleaved(GamutMapping::Clip, samples, &mut out);
        assert_eq!(r, expected, "{what}");
        assert!(out.iter().all(|o| *o == [9; 3]), "{what}");
        let mut lin = [0, 1, 2].map(|_| vec![-7.5f32; 20]);
        let [r, g, b] = &mut lin;
        assert_eq!(
            set.linear_rgb_planar(samples, [r, g, b]),
            expected,
            "{what}"
        );
        assert!(lin.iter().flatten().all(|v| *v == -7.5), "{what}");
    }
    // Outputs of the wrong length, the samples all 20 pixels long.
    let samples = plane_refs(&pl);
    for len in [0, 19, 21, 32] {
        let expected = |what| {
            Err(Error::LengthMismatch {
                what,
                expected: 20,
                got: len,
            })
        };
        let mut out = vec![[9u8; 3]; len];
        let r = set.encode_u8_planar_to_interleaved(GamutMapping::Clip, samples, &mut out);
        assert_eq!(r, expected(LengthOf::Output));
        assert!(out.iter().all(|o| *o == [9; 3]));
        for c in 0..3 {
            let mut lin = [0, 1, 2].map(|_| vec![-7.5f32; 20]);
            lin[c] = vec![-7.5; len];
            let [r, g, b] = &mut lin;
            assert_eq!(
                set.linear_rgb_planar(samples, [r, g, b]),
                expected(LengthOf::OutputPlane)
            );
            assert!(lin.iter().flatten().all(|v| *v == -7.5));
        }
    }
}

#[test]
fn new_layouts_refuse_length_mismatches_and_write_nothing() {
    let set = folded::TABLE2_ROW2_SRGB;
    let (a, short) = ([0.5f32; 70], [0.5f32; 69]);
    let mismatch = |what, got| {
        Err(Error::LengthMismatch {
            what,
            expected: 70,
            got,
        })
    };
    use LengthOf::{InputPlane, Output, OutputPlane};
    for mapping in MAPPINGS {
        // A short sample plane.
        let mut p8 = [[9u8; 70]; 3];
        let [r, g, b] = &mut p8;
        let got = set.encode_u8_planar(mapping, [&a, &a, &short, &a], [r, g, b]);
        assert_eq!(got, mismatch(InputPlane, 69));
        // A short output plane, after a full chunk: nothing is written, not even the first.
        let (mut r, mut g, mut b) = ([9u8; 70], [9u8; 70], [9u8; 69]);
        let got = set.encode_u8_planar(mapping, [&a; 4], [&mut r, &mut g, &mut b]);
        assert_eq!(got, mismatch(OutputPlane, 69));
        assert!(p8
            .iter()
            .flatten()
            .chain(&r)
            .chain(&g)
            .chain(&b)
            .all(|&v| v == 9));
        let mut i16 = [[9u16; 3]; 71];
        let got = set.encode_u16_planar_to_interleaved(mapping, [&a; 4], &mut i16);
        assert_eq!(got, mismatch(Output, 71));
        let (mut r, mut g, mut b) = ([9u16; 70], [9u16; 71], [9u16; 70]);
        let got = set.encode_u16_planar(mapping, [&a; 4], [&mut r, &mut g, &mut b]);
        assert_eq!(got, mismatch(OutputPlane, 71));
        assert!(i16
            .iter()
            .flatten()
            .chain(&r)
            .chain(&g)
            .chain(&b)
            .all(|&v| v == 9));
    }
}
