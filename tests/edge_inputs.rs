//! Deterministic tests of the documented input handling: NaN, ±Inf, subnormals, −0, negative and
//! huge values through every runtime entry point, the lookup-table checks, the transfer
//! functions' round trips and the error messages. Each test asserts what the doc comments in
//! `src/` promise.

// Channel loops index several parallel arrays (weights, references, outputs) by channel.
#![allow(clippy::needless_range_loop)]

mod common;

use common::MAPPINGS;
use spectral_quadrature::tables::{self, displays, folded, rules};
use spectral_quadrature::{
    ac1c2_from_xyz, f32_budget, quantize_u16, quantize_u8, xyz_from_ac1c2, Channel, ChannelLuts,
    Display, DisplayError, DynamicSet, Error, FoldedSet, GamutMapping, GaussRule, LengthOf, Point,
    Rgb, RuleStatus, TransferFunction, WavelengthSet, MAX_PRIMARIES_CONDITION,
};

const NAN: f32 = f32::NAN;
const INF: f32 = f32::INFINITY;
const SUB_HALF_MIN: f32 = f32::MIN_POSITIVE / 2.0;
/// The smallest positive subnormal, 2⁻¹⁴⁹ ≈ 1.4e-45.
const SUB_MIN: f32 = 1e-45;

/// Every kind of awkward input, and a few ordinary ones.
const SPECIALS: [f32; 18] = [
    NAN,
    INF,
    -INF,
    f32::MAX,
    -f32::MAX,
    1e30,
    -1e30,
    SUB_HALF_MIN,
    SUB_MIN,
    -SUB_MIN,
    0.0,
    -0.0,
    -1.0,
    0.25,
    0.5,
    1.0,
    2.0,
    f32::MIN_POSITIVE,
];

/// A well-formed lookup table for each channel (first entry 0, last 1), as the tests need them.
const LUT_R: &[f32] = &[0.0, 0.35, 0.55, 0.7, 0.82, 0.92, 1.0];
const LUT_G: &[f32] = &[0.0, 0.5, 1.0];
const LUT_B: &[f32] = &[0.0, 0.2, 0.2, 0.6, 1.0];

fn luts() -> ChannelLuts {
    ChannelLuts::new([LUT_R, LUT_G, LUT_B]).expect("valid tables")
}

/// Every transfer-function variant, the lookup table included.
fn transfers() -> [TransferFunction; 6] {
    [
        TransferFunction::Linear,
        TransferFunction::Srgb,
        TransferFunction::Gamma(2.2),
        TransferFunction::Gamma(2.4),
        TransferFunction::Gamma(0.5),
        TransferFunction::Lut(luts()),
    ]
}

/// The standard displays, and sRGB driven through the lookup tables.
fn all_displays() -> Vec<Display> {
    let mut v = displays::ALL.to_vec();
    v.push(displays::SRGB.with_transfer(TransferFunction::Lut(luts())));
    v
}

fn in_unit(v: f32) -> bool {
    (0.0..=1.0).contains(&v)
}

/// `(Σ w_i s_i, Σ |w_i s_i|)` in f64, weights as f32.
fn dot64(w: &[f32], s: &[f32]) -> (f64, f64) {
    w.iter().zip(s).fold((0.0, 0.0), |(sum, abs), (w, s)| {
        let p = f64::from(*w) * f64::from(*s);
        (sum + p, abs + p.abs())
    })
}

// ---------------------------------------------------------------------------------------------
// WavelengthSet::ac1c2 and FoldedSet::linear_rgb: IEEE arithmetic
// ---------------------------------------------------------------------------------------------

/// Checks the IEEE promises of a 3×N product `f` over `weights` with one special sample at a
/// time: a NaN sample gives NaN in every channel whose weight for it is non-zero; a lone ±Inf
/// gives ±Inf (sign of w·s) in those channels.
fn ieee_one_special<const N: usize>(
    name: &str,
    weights: &[[f32; N]; 3],
    f: impl Fn(&[f32; N]) -> [f32; 3],
) {
    for i in 0..N {
        let mut s = [0.5f32; N];
        s[i] = NAN;
        let out = f(&s);
        for c in 0..3 {
            if weights[c][i] != 0.0 {
                assert!(
                    out[c].is_nan(),
                    "{name}: NaN at {i} must make channel {c} NaN: {out:?}"
                );
            }
        }
        for sign in [1.0f32, -1.0] {
            s[i] = sign * INF;
            let out = f(&s);
            for c in 0..3 {
                let w = weights[c][i];
                if w != 0.0 {
                    let expected = if (w > 0.0) == (sign > 0.0) { INF } else { -INF };
                    assert_eq!(out[c], expected, "{name}: {}Inf at {i}, channel {c}", sign);
                }
            }
        }
    }
}

#[test]
fn ac1c2_nan_and_inf_samples_propagate_in_the_channels_that_use_them() {
    ieee_one_special("TABLE2_ROW1", &tables::TABLE2_ROW1.weights(), |s| {
        tables::TABLE2_ROW1.ac1c2(s)
    });
    ieee_one_special("TABLE2_ROW2", &tables::TABLE2_ROW2.weights(), |s| {
        tables::TABLE2_ROW2.ac1c2(s)
    });
    ieee_one_special("A_3", &rules::A_3.weights(), |s| rules::A_3.ac1c2(s));
    ieee_one_special("C1_2", &rules::C1_2.weights(), |s| rules::C1_2.ac1c2(s));
    ieee_one_special("C2_1", &rules::C2_1.weights(), |s| rules::C2_1.ac1c2(s));
    // xyz: the same, one matrix later (every XYZ row mixes all of A, C1, C2, so any NaN
    // channel reaches all three).
    let mut s = [0.5f32; 6];
    s[3] = NAN;
    assert!(tables::TABLE2_ROW1.xyz(&s).iter().all(|v| v.is_nan()));
}

#[test]
fn ac1c2_special_samples_poison_every_channel() {
    // Documented: the sum runs over all N samples, and 0 · NaN = 0 · ∞ = NaN, so a NaN sample
    // makes every channel NaN and an infinite one every channel ±Inf or NaN, even where its
    // weight is 0.
    fn check<const N: usize>(name: &str, set: &WavelengthSet<N>) {
        for i in 0..N {
            for special in [NAN, INF, -INF] {
                let mut s = [0.5f32; N];
                s[i] = special;
                let out = set.ac1c2(&s);
                for (c, v) in out.iter().enumerate() {
                    if special.is_nan() {
                        assert!(v.is_nan(), "{name}: NaN at {i}, channel {c} = {v}");
                    } else {
                        assert!(
                            !v.is_finite(),
                            "{name}: {special} at {i}, channel {c} = {v}"
                        );
                    }
                    if set.weights()[c][i] == 0.0 {
                        assert!(
                            v.is_nan(),
                            "{name}: 0 · {special} at {i} must be NaN in channel {c}"
                        );
                    }
                }
            }
        }
    }
    check("A_3", &rules::A_3);
    check("C2_1", &rules::C2_1);
    check("TABLE2_ROW1", &tables::TABLE2_ROW1);
}

