//! The baked tables equal a fresh derivation: every f64 value rounded to f32 exactly as the code
//! generator does (`as f32`), so the comparisons are exact.

/// The data files the derivation reads (the runtime crate's `data/`).
const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data");

use spectral_quadrature::{tables, Channel, RuleStatus, WavelengthSet};

/// `TABLE_BYTES` and `ALL_TABLES` against the constants a `tables.rs` declares (shared with
/// `.ci/tables-check`, which runs it on every example scene).
mod table_bytes;
use spectral_quadrature_generator::{derive, Derivation, Settings};
use std::sync::OnceLock;

fn fresh() -> &'static Derivation {
    static D: OnceLock<Derivation> = OnceLock::new();
    D.get_or_init(|| derive(&Settings::new(DATA_DIR)).expect("default derivation"))
}

fn f32s(v: &[f64]) -> Vec<f32> {
    v.iter().map(|&x| x as f32).collect()
}

#[test]
fn header_constants() {
    let d = fresh();
    assert_eq!(tables::OBSERVER, d.settings.observer.name());
    assert_eq!(tables::SETTINGS, d.settings.to_string());
    assert_eq!(tables::RANGE_NM, [380.0, 770.0]);
    assert_eq!(tables::STEP_NM, 5.0);
    assert_eq!(tables::MAX_ORDER, d.settings.max_order);
    // The observer, then what the default scene's shared sets (KQ_C_*, KQ_F11_6) were made from,
    // then what the upsamplings add (the other training file, the upsampling cache, and D65, the
    // reference light of Table 2's rows, sets for radiances), then what the light group adds (the
    // ColorChecker, its third training file, and its lights A and LED_B2).
    let labels: Vec<&str> = tables::INPUTS.iter().map(|(l, _)| *l).collect();
    assert_eq!(
        labels,
        [
            d.observer.file.as_str(),
            "data/reflectance_cie_tcs.csv",
            "data/illuminant_C.csv",
            "data/shared_nodes.csv",
            "data/illuminant_F11.csv",
            "data/reflectance_rawtoaces_190.csv",
            "data/upsampling_codes.csv",
            "data/illuminant_D65.csv",
            "data/reflectance_colorchecker_ohta.csv",
            "data/illuminant_A.csv",
            "data/illuminant_LED_B2.csv",
        ]
    );
    assert_eq!(tables::INPUTS[0].1, d.observer.sha256);
}

#[test]
fn matrices_eigenvalues_grid_and_sensitivities() {
    let d = fresh();
    for r in 0..3 {
        assert_eq!(
            tables::XYZ_TO_AC1C2[r].to_vec(),
            f32s(&d.opponent.xyz_to_ac1c2[r])
        );
        assert_eq!(
            tables::AC1C2_TO_XYZ[r].to_vec(),
            f32s(&d.opponent.ac1c2_to_xyz[r])
        );
    }
    assert_eq!(tables::EIGENVALUES.to_vec(), f32s(&d.opponent.eigenvalues));
    assert_eq!(tables::GRID_NM.to_vec(), f32s(&d.grid_nm));
    assert_eq!(tables::SENSITIVITIES.len(), d.sensitivities.len());
    for (baked, s) in tables::SENSITIVITIES.iter().zip(&d.sensitivities) {
        assert_eq!(baked.to_vec(), f32s(s));
    }
}

#[test]
fn every_rule_and_its_status() {
    let d = fresh();
    let mut defined = 0;
    for (c, channel) in Channel::ALL.into_iter().enumerate() {
        assert_eq!(tables::RULES[c].len(), d.rules[c].len());
        for (baked, rule) in tables::RULES[c].iter().zip(&d.rules[c]) {
            assert_eq!(baked.channel(), channel);
            assert_eq!(usize::from(baked.order()), rule.order);
            assert_eq!(baked.status().name(), rule.status.as_str());
            if baked.status() == RuleStatus::Defined {
                defined += 1;
                assert_eq!(baked.wavelengths_nm(), f32s(&rule.nodes_nm).as_slice());
                assert_eq!(baked.weights(), f32s(&rule.weights).as_slice());
            } else {
                assert!(baked.wavelengths_nm().is_empty() && baked.weights().is_empty());
            }
        }
    }
    assert!(defined >= 30, "{defined} defined rules");
}

