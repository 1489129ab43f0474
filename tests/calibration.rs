//! Per-device calibration: the run-time forms (`Calibration`, `CountCalibration`) on their own,
//! and simulated devices of the example sensor (`data/sensor_as7341_gaussian.csv`, fitted for
//! reflectances under C) read through the golden device's matrix: alone, after a dark and white
//! calibration, and after the correction fitted at build time.
//!
//! `cargo test --release --test integration -- calibration:: --nocapture` prints the table of
//! docs/colour-temperature-and-calibration.md.

use spectral_quadrature_build as sqd;

mod common;

use proptest::prelude::*;
use spectral_quadrature::{
    xyz_from_ac1c2, Calibration, CalibrationProblem, CountCalibration, Error, Samples,
    WavelengthSet,
};
use sqd::calibration::{self, Readings};
use sqd::evaluate::Curve;
use std::sync::OnceLock;

/// The data files the derivation reads (the runtime crate's `data/`).
const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data");

// ---------------------------------------------------------------------------------------------
// The run-time forms on their own.

#[test]
fn dark_and_white_make_the_white_read_as_the_reference() {
    let dark = [10.0, 200.5, 0.0];
    let white = [1010.0, 700.5, 3.0];
    let reference = [0.5, 2.0, 3.0];
    let cal = Calibration::from_dark_white(&dark, &white, &reference).unwrap();
    assert_eq!(cal.dark, dark);
    assert_eq!(cal.apply(&white), reference);
    assert_eq!(cal.apply(&dark), [0.0; 3]);
    // Below the dark offset: negative, as it is (noise averages out).
    assert!(cal.apply(&[0.0, 0.0, 0.0])[0] < 0.0);
    assert_eq!(Calibration::<3>::IDENTITY.apply(&white), white);
    // NaN propagates, and never panics.
    assert!(cal.apply(&[f32::NAN, 1.0, 1.0])[0].is_nan());
}

#[test]
fn bad_calibration_readings_name_the_channel() {
    fn err<T>(channel: usize, problem: CalibrationProblem) -> Result<T, Error> {
        Err(Error::Calibration { channel, problem })
    }
    let ok = [1.0f32; 3];
    let white = [5.0f32; 3];
    let dark = [1.0, 5.0, 1.0];
    assert_eq!(
        Calibration::from_dark_white(&dark, &white, &ok),
        err(1, CalibrationProblem::NoSignal)
    );
    assert_eq!(
        Calibration::from_dark_white(&[1.0, 1.0, 6.0], &white, &ok),
        err(2, CalibrationProblem::NoSignal)
    );
    assert_eq!(
        Calibration::from_dark_white(&[f32::NAN, 1.0, 1.0], &white, &ok),
        err(0, CalibrationProblem::NoSignal)
    );
    assert_eq!(
        Calibration::from_dark_white(&[f32::NEG_INFINITY, 1.0, 1.0], &white, &ok),
        err(0, CalibrationProblem::NoSignal)
    );
    assert_eq!(
        Calibration::from_dark_white(&ok, &white, &[1.0, 0.0, 1.0]),
        err(1, CalibrationProblem::Reference)
    );
    assert_eq!(
        Calibration::from_dark_white(&ok, &white, &[1.0, 1.0, f32::INFINITY]),
        err(2, CalibrationProblem::Reference)
    );
    // A signal of one subnormal and a huge reference: the gain overflows.
    assert_eq!(
        Calibration::from_dark_white(&[0.0; 1], &[1e-45], &[1e30]),
        err(0, CalibrationProblem::OutOfRange)
    );
    let counts =
        |d: [u16; 2], w: [u16; 2], r: [u16; 2]| CountCalibration::from_dark_white(&d, &w, &r);
    assert_eq!(
        counts([5, 5], [5, 6], [1, 1]),
        err(0, CalibrationProblem::NoSignal)
    );
    assert_eq!(
        counts([5, 7], [6, 6], [1, 1]),
        err(1, CalibrationProblem::NoSignal)
    );
    assert_eq!(
        counts([0, 0], [6, 6], [1, 0]),
        err(1, CalibrationProblem::Reference)
    );
    let msg = Error::Calibration {
        channel: 3,
        problem: CalibrationProblem::NoSignal,
    }
    .to_string();
    assert_eq!(
        msg,
        "calibration of channel 3: the white reading is not above the dark one"
    );
}

