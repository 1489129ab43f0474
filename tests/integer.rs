//! The integer path (`IntegerSet`): u16 counts → 8-bit display RGB in integer arithmetic.
//!
//! For every baked integer set (the default scene's 24, `tables::integer`) and every set of the
//! example sensor scene (`examples/scenes/sensor.toml`, made here from a fresh derivation the way
//! the build bakes it):
//!
//! 1. The fixed-point weights are `round(w · q · 2^P)` of the f32 weights, recomputed here in
//!    f64 (exact: two 24-bit significands), and P is the largest that keeps the proven bound
//!    `Σ|V >> 16| · 65535 + N · 65535 ≤ i32::MAX` (no overflow for any u16 input).
//! 2. The bound of `INTEGER_MAX_ERROR_CODES` is proven: for each channel and each pair of
//!    neighbouring thresholds of the f32 encoder, the pair is further apart than the
//!    fixed-point error plus the f32 path's error budget next to it.
//! 3. `encode_u8` equals an independent reference (the exact sum in i128 against the f32
//!    encoder's thresholds, found here by bisection on the public f32 encoder), and is within 1
//!    code of the f32 path, on random inputs (proptest) and dense sweeps: every grey level, and
//!    each sample alone ramped over its whole range with the others at 0 and at full scale.

mod common;

use spectral_quadrature::tables::{displays, folded, integer};
use spectral_quadrature::{
    f32_budget, Display, Error, FoldedSet, GamutMapping, IntegerSet, LengthOf, Samples,
    INTEGER_MAX_ERROR_CODES,
};

use proptest::prelude::*;

/// The data files of the derivation (the runtime crate's `data/`).
const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data");

/// The f32 encoder's thresholds θₖ of a display (k = 1..=255; entry 0 is 0): the smallest f32 in
/// 0..=1 that the f32 path encodes to k or more, by bisection on the bits.
fn thresholds(display: &Display) -> [f32; 256] {
    let code = |x: f32| display.encode_u8(GamutMapping::Clip, [x; 3])[0];
    let mut t = [0.0f32; 256];
    for (k, slot) in t.iter_mut().enumerate().skip(1) {
        let (mut lo, mut hi) = (0u32, 1.0f32.to_bits());
        while lo < hi {
            let mid = lo + (hi - lo) / 2;
            if usize::from(code(f32::from_bits(mid))) >= k {
                hi = mid;
            } else {
                lo = mid + 1;
            }
        }
        *slot = f32::from_bits(lo);
    }
    t
}

/// `⌈θ · 2^p⌉` exactly, for a positive f32 θ.
fn scaled_ceil(theta: f32, p: u32) -> i128 {
    let bits = theta.to_bits();
    let exp = ((bits >> 23) & 0xff) as i32;
    let (m, e) = if exp == 0 {
        (i128::from(bits & 0x7f_ffff), -149)
    } else {
        (i128::from((bits & 0x7f_ffff) | 0x80_0000), exp - 150)
    };
    let s = e + p as i32;
    if s >= 0 {
        m << s
    } else {
        let r = -s;
        if r >= 120 {
            return i128::from(m > 0);
        }
        (m + (1 << r) - 1) >> r
    }
}

/// One set under test: the f32 folded set, its integer form, and what the reference needs.
struct Case<const N: usize> {
    name: String,
    folded: FoldedSet<N>,
    set: IntegerSet<N>,
    /// Per channel, `⌈θₖ · 2^P⌉` for k = 1..=255: F ≥ this ⇔ F / 2^P ≥ θₖ.
    scaled: [Vec<i128>; 3],
}

impl<const N: usize> Case<N> {
    fn new(name: &str, folded: FoldedSet<N>, set: IntegerSet<N>) -> Case<N> {
        let t = thresholds(&folded.display());
        let p = set.frac_bits();
        let scaled: Vec<i128> = t[1..].iter().map(|&th| scaled_ceil(th, p)).collect();
        Case {
            name: name.into(),
            folded,
            set,
            scaled: [scaled.clone(), scaled.clone(), scaled],
        }
    }