fn assert_set<const N: usize>(
    baked: &WavelengthSet<N>,
    fresh: &spectral_quadrature_generator::WavelengthSet,
) {
    assert_eq!(baked.wavelengths_nm().to_vec(), f32s(&fresh.wavelengths_nm));
    for c in 0..3 {
        assert_eq!(baked.weights()[c].to_vec(), f32s(&fresh.weights[c]));
    }
}

#[test]
fn table2_sets_and_rule_sets() {
    let d = fresh();
    assert_set(&tables::TABLE2_ROW1, &d.table2[0]);
    assert_set(&tables::TABLE2_ROW2, &d.table2[1]);
    // A few of the per-rule sets: the rule's own row, the other rows zero.
    for (set_nm, set_w, c, order) in [
        (
            tables::rules::A_3.wavelengths_nm().to_vec(),
            tables::rules::A_3.weights().map(|r| r.to_vec()),
            0,
            3,
        ),
        (
            tables::rules::C1_2.wavelengths_nm().to_vec(),
            tables::rules::C1_2.weights().map(|r| r.to_vec()),
            1,
            2,
        ),
        (
            tables::rules::C2_1.wavelengths_nm().to_vec(),
            tables::rules::C2_1.weights().map(|r| r.to_vec()),
            2,
            1,
        ),
        (
            tables::rules::A_16.wavelengths_nm().to_vec(),
            tables::rules::A_16.weights().map(|r| r.to_vec()),
            0,
            16,
        ),
    ] {
        let rule = &d.rules[c][order - 1];
        assert_eq!(set_nm, f32s(&rule.nodes_nm));
        for (k, row) in set_w.iter().enumerate() {
            if k == c {
                assert_eq!(*row, f32s(&rule.weights));
            } else {
                assert!(row.iter().all(|&w| w == 0.0));
            }
        }
    }
}

#[test]
fn generated_source_is_what_the_generator_writes_now() {
    // The whole file, byte for byte: nothing in it comes from anywhere but the derivation.
    let generated = spectral_quadrature_generator::generate(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")),
        None,
    )
    .unwrap()
    .tables_rs;
    let baked = include_str!(concat!(env!("OUT_DIR"), "/tables.rs"));
    assert_eq!(generated, baked);
    assert!(!baked.contains("NaN") && !baked.contains("inf"));
}

#[test]
fn every_input_checksum_is_that_of_the_file_in_data() {
    // The observer first, then the shared sets' training reflectances, lights and node cache.
    assert_eq!(tables::INPUTS[0].0, "data/cmf_cie1931_2deg_1nm.csv");
    assert!(tables::INPUTS.len() > 1);
    for (label, sha) in tables::INPUTS {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(label);
        let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{label}: {e}"));
        // Computed here with `sha2`, not by the generator's helper that wrote the header.
        let hex: String = {
            use sha2::Digest;
            sha2::Sha256::digest(&bytes)
                .iter()
                .map(|b| format!("{b:02x}"))
                .collect()
        };
        assert_eq!(hex, *sha, "{label}");
    }
}

#[test]
fn the_header_const_names_every_input_and_the_settings() {
    for (label, sha) in tables::INPUTS {
        assert!(
            tables::HEADER.contains(&format!("{label} sha256={sha}")),
            "{label} missing from HEADER"
        );
    }
    assert!(tables::HEADER.contains(tables::SETTINGS));
    assert!(tables::HEADER.contains(&format!("Scene: {}", tables::SCENE)));
}