#[test]
fn linear_rgb_nan_and_inf_samples_propagate() {
    for (k, set) in [folded::TABLE2_ROW1_SRGB, folded::TABLE2_ROW1_REC2020]
        .iter()
        .enumerate()
    {
        // Every folded weight is non-zero, so a NaN sample reaches all three channels.
        assert!(set.weights().iter().flatten().all(|&w| w != 0.0));
        ieee_one_special(&format!("ROW1 folded {k}"), &set.weights(), |s| {
            set.linear_rgb(s)
        });
    }
    for set in [
        folded::TABLE2_ROW2_SRGB,
        folded::TABLE2_ROW2_DISPLAY_P3,
        folded::TABLE2_ROW2_MEYER_1987,
    ] {
        ieee_one_special("ROW2 folded", &set.weights(), |s| set.linear_rgb(s));
        let out = set.linear_rgb(&[0.5, NAN, 0.5, 0.5]);
        assert!(out.iter().all(|v| v.is_nan()), "{out:?}");
    }
}

#[test]
fn infinities_of_both_signs_give_nan() {
    // C1 of TABLE2_ROW1: +32.2 at 490.8 nm and −46.5 at 631.4 nm (indices 2 and 4).
    let w = tables::TABLE2_ROW1.weights()[1];
    assert!(w[2] > 0.0 && w[4] < 0.0);
    let out = tables::TABLE2_ROW1.ac1c2(&[0.0, 0.0, INF, 0.0, INF, 0.0]);
    assert!(out[1].is_nan(), "+Inf·w⁺ + Inf·w⁻ = NaN: {out:?}");
    // A sees +Inf at 631.4 nm only if its weight there is non-zero: it is 0, A uses 632.3 nm.
    let out = tables::TABLE2_ROW1.ac1c2(&[0.0, INF, 0.0, 0.0, 0.0, -INF]);
    assert!(out[0].is_nan(), "A: +Inf·16.1 + (−Inf)·18.2 = NaN: {out:?}");
}

#[test]
fn huge_samples_overflow_to_inf_or_nan_and_large_finite_ones_stay_accurate() {
    // f32::MAX: every A weight of TABLE2_ROW1 exceeds 1, so each non-zero product is +Inf.
    let s = [f32::MAX; 6];
    let out = tables::TABLE2_ROW1.ac1c2(&s);
    assert_eq!(out[0], INF, "{out:?}");
    assert!(out[1].is_nan(), "C1 meets +Inf and −Inf: {out:?}");
    assert_eq!(out[2], INF, "C2: 55.2·MAX: {out:?}");
    let out = tables::TABLE2_ROW1.ac1c2(&s.map(|v| -v));
    assert_eq!(out[0], -INF);
    // Folded weights below 1 do not overflow on their own: R of ROW2 sRGB at 631 nm is 1.04
    // (overflows), G and B there are −0.038 and −0.095 (finite, to f32_budget).
    let set = folded::TABLE2_ROW2_SRGB;
    let out = set.linear_rgb(&[0.0, 0.0, 0.0, f32::MAX]);
    assert_eq!(out[0], INF, "{out:?}");
    for c in 1..3 {
        let (exact, abs) = dot64(&set.weights()[c], &[0.0, 0.0, 0.0, f32::MAX]);
        assert!(
            (f64::from(out[c]) - exact).abs() <= f32_budget(4, abs),
            "{out:?}"
        );
    }
    // 1e30 (and ±1e30 mixed): finite, within the stated budget of the sum with the f32 weights.
    for s in [[1e30f32; 6], [1e30, -1e30, 1e30, -1e30, 1e30, -1e30]] {
        let out = tables::TABLE2_ROW1.ac1c2(&s);
        for c in 0..3 {
            let (exact, abs) = dot64(&tables::TABLE2_ROW1.weights()[c], &s);
            assert!(out[c].is_finite());
            assert!(
                (f64::from(out[c]) - exact).abs() <= f32_budget(6, abs),
                "channel {c}: {} vs {exact}",
                out[c]
            );
        }
    }
}

/// A 3×N product over subnormal / tiny samples against the f64 product with the same f32 weights,
/// within `f32_budget` (whose N · 2⁻¹⁵⁰ term is exactly for products that underflow).
fn subnormal_case<const N: usize>(
    name: &str,
    weights: &[[f32; N]; 3],
    f: impl Fn(&[f32; N]) -> [f32; 3],
) {
    let patterns: [[f32; 4]; 4] = [
        [SUB_HALF_MIN; 4],
        [SUB_MIN; 4],
        [SUB_MIN, SUB_HALF_MIN, -SUB_MIN, f32::MIN_POSITIVE],
        [-SUB_HALF_MIN, 3e-39, 0.0, -0.0],
    ];
    for p in patterns {
        let s: [f32; N] = std::array::from_fn(|i| p[i % 4]);
        let out = f(&s);
        for c in 0..3 {
            let (exact, abs) = dot64(&weights[c], &s);
            let err = (f64::from(out[c]) - exact).abs();
            assert!(out[c].is_finite());
            assert!(
                err <= f32_budget(N, abs),
                "{name} {s:?} channel {c}: {:e} vs {exact:e}, error {err:e} > {:e}",
                out[c],
                f32_budget(N, abs)
            );
        }
    }
}

#[test]
fn subnormal_samples_are_used_as_they_are() {
    subnormal_case("TABLE2_ROW1", &tables::TABLE2_ROW1.weights(), |s| {
        tables::TABLE2_ROW1.ac1c2(s)
    });
    subnormal_case("TABLE2_ROW2", &tables::TABLE2_ROW2.weights(), |s| {
        tables::TABLE2_ROW2.ac1c2(s)
    });
    subnormal_case("A_16", &rules::A_16.weights(), |s| rules::A_16.ac1c2(s));
    for set in [folded::TABLE2_ROW1_SRGB, folded::TABLE2_ROW1_MEYER_1987] {
        subnormal_case("ROW1 folded", &set.weights(), |s| set.linear_rgb(s));
    }
    // Not flushed to zero: 72.4 · 2⁻¹²⁶ / 2 is a normal number.
    let out = rules::A_3.ac1c2(&[0.0, SUB_HALF_MIN, 0.0]);
    assert!(out[0] > 30.0 * f32::MIN_POSITIVE, "{out:?}");
}

