//! Shared by the fuzz targets: the f64 reference, input decoding and the property checks.
//!
//! Every check panics (which libFuzzer reports as a crash) with the inputs as hex bit
//! patterns, so a failure can be reproduced from the message as well as from the artifact.
//!
//! The targets' library (`[lib]` of fuzz/Cargo.toml), built once with the sanitizer and
//! coverage flags cargo-fuzz gives every crate.

pub mod loops;

use std::sync::OnceLock;

use spectral_quadrature::tables::{self, displays, folded};
use spectral_quadrature::{
    f32_budget, quantize_u16, quantize_u8, Display, FoldedSet, GamutMapping, Rgb, WavelengthSet,
};
use spectral_quadrature_generator::{derive, Settings};

/// The runtime crate's data directory, which its build script bakes the tables from.
pub const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../data");

/// Both gamut mappings.
pub const MAPPINGS: [GamutMapping; 2] = [GamutMapping::Clip, GamutMapping::PreserveA];

/// The baked folded sets of Table 2 row 1 (N = 6), in the order of [`displays::ALL`].
pub const FOLDED_ROW1: [FoldedSet<6>; 4] = [
    folded::TABLE2_ROW1_SRGB,
    folded::TABLE2_ROW1_DISPLAY_P3,
    folded::TABLE2_ROW1_REC2020,
    folded::TABLE2_ROW1_MEYER_1987,
];

/// The baked folded sets of Table 2 row 2 (N = 4), in the order of [`displays::ALL`].
pub const FOLDED_ROW2: [FoldedSet<4>; 4] = [
    folded::TABLE2_ROW2_SRGB,
    folded::TABLE2_ROW2_DISPLAY_P3,
    folded::TABLE2_ROW2_REC2020,
    folded::TABLE2_ROW2_MEYER_1987,
];

/// The f64 weights of the derivation that the baked f32 tables were rounded from.
pub struct Reference {
    /// A, C1, C2 weights of `TABLE2_ROW1` (N = 6).
    pub row1: [Vec<f64>; 3],
    /// A, C1, C2 weights of `TABLE2_ROW2` (N = 4).
    pub row2: [Vec<f64>; 3],
    /// R, G, B weights of `TABLE2_ROW1` folded for each display of [`displays::ALL`].
    pub row1_folded: Vec<[Vec<f64>; 3]>,
    /// R, G, B weights of `TABLE2_ROW2` folded for each display of [`displays::ALL`].
    pub row2_folded: Vec<[Vec<f64>; 3]>,
}

/// The f64 reference, derived once per process (`derive(&Settings::new(DATA_DIR))`, the
/// settings the tables are baked with). The derived sets and displays are matched to the baked
/// ones by their wavelengths and primaries, and every baked weight is checked to be the f64
/// weight rounded to f32 (within one ulp), so a mix-up fails on the first input.
pub fn reference() -> &'static Reference {
    static REFERENCE: OnceLock<Reference> = OnceLock::new();
    REFERENCE.get_or_init(|| {
        let d =
            derive(&Settings::new(DATA_DIR)).expect("the f64 derivation with the default settings");
        let find_set = |wavelengths: &[f32]| {
            d.table2
                .iter()
                .find(|s| {
                    s.wavelengths_nm.len() == wavelengths.len()
                        && s.wavelengths_nm
                            .iter()
                            .zip(wavelengths)
                            .all(|(a, b)| (*a as f32) == *b)
                })
                .unwrap_or_else(|| panic!("no derived Table 2 set has wavelengths {wavelengths:?}"))
        };
        let row1 = find_set(&tables::TABLE2_ROW1.wavelengths_nm());
        let row2 = find_set(&tables::TABLE2_ROW2.wavelengths_nm());
        let matrices: Vec<_> = displays::ALL
            .iter()
            .map(|disp| {
                &d.displays
                    .iter()
                    .find(|(spec, _)| {
                        spec.primaries_xy
                            .iter()
                            .flatten()
                            .zip(disp.primaries_xy().iter().flatten())
                            .all(|(a, b)| (*a as f32) == *b)
                    })
                    .unwrap_or_else(|| panic!("no derived display matches {}", disp.name()))
                    .1
            })
            .collect();
        let r = Reference {
            row1: row1.weights.clone(),
            row2: row2.weights.clone(),
            row1_folded: matrices.iter().map(|m| d.folded(row1, m)).collect(),
            row2_folded: matrices.iter().map(|m| d.folded(row2, m)).collect(),
        };
        check_rounded("TABLE2_ROW1", &tables::TABLE2_ROW1.weights(), &r.row1);
        check_rounded("TABLE2_ROW2", &tables::TABLE2_ROW2.weights(), &r.row2);
        for j in 0..displays::ALL.len() {
            let name = displays::ALL[j].name();
            check_rounded(name, &FOLDED_ROW1[j].weights(), &r.row1_folded[j]);
            check_rounded(name, &FOLDED_ROW2[j].weights(), &r.row2_folded[j]);
        }
        r
    })
}

