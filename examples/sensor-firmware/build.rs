//! Simulates what the firmware reads, at build time, and writes it to `OUT_DIR/simulated.rs`:
//! the example AS7341 model's (`data/sensor_as7341_gaussian.csv`) u16 counts for each of the 24
//! ColorChecker patches (`data/reflectance_colorchecker_ohta.csv`) under illuminant C, on the
//! golden device (the scale of the baked integer set: 65535 counts for the largest channel's
//! reading of white) and on one simulated device with its own exposure, per-channel gains
//! (±10 %), dark offsets and read noise, with that device's dark and white readings.
//!
//! It takes the scale from the derivation that bakes the tables (the scene of
//! `.cargo/config.toml`), so a count means here what it means to `tables::integer`.
//!
//! On a microcontroller target it also puts memory.x where cortex-m-rt's link.x finds it, and
//! links with link.x.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use spectral_quadrature_spectra::{builtin_illuminant, Curve, Spectra};

/// The simulated device's exposure: its golden-device counts times this (a white reading
/// leaves headroom for its gains).
const EXPOSURE: f64 = 0.8;
/// Per-channel gains drawn uniformly from 1 ± this.
const GAIN_SPREAD: f64 = 0.10;
/// Dark offsets drawn uniformly from this range, in counts.
const DARK_COUNTS: [f64; 2] = [200.0, 2500.0];
/// The read noise's standard deviation, in counts (Gaussian, added to every reading).
const READ_NOISE: f64 = 12.0;
/// The generator's seed: the simulated device is the same on every build.
const SEED: u64 = 0x5eed_a573_4100_0001;

fn main() {
    let manifest = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets it"));
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=scene.toml");
    println!("cargo:rerun-if-changed=../../data");
    if let Err(e) = simulate(&manifest, &out) {
        panic!("simulating the sensor: {e}");
    }
    if std::env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("none") {
        std::fs::copy("memory.x", out.join("memory.x")).expect("copy memory.x");
        println!("cargo:rustc-link-search={}", out.display());
        println!("cargo:rustc-link-arg-bins=-Tlink.x");
    }
}

/// splitmix64: a small, fixed generator, so the simulated device does not depend on a crate's
/// version.
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

    /// Standard normal (Box-Muller).
    fn normal(&mut self) -> f64 {
        let u = 1.0 - self.uniform();
        let v = self.uniform();
        (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
    }
}

/// A count: rounded, clamped to the 16 bits a sensor reports.
fn count(v: f64) -> u16 {
    v.round().clamp(0.0, 65535.0) as u16
}

fn array<T: std::fmt::Debug>(items: &[T]) -> String {
    let inner: Vec<String> = items.iter().map(|v| format!("{v:?}")).collect();
    format!("[{}]", inner.join(", "))
}