    /// The exact sum per channel, in i128.
    fn exact_sum(&self, x: &[u16; N]) -> [i128; 3] {
        let w = self.set.weights();
        [0, 1, 2].map(|c| (0..N).map(|i| i128::from(w[c][i]) * i128::from(x[i])).sum())
    }

    /// The reference code values: the number of thresholds at or below F / 2^P.
    fn reference(&self, x: &[u16; N]) -> [u8; 3] {
        let f = self.exact_sum(x);
        [0, 1, 2].map(|c| self.scaled[c].partition_point(|&t| t <= f[c]) as u8)
    }

    fn f32_path(&self, x: &[u16; N]) -> [u8; 3] {
        self.folded
            .encode_u8(GamutMapping::Clip, &self.set.counts_as_f32(x))
    }

    /// Checks one input; the message names the set and the input.
    fn check(&self, x: &[u16; N]) -> Result<(), String> {
        let got = self.set.encode_u8(x);
        let want = self.reference(x);
        if got != want {
            return Err(format!(
                "{}: {x:?} encodes to {got:?}, the reference to {want:?}",
                self.name
            ));
        }
        let f = self.f32_path(x);
        if got
            .iter()
            .zip(f)
            .any(|(a, b)| a.abs_diff(b) > INTEGER_MAX_ERROR_CODES)
        {
            return Err(format!(
                "{}: {x:?} encodes to {got:?}, the f32 path to {f:?}",
                self.name
            ));
        }
        let lin = self.set.linear_fixed(x);
        if lin.map(i128::from) != self.exact_sum(x) {
            return Err(format!("{}: linear_fixed({x:?}) = {lin:?}", self.name));
        }
        Ok(())
    }

    /// Item 1: the weights are the exact fixed-point form of the f32 weights, and P the
    /// largest the overflow bound allows.
    fn check_weights(&self) {
        let q = f64::from(self.set.sample_unit());
        let p = self.set.frac_bits() as i32;
        let fixed = |p: i32| -> [[i64; N]; 3] {
            self.folded.weights().map(|row| {
                row.map(|w| {
                    // Exact: two 24-bit significands, and a power of two.
                    let v = f64::from(w) * q * 2f64.powi(p);
                    (v.abs() + 0.5).floor().copysign(v) as i64
                })
            })
        };
        let weights = self.set.weights().map(|r| r.map(i64::from));
        assert_eq!(weights, fixed(p), "{}", self.name);
        let margin = N as i64 * 65535;
        let bound_holds = |w: &[[i64; N]; 3]| {
            w.iter().all(|row| {
                row.iter().map(|v| (v >> 16).abs() * 65535).sum::<i64>() + margin
                    <= i64::from(i32::MAX)
            })
        };
        assert!(bound_holds(&weights), "{}", self.name);
        // P + 1 would break the bound, unless P is already the largest the type allows.
        assert!(p == 46 || !bound_holds(&fixed(p + 1)), "{}", self.name);
        assert!(1i64 << (p - 16) > margin, "{}", self.name);
    }

