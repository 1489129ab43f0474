//! The upsampling's build-time side: the box programme against its optimality conditions, the
//! training reader's tolerance, the scene's `[upsampling]` table, and the figures the docs state
//! for the radiance sets (what node values reach, whether a bounded exact linear map exists, the
//! round trip on a 17³ grid).

use crate::upsampling::{self as up, nearest_in_box};
use crate::{derive, Settings};
use spectral_quadrature_spectra::builtin_illuminant;

/// The data files the derivation reads (the runtime crate's `data/`).
const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../data");

/// A deterministic stream in [0, 1).
fn lcg(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s = s
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (s >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[test]
fn box_programme_meets_its_optimality_conditions() {
    let mut r = lcg(7);
    for case in 0..300 {
        let n = 3 + case % 8;
        let m = 1 + case % 3;
        let u: Vec<f64> = (0..n).map(|_| 2.0 * r() - 0.5).collect();
        let b: Vec<Vec<f64>> = (0..m)
            .map(|_| (0..n).map(|_| r() - 0.3).collect())
            .collect();
        // A right-hand side the box reaches (the image of a point in it) or, every third case,
        // one it may not.
        let x0: Vec<f64> = (0..n).map(|_| r()).collect();
        let d: Vec<f64> = b
            .iter()
            .map(|row| {
                let v: f64 = row.iter().zip(&x0).map(|(a, x)| a * x).sum();
                if case % 3 == 0 {
                    v + 3.0
                } else {
                    v
                }
            })
            .collect();
        let s = nearest_in_box(&u, &b, &d).unwrap();
        assert!(s.x.iter().all(|v| (0.0..=1.0).contains(v)));
        if case % 3 != 0 {
            // Reachable: the rows are met to within the penalty's ε times the multipliers.
            let worst = s.residual.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            assert!(worst < 1e-6, "case {case}: residual {worst}");
        }
        // No feasible direction lowers the objective: perturbing one variable, or two in
        // opposite directions, within the box never does better (by more than rounding).
        let f = |x: &[f64]| {
            let near: f64 = x.iter().zip(&u).map(|(a, b)| (a - b).powi(2)).sum::<f64>() / 2.0;
            let norm = b.iter().flatten().map(|v| v * v).sum::<f64>().sqrt();
            let rows: f64 = b
                .iter()
                .zip(&d)
                .map(|(row, di)| (row.iter().zip(x).map(|(a, v)| a * v).sum::<f64>() - di).powi(2))
                .sum::<f64>()
                / (norm * norm);
            near + rows / (2.0 * up::qp::EPSILON)
        };
        let best = f(&s.x);
        for i in 0..n {
            for step in [1e-4, -1e-4] {
                let mut x = s.x.clone();
                x[i] = (x[i] + step).clamp(0.0, 1.0);
                assert!(
                    f(&x) >= best - 1e-9 * best.abs().max(1.0),
                    "case {case} var {i}"
                );
            }
        }
    }
}

#[test]
fn training_reader_takes_rounding_noise_and_refuses_the_rest() {
    let ok = "wavelength_nm,a,b\n380,0.5,-6.9e-18\n770,-5.6e-17,1\n";
    let curves = up::parse_training("noise.csv", ok, [380.0, 770.0]).unwrap();
    assert_eq!(curves[1].values, [0.0, 1.0]);
    assert_eq!(curves[0].values, [0.5, 0.0]);
    // −1e-5 of the largest value is ten times the readers' tolerance (table::NEGATIVE_TOLERANCE).
    let bad = "wavelength_nm,a,b\n380,0.5,0.1\n770,-1e-5,1\n";
    let e = up::parse_training("bad.csv", bad, [380.0, 770.0]).unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("bad.csv") && text.contains('3') && text.contains("column 2"),
        "{text}"
    );
    // The shipped file's noise is read.
    let all = up::training(std::path::Path::new(DATA_DIR), [380.0, 770.0]).unwrap();
    assert_eq!(all.len(), 14 + 190);
}

#[test]
fn scene_upsampling_table() {
    let data = std::path::Path::new(DATA_DIR);
    let parse = |text: &str| crate::scene::Scene::parse("s.toml", text, data);
    let s = parse("sets = [\"KQ_4\"]\ndisplays = [\"SRGB\"]\n[upsampling]\ngrid = 5\n").unwrap();
    assert_eq!(s.upsampling.as_ref().map(|u| u.grid), Some(5));
    let e = parse("sets = [\"KQ_4\"]\n[upsampling]\ngrid = 1\n").unwrap_err();
    assert!(e.to_string().contains("s.toml:3"), "{e}");
    let e = parse("sets = [\"KQ_4\"]\n[upsampling]\nsize = 9\n").unwrap_err();
    assert!(e.to_string().contains("s.toml"), "{e}");
    let d = derive(&Settings::new(DATA_DIR)).unwrap();
    let s = parse("sets = [\"KQ_4\"]\ndisplays = [\"SRGB\"]\n[upsampling]\nsets = [\"KQ_6\"]\n")
        .unwrap();
    let e = s.resolve(&d).unwrap_err().to_string();
    assert!(
        e.contains("s.toml:4") && e.contains("KQ_6") && e.contains("KQ_4"),
        "{e}"
    );
    let s =
        parse("sets = [\"KQ_4\"]\ndisplays = [\"SRGB\"]\n[upsampling]\ndisplays = [\"REC2020\"]\n")
            .unwrap();
    let e = s.resolve(&d).unwrap_err().to_string();
    assert!(e.contains("s.toml:4") && e.contains("REC2020"), "{e}");
    // Without the table nothing is upsampled; with it, the scene's sets on its displays.
    let s = parse("sets = [\"KQ_4\"]\ndisplays = [\"SRGB\"]\n").unwrap();
    assert!(s.resolve(&d).unwrap().upsamplings.is_empty());
    let s = parse("sets = [\"KQ_4\", \"KQ_C_6\"]\ndisplays = [\"SRGB\", \"DISPLAY_P3\"]\n[upsampling]\ngrid = 3\n")
        .unwrap();
    let r = s.resolve(&d).unwrap();
    let names: Vec<(String, String, String)> = r
        .upsamplings
        .iter()
        .map(|u| (u.set.clone(), u.display.clone(), u.light.clone()))
        .collect();
    assert_eq!(
        names,
        [
            ("KQ_4".into(), "SRGB".into(), "D65".into()),
            ("KQ_4".into(), "DISPLAY_P3".into(), "D65".into()),
            ("KQ_C_6".into(), "SRGB".into(), "C".into()),
            ("KQ_C_6".into(), "DISPLAY_P3".into(), "C".into()),
        ]
    );
}

/// `[upsampling]` may name a light group: its map takes RGB under the group's first light,
/// round-trips through that light's member, gives 1 at every node for white and a flat spectrum
/// for greys, and is baked by default with the scene's sets. A name that is neither a set nor a
/// group is an error that lists both.
#[test]
fn a_light_group_is_upsampled_under_its_first_light() {
    let data = std::path::Path::new(DATA_DIR);
    let d = derive(&Settings::new(DATA_DIR)).unwrap();
    let parse = |text: &str| crate::scene::Scene::parse("s.toml", text, data).unwrap();
    let group = "[groups.ROOM]\nlights = [\"D65\", \"A\"]\nwavelengths = 8\n";
    let s = parse(&format!(
        "displays = [\"SRGB\"]\n{group}[upsampling]\nsets = [\"ROOM\"]\ngrid = 5\n"
    ));
    let r = s.resolve(&d).unwrap();
    let [u] = &r.upsamplings[..] else {
        panic!("one map: {:?}", r.upsamplings.len())
    };
    let (_, g) = &r.groups[0];
    assert_eq!(
        (u.set.as_str(), u.display.as_str(), u.light.as_str()),
        ("ROOM", "SRGB", "D65")
    );
    assert_eq!(
        u.group_lights.as_deref(),
        Some(&["D65".to_string(), "A".to_string()][..])
    );
    assert_eq!(u.wavelengths_nm, g.wavelengths_nm);
    // The encoding is the D65 member's folded weights, each row scaled to sum to 1.
    let (_, m) = d.display("SRGB").unwrap();
    let member = g.members[0].wavelength_set(&d, "ROOM", &g.wavelengths_nm);
    let folded = d.folded(&member, m);
    for (c, row) in folded.iter().enumerate() {
        let sum: f64 = row.iter().sum();
        for (w, f) in u.encoding[c].iter().zip(row) {
            assert!(
                (w - f / sum).abs() <= 1e-15,
                "channel {c}: {w} against {}",
                f / sum
            );
        }
    }
    // White is 1 at every node, greys flat at their value.
    let grid = u.grid;
    for i in 0..grid {
        let g = (i * grid + i) * grid + i;
        let v = (i as f64 / (grid - 1) as f64 * up::CODE_ONE).round() as u16;
        assert!(
            u.codes[g].iter().all(|&c| c == v),
            "grey {i}: {:?}",
            u.codes[g]
        );
    }
    assert!(u.codes.last().unwrap().iter().all(|&c| c == u16::MAX));
    // Every reachable grid point round-trips through the D65 member within the 16-bit codes'
    // rounding (half a code, 7.6e-6 in a node value, moves a colour by well under 0.01 ΔE00).
    assert!(u.reachable_share() > 0.9, "{}", u.reachable_share());
    assert!(u.max_round_trip_de00 <= 0.01, "{}", u.max_round_trip_de00);
    for idx in 0..grid * grid * grid {
        let p = up::grid_point(grid, idx);
        let decoded: Vec<f64> = u.codes[idx]
            .iter()
            .map(|&q| f64::from(q) / up::CODE_ONE)
            .collect();
        assert!(decoded.iter().all(|v| (0.0..=1.0).contains(v)));
        if u.reachable[idx] {
            let back = up::encode(&u.encoding, &decoded);
            let de = spectral_quadrature_math::delta_e2000(
                up::lab_of_rgb(m, p),
                up::lab_of_rgb(m, back),
            );
            assert!(de <= u.max_round_trip_de00, "{p:?}: {de}");
        }
    }
    // Without `sets`, every colour set and then every light group.
    let s = parse(&format!(
        "sets = [\"KQ_4\"]\ndisplays = [\"SRGB\"]\n{group}[upsampling]\ngrid = 3\n"
    ));
    let names: Vec<(String, String)> = s
        .resolve(&d)
        .unwrap()
        .upsamplings
        .iter()
        .map(|u| (u.set.clone(), u.light.clone()))
        .collect();
    assert_eq!(
        names,
        [("KQ_4".into(), "D65".into()), ("ROOM".into(), "D65".into())]
    );
    // A name that is neither: the sets and the groups it could have been.
    let s = parse(&format!(
        "sets = [\"KQ_C_4\"]\ndisplays = [\"SRGB\"]\n{group}[upsampling]\nsets = [\"ROOMS\"]\n"
    ));
    let e = s.resolve(&d).unwrap_err().to_string();
    assert!(
        e.contains("s.toml:7")
            && e.contains("names ROOMS")
            && e.contains("colour sets that sample wavelengths (KQ_C_4)")
            && e.contains("its light groups (ROOM)"),
        "{e}"
    );
    let s = parse("displays = [\"SRGB\"]\n[fixed.BINS]\nwavelengths_nm = [450, 550, 650]\nlight = \"C\"\n[upsampling]\nsets = [\"ROOM\"]\n");
    let e = s.resolve(&d).unwrap_err().to_string();
    assert!(
        e.contains("(BINS)") && e.contains("the scene has no [groups.*]"),
        "{e}"
    );
}

/// The least squares of a light group's map ([`up::GroupColours`]) against its definition: the
/// map's rows sum to 1, and the objective, written out pair by pair, does not decrease along any
/// direction that keeps them so (finite differences of a quadratic: exact up to rounding).
#[test]
fn a_light_groups_map_minimises_its_objective() {
    let mut r = lcg(11);
    let (n, lights, pairs) = (5, 2, 40);
    let encodings: Vec<[Vec<f64>; 3]> = (0..lights)
        .map(|_| [0, 1, 2].map(|_| (0..n).map(|_| r()).collect()))
        .collect();
    let colours: Vec<Vec<[f64; 3]>> = (0..lights)
        .map(|_| (0..pairs).map(|_| [r(), r(), r()]).collect())
        .collect();
    let rgb: Vec<[f64; 3]> = (0..pairs).map(|_| [r(), r(), r()]).collect();
    let nodes: Vec<Vec<f64>> = (0..pairs).map(|_| (0..n).map(|_| r()).collect()).collect();
    let weights: Vec<f64> = (0..pairs).map(|_| r()).collect();
    let global: Vec<[f64; 3]> = (0..n).map(|_| [r(), r(), r()]).collect();
    let prior = 0.3;
    let fit = up::GroupColours::new(&encodings, &colours).unwrap();
    let beta = up::GROUP_COLOUR_WEIGHT;
    for with_prior in [false, true] {
        let g = with_prior.then_some((&global[..], prior));
        let m = fit.map(&|k| weights[k], &rgb, &nodes, g).unwrap();
        // The objective, from its definition.
        let total: f64 = weights.iter().sum();
        let objective = |m: &[[f64; 3]]| {
            let apply = |x: [f64; 3]| -> Vec<f64> {
                m.iter()
                    .map(|row| row[0] * x[0] + row[1] * x[1] + row[2] * x[2])
                    .collect()
            };
            let mut f = 0.0;
            for k in 0..pairs {
                let v = apply(rgb[k]);
                let mut e: f64 = v.iter().zip(&nodes[k]).map(|(a, b)| (a - b).powi(2)).sum();
                for (w, c) in encodings.iter().zip(&colours) {
                    let back = up::encode(w, &v);
                    e += beta * (0..3).map(|ch| (back[ch] - c[k][ch]).powi(2)).sum::<f64>();
                }
                f += weights[k] * e;
            }
            if with_prior {
                // α tr(Dᵀ Q D), Q = I + β Σ_l W_lᵀ W_l.
                let alpha = prior * total;
                for col in 0..3 {
                    let dcol: Vec<f64> = (0..n).map(|i| m[i][col] - global[i][col]).collect();
                    let mut q = dcol.iter().map(|v| v * v).sum::<f64>();
                    for w in &encodings {
                        let back = up::encode(w, &dcol);
                        q += beta * back.iter().map(|v| v * v).sum::<f64>();
                    }
                    f += alpha * q;
                }
            }
            f
        };
        for row in &m {
            assert!((row.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{row:?}");
        }
        let base = objective(&m);
        let h = 1e-4;
        for i in 0..n {
            for (a, b) in [(0, 1), (1, 2), (0, 2)] {
                // Along e_i (u_a − u_b): the row still sums to 1.
                let moved = |t: f64| {
                    let mut p = m.clone();
                    p[i][a] += t;
                    p[i][b] -= t;
                    objective(&p)
                };
                let slope = (moved(h) - moved(-h)) / (2.0 * h);
                assert!(
                    slope.abs() <= 1e-7 * base.max(1.0),
                    "prior {with_prior}, row {i}, ({a}, {b}): slope {slope} at {base}"
                );
            }
        }
    }
}

/// What the docs state for the radiance sets at sRGB under D65: the share of a 9³ grid that
/// node values in [0, 1] reach, and on a 17³ table the round trip within 0.05 ΔE00 at every
/// reachable point of the 17³ grid. (Whether a bounded exact linear map exists is the report's
/// measure, tested with it in the tools.)
#[test]
fn radiance_sets_reach_and_round_trip() {
    let d = derive(&Settings::new(DATA_DIR)).unwrap();
    let data = std::path::Path::new(DATA_DIR);
    let range = d.settings.range_nm;
    let training = up::training(data, range).unwrap();
    let d65 = builtin_illuminant(data, "D65", range).unwrap();
    let (_, m) = d.display("SRGB").unwrap();
    // (set, reachable share of 9³ rounded to 0.1 %)
    for (name, share) in [("KQ_4", 96.2), ("KQ_6", 99.7), ("KQ_8", 100.0)] {
        let set = crate::catalog::resolve(&d, name).unwrap();
        let b9 = up::bake(&d, &set, ("SRGB", m), &d65, false, &training, 9).unwrap();
        assert_eq!(
            (1000.0 * b9.reachable_share()).round() / 10.0,
            share,
            "{name}"
        );
        let b17 = up::bake(&d, &set, ("SRGB", m), &d65, false, &training, 17).unwrap();
        let mut worst = 0.0f64;
        for idx in 0..17 * 17 * 17 {
            if !b17.reachable[idx] {
                continue;
            }
            let p = up::grid_point(17, idx);
            let decoded: Vec<f64> = b17.codes[idx]
                .iter()
                .map(|&q| f64::from(q) / up::CODE_ONE)
                .collect();
            let back = up::encode(&b17.encoding, &decoded);
            worst = worst.max(spectral_quadrature_math::delta_e2000(
                up::lab_of_rgb(m, p),
                up::lab_of_rgb(m, back),
            ));
        }
        assert!(worst <= 0.05, "{name}: {worst}");
        assert_eq!(worst, b17.max_round_trip_de00);
    }
}

// The upsampling cache (data/upsampling_codes.csv) cannot drift from the fit: every cached map is
// fitted afresh here and must give the very same codes.

const REGENERATE: &str = "regenerate with `cargo run --release -p spectral-quadrature-tools --bin tables -- --upsampling-cache > data/upsampling_codes.csv`";

/// The checked-in cache, read and written again (through the `csv` crate's writer, as
/// `tables --upsampling-cache` writes it), is the same bytes.
#[test]
fn the_cache_file_round_trips_through_the_writer() {
    let data = std::path::Path::new(DATA_DIR);
    let text = std::fs::read_to_string(data.join("upsampling_codes.csv")).unwrap();
    let cache = up::read_cache(data).expect("data/upsampling_codes.csv parses");
    assert!(
        up::write_cache(&cache) == text,
        "data/upsampling_codes.csv is not what the writer makes of it"
    );
}

#[test]
fn the_cache_equals_a_fresh_fit_of_every_default_map() {
    let d = derive(&Settings::new(DATA_DIR)).unwrap();
    let data = std::path::Path::new(DATA_DIR);
    let cache = up::read_cache(data).expect("data/upsampling_codes.csv parses");
    let scene = crate::scene::Scene::default_scene(data);
    let fitted = scene.resolve_fitting(&d).unwrap();
    let fresh = fitted.upsampling_cache(&d).unwrap();
    assert_eq!(
        cache.len(),
        fresh.len(),
        "one entry per upsampling of the default scene; {REGENERATE}"
    );
    for (f, b) in fresh.iter().zip(&fitted.upsamplings) {
        let what = format!("{} {}", f.set, f.display);
        let e = cache
            .iter()
            .find(|e| e.set == f.set && e.display == f.display)
            .unwrap_or_else(|| panic!("{what} is not in data/upsampling_codes.csv; {REGENERATE}"));
        assert_eq!(
            e.fingerprint, f.fingerprint,
            "{what}: stale fingerprint; {REGENERATE}"
        );
        // Bit for bit: the codes, which points are reachable, and the two figures.
        assert!(
            e.codes == f.codes,
            "{what}: the fit now gives other codes; {REGENERATE}"
        );
        assert_eq!(e.reachable, f.reachable, "{what}; {REGENERATE}");
        assert_eq!(
            e.lipschitz.to_bits(),
            f.lipschitz.to_bits(),
            "{what}; {REGENERATE}"
        );
        assert_eq!(
            e.max_round_trip_de00.to_bits(),
            f.max_round_trip_de00.to_bits(),
            "{what}; {REGENERATE}"
        );
        assert!(b.fit.is_some(), "{what}: resolve_fitting fits");
    }
    // And the build's way, from the cache: the same tables, without the fit.
    let cached = scene.resolve(&d).unwrap();
    assert_eq!(cached.upsamplings.len(), fitted.upsamplings.len());
    for (c, f) in cached.upsamplings.iter().zip(&fitted.upsamplings) {
        assert!(
            c.fit.is_none(),
            "{} {}: taken from the cache",
            c.set,
            c.display
        );
        assert_eq!(
            (&c.set, &c.display, &c.light),
            (&f.set, &f.display, &f.light)
        );
        assert_eq!(c.codes, f.codes);
        assert_eq!(c.reachable, f.reachable);
        assert_eq!(c.encoding, f.encoding);
        assert_eq!(c.wavelengths_nm, f.wavelengths_nm);
        assert_eq!(c.edge_cells(), f.edge_cells());
    }
}

#[test]
fn a_changed_input_is_fitted_instead_of_taken_from_the_cache() {
    // The fingerprint covers the grid, the display and the light: a scene that asks for a
    // cached set on another grid, or whose inputs differ, gets a fit.
    let d = derive(&Settings::new(DATA_DIR)).unwrap();
    let data = std::path::Path::new(DATA_DIR);
    let parse = |text: &str| crate::scene::Scene::parse("s.toml", text, data).unwrap();
    let same = parse("sets = [\"KQ_C_6\"]\ndisplays = [\"SRGB\"]\n[upsampling]\n");
    let r = same.resolve(&d).unwrap();
    assert!(
        r.upsamplings[0].fit.is_none(),
        "the default scene's map is cached"
    );
    let other_grid = parse("sets = [\"KQ_C_6\"]\ndisplays = [\"SRGB\"]\n[upsampling]\ngrid = 5\n");
    let r = other_grid.resolve(&d).unwrap();
    assert!(r.upsamplings[0].fit.is_some(), "another grid is fitted");
    let radiance = parse("sets = [\"KQ_6\"]\ndisplays = [\"SRGB\"]\n[upsampling]\n");
    assert!(radiance.resolve(&d).unwrap().upsamplings[0].fit.is_some());
}

#[test]
fn a_malformed_cache_names_file_and_line() {
    let header = "set,display,grid,fingerprint,lipschitz,max_round_trip_de00,reachable,codes";
    let fp = "0".repeat(64);
    let ok_reach = "f".repeat(2); // a 2³ grid: 8 points, two hex digits
    let codes = "0000".repeat(8); // N = 1
    let line = |grid: &str, fp: &str, lip: &str, reach: &str, codes: &str| {
        format!("# c\n{header}\nKQ_C_4,SRGB,{grid},{fp},{lip},0.001,{reach},{codes}\n")
    };
    let good = line("2", &fp, "1.5", &ok_reach, &codes);
    let parsed = up::parse_cache("data/upsampling_codes.csv", &good).unwrap();
    assert_eq!(parsed[0].codes, vec![vec![0u16]; 8]);
    assert_eq!(up::write_cache(&parsed).lines().last(), good.lines().last());
    let bad = [
        ("set,display\n".to_string(), 1, "expected the header"),
        (format!("{header}\nKQ_C_4,SRGB,2\n"), 2, "expected 8 fields"),
        (line("1", &fp, "1.5", &ok_reach, &codes), 3, "grid"),
        (line("2", "abc", "1.5", &ok_reach, &codes), 3, "fingerprint"),
        (line("2", &fp, "NaN", &ok_reach, &codes), 3, "lipschitz"),
        (
            line("2", &fp, "1.5", "f", &codes),
            3,
            "reachable has 1 hex digits",
        ),
        (
            line("2", &fp, "1.5", "fg", &codes),
            3,
            "reachable: character 2",
        ),
        // A 3³ grid: 27 points in 7 digits, the last digit's top bit past the grid.
        (
            line("3", &fp, "1.5", "fffffff", &"0000".repeat(27)),
            3,
            "past the grid",
        ),
        (
            line("2", &fp, "1.5", &ok_reach, "000"),
            3,
            "codes has 3 hex digits",
        ),
        (
            line(
                "2",
                &fp,
                "1.5",
                &ok_reach,
                &format!("{}000G", "0".repeat(28)),
            ),
            3,
            "codes: character 32",
        ),
        (
            format!("{good}{}", good.lines().last().unwrap()),
            4,
            "appears twice",
        ),
    ];
    for (text, line, message) in bad {
        let e = up::parse_cache("data/upsampling_codes.csv", &text).unwrap_err();
        let shown = e.to_string();
        assert!(
            shown.starts_with(&format!("data/upsampling_codes.csv:{line}: "))
                && shown.contains(message),
            "{shown}"
        );
    }
}

#[test]
fn a_corrupted_copy_of_the_cache_stops_the_build_with_its_file_and_line() {
    // A copy of the crate's data with one code of the shipped cache made a non-digit: the
    // generation fails naming the file and the line, instead of fitting or guessing.
    let dir = std::env::temp_dir().join(format!("sq-upsampling-cache-{}", std::process::id()));
    let data = dir.join("data");
    std::fs::create_dir_all(&data).unwrap();
    for entry in std::fs::read_dir(DATA_DIR).unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, data.join(path.file_name().unwrap())).unwrap();
    }
    let text = std::fs::read_to_string(data.join("upsampling_codes.csv")).unwrap();
    let (n, victim) = text
        .lines()
        .enumerate()
        .find(|(_, l)| l.starts_with("KQ_C_6,SRGB,"))
        .unwrap();
    let broken = text.replacen(victim, &format!("{}z", &victim[..victim.len() - 1]), 1);
    std::fs::write(data.join("upsampling_codes.csv"), broken).unwrap();
    let e = crate::generate(&dir, None).unwrap_err().to_string();
    std::fs::remove_dir_all(&dir).ok();
    assert!(
        e.contains(&format!("data/upsampling_codes.csv:{}:", n + 1))
            && e.contains("KQ_C_6 SRGB: codes: character")
            && e.contains("not a lower-case hex digit"),
        "{e}"
    );
}

#[test]
fn the_cache_file_round_trips() {
    let text = std::fs::read_to_string(std::path::Path::new(DATA_DIR).join("upsampling_codes.csv"))
        .unwrap();
    let entries = up::parse_cache("data/upsampling_codes.csv", &text).unwrap();
    assert_eq!(up::write_cache(&entries), text);
}