#[test]
fn negative_and_signed_zero_samples() {
    fn check<const N: usize>(name: &str, f: impl Fn(&[f32; N]) -> [f32; 3]) {
        // −0 everywhere: zero out (either sign).
        assert_eq!(f(&[-0.0; N]), [0.0; 3], "{name}");
        // Round-to-nearest is symmetric: negating every sample negates every output exactly.
        let s: [f32; N] = std::array::from_fn(|i| 0.37 + 1.9 * i as f32);
        let neg = f(&s.map(|v| -v));
        let pos = f(&s);
        assert_eq!(neg, pos.map(|v| -v), "{name}");
    }
    check::<6>("TABLE2_ROW1", |s| tables::TABLE2_ROW1.ac1c2(s));
    check::<4>("TABLE2_ROW2", |s| tables::TABLE2_ROW2.ac1c2(s));
    check::<6>("ROW1 sRGB", |s| folded::TABLE2_ROW1_SRGB.linear_rgb(s));
    check::<4>("ROW2 Rec. 2020", |s| {
        folded::TABLE2_ROW2_REC2020.linear_rgb(s)
    });
}

#[test]
fn matrix_helpers_propagate_ieee_values() {
    assert!(xyz_from_ac1c2([NAN, 0.0, 0.0]).iter().all(|v| v.is_nan()));
    assert!(ac1c2_from_xyz([0.0, NAN, 0.0]).iter().all(|v| v.is_nan()));
    // +Inf in X: every row's X coefficient is non-zero; signs follow the coefficients.
    let out = ac1c2_from_xyz([INF, 1.0, 1.0]);
    for r in 0..3 {
        let expected = if tables::XYZ_TO_AC1C2[r][0] > 0.0 {
            INF
        } else {
            -INF
        };
        assert_eq!(out[r], expected);
    }
    let d = &displays::SRGB;
    assert!(d
        .linear_from_xyz([NAN, 0.0, 0.0])
        .iter()
        .all(|v| v.is_nan()));
    assert_eq!(d.linear_from_xyz([0.0, INF, 0.0]), [-INF, INF, -INF]);
    assert!(d
        .xyz_from_linear([INF, -INF, 0.0])
        .iter()
        .all(|v| v.is_nan()));
}

// ---------------------------------------------------------------------------------------------
// Display: map_gamut / encode / encode_u8 / encode_u16
// ---------------------------------------------------------------------------------------------

