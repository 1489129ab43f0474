//! The random-wavelength samplers the report measures the fixed sets against: each density
//! integrates to 1 on its range and is the density its wavelengths are drawn with, each
//! estimator is unbiased for the report's 1 nm reference integral, the prepared estimator the
//! trials run gives the sampler's own estimates, and the f32 path the report times computes what
//! the f64 one does.

use spectral_quadrature_tools::random_wavelengths::{
    pixel_rng, reach, run_trials, Cells, Config, Estimator, Reach, Sampler, SensorRgb, Target,
    Trials, VISIBLE_RANGE_NM,
};

use spectral_quadrature_spectra::{
    builtin_illuminant, emissions, surfaces_under_lights, EvalSet, Spectra, Stimulus,
};

const DATA_DIR: &str = spectral_quadrature_tools::DATA_DIR;
const RANGE: [f64; 2] = [380.0, 770.0];
/// The 1 nm reference's cells: 1 nm wide around 380, 381, …, 770 nm.
const SPAN: [f64; 2] = [379.5, 770.5];

fn samplers() -> [Sampler; 3] {
    [
        Sampler::Visible,
        Sampler::Hero { range_nm: SPAN },
        Sampler::Uniform { range_nm: SPAN },
    ]
}

fn reference() -> EvalSet {
    let d = spectral_quadrature_generator::derive(&spectral_quadrature_generator::Settings::new(
        DATA_DIR,
    ))
    .unwrap();
    d.observer.full_integration(RANGE, 1.0).unwrap()
}

/// A ColorChecker patch under the spiky F11, a test colour under A, and LED-B2 seen directly:
/// a line spectrum, a smooth one and a narrow-band emitter.
fn stimuli() -> Vec<Stimulus> {
    let dir = std::path::Path::new(DATA_DIR);
    let cc = Spectra::builtin(dir, "data/reflectance_colorchecker_ohta.csv")
        .and_then(|s| s.curves(RANGE))
        .unwrap();
    let tcs = Spectra::builtin(dir, "data/reflectance_cie_tcs.csv")
        .and_then(|s| s.curves(RANGE))
        .unwrap();
    let light = |n| builtin_illuminant(dir, n, RANGE).unwrap();
    let mut v = surfaces_under_lights(&cc[14..15], &[light("F11")]);
    v.extend(surfaces_under_lights(&tcs[8..9], &[light("A")]));
    v.extend(emissions(&[light("LED_B2")]));
    v
}

/// Composite Simpson's rule on [a, b] with `n` (even) intervals.
fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
    let h = (b - a) / n as f64;
    let inner: f64 = (1..n)
        .map(|i| f(a + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 })
        .sum();
    (f(a) + f(b) + inner) * h / 3.0
}

#[test]
fn each_density_integrates_to_one_on_its_range() {
    for s in samplers() {
        let [a, b] = s.range_nm();
        let total = simpson(|l| s.pdf(l), a, b, 47_000);
        // pbrt-v4 prints its constants to 8-9 significant digits; with them the sech² density
        // integrates to 1 - 7.4e-9 on 360-830 nm (tanh's closed form). Simpson's error at
        // 0.01 nm is far below that. 1e-7 leaves room for the constants' rounding only.
        assert!((total - 1.0).abs() < 1e-7, "{}: {total}", s.name());
        // Zero outside, NaN for NaN.
        assert_eq!(s.pdf(a - 0.01), 0.0);
        assert_eq!(s.pdf(b + 0.01), 0.0);
        assert!(s.pdf(f64::NAN).is_nan());
    }
    assert_eq!(Sampler::Visible.range_nm(), VISIBLE_RANGE_NM);
}

