//! Light-group sets on arbitrary accumulators: raw bytes → f32 (every bit pattern: NaN
//! payloads, ±Inf, subnormals, ±MAX, −0.0) → one-light and two-light `LightGroupSet`s at
//! N = 8, on a display the first byte picks (sRGB, Display P3, a γ, linear), through every
//! path: `linear_rgb`, `encode_u8`, `encode_u16`, their `_batch` forms and the five planar
//! functions, with both gamut mappings.
//!
//! Checked: no panic; with one light, every value equals the member `FoldedSet`'s own (per
//! pixel); with two, `linear_rgb` is the members' sum in light order and the encoders encode
//! it as the display does; batch and planar paths give the per-pixel bits and bytes (NaN
//! payloads aside).
#![no_main]

use common::{same, MAPPINGS};
use libfuzzer_sys::fuzz_target;
use spectral_quadrature::tables::folded::{KQ_C_8_DISPLAY_P3, KQ_C_8_SRGB};
use spectral_quadrature::{FoldedSet, LightGroupSet, Samples, TransferFunction};

/// At most this many pixels per input (longer inputs are truncated).
const MAX_PIXELS: usize = 20;

fn same3(a: [f32; 3], b: [f32; 3]) -> bool {
    (0..3).all(|c| same(a[c], b[c]))
}

/// A second light at `set`'s nodes: its weights scaled per node.
fn warm(set: FoldedSet<8>) -> FoldedSet<8> {
    let w = set
        .weights()
        .map(|row| std::array::from_fn(|i| row[i] * (0.6 + 0.1 * i as f32)));
    FoldedSet::new(
        set.wavelengths_nm(),
        w,
        Samples::Reflectance { light: "A" },
        set.display(),
    )
    .unwrap()
}

/// Every batch and planar path of `set` against its per-pixel functions.
fn check_paths<const L: usize>(set: &LightGroupSet<8, L>, px: &[[[f32; 8]; L]]) {
    let n = px.len();
    let planes: [[Vec<f32>; 8]; L] =
        std::array::from_fn(|l| std::array::from_fn(|i| px.iter().map(|g| g[l][i]).collect()));
    let refs: [[&[f32]; 8]; L] = planes.each_ref().map(|l| l.each_ref().map(|p| &p[..]));

    let mut batch = vec![[0f32; 3]; n];
    set.linear_rgb_batch(px, &mut batch).unwrap();
    let (mut r, mut g, mut b) = (vec![0f32; n], vec![0f32; n], vec![0f32; n]);
    set.linear_rgb_planar(refs, [&mut r, &mut g, &mut b])
        .unwrap();
    for (p, groups) in px.iter().enumerate() {
        let one = set.linear_rgb(groups);
        assert!(same3(batch[p], one), "batch pixel {p}: {groups:?}");
        assert!(
            same3([r[p], g[p], b[p]], one),
            "planar pixel {p}: {groups:?}"
        );
    }
    for m in MAPPINGS {
        let want8: Vec<[u8; 3]> = px.iter().map(|g| set.encode_u8(m, g)).collect();
        let want16: Vec<[u16; 3]> = px.iter().map(|g| set.encode_u16(m, g)).collect();
        let mut o8 = vec![[0u8; 3]; n];
        set.encode_u8_batch(m, px, &mut o8).unwrap();
        assert_eq!(o8, want8);
        set.encode_u8_planar_to_interleaved(m, refs, &mut o8)
            .unwrap();
        assert_eq!(o8, want8);
        let (mut r, mut g, mut b) = (vec![0u8; n], vec![0u8; n], vec![0u8; n]);
        set.encode_u8_planar(m, refs, [&mut r, &mut g, &mut b])
            .unwrap();
        let mut o16 = vec![[0u16; 3]; n];
        set.encode_u16_batch(m, px, &mut o16).unwrap();
        assert_eq!(o16, want16);
        set.encode_u16_planar_to_interleaved(m, refs, &mut o16)
            .unwrap();
        assert_eq!(o16, want16);
        let (mut r16, mut g16, mut b16) = (vec![0u16; n], vec![0u16; n], vec![0u16; n]);
        set.encode_u16_planar(m, refs, [&mut r16, &mut g16, &mut b16])
            .unwrap();
        for p in 0..n {
            assert_eq!([r[p], g[p], b[p]], want8[p], "u8 planes, pixel {p}");
            assert_eq!([r16[p], g16[p], b16[p]], want16[p], "u16 planes, pixel {p}");
            // The encoders encode the sum as the display does.
            let rgb = set.linear_rgb(&px[p]);
            assert_eq!(want8[p], set.display().encode_u8(m, rgb));
            assert_eq!(want16[p], set.display().encode_u16(m, rgb));
        }
    }
}

fuzz_target!(|data: &[u8]| {
    let Some((&pick, rest)) = data.split_first() else {
        return;
    };
    let base = match pick % 4 {
        0 => KQ_C_8_SRGB,
        1 => KQ_C_8_DISPLAY_P3,
        2 => on(KQ_C_8_SRGB, TransferFunction::Gamma(2.2)),
        _ => on(KQ_C_8_SRGB, TransferFunction::Linear),
    };
    let (c, a) = (base, warm(base));
    let one = LightGroupSet::from_members([c]).unwrap();
    let two = LightGroupSet::from_members([c, a]).unwrap();

    let values: Vec<f32> = common::f32s(rest).take(MAX_PIXELS * 16).collect();
    let px2: Vec<[[f32; 8]; 2]> = values
        .chunks_exact(16)
        .map(|v| std::array::from_fn(|l| std::array::from_fn(|i| v[l * 8 + i])))
        .collect();
    let px1: Vec<[[f32; 8]; 1]> = values
        .chunks_exact(8)
        .map(|v| [std::array::from_fn(|i| v[i])])
        .collect();

    for g in &px1 {
        assert!(same3(one.linear_rgb(g), c.linear_rgb(&g[0])), "{g:?}");
        for m in MAPPINGS {
            assert_eq!(one.encode_u8(m, g), c.encode_u8(m, &g[0]), "{m:?} {g:?}");
            assert_eq!(one.encode_u16(m, g), c.encode_u16(m, &g[0]), "{m:?} {g:?}");
        }
    }
    for g in &px2 {
        let (x, y) = (c.linear_rgb(&g[0]), a.linear_rgb(&g[1]));
        let sum = [x[0] + y[0], x[1] + y[1], x[2] + y[2]];
        assert!(same3(two.linear_rgb(g), sum), "{g:?}");
    }
    check_paths(&one, &px1);
    check_paths(&two, &px2);
});

/// `set` with its display's transfer function replaced.
fn on(set: FoldedSet<8>, transfer: TransferFunction) -> FoldedSet<8> {
    let display = set.display().with_transfer(transfer);
    FoldedSet::new(set.wavelengths_nm(), set.weights(), set.samples(), display).unwrap()
}