fn check_rounded<const N: usize>(what: &str, w32: &[[f32; N]; 3], w64: &[Vec<f64>; 3]) {
    for c in 0..3 {
        assert_eq!(w64[c].len(), N, "{what}: f64 row {c} has the wrong length");
        for i in 0..N {
            let (a, b) = (f64::from(w32[c][i]), w64[c][i]);
            assert!(
                (a - b).abs() <= f64::from(f32::EPSILON) * b.abs(),
                "{what}: baked weight [{c}][{i}] = {a:e} is not the f64 weight {b:e} rounded to f32"
            );
        }
    }
}

/// Every 4-byte little-endian chunk as an f32: all bit patterns (NaN payloads, ±Inf,
/// subnormals, ±MAX, −0.0) are reachable.
pub fn f32s(data: &[u8]) -> impl Iterator<Item = f32> + '_ {
    data.chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// Bits of a slice of f32, for messages.
pub fn hex<const K: usize>(v: &[f32; K]) -> [String; K] {
    v.map(|x| format!("{:#010x}", x.to_bits()))
}

/// Same value, or both NaN (Rust does not promise NaN payloads, so a batch and a single call
/// may differ in the payload only).
pub fn same(a: f32, b: f32) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

/// Values a byte-driven input can pick exactly, then step by a few ulps: the breakpoints of
/// the transfer functions and quantizers, the lookup tables' nodes and the f32 landmarks.
pub const INTERESTING: [f32; 32] = [
    0.0,
    -0.0,
    1.0,
    -1.0,
    0.5,
    0.25,
    0.75,
    0.003_130_8,   // sRGB encode breakpoint
    0.040_45,      // sRGB decode breakpoint
    0.040_449_936, // 12.92 · 0.0031308
    1.0 / 255.0,
    0.5 / 255.0,
    254.5 / 255.0,
    0.5 / 65535.0,
    65534.5 / 65535.0,
    0.2,
    0.7,
    0.9,
    1.0 / 3.0,
    2.0 / 3.0,
    2.2,
    2.4,
    f32::MIN_POSITIVE,
    1.0e-45, // the smallest subnormal
    f32::EPSILON,
    f32::MAX,
    f32::MIN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::NAN,
    1.0e20,
    106.856_46, // UNIT_SPECTRUM_Y
];

/// `x` moved by `k` steps through the ordered f32 values (−0.0 and +0.0 are neighbours;
/// saturates at ±Inf; NaN stays NaN).
pub fn step_ulps(x: f32, k: i32) -> f32 {
    if x.is_nan() {
        return x;
    }
    // Map to a monotone integer key: negative floats reversed below the positive ones.
    let bits = x.to_bits() as i32;
    let key = if bits < 0 { i32::MIN - bits - 1 } else { bits };
    let inf = f32::INFINITY.to_bits() as i32;
    let key = (i64::from(key) + i64::from(k)).clamp(-i64::from(inf) - 1, i64::from(inf)) as i32;
    let bits = if key < 0 { i32::MIN - key - 1 } else { key };
    f32::from_bits(bits as u32)
}