    /// Item 2: the proof of the 1-code bound. Returns the smallest ratio, over channels and
    /// pairs of neighbouring thresholds, of the pair's distance to the error it must exceed.
    fn prove_within_one_code(&self) -> f64 {
        let t = thresholds(&self.folded.display());
        let q = f64::from(self.set.sample_unit());
        let p = self.set.frac_bits();
        let v = self.set.weights();
        // The largest f32 sample: 65535 · q rounded once (half an f32 unit up at most).
        let s_max = 65535.0 * q * (1.0 + f64::from(f32::EPSILON) / 2.0);
        let mut worst = f64::INFINITY;
        for (c, (fixed, w)) in v.iter().zip(self.folded.weights()).enumerate() {
            let w = w.map(f64::from);
            // The fixed-point rounding, for the largest count: Σ|Vᵢ/2^P − wᵢ·q| · 65535.
            let fixed_error: f64 = fixed
                .iter()
                .zip(w)
                .map(|(&vi, wi)| (vi as f64 / 2f64.powi(p as i32) - wi * q).abs() * 65535.0)
                .sum();
            let positive: f64 = w.iter().filter(|&&x| x > 0.0).sum::<f64>() * s_max;
            let negative: f64 = -w.iter().filter(|&&x| x < 0.0).sum::<f64>() * s_max;
            let abs_max = positive + negative;
            for k in 1..255 {
                let (lo, hi) = (f64::from(t[k]), f64::from(t[k + 1]));
                // Codes 2 apart need both θₖ and θₖ₊₁ between the two values, so the exact
                // value is at most θₖ₊₁ plus both errors; Σ|wᵢsᵢ| = value + 2 · (the negative
                // terms) is then at most that plus twice the negative weights at full scale.
                let slack = fixed_error + f32_budget(N, abs_max);
                let abs_sum = abs_max.min(hi + slack + 2.0 * negative);
                let error = fixed_error + f32_budget(N, abs_sum);
                let ratio = (hi - lo) / error;
                assert!(
                    ratio > 1.0,
                    "{} channel {c}: thresholds {k} and {} are {:e} apart, the errors {error:e}",
                    self.name,
                    k + 1,
                    hi - lo
                );
                worst = worst.min(ratio);
            }
        }
        worst
    }

    /// Item 3, dense: every grey level, and each sample ramped alone (the others at 0, and at
    /// full scale) in steps of `step` counts.
    fn sweep(&self, step: usize) -> usize {
        let mut n = 0;
        for g in 0..=u16::MAX {
            self.check(&[g; N]).unwrap();
            n += 1;
        }
        for i in 0..N {
            for base in [0, u16::MAX] {
                for t in (0..=u16::MAX).step_by(step) {
                    let mut x = [base; N];
                    x[i] = t;
                    self.check(&x).unwrap();
                    n += 1;
                }
            }
        }
        n
    }
}

/// Counts biased toward the ends of the range, where codes change fastest or saturate.
fn counts() -> impl Strategy<Value = u16> {
    prop_oneof![any::<u16>(), 0u16..512, 65000u16..=u16::MAX]
}

fn all_checks<const N: usize>(case: &Case<N>, cases: u32, step: usize) {
    case.check_weights();
    let ratio = case.prove_within_one_code();
    let swept = case.sweep(step);
    common::check_property(
        cases,
        &case.name,
        proptest::array::uniform(counts()),
        |x: [u16; N]| {
            case.check(&x).map_err(TestCaseError::fail)?;
            Ok(())
        },
    );
    println!(
        "{:<28} P = {:2}  closest thresholds {ratio:>8.1} times the error bound; {swept} swept",
        case.name,
        case.set.frac_bits()
    );
}

/// Runs [`all_checks`] on each named baked set; returns how many there were.
macro_rules! check_baked {
    ($($name:ident,)*) => {{
        let mut n = 0;
        $(
            all_checks(&Case::new(stringify!($name), folded::$name, integer::$name), 500, 7);
            n += 1;
        )*
        n
    }};
}

#[test]
fn every_baked_set_is_proven_within_one_code_and_exact() {
    // The build's own list of the integer sets it baked.
    let n = integer::all!(check_baked);
    assert_eq!(n, integer::NAMES.len());
    // The list holds every integer set the build baked.
    let baked = include_str!(concat!(env!("OUT_DIR"), "/tables.rs"));
    assert_eq!(baked.matches(": IntegerSet<").count(), n);
}