/// The integer form: saturation at both ends, rounding to nearest, and the largest values
/// without overflow.
#[test]
fn counts_saturate_and_round() {
    let one = CountCalibration::<1>::IDENTITY;
    for x in [0u16, 1, 1000, 65_535] {
        assert_eq!(one.apply(&[x]), [x]);
    }
    let half = CountCalibration {
        dark: [10],
        gain_q16: [1 << 15],
    };
    // (13 − 10) / 2 = 1.5 rounds up to 2; (12 − 10) / 2 = 1; below the dark offset: 0.
    assert_eq!(half.apply(&[13]), [2]);
    assert_eq!(half.apply(&[12]), [1]);
    assert_eq!(half.apply(&[3]), [0]);
    let largest = CountCalibration {
        dark: [0],
        gain_q16: [u32::MAX],
    };
    assert_eq!(largest.apply(&[65_535]), [65_535]);
    assert_eq!(largest.apply(&[1]), [65_535]);
    assert_eq!(largest.apply(&[0]), [0]);
    // Every white and reference pair of a coarse grid: the white comes back as the reference
    // to within one count (the gain's rounding to 2⁻¹⁶, times at most 65 535 counts, is at
    // most half a count, and the result's own rounding another half).
    for white in (1..=65_535u16).step_by(997) {
        for reference in (1..=65_535u16).step_by(1009) {
            let cal = CountCalibration::from_dark_white(&[0], &[white], &[reference]).unwrap();
            let got = cal.apply(&[white])[0];
            assert!(got.abs_diff(reference) <= 1, "{white} {reference}: {got}");
        }
    }
}

/// `to_counts` gives the integer form of the same calibration: within one count of the f32
/// form's result times the scale, for every reading.
#[test]
fn the_integer_form_follows_the_float_form() {
    common::check_property(
        10_000,
        "to_counts",
        (0.0f32..3000.0, 0.5f32..2.0, 1.0f32..40_000.0, 0u16..=65_535),
        |(dark, gain, scale, x)| {
            let cal = Calibration {
                dark: [dark],
                gain: [gain / scale],
            };
            let counts = cal.to_counts(scale).unwrap();
            let want = (f64::from(x) - f64::from(counts.dark[0])).max(0.0)
                * f64::from(gain / scale)
                * f64::from(scale);
            let got = f64::from(counts.apply(&[x])[0]);
            // The gain rounds to 2⁻¹⁶ (half of that, times up to 65 535 counts: half a
            // count), the f32 products to a few ulps, and the result to half a count.
            prop_assert!((got - want.min(65_535.0)).abs() <= 1.0, "{got} vs {want}");
            Ok(())
        },
    );
    let out_of_range = Err(Error::Calibration {
        channel: 0,
        problem: CalibrationProblem::OutOfRange,
    });
    let cal = |dark: f32, gain: f32| Calibration {
        dark: [dark],
        gain: [gain],
    };
    assert_eq!(cal(-1.0, 1.0).to_counts(1.0), out_of_range);
    assert_eq!(cal(65_535.6, 1.0).to_counts(1.0), out_of_range);
    assert_eq!(cal(0.0, 65_536.0).to_counts(1.0), out_of_range);
    assert_eq!(cal(0.0, -1.0).to_counts(1.0), out_of_range);
    assert_eq!(cal(f32::NAN, 1.0).to_counts(1.0), out_of_range);
    assert_eq!(cal(0.0, 1.0).to_counts(f32::INFINITY), out_of_range);
    // The largest gains fit: 65 535.5 · 2¹⁶ is exact in f32 and in u32; a dark offset of
    // −0.4 rounds to 0.
    assert_eq!(
        cal(-0.4, 65_535.5).to_counts(1.0).unwrap(),
        CountCalibration {
            dark: [0],
            gain_q16: [4_294_934_528],
        }
    );
}

// ---------------------------------------------------------------------------------------------
// Simulated devices.

/// A small deterministic generator (SplitMix64) and normal deviates by Box-Muller: the
/// simulation is the same on every machine.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    fn uniform(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn between(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }
    fn normal(&mut self) -> f64 {
        let u = 1.0 - self.uniform();
        let v = self.uniform();
        (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
    }
}

/// The example sensor, its golden matrix, the ColorChecker under C and what the golden device
/// reads on it, in the units of `spectral_quadrature_build::calibration`.
struct Bench {
    /// The golden device's set, as the runtime bakes it (AC1C2 rows, f32).
    set: WavelengthSet<8>,
    /// The golden device's readings of each patch.
    golden: Vec<Vec<f64>>,
    /// Its reading of a perfect white: the white reference.
    white: Vec<f64>,
    /// Each patch's exact CIELAB (1 nm integration, the perfect white's XYZ as the white).
    labs: Vec<[f64; 3]>,
    /// The perfect white's exact XYZ.
    white_xyz: [f64; 3],
    /// The patches' names.
    names: Vec<String>,
}