/// A byte reader that never fails: past the end it reads zeros.
pub struct Bytes<'a> {
    data: &'a [u8],
}

impl<'a> Bytes<'a> {
    pub fn new(data: &'a [u8]) -> Self {
        Bytes { data }
    }

    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    pub fn u8(&mut self) -> u8 {
        match self.data.split_first() {
            Some((&b, rest)) => {
                self.data = rest;
                b
            }
            None => 0,
        }
    }

    pub fn f32_bits(&mut self) -> f32 {
        f32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }

    /// A tag byte, then either a raw f32 (any bit pattern) or an [`INTERESTING`] value moved
    /// by −8..=7 ulps: finds breakpoint and ulp-level problems that raw bits almost never hit.
    pub fn value(&mut self) -> f32 {
        let tag = self.u8();
        if tag < 0x80 {
            self.f32_bits()
        } else {
            let base = INTERESTING[usize::from(tag & 0x1f)];
            let offset = i32::from(self.u8() & 0x0f) - 8;
            step_ulps(base, offset)
        }
    }
}

/// Checks one 3×N product (`ac1c2` or `linear_rgb`) against the f64 weights.
///
/// - a NaN sample gives NaN in every channel whose weight for it is non-zero;
/// - otherwise an infinite sample with a non-zero weight gives a non-finite channel;
/// - for finite samples whose f32 products and sum are finite, the channel is within
///   `f32_budget(N, Σ|w_i s_i|)` of the exact sum with the f64 weights (computed in f64).
pub fn check_product<const N: usize>(
    what: &str,
    w32: &[[f32; N]; 3],
    w64: &[Vec<f64>; 3],
    s: &[f32; N],
    out: [f32; 3],
) {
    for c in 0..3 {
        let nan_in = (0..N).any(|i| s[i].is_nan() && w32[c][i] != 0.0);
        let inf_in = (0..N).any(|i| s[i].is_infinite() && w32[c][i] != 0.0);
        if nan_in {
            assert!(
                out[c].is_nan(),
                "{what}: channel {c} = {} is not NaN for NaN samples {:?}",
                out[c],
                hex(s)
            );
            continue;
        }
        if inf_in {
            assert!(
                !out[c].is_finite(),
                "{what}: channel {c} = {} is finite for infinite samples {:?}",
                out[c],
                hex(s)
            );
            continue;
        }
        let products_finite = (0..N).all(|i| (w32[c][i] * s[i]).is_finite());
        if !(s.iter().all(|v| v.is_finite()) && products_finite && out[c].is_finite()) {
            continue;
        }
        let mut exact = 0.0f64;
        let mut abs_sum = 0.0f64;
        for i in 0..N {
            let p = w64[c][i] * f64::from(s[i]);
            exact += p;
            abs_sum += p.abs();
        }
        let budget = f32_budget(N, abs_sum);
        let err = (f64::from(out[c]) - exact).abs();
        assert!(
            err <= budget,
            "{what}: channel {c} = {:e} is {err:e} from the f64 sum {exact:e}, over the budget \
             {budget:e} (Σ|w·s| = {abs_sum:e}); samples {:?}",
            out[c],
            hex(s)
        );
    }
}

pub fn in01(v: f32) -> bool {
    (0.0..=1.0).contains(&v)
}

pub fn clamp01(v: f32) -> f32 {
    if v > 0.0 {
        v.min(1.0)
    } else {
        0.0
    }
}