#[test]
fn each_density_is_the_one_its_wavelengths_are_drawn_with() {
    // pdf(λ(u)) · dλ/du = 1 wherever the inverse distribution is differentiable: otherwise
    // f(λ)/p(λ) would weight the wavelengths wrongly however many samples are taken.
    for s in samplers() {
        for k in 1..1000 {
            let u = k as f64 / 1000.0;
            let h = 1e-6;
            let slope = (s.wavelength(u + h) - s.wavelength(u - h)) / (2.0 * h);
            let product = s.pdf(s.wavelength(u)) * slope;
            // pbrt's constants agree with each other to about 1e-8 (measured 0.8-1.0e-8); the
            // central difference adds h² times the third derivative, below 1e-9 up to u = 0.999.
            assert!(
                (product - 1.0).abs() < 1e-7,
                "{} at u = {u}: {product}",
                s.name()
            );
        }
        let [a, b] = s.range_nm();
        // The ends of the range: pbrt's map gives 360.0000027 and 830.0000076 nm.
        assert!((s.wavelength(0.0) - a).abs() < 1e-5);
        assert!((s.wavelength(1.0) - b).abs() < 1e-5);
    }
}

#[test]
fn the_cells_integrate_to_the_reference_sum() {
    let reference = reference();
    for s in stimuli() {
        let cells = Cells::weighted(&reference, |l| s.radiance(l)).unwrap();
        let exact = reference.xyz(|l| s.radiance(l));
        let sum = cells.integral();
        for c in 0..3 {
            // The same products summed in the same order, divided and multiplied by a 1 nm
            // step: equal to the last few bits.
            assert!(
                (sum[c] - exact[c]).abs() <= 1e-12 * exact[c].abs(),
                "{}: {sum:?} vs {exact:?}",
                s.name
            );
        }
        assert_eq!(cells.span_nm(), SPAN);
        // Each cell holds its grid value over its whole width, and nothing lies outside.
        assert_eq!(cells.at(500.0), cells.at(500.49));
        assert_eq!(cells.at(500.0), cells.at(499.5));
        assert_ne!(cells.at(500.0), cells.at(500.5));
        assert_eq!(cells.at(379.49), [0.0; 3]);
        assert_eq!(cells.at(770.5), [0.0; 3]);
        assert_eq!(cells.at(f64::NAN), [0.0; 3]);
    }
    let uneven = EvalSet {
        wavelengths_nm: vec![380.0, 381.0, 383.0],
        xyz_weights: [vec![1.0; 3], vec![1.0; 3], vec![1.0; 3]],
        ..reference
    };
    assert!(Cells::weighted(&uneven, |_| 1.0).is_err());
}

#[test]
fn every_sampler_is_unbiased() {
    let reference = reference();
    const SAMPLES: usize = 400_000;
    for (k, stimulus) in stimuli().iter().enumerate() {
        let cells = Cells::weighted(&reference, |l| stimulus.radiance(l)).unwrap();
        let exact = cells.integral();
        for (j, s) in samplers().into_iter().enumerate() {
            assert!(s.covers(&cells));
            for n in [1, 4, 8] {
                let mut rng = pixel_rng(7, &[k as u64, j as u64, n as u64]);
                let mut scratch = vec![0.0; n];
                let mut sum = [0.0f64; 3];
                let mut sum_sq = [0.0f64; 3];
                for _ in 0..SAMPLES {
                    let e = s.estimate(&cells, &mut rng, &mut scratch);
                    for c in 0..3 {
                        sum[c] += e[c];
                        sum_sq[c] += e[c] * e[c];
                    }
                }
                for c in 0..3 {
                    let mean = sum[c] / SAMPLES as f64;
                    let var = (sum_sq[c] / SAMPLES as f64 - mean * mean) * SAMPLES as f64
                        / (SAMPLES - 1) as f64;
                    let se = (var / SAMPLES as f64).sqrt();
                    // k = 4 standard errors: the mean of 4·10^5 samples is normal to a good
                    // approximation, and an unbiased estimator leaves it beyond 4 SE with
                    // probability 6e-5 per check (0.5 % for all 81 here; the seeds are fixed,
                    // so the outcome is too).
                    assert!(
                        (mean - exact[c]).abs() <= 4.0 * se,
                        "{} ×{n} on {}, channel {c}: mean {mean} vs {} (SE {se})",
                        s.name(),
                        stimulus.name,
                        exact[c]
                    );
                    // And the test can see a bias of 2 %: the standard error is below a
                    // quarter of that (at most 0.47 %, one wavelength a sample on the red
                    // patch under F11), so a 2 % bias would sit 4 SE away or more.
                    assert!(
                        se < 0.005 * exact[c],
                        "{} ×{n} on {}: SE {se} too large to resolve 1 % of {}",
                        s.name(),
                        stimulus.name,
                        exact[c]
                    );
                }
            }
        }
    }
}