#[test]
fn sets_say_what_their_samples_are_and_folded_sets_carry_their_display() {
    use spectral_quadrature::Samples;
    assert_eq!(tables::TABLE2_ROW2.samples(), Samples::Radiance);
    assert_eq!(
        tables::KQ_C_6.samples(),
        Samples::Reflectance { light: "C" }
    );
    assert_eq!(tables::KQ_F11_6.samples().light(), Some("F11"));
    assert_eq!(tables::rules::A_3.samples(), Samples::Radiance);
    // Each folded set: the samples of its set, and the display its name gives.
    let folded = [
        (
            tables::folded::TABLE2_ROW2_SRGB.samples(),
            tables::folded::TABLE2_ROW2_SRGB.display(),
            tables::displays::SRGB,
        ),
        (
            tables::folded::TABLE2_ROW1_REC2020.samples(),
            tables::folded::TABLE2_ROW1_REC2020.display(),
            tables::displays::REC2020,
        ),
        (
            tables::folded::KQ_C_6_DISPLAY_P3.samples(),
            tables::folded::KQ_C_6_DISPLAY_P3.display(),
            tables::displays::DISPLAY_P3,
        ),
        (
            tables::folded::KQ_F11_6_MEYER_1987.samples(),
            tables::folded::KQ_F11_6_MEYER_1987.display(),
            tables::displays::MEYER_1987,
        ),
    ];
    assert_eq!(folded[0].0, Samples::Radiance);
    assert_eq!(folded[2].0, Samples::Reflectance { light: "C" });
    assert_eq!(folded[3].0, Samples::Reflectance { light: "F11" });
    for (_, display, expected) in folded {
        assert_eq!(display, expected);
    }
    // The generated source pairs every folded set with the display of its own name: the last
    // argument of its `FoldedSet::new`.
    let baked = include_str!(concat!(env!("OUT_DIR"), "/tables.rs"));
    let mut n = 0;
    for block in baked.split("pub const ").skip(1) {
        if let Some((name, rest)) = block.split_once(": FoldedSet<") {
            let display = rest
                .split("super::displays::")
                .nth(1)
                .and_then(|r| {
                    r.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                        .next()
                })
                .expect("a display argument");
            assert!(
                name.ends_with(&format!("_{display}")),
                "{name} has {display}"
            );
            n += 1;
        }
    }
    assert_eq!(
        n,
        6 * 4,
        "Table 2's two sets and four shared sets, for four displays"
    );
}

/// The baked tables, as the build script wrote them.
const TABLES_RS: &str = concat!(env!("OUT_DIR"), "/tables.rs");

#[test]
fn baked_tables_fit_in_100_columns() {
    // rustfmt's max_width: the generator lays the tables out as rustfmt would.
    let baked = include_str!(concat!(env!("OUT_DIR"), "/tables.rs"));
    for (i, line) in baked.lines().enumerate() {
        let columns = line.chars().count();
        assert!(columns <= 100, "tables.rs:{}: {columns} columns", i + 1);
    }
}