/// Every triple of SPECIALS (18³ = 5832) for every display and mapping: the output of
/// `map_gamut` and `encode` is in 0..=1 (never NaN), NaN anywhere gives black, and the
/// quantized forms are the quantized `encode`.
#[test]
fn every_special_triple_maps_into_the_unit_cube() {
    for display in all_displays() {
        for mapping in MAPPINGS {
            for &r in &SPECIALS {
                for &g in &SPECIALS {
                    for &b in &SPECIALS {
                        let rgb = [r, g, b];
                        let m = display.map_gamut(mapping, rgb);
                        let e = display.encode(mapping, rgb);
                        assert!(
                            m.iter().all(|&v| in_unit(v)),
                            "{} {mapping:?} {rgb:?} → {m:?}",
                            display.name()
                        );
                        assert!(
                            e.iter().all(|&v| in_unit(v)),
                            "{} {mapping:?} {rgb:?} → {e:?}",
                            display.name()
                        );
                        if rgb.iter().any(|v| v.is_nan()) {
                            assert_eq!(m, [0.0; 3], "{} {mapping:?} {rgb:?}", display.name());
                        }
                        // The quantized encoders are the transfer function's own, channel
                        // by channel, on the gamut-mapped colour.
                        let (e8, e16) = (
                            display.encode_u8(mapping, rgb),
                            display.encode_u16(mapping, rgb),
                        );
                        for c in Rgb::ALL {
                            let i = c.index();
                            assert_eq!(e8[i], display.transfer().encode_u8(c, m[i]));
                            assert_eq!(e16[i], display.transfer().encode_u16(c, m[i]));
                            // They round the exact curve (8 bits) or the f32 curve (16 bits);
                            // `encode` quantized rounds twice: one step apart at most.
                            assert!(e8[i].abs_diff(quantize_u8(e[i])) <= 1);
                            assert!(e16[i].abs_diff(quantize_u16(e[i])) <= 1);
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn nan_anywhere_encodes_as_black_on_the_standard_displays() {
    for display in displays::ALL {
        for mapping in MAPPINGS {
            for pos in 0..3 {
                for other in [0.5f32, INF, -INF, 2.0, -1.0] {
                    let mut rgb = [other; 3];
                    rgb[pos] = NAN;
                    assert_eq!(display.map_gamut(mapping, rgb), [0.0; 3]);
                    assert_eq!(display.encode(mapping, rgb), [0.0; 3]);
                    assert_eq!(
                        display.encode_u8(mapping, rgb),
                        [0; 3],
                        "{} {mapping:?} {rgb:?}",
                        display.name()
                    );
                    assert_eq!(display.encode_u16(mapping, rgb), [0; 3]);
                }
            }
        }
    }
    // Through a folded set: a NaN sample → black.
    let set = folded::TABLE2_ROW1_SRGB;
    for mapping in MAPPINGS {
        assert_eq!(
            set.encode_u8(mapping, &[0.5, 0.5, NAN, 0.5, 0.5, 0.5]),
            [0; 3]
        );
        assert_eq!(set.encode_u16(mapping, &[NAN; 6]), [0; 3]);
    }
}

#[test]
fn lut_with_offsets_still_maps_nan_and_out_of_range_to_0_and_1() {
    let offset = ChannelLuts::new([&[0.1, 0.5, 0.9], &[0.1, 0.9], &[0.05, 0.95]]).unwrap();
    let tf = TransferFunction::Lut(offset);
    for c in Rgb::ALL {
        assert_eq!(tf.encode(c, NAN), 0.0, "channel {c:?}: NaN");
        assert_eq!(tf.encode(c, -1.0), 0.0, "channel {c:?}: −1");
        assert_eq!(tf.encode(c, 0.0), 0.0, "channel {c:?}: 0");
        assert_eq!(tf.encode(c, 2.0), 1.0, "channel {c:?}: 2");
    }
    let display = displays::SRGB.with_transfer(tf);
    assert_eq!(
        display.encode_u8(GamutMapping::Clip, [NAN, 0.5, 0.5]),
        [0; 3]
    );
}

#[test]
fn clip_handles_infinities_huge_subnormal_and_negative_values() {
    for display in all_displays() {
        let m = |rgb| display.map_gamut(GamutMapping::Clip, rgb);
        assert_eq!(m([INF, -INF, 0.5]), [1.0, 0.0, 0.5]);
        assert_eq!(m([f32::MAX, -f32::MAX, 1e30]), [1.0, 0.0, 1.0]);
        assert_eq!(m([-1e30, -1.0, 2.0]), [0.0, 0.0, 1.0]);
        assert_eq!(m([-0.0, 0.0, 1.0]), [0.0, 0.0, 1.0]);
        // Subnormals are inside 0..=1 and kept as they are.
        let sub = m([SUB_MIN, SUB_HALF_MIN, -SUB_MIN]);
        assert_eq!(sub[0].to_bits(), SUB_MIN.to_bits());
        assert_eq!(sub[1].to_bits(), SUB_HALF_MIN.to_bits());
        assert_eq!(sub[2], 0.0);
        assert_eq!(
            display.encode_u8(GamutMapping::Clip, [INF, 0.0, -INF])[0],
            255
        );
        assert_eq!(
            display.encode_u16(GamutMapping::Clip, [INF, 0.0, -INF])[0],
            65535
        );
    }
    for display in displays::ALL {
        assert_eq!(
            display.encode_u8(GamutMapping::Clip, [INF, 0.0, -INF]),
            [255, 0, 0]
        );
        assert_eq!(
            display.encode_u16(GamutMapping::Clip, [1e30, SUB_MIN, -1e30]),
            [65535, 0, 0]
        );
    }
}

#[test]
fn preserve_a_clips_infinities_and_sends_huge_colours_to_white_or_black() {
    for display in displays::ALL {
        let p = |rgb| display.map_gamut(GamutMapping::PreserveA, rgb);
        // An infinite channel: clipped as with Clip.
        assert_eq!(p([INF, 0.5, -INF]), [1.0, 0.5, 0.0], "{}", display.name());
        assert_eq!(p([-INF, -INF, 0.25]), [0.0, 0.0, 0.25]);
        assert_eq!(p([INF, 2.0, -3.0]), [1.0, 1.0, 0.0]);
        // Huge finite: A far above white → white; far below 0 → black.
        assert_eq!(p([f32::MAX; 3]), [1.0; 3]);
        assert_eq!(p([1e30, 0.0, 0.0]), [1.0; 3]);
        assert_eq!(p([-1e30, 0.0, 0.0]), [0.0; 3]);
        assert_eq!(p([-f32::MAX; 3]), [0.0; 3]);
        // Green carries most of A on every display: (1e30, −1e30, 0) has A < 0.
        assert_eq!(p([1e30, -1e30, 0.0]), [0.0; 3]);
        assert_eq!(p([-1e30, 1e30, 0.0]), [1.0; 3]);
        // Negative and zero A: black.
        assert_eq!(p([-1.0, -1.0, -1.0]), [0.0; 3]);
        assert_eq!(p([-0.0; 3]), [0.0; 3]);
        assert_eq!(p([0.0; 3]), [0.0; 3]);
        // Subnormal greys: black or a subnormal grey, never more.
        for v in [SUB_MIN, SUB_HALF_MIN] {
            let out = p([v; 3]);
            assert!(
                out.iter().all(|&c| (0.0..=2.0 * v).contains(&c)),
                "{v:e} → {out:?}"
            );
        }
        // White and brighter.
        assert_eq!(p([1.0; 3]), [1.0; 3]);
        assert_eq!(p([2.0; 3]), [1.0; 3]);
        assert_eq!(
            display.encode_u8(GamutMapping::PreserveA, [INF, 0.5, -INF])[0],
            255
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Transfer functions
// ---------------------------------------------------------------------------------------------

#[test]
fn transfer_functions_handle_nan_signs_and_range() {
    for tf in transfers() {
        for c in Rgb::ALL {
            for f in [
                TransferFunction::encode as fn(&TransferFunction, Rgb, f32) -> f32,
                TransferFunction::decode,
            ] {
                assert_eq!(f(&tf, c, NAN), 0.0, "{tf:?} c{c:?}: NaN");
                assert_eq!(f(&tf, c, -NAN), 0.0, "{tf:?} c{c:?}: −NaN");
                for low in [0.0, -0.0, -SUB_MIN, -1.0, -1e30, -f32::MAX, -INF] {
                    assert_eq!(f(&tf, c, low), 0.0, "{tf:?} c{c:?}: {low}");
                }
                for high in [1.0, 1.0 + f32::EPSILON, 2.0, 1e30, f32::MAX, INF] {
                    assert_eq!(f(&tf, c, high), 1.0, "{tf:?} c{c:?}: {high}");
                }
                for &x in &SPECIALS {
                    assert!(in_unit(f(&tf, c, x)), "{tf:?} c{c:?}: {x}");
                }
            }
        }
    }
}

#[test]
fn srgb_encodes_one_and_above_as_one() {
    for high in [1.0f32, 2.0, f32::MAX, INF] {
        assert_eq!(
            TransferFunction::Srgb.encode(Rgb::R, high),
            1.0,
            "encode({high})"
        );
        #[cfg(feature = "micromath")]
        assert_eq!(
            TransferFunction::Srgb.encode_fast(Rgb::R, high),
            1.0,
            "encode_fast({high})"
        );
    }
}

#[test]
fn srgb_one_and_above_quantize_to_full_scale() {
    for high in [1.0f32, 2.0, f32::MAX, INF] {
        let e = TransferFunction::Srgb.encode(Rgb::R, high);
        assert_eq!(quantize_u8(e), 255);
        assert_eq!(quantize_u16(e), 65535);
    }
}

#[test]
fn transfer_outputs_stay_in_the_unit_interval_over_every_binade() {
    // Every 4099th bit pattern of the non-negative f32 (and their negatives): all binades,
    // subnormals, the values just below 1 and above.
    for tf in transfers() {
        for bits in (0..=INF.to_bits()).step_by(4099) {
            for x in [f32::from_bits(bits), -f32::from_bits(bits)] {
                for c in Rgb::ALL {
                    assert!(in_unit(tf.encode(c, x)), "{tf:?} encode({x:e})");
                    assert!(in_unit(tf.decode(c, x)), "{tf:?} decode({x:e})");
                }
            }
        }
    }
}

#[test]
fn subnormals_encode_below_1e_37_for_linear_srgb_and_lut() {
    // "subnormals give 0 or their linear-segment image (sRGB), both below 1e-37".
    for tf in [
        TransferFunction::Linear,
        TransferFunction::Srgb,
        TransferFunction::Lut(luts()),
        TransferFunction::Gamma(0.5),
    ] {
        for x in [SUB_MIN, SUB_HALF_MIN, 3e-39] {
            for c in Rgb::ALL {
                let e = tf.encode(c, x);
                assert!((0.0..1e-37).contains(&e), "{tf:?} encode({x:e}) = {e:e}");
            }
        }
    }
    // sRGB: exactly the linear segment, 12.92 · x.
    assert_eq!(
        TransferFunction::Srgb.encode(Rgb::R, SUB_HALF_MIN),
        12.92 * SUB_HALF_MIN
    );
}

#[test]
fn subnormals_encode_as_the_tiny_numbers_they_are() {
    // Documented: Gamma(γ) gives x^(1/γ) for subnormal x (e.g. about 4e-21 for 1e-45 at 2.2):
    // positive, finite, tiny, and libm's f64 power rounded once to f32.
    for g in [2.2f32, 2.4, 1.8] {
        for x in [SUB_MIN, SUB_HALF_MIN] {
            let e = TransferFunction::Gamma(g).encode(Rgb::R, x);
            let expected = libm::pow(f64::from(x), 1.0 / f64::from(g)) as f32;
            assert_eq!(e, expected, "Gamma({g}).encode({x:e})");
            assert!(e > 0.0 && e < 1e-15, "Gamma({g}).encode({x:e}) = {e:e}");
        }
    }
    let e = TransferFunction::Gamma(2.2).encode(Rgb::R, 1e-45);
    assert!((3e-21..5e-21).contains(&e), "{e:e}");
}

#[test]
fn non_positive_or_non_finite_gamma_is_linear() {
    let x_values: Vec<f32> = SPECIALS
        .iter()
        .copied()
        .chain((0..=1000).map(|k| k as f32 / 1000.0))
        .collect();
    for g in [NAN, -NAN, -1.0, 0.0, -0.0, INF, -INF, -SUB_MIN] {
        let tf = TransferFunction::Gamma(g);
        for &x in &x_values {
            let lin = TransferFunction::Linear;
            assert_eq!(
                tf.encode(Rgb::R, x).to_bits(),
                lin.encode(Rgb::R, x).to_bits(),
                "Gamma({g}) encode({x})"
            );
            assert_eq!(
                tf.decode(Rgb::G, x).to_bits(),
                lin.decode(Rgb::G, x).to_bits(),
                "Gamma({g}) decode({x})"
            );
        }
    }
    // And a positive gamma is not linear (the test above could not pass vacuously).
    assert_ne!(TransferFunction::Gamma(2.2).encode(Rgb::R, 0.5), 0.5);
    // A positive subnormal γ is finite and positive: a real (if extreme) power, not Linear.
    assert_eq!(TransferFunction::Gamma(SUB_MIN).encode(Rgb::R, 0.5), 0.0);
}

#[test]
fn lut_interpolates_per_channel_and_decodes_flat_stretches_to_their_start() {
    let tf = TransferFunction::Lut(luts());
    // LUT_G = [0, 0.5, 1]: linear 0.25 → 0.25 (halfway to the middle entry).
    assert_eq!(tf.encode(Rgb::G, 0.25), 0.25);
    assert_eq!(tf.encode(Rgb::G, 0.5), 0.5);
    // LUT_R entry k at k/6.
    for (k, &t) in LUT_R.iter().enumerate() {
        let x = k as f32 / 6.0;
        assert!(
            (tf.encode(Rgb::R, x) - t).abs() <= 2.0 * f32::EPSILON,
            "R entry {k}"
        );
    }
    // LUT_B = [0, 0.2, 0.2, 0.6, 1] at linear 0, 1/4, 2/4, 3/4, 1: 0.2 is flat over [1/4, 1/2];
    // decode gives the lowest linear value of the stretch.
    assert_eq!(tf.decode(Rgb::B, 0.2), 0.25);
    assert!(tf.decode(Rgb::B, 0.2000001) >= 0.5);
    // ChannelLuts::table
    let l = luts();
    assert_eq!(l.table(Rgb::R), LUT_R);
    assert_eq!(l.table(Rgb::G), LUT_G);
    assert_eq!(l.table(Rgb::B), LUT_B);
}

/// Measures `max |decode(encode(x)) − x| / max(x, floor)` and `max |encode(decode(e)) − e|`.
fn round_trip_errors(tf: TransferFunction, c: Rgb, floor: f32) -> (f32, f32) {
    let one = 1.0f32.to_bits();
    let mut xs: Vec<f32> = (0..=one).step_by(1021).map(f32::from_bits).collect();
    xs.extend((0..=65535).map(|k| k as f32 / 65535.0));
    let (mut rel, mut abs) = (0.0f32, 0.0f32);
    for &x in &xs {
        let back = tf.decode(c, tf.encode(c, x));
        rel = rel.max((back - x).abs() / x.max(floor));
        let e = x;
        abs = abs.max((tf.encode(c, tf.decode(c, e)) - e).abs());
    }
    (rel, abs)
}

#[test]
fn round_trips() {
    let eps = f32::EPSILON;
    // Bounds: the largest error of the deterministic sweep below (every 1021st f32 bit pattern
    // in 0..=1 and every u16 level), measured with this libm and rounded up by ~1.3-2× for
    // another libm's powf (which may differ by an ulp).
    //
    // sRGB, decode(encode(x)) relative to x: measured 2.76 ε (libm's powf is within 1 ulp;
    // 1.055·p − 0.055 cancels by up to 2.4× at the segment break; decode's power 2.4 multiplies
    // relative error by 2.4). Asserted 4 ε (floor 1e-30: the linear segment is relative too).
    // encode(decode(e)) absolute: measured 1.0 ε; asserted 2 ε.
    let (rel, abs) = round_trip_errors(TransferFunction::Srgb, Rgb::R, 1e-30);
    eprintln!(
        "sRGB round trip: max rel {:.3} ε, max abs (encoded) {:.3} ε",
        rel / eps,
        abs / eps
    );
    assert!(rel <= 4.0 * eps, "sRGB decode∘encode: {} ε", rel / eps);
    assert!(abs <= 2.0 * eps, "sRGB encode∘decode: {} ε", abs / eps);
    // Gamma(2.2): two powf (≤ 1 ulp each, the second scaled by γ in relative terms) and the
    // rounding of 1/γ (relative u on the exponent: |ln x|·u/γ, growing as x → 0, hence the floor
    // 1e-6 below which the error is taken as absolute). Measured 3.18 ε relative and 0.5 ε for
    // encode(decode(e)); asserted 5 ε and 1 ε.
    let (rel, abs) = round_trip_errors(TransferFunction::Gamma(2.2), Rgb::R, 1e-6);
    eprintln!(
        "Gamma(2.2) round trip: max rel {:.3} ε, max abs {:.3} ε",
        rel / eps,
        abs / eps
    );
    assert!(rel <= 5.0 * eps, "Gamma decode∘encode: {} ε", rel / eps);
    assert!(abs <= eps, "Gamma encode∘decode: {} ε", abs / eps);
    // LUT: piecewise linear and its exact inverse; errors are the roundings of pos, f, the
    // interpolation and the division, over the segment's slope (LUT_R's smallest is 0.48 per
    // unit). Measured 1.0 ε absolute (linear) and 0.5 ε (encoded); asserted 2 ε and 1 ε.
    let lut = TransferFunction::Lut(luts());
    let (rel, abs) = round_trip_errors(lut, Rgb::R, 1.0);
    eprintln!(
        "LUT round trip: max abs {:.3} ε (linear), {:.3} ε (encoded)",
        rel / eps,
        abs / eps
    );
    assert!(rel <= 2.0 * eps, "LUT decode∘encode: {} ε", rel / eps);
    assert!(abs <= eps, "LUT encode∘decode: {} ε", abs / eps);
    // Linear: exact.
    let (rel, abs) = round_trip_errors(TransferFunction::Linear, Rgb::R, 1e-30);
    assert_eq!((rel, abs), (0.0, 0.0));
}

// ---------------------------------------------------------------------------------------------
// Quantization
// ---------------------------------------------------------------------------------------------

#[test]
fn quantize_handles_special_values() {
    for (x, q8, q16) in [
        (NAN, 0u8, 0u16),
        (-NAN, 0, 0),
        (INF, 255, 65535),
        (-INF, 0, 0),
        (f32::MAX, 255, 65535),
        (-f32::MAX, 0, 0),
        (1e30, 255, 65535),
        (-1.0, 0, 0),
        (-0.0, 0, 0),
        (0.0, 0, 0),
        (SUB_MIN, 0, 0),
        (SUB_HALF_MIN, 0, 0),
        (1.0, 255, 65535),
        (1.5, 255, 65535),
        (0.5, 128, 32768),
    ] {
        assert_eq!(quantize_u8(x), q8, "quantize_u8({x})");
        assert_eq!(quantize_u16(x), q16, "quantize_u16({x})");
    }
}

#[test]
fn quantize_rounds_to_nearest() {
    // Every level k: k/L → k, and just inside either side of the midpoints (k ± 0.49)/L.
    for k in 0..=255u32 {
        let l = 255.0f64;
        assert_eq!(quantize_u8((f64::from(k) / l) as f32), k as u8);
        if k < 255 {
            assert_eq!(quantize_u8(((f64::from(k) + 0.49) / l) as f32), k as u8);
            assert_eq!(quantize_u8(((f64::from(k) + 0.51) / l) as f32), k as u8 + 1);
        }
    }
    for k in 0..=65535u32 {
        let l = 65535.0f64;
        assert_eq!(quantize_u16((f64::from(k) / l) as f32), k as u16);
        if k < 65535 {
            assert_eq!(quantize_u16(((f64::from(k) + 0.49) / l) as f32), k as u16);
            assert_eq!(
                quantize_u16(((f64::from(k) + 0.51) / l) as f32),
                k as u16 + 1
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// ChannelLuts::new
// ---------------------------------------------------------------------------------------------

#[test]
fn channel_luts_reject_bad_tables_and_name_the_channel() {
    let good: &'static [f32] = &[0.0, 0.5, 1.0];
    let bad: [&'static [f32]; 12] = [
        &[],
        &[0.5],
        &[0.0, NAN],
        &[NAN, 1.0],
        &[0.0, INF],
        &[-INF, 1.0],
        &[0.0, 0.6, 0.5, 1.0],
        &[1.0, 0.0],
        &[-0.1, 1.0],
        &[-SUB_MIN, 1.0],
        &[0.0, 1.0 + f32::EPSILON],
        &[0.0, 2.0],
    ];
    for table in bad {
        for c in 0..3 {
            let mut tables = [good; 3];
            tables[c] = table;
            assert_eq!(
                ChannelLuts::new(tables),
                Err(Error::InvalidLut {
                    channel: Rgb::ALL[c]
                }),
                "{table:?} in channel {c}"
            );
        }
    }
    // Accepted: two entries, flat stretches, offsets, −0 and subnormal entries, constants.
    let ok: [&'static [f32]; 6] = [
        &[0.0, 1.0],
        &[0.0, 0.5, 0.5, 1.0],
        &[0.1, 0.9],
        &[-0.0, 1.0],
        &[SUB_MIN, 1e-40, 1.0],
        &[0.3, 0.3],
    ];
    for table in ok {
        for c in 0..3 {
            let mut tables = [good; 3];
            tables[c] = table;
            assert!(ChannelLuts::new(tables).is_ok(), "{table:?} in channel {c}");
        }
    }
    // Usable in a const.
    const LUTS: Result<ChannelLuts, Error> = ChannelLuts::new([&[0.0, 1.0], &[0.0, 1.0], &[0.0]]);
    assert_eq!(LUTS, Err(Error::InvalidLut { channel: Rgb::B }));
}

// ---------------------------------------------------------------------------------------------
// DynamicSet and errors
// ---------------------------------------------------------------------------------------------

#[test]
fn dynamic_set_rejects_wrong_lengths_and_follows_ieee() {
    let set = DynamicSet::<8>::from_rules(&[tables::A_RULES[1], tables::C2_RULES[0]]).unwrap();
    assert_eq!(set.len(), 3);
    for n in [0usize, 1, 2, 4, 100] {
        let s = vec![0.5f32; n];
        assert_eq!(
            set.ac1c2(&s),
            Err(Error::LengthMismatch {
                what: LengthOf::Samples,
                expected: 3,
                got: n
            })
        );
    }
    let ok = set.ac1c2(&[1.0, 1.0, 1.0]).unwrap();
    assert!(ok.iter().all(|v| v.is_finite()));
    // The C2 node (456.5 nm) comes first: NaN there reaches C2.
    assert_eq!(
        set.wavelengths_nm()[0],
        tables::C2_RULES[0].wavelengths_nm()[0]
    );
    assert!(set.ac1c2(&[NAN, 1.0, 1.0]).unwrap()[2].is_nan());
    assert_eq!(set.ac1c2(&[1.0, INF, 1.0]).unwrap()[0], INF);
    // Empty set: only the empty slice fits, giving zeros.
    let empty = DynamicSet::<4>::new();
    assert!(empty.is_empty());
    assert_eq!(empty.ac1c2(&[]), Ok([0.0; 3]));
    assert_eq!(
        empty.ac1c2(&[1.0]),
        Err(Error::LengthMismatch {
            what: LengthOf::Samples,
            expected: 0,
            got: 1
        })
    );
    // Capacity 0: any rule overflows, with the capacity named.
    assert_eq!(
        DynamicSet::<0>::from_rules(&[tables::A_RULES[0]]),
        Err(Error::Capacity { capacity: 0 })
    );
}

/// `GaussRule::new` refuses lengths that are not the order's (none for a rule that is not
/// `Defined`), naming which of its slices is wrong, then wavelengths and weights as the sets do.
#[test]
fn gauss_rule_new_checks_its_lengths_and_values() {
    static NM: [f32; 2] = [450.0, 600.0];
    static W: [f32; 2] = [1.0, 2.0];
    let mismatch = |what, expected, got| {
        Err(Error::LengthMismatch {
            what,
            expected,
            got,
        })
    };
    let rule = GaussRule::new(Channel::C1, 2, RuleStatus::Defined, &NM, &W).unwrap();
    assert_eq!((rule.channel(), rule.order()), (Channel::C1, 2));
    assert_eq!(
        GaussRule::new(Channel::A, 3, RuleStatus::Defined, &NM, &W),
        mismatch(LengthOf::RuleWavelengths, 3, 2)
    );
    assert_eq!(
        GaussRule::new(Channel::A, 2, RuleStatus::Defined, &NM, &W[..1]),
        mismatch(LengthOf::RuleWeights, 2, 1)
    );
    // A rule that does not exist has no nodes.
    assert!(GaussRule::new(Channel::C2, 2, RuleStatus::Complex, &[], &[]).is_ok());
    assert_eq!(
        GaussRule::new(Channel::C2, 2, RuleStatus::Complex, &NM, &[]),
        mismatch(LengthOf::RuleWavelengths, 0, 2)
    );
    static DOWN: [f32; 2] = [600.0, 450.0];
    assert_eq!(
        GaussRule::new(Channel::A, 2, RuleStatus::Defined, &DOWN, &W),
        Err(Error::InvalidWavelength { index: 1 })
    );
    static NAN_W: [f32; 2] = [1.0, NAN];
    assert_eq!(
        GaussRule::new(Channel::C2, 2, RuleStatus::Defined, &NM, &NAN_W),
        Err(Error::InvalidWeight { row: 2, index: 1 })
    );
}

#[test]
fn error_messages() {
    let cases = [
        // Each kind of length mismatch in its own words: what was compared, and the two
        // lengths in its units.
        (
            Error::LengthMismatch {
                what: LengthOf::Output,
                expected: 3,
                got: 5,
            },
            "length mismatch: an output of 5 pixels for an input of 3",
        ),
        (
            Error::LengthMismatch {
                what: LengthOf::InputPlane,
                expected: 20,
                got: 19,
            },
            "length mismatch: an input plane of 19 values where the first has 20",
        ),
        (
            Error::LengthMismatch {
                what: LengthOf::OutputPlane,
                expected: 20,
                got: 21,
            },
            "length mismatch: an output plane of 21 values for 20 pixels",
        ),
        (
            Error::LengthMismatch {
                what: LengthOf::Samples,
                expected: 3,
                got: 4,
            },
            "length mismatch: 4 samples for a set of 3 wavelengths",
        ),
        (
            Error::LengthMismatch {
                what: LengthOf::RuleWavelengths,
                expected: 4,
                got: 3,
            },
            "length mismatch: 3 wavelengths for a rule of 4 nodes",
        ),
        (
            Error::LengthMismatch {
                what: LengthOf::RuleWeights,
                expected: 0,
                got: 2,
            },
            "length mismatch: 2 weights for a rule of 0 nodes",
        ),
        (
            Error::Capacity { capacity: 16 },
            "the set would need more than its 16 wavelengths",
        ),
        (
            Error::UndefinedRule {
                channel: Channel::A,
                order: 7,
            },
            "channel A order 7 is not a defined rule",
        ),
        (
            Error::UndefinedRule {
                channel: Channel::C1,
                order: 3,
            },
            "channel C1 order 3 is not a defined rule",
        ),
        (
            Error::UndefinedRule {
                channel: Channel::C2,
                order: 4,
            },
            "channel C2 order 4 is not a defined rule",
        ),
        (
            Error::UpsamplingReadings,
            "an upsampling needs a set whose samples are at wavelengths, not a sensor's readings",
        ),
        (
            Error::InvalidLuxScale,
            "a lux scale needs a finite, positive illuminance per unit Y (from a finite, positive Y and illuminance)",
        ),
        (
            Error::InvalidLut { channel: Rgb::G },
            "lookup table for channel G needs 2 or more finite, non-decreasing entries in 0..=1",
        ),
    ];
    for (e, text) in cases {
        assert_eq!(e.to_string(), text);
        // And it is a std error (no source).
        let dyn_err: &dyn std::error::Error = &e;
        assert!(dyn_err.source().is_none());
    }
}

#[test]
fn batch_length_mismatch_on_empty_inputs() {
    let set: FoldedSet<4> = folded::TABLE2_ROW2_SRGB;
    let mut out = [[3.0f32; 3]; 2];
    assert_eq!(
        set.linear_rgb_batch(&[], &mut out),
        Err(Error::LengthMismatch {
            what: LengthOf::Output,
            expected: 0,
            got: 2
        })
    );
    assert_eq!(out, [[3.0; 3]; 2]);
    assert_eq!(set.linear_rgb_batch(&[], &mut []), Ok(()));
    assert_eq!(
        tables::TABLE2_ROW2.ac1c2_batch(&[[NAN; 4]], &mut []),
        Err(Error::LengthMismatch {
            what: LengthOf::Output,
            expected: 1,
            got: 0
        })
    );
}

// ---------------------------------------------------------------------------------------------
// micromath: encode_fast input handling
// ---------------------------------------------------------------------------------------------

#[cfg(feature = "micromath")]
#[test]
fn encode_fast_input_handling() {
    for tf in transfers() {
        for c in Rgb::ALL {
            for low in [NAN, 0.0, -0.0, -1.0, -INF, -f32::MAX] {
                assert_eq!(tf.encode_fast(c, low), 0.0, "{tf:?} {low}");
            }
            for high in [1.0, 2.0, INF, f32::MAX] {
                assert_eq!(tf.encode_fast(c, high), 1.0, "{tf:?} {high}");
            }
            for bits in (0..=1.0f32.to_bits()).step_by(100_003) {
                let x = f32::from_bits(bits);
                let fast = tf.encode_fast(c, x);
                assert!(in_unit(fast), "{tf:?} encode_fast({x:e}) = {fast}");
                // Linear and lookup tables are exact already: encode_fast is encode.
                if matches!(tf, TransferFunction::Linear | TransferFunction::Lut(_)) {
                    assert_eq!(fast, tf.encode(c, x));
                }
            }
        }
    }
}

#[cfg(feature = "micromath")]
#[test]
fn encode_fast_maps_nan_and_non_positive_to_exactly_zero() {
    for tf in transfers() {
        for low in [NAN, 0.0, -0.0, -1.0, -INF] {
            assert_eq!(tf.encode_fast(Rgb::R, low), 0.0, "{tf:?} {low}");
        }
    }
}

/// Every f32 from `lo` to `hi`, in order.
fn consecutive(lo: f32, hi: f32) -> impl Iterator<Item = f32> {
    (lo.to_bits()..=hi.to_bits()).map(f32::from_bits)
}

#[test]
fn srgb_is_monotonic_across_its_join_for_every_f32() {
    // The IEC constants leave the power branch ~2e-8 below the linear one at 0.0031308; found by
    // the encoders fuzz target. Every consecutive pair of f32 around both joins.
    let tf = TransferFunction::Srgb;
    for (lo, hi, decode) in [(0.0030f32, 0.0033f32, false), (0.0400f32, 0.0410f32, true)] {
        let mut prev = f32::NEG_INFINITY;
        for x in consecutive(lo, hi) {
            let v = if decode {
                tf.decode(Rgb::R, x)
            } else {
                tf.encode(Rgb::R, x)
            };
            assert!(
                v >= prev,
                "{} not monotonic at {x:e}: {v} < {prev}",
                if decode { "decode" } else { "encode" }
            );
            prev = v;
        }
    }
}

#[test]
fn gamma_is_monotonic_between_neighbouring_f32() {
    // libm's f32 power is not correctly rounded: for γ = 5 to 10 it stepped back by one unit in
    // the last place between neighbours (found by the fuzz target). Powers are now taken in f64
    // and rounded once. Windows of 200 000 consecutive f32 at several magnitudes.
    for g in [2.2f32, 2.4, 5.0, 8.0, 10.0, 0.0031308006] {
        let tf = TransferFunction::Gamma(g);
        for start in [1e-6f32, 0.01, 0.2, 0.7, 0.99] {
            let mut prev = (f32::NEG_INFINITY, f32::NEG_INFINITY);
            for x in consecutive(start, f32::from_bits(start.to_bits() + 200_000).min(1.0)) {
                let v = (tf.encode(Rgb::R, x), tf.decode(Rgb::R, x));
                assert!(
                    v.0 >= prev.0 && v.1 >= prev.1,
                    "Gamma({g}) at {x:e}: {v:?} after {prev:?}"
                );
                prev = v;
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Displays made at run time
// ---------------------------------------------------------------------------------------------

#[test]
fn display_new_rebuilds_every_baked_display() {
    for baked in displays::ALL {
        let made = Display::new(
            baked.name(),
            baked.primaries_xy(),
            baked.white_xy(),
            baked.transfer(),
        )
        .unwrap_or_else(|e| panic!("{}: {e}", baked.name()));
        // The baked matrices come from the f64 decimals of the standards; `new` starts from the
        // same values rounded to f32 (2⁻²⁴ relative each). The matrices' condition numbers are
        // below 10, so the inputs' rounding moves an entry by less than 10 · 3 · 2⁻²⁴ ≈ 2e-6
        // relative to the largest entry of its matrix, plus the output's own rounding (2⁻²⁴).
        for (name, a, b) in [
            ("rgb_to_xyz", made.rgb_to_xyz(), baked.rgb_to_xyz()),
            ("xyz_to_rgb", made.xyz_to_rgb(), baked.xyz_to_rgb()),
        ] {
            let scale = b.iter().flatten().fold(0.0f32, |m, v| m.max(v.abs()));
            for (r, (ra, rb)) in a.iter().zip(&b).enumerate() {
                for (c, (x, y)) in ra.iter().zip(rb).enumerate() {
                    assert!(
                        (x - y).abs() <= 2e-6 * scale,
                        "{} {name}[{r}][{c}]: {x} vs baked {y}",
                        baked.name()
                    );
                }
            }
        }
        for (x, y) in made.a_from_rgb().iter().zip(&baked.a_from_rgb()) {
            assert!(
                (x - y).abs() <= 2e-6 * y.abs().max(1.0),
                "{}: A {x} vs {y}",
                baked.name()
            );
        }
        assert_eq!(made.transfer(), baked.transfer());
    }
}

#[test]
fn display_new_refuses_bad_input_with_its_error() {
    let srgb = displays::SRGB;
    let (p, w) = (srgb.primaries_xy(), srgb.white_xy());
    let new = |p: [[f32; 2]; 3], w: [f32; 2], t: TransferFunction| Display::new("test", p, w, t);
    for bad in [
        [NAN, 0.3],
        [0.3, INF],
        [-0.1, 0.3],
        [0.3, 0.0],
        [0.7, 0.5],
        [0.3, -0.2],
    ] {
        assert!(
            matches!(
                new([bad, p[1], p[2]], w, TransferFunction::Srgb),
                Err(Error::Display(DisplayError::Chromaticity { point: Point::Red, xy }))
                    if xy.map(|v| v.to_bits()) == bad.map(|v| v.to_bits())
            ),
            "primary {bad:?}"
        );
        assert!(
            matches!(
                new(p, bad, TransferFunction::Srgb),
                Err(Error::Display(DisplayError::Chromaticity {
                    point: Point::White,
                    ..
                }))
            ),
            "white {bad:?}"
        );
    }
    // Collinear primaries (all on x = y), and two equal ones.
    let collinear = |r| matches!(r, Err(Error::Display(DisplayError::Collinear { condition })) if f64::from(condition) > MAX_PRIMARIES_CONDITION);
    assert!(collinear(new(
        [[0.2, 0.2], [0.4, 0.4], [0.3, 0.3]],
        w,
        TransferFunction::Srgb
    )));
    assert!(collinear(new(
        [p[0], p[0], p[2]],
        w,
        TransferFunction::Srgb
    )));
    // A white no positive mix of the primaries reaches.
    assert!(matches!(
        new(p, [0.1, 0.8], TransferFunction::Srgb),
        Err(Error::Display(DisplayError::WhiteOutside { drives, .. })) if drives.iter().any(|d| *d <= 0.0)
    ));
    for g in [0.0, -2.2, NAN, INF, -0.0] {
        let e = new(p, w, TransferFunction::Gamma(g));
        assert!(
            matches!(e, Err(Error::Display(DisplayError::Gamma { gamma })) if gamma.to_bits() == g.to_bits()),
            "γ = {g}: {e:?}"
        );
        // Every error prints a sentence, with the details.
        let text = e.unwrap_err().to_string();
        assert!(
            text.contains("gamma") && text.contains(&g.to_string()),
            "{text}"
        );
    }
    assert!(new(p, w, TransferFunction::Gamma(2.2)).is_ok());
}

#[test]
fn display_new_never_panics_and_accepts_only_finite_matrices() {
    // Arbitrary bit patterns, specials and near-degenerate triangles.
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        match state % 4 {
            0 => f32::from_bits((state >> 32) as u32),
            1 => [NAN, INF, -INF, 0.0, -0.0, SUB_MIN, 1.0, f32::MAX][(state >> 8) as usize % 8],
            _ => ((state >> 40) as f32) / (1u64 << 24) as f32,
        }
    };
    let mut accepted = 0;
    for _ in 0..200_000 {
        let p = [[next(), next()], [next(), next()], [next(), next()]];
        let w = [next(), next()];
        if let Ok(d) = Display::new("fuzz", p, w, TransferFunction::Srgb) {
            accepted += 1;
            let (to_xyz, to_rgb) = (d.rgb_to_xyz(), d.xyz_to_rgb());
            let all = to_xyz.iter().chain(&to_rgb).flatten();
            assert!(all.clone().all(|v| v.is_finite()), "{p:?} {w:?}");
            assert!(d.a_from_rgb().iter().all(|v| v.is_finite()), "{p:?} {w:?}");
        }
    }
    // A few random triangles are valid displays (22 of these 200 000 inputs).
    assert!(accepted > 0);
    // Every sRGB chromaticity moved by up to ±0.02 is still a valid display.
    for k in 0..1000 {
        let j = |i: usize| (((k * 7 + i * 13) % 41) as f32 - 20.0) / 1000.0;
        let s = displays::SRGB;
        let p = [0, 1, 2].map(|c| {
            [
                s.primaries_xy()[c][0] + j(2 * c),
                s.primaries_xy()[c][1] + j(2 * c + 1),
            ]
        });
        let w = [s.white_xy()[0] + j(6), s.white_xy()[1] + j(7)];
        assert!(
            Display::new("jitter", p, w, TransferFunction::Srgb).is_ok(),
            "{p:?} {w:?}"
        );
    }
}
