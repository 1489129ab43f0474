//! Lights read by the example sensor (`data/sensor_as7341_gaussian.csv`): illuminance from a set
//! calibrated against one reading of illuminant A (as lux meters are), and CCT and Duv from the
//! set's XYZ, for every CIE illuminant and LED light in data/, against the exact values.
//!
//! `cargo test --release --test integration -- sensor_lights:: --nocapture` prints the table of
//! docs/colour-temperature-and-calibration.md.

mod common;

use spectral_quadrature::tables::PLANCKIAN_LOCUS;
use spectral_quadrature::{Error, LuxScale, Samples, WavelengthSet};
use spectral_quadrature_spectra::{builtin_illuminant, builtin_lights, Curve};
use std::path::Path;

/// The data files the derivation reads (the runtime crate's `data/`).
const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data");

/// A fitted set of the example sensor as the runtime bakes it (AC1C2 rows, f32).
fn sensor_set(
    d: &spectral_quadrature_generator::Derivation,
    fitted: &spectral_quadrature_generator::user::Fitted,
) -> WavelengthSet<8> {
    let m = d.opponent.xyz_to_ac1c2;
    WavelengthSet::new(
        core::array::from_fn(|k| fitted.wavelengths_nm[k] as f32),
        core::array::from_fn(|r| {
            core::array::from_fn(|k| {
                (0..3)
                    .map(|c| m[r][c] * fitted.xyz_weights[c][k])
                    .sum::<f64>() as f32
            })
        }),
        Samples::Readings {
            sensor: "AS7341",
            light: None,
        },
    )
    .unwrap()
}

/// Every light read through the sensor's set fitted for radiances and through the one fitted
/// for reflectances under C: the illuminance (calibrated on A) and the CCT within the measured
/// bounds below.
#[test]
fn lux_and_cct_of_the_lights() {
    let d = spectral_quadrature_generator::derive(&spectral_quadrature_generator::Settings::new(
        DATA_DIR,
    ))
    .unwrap();
    let range = d.settings.range_nm;
    let fits = [None, Some("C")].map(|light| common::example_sensor(&d, light));
    let sensor = fits[0].channels.as_ref().unwrap();
    let full = d.observer.full_integration(range, 1.0).unwrap();
    let lights: Vec<(&str, Curve)> = builtin_lights()
        .into_iter()
        .map(|n| {
            (
                n,
                builtin_illuminant(Path::new(DATA_DIR), n, range).unwrap(),
            )
        })
        .collect();
    let white = Curve::constant("white", 1.0, range);
    // Readings of each light seen directly: the golden readings of a perfect white under it.
    // Each light is scaled to the same luminance (Y = UNIT_SPECTRUM_Y): the illuminance the
    // set should report is the same for every light.
    let readings = |l: &Curve| -> [f32; 8] {
        let r = spectral_quadrature_generator::calibration::golden_readings(
            &d,
            sensor,
            Some(l),
            std::slice::from_ref(&white),
        )
        .unwrap()
        .remove(0);
        core::array::from_fn(|k| r[k] as f32)
    };
    println!("| light | exact CCT | radiance fit: lux error | CCT error | Duv error | fit under C: lux error | CCT error | Duv error |");
    println!("|---|---|---|---|---|---|---|---|");
    let sets = fits.each_ref().map(|f| sensor_set(&d, f));
    let a = &lights.iter().find(|(n, _)| *n == "A").unwrap().1;
    // Calibrated on one reading of A, at 1000 lx.
    let scales = sets.map(|s| LuxScale::from_reading(s.xyz(&readings(a))[1], 1000.0).unwrap());
    let mut worst = [[0.0f64; 3]; 2];
    // The same without the triband fluorescent lamps F10-F12.
    let mut worst_broad = [[0.0f64; 3]; 2];
    for (name, l) in &lights {
        let exact_xyz = full.xyz(|nm| l.at(nm)).map(|v| v as f32);
        let exact = PLANCKIAN_LOCUS.cct(exact_xyz).unwrap();
        let mut line = format!("| {name} | {:.0} K |", exact.kelvin);
        for (i, set) in sets.iter().enumerate() {
            let xyz = set.xyz(&readings(l));
            let lux_error = scales[i].lux(xyz) / 1000.0 - 1.0;
            let got = PLANCKIAN_LOCUS.cct(xyz).unwrap();
            let dt = got.kelvin - exact.kelvin;
            let dduv = got.duv - exact.duv;
            line += &format!(" {:+.2} % | {dt:+.1} K | {dduv:+.5} |", 100.0 * lux_error);
            let errors = [lux_error, dt, dduv].map(|e| f64::from(e.abs()));
            for (w, e) in worst[i].iter_mut().zip(errors) {
                *w = w.max(e);
            }
            if !["F10", "F11", "F12"].contains(name) {
                for (w, e) in worst_broad[i].iter_mut().zip(errors) {
                    *w = w.max(e);
                }
            }
        }
        println!("{line}");
    }
    println!(
        "worst: radiance fit {:.2} %, {:.1} K, {:.5}; fit under C {:.2} %, {:.1} K, {:.5}",
        100.0 * worst[0][0],
        worst[0][1],
        worst[0][2],
        100.0 * worst[1][0],
        worst[1][1],
        worst[1][2]
    );
    // Measured bounds of this model sensor (Gaussian channels), rounded up: with either fit it
    // reads every light's illuminance within 3 % (measured 2.7 %), its CCT within 360 K
    // (353 K) and its Duv within 0.0015 (0.00143), the worst being the triband fluorescent
    // lamps F10-F12, whose narrow lines eight broad channels cannot resolve; the others within
    // 1.2 % (1.19 %) and 115 K (112 K).
    for (i, w) in worst.iter().enumerate() {
        assert!(w[0] < 0.03 && w[1] < 360.0 && w[2] < 0.0015, "{i}: {w:?}");
        let b = worst_broad[i];
        assert!(b[0] < 0.012 && b[1] < 115.0, "{i}: {b:?}");
    }
}