/// The sets of `examples/scenes/sensor.toml` (the AS7341 sensor, fixed wavelengths, a shared
/// set for a measured light), folded for its display and put in fixed point as the build would.
#[test]
fn the_example_sensor_scenes_sets_are_proven_within_one_code_and_exact() {
    let root = env!("CARGO_MANIFEST_DIR");
    let path = format!("{root}/examples/scenes/sensor.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let scene = spectral_quadrature_generator::scene::Scene::parse(
        &path,
        &text,
        std::path::Path::new(DATA_DIR),
    )
    .unwrap();
    let d = spectral_quadrature_generator::derive(&scene.settings).unwrap();
    let resolved = scene.resolve(&d).unwrap();
    let mut sensors = 0;
    for set in &resolved.colour_sets {
        for (spec, m) in &resolved.displays {
            let display = displays::ALL
                .into_iter()
                .find(|x| x.name() == spec.label)
                .expect("a display of the default scene");
            assert_eq!(
                display.xyz_to_rgb(),
                m.xyz_to_rgb.map(|r| r.map(|v| v as f32))
            );
            let w = d.folded(set, m);
            let unit =
                spectral_quadrature_generator::fixed_point::sample_unit(set, &resolved) as f32;
            let light = set.light.clone().map(|l| &*String::leak(l));
            let samples = match (&set.sensor, light) {
                (Some(s), light) => {
                    sensors += 1;
                    Samples::Readings {
                        sensor: String::leak(s.clone()),
                        light,
                    }
                }
                (None, Some(light)) => Samples::Reflectance { light },
                (None, None) => Samples::Radiance,
            };
            let name = format!("{}_{}", set.name, spec.name);
            macro_rules! run {
                ($n:literal) => {{
                    let folded = FoldedSet::<$n>::new(
                        std::array::from_fn(|i| set.wavelengths_nm[i] as f32),
                        w.clone().map(|r| std::array::from_fn(|i| r[i] as f32)),
                        samples,
                        display,
                    )
                    .unwrap();
                    let int = IntegerSet::new(&folded, unit).unwrap();
                    all_checks(&Case::new(&name, folded, int), 500, 7);
                }};
            }
            match set.len() {
                6 => run!(6),
                8 => run!(8),
                n => panic!("{name}: {n} samples, not covered here"),
            }
        }
    }
    assert_eq!(sensors, 1, "the AS7341");
    // A sensor's white fills the 16 bits: its largest reading of white is 65535 counts.
    let (_, white) = &resolved.white_samples[0];
    let largest = white.iter().copied().fold(0.0, f64::max);
    let set = resolved
        .colour_sets
        .iter()
        .find(|s| s.sensor.is_some())
        .unwrap();
    assert_eq!(
        spectral_quadrature_generator::fixed_point::sample_unit(set, &resolved),
        largest / 65535.0
    );
}

#[test]
fn batch_equals_per_pixel_and_checks_lengths() {
    let set = integer::KQ_C_4_SRGB;
    let counts: Vec<[u16; 4]> = (0..1000u32)
        .map(|p| {
            std::array::from_fn(|i| (p * 131 + i as u32 * 977).wrapping_mul(2654435761) as u16)
        })
        .collect();
    let mut out = vec![[0u8; 3]; counts.len()];
    set.encode_u8_batch(&counts, &mut out).unwrap();
    for (x, o) in counts.iter().zip(&out) {
        assert_eq!(*o, set.encode_u8(x));
    }
    let mut short = vec![[7u8; 3]; 3];
    assert_eq!(
        set.encode_u8_batch(&counts, &mut short),
        Err(Error::LengthMismatch {
            what: LengthOf::Output,
            expected: 1000,
            got: 3
        })
    );
    assert_eq!(short, vec![[7u8; 3]; 3], "nothing written");
}

#[test]
fn ends_of_the_range() {
    // Zero counts are black; full scale on every sample is white (a reflectance of 1 under C:
    // brighter than the display's white in some channel, so at least one channel saturates).
    let set = integer::KQ_C_8_SRGB;
    assert_eq!(set.encode_u8(&[0; 8]), [0; 3]);
    let white = set.encode_u8(&[u16::MAX; 8]);
    assert!(
        white.iter().all(|&c| c > 240) && white.contains(&255),
        "{white:?}"
    );
    assert_eq!(set.samples(), Samples::Reflectance { light: "C" });
    assert_eq!(set.sample_unit(), 1.0 / 65535.0);
    assert_eq!(set.display(), displays::SRGB);
    assert_eq!(set.wavelengths_nm(), folded::KQ_C_8_SRGB.wavelengths_nm());
}

