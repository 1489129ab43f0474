//! Spiky spectra and pre-filtering: band averaging (a) and exact lines (b).

use spectral_quadrature_tools as tools;

/// The data files the derivation reads (the runtime crate's `data/`).
const DATA_DIR: &str = spectral_quadrature_tools::DATA_DIR;

use spectral_quadrature_generator::{derive, Settings};
use spectral_quadrature_spectra::{
    builtin_illuminant, surfaces_under_lights, Curve, EvalSet, Reference, Stimulus,
};
use tools::prefilter::{self, BandShape, ChannelSet, LineDetection, Method, Prefiltered};

const RANGE: [f64; 2] = [380.0, 770.0];

fn reference_set() -> EvalSet {
    let obs = spectral_quadrature_generator::ObserverId::Cie1931_2deg
        .load(std::path::Path::new(DATA_DIR))
        .unwrap();
    obs.full_integration(RANGE, 1.0).unwrap()
}

fn table2_sets(d: &spectral_quadrature_generator::Derivation) -> Vec<ChannelSet> {
    prefilter::default_sets(d)
        .unwrap()
        .into_iter()
        .take(2)
        .collect()
}

/// ColorChecker + TCS under each F lamp (lamp-major, as `surfaces_under_lights` lists them).
fn f_series_stimuli() -> Vec<Stimulus> {
    let surfaces = prefilter::default_surfaces(RANGE).unwrap();
    surfaces_under_lights(&surfaces, &prefilter::f_series(RANGE).unwrap())
}

#[test]
fn plain_method_matches_evaluate() {
    let d = derive(&Settings::new(DATA_DIR)).unwrap();
    let stimuli = f_series_stimuli();
    let reference = Reference::new(reference_set(), &stimuli);
    let mut sets = table2_sets(&d);
    sets.push(d.observer.uniform_set(RANGE, 6).into());
    for cs in &sets {
        let mine = prefilter::errors(cs, &reference, &stimuli, Method::Plain);
        let theirs = reference.errors(&cs.set, &stimuli);
        for (a, b) in mine.de00.iter().zip(&theirs.de00) {
            assert!((a - b).abs() < 1e-9, "{}: {a} vs {b}", cs.set.name);
        }
        for (a, b) in mine.de76.iter().zip(&theirs.de76) {
            assert!((a - b).abs() < 1e-9, "{}: {a} vs {b}", cs.set.name);
        }
    }
}

#[test]
fn band_averaging_a_constant_is_the_identity() {
    let d = derive(&Settings::new(DATA_DIR)).unwrap();
    let reference = reference_set();
    let value = 3.7;
    let flat = Curve::constant("flat", value, RANGE);
    for cs in prefilter::default_sets(&d).unwrap() {
        let set = &cs.set;
        for s in prefilter::band_averaged_samples(&flat, set, RANGE) {
            assert!((s - value).abs() < 1e-12, "{}: {s}", set.name);
        }
        for row in prefilter::sensitivity_weighted_samples(&flat, set, &reference, RANGE) {
            for s in row {
                assert!((s - value).abs() < 1e-12, "{}: {s}", set.name);
            }
        }
        // Per channel: the effective weights are the set's own times the constant.
        let w = prefilter::channel_band_weights(&cs, &flat, RANGE);
        for (row, own) in w.iter().zip(&set.xyz_weights) {
            for (a, b) in row.iter().zip(own) {
                assert!(
                    (a - value * b).abs() < 1e-12 * (1.0 + b.abs()),
                    "{}",
                    set.name
                );
            }
        }
        // And every method reads the constant as the plain method does.
        for m in Method::ALL {
            let p = Prefiltered::new(&flat, &cs, &reference, m);
            let plain = set.xyz(|_| value);
            let got = p.xyz(set, None);
            for c in 0..3 {
                let tol = 1e-9 * plain[c].abs().max(1.0);
                if m == Method::LampAdapted && cs.channels.is_some() {
                    // Lamp-adapted weights integrate the constant exactly (the reference's
                    // answer), not as the set's rule does.
                    let exact = reference.xyz(|_| value);
                    assert!((got[c] - exact[c]).abs() < tol, "{} {c}", set.name);
                } else {
                    assert!(
                        (got[c] - plain[c]).abs() < tol,
                        "{} {}: {got:?} vs {plain:?}",
                        set.name,
                        m.as_str()
                    );
                }
            }
        }
    }
    // The band mean integrates the linear interpolant exactly: a ramp averages to its midpoint.
    let ramp = Curve {
        name: "ramp".into(),
        wavelengths: vec![380.0, 500.0, 770.0],
        values: vec![1.0, 2.2, 4.9],
    };
    for band in [
        [390.0, 410.0],
        [450.0, 560.0],
        [600.0, 770.0],
        [499.0, 501.0],
    ] {
        let mid = 0.5 * (band[0] + band[1]);
        let m = prefilter::band_mean(&ramp, band);
        // 1 + (λ - 380) / 100 on both pieces: the interpolant is one straight line.
        assert!(
            (m - (1.0 + (mid - 380.0) / 100.0)).abs() < 1e-12,
            "{band:?}: {m}"
        );
    }
    assert_eq!(
        prefilter::node_bands(&[450.0, 550.0, 650.0], RANGE),
        vec![[380.0, 500.0], [500.0, 600.0], [600.0, 770.0]]
    );
}