fn bench() -> &'static Bench {
    static B: OnceLock<Bench> = OnceLock::new();
    B.get_or_init(|| {
        let d = sqd::derive(&sqd::Settings::new(DATA_DIR)).unwrap();
        let range = d.settings.range_nm;
        let sensor = sqd::user::Sensor::read(
            std::path::Path::new(DATA_DIR)
                .join("sensor_as7341_gaussian.csv")
                .as_path(),
            "data/sensor_as7341_gaussian.csv",
            range,
        )
        .unwrap();
        let light =
            sqd::evaluate::builtin_illuminant(std::path::Path::new(DATA_DIR), "C", range).unwrap();
        let fitted = sqd::user::sensor_set(&d, "AS7341", "AS7341", &sensor, Some(&light)).unwrap();
        // AC1C2 rows = Eq. 9 · XYZ rows, rounded to f32 as the build rounds them.
        let m = d.opponent.xyz_to_ac1c2;
        let weights: [[f32; 8]; 3] = core::array::from_fn(|r| {
            core::array::from_fn(|k| {
                (0..3)
                    .map(|c| m[r][c] * fitted.xyz_weights[c][k])
                    .sum::<f64>() as f32
            })
        });
        let set = WavelengthSet {
            wavelengths_nm: fitted
                .wavelengths_nm
                .iter()
                .map(|&l| l as f32)
                .collect::<Vec<_>>()
                .try_into()
                .unwrap(),
            weights,
            samples: Samples::Readings {
                sensor: "AS7341",
                light: Some("C"),
            },
        };
        let chart = sqd::evaluate::Spectra::builtin(
            std::path::Path::new(DATA_DIR),
            calibration::DEFAULT_REFLECTANCES,
        )
        .unwrap();
        let patches: Vec<Curve> = chart.curves(range).unwrap();
        let golden = calibration::golden_readings(&d, &sensor, Some(&light), &patches).unwrap();
        let white = calibration::white_readings(&d, &sensor, Some(&light)).unwrap();
        // Exact colours in the same units: the light scaled so the perfect white has
        // Y = UNIT_SPECTRUM_Y.
        let full = sqd::evaluate::full_integration(&d.observer, range, 1.0).unwrap();
        let scale = d.unit_spectrum_y / full.xyz(|nm| light.at(nm))[1];
        let white_xyz = full.xyz(|nm| scale * light.at(nm));
        let labs = patches
            .iter()
            .map(|p| {
                let xyz = full.xyz(|nm| scale * light.at(nm) * p.at(nm));
                spectral_quadrature::lab_from_xyz(xyz, white_xyz)
            })
            .collect();
        Bench {
            set,
            golden,
            white,
            labs,
            white_xyz,
            names: chart.names().to_vec(),
        }
    })
}

/// One simulated device: per-channel gain and dark offset, the exposure (counts per golden
/// unit) it shares with the golden device, and its read noise.
struct Device {
    gain: [f64; 8],
    dark: [f64; 8],
    counts_per_unit: f64,
    noise_counts: f64,
}

/// The exposure of every device: the golden device's brightest channel reads a perfect white
/// at 50 000 counts, so a device 10 % more sensitive stays below 65 535.
fn counts_per_unit() -> f64 {
    50_000.0 / bench().white.iter().copied().fold(0.0, f64::max)
}

impl Device {
    /// The golden device: unit gains, no dark offset, the same read noise.
    fn golden(noise_counts: f64) -> Device {
        Device {
            gain: [1.0; 8],
            dark: [0.0; 8],
            counts_per_unit: counts_per_unit(),
            noise_counts,
        }
    }

    /// Gains uniform in 1 ± 10 %, dark offsets uniform in 100-1500 counts.
    fn random(rng: &mut Rng, noise_counts: f64) -> Device {
        Device {
            gain: core::array::from_fn(|_| rng.between(0.9, 1.1)),
            dark: core::array::from_fn(|_| rng.between(100.0, 1500.0)),
            counts_per_unit: counts_per_unit(),
            noise_counts,
        }
    }