/// Everything a display does to one linear colour, with both mappings:
///
/// - `map_gamut` and `encode` give values in 0..=1; `encode` is `map_gamut` then the
///   transfer function per channel; `encode_u8`/`encode_u16` are `map_gamut` then the transfer
///   function's own 8- and 16-bit encoders, within one step of `encode` quantized;
/// - a NaN channel gives linear black (and encoded `[0, 0, 0]` when the transfer function
///   sends 0 to 0);
/// - `Clip` clamps each channel; `PreserveA` clips colours with an infinite channel, and
///   otherwise keeps A (clamped to black..white) and leaves in-gamut colours alone.
pub fn check_display(display: &Display, rgb: [f32; 3]) {
    let tf = display.transfer();
    let zero_is_black = Rgb::ALL.into_iter().all(|c| tf.encode(c, 0.0) == 0.0);
    let has_nan = rgb.iter().any(|v| v.is_nan());
    let has_inf = rgb.iter().any(|v| v.is_infinite());
    for mapping in MAPPINGS {
        let ctx = || {
            format!(
                "{} {:?} {:?}, rgb {:?}",
                display.name(),
                tf,
                mapping,
                hex(&rgb)
            )
        };
        let m = display.map_gamut(mapping, rgb);
        assert!(
            m.iter().all(|&v| in01(v)),
            "map_gamut {m:?} not in 0..=1: {}",
            ctx()
        );
        let e = display.encode(mapping, rgb);
        assert!(
            e.iter().all(|&v| in01(v)),
            "encode {e:?} not in 0..=1: {}",
            ctx()
        );
        let expect = [
            tf.encode(Rgb::R, m[0]),
            tf.encode(Rgb::G, m[1]),
            tf.encode(Rgb::B, m[2]),
        ];
        assert_eq!(e, expect, "encode is not map_gamut + transfer: {}", ctx());
        // The quantized encoders are the transfer function's own per channel (8 bits: the exact
        // curve rounded for sRGB and baked γ; 16 bits: the f32 curve), so they are within one
        // step of `encode` quantized, which rounds twice.
        let q8 = display.encode_u8(mapping, rgb);
        let q16 = display.encode_u16(mapping, rgb);
        for c in Rgb::ALL {
            let i = c.index();
            assert_eq!(
                (q8[i], q16[i]),
                (tf.encode_u8(c, m[i]), tf.encode_u16(c, m[i])),
                "encode_u8/u16 is not map_gamut + the transfer's own: {}",
                ctx()
            );
            assert!(
                q8[i].abs_diff(quantize_u8(e[i])) <= 1 && q16[i].abs_diff(quantize_u16(e[i])) <= 1,
                "encode_u8/u16 more than one step from encode quantized: {}",
                ctx()
            );
        }
        if has_nan {
            assert_eq!(m, [0.0; 3], "NaN did not map to black: {}", ctx());
            if zero_is_black {
                assert_eq!(e, [0.0; 3], "NaN did not encode to black: {}", ctx());
                assert_eq!(q8, [0; 3], "NaN did not encode_u8 to black: {}", ctx());
                assert_eq!(q16, [0; 3], "NaN did not encode_u16 to black: {}", ctx());
            }
            continue;
        }
        let clipped = rgb.map(clamp01);
        match mapping {
            GamutMapping::Clip => assert_eq!(m, clipped, "Clip is not a clamp: {}", ctx()),
            GamutMapping::PreserveA if has_inf => {
                assert_eq!(
                    m,
                    clipped,
                    "PreserveA with an infinite channel is not Clip: {}",
                    ctx()
                )
            }
            GamutMapping::PreserveA => check_preserve_a(display.a_from_rgb(), rgb, m, &ctx),
            // `GamutMapping` is non_exhaustive: a new mapping needs its own property here.
            other => panic!("no property for {other:?} yet: {}", ctx()),
        }
    }
}