#[test]
fn lines_are_found_in_f2_and_f11_and_not_in_smooth_lamps() {
    let det = LineDetection::default();
    for name in ["F2", "F11"] {
        let lamp = builtin_illuminant(std::path::Path::new(DATA_DIR), name, RANGE).unwrap();
        let lines = prefilter::detect_lines(&lamp, RANGE, &det);
        for known in [404.7, 435.8, 546.1] {
            assert!(
                lines.iter().any(|l| (l.nm - known).abs() <= 5.0),
                "{name}: no line near the mercury line at {known} nm in {lines:?}"
            );
        }
        for l in &lines {
            assert!(l.height > 0.0 && l.power() > 0.0);
            // A 5 nm table: each line is a hat 10 nm wide of power height × 5 nm.
            assert_eq!(l.support_nm, [l.nm - 5.0, l.nm + 5.0]);
            assert!((l.power() - 5.0 * l.height).abs() < 1e-12);
        }
    }
    // Every F lamp has the three mercury lines; F10-F12 add europium's 610 and 710 nm.
    for lamp in prefilter::f_series(RANGE).unwrap() {
        let nm: Vec<f64> = prefilter::detect_lines(&lamp, RANGE, &det)
            .iter()
            .map(|l| l.nm)
            .collect();
        let expected: &[f64] = if ["F10", "F11", "F12"].contains(&lamp.name.as_str()) {
            &[405.0, 435.0, 545.0, 610.0, 710.0]
        } else {
            &[405.0, 435.0, 545.0]
        };
        assert_eq!(nm, expected, "{}", lamp.name);
    }
    let mut smooth: Vec<Curve> = ["D65", "A", "C", "D50", "E"]
        .iter()
        .map(|n| builtin_illuminant(std::path::Path::new(DATA_DIR), n, RANGE).unwrap())
        .collect();
    smooth.extend(prefilter::led_lamps(RANGE).unwrap());
    for lamp in &smooth {
        let lines = prefilter::detect_lines(lamp, RANGE, &det);
        assert!(lines.is_empty(), "{}: {lines:?}", lamp.name);
    }
}

#[test]
fn smooth_remainder_plus_lines_is_the_lamp() {
    let reference = reference_set();
    let det = LineDetection::default();
    for lamp in prefilter::f_series(RANGE).unwrap() {
        let split = prefilter::split_lines(&lamp, RANGE, &det);
        assert!(!split.lines.is_empty());
        // Pointwise: remainder + hats = the table's interpolant.
        for k in 0..=4 * 390 {
            let nm = 380.0 + 0.25 * k as f64;
            let sum = split.smooth.at(nm) + split.lines.iter().map(|l| l.profile(nm)).sum::<f64>();
            assert!((sum - lamp.at(nm)).abs() < 1e-12, "{} at {nm}", lamp.name);
        }
        // Integrated: the lamp's full (1 nm) XYZ, to rounding.
        let full = reference.xyz(|l| lamp.at(l));
        let mut parts = reference.xyz(|l| split.smooth.at(l));
        for line in &split.lines {
            let t = line.tristimulus(&reference);
            for c in 0..3 {
                parts[c] += t[c];
            }
        }
        for c in 0..3 {
            let rel = (parts[c] - full[c]).abs() / full[c];
            assert!(
                rel < 1e-13,
                "{} channel {c}: {parts:?} vs {full:?}",
                lamp.name
            );
        }
        // The lines carry a real share of the lamp's luminance.
        let line_y: f64 = split
            .lines
            .iter()
            .map(|l| l.tristimulus(&reference)[1])
            .sum();
        assert!(line_y > 0.02 * full[1], "{}", lamp.name);
    }
}

#[test]
fn prefiltering_lowers_table2_error_on_the_f_series() {
    // Measured (mean ΔE00 over ColorChecker + TCS under F1-F12, 456 stimuli):
    //              plain  band (common)  band (per channel)  lines exact  both
    //   row 1      6.06   6.81           4.33                4.37         3.80
    //   row 2      5.96   4.60           4.33                4.33         3.79
    // Margins: each helpful method at least 20 % below plain (measured 27-37 %). Common bands
    // make row 1 worse: its A nodes 483.1 and 632.3 nm sit 7.8 and 0.8 nm from C1's, so their
    // common bands are 17 and 138 nm wide instead of A's own 140 and 175 nm; asserted as is.
    let d = derive(&Settings::new(DATA_DIR)).unwrap();
    let stimuli = f_series_stimuli();
    let reference = Reference::new(reference_set(), &stimuli);
    let mean =
        |cs: &ChannelSet, m: Method| prefilter::errors(cs, &reference, &stimuli, m).mean_de00();
    let sets = table2_sets(&d);
    for (k, cs) in sets.iter().enumerate() {
        let plain = mean(cs, Method::Plain);
        let common = mean(cs, Method::BandAveraged);
        let channel = prefilter::evaluate_band_averaged(cs, &reference, &stimuli).mean_de00();
        let lines = prefilter::evaluate_lines_exact(cs, &reference, &stimuli).mean_de00();
        let both = mean(cs, Method::LinesExactBandAveraged(LineDetection::default()));
        eprintln!(
            "{}: plain {plain:.3} band {common:.3} channel band {channel:.3} lines {lines:.3} both {both:.3}",
            cs.set.name
        );
        assert!((5.0..7.0).contains(&plain), "{plain}");
        assert!(
            channel < 0.8 * plain,
            "{}: {channel} vs {plain}",
            cs.set.name
        );
        assert!(lines < 0.8 * plain, "{}: {lines} vs {plain}", cs.set.name);
        assert!(both < channel.min(lines), "{}: {both}", cs.set.name);
        if k == 0 {
            assert!(common > 1.05 * plain, "row 1: {common} vs {plain}");
        } else {
            assert!(common < 0.85 * plain, "row 2: {common} vs {plain}");
        }
    }
}

