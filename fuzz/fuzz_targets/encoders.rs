//! Transfer functions, quantizers and display encoding on arbitrary values.
//!
//! Bytes → a transfer function (`Linear`, `Srgb`, `Gamma(g)` with g from the bytes: NaN, 0,
//! negative, subnormal, huge ..., or `Lut` from a few static tables), a channel index (any
//! `usize`-sized byte, 3 and up included), then pairs of values (raw f32 bits, or landmarks
//! such as the sRGB breakpoints moved by a few ulps; see `common::Bytes::value`).
//!
//! Checked: `encode`/`decode` in 0..=1 and never NaN; NaN and ≤ 0 give exactly 0, ≥ 1 exactly 1
//! (every variant, lookup tables that do not span 0..=1 included);
//! `Gamma` with a γ that is not finite and positive is `Linear`; channels ≥ 3 are blue;
//! monotonic (x ≤ y → encode(x) ≤ encode(y), same for decode); `Linear` and `Srgb`
//! round-trip; `quantize_u8`/`quantize_u16` round to nearest, clamp, NaN → 0, monotonic;
//! `Display::encode_u8`/`encode_u16` for every display with this transfer function, both
//! mappings (see `common::check_display`); `ChannelLuts::new` rejects bad tables.
#![no_main]

use common::{check_display, clamp01, in01, step_ulps, Bytes};
use libfuzzer_sys::fuzz_target;
use spectral_quadrature::tables::displays;
use spectral_quadrature::{quantize_u16, quantize_u8, ChannelLuts, Error, Rgb, TransferFunction};

/// Valid lookup tables: identity, a knee, a flat stretch, one that does not span 0..=1, a
/// constant, subnormal entries, a 17-entry γ 2.2 table, a low entry before the top, a step.
const LUTS: [&[f32]; 9] = [
    &[0.0, 1.0],
    &[0.0, 0.7, 1.0],
    &[0.0, 0.2, 0.2, 0.2, 0.9, 1.0],
    &[0.1, 0.5, 0.6],
    &[0.5, 0.5],
    &[0.0, 1.0e-45, 1.0e-40, 1.0],
    &[
        0.0, 0.2835781, 0.3886016, 0.4672465, 0.5325205, 0.5893678, 0.6402917, 0.6867651,
        0.7297401, 0.7698734, 0.8076407, 0.8433989, 0.8774243, 0.9099355, 0.9411092, 0.9710904,
        1.0,
    ],
    &[0.0, 0.1, 1.0],
    &[0.0, 0.0, 0.0, 1.0],
];

/// Invalid tables: too short, not finite, outside 0..=1, decreasing.
const BAD_LUTS: [&[f32]; 7] = [
    &[],
    &[0.5],
    &[0.0, f32::NAN],
    &[0.0, f32::INFINITY],
    &[-0.1, 1.0],
    &[0.0, 1.5],
    &[0.0, 0.6, 0.5, 1.0],
];

/// At most this many value pairs per input.
const MAX_PAIRS: usize = 32;

fuzz_target!(|data: &[u8]| {
    let mut b = Bytes::new(data);
    let tf = match b.u8() % 4 {
        0 => TransferFunction::Linear,
        1 => TransferFunction::Srgb,
        2 => TransferFunction::Gamma(b.value()),
        _ => {
            let pick = |b: &mut Bytes| LUTS[usize::from(b.u8()) % LUTS.len()];
            let tables = [pick(&mut b), pick(&mut b), pick(&mut b)];
            let luts = ChannelLuts::new(tables).expect("a valid table was rejected");
            for (c, t) in Rgb::ALL.into_iter().zip(&tables) {
                assert_eq!(luts.table(c), *t, "ChannelLuts::table({c:?})");
            }
            // One bad table among good ones is reported with its channel.
            let bad = BAD_LUTS[usize::from(b.u8()) % BAD_LUTS.len()];
            let at = usize::from(b.u8()) % 3;
            let mut with_bad = tables;
            with_bad[at] = bad;
            assert_eq!(
                ChannelLuts::new(with_bad),
                Err(Error::InvalidLut {
                    channel: Rgb::ALL[at]
                }),
                "bad table {bad:?} at channel {at}"
            );
            TransferFunction::Lut(luts)
        }
    };
    let c = Rgb::ALL[usize::from(b.u8()) % 3];
    check_fixed_points(&tf);

    for _ in 0..MAX_PAIRS {
        if b.is_empty() {
            break;
        }
        let x = b.value();
        let mode = b.u8();
        // Half the pairs are neighbours within ±64 ulps: where monotonicity breaks if it does.
        let y = if mode & 1 == 0 {
            step_ulps(x, i32::from(mode as i8) / 2)
        } else {
            b.value()
        };
        check_value(&tf, c, x);
        check_value(&tf, c, y);
        check_monotonic(&tf, c, x, y);
        check_quantize(x, y);
        let rgb = [x, y, b.value()];
        for display in displays::ALL {
            check_display(&display.with_transfer(tf), rgb);
        }
    }
});

fn gamma_is_valid(tf: &TransferFunction) -> bool {
    match *tf {
        TransferFunction::Gamma(g) => g.is_finite() && g > 0.0,
        _ => true,
    }
}

