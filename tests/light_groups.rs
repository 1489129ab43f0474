//! Light-group sets (`LightGroupSet`): with one light, every path gives the member folded set's
//! bits and bytes; the sum over lights is the members' sum; per-pixel, batch and planar paths
//! agree bit for bit; NaN, ±Inf and negative accumulators give what the docs say; the
//! constructors refuse what they document refusing.

// Channel and light loops index several parallel arrays by their index.
#![allow(clippy::needless_range_loop)]

mod common;

use common::MAPPINGS;
use proptest::prelude::*;
use proptest::test_runner::TestCaseResult;
use spectral_quadrature::tables::folded::{
    self, KQ_C_8_DISPLAY_P3, KQ_C_8_MEYER_1987, KQ_C_8_REC2020, KQ_C_8_SRGB,
};
use spectral_quadrature::{
    f32_budget, ChannelLuts, Display, Error, FoldedSet, GamutMapping, LightGroupProblem,
    LightGroupSet, Rgb, Samples, TransferFunction,
};

/// Cases per property: each case is a whole image of up to 24 pixels.
const CASES: u32 = 1_000;

/// One accumulator value: mostly what a renderer accumulates (0..1 throughputs, larger sums,
/// signed values from a signed estimator), sometimes any f32 at all (NaN, ±Inf, subnormals,
/// huge), or one of the edge values below.
fn sample() -> impl Strategy<Value = f32> + Clone {
    prop_oneof![
        3 => 0.0f32..=1.0,
        2 => 0.0f32..=1e4,
        2 => -1e3f32..=1e3,
        1 => any::<f32>(),
        1 => any::<u32>().prop_map(f32::from_bits),
        1 => prop::sample::select(EDGES.to_vec()),
    ]
}

/// NaN, ±Inf, ±0, negative, subnormal, huge and the f32 ends.
const EDGES: [f32; 16] = [
    f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    0.0,
    -0.0,
    -1.0,
    1.4e-45,
    -1.4e-45,
    1.0e-40,
    f32::MIN_POSITIVE,
    0.5,
    1.0,
    1.0e30,
    -1.0e30,
    f32::MAX,
    f32::MIN,
];

/// Pixels of L groups of N values, 0 to 24 of them, drawn as one flat vector.
fn pixels<const N: usize, const L: usize>() -> impl Strategy<Value = Vec<[[f32; N]; L]>> {
    proptest::collection::vec(sample(), 0..24 * N * L).prop_map(|flat| {
        flat.chunks_exact(N * L)
            .map(|c| std::array::from_fn(|l| std::array::from_fn(|i| c[l * N + i])))
            .collect()
    })
}

/// The same bits, or both NaN (the docs promise the bits "NaN payloads aside").
fn same(a: f32, b: f32) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

fn same3(a: [f32; 3], b: [f32; 3]) -> bool {
    (0..3).all(|c| same(a[c], b[c]))
}

/// Planes of pixels: `planes[l][i][p]`.
fn planes<const N: usize, const L: usize>(px: &[[[f32; N]; L]]) -> [[Vec<f32>; N]; L] {
    std::array::from_fn(|l| std::array::from_fn(|i| px.iter().map(|g| g[l][i]).collect()))
}

fn plane_refs<const N: usize, const L: usize>(planes: &[[Vec<f32>; N]; L]) -> [[&[f32]; N]; L] {
    planes
        .each_ref()
        .map(|light| light.each_ref().map(|p| &p[..]))
}

/// A lookup-table transfer function (the per-pixel encoders' generic branch).
const LUTS: ChannelLuts = match ChannelLuts::new([
    &[0.0, 0.35, 0.55, 0.7, 0.82, 0.92, 1.0],
    &[0.0, 0.5, 1.0],
    &[0.0, 0.2, 0.2, 0.6, 1.0],
]) {
    Ok(l) => l,
    Err(_) => panic!("valid tables"),
};

/// The sRGB display with each kind of transfer function, and the baked displays.
fn displays() -> Vec<Display> {
    let srgb = KQ_C_8_SRGB.display();
    vec![
        srgb,
        KQ_C_8_DISPLAY_P3.display(),
        KQ_C_8_REC2020.display(),
        KQ_C_8_MEYER_1987.display(),
        srgb.with_transfer(TransferFunction::Linear),
        srgb.with_transfer(TransferFunction::Gamma(2.2)),
        srgb.with_transfer(TransferFunction::Lut(LUTS)),
    ]
}