#[test]
fn lines_seen_directly() {
    let d = derive(&Settings::new(DATA_DIR)).unwrap();
    let reference = reference_set();
    let lines = prefilter::monochromatic_lines(RANGE, 1.0);
    assert_eq!(lines.len(), 391);
    let r = Reference::new(reference.clone(), &lines);
    let row2 = &table2_sets(&d)[1];
    // Plain sampling: a line more than 1 nm from every node is black to the set.
    let plain = prefilter::errors(row2, &r, &lines, Method::Plain);
    let missed = lines
        .iter()
        .zip(&plain.de00)
        .filter(|(s, _)| {
            let nm = s.light.wavelengths[1];
            row2.set
                .wavelengths_nm
                .iter()
                .all(|n| (n - nm).abs() >= 1.0)
        })
        .map(|(_, e)| *e)
        .collect::<Vec<_>>();
    assert!(missed.len() > 380);
    assert!(missed.iter().all(|e| *e > 50.0), "{missed:?}");
    // A line is a line: (b) integrates it exactly, up to nothing at all.
    let exact = prefilter::errors(
        row2,
        &r,
        &lines,
        Method::LinesExact(LineDetection::default()),
    );
    assert!(exact.max_de00() < 0.01, "{}", exact.max_de00());
    // Lamp-adapted weights integrate any light seen directly exactly.
    let adapted = prefilter::errors(row2, &r, &lines, Method::LampAdapted);
    assert!(adapted.max_de00() < 0.01, "{}", adapted.max_de00());
    // Band averaging sees every line, if with the node's colour: the median drops.
    let band = prefilter::errors(row2, &r, &lines, Method::ChannelBandAveraged);
    let median = |v: &[f64]| {
        let mut s = v.to_vec();
        s.sort_by(f64::total_cmp);
        s[s.len() / 2]
    };
    assert!(median(&band.de00) < 0.7 * median(&plain.de00));
}

#[test]
fn lamp_adapted_weights_integrate_the_lamp_exactly() {
    let d = derive(&Settings::new(DATA_DIR)).unwrap();
    let reference = reference_set();
    for cs in table2_sets(&d) {
        for lamp in prefilter::f_series(RANGE).unwrap() {
            let p = Prefiltered::new(&lamp, &cs, &reference, Method::LampAdapted);
            let got = p.xyz(&cs.set, None);
            let full = reference.xyz(|l| lamp.at(l));
            for c in 0..3 {
                let rel = (got[c] - full[c]).abs() / full[c];
                assert!(
                    rel < 1e-9,
                    "{} {} {c}: {got:?} {full:?}",
                    cs.set.name,
                    lamp.name
                );
            }
        }
    }
}

#[test]
fn narrow_bands_have_their_width() {
    let reference = reference_set();
    for w in [5.0, 10.0, 20.0] {
        let boxes = prefilter::narrow_bands(&[w], &[550.0, 552.5], BandShape::Box);
        let gauss = prefilter::narrow_bands(&[w], &[550.0], BandShape::Gaussian);
        // On the 1 nm grid a box integrates to its width, a Gaussian to w·√(π / 4 ln 2).
        for b in &boxes {
            let area: f64 = reference
                .wavelengths_nm
                .iter()
                .map(|&l| b.light.at(l))
                .sum();
            assert!((area - w).abs() < 1e-9, "{}: {area}", b.name);
        }
        let g = &gauss[0].light;
        let area: f64 = reference.wavelengths_nm.iter().map(|&l| g.at(l)).sum();
        let expected = w * (std::f64::consts::PI / (4.0 * std::f64::consts::LN_2)).sqrt();
        assert!(
            (area - expected).abs() < 1e-6 * expected,
            "{w}: {area} vs {expected}"
        );
        if (0.5 * w).fract() == 0.0 {
            // Half maximum at ± w / 2 (a 1 nm knot there).
            assert!((g.at(550.0 + 0.5 * w) - 0.5).abs() < 1e-12);
        }
        assert_eq!(g.at(500.0 - 4.0 * w), 0.0);
    }
}