#[test]
fn a_sampler_that_misses_part_of_the_integrand_is_refused() {
    let reference = reference();
    let s = &stimuli()[0];
    let cells = Cells::weighted(&reference, |l| s.radiance(l)).unwrap();
    let narrow = Sampler::Hero {
        range_nm: [380.0, 770.0],
    };
    assert!(!narrow.covers(&cells));
    let target = Target {
        cells,
        white: [1.0; 3],
        lab: [50.0, 0.0, 0.0],
    };
    let config = Config {
        sampler: narrow,
        wavelengths: 4,
    };
    let e = run_trials(config, &[target], &[1, 4], 0..2, 1, 0, 1).unwrap_err();
    assert!(
        e.to_string().contains("misses part of the integrand"),
        "{e}"
    );
}

fn targets() -> Vec<Target> {
    let reference = reference();
    stimuli()
        .iter()
        .filter(|s| s.reflectance.is_some())
        .map(|s| {
            let white = reference.xyz(|l| s.light.at(l));
            Target {
                cells: Cells::weighted(&reference, |l| s.radiance(l)).unwrap(),
                white,
                lab: spectral_quadrature::lab_from_xyz(reference.xyz(|l| s.radiance(l)), white),
            }
        })
        .collect()
}

#[test]
fn trials_are_seeded_and_independent_of_the_threads() {
    let targets = targets();
    let config = Config {
        sampler: Sampler::Visible,
        wavelengths: 4,
    };
    let one = run_trials(config, &targets, &[1, 4, 16], 0..5, 42, 3, 1).unwrap();
    let two = run_trials(config, &targets, &[1, 4, 16], 0..5, 42, 3, 2).unwrap();
    assert_eq!(one, two);
    // Trials run in two rounds are the trials run at once.
    let mut rounds = run_trials(config, &targets, &[1, 4, 16], 0..2, 42, 3, 2).unwrap();
    rounds
        .append(run_trials(config, &targets, &[1, 4, 16], 2..5, 42, 3, 2).unwrap())
        .unwrap();
    assert_eq!(one, rounds);
    let other_seed = run_trials(config, &targets, &[1, 4, 16], 0..5, 43, 3, 2).unwrap();
    assert_ne!(one, other_seed);
    let other_stream = run_trials(config, &targets, &[1, 4, 16], 0..5, 42, 4, 2).unwrap();
    assert_ne!(one, other_stream);
    assert_eq!(one.len(), 5);
    assert!(one
        .errors
        .iter()
        .all(|t| t.len() == 3 && t[0].len() == targets.len()));
    assert!(run_trials(config, &targets, &[4, 1], 0..5, 42, 3, 1).is_err());
    assert!(run_trials(config, &targets, &[], 0..5, 42, 3, 1).is_err());
    let other_levels = run_trials(config, &targets, &[1, 4], 5..6, 42, 3, 1).unwrap();
    assert!(rounds.append(other_levels).is_err());
}

#[test]
fn the_error_falls_as_one_over_the_root_of_the_samples() {
    // Unbiased noise: the colour error falls as spp^-1/2 once it is small enough for ΔE to be
    // linear in the XYZ error, a factor 4 from 16 to 256 samples per pixel.
    let targets = targets();
    let config = Config {
        sampler: Sampler::Visible,
        wavelengths: 4,
    };
    let t = run_trials(config, &targets, &[1, 16, 256], 0..256, 1, 0, 2).unwrap();
    let s = t.summarize(&[0, 1]);
    assert_eq!(s.len(), 3);
    let ratio = s[1].mean_de00 / s[2].mean_de00;
    // 256 trials of 2 targets: each mean has a relative standard error of about 3.2 %
    // (measured), the ratio about 4.5 %: 3.4-4.6 is more than 3 of those either side of 4.
    assert!(
        (3.4..4.6).contains(&ratio),
        "16 → 256 spp: {} → {} (ratio {ratio})",
        s[1].mean_de00,
        s[2].mean_de00
    );
    for x in &s {
        // The measured 1.8-3.2 % with room for another seed.
        assert!(x.standard_error < 0.05 * x.mean_de00, "{x:?}");
        assert!(x.p90_pixel > x.mean_de00 * 0.5);
    }
}

