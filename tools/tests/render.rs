//! The path tracer of the render tool (`render`): every method on a furnace-like box (every
//! paint a flat grey, so that each path's spectrum is the light's times a number) against the
//! 1 nm reference through the same paths, the vector loop against the baseline loop, the
//! reference's two-seed estimate of its own error against a finer reference, and the scene
//! file's errors.

use std::path::Path;
use std::sync::OnceLock;

use spectral_quadrature_generator::Derivation;
use spectral_quadrature_spectra::Curve;
use spectral_quadrature_tools::random_wavelengths::Sampler;
use spectral_quadrature_tools::render::measure::{self, CachedReference};
use spectral_quadrature_tools::render::methods::{Method, Setup, HERO};
use spectral_quadrature_tools::render::scene::Scene;
use spectral_quadrature_tools::render::transport::{has_avx2, Geometry, Options};

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