    /// One frame: the 16-bit counts for golden readings `golden` (plus noise, rounded and
    /// clipped as an ADC does).
    fn read(&self, rng: &mut Rng, golden: &[f64]) -> [u16; 8] {
        core::array::from_fn(|k| {
            let x = self.gain[k] * self.counts_per_unit * golden[k]
                + self.dark[k]
                + self.noise_counts * rng.normal();
            x.round().clamp(0.0, 65_535.0) as u16
        })
    }
}

/// Mean ΔE00 over the chart of readings already in golden units.
fn mean_de00(frames: &[[f32; 8]]) -> (f64, f64) {
    let b = bench();
    let mut sum = 0.0;
    let mut worst: f64 = 0.0;
    for (r, exact) in frames.iter().zip(&b.labs) {
        let xyz = xyz_from_ac1c2(b.set.ac1c2(r)).map(f64::from);
        let de = spectral_quadrature::delta_e2000(
            *exact,
            spectral_quadrature::lab_from_xyz(xyz, b.white_xyz),
        );
        sum += de;
        worst = worst.max(de);
    }
    (sum / frames.len() as f64, worst)
}

/// What each way of reading a device measures, over many devices.
#[derive(Default)]
struct Row {
    mean: f64,
    worst_device: f64,
    worst_patch: f64,
    devices: usize,
}

impl Row {
    fn add(&mut self, (mean, worst): (f64, f64)) {
        self.mean += mean;
        self.worst_device = self.worst_device.max(mean);
        self.worst_patch = self.worst_patch.max(worst);
        self.devices += 1;
    }
    fn mean(&self) -> f64 {
        self.mean / self.devices as f64
    }
}

/// The four rows of the table for one level of read noise, over `devices` devices.
fn simulate(noise_counts: f64, devices: usize, seed: u64) -> [Row; 4] {
    let b = bench();
    let mut rng = Rng(seed);
    let mut rows: [Row; 4] = Default::default();
    let golden_units = |frame: &[u16; 8], e: f64| -> [f32; 8] {
        core::array::from_fn(|k| (f64::from(frame[k]) / e) as f32)
    };
    let e = counts_per_unit();
    let white_ref: [f32; 8] = core::array::from_fn(|k| b.white[k] as f32);
    for i in 0..devices {
        // The golden device itself, with the same noise: the error the others aim for.
        let golden = Device::golden(noise_counts);
        let frames: Vec<[f32; 8]> = b
            .golden
            .iter()
            .map(|g| golden_units(&golden.read(&mut rng, g), e))
            .collect();
        rows[0].add(mean_de00(&frames));
        let device = Device::random(&mut rng, noise_counts);
        // Its readings of the chart, through the golden matrix alone.
        let chart: Vec<[u16; 8]> = b.golden.iter().map(|g| device.read(&mut rng, g)).collect();
        let frames: Vec<[f32; 8]> = chart.iter().map(|c| golden_units(c, e)).collect();
        rows[1].add(mean_de00(&frames));
        // One dark frame and one frame of a perfect white.
        let dark = device.read(&mut rng, &[0.0; 8]).map(f32::from);
        let white = device.read(&mut rng, &b.white).map(f32::from);
        let cal = Calibration::from_dark_white(&dark, &white, &white_ref).unwrap();
        let frames: Vec<[f32; 8]> = chart.iter().map(|c| cal.apply(&c.map(f32::from))).collect();
        rows[2].add(mean_de00(&frames));
        // The fitted correction: fitted to one frame of the chart, judged on another.
        let training: Vec<Vec<f64>> = b
            .golden
            .iter()
            .map(|g| device.read(&mut rng, g).map(f64::from).to_vec())
            .collect();
        let fit = calibration::fit(&b.golden, &training).unwrap();
        let cal = Calibration {
            dark: core::array::from_fn(|k| fit.dark[k] as f32),
            gain: core::array::from_fn(|k| fit.gain[k] as f32),
        };
        let frames: Vec<[f32; 8]> = chart.iter().map(|c| cal.apply(&c.map(f32::from))).collect();
        rows[3].add(mean_de00(&frames));
        let _ = i;
    }
    rows
}

/// Noise-free, the golden device reads the chart as the report says (0.100 mean ΔE00, the
/// AS7341 line of docs/your-light-and-sensor.md): the bench is the report's.
#[test]
fn the_golden_device_without_noise_is_the_reports() {
    let b = bench();
    let frames: Vec<[f32; 8]> = b
        .golden
        .iter()
        .map(|g| core::array::from_fn(|k| g[k] as f32))
        .collect();
    let (mean, worst) = mean_de00(&frames);
    // The report prints 0.0998 and 0.3091 from f64 weights; these are the f32 weights.
    assert!((mean - 0.0998).abs() < 5e-4, "{mean}");
    assert!((worst - 0.3091).abs() < 5e-4, "{worst}");
    assert_eq!(b.names.len(), 24);
}