/// Black and white are fixed points of every transfer function, lookup tables whose ends are
/// not 0 and 1 included (the documented "exactly 0" and "exactly 1").
fn check_fixed_points(tf: &TransferFunction) {
    for c in Rgb::ALL {
        assert_eq!(tf.encode(c, 0.0), 0.0, "{tf:?} channel {c:?}: encode(0)");
        assert_eq!(tf.encode(c, 1.0), 1.0, "{tf:?} channel {c:?}: encode(1)");
        assert_eq!(tf.decode(c, 0.0), 0.0, "{tf:?} channel {c:?}: decode(0)");
        assert_eq!(tf.decode(c, 1.0), 1.0, "{tf:?} channel {c:?}: decode(1)");
    }
}

fn check_value(tf: &TransferFunction, c: Rgb, x: f32) {
    let bits = format!("{:#010x}", x.to_bits());
    let e = tf.encode(c, x);
    let d = tf.decode(c, x);
    assert!(
        in01(e),
        "{tf:?} channel {c:?}: encode({bits}) = {e} not in 0..=1"
    );
    assert!(
        in01(d),
        "{tf:?} channel {c:?}: decode({bits}) = {d} not in 0..=1"
    );
    // NaN and ≤ 0 as 0, ≥ 1 as 1.
    let k = clamp01(x);
    assert_eq!(
        e.to_bits(),
        tf.encode(c, k).to_bits(),
        "{tf:?} {c:?}: encode({bits}) != encode({k})"
    );
    assert_eq!(
        d.to_bits(),
        tf.decode(c, k).to_bits(),
        "{tf:?} {c:?}: decode({bits}) != decode({k})"
    );
    match *tf {
        TransferFunction::Linear => {
            assert_eq!(e, k, "Linear encode({bits})");
            assert_eq!(tf.decode(c, e), k, "Linear decode(encode({bits}))");
        }
        TransferFunction::Gamma(_) if !gamma_is_valid(tf) => {
            let lin = TransferFunction::Linear;
            assert_eq!(
                e,
                lin.encode(c, x),
                "{tf:?} (invalid γ) encode({bits}) is not Linear"
            );
            assert_eq!(
                d,
                lin.decode(c, x),
                "{tf:?} (invalid γ) decode({bits}) is not Linear"
            );
        }
        TransferFunction::Srgb => {
            // decode inverts encode: measured over every f32 in 0..=1 the error is below
            // 1.5e-7; allow 1e-6.
            let back = tf.decode(c, e);
            assert!(
                (back - k).abs() <= 1.0e-6,
                "Srgb decode(encode({bits})) = {back:e}, not {k:e}"
            );
        }
        _ => {}
    }
}

fn check_monotonic(tf: &TransferFunction, c: Rgb, x: f32, y: f32) {
    if x.is_nan() || y.is_nan() {
        return;
    }
    let (lo, hi) = if x <= y { (x, y) } else { (y, x) };
    let (bl, bh) = (lo.to_bits(), hi.to_bits());
    let (el, eh) = (tf.encode(c, lo), tf.encode(c, hi));
    assert!(
        el <= eh,
        "{tf:?} channel {c:?}: encode not monotonic: encode({lo:e} = {bl:#010x}) = {el:e} > \
         encode({hi:e} = {bh:#010x}) = {eh:e}"
    );
    let (dl, dh) = (tf.decode(c, lo), tf.decode(c, hi));
    assert!(
        dl <= dh,
        "{tf:?} channel {c:?}: decode not monotonic: decode({lo:e} = {bl:#010x}) = {dl:e} > \
         decode({hi:e} = {bh:#010x}) = {dh:e}"
    );
}

fn check_quantize(x: f32, y: f32) {
    for v in [x, y] {
        let (q8, q16) = (quantize_u8(v), quantize_u16(v));
        let bits = format!("{:#010x}", v.to_bits());
        if v.is_nan() || v <= 0.0 {
            assert_eq!((q8, q16), (0, 0), "quantize({bits})");
        } else if v >= 1.0 {
            assert_eq!((q8, q16), (255, 65535), "quantize({bits})");
        } else {
            // Round to nearest: within half a step (plus the f32 rounding of v · 255).
            let e8 = (f64::from(q8) - f64::from(v) * 255.0).abs();
            let e16 = (f64::from(q16) - f64::from(v) * 65535.0).abs();
            assert!(e8 <= 0.5 + 1e-4, "quantize_u8({bits}) = {q8}");
            assert!(e16 <= 0.5 + 1e-2, "quantize_u16({bits}) = {q16}");
        }
    }
    if !x.is_nan() && !y.is_nan() {
        let (lo, hi) = if x <= y { (x, y) } else { (y, x) };
        assert!(
            quantize_u8(lo) <= quantize_u8(hi),
            "quantize_u8 not monotonic at {lo:e}, {hi:e}"
        );
        assert!(
            quantize_u16(lo) <= quantize_u16(hi),
            "quantize_u16 not monotonic at {lo:e}, {hi:e}"
        );
    }
}