/// `set` with another display (its weights kept).
fn on<const N: usize>(set: FoldedSet<N>, display: Display) -> FoldedSet<N> {
    FoldedSet::new(set.wavelengths_nm(), set.weights(), set.samples(), display).unwrap()
}

/// A second light at `set`'s nodes: its weights scaled per node (positive factors from 0.6 to
/// 1.3, as a warmer light's would change them), the same wavelengths and display.
fn other_light<const N: usize>(set: FoldedSet<N>, light: &'static str) -> FoldedSet<N> {
    let weights = set
        .weights()
        .map(|row| std::array::from_fn(|i| row[i] * (0.6 + 0.7 * i as f32 / N.max(1) as f32)));
    FoldedSet::new(
        set.wavelengths_nm(),
        weights,
        Samples::Reflectance { light },
        set.display(),
    )
    .unwrap()
}

// ---------------------------------------------------------------------------------------------
// One light: the member's bits and bytes, on every path
// ---------------------------------------------------------------------------------------------

/// Every path of the one-light set of `member` against the member's own on `px`.
fn one_light_case<const N: usize>(member: FoldedSet<N>, px: &[[[f32; N]; 1]]) -> TestCaseResult {
    let set = LightGroupSet::from_members([member]).unwrap();
    let flat: Vec<[f32; N]> = px.iter().map(|g| g[0]).collect();
    let n = px.len();
    for (g, s) in px.iter().zip(&flat) {
        prop_assert!(
            same3(set.linear_rgb(g), member.linear_rgb(s)),
            "linear_rgb {s:?}"
        );
        for m in MAPPINGS {
            prop_assert_eq!(
                set.encode_u8(m, g),
                member.encode_u8(m, s),
                "{:?} {:?}",
                m,
                s
            );
            prop_assert_eq!(
                set.encode_u16(m, g),
                member.encode_u16(m, s),
                "{:?} {:?}",
                m,
                s
            );
        }
    }
    // Batch.
    let (mut a, mut b) = (vec![[0f32; 3]; n], vec![[0f32; 3]; n]);
    set.linear_rgb_batch(px, &mut a).unwrap();
    member.linear_rgb_batch(&flat, &mut b).unwrap();
    prop_assert!(a.iter().zip(&b).all(|(x, y)| same3(*x, *y)));
    for m in MAPPINGS {
        let (mut a, mut b) = (vec![[0u8; 3]; n], vec![[0u8; 3]; n]);
        set.encode_u8_batch(m, px, &mut a).unwrap();
        member.encode_u8_batch(m, &flat, &mut b).unwrap();
        prop_assert_eq!(&a, &b);
        let (mut a, mut b) = (vec![[0u16; 3]; n], vec![[0u16; 3]; n]);
        set.encode_u16_batch(m, px, &mut a).unwrap();
        member.encode_u16_batch(m, &flat, &mut b).unwrap();
        prop_assert_eq!(&a, &b);
    }
    // Planar.
    let pl = planes(px);
    let refs = plane_refs(&pl);
    let single: [&[f32]; N] = refs[0];
    let mut a: [Vec<f32>; 3] = std::array::from_fn(|_| vec![0.0; n]);
    let mut b: [Vec<f32>; 3] = std::array::from_fn(|_| vec![0.0; n]);
    {
        let [r, g, bl] = &mut a;
        set.linear_rgb_planar(refs, [r, g, bl]).unwrap();
        let [r, g, bl] = &mut b;
        member.linear_rgb_planar(single, [r, g, bl]).unwrap();
    }
    for c in 0..3 {
        prop_assert!(a[c].iter().zip(&b[c]).all(|(x, y)| same(*x, *y)));
    }
    for m in MAPPINGS {
        let (mut a, mut b) = (vec![[0u8; 3]; n], vec![[0u8; 3]; n]);
        set.encode_u8_planar_to_interleaved(m, refs, &mut a)
            .unwrap();
        member
            .encode_u8_planar_to_interleaved(m, single, &mut b)
            .unwrap();
        prop_assert_eq!(&a, &b);
        let mut a: [Vec<u8>; 3] = std::array::from_fn(|_| vec![0; n]);
        let mut b: [Vec<u8>; 3] = std::array::from_fn(|_| vec![0; n]);
        {
            let [r, g, bl] = &mut a;
            set.encode_u8_planar(m, refs, [r, g, bl]).unwrap();
            let [r, g, bl] = &mut b;
            member.encode_u8_planar(m, single, [r, g, bl]).unwrap();
        }
        prop_assert_eq!(&a, &b);
        let (mut a, mut b) = (vec![[0u16; 3]; n], vec![[0u16; 3]; n]);
        set.encode_u16_planar_to_interleaved(m, refs, &mut a)
            .unwrap();
        member
            .encode_u16_planar_to_interleaved(m, single, &mut b)
            .unwrap();
        prop_assert_eq!(&a, &b);
        let mut a: [Vec<u16>; 3] = std::array::from_fn(|_| vec![0; n]);
        let mut b: [Vec<u16>; 3] = std::array::from_fn(|_| vec![0; n]);
        {
            let [r, g, bl] = &mut a;
            set.encode_u16_planar(m, refs, [r, g, bl]).unwrap();
            let [r, g, bl] = &mut b;
            member.encode_u16_planar(m, single, [r, g, bl]).unwrap();
        }
        prop_assert_eq!(&a, &b);
    }
    Ok(())
}