/// The table: simulated devices (gains ±10 %, dark offsets of 100-1500 counts, read noise) read
/// through the golden matrix alone, after a dark and white calibration, and after the
/// correction fitted to their readings of the chart; the last within 10 % of the golden
/// device's own error (the same noise, no gain or offset error).
#[test]
fn simulated_devices() {
    const DEVICES: usize = 200;
    println!("| read noise | golden device | golden matrix alone | after dark and white | after the fitted correction | fitted against golden |");
    println!("|---|---|---|---|---|---|");
    for (noise, seed) in [(2.0, 1), (10.0, 2), (50.0, 3)] {
        let rows = simulate(noise, DEVICES, seed);
        let cell = |r: &Row| {
            std::format!(
                "{:.3} (worst device {:.3}, patch {:.2})",
                r.mean(),
                r.worst_device,
                r.worst_patch
            )
        };
        let golden = rows[0].mean();
        let excess = rows[3].mean() / golden - 1.0;
        println!(
            "| {noise} counts | {} | {} | {} | {} | {:+.1} % ({} 10 %) |",
            cell(&rows[0]),
            cell(&rows[1]),
            cell(&rows[2]),
            cell(&rows[3]),
            100.0 * excess,
            if excess <= 0.1 { "within" } else { "beyond" }
        );
        assert!(
            rows[1].mean() > 3.0 * golden,
            "uncalibrated devices are far off"
        );
        assert!(rows[2].mean() < rows[1].mean());
        assert!(
            rows[3].mean() <= 1.1 * golden,
            "{noise} counts: fitted {} against the golden device's {golden}",
            rows[3].mean()
        );
    }
}

/// The example readings (`examples/sensors/as7341_device.csv`): one simulated device's frame of
/// the chart, as a scene's `calibration` reads it; the build's fit recovers the device's gains
/// and offsets.
#[test]
fn the_example_device_readings() {
    let b = bench();
    let mut rng = Rng(42);
    let device = Device::random(&mut rng, 10.0);
    let frame: Vec<[u16; 8]> = b.golden.iter().map(|g| device.read(&mut rng, g)).collect();
    let channels = [
        "F1_415", "F2_445", "F3_480", "F4_515", "F5_555", "F6_590", "F7_630", "F8_680",
    ];
    let mut text = String::from(
        "# One simulated AS7341 (gains 1 ± 10 %, dark offsets of 100-1500 counts, read noise of 10\n\
         # counts) reading the ColorChecker under illuminant C, in 16-bit counts. Written by\n\
         # UPDATE_EXAMPLES=1 cargo test --test integration calibration::the_example_device_readings\n",
    );
    text.push_str(&std::format!("patch,{}\n", channels.join(",")));
    for (name, counts) in b.names.iter().zip(&frame) {
        let values: Vec<String> = counts.iter().map(u16::to_string).collect();
        text.push_str(&std::format!("\"{name}\",{}\n", values.join(",")));
    }
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/sensors/as7341_device.csv");
    if std::env::var_os("UPDATE_EXAMPLES").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, &text).unwrap();
    }
    let shipped = std::fs::read_to_string(&path).unwrap();
    assert_eq!(
        shipped, text,
        "run UPDATE_EXAMPLES=1 cargo test --test integration calibration:: to rewrite it"
    );
    // What the build does with it.
    let names: Vec<String> = channels.iter().map(|c| c.to_string()).collect();
    let readings = Readings::parse("as7341_device.csv", &shipped, &names).unwrap();
    let fit = calibration::fit(&b.golden, &readings.values).unwrap();
    for k in 0..8 {
        let gain = 1.0 / (device.gain[k] * device.counts_per_unit);
        // 24 readings with 10 counts of noise: the offset to a few counts, the gain to a few
        // parts in 10⁴ (the standard errors of a straight-line fit, times about 4).
        assert!(
            (fit.dark[k] - device.dark[k]).abs() < 20.0,
            "{k}: {} vs {}",
            fit.dark[k],
            device.dark[k]
        );
        assert!(
            (fit.gain[k] / gain - 1.0).abs() < 2e-3,
            "{k}: {} vs {gain}",
            fit.gain[k]
        );
    }
}
