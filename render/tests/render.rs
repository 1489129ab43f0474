//! The path tracer of the render tool (`render`): every method on a furnace-like box (every
//! paint a flat grey, so that each path's spectrum is the light's times a number) against the
//! 1 nm reference through the same paths, the vector loop against the baseline loop, the
//! reference's two-seed estimate of its own error against a finer reference, the scene
//! file's errors, where a curve of error against time is taken to have flattened and where one
//! curve passes below another (against curves whose answers are known in closed form), and the
//! pictures' labels.

use std::path::Path;
use std::sync::OnceLock;

use spectral_quadrature_generator::Derivation;
use spectral_quadrature_render::cornell::picture::{self, Rgb8, LABEL_MARGIN};
use spectral_quadrature_render::render::curves::{self, Point};
use spectral_quadrature_render::render::measure::{self, CachedReference};
use spectral_quadrature_render::render::methods::{Method, Setup, HERO};
use spectral_quadrature_render::render::scene::Scene;
use spectral_quadrature_render::render::transport::{has_avx2, Geometry, Options};
use spectral_quadrature_spectra::Curve;
use spectral_quadrature_tools::random_wavelengths::Sampler;

fn derivation() -> &'static Derivation {
    static D: OnceLock<Derivation> = OnceLock::new();
    D.get_or_init(|| {
        spectral_quadrature_generator::derive(&spectral_quadrature_tools::settings()).unwrap()
    })
}

fn scene_file(name: &str) -> std::path::PathBuf {
    Path::new(spectral_quadrature_tools::CRATE_DIR)
        .join("examples/render")
        .join(name)
}

/// Scene (a) with every paint a flat 0.5: a path's spectrum is the light's times a number.
fn furnace(file: &str) -> Scene {
    let mut s = Scene::read(&scene_file(file), derivation()).unwrap();
    for p in s.data.paints.iter_mut() {
        *p = Curve::constant(&p.name, 0.5, [400.0, 700.0]);
    }
    s
}

fn opts(seed: u64) -> Options {
    Options {
        seed,
        threads: 2,
        simd: true,
    }
}

/// The largest relative difference of X, Y or Z over the seen pixels.
fn max_relative(a: &[[f64; 3]], b: &[[f64; 3]], seen: &[usize]) -> f64 {
    seen.iter()
        .flat_map(|&k| (0..3).map(move |c| (a[k][c] - b[k][c]).abs() / b[k][c].abs().max(1e-30)))
        .fold(0.0, f64::max)
}

#[test]
fn every_fixed_method_and_rgb_match_the_reference_on_flat_paints_through_the_same_paths() {
    // One light (a: folded sets) and two (b: light groups).
    for file in ["a.toml", "b-f11.toml"] {
        let scene = furnace(file);
        let setup = Setup::new(&scene, derivation()).unwrap();
        let g = Geometry::new(&scene, 12);
        let seen = measure::seen(&g);
        assert!(
            seen.len() > 100,
            "{file}: {} pixels see the box",
            seen.len()
        );
        let spp = [8];
        let reference = setup.render(Method::Reference, &g, &spp, opts(7)).unwrap();
        let r = &reference.images[0];
        // A flat reflectance is integrated exactly by a folded set or light group (each white
        // is pinned) and by RGB (grey times the light's own colour), so the same paths give the
        // same pixels up to f32: the path products, the weights and display matrices in f32 and
        // the 301-term reference sums. Measured at most 2.7e-7 (the fixed sets) and 9e-8 (RGB);
        // 1e-5 leaves a factor of 37 and still catches one path traced differently (a path is
        // 1/8 of a pixel here).
        for method in [Method::Rgb]
            .into_iter()
            .chain([4, 6, 8, 16].map(|n| Method::Fixed { n }))
        {
            let img = setup.render(method, &g, &spp, opts(7)).unwrap();
            let d = max_relative(&img.images[0], r, &seen);
            eprintln!(
                "{file}: {}: largest relative difference {d:e}",
                method.name()
            );
            assert!(
                d < 1e-5,
                "{file}: {}: relative difference {d:e}",
                method.name()
            );
        }
        // Another seed: other paths, so pixels differ by far more than the bound above.
        let other = setup.render(Method::Rgb, &g, &spp, opts(8)).unwrap();
        assert!(max_relative(&other.images[0], r, &seen) > 1e-2);
    }
}

