//! The planar (structure-of-arrays) path: bytes → a pixel count, samples, a length error.
//!
//! With matching lengths both planar calls return `Ok`: `linear_rgb_planar` equals
//! `linear_rgb` bit for bit on every pixel (NaN payloads aside), and `encode_u8_planar` equals
//! the per-pixel product clipped (NaN anywhere → black) and encoded with `srgb8_from_linear` on
//! the sRGB display with `Clip`, within `SRGB8_MAX_STEP_ERROR` of `encode_u8`, and exactly
//! `encode_u8` for every other display or mapping. With one plane or output too long or too
//! short, both return `Err(Error::LengthMismatch { .. })` and leave their outputs as they were.
#![no_main]

mod common;

use common::{same, Bytes, FOLDED_ROW1, FOLDED_ROW2, MAPPINGS};
use libfuzzer_sys::fuzz_target;
use spectral_quadrature::tables::displays;
use spectral_quadrature::{
    srgb8_from_linear, Display, Error, FoldedSet, GamutMapping, TransferFunction,
    SRGB8_MAX_STEP_ERROR,
};

/// At most this many pixels per input: several 16-pixel chunks and a partial one.
const MAX_PIXELS: usize = 70;

fuzz_target!(|data: &[u8]| {
    let mut b = Bytes::new(data);
    let pixels = usize::from(b.u8()) % (MAX_PIXELS + 1);
    let j = usize::from(b.u8()) % displays::ALL.len();
    let mapping = MAPPINGS[usize::from(b.u8()) % 2];
    let wrong = usize::from(b.u8());
    let values: Vec<f32> = (0..pixels * 6).map(|_| b.value()).collect();
    let display = &displays::ALL[j];
    let p6: [Vec<f32>; 6] = std::array::from_fn(|i| values[i * pixels..(i + 1) * pixels].to_vec());
    let p4: [Vec<f32>; 4] = std::array::from_fn(|i| p6[i].clone());
    check(&FOLDED_ROW2[j], display, mapping, &p4, wrong);
    check(&FOLDED_ROW1[j], display, mapping, &p6, wrong);
});

fn check<const N: usize>(
    set: &FoldedSet<N>,
    display: &Display,
    mapping: GamutMapping,
    planes: &[Vec<f32>; N],
    wrong: usize,
) {
    let n = planes[0].len();
    let samples: [&[f32]; N] = planes.each_ref().map(|p| &p[..]);
    let mut lin = [0, 1, 2].map(|_| vec![0.0f32; n]);
    let [r, g, b] = &mut lin;
    assert_eq!(set.linear_rgb_planar(samples, [r, g, b]), Ok(()));
    let mut out = vec![[0u8; 3]; n];
    assert_eq!(set.encode_u8_planar(mapping, samples, &mut out), Ok(()));
    let fast = display.transfer == TransferFunction::Srgb && mapping == GamutMapping::Clip;
    for p in 0..n {
        let s: [f32; N] = std::array::from_fn(|i| planes[i][p]);
        let rgb = set.linear_rgb(&s);
        assert!(
            (0..3).all(|c| same(lin[c][p], rgb[c])),
            "linear_rgb_planar N={N} pixel {p}: {:?} != {rgb:?}",
            [lin[0][p], lin[1][p], lin[2][p]]
        );
        let one = set.encode_u8(mapping, &s);
        if fast {
            let reference = if rgb.iter().any(|v| v.is_nan()) {
                [0; 3]
            } else {
                rgb.map(srgb8_from_linear)
            };
            assert_eq!(out[p], reference, "encode_u8_planar N={N} pixel {p}");
            assert!(
                (0..3).all(|c| out[p][c].abs_diff(one[c]) <= SRGB8_MAX_STEP_ERROR),
                "encode_u8_planar N={N} pixel {p}: {:?} vs encode_u8 {one:?}",
                out[p]
            );
        } else {
            assert_eq!(
                out[p], one,
                "encode_u8_planar {} {mapping:?} N={N} pixel {p}",
                display.name
            );
        }
    }

    // One plane (or the output) of another length: an error, outputs untouched.
    let other = if wrong % (n + 2) == n {
        n + 1
    } else {
        wrong % (n + 2)
    };
    let which = wrong % (N + 1);
    let mut short: [Vec<f32>; N] = planes.clone();
    let mut out_len = n;
    if which < N {
        short[which].resize(other, 0.5);
    } else {
        out_len = other;
    }
    let samples: [&[f32]; N] = short.each_ref().map(|p| &p[..]);
    let mut out = vec![[9u8; 3]; out_len];
    let result = set.encode_u8_planar(mapping, samples, &mut out);
    assert!(
        matches!(result, Err(Error::LengthMismatch { .. })),
        "{result:?}"
    );
    assert!(out.iter().all(|o| *o == [9; 3]));
    let mut lin = [0, 1, 2].map(|_| vec![-7.5f32; out_len]);
    let [r, g, b] = &mut lin;
    let result = set.linear_rgb_planar(samples, [r, g, b]);
    assert!(
        matches!(result, Err(Error::LengthMismatch { .. })),
        "{result:?}"
    );
    assert!(lin.iter().flatten().all(|v| *v == -7.5));
}