#[test]
fn summaries_are_the_trials_means_spread_and_percentile() {
    // Two trials, one level, ten targets with ΔE00 k + trial (k = 1..=10).
    let errors = (0..2)
        .map(|t| vec![(1..=10).map(|k| ((k + t) as f64, 2.0 * k as f64)).collect()])
        .collect();
    let trials = Trials {
        spp: vec![1],
        errors,
    };
    let all: Vec<usize> = (0..10).collect();
    let s = trials.summarize(&all)[0];
    assert_eq!(s.mean_de00, 6.0); // trial means 5.5 and 6.5
    assert!((s.sd_trials - 0.5f64.sqrt()).abs() < 1e-12);
    assert!((s.standard_error - 0.5).abs() < 1e-12);
    // 20 pixels: 1..=10 and 2..=11; the 18th smallest is 10.
    assert_eq!(s.p90_pixel, 10.0);
    assert_eq!(s.mean_de76, 11.0);
    assert!(trials.summarize(&[]).is_empty());
    assert_eq!(trials.summarize(&[3])[0].mean_de00, 4.5);
    // The worst group: target 0 alone, means 1 and 2, SE 0.5 of a mean of 1.5.
    let worst = trials.worst_relative_error(&[all.clone(), vec![0]]);
    assert!((worst - 1.0 / 3.0).abs() < 1e-12, "{worst}");
}

#[test]
fn reach_interpolates_in_log_spp_and_log_error() {
    let curve = [(1, 8.0), (4, 4.0), (16, 2.0)];
    assert_eq!(reach(&curve, 9.0), Reach::AtFirst);
    assert_eq!(reach(&curve, 8.0), Reach::AtFirst);
    let near = |r: Reach, want: f64| match r {
        Reach::Between(x) | Reach::Beyond(x) => (x - want).abs() < 1e-9 * want,
        _ => false,
    };
    assert!(near(reach(&curve, 4.0), 4.0));
    assert!(near(reach(&curve, 8.0 / 2f64.sqrt()), 2.0));
    assert!(matches!(reach(&curve, 3.0), Reach::Between(_)));
    assert!(near(reach(&curve, 1.0), 64.0));
    assert!(matches!(reach(&curve, 1.0), Reach::Beyond(_)));
    assert_eq!(reach(&[(1, 8.0), (4, 8.0)], 1.0), Reach::Never);
    assert_eq!(reach(&[], 1.0), Reach::Never);
}