#[test]
fn what_has_no_fixed_point_form_is_an_error() {
    let f = folded::KQ_C_4_SRGB;
    for unit in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        assert_eq!(
            IntegerSet::new(&f, unit),
            Err(Error::IntegerRange),
            "{unit}"
        );
    }
    // The same set with other weights or another display.
    let with = |weights: [[f32; 4]; 3], display: spectral_quadrature::Display| {
        spectral_quadrature::FoldedSet::new(f.wavelengths_nm(), weights, f.samples(), display)
    };
    // A folded set's constructor refuses weights that are not finite; a set folded at run time
    // with a scale that is not finite has them, and IntegerSet::new refuses that.
    let mut weights = f.weights();
    weights[1][2] = f32::INFINITY;
    assert_eq!(
        with(weights, f.display()),
        Err(Error::InvalidWeight { row: 1, index: 2 })
    );
    for scale in [f32::INFINITY, f32::NAN] {
        let bad = spectral_quadrature::tables::KQ_C_4.fold(&displays::SRGB, scale);
        assert_eq!(IntegerSet::new(&bad, 1e-5), Err(Error::IntegerRange));
    }
    // Weights so large that even 17 fractional bits overflow 32-bit sums.
    let mut weights = f.weights();
    weights[0][0] = 1e30;
    let huge = with(weights, f.display()).unwrap();
    assert_eq!(IntegerSet::new(&huge, 1e-5), Err(Error::IntegerRange));
    // A measured display's lookup tables and a γ no baked display has: no integer encoder.
    let luts = spectral_quadrature::ChannelLuts::new([&[0.0, 1.0], &[0.0, 1.0], &[0.0, 1.0]]);
    let transfer = |t| with(f.weights(), displays::SRGB.with_transfer(t)).unwrap();
    let lut = transfer(spectral_quadrature::TransferFunction::Lut(luts.unwrap()));
    assert_eq!(IntegerSet::new(&lut, 1e-5), Err(Error::IntegerTransfer));
    let gamma = transfer(spectral_quadrature::TransferFunction::Gamma(1.8));
    assert_eq!(IntegerSet::new(&gamma, 1e-5), Err(Error::IntegerTransfer));
    // Linear light: the integer encoder has quantize_u8's thresholds.
    let linear = transfer(spectral_quadrature::TransferFunction::Linear);
    let set = IntegerSet::new(&linear, 1.0 / 65535.0).unwrap();
    all_checks(&Case::new("KQ_C_4 linear", linear, set), 200, 61);
}

#[test]
fn a_set_folded_at_run_time_and_tiny_weights() {
    // Folded in f32 at run time, then put in fixed point on the spot.
    let f = spectral_quadrature::tables::KQ_C_6.fold(&displays::REC2020, 1.0 / 106.85);
    let set = IntegerSet::new(&f, 1.0 / 65535.0).unwrap();
    all_checks(&Case::new("KQ_C_6 folded at run time", f, set), 200, 61);
    // Weights a million times smaller: P stops at 46, and what is left is still exact.
    let tiny = spectral_quadrature::FoldedSet::new(
        f.wavelengths_nm(),
        f.weights().map(|r| r.map(|w| w * 1e-6)),
        f.samples(),
        f.display(),
    )
    .unwrap();
    let set = IntegerSet::new(&tiny, 1.0 / 65535.0).unwrap();
    assert_eq!(set.frac_bits(), 46);
    let case = Case::new("tiny", tiny, set);
    for g in (0..=u16::MAX).step_by(5) {
        case.check(&[g; 6]).unwrap();
    }
}