#[test]
fn random_wavelengths_average_to_the_reference_on_flat_paints() {
    let scene = furnace("a.toml");
    let setup = Setup::new(&scene, derivation()).unwrap();
    let g = Geometry::new(&scene, 12);
    let seen = measure::seen(&g);
    let spp = [16];
    let reference = setup.render(Method::Reference, &g, &spp, opts(3)).unwrap();
    let sum = |img: &[[f64; 3]]| -> [f64; 3] {
        let mut s = [0.0; 3];
        for &k in &seen {
            for c in 0..3 {
                s[c] += img[k][c];
            }
        }
        s
    };
    let want = sum(&reference.images[0]);
    for (sampler, k) in [
        (Sampler::Visible, 4),
        (HERO, 4),
        (Sampler::Visible, 16),
        (HERO, 16),
    ] {
        let m = Method::Random { sampler, k };
        let img = setup.render(m, &g, &spp, opts(3)).unwrap();
        let got = sum(&img.images[0]);
        // The paths are the reference's, so the ratio is the spectral estimate alone, averaged
        // over the seen pixels' 16 paths each (about 2000 paths) of a smooth light's spectrum.
        // Measured within 0.15 % of 1 (pbrt-v4 ×4's Z, the widest); 1 % leaves a factor of 7,
        // and a density off by a constant (a missing 1/K, a cut range) is off by far more.
        for c in 0..3 {
            let ratio = got[c] / want[c];
            eprintln!("{}: channel {c}: ratio {ratio}", m.name());
            assert!(
                (ratio - 1.0).abs() < 0.01,
                "{}: channel {c}: {ratio}",
                m.name()
            );
        }
    }
}

#[test]
fn the_vector_loop_gives_the_baseline_loops_bits() {
    if !has_avx2() {
        eprintln!("no AVX2 on this CPU: only the baseline loop runs");
        return;
    }
    let scene = Scene::read(&scene_file("c-f11.toml"), derivation()).unwrap();
    let setup = Setup::new(&scene, derivation()).unwrap();
    let g = Geometry::new(&scene, 10);
    for method in [
        Method::Fixed { n: 8 },
        Method::Random {
            sampler: HERO,
            k: 4,
        },
    ] {
        let a = setup.render(method, &g, &[4], opts(11)).unwrap();
        let b = setup
            .render(
                method,
                &g,
                &[4],
                Options {
                    simd: false,
                    ..opts(11)
                },
            )
            .unwrap();
        assert!(a.avx2 && !b.avx2);
        // No fused multiply-add is enabled in either: the same IEEE operations in the same
        // order, so the same bits.
        assert_eq!(a.images, b.images, "{}", method.name());
    }
}