#[test]
fn rustfmt_accepts_the_baked_tables() {
    use std::io::Write as _;
    use std::process::Command;
    // Where rustfmt is not installed (a toolchain without the component), only the widths
    // above are checked; say so in the test output (written past the harness's capture).
    let missing = |why: &str| {
        // Where `.ci/run` found rustfmt (SPECTRAL_QUADRATURE_REQUIRE names it), it must run.
        let required = std::env::var("SPECTRAL_QUADRATURE_REQUIRE")
            .is_ok_and(|list| list.split(',').any(|c| c.trim() == "rustfmt"));
        assert!(
            !required,
            "rustfmt is not available ({why}), but SPECTRAL_QUADRATURE_REQUIRE says this machine has it"
        );
        let note = format!(
            "note: rustfmt is not available ({why}): tables.rs checked for 100 columns only\n"
        );
        std::io::stderr().write_all(note.as_bytes()).ok();
    };
    match Command::new("rustfmt").arg("--version").output() {
        Err(e) => return missing(&e.to_string()),
        Ok(out) if !out.status.success() => {
            return missing(String::from_utf8_lossy(&out.stderr).trim());
        }
        Ok(_) => {}
    }
    // An empty configuration: rustfmt's defaults, whatever rustfmt.toml a parent directory or
    // the user's configuration holds.
    let dir = std::env::temp_dir().join(format!("sq-rustfmt-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let config = dir.join("rustfmt.toml");
    std::fs::write(&config, "").unwrap();
    let out = Command::new("rustfmt")
        .args(["--check", "--edition", "2021", "--config-path"])
        .arg(&config)
        .arg(TABLES_RS)
        .output()
        .expect("rustfmt runs");
    std::fs::remove_dir_all(&dir).ok();
    assert!(
        out.status.success(),
        "rustfmt --check --edition 2021 {TABLES_RS} wants changes:\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn table_bytes_is_the_size_of_every_baked_constant() {
    let baked = include_str!(concat!(env!("OUT_DIR"), "/tables.rs"));
    let (constants, in_slices) =
        table_bytes::check(tables::ALL_TABLES, tables::TABLE_BYTES, baked).unwrap();
    // The default scene bakes every kind of constant: the check above must have seen the
    // slices of the rules and of the upsampling maps, and the integer, group, light and
    // upsampling modules (which the old hand count left out).
    assert!(in_slices > 0);
    for module in [
        "integer::",
        "groups::",
        "lights::",
        "upsampling::",
        "displays::",
    ] {
        assert!(
            tables::ALL_TABLES
                .iter()
                .any(|(path, _, _)| path.starts_with(module)),
            "{module}"
        );
    }
    let declared = table_bytes::declared(baked);
    assert_eq!(constants, declared.len());
    // The text the check reads, against what the lists say: every folded set and upsampling.
    for name in tables::folded::NAMES {
        assert!(declared.contains(&format!("folded::{name}")), "{name}");
    }
    for name in tables::upsampling::NAMES {
        assert!(declared.contains(&format!("upsampling::{name}")), "{name}");
    }
}

#[test]
fn table_bytes_check_refuses_a_list_that_leaves_a_constant_out_or_miscounts() {
    let baked = include_str!(concat!(env!("OUT_DIR"), "/tables.rs"));
    let all = tables::ALL_TABLES;
    // One constant left out (and its bytes with it): named.
    let short: Vec<table_bytes::Entry> = all
        .iter()
        .copied()
        .filter(|(path, _, _)| *path != "integer::KQ_C_4_SRGB")
        .collect();
    let bytes = short.iter().map(|(_, b, _)| b).sum();
    let err = table_bytes::check(&short, bytes, baked).unwrap_err();
    assert!(err.contains("integer::KQ_C_4_SRGB"), "{err}");
    // An upsampling counted without its edge cells, as a count by hand can drift: named.
    let mut drifted: Vec<table_bytes::Entry> = all.to_vec();
    let k = drifted
        .iter()
        .position(|(path, _, _)| *path == "upsampling::KQ_C_4_SRGB")
        .unwrap();
    drifted[k].1 -= 4;
    let err = table_bytes::check(&drifted, tables::TABLE_BYTES - 4, baked).unwrap_err();
    assert!(err.contains("upsampling::KQ_C_4_SRGB"), "{err}");
    // A total that is not the sum.
    let err = table_bytes::check(all, tables::TABLE_BYTES + 1, baked).unwrap_err();
    assert!(err.contains("TABLE_BYTES"), "{err}");
}

/// Every baked constant is what its checked constructor gives for its parts, read back through
/// the accessors: the tables call the same constructors, so nothing baked bypasses a check.
#[test]
fn every_baked_constant_is_its_constructors_value() {
    use spectral_quadrature::{
        Display, FoldedSet, GaussRule, LightGroupSet, Upsampling, WavelengthSet,
    };
    for d in tables::displays::ALL {
        let made = Display::from_matrices(
            d.name(),
            d.primaries_xy(),
            d.white_xy(),
            d.rgb_to_xyz(),
            d.xyz_to_rgb(),
            d.a_from_rgb(),
            d.transfer(),
        );
        assert_eq!(made, Ok(d), "{}", d.name());
    }
    for rule in tables::RULES.iter().flatten() {
        let made = GaussRule::new(
            rule.channel(),
            rule.order(),
            rule.status(),
            rule.wavelengths_nm(),
            rule.weights(),
        );
        assert_eq!(made, Ok(*rule));
    }
    macro_rules! sets {
        ($($set:ident,)*) => {
            $(
                let s = tables::sets::$set;
                assert_eq!(WavelengthSet::new(s.wavelengths_nm(), s.weights(), s.samples()), Ok(s));
            )*
        };
    }
    tables::sets::all!(sets);
    macro_rules! folded {
        ($($set:ident,)*) => {
            $(
                let f = tables::folded::$set;
                let made = FoldedSet::new(f.wavelengths_nm(), f.weights(), f.samples(), f.display());
                assert_eq!(made, Ok(f));
            )*
        };
    }
    tables::folded::all!(folded);
    macro_rules! groups {
        ($($group:ident,)*) => {
            $(
                let g = tables::groups::$group;
                let made = LightGroupSet::new(g.wavelengths_nm(), g.weights(), g.lights(), g.display());
                assert_eq!(made, Ok(g));
            )*
        };
    }
    tables::groups::all!(groups);
    macro_rules! upsampling {
        ($($map:ident,)*) => {
            $(
                let u = tables::upsampling::$map;
                let made = Upsampling::new(u.set(), u.grid(), u.table(), u.round_trip())
                    .and_then(|m| {
                        let figure = |f: Option<f32>| f.expect("a baked map's measured figure");
                        m.with_measured(
                            figure(u.lipschitz()),
                            figure(u.max_round_trip_delta_e00()),
                            figure(u.reachable_share()),
                        )
                    });
                assert_eq!(made, Ok(u));
            )*
        };
    }
    tables::upsampling::all!(upsampling);
}

/// `Display::from_matrices` refuses what a baked display cannot be: a singular matrix, a pair
/// that are not each other's inverse, a value that is not finite, a chromaticity or γ
/// `Display::new` refuses, each with `Display::new`'s error.
#[test]
fn a_display_from_matrices_refuses_singular_and_mismatched_matrices() {
    use spectral_quadrature::{Display, DisplayError, Error, Point, TransferFunction};
    let s = tables::displays::SRGB;
    let make = |rgb_to_xyz: [[f32; 3]; 3], xyz_to_rgb: [[f32; 3]; 3]| {
        Display::from_matrices(
            "test",
            s.primaries_xy(),
            s.white_xy(),
            rgb_to_xyz,
            xyz_to_rgb,
            s.a_from_rgb(),
            s.transfer(),
        )
    };
    let singular = |r: Result<Display, Error>| {
        matches!(
            r,
            Err(Error::Display(DisplayError::Collinear { condition })) if condition == f32::INFINITY
        )
    };
    assert!(make(s.rgb_to_xyz(), s.xyz_to_rgb()).is_ok());
    // Singular: a row of zeros, and two equal rows.
    let mut zero = s.rgb_to_xyz();
    zero[1] = [0.0; 3];
    assert!(singular(make(zero, s.xyz_to_rgb())));
    let mut equal = s.rgb_to_xyz();
    equal[2] = equal[0];
    assert!(singular(make(equal, s.xyz_to_rgb())));
    // Another display's inverse; an inverse one entry of which is 1 % off.
    assert!(singular(make(
        s.rgb_to_xyz(),
        tables::displays::DISPLAY_P3.xyz_to_rgb()
    )));
    let mut off = s.xyz_to_rgb();
    off[1][1] *= 1.01;
    assert!(singular(make(s.rgb_to_xyz(), off)));
    // Not finite.
    let mut nan = s.xyz_to_rgb();
    nan[2][0] = f32::NAN;
    assert!(singular(make(s.rgb_to_xyz(), nan)));
    let mut huge = s.rgb_to_xyz();
    huge[0] = [f32::MAX; 3];
    assert!(singular(make(huge, s.xyz_to_rgb())));
    // A chromaticity and a γ, named as `Display::new` names them.
    let mut primaries = s.primaries_xy();
    primaries[1] = [0.7, 0.4];
    let refused = Display::from_matrices(
        "test",
        primaries,
        s.white_xy(),
        s.rgb_to_xyz(),
        s.xyz_to_rgb(),
        s.a_from_rgb(),
        s.transfer(),
    );
    assert!(matches!(
        refused,
        Err(Error::Display(DisplayError::Chromaticity {
            point: Point::Green,
            ..
        }))
    ));
    let gamma = s.with_transfer(TransferFunction::Gamma(0.0));
    let refused = Display::from_matrices(
        "test",
        gamma.primaries_xy(),
        gamma.white_xy(),
        gamma.rgb_to_xyz(),
        gamma.xyz_to_rgb(),
        gamma.a_from_rgb(),
        gamma.transfer(),
    );
    assert!(matches!(
        refused,
        Err(Error::Display(DisplayError::Gamma { .. }))
    ));
}

/// `Upsampling::new` refuses a round trip that measures colour in another display's space, and
/// `with_measured` figures that are not finite and non-negative, or a share above 1.
#[test]
fn an_upsampling_refuses_another_displays_round_trip_and_bad_figures() {
    use spectral_quadrature::{Error, RoundTrip, Upsampling};
    let u = tables::upsampling::KQ_C_4_SRGB;
    let rt = u.round_trip().unwrap();
    let other = RoundTrip::new(
        rt.weights(),
        tables::displays::DISPLAY_P3.rgb_to_xyz(),
        rt.edge_cells(),
    );
    assert_eq!(
        Upsampling::new(u.set(), u.grid(), u.table(), Some(other)),
        Err(Error::UpsamplingRoundTrip)
    );
    let made = Upsampling::new(u.set(), u.grid(), u.table(), Some(rt)).unwrap();
    for figures in [
        [f32::NAN, 0.1, 0.9],
        [1.0, -0.1, 0.9],
        [1.0, 0.1, 1.5],
        [f32::INFINITY, 0.1, 0.9],
    ] {
        let [l, d, s] = figures;
        assert_eq!(
            made.with_measured(l, d, s),
            Err(Error::UpsamplingFigures),
            "{figures:?}"
        );
    }
    assert_eq!(
        made.with_measured(0.0, 0.0, 1.0).unwrap().reachable_share(),
        Some(1.0)
    );
}