/// What `LuxScale::SPECTRAL_IRRADIANCE` assumes: V(λ) is the scene's ȳ over the scene's range
/// (380-770 nm by default), where CIE 015 has illuminance K_m ∫ V(λ) E(λ) dλ over 360-830 nm
/// (V = ȳ of CIE 1931 2°). For every CIE illuminant and LED light in data/ (each file linearly
/// interpolated to 1 nm, zero outside its range; A, C, D50, D65 and E reach below 380 nm, none
/// beyond 780 nm), the Y of the scene's range falls short of the standard's by less than 1e-5
/// relative (measured 6.5e-6, E; 4.9e-6 for A; below 3e-7 for the lamps and LEDs, which have
/// no power below 380 nm): far below what a set's own quadrature or a sensor's calibration
/// errs by (0.04 % and more in the table above), so the scale is not corrected. Prints the numbers of docs/colour-temperature-and-calibration.md.
#[test]
fn spectral_irradiance_y_against_cie_015s_range() {
    use common::cie015::{plain_light_xyz, plain_light_xyz_over};
    let d = spectral_quadrature_generator::derive(&spectral_quadrature_generator::Settings::new(
        DATA_DIR,
    ))
    .unwrap();
    let [lo, hi] = d.settings.range_nm.map(|nm| nm as u32);
    let mut worst = (0.0f64, "");
    println!("| light | Y over {lo}-{hi} nm / Y over 360-830 nm − 1 |");
    println!("|---|---|");
    for name in builtin_lights() {
        let scene = plain_light_xyz_over([lo, hi], name)[1];
        let standard = plain_light_xyz(name)[1];
        let relative = scene / standard - 1.0;
        println!("| {name} | {relative:+.1e} |");
        // The range only leaves power out: never more than the standard's.
        assert!(relative <= 0.0, "{name}: {relative}");
        if relative.abs() > worst.0 {
            worst = (relative.abs(), name);
        }
    }
    println!("largest: {:.1e} ({})", worst.0, worst.1);
    assert!(worst.0 < 1e-5, "{worst:?}");
}

/// `LuxScale::new` and `from_reading` refuse whatever gives no finite, positive scale, with
/// `Error::InvalidLuxScale`, and never panic; what they accept is the ratio, exactly.
#[test]
fn lux_scale_refuses_what_gives_no_scale() {
    let refused = Err(Error::InvalidLuxScale);
    assert_eq!(LuxScale::new(683.002), Ok(LuxScale::SPECTRAL_IRRADIANCE));
    assert_eq!(
        LuxScale::new(f32::MIN_POSITIVE / 2.0).map(|s| s.lux_per_y()),
        Ok(f32::MIN_POSITIVE / 2.0)
    );
    for bad in [0.0, -0.0, -1.0, f32::NAN, f32::INFINITY, -f32::INFINITY] {
        assert_eq!(LuxScale::new(bad), refused, "{bad}");
    }
    assert_eq!(
        LuxScale::from_reading(0.0125, 500.0),
        LuxScale::new(40_000.0)
    );
    for (y, lux) in [
        (0.0, 500.0),
        (-1.0, 500.0),
        (f32::NAN, 1.0),
        (1.0, f32::NAN),
        (1.0, 0.0),
        (1.0, -3.0),
        (f32::INFINITY, 1.0),
        (1.0, f32::INFINITY),
        // The ratio overflows f32.
        (1e-30, 1e30),
    ] {
        assert_eq!(LuxScale::from_reading(y, lux), refused, "{y} {lux}");
    }
}