/// `PreserveA` on a finite colour: the output's A is the input's A clamped to
/// 0..=A(white), within 8 ε of the magnitudes involved (the f32 sum A may cancel); an in-gamut
/// colour comes back within 8 ε per channel. Skipped when the f32 sum A overflows, where the
/// runtime's A is ±Inf or NaN by IEEE rules and the colour goes to white or black.
fn check_preserve_a(a: [f32; 3], rgb: [f32; 3], out: [f32; 3], ctx: &dyn Fn() -> String) {
    let a_f32 = a[0] * rgb[0] + a[1] * rgb[1] + a[2] * rgb[2];
    if !a_f32.is_finite() {
        return;
    }
    let eps = f64::from(f32::EPSILON);
    let a64 = a.map(f64::from);
    let a_white: f64 = a64.iter().sum();
    let a_in: f64 = (0..3).map(|c| a64[c] * f64::from(rgb[c])).sum();
    let abs_in: f64 = (0..3).map(|c| (a64[c] * f64::from(rgb[c])).abs()).sum();
    let a_out: f64 = (0..3).map(|c| a64[c] * f64::from(out[c])).sum();
    let expect = a_in.clamp(0.0, a_white);
    let tol = 8.0 * eps * (abs_in + a64.iter().map(|v| v.abs()).sum::<f64>());
    assert!(
        (a_out - expect).abs() <= tol,
        "PreserveA changed A: in {a_in:e} (clamped {expect:e}), out {a_out:e} ({out:?}), \
         tolerance {tol:e}: {}",
        ctx()
    );
    if a.iter().all(|&v| v > 0.0) && rgb.iter().all(|&v| in01(v)) {
        for c in 0..3 {
            assert!(
                (f64::from(out[c]) - f64::from(rgb[c])).abs() <= 8.0 * eps,
                "PreserveA moved an in-gamut colour to {out:?}: {}",
                ctx()
            );
        }
    }
}

/// `ac1c2`, `xyz` of a wavelength set on one pixel, checked against the reference.
pub fn check_set<const N: usize>(
    what: &str,
    set: &WavelengthSet<N>,
    w64: &[Vec<f64>; 3],
    s: &[f32; N],
) -> [f32; 3] {
    let ac = set.ac1c2(s);
    check_product(what, &set.weights(), w64, s, ac);
    let xyz = set.xyz(s);
    let expect = spectral_quadrature::xyz_from_ac1c2(ac);
    assert!(
        (0..3).all(|c| same(xyz[c], expect[c])),
        "{what}: xyz {xyz:?} is not xyz_from_ac1c2(ac1c2) = {expect:?}; samples {:?}",
        hex(s)
    );
    ac
}

/// `linear_rgb`, `encode_u8`, `encode_u16` of a folded set on one pixel, checked against the
/// reference and [`check_display`].
pub fn check_folded<const N: usize>(
    what: &str,
    set: &FoldedSet<N>,
    display: &Display,
    w64: &[Vec<f64>; 3],
    s: &[f32; N],
) -> [f32; 3] {
    let lin = set.linear_rgb(s);
    check_product(what, &set.weights(), w64, s, lin);
    check_display(display, lin);
    for mapping in MAPPINGS {
        let q8 = set.encode_u8(mapping, s);
        let q16 = set.encode_u16(mapping, s);
        assert_eq!(
            q8,
            display.encode_u8(mapping, lin),
            "{what} {mapping:?}: encode_u8 differs from the display's on linear_rgb; samples {:?}",
            hex(s)
        );
        assert_eq!(
            q16,
            display.encode_u16(mapping, lin),
            "{what} {mapping:?}: encode_u16 differs from the display's on linear_rgb; samples {:?}",
            hex(s)
        );
        if lin.iter().any(|v| v.is_nan()) {
            assert_eq!(
                q8,
                [0; 3],
                "{what} {mapping:?}: NaN not black; samples {:?}",
                hex(s)
            );
            assert_eq!(
                q16,
                [0; 3],
                "{what} {mapping:?}: NaN not black; samples {:?}",
                hex(s)
            );
        }
    }
    lin
}