#[test]
fn one_light_gives_the_folded_sets_bits_and_bytes_on_every_path() {
    for display in displays() {
        let member = on(KQ_C_8_SRGB, display);
        common::check_property(
            CASES,
            &format!("KQ_C_8 on {} {:?}", display.name(), display.transfer()),
            pixels::<8, 1>(),
            |px| one_light_case(member, &px),
        );
    }
    // Table 2's sets are for radiances: KQ_C_4 is the baked N = 4 set with a light folded in.
    for member in [
        folded::KQ_C_4_SRGB,
        folded::KQ_C_4_DISPLAY_P3,
        folded::KQ_C_4_REC2020,
        folded::KQ_C_4_MEYER_1987,
    ] {
        common::check_property(
            CASES / 4,
            &format!("KQ_C_4 on {}", member.display().name()),
            pixels::<4, 1>(),
            |px| one_light_case(member, &px),
        );
    }
}

#[test]
fn one_light_on_the_edge_values_gives_the_folded_sets_bytes() {
    // Every pair of edge values at two nodes (the rest 0.5): the deterministic counterpart of
    // the property above, so that each edge value is met whatever proptest draws.
    for display in displays() {
        let member = on(KQ_C_8_SRGB, display);
        let set = LightGroupSet::from_members([member]).unwrap();
        for &x in &EDGES {
            for &y in &EDGES {
                let mut s = [0.5f32; 8];
                (s[2], s[6]) = (x, y);
                assert!(same3(set.linear_rgb(&[s]), member.linear_rgb(&s)), "{s:?}");
                for m in MAPPINGS {
                    assert_eq!(set.encode_u8(m, &[s]), member.encode_u8(m, &s), "{s:?}");
                    assert_eq!(set.encode_u16(m, &[s]), member.encode_u16(m, &s), "{s:?}");
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Several lights: per pixel = batch = planar; the sum of the members
// ---------------------------------------------------------------------------------------------

/// Every batch and planar path of `set` against its per-pixel functions on `px`, bit for bit.
fn paths_case<const N: usize, const L: usize>(
    set: &LightGroupSet<N, L>,
    px: &[[[f32; N]; L]],
) -> TestCaseResult {
    let n = px.len();
    let pl = planes(px);
    let refs = plane_refs(&pl);

    let mut batch = vec![[0f32; 3]; n];
    set.linear_rgb_batch(px, &mut batch).unwrap();
    let mut planar: [Vec<f32>; 3] = std::array::from_fn(|_| vec![0.0; n]);
    {
        let [r, g, b] = &mut planar;
        set.linear_rgb_planar(refs, [r, g, b]).unwrap();
    }
    for (p, g) in px.iter().enumerate() {
        let one = set.linear_rgb(g);
        prop_assert!(same3(batch[p], one), "batch, pixel {p}: {g:?}");
        let pla = [planar[0][p], planar[1][p], planar[2][p]];
        prop_assert!(same3(pla, one), "planar, pixel {p}: {g:?}");
    }
    for m in MAPPINGS {
        let want8: Vec<[u8; 3]> = px.iter().map(|g| set.encode_u8(m, g)).collect();
        let want16: Vec<[u16; 3]> = px.iter().map(|g| set.encode_u16(m, g)).collect();

        let mut out = vec![[0u8; 3]; n];
        set.encode_u8_batch(m, px, &mut out).unwrap();
        prop_assert_eq!(&out, &want8);
        let mut out = vec![[0u8; 3]; n];
        set.encode_u8_planar_to_interleaved(m, refs, &mut out)
            .unwrap();
        prop_assert_eq!(&out, &want8);
        let mut out: [Vec<u8>; 3] = std::array::from_fn(|_| vec![0; n]);
        {
            let [r, g, b] = &mut out;
            set.encode_u8_planar(m, refs, [r, g, b]).unwrap();
        }
        for p in 0..n {
            prop_assert_eq!([out[0][p], out[1][p], out[2][p]], want8[p]);
        }

        let mut out = vec![[0u16; 3]; n];
        set.encode_u16_batch(m, px, &mut out).unwrap();
        prop_assert_eq!(&out, &want16);
        let mut out = vec![[0u16; 3]; n];
        set.encode_u16_planar_to_interleaved(m, refs, &mut out)
            .unwrap();
        prop_assert_eq!(&out, &want16);
        let mut out: [Vec<u16>; 3] = std::array::from_fn(|_| vec![0; n]);
        {
            let [r, g, b] = &mut out;
            set.encode_u16_planar(m, refs, [r, g, b]).unwrap();
        }
        for p in 0..n {
            prop_assert_eq!([out[0][p], out[1][p], out[2][p]], want16[p]);
        }

        // The encoders encode the sum as the display does (zero's sign aside, which encodes
        // the same).
        for (p, g) in px.iter().enumerate() {
            let rgb = set.linear_rgb(g);
            prop_assert_eq!(want8[p], set.display().encode_u8(m, rgb));
            prop_assert_eq!(want16[p], set.display().encode_u16(m, rgb));
        }
    }
    Ok(())
}

/// The sum of the members, in light order, per pixel: what `linear_rgb` documents.
fn members_sum<const N: usize, const L: usize>(
    set: &LightGroupSet<N, L>,
    g: &[[f32; N]; L],
) -> [f32; 3] {
    let mut rgb = set.member(0).unwrap().linear_rgb(&g[0]);
    for l in 1..L {
        let c = set.member(l).unwrap().linear_rgb(&g[l]);
        rgb = [rgb[0] + c[0], rgb[1] + c[1], rgb[2] + c[2]];
    }
    rgb
}

#[test]
fn every_path_agrees_bit_for_bit_and_sums_the_members() {
    for display in displays() {
        let c = on(KQ_C_8_SRGB, display);
        let two = LightGroupSet::from_members([c, other_light(c, "A")]).unwrap();
        common::check_property(
            CASES,
            &format!("two lights on {} {:?}", display.name(), display.transfer()),
            pixels::<8, 2>(),
            |px| {
                for g in &px {
                    prop_assert!(same3(two.linear_rgb(g), members_sum(&two, g)), "{g:?}");
                }
                paths_case(&two, &px)
            },
        );
    }
    let c = folded::KQ_C_4_REC2020;
    let three = LightGroupSet::from_members([
        c,
        other_light(c, "A"),
        other_light(other_light(c, "x"), "F11"),
    ])
    .unwrap();
    common::check_property(CASES, "three lights, N = 4", pixels::<4, 3>(), |px| {
        for g in &px {
            prop_assert!(same3(three.linear_rgb(g), members_sum(&three, g)), "{g:?}");
        }
        paths_case(&three, &px)
    });
}

/// Within [`f32_budget`]`(L · N, Σ |w · s|)` of the exact sum, computed in f64 with the same f32
/// weights: the bound `linear_rgb` documents, against the exact sum of the f64 derivation's
/// weights, is looser than this by the weights' rounding, so this checks the arithmetic part.
#[test]
fn the_sum_is_within_the_documented_budget() {
    let c = KQ_C_8_SRGB;
    let set = LightGroupSet::from_members([c, other_light(c, "A"), other_light(c, "B")]).unwrap();
    let w = set.weights();
    // Finite samples whose sums stay far from overflow: the budget's domain.
    let finite = prop_oneof![4 => -10.0f32..=10.0, 2 => 0.0f32..=1e4, 1 => -1e-38f32..=1e-38];
    common::check_property(
        CASES * 4,
        "budget",
        proptest::collection::vec(finite, 24),
        |flat| {
            let g: [[f32; 8]; 3] =
                std::array::from_fn(|l| std::array::from_fn(|i| flat[l * 8 + i]));
            let rgb = set.linear_rgb(&g);
            for ch in 0..3 {
                let (mut exact, mut abs) = (0.0f64, 0.0f64);
                for l in 0..3 {
                    for i in 0..8 {
                        let t = f64::from(w[l][ch][i]) * f64::from(g[l][i]);
                        exact += t;
                        abs += t.abs();
                    }
                }
                let err = (f64::from(rgb[ch]) - exact).abs();
                prop_assert!(
                    err <= f32_budget(24, abs),
                    "channel {ch}: {err} > budget, {g:?}"
                );
            }
            Ok(())
        },
    );
}

#[test]
fn groups_add_and_scale_as_light_does() {
    let c = KQ_C_8_SRGB;
    let a = other_light(c, "A");
    let set = LightGroupSet::from_members([c, a]).unwrap();
    let finite = prop_oneof![4 => 0.0f32..=1.0, 1 => -1e3f32..=1e3];
    common::check_property(
        CASES,
        "linearity",
        (proptest::collection::vec(finite, 16), 0.0f32..=8.0),
        |(flat, k)| {
            let s0: [f32; 8] = std::array::from_fn(|i| flat[i]);
            let s1: [f32; 8] = std::array::from_fn(|i| flat[8 + i]);
            // Groups sum: exactly the members' sum (one f32 addition per channel), which is
            // within f32 rounding of the exact sum (the budget test above).
            let (m0, m1) = (c.linear_rgb(&s0), a.linear_rgb(&s1));
            let both = set.linear_rgb(&[s0, s1]);
            prop_assert_eq!(both, [m0[0] + m1[0], m0[1] + m1[1], m0[2] + m1[2]]);
            // A dark group adds nothing: light 0 alone is its member's colour (an exact zero
            // may turn +0.0, since m + 0.0 = m except for −0.0).
            let alone = set.linear_rgb(&[s0, [0.0; 8]]);
            for ch in 0..3 {
                prop_assert!(alone[ch] == m0[ch]);
            }
            // Doubling a group doubles its contribution exactly (a power of two scales every
            // product and partial sum exactly, away from overflow and subnormals, which these
            // samples and weights do not reach).
            let twice = set.linear_rgb(&[s0.map(|v| 2.0 * v), [0.0; 8]]);
            prop_assert_eq!(twice, m0.map(|v| 2.0 * v));
            // Scaling by any k scales the contribution to within the rounding of the k·s
            // products and of the sum: f32_budget(N, Σ|w · k s|) for each, so twice that.
            let scaled = set.linear_rgb(&[s0, s1.map(|v| k * v)]);
            let w = a.weights();
            for ch in 0..3 {
                let abs: f64 = (0..8)
                    .map(|i| (f64::from(w[ch][i]) * f64::from(k * s1[i])).abs())
                    .sum::<f64>()
                    + (0..8)
                        .map(|i| (f64::from(c.weights()[ch][i]) * f64::from(s0[i])).abs())
                        .sum::<f64>();
                let want = f64::from(m0[ch]) + f64::from(k) * f64::from(m1[ch]);
                let err = (f64::from(scaled[ch]) - want).abs();
                prop_assert!(err <= 2.0 * f32_budget(16, abs), "{err} {abs}");
            }
            Ok(())
        },
    );
}

// ---------------------------------------------------------------------------------------------
// Bad input: what the docs say it yields
// ---------------------------------------------------------------------------------------------

#[test]
fn nan_infinity_and_negative_groups_give_the_documented_result() {
    let c = KQ_C_8_SRGB;
    let set = LightGroupSet::from_members([c, other_light(c, "A")]).unwrap();
    let ok = [0.4f32; 8];
    for l in 0..2 {
        for i in 0..8 {
            // A NaN in either group: every channel NaN, black in every encoding.
            let mut g = [ok; 2];
            g[l][i] = f32::NAN;
            assert!(
                set.linear_rgb(&g).iter().all(|v| v.is_nan()),
                "NaN at {l}, {i}"
            );
            for m in MAPPINGS {
                assert_eq!(set.encode_u8(m, &g), [0; 3]);
                assert_eq!(set.encode_u16(m, &g), [0; 3]);
            }
            // An infinity: every channel ±Inf or NaN; the encoders clip it or (NaN) give black.
            for inf in [f32::INFINITY, f32::NEG_INFINITY] {
                let mut g = [ok; 2];
                g[l][i] = inf;
                let rgb = set.linear_rgb(&g);
                assert!(
                    rgb.iter().all(|v| !v.is_finite()),
                    "{inf} at {l}, {i}: {rgb:?}"
                );
                let w = set.weights()[l];
                for ch in 0..3 {
                    // Infinite with the sign of weight · sample where the weight is not 0.
                    if w[ch][i] != 0.0 {
                        assert_eq!(rgb[ch], inf * w[ch][i].signum(), "{ch}");
                    }
                }
                let px = set.encode_u8(GamutMapping::Clip, &g);
                if rgb.iter().any(|v| v.is_nan()) {
                    assert_eq!(px, [0; 3]);
                } else {
                    assert_eq!(px, rgb.map(|v| if v > 0.0 { 255 } else { 0 }));
                }
            }
        }
    }
    // +∞ in one light and −∞ in the other meet as ∞ − ∞: NaN, so black.
    let (mut g0, mut g1) = (ok, ok);
    g0[5] = f32::INFINITY;
    g1[5] = f32::NEG_INFINITY;
    let rgb = set.linear_rgb(&[g0, g1]);
    assert!(rgb.iter().all(|v| v.is_nan()), "{rgb:?}");
    assert_eq!(set.encode_u8(GamutMapping::PreserveA, &[g0, g1]), [0; 3]);
    // Negative accumulators are used as they are: negating both groups negates the colour.
    let g = [[0.3f32, 0.1, 0.7, 0.2, 0.9, 0.4, 0.5, 0.6], ok];
    let neg = g.map(|s| s.map(|v| -v));
    assert_eq!(set.linear_rgb(&neg), set.linear_rgb(&g).map(|v| -v));
    // Huge finite values overflow to ±Inf, and clip.
    let huge = [[f32::MAX; 8], [f32::MAX; 8]];
    assert!(set.linear_rgb(&huge).iter().all(|v| !v.is_finite()));
    // Subnormal accumulators are used as the tiny numbers they are (no flush to zero): the
    // colour of the smallest subnormal at one node is its weights times it, rounded.
    let mut tiny = [[0.0f32; 8]; 2];
    tiny[0][7] = 1e-38;
    let rgb = set.linear_rgb(&tiny);
    assert_eq!(rgb, c.weights().map(|row| row[7] * 1e-38));
}

#[test]
fn no_wavelengths_give_black() {
    let set =
        LightGroupSet::<0, 2>::new([], [[[]; 3]; 2], ["C", "A"], KQ_C_8_SRGB.display()).unwrap();
    assert_eq!(set.linear_rgb(&[[], []]), [0.0; 3]);
    assert_eq!(set.encode_u8(GamutMapping::Clip, &[[], []]), [0; 3]);
    let mut out = [[9u8; 3]; 5];
    set.encode_u8_planar_to_interleaved(GamutMapping::Clip, [[], []], &mut out)
        .unwrap();
    assert_eq!(out, [[0; 3]; 5]);
}

// ---------------------------------------------------------------------------------------------
// Construction and length errors
// ---------------------------------------------------------------------------------------------

/// A const built from baked sets: the constructors run at compile time.
const TWO: LightGroupSet<8, 2> = match LightGroupSet::from_members([KQ_C_8_SRGB, KQ_C_8_SRGB]) {
    Ok(set) => set,
    Err(_) => panic!("the same member twice is a set"),
};

#[test]
fn members_come_back_and_accessors_read_the_fields() {
    let c = KQ_C_8_SRGB;
    let a = other_light(c, "A");
    let set = LightGroupSet::from_members([c, a]).unwrap();
    assert_eq!(set.member(0), Some(c));
    assert_eq!(set.member(1), Some(a));
    assert_eq!(set.member(2), None);
    assert_eq!(set.lights(), ["C", "A"]);
    assert_eq!(set.weights(), [c.weights(), a.weights()]);
    assert_eq!(set.wavelengths_nm(), c.wavelengths_nm());
    assert_eq!(set.display(), c.display());
    assert_eq!(
        (LightGroupSet::<8, 2>::LEN, LightGroupSet::<8, 2>::LIGHTS),
        (8, 2)
    );
    let rebuilt = LightGroupSet::new(
        set.wavelengths_nm(),
        set.weights(),
        set.lights(),
        set.display(),
    );
    assert_eq!(rebuilt, Ok(set));
    assert_eq!(TWO.lights(), ["C", "C"]);
}

/// What the constructors return for a light at fault.
fn refused<T>(light: usize, problem: LightGroupProblem) -> Result<T, Error> {
    Err(Error::LightGroup { light, problem })
}

#[test]
fn constructors_refuse_what_they_document() {
    let c = KQ_C_8_SRGB;
    let display = c.display();

    assert_eq!(
        LightGroupSet::<8, 0>::from_members([]),
        refused(0, LightGroupProblem::NoLights)
    );
    assert_eq!(
        LightGroupSet::<8, 0>::new(c.wavelengths_nm(), [], [], display),
        refused(0, LightGroupProblem::NoLights)
    );
    // Wavelengths one ulp apart are different nodes.
    let mut nm = c.wavelengths_nm();
    nm[3] = f32::from_bits(nm[3].to_bits() + 1);
    let moved = FoldedSet::new(nm, c.weights(), c.samples(), display).unwrap();
    assert_eq!(
        LightGroupSet::from_members([c, c, moved]),
        refused(2, LightGroupProblem::Wavelengths)
    );
    // Another display, or the same one with another transfer function or table.
    assert_eq!(
        LightGroupSet::from_members([c, KQ_C_8_DISPLAY_P3]),
        refused(1, LightGroupProblem::Display)
    );
    let gamma = on(c, display.with_transfer(TransferFunction::Gamma(2.2)));
    assert_eq!(
        LightGroupSet::from_members([gamma, c]),
        refused(1, LightGroupProblem::Display)
    );
    let lut = on(c, display.with_transfer(TransferFunction::Lut(LUTS)));
    let other_lut =
        ChannelLuts::new([&[0.0, 1.0], &[0.0, 0.5, 1.0], &[0.0, 0.2, 0.2, 0.6, 1.0]]).unwrap();
    let lut2 = on(c, display.with_transfer(TransferFunction::Lut(other_lut)));
    assert!(LightGroupSet::from_members([lut, lut]).is_ok());
    assert_eq!(
        LightGroupSet::from_members([lut, lut2]),
        refused(1, LightGroupProblem::Display)
    );
    // Members without a light folded in.
    let radiance =
        FoldedSet::new(c.wavelengths_nm(), c.weights(), Samples::Radiance, display).unwrap();
    assert_eq!(
        LightGroupSet::from_members([radiance, c]),
        refused(0, LightGroupProblem::NotReflectance)
    );
    let readings = Samples::Readings {
        sensor: "s",
        light: Some("C"),
    };
    let sensor = FoldedSet::new(c.wavelengths_nm(), c.weights(), readings, display).unwrap();
    assert_eq!(
        LightGroupSet::from_members([c, sensor]),
        refused(1, LightGroupProblem::NotReflectance)
    );
    // `new`: the wavelengths and weights checked as FoldedSet::new checks them, a weight named
    // by its light, channel and index.
    let mut w = [c.weights(); 2];
    w[1][2][4] = f32::INFINITY;
    let e = LightGroupSet::new(c.wavelengths_nm(), w, ["C", "A"], display).unwrap_err();
    assert_eq!(
        e,
        Error::LightGroup {
            light: 1,
            problem: LightGroupProblem::InvalidWeight {
                channel: Rgb::B,
                index: 4
            }
        }
    );
    assert_eq!(
        e.to_string(),
        "light group 1: weight 4 of channel B is not finite"
    );
    let mut w = [c.weights(); 2];
    w[0][0][0] = f32::NAN;
    w[1][1][3] = f32::NAN;
    assert_eq!(
        LightGroupSet::new(c.wavelengths_nm(), w, ["C", "A"], display),
        refused(
            0,
            LightGroupProblem::InvalidWeight {
                channel: Rgb::R,
                index: 0
            }
        )
    );
    let mut nm = c.wavelengths_nm();
    nm.swap(1, 2);
    assert_eq!(
        LightGroupSet::new(nm, [c.weights(); 2], ["C", "A"], display),
        Err(Error::InvalidWavelength { index: 2 })
    );
    nm[1] = f32::NAN;
    assert_eq!(
        LightGroupSet::new(nm, [c.weights(); 2], ["C", "A"], display),
        Err(Error::InvalidWavelength { index: 1 })
    );
    // The messages say what is wrong.
    let e = LightGroupSet::from_members([c, KQ_C_8_DISPLAY_P3]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "light group 1: the member's display is not member 0's"
    );
}

#[test]
fn length_mismatches_are_errors_and_write_nothing() {
    let set = LightGroupSet::from_members([KQ_C_8_SRGB, other_light(KQ_C_8_SRGB, "A")]).unwrap();
    let px = vec![[[0.5f32; 8]; 2]; 5];
    let mismatch = |what, expected, got| {
        Err(Error::LengthMismatch {
            what,
            expected,
            got,
        })
    };
    use spectral_quadrature::LengthOf::{InputPlane, Output, OutputPlane};

    let mut out = [[7.0f32; 3]; 4];
    assert_eq!(set.linear_rgb_batch(&px, &mut out), mismatch(Output, 5, 4));
    assert_eq!(out, [[7.0; 3]; 4]);
    let mut out8 = [[7u8; 3]; 6];
    assert_eq!(
        set.encode_u8_batch(GamutMapping::Clip, &px, &mut out8),
        mismatch(Output, 5, 6)
    );
    assert_eq!(out8, [[7; 3]; 6]);
    let mut out16 = [[7u16; 3]; 4];
    assert_eq!(
        set.encode_u16_batch(GamutMapping::Clip, &px, &mut out16),
        mismatch(Output, 5, 4)
    );
    assert_eq!(out16, [[7; 3]; 4]);

    // One plane of light 1 short: named after the planes before it.
    let long = [0.5f32; 5];
    let short = [0.5f32; 4];
    let mut planes: [[&[f32]; 8]; 2] = [[&long[..]; 8]; 2];
    planes[1][6] = &short;
    let mut out = [[7u8; 3]; 5];
    assert_eq!(
        set.encode_u8_planar_to_interleaved(GamutMapping::Clip, planes, &mut out),
        mismatch(InputPlane, 5, 4)
    );
    assert_eq!(out, [[7; 3]; 5]);
    let (mut r, mut g, mut b) = ([7.0f32; 5], [7.0f32; 5], [7.0f32; 5]);
    assert_eq!(
        set.linear_rgb_planar(planes, [&mut r, &mut g, &mut b]),
        mismatch(InputPlane, 5, 4)
    );
    assert_eq!(r, [7.0; 5]);
    // Outputs of the wrong length.
    let planes: [[&[f32]; 8]; 2] = [[&long[..]; 8]; 2];
    let (mut r, mut g, mut b) = ([7u8; 5], [7u8; 5], [7u8; 3]);
    assert_eq!(
        set.encode_u8_planar(GamutMapping::Clip, planes, [&mut r, &mut g, &mut b]),
        mismatch(OutputPlane, 5, 3)
    );
    assert_eq!(r, [7; 5]);
    let (mut r, mut g, mut b) = ([7u16; 5], [7u16; 6], [7u16; 5]);
    assert_eq!(
        set.encode_u16_planar(GamutMapping::Clip, planes, [&mut r, &mut g, &mut b]),
        mismatch(OutputPlane, 5, 6)
    );
    let mut out16 = [[7u16; 3]; 2];
    assert_eq!(
        set.encode_u16_planar_to_interleaved(GamutMapping::Clip, planes, &mut out16),
        mismatch(Output, 5, 2)
    );
    assert_eq!(out16, [[7; 3]; 2]);
}