#[test]
fn the_references_two_seed_estimate_matches_its_error_against_a_finer_reference() {
    let scene = Scene::read(&scene_file("a.toml"), derivation()).unwrap();
    let setup = Setup::new(&scene, derivation()).unwrap();
    let g = Geometry::new(&scene, 10);
    let seen = measure::seen(&g);
    let spp = 128;
    let a = setup
        .render(Method::Reference, &g, &[spp], opts(21))
        .unwrap();
    let b = setup
        .render(Method::Reference, &g, &[spp], opts(22))
        .unwrap();
    let fine = setup
        .render(Method::Reference, &g, &[32 * spp], opts(23))
        .unwrap();
    let white = measure::white(derivation(), &scene, &fine.images[0], &seen).unwrap();
    let r = CachedReference::from_pair(
        &a.images[0],
        &b.images[0],
        &seen,
        white,
        (10, spp, [21, 22], 0.0, String::new()),
    );
    let (actual, _) = measure::stats(&r.xyz, &fine.images[0], &seen, white);
    // The finer reference has 1/16 of the pair's variance: its own error adds about 3 % (in
    // quadrature) to the measured one. The pair's estimate is itself a mean over about 90
    // pixels of a noisy difference: measured 0.93 of the error against the finer reference;
    // a wrong halving (÷√2, or none) would be at 1.3 or 1.9.
    let ratio = r.own_mean / actual;
    eprintln!(
        "estimated {} against {actual} measured: {ratio}",
        r.own_mean
    );
    assert!(
        (0.75..1.2).contains(&ratio),
        "estimated {} against {actual} measured",
        r.own_mean
    );
    // The cache file's text reads back as written.
    let dir = std::env::temp_dir().join("render-test-reference");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("a-10.txt");
    std::fs::write(&path, r.to_text("the test")).unwrap();
    let back = CachedReference::read(&path).unwrap();
    assert_eq!((back.size, back.spp, back.seeds), (10, spp, [21, 22]));
    assert!((back.own_mean - r.own_mean).abs() < 1e-6);
    for (x, y) in back.xyz.iter().zip(&r.xyz) {
        for c in 0..3 {
            assert!((x[c] - y[c]).abs() <= 1e-6 * y[c].abs());
        }
    }
}

#[test]
fn a_bad_scene_file_is_an_error_naming_the_file_and_line() {
    let dir = std::env::temp_dir().join("render-test-scenes");
    std::fs::create_dir_all(&dir).unwrap();
    let cases = [
        (
            "scene = \"a\"\nlight = \"box\"\ndescription = \"x\"\npaints = \"painted\"\n[[lights]]\nspectrum = \"box\"\nquad = \"light\"\n",
            4,
            "measured",
        ),
        (
            "scene = \"a\"\nlight = \"box\"\ndescription = \"x\"\npaints = \"measured\"\n[[lights]]\nspectrum = \"NOPE\"\nquad = \"light\"\n",
            6,
            "NOPE",
        ),
        (
            "scene = \"a\"\nlight = \"box\"\ndescription = \"x\"\npaints = \"measured\"\ncolour = 3\n",
            5,
            "colour",
        ),
    ];
    for (k, (text, line, word)) in cases.iter().enumerate() {
        let path = dir.join(format!("bad{k}.toml"));
        std::fs::write(&path, text).unwrap();
        let e = Scene::read(&path, derivation()).unwrap_err().to_string();
        let at = format!("{}:{line}:", path.display());
        assert!(e.contains(&at) && e.contains(word), "{e}");
    }
}

/// A curve of error `e² = b² + σ²/spp` (a bias `b` and noise that falls as 1/√spp), one second a
/// path a pixel, at 1, 2, 4, … up to `max` paths a pixel.
fn biased(b: f64, sigma: f64, max: usize) -> Vec<Point> {
    std::iter::successors(Some(1usize), |s| Some(s * 2))
        .take_while(|&s| s <= max)
        .map(|spp| {
            let mean = (b * b + sigma * sigma / spp as f64).sqrt();
            Point {
                spp,
                seconds: spp as f64,
                mean,
                p95: 2.0 * mean,
            }
        })
        .collect()
}

