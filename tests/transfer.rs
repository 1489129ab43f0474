//! The per-pixel encoders without f64: `TransferFunction::encode_u8` and `encode_u16` against
//! the exact curves, recomputed here in f64 with `libm::pow`.
//!
//! 1. 8 bits, every baked display (sRGB, Display P3: the sRGB table; Rec. 2020 and Meyer 1987:
//!    the build script's thresholds for γ = 2.4 and 2.2): equal to the exact curve rounded to
//!    nearest at every f32 within 3 units in the last place of each of the 255 code boundaries,
//!    and on a stride of some 2 million f32 across 0..=1.
//! 2. 16 bits: within `U16_MAX_ERROR` (1 step) of the exact curve rounded, at every f32
//!    within 2 units of each of the 65 535 16-bit boundaries and of each 8-bit one; how often it
//!    is off is printed.
//! 3. A γ that no baked display has (1.8) goes through f32 `powf`: within 1 step in 8 bits too.

use spectral_quadrature::tables::displays;
use spectral_quadrature::{Rgb, TransferFunction, U16_MAX_ERROR};

/// The exact curve in f64 for x in 0..=1 (sRGB or a power law; other variants are not tested
/// here).
fn curve64(tf: TransferFunction, x: f64) -> f64 {
    match tf {
        TransferFunction::Srgb => {
            if x <= 0.003_130_8 {
                12.92 * x
            } else {
                1.055 * libm::pow(x, 1.0 / 2.4) - 0.055
            }
        }
        TransferFunction::Gamma(g) => libm::pow(x, 1.0 / f64::from(g)),
        TransferFunction::Linear => x,
        _ => unreachable!("not tested here"),
    }
}

/// The linear value where the exact curve reaches `v` (the inverse, in f64).
fn inverse64(tf: TransferFunction, v: f64) -> f64 {
    match tf {
        TransferFunction::Srgb => {
            if v <= 0.040_45 {
                v / 12.92
            } else {
                libm::pow((v + 0.055) / 1.055, 2.4)
            }
        }
        TransferFunction::Gamma(g) => libm::pow(v, f64::from(g)),
        TransferFunction::Linear => v,
        _ => unreachable!("not tested here"),
    }
}

/// The exact curve times `levels` rounded to nearest (halves up).
fn exact(tf: TransferFunction, x: f32, levels: f64) -> u32 {
    let x = f64::from(x).clamp(0.0, 1.0);
    (levels * curve64(tf, x) + 0.5).floor() as u32
}

/// The f32 bit patterns within `reach` units of the boundary where the curve crosses
/// `(k − ½) / levels`, for k = 1..=levels, inside 0..=1.
fn near_boundaries(tf: TransferFunction, levels: u32, reach: u32) -> Vec<f32> {
    let mut v = Vec::new();
    for k in 1..=levels {
        let b = inverse64(tf, (f64::from(k) - 0.5) / f64::from(levels)) as f32;
        let bits = b.to_bits();
        for d in bits.saturating_sub(reach)..=bits.saturating_add(reach) {
            if d <= 1.0f32.to_bits() {
                v.push(f32::from_bits(d));
            }
        }
    }
    v
}

fn baked_transfers() -> Vec<(&'static str, TransferFunction)> {
    displays::ALL
        .iter()
        .map(|d| (d.name(), d.transfer()))
        .filter(|(_, t)| matches!(t, TransferFunction::Srgb | TransferFunction::Gamma(_)))
        .collect()
}

#[test]
fn u8_is_correctly_rounded_for_every_baked_display() {
    let transfers = baked_transfers();
    assert!(
        !transfers.is_empty(),
        "the scene bakes no sRGB or gamma display"
    );
    for (name, tf) in transfers {
        let mut xs = near_boundaries(tf, 255, 3);
        // A stride over all of 0..=1 (every 509th f32: some 2.1 million values).
        xs.extend((0..=1.0f32.to_bits()).step_by(509).map(f32::from_bits));
        for x in xs {
            let got = tf.encode_u8(Rgb::G, x);
            let want = exact(tf, x, 255.0);
            assert_eq!(
                u32::from(got),
                want,
                "{name}: encode_u8({x:e} = {:#x}) = {got}, exact {want} (255·curve = {})",
                x.to_bits(),
                255.0 * curve64(tf, f64::from(x))
            );
        }
    }
}

#[test]
fn u16_is_within_its_bound_at_every_code_boundary() {
    for (name, tf) in baked_transfers() {
        let mut xs = near_boundaries(tf, 65535, 2);
        xs.extend(near_boundaries(tf, 255, 2));
        let (mut off, mut worst) = (0usize, 0u32);
        for &x in &xs {
            let got = u32::from(tf.encode_u16(Rgb::B, x));
            let want = exact(tf, x, 65535.0);
            let d = got.abs_diff(want);
            if d != 0 {
                off += 1;
                worst = worst.max(d);
            }
            assert!(
                d <= u32::from(U16_MAX_ERROR),
                "{name}: encode_u16({x:e}) = {got}, exact {want}"
            );
        }
        eprintln!(
            "{name}: encode_u16 off the exact curve rounded on {off} of {} f32 next to code \
             boundaries, by at most {worst} step (bound {U16_MAX_ERROR})",
            xs.len()
        );
    }
}

#[test]
fn a_gamma_without_baked_thresholds_is_within_one_step() {
    let tf = TransferFunction::Gamma(1.8);
    let mut off = 0usize;
    for x in near_boundaries(tf, 255, 3) {
        let got = u32::from(tf.encode_u8(Rgb::R, x));
        let want = exact(tf, x, 255.0);
        // f32 `powf` is within a few units in the last place: only inputs next to a step's half
        // can round the other way, by one step.
        assert!(
            got.abs_diff(want) <= 1,
            "encode_u8({x:e}) = {got}, exact {want}"
        );
        off += usize::from(got != want);
    }
    eprintln!("Gamma(1.8): encode_u8 off by one step on {off} of 1 785 f32 next to boundaries");
}

#[test]
fn specials_encode_as_documented() {
    let sub = f32::from_bits(1);
    for tf in [
        TransferFunction::Srgb,
        TransferFunction::Gamma(2.2),
        TransferFunction::Gamma(2.4),
        TransferFunction::Gamma(1.8),
        TransferFunction::Linear,
    ] {
        for (x, want8, want16) in [
            (f32::NAN, 0, 0),
            (-1.0, 0, 0),
            (f32::NEG_INFINITY, 0, 0),
            (-0.0, 0, 0),
            (0.0, 0, 0),
            (1.0, 255, 65535),
            (1e30, 255, 65535),
            (f32::INFINITY, 255, 65535),
        ] {
            assert_eq!(tf.encode_u8(Rgb::R, x), want8, "{tf:?} {x}");
            assert_eq!(tf.encode_u16(Rgb::R, x), want16, "{tf:?} {x}");
        }
        // The smallest subnormal: x^(1/γ) is about 1e-20 for these γ, far below half a step.
        assert_eq!(tf.encode_u8(Rgb::R, sub), 0, "{tf:?}");
        assert_eq!(tf.encode_u16(Rgb::R, sub), 0, "{tf:?}");
    }
}