#[test]
fn the_f32_path_computes_what_the_f64_one_does() {
    let m = spectral_quadrature::tables::displays::SRGB.xyz_to_rgb();
    let d = spectral_quadrature_generator::derive(&spectral_quadrature_generator::Settings::new(
        DATA_DIR,
    ))
    .unwrap();
    // x̄ȳz̄ at every nm of the range: the full integration's weights at dλ = 1 nm.
    let full = d.observer.full_integration(RANGE, 1.0).unwrap();
    let xyz_bar: Vec<[f64; 3]> = (0..full.len())
        .map(|i| [0, 1, 2].map(|c| full.xyz_weights[c][i]))
        .collect();
    let sensor = SensorRgb::new(RANGE[0], &xyz_bar, m, 1.0);
    for s in samplers() {
        for k in 0..1000 {
            let u = (k as f64 + 0.5) / 1000.0;
            let l64 = s.wavelength(u);
            let l32 = s.wavelength_f32(u as f32);
            // f32 near 830 nm has a spacing of 6e-5 nm, and the map's slope reaches 4300 nm
            // per unit of u at its end, where u itself rounds by 3e-8: 2e-3 nm covers both.
            assert!(
                (f64::from(l32) - l64).abs() < 2e-3,
                "{}: {l32} vs {l64}",
                s.name()
            );
            let p64 = s.pdf(f64::from(l32));
            let p32 = s.pdf_f32(l32);
            // A few f32 roundings in cosh and the division: 1e-5 relative.
            assert!(
                (f64::from(p32) - p64).abs() <= 1e-5 * p64,
                "{l32}: {p32} vs {p64}"
            );
        }
        // One sample of 4 wavelengths added by the f32 sensor against the f64 sum.
        let mut rng = pixel_rng(3, &[]);
        for _ in 0..100 {
            let (l, p) = s.wavelengths_f32::<4, _>(&mut rng);
            let radiance = [0.3f32, 0.7, 1.1, 0.05];
            let mut px = [0.0f32; 3];
            sensor.add_sample(&l, &p, &radiance, &mut px);
            let mut want = [0.0f64; 3];
            for i in 0..4 {
                let k = (f64::from(l[i]) - RANGE[0] + 0.5).floor();
                if k < 0.0 || k as usize >= xyz_bar.len() {
                    continue;
                }
                let x = xyz_bar[k as usize];
                for (c, w) in want.iter_mut().enumerate() {
                    let rgb: f64 = (0..3).map(|j| f64::from(m[c][j]) * x[j]).sum();
                    *w += rgb * f64::from(radiance[i]) / f64::from(p[i]) / 4.0;
                }
            }
            let scale = want.iter().map(|v| v.abs()).fold(0.0, f64::max);
            for c in 0..3 {
                // f32 products and sums of four terms: 1e-5 of the largest channel.
                assert!(
                    (f64::from(px[c]) - want[c]).abs() <= 1e-5 * scale + 1e-30,
                    "{}: {px:?} vs {want:?}",
                    s.name()
                );
            }
        }
    }
}

/// Random numbers a test chooses: rand's `random::<f64>()` is the top 53 bits of `next_u64`
/// times 2⁻⁵³, so `m` gives `u = m · 2⁻⁵³`.
struct Chosen(std::vec::IntoIter<u64>);

impl rand::TryRng for Chosen {
    type Error = std::convert::Infallible;
    fn try_next_u32(&mut self) -> Result<u32, Self::Error> {
        Ok((self.try_next_u64()? >> 32) as u32)
    }
    fn try_next_u64(&mut self) -> Result<u64, Self::Error> {
        Ok(self.0.next().expect("a chosen number for every draw") << 11)
    }
    fn try_fill_bytes(&mut self, dst: &mut [u8]) -> Result<(), Self::Error> {
        for chunk in dst.chunks_mut(8) {
            let v = self.try_next_u64()?.to_le_bytes();
            chunk.copy_from_slice(&v[..chunk.len()]);
        }
        Ok(())
    }
}

/// The largest relative difference of two estimates' channels (both non-negative here).
fn relative_difference(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3)
        .map(|c| {
            let d = (a[c] - b[c]).abs();
            if d == 0.0 {
                0.0
            } else {
                d / b[c].abs()
            }
        })
        .fold(0.0, f64::max)
}