#[test]
fn a_curve_flattens_where_its_bias_dominates_and_never_when_it_is_all_noise() {
    // curves::FLAT's documented bound: with r = σ²/(b²·spp) at the level before the last, a fall
    // of FLAT over the doubling is (1 + r)/(1 + r/2) = 1.05², r = 0.2284, so the last point is
    // within √(1 + r/2) = 1.0556 of the bias when the curve stops, and the point before a
    // doubling that fell by more is not (the bound's own arithmetic; 1e-9 for rounding).
    let bound = (1.0 + 0.5 * (1.05f64.powi(2) - 1.0) / (1.0 - 0.5 * 1.05f64.powi(2))).sqrt();
    assert!((bound - 1.0556).abs() < 1e-4, "{bound}");
    for (b, sigma) in [(0.4, 15.0), (0.8, 15.0), (0.05, 20.0), (1.0, 1.0)] {
        let pts = biased(b, sigma, 1 << 24);
        let k = (1..=pts.len())
            .find(|&k| curves::flattened(&pts[..k]))
            .unwrap_or_else(|| panic!("b {b}, σ {sigma}: never flattened"));
        let at = pts[k - 1];
        assert!(
            at.mean / b <= bound + 1e-9,
            "b {b}, σ {sigma}: flat at {} spp, {} of b",
            at.spp,
            at.mean / b
        );
        // The first level where it holds: the doubling before fell by more than FLAT, so the
        // point before the last was farther than the bound from the bias.
        assert!(k >= 3, "b {b}, σ {sigma}: flat at {} spp", at.spp);
        assert!(
            !curves::flattened(&pts[..k - 1]),
            "b {b}: flat one level early"
        );
        assert!(
            pts[k - 2].mean / b >= bound - 1e-9,
            "b {b}: {} of b one level before",
            pts[k - 2].mean / b
        );
    }
    // All noise: the mean halves every four doublings (a fall of 29 %), never flat.
    let noise = biased(0.0, 10.0, 1 << 20);
    assert!((1..=noise.len()).all(|k| !curves::flattened(&noise[..k])));
}

#[test]
fn a_curve_read_between_its_points_in_log_log_and_where_one_passes_below_another() {
    // A power law is a line in log-log: read between two points it is exact.
    let pts = biased(0.0, 3.0, 1024);
    for t in [1.5, 3.0, 100.0, 700.0] {
        let e = curves::at_time(&pts, t).unwrap();
        let want = 3.0 / t.sqrt();
        assert!((e / want - 1.0).abs() < 1e-12, "{t} s: {e} against {want}");
    }
    assert_eq!(curves::at_time(&pts, 0.5), None);
    assert_eq!(curves::at_time(&pts, 2048.0), None);
    // Unbiased noise 3/√t against a biased curve stopped at 64 s (then held at its last
    // value, 0.5·√(1 + 1/64)·…): the first falls below the second's last value once
    // 3/√t < e(64), at t > 9/e(64)², and stays below.
    let fixed = biased(0.5, 2.0, 64);
    let last = fixed.last().unwrap().mean;
    let k = curves::passes_below(&pts, &fixed).expect("passes below");
    let t_cross = 9.0 / (last * last);
    assert!(
        pts[k].seconds > t_cross && pts[k - 1].seconds <= t_cross,
        "{} s, crossing at {t_cross} s",
        pts[k].seconds
    );
    // The biased curve is above the unbiased one at its last point (0.52 against 3/8 at 64 s):
    // it is not below for good, whatever it was before.
    assert!(curves::at_time(&pts, 64.0).unwrap() < last);
    assert_eq!(curves::passes_below(&fixed, &pts), None);
    // Below at every point of the shorter noise curve: from its first point on.
    assert_eq!(curves::passes_below(&fixed, &pts[..5]), Some(0));
    assert_eq!(curves::median(&[3.0, 1.0, 2.0, 10.0]), 2.5);
    assert_eq!(curves::median(&[3.0, 1.0, 2.0]), 2.0);
}

#[test]
fn labels_wrap_inside_their_panel_with_a_margin_and_never_run_into_the_next() {
    let tile = Rgb8::filled(128, 64, [0, 0, 0]);
    for text in [
        "reference (1 nm)",
        "hero ×16, 64 spp",
        "RGB (paints' sRGB under D65)",
        "pbrt-v4 visible ×16",
        "averyveryverylongnamewithoutspaces",
    ] {
        let img = picture::labelled(&tile, text, 3);
        let strip = 3 * picture::LABEL_LINE;
        let background = [24u8, 24, 24];
        let mut ink = false;
        for y in 0..strip {
            for x in 0..img.width {
                let px = &img.data[(y * img.width + x) * 3..][..3];
                if px != background {
                    ink = true;
                    assert!(
                        x < img.width - LABEL_MARGIN,
                        "{text:?}: ink at column {x} of {}, in the margin",
                        img.width
                    );
                }
            }
        }
        assert!(ink, "{text:?}: nothing drawn");
    }
}
