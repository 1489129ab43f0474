//! The batch APIs: bytes → a pixel count, a length error and samples.
//!
//! With matching lengths every batch call returns `Ok` and equals the per-pixel call on each
//! pixel (NaN payloads aside, which Rust does not promise). With mismatched lengths every batch
//! call returns `Err(Error::LengthMismatch { inputs, outputs })` with the two lengths and
//! leaves the output slice exactly as it was.
#![no_main]

mod common;

use common::{same, Bytes, FOLDED_ROW1, FOLDED_ROW2, MAPPINGS};
use libfuzzer_sys::fuzz_target;
use spectral_quadrature::tables::{displays, TABLE2_ROW1, TABLE2_ROW2};
use spectral_quadrature::{Error, FoldedSet, WavelengthSet};

/// At most this many pixels per input.
const MAX_PIXELS: usize = 64;

fuzz_target!(|data: &[u8]| {
    let mut b = Bytes::new(data);
    // Header: requested pixel count, output length error, fill pattern for untouched outputs.
    let pixels = usize::from(b.u8()) % (MAX_PIXELS + 1);
    let delta = i32::from(b.u8() as i8);
    let fill = b.f32_bits();
    let fill_u8 = b.u8();
    let fill_u16 = u16::from(b.u8()) << 8 | u16::from(b.u8());
    // Samples: as many as the rest holds, up to `pixels` pixels (zeros past the end).
    let floats: Vec<f32> = (0..pixels * 6).map(|_| b.f32_bits()).collect();

    let s4: Vec<[f32; 4]> = floats
        .chunks_exact(4)
        .take(pixels)
        .map(|c| c.try_into().unwrap())
        .collect();
    let s6: Vec<[f32; 6]> = floats
        .chunks_exact(6)
        .take(pixels)
        .map(|c| c.try_into().unwrap())
        .collect();
    // A wrong output length, never equal to `pixels`: pixels + delta when that is a length
    // other than `pixels`, else a longer one.
    let wrong = match pixels as i64 + i64::from(delta) {
        n if n < 0 => pixels + 1 + (delta.unsigned_abs() as usize % 3),
        n if n as usize == pixels => pixels + 1,
        n => n as usize,
    };
    assert_ne!(wrong, pixels);

    check_set(&TABLE2_ROW2, &s4, wrong, fill);
    check_set(&TABLE2_ROW1, &s6, wrong, fill);
    for (j, display) in displays::ALL.iter().enumerate() {
        check_folded(
            &FOLDED_ROW2[j],
            display,
            &s4,
            wrong,
            (fill, fill_u8, fill_u16),
        );
        check_folded(
            &FOLDED_ROW1[j],
            display,
            &s6,
            wrong,
            (fill, fill_u8, fill_u16),
        );
    }
});

fn mismatch(result: Result<(), Error>, inputs: usize, outputs: usize, what: &str) {
    assert_eq!(
        result,
        Err(Error::LengthMismatch { inputs, outputs }),
        "{what}: {inputs} inputs, {outputs} outputs"
    );
}

fn untouched<T: Copy + PartialEq + std::fmt::Debug>(out: &[T], fill: T, what: &str) {
    assert!(
        out.iter().all(|&o| o == fill),
        "{what}: a failed call wrote its output: {out:?}"
    );
}

fn untouched_f32(out: &[[f32; 3]], fill: f32, what: &str) {
    assert!(
        out.iter().flatten().all(|o| o.to_bits() == fill.to_bits()),
        "{what}: a failed call wrote its output: {out:?}"
    );
}

fn check_set<const N: usize>(set: &WavelengthSet<N>, s: &[[f32; N]], wrong: usize, fill: f32) {
    let mut out = vec![[fill; 3]; s.len()];
    assert_eq!(
        set.ac1c2_batch(s, &mut out),
        Ok(()),
        "ac1c2_batch N={N}, {} pixels",
        s.len()
    );
    for (p, (o, px)) in out.iter().zip(s).enumerate() {
        let one = set.ac1c2(px);
        assert!(
            (0..3).all(|c| same(o[c], one[c])),
            "ac1c2_batch N={N} pixel {p}: {o:?} != ac1c2 {one:?}"
        );
    }
    // An output of the wrong length.
    let mut out = vec![[fill; 3]; wrong];
    mismatch(set.ac1c2_batch(s, &mut out), s.len(), wrong, "ac1c2_batch");
    untouched_f32(&out, fill, "ac1c2_batch");
}

fn check_folded<const N: usize>(
    set: &FoldedSet<N>,
    display: &spectral_quadrature::Display,
    s: &[[f32; N]],
    wrong: usize,
    (fill, fill_u8, fill_u16): (f32, u8, u16),
) {
    let name = display.name;
    let n = s.len();
    let mut lin = vec![[fill; 3]; n];
    assert_eq!(
        set.linear_rgb_batch(s, &mut lin),
        Ok(()),
        "linear_rgb_batch {name} N={N}"
    );
    for (p, (o, px)) in lin.iter().zip(s).enumerate() {
        let one = set.linear_rgb(px);
        assert!(
            (0..3).all(|c| same(o[c], one[c])),
            "linear_rgb_batch {name} N={N} pixel {p}: {o:?} != linear_rgb {one:?}"
        );
    }
    let mut bad = vec![[fill; 3]; wrong];
    mismatch(
        set.linear_rgb_batch(s, &mut bad),
        n,
        wrong,
        "linear_rgb_batch",
    );
    untouched_f32(&bad, fill, "linear_rgb_batch");

    for mapping in MAPPINGS {
        let mut q8 = vec![[fill_u8; 3]; n];
        let mut q16 = vec![[fill_u16; 3]; n];
        assert_eq!(set.encode_u8_batch(mapping, s, &mut q8), Ok(()));
        assert_eq!(set.encode_u16_batch(mapping, s, &mut q16), Ok(()));
        for p in 0..n {
            assert_eq!(
                q8[p],
                set.encode_u8(mapping, &s[p]),
                "encode_u8_batch {name} {mapping:?} N={N} pixel {p}"
            );
            assert_eq!(
                q16[p],
                set.encode_u16(mapping, &s[p]),
                "encode_u16_batch {name} {mapping:?} N={N} pixel {p}"
            );
        }
        let mut bad8 = vec![[fill_u8; 3]; wrong];
        mismatch(
            set.encode_u8_batch(mapping, s, &mut bad8),
            n,
            wrong,
            "encode_u8_batch",
        );
        untouched(&bad8, [fill_u8; 3], "encode_u8_batch");
        let mut bad16 = vec![[fill_u16; 3]; wrong];
        mismatch(
            set.encode_u16_batch(mapping, s, &mut bad16),
            n,
            wrong,
            "encode_u16_batch",
        );
        untouched(&bad16, [fill_u16; 3], "encode_u16_batch");
    }
}