#[test]
fn the_prepared_estimator_gives_the_samplers_estimates() {
    let d = spectral_quadrature_generator::derive(&spectral_quadrature_generator::Settings::new(
        DATA_DIR,
    ))
    .unwrap();
    // The 1 nm grid of these tests and the report's 5 nm one.
    let grids = [1.0, 5.0].map(|step| d.observer.full_integration(RANGE, step).unwrap());
    // pbrt's pdf at λ(u) against 0.0039398042 (1 - x²): 0.0072 × 138.888889 = 1 + 8·10⁻¹⁰ inside
    // cosh², times 2 y tanh(y) ≤ 4.1 (y = atanh(x), |x| ≤ 0.971), 3.3·10⁻⁹; the f64 roundings
    // of atanh, cosh and the sums are below 10⁻¹³.
    const TOLERANCE: f64 = 4e-9;
    let mut worst = 0.0f64;
    for (g, grid) in grids.iter().enumerate() {
        for (k, stimulus) in stimuli().iter().enumerate() {
            let cells = Cells::weighted(grid, |l| stimulus.radiance(l)).unwrap();
            for (j, s) in samplers().into_iter().enumerate() {
                let prepared = Estimator::new(s, &cells);
                assert_eq!(prepared.sampler(), s);
                for n in [1, 3, 4, 8] {
                    let parts = [g as u64, k as u64, j as u64, n as u64];
                    let (mut a, mut b) = (pixel_rng(11, &parts), pixel_rng(11, &parts));
                    let mut scratch = vec![0.0; n];
                    for _ in 0..20_000 {
                        let e = prepared.estimate(&cells, &mut a, &mut scratch);
                        let want = s.estimate(&cells, &mut b, &mut scratch);
                        if s == Sampler::Visible {
                            let r = relative_difference(e, want);
                            worst = worst.max(r);
                            assert!(r <= TOLERANCE, "{} ×{n}: {e:?} vs {want:?}", s.name());
                        } else {
                            // Hero and uniform take the sampler's own path.
                            assert_eq!(e, want, "{} ×{n}", s.name());
                        }
                    }
                }
            }
            // Every cell boundary's u and 48 steps of 2⁻⁵³ either side, and both ends of [0, 1),
            // one wavelength a sample: a cell taken one boundary off would differ by a cell's
            // change, not 10⁻⁹.
            let [first, step] = [
                grid.wavelengths_nm[0],
                grid.wavelengths_nm[1] - grid.wavelengths_nm[0],
            ];
            for s in samplers() {
                let prepared = Estimator::new(s, &cells);
                let [lo, hi] = s.range_nm();
                let inverse = |nm: f64| match s {
                    // pbrt's map, λ = 538 - 138.888889 atanh(0.85691062 - 1.82750197 u).
                    Sampler::Visible => {
                        (0.85691062 - ((538.0 - nm) / 138.888889).tanh()) / 1.82750197
                    }
                    _ => (nm - lo) / (hi - lo),
                };
                const ONE: u64 = 1 << 53;
                let mut draws = vec![0, 1, ONE - 2, ONE - 1];
                for edge in 0..=grid.len() {
                    let u = inverse(first + (edge as f64 - 0.5) * step);
                    let m = (u.clamp(0.0, 1.0) * ONE as f64).round() as u64;
                    draws.extend(m.saturating_sub(48)..=(m + 48).min(ONE - 1));
                }
                let count = draws.len();
                let (mut a, mut b) = (Chosen(draws.clone().into_iter()), Chosen(draws.into_iter()));
                let mut scratch = [0.0; 1];
                for _ in 0..count {
                    let e = prepared.estimate(&cells, &mut a, &mut scratch);
                    let want = s.estimate(&cells, &mut b, &mut scratch);
                    if s == Sampler::Visible {
                        let r = relative_difference(e, want);
                        worst = worst.max(r);
                        assert!(r <= TOLERANCE, "{e:?} vs {want:?}");
                    } else {
                        assert_eq!(e, want, "{}", s.name());
                    }
                }
            }
        }
    }
    println!("largest relative difference from the sampler's estimate: {worst:.2e}");
    // Prepared for one grid and given cells on another, it takes the sampler's own path.
    let on_1nm = Cells::weighted(&grids[0], |_| 1.0).unwrap();
    let on_5nm = Cells::weighted(&grids[1], |_| 1.0).unwrap();
    let prepared = Estimator::new(Sampler::Visible, &on_1nm);
    let (mut a, mut b) = (pixel_rng(5, &[]), pixel_rng(5, &[]));
    let mut scratch = [0.0; 4];
    for _ in 0..1000 {
        assert_eq!(
            prepared.estimate(&on_5nm, &mut a, &mut scratch),
            Sampler::Visible.estimate(&on_5nm, &mut b, &mut scratch)
        );
    }
}