fn simulate(manifest: &Path, out: &Path) -> Result<(), Box<dyn std::error::Error>> {
    let root = manifest.join("../..");
    let data = root.join("data");
    let scene_path = manifest.join("scene.toml");
    let text = std::fs::read_to_string(&scene_path)?;
    let scene = spectral_quadrature_generator::scene::Scene::parse(
        &scene_path.display().to_string(),
        &text,
        &data,
    )?;
    let d = spectral_quadrature_generator::derive(&scene.settings)?;
    let range = d.settings.range_nm;
    let (_, fitted) = scene.resolve_user(&d)?;
    let sensor_set = fitted
        .iter()
        .find(|f| f.name == "AS7341")
        .ok_or("the scene has no AS7341 sensor")?;
    let channels = &sensor_set
        .channels
        .as_ref()
        .ok_or("not a sensor set")?
        .channels;
    // One count is what `tables::integer::AS7341_SRGB` takes it for (the generator's rule).
    let largest_white = sensor_set.white_samples.iter().copied().fold(0.0, f64::max);
    let unit =
        f64::from((largest_white / spectral_quadrature_generator::fixed_point::FULL_SCALE) as f32);

    // Illuminant C at the luminance of a spectrum of constant 1, as the set was fitted for.
    let full = d.observer.full_integration(range, 1.0)?;
    let grid = &full.wavelengths_nm;
    let light = builtin_illuminant(&data, "C", range)?;
    let raw: Vec<f64> = grid.iter().map(|&nm| light.at(nm)).collect();
    let y: f64 = raw
        .iter()
        .zip(&full.xyz_weights[1])
        .map(|(a, b)| a * b)
        .sum();
    let scale = full.xyz_weights[1].iter().sum::<f64>() / y;
    let lit: Vec<f64> = raw.iter().map(|v| v * scale).collect();
    let readings = |reflectance: &dyn Fn(f64) -> f64| -> Vec<f64> {
        channels
            .iter()
            .map(|c: &Curve| {
                grid.iter()
                    .zip(&lit)
                    .map(|(&nm, l)| c.at(nm) * l * reflectance(nm))
                    .sum()
            })
            .collect()
    };
    let patches =
        Spectra::builtin(&data, "data/reflectance_colorchecker_ohta.csv")?.curves(range)?;

    let mut rng = Rng(SEED);
    let n = channels.len();
    let gains: Vec<f64> = (0..n)
        .map(|_| 1.0 + GAIN_SPREAD * (2.0 * rng.uniform() - 1.0))
        .collect();
    let dark: Vec<f64> = (0..n)
        .map(|_| DARK_COUNTS[0] + (DARK_COUNTS[1] - DARK_COUNTS[0]) * rng.uniform())
        .collect();
    let mut device = |r: &[f64]| -> Vec<u16> {
        r.iter()
            .zip(gains.iter().zip(&dark))
            .map(|(r, (g, d))| count(EXPOSURE * g * r / unit + d + READ_NOISE * rng.normal()))
            .collect()
    };
    let white = readings(&|_| 1.0);
    let device_dark = device(&vec![0.0; n]);
    let device_white = device(&white);
    let mut golden = Vec::new();
    let mut simulated = Vec::new();
    let mut xyz = Vec::new();
    for p in &patches {
        let r = readings(&|nm| p.at(nm));
        golden.push(r.iter().map(|v| count(v / unit)).collect::<Vec<u16>>());
        simulated.push(device(&r));
        // The patch's exact XYZ under the same light (1 nm, the crate's observer).
        xyz.push([0, 1, 2].map(|c| {
            grid.iter()
                .zip(&full.xyz_weights[c])
                .zip(&lit)
                .map(|((&nm, w), l)| w * l * p.at(nm))
                .sum::<f64>() as f32
        }));
    }

    let mut o = String::new();
    writeln!(
        o,
        "// @generated by examples/sensor-firmware/build.rs: `cargo build` rewrites it."
    )?;
    writeln!(
        o,
        "/// The number of ColorChecker patches.\npub const PATCHES: usize = {};",
        patches.len()
    )?;
    writeln!(
        o,
        "/// The sensor's channels.\npub const CHANNELS: usize = {n};"
    )?;
    let names: Vec<&str> = patches.iter().map(|p| p.name.as_str()).collect();
    writeln!(o, "/// The patches' names, in the order of data/reflectance_colorchecker_ohta.csv.\npub const PATCH_NAMES: [&str; PATCHES] = {};", array(&names))?;
    writeln!(o, "/// The sample one count stands for (the baked integer set's `sample_unit`).\npub const SAMPLE_UNIT: f32 = {:?};", unit as f32)?;
    let rows = |v: &[Vec<u16>]| {
        let r: Vec<String> = v.iter().map(|x| array(x)).collect();
        format!("[\n    {},\n]", r.join(",\n    "))
    };
    writeln!(o, "/// The golden device's counts of each patch under C: 65535 is the largest channel's reading of white.\npub const GOLDEN_COUNTS: [[u16; CHANNELS]; PATCHES] = {};", rows(&golden))?;
    writeln!(o, "/// A simulated device's counts of each patch: exposure {EXPOSURE}, gains {}, dark offsets {} counts, read noise {READ_NOISE} counts.\npub const DEVICE_COUNTS: [[u16; CHANNELS]; PATCHES] = {};", array(&gains.iter().map(|g| format!("{g:.3}")).collect::<Vec<_>>()).replace('"', ""), array(&dark.iter().map(|d| format!("{d:.0}")).collect::<Vec<_>>()).replace('"', ""), rows(&simulated))?;
    writeln!(o, "/// The simulated device's dark reading (covered).\npub const DEVICE_DARK: [u16; CHANNELS] = {};", array(&device_dark))?;
    writeln!(o, "/// The simulated device's reading of a white of reflectance 1 under C.\npub const DEVICE_WHITE: [u16; CHANNELS] = {};", array(&device_white))?;
    let xyz_rows: Vec<String> = xyz.iter().map(|x| array(x)).collect();
    writeln!(o, "/// Each patch's exact XYZ under C (1 nm, the crate's observer; a spectrum of constant 1 has Y = UNIT_SPECTRUM_Y).\n#[allow(dead_code)]\npub const EXACT_XYZ: [[f32; 3]; PATCHES] = [\n    {},\n];", xyz_rows.join(",\n    "))?;
    std::fs::write(out.join("simulated.rs"), o)?;
    Ok(())
}
