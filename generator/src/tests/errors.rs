//! Errors are types: each mistake has its variant, callers match on it, and the message the
//! build script and the tools print names the file and the line where a file is involved.
//! Displays have one description, used by the derivation, scenes, code generation and shaders.

use spectral_quadrature_spectra::Curve;
use std::path::Path;
use std::sync::OnceLock;

use crate::display::{display_matrices, standard_displays, DisplaySpec, Transfer, MAX_CONDITION};
use crate::plan::Metric;
use crate::scene::Scene;
use crate::shader::Language;
use crate::{derive, Derivation, DisplayError, Error, SetNameProblem, Settings};

const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../data");

fn default_derivation() -> &'static Derivation {
    static D: OnceLock<Derivation> = OnceLock::new();
    D.get_or_init(|| derive(&Settings::new(DATA_DIR)).unwrap())
}

fn parse(text: &str) -> Result<Scene, Error> {
    Scene::parse("scene.toml", text, Path::new(DATA_DIR))
}

/// The error a scene gives when parsed and resolved.
fn scene_error(text: &str) -> Error {
    match parse(text) {
        Err(e) => e,
        Ok(scene) => scene.resolve(default_derivation()).unwrap_err(),
    }
}

/// The typed error inside an [`Error::At`], with its line.
fn inner(e: &Error) -> (u64, &Error) {
    match e {
        Error::At {
            file, line, error, ..
        } => {
            assert_eq!(file, "scene.toml", "{e}");
            (*line, error)
        }
        other => panic!("expected Error::At, got {other:?}"),
    }
}

#[test]
fn an_unknown_display_is_typed_at_its_line() {
    let e = scene_error("sets = [\"TABLE2_ROW2\"]\ndisplays = [\"SRGB\", \"CRT\"]\n");
    let (line, error) = inner(&e);
    assert_eq!(line, 2);
    let Error::UnknownDisplay { name, valid } = error else {
        panic!("expected UnknownDisplay, got {error:?}");
    };
    assert_eq!(name, "CRT");
    let standard: Vec<String> = standard_displays().into_iter().map(|d| d.name).collect();
    assert_eq!(valid, &standard);
    assert_eq!(
        e.to_string(),
        format!(
            "scene.toml:2: unknown display \"CRT\"; valid: {}",
            standard.join(", ")
        )
    );
    assert_eq!(e.location(), Some(("scene.toml", 2)));
}

#[test]
fn transfer_and_metric_mistakes_are_typed_at_their_lines() {
    let e = scene_error(
        "sets = [\"TABLE2_ROW2\"]\ndisplays = [\"SRGB\"]\n[transfer]\nSRGB = \"gamma -1\"\n",
    );
    let (line, error) = inner(&e);
    assert_eq!((line, error), (4, &Error::Transfer("gamma -1".into())));
    assert!(e.to_string().contains("\"gamma <γ>\" with γ > 0"), "{e}");

    let e = scene_error(
        "[plan]\nmax_delta_e00 = 1.0\nmetric = \"median\"\nreflectances = \"a.csv\"\nilluminants = \"b.csv\"\n",
    );
    let (line, error) = inner(&e);
    assert_eq!((line, error), (3, &Error::Metric("median".into())));
    assert_eq!(
        "median".parse::<Metric>(),
        Err(Error::Metric("median".into()))
    );
}

#[test]
fn a_scene_metric_is_parsed_once_into_the_enum() {
    for (text, metric) in [
        ("", Metric::Mean),
        ("metric = \"mean\"\n", Metric::Mean),
        ("metric = \"max\"\n", Metric::Max),
        ("metric = \"MAX\"\n", Metric::Max),
    ] {
        let scene = parse(&format!(
            "[plan]\nmax_delta_e00 = 1.0\n{text}reflectances = \"a.csv\"\nilluminants = \"b.csv\"\n"
        ))
        .unwrap();
        assert_eq!(scene.plan.unwrap().metric, metric, "{text:?}");
    }
}

#[test]
fn set_name_mistakes_are_typed_and_the_scene_adds_the_choices() {
    let d = default_derivation();
    type Expected = fn(&SetNameProblem) -> bool;
    let cases: [(&str, Expected); 5] = [
        ("TABLE9_ROW1", |p| *p == SetNameProblem::UnknownForm),
        ("AC1C2_3_2", |p| {
            matches!(p, SetNameProblem::Malformed { .. })
        }),
        ("UNIFORM_x", |p| {
            *p == SetNameProblem::NotAnOrder("x".into())
        }),
        ("A_99", |p| {
            matches!(
                p,
                SetNameProblem::OrderNotDerived {
                    channel: 0,
                    order: 99,
                    ..
                }
            )
        }),
        ("AC1C2_3_3_1", |p| {
            matches!(
                p,
                SetNameProblem::RuleUndefined {
                    channel: 1,
                    order: 3,
                    status: "outside",
                    ..
                }
            )
        }),
    ];
    for (name, expected) in cases {
        let e = crate::catalog::resolve(d, name).unwrap_err();
        let Error::SetName { name: n, problem } = &e else {
            panic!("{name}: expected SetName, got {e:?}");
        };
        assert_eq!(n, name);
        assert!(expected(problem), "{name}: {problem:?}");
        assert!(e.to_string().starts_with(&format!("{name}: ")), "{e}");
        // In a scene: the same error at the set's line, with the valid choices after it.
        let s = scene_error(&format!("displays = [\"SRGB\"]\nsets = [\"{name}\"]\n"));
        let Error::At {
            line, error, hint, ..
        } = &s
        else {
            panic!("{name}: expected Error::At, got {s:?}");
        };
        assert_eq!((*line, error.as_ref()), (2, &e));
        let hint = hint.as_deref().expect("a hint with the choices");
        assert_eq!(s.to_string(), format!("scene.toml:2: {e}; {hint}"));
    }
}

#[test]
fn at_keeps_the_first_location() {
    let e = Error::Settings("x".into()).at("a.toml", 3);
    assert_eq!(e.location(), Some(("a.toml", 3)));
    assert_eq!(e.to_string(), "a.toml:3: x");
    // An error that already names its file keeps it.
    let again = e.clone().at("b.toml", 9);
    assert_eq!(again, e);
    let whole = Error::Settings("y".into()).at("a.toml", 0);
    assert_eq!(whole.to_string(), "a.toml: y");
}

#[test]
fn values_no_literal_reproduces_are_typed() {
    assert_eq!(
        crate::emit::layout::f32_literal(1e39),
        Err(Error::Literal {
            value: 1e39,
            language: "Rust"
        })
    );
    for (lang, name) in [(Language::Wgsl, "WGSL"), (Language::Glsl, "GLSL")] {
        assert_eq!(
            lang.float(f64::NAN).unwrap_err().to_string(),
            Error::Literal {
                value: f64::NAN,
                language: "Rust"
            }
            .to_string(),
            "{name}: the f32 literal fails first"
        );
        assert_eq!(lang.name(), name);
    }
}

#[test]
fn displays_have_one_description() {
    let d = default_derivation();
    // The derivation derives the standard displays' matrices once, in their order.
    let standard = standard_displays();
    assert_eq!(d.displays.len(), standard.len());
    for ((spec, m), s) in d.displays.iter().zip(&standard) {
        assert_eq!(spec, s);
        assert_eq!(m, &crate::display::display_matrices(s).unwrap());
    }
    // A scene takes its displays from there; a transfer override changes only the transfer.
    let scene = parse(
        "sets = [\"TABLE2_ROW2\"]\ndisplays = [\"DISPLAY_P3\", \"SRGB\"]\n[transfer]\nSRGB = \"gamma 2.2\"\n",
    )
    .unwrap();
    let resolved = scene.resolve(d).unwrap();
    let names: Vec<&str> = resolved
        .displays
        .iter()
        .map(|(s, _)| s.name.as_str())
        .collect();
    assert_eq!(names, ["DISPLAY_P3", "SRGB"]);
    for (spec, m) in &resolved.displays {
        let (own, own_m) = d.display(&spec.name).unwrap();
        assert_eq!(m, own_m, "{}", spec.name);
        assert_eq!(
            (&spec.label, spec.primaries_xy, spec.white_xy),
            (&own.label, own.primaries_xy, own.white_xy)
        );
    }
    assert_eq!(resolved.displays[1].0.transfer, Transfer::Gamma(2.2));
    // Code generation bakes each display's label as its name, once per display.
    let src = crate::tests::tables_rs(d, &[], &resolved).unwrap();
    for (spec, _) in &resolved.displays {
        let baked = format!("Display::from_matrices(\n        {:?},", spec.label);
        assert_eq!(src.matches(&baked).count(), 1, "{baked}");
    }
    // The shaders name the same displays.
    let wgsl = crate::shader::snippet(d, &resolved, Language::Wgsl).unwrap();
    assert!(wgsl.contains("fn display_p3_encode(") && wgsl.contains("fn srgb_encode("));
    // An unknown name is typed.
    assert!(matches!(
        d.display("CRT"),
        Err(Error::UnknownDisplay { name, .. }) if name == "CRT"
    ));
}

#[test]
fn light_problems_are_typed() {
    let d = default_derivation();
    let dark = Curve::constant("dark", 0.0, d.settings.range_nm);
    let e = crate::shared::Problem::new(
        d,
        Some(&dark),
        Some(crate::shared::Kernel::Matern52 { length_nm: 30.0 }),
        &[],
    )
    .map(|_| ())
    .unwrap_err();
    assert_eq!(
        e,
        Error::Light {
            name: "dark".into(),
            problem: crate::LightProblem::NoLuminance
        }
    );
    let e = crate::shared::problem(d, Some("Z9"))
        .map(|_| ())
        .unwrap_err();
    assert!(
        matches!(&e, Error::Light { name, problem: crate::LightProblem::NotBuiltIn { valid } } if name == "Z9" && valid.iter().any(|l| l == "C")),
        "{e:?}"
    );
}

// ---------------------------------------------------------------------------------------------
// Displays the derivation refuses.

fn spec(name: &str, primaries: [[f64; 2]; 3], white: [f64; 2]) -> DisplaySpec {
    DisplaySpec {
        name: name.into(),
        label: name.into(),
        doc: String::new(),
        primaries_xy: primaries,
        white_xy: white,
        transfer: Transfer::Gamma(2.2),
    }
}

#[test]
fn nearly_collinear_primaries_are_refused_with_condition_number_and_threshold() {
    // Green almost on the line from red to blue.
    let red = [0.64, 0.33];
    let blue = [0.15, 0.06];
    let t = 0.5;
    let on_line = [
        red[0] + t * (blue[0] - red[0]),
        red[1] + t * (blue[1] - red[1]) + 1e-5,
    ];
    let e = display_matrices(&spec("FLAT", [red, on_line, blue], [0.3127, 0.329])).unwrap_err();
    let Error::Display {
        name,
        problem: DisplayError::Collinear { condition },
    } = &e
    else {
        panic!("expected collinear primaries, got {e:?}");
    };
    assert_eq!(name, "FLAT");
    assert!(f64::from(*condition) > MAX_CONDITION, "{condition}");
    let e = e.to_string();
    assert!(e.contains("FLAT") && e.contains("collinear"), "{e}");
    assert!(
        e.contains("condition number") && e.contains(&format!("{MAX_CONDITION:e}")),
        "{e}"
    );
}

#[test]
fn white_outside_the_primaries_triangle_is_refused() {
    let e = display_matrices(&spec(
        "ODD_WHITE",
        [[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]],
        [0.60, 0.38],
    ))
    .unwrap_err();
    assert!(
        matches!(
            &e,
            Error::Display { problem: DisplayError::WhiteOutside { drives, .. }, .. }
                if drives.iter().any(|d| *d <= 0.0)
        ),
        "{e:?}"
    );
    let e = e.to_string();
    assert!(
        e.contains("ODD_WHITE") && e.contains("outside the primaries' triangle"),
        "{e}"
    );
}

#[test]
fn invalid_chromaticities_are_refused() {
    for bad in [[0.5, 0.0], [0.7, 0.5], [f64::NAN, 0.3], [-0.1, 0.3]] {
        let e = display_matrices(&spec(
            "BAD",
            [bad, [0.3, 0.6], [0.15, 0.06]],
            [0.3127, 0.329],
        ))
        .unwrap_err();
        assert!(
            matches!(
                &e,
                Error::Display {
                    problem: DisplayError::Chromaticity { point, .. },
                    ..
                } if *point == spectral_quadrature_math::Point::Red
            ),
            "{e:?}"
        );
        let e = e.to_string();
        assert!(
            e.contains("BAD") && e.contains("red primary chromaticity"),
            "{e}"
        );
    }
}

#[test]
fn standard_displays_are_well_conditioned_and_balanced() {
    // Condition numbers of real displays lie far below the threshold (measured 19-23), and each
    // white balance sums to 1 (white at Y = 1; f64 rounding 1e-12).
    for s in standard_displays() {
        let m = display_matrices(&s).unwrap();
        assert!(m.condition < 50.0, "{}: {}", s.name, m.condition);
        assert!((m.luminance.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    }
    // The paper's monitor: Y_r : Y_g : Y_b ≈ 0.222 : 0.707 : 0.071
    // (docs/reproducing-the-paper.md).
    let meyer = standard_displays().pop().unwrap();
    let l = display_matrices(&meyer).unwrap().luminance;
    for (v, expect) in l.iter().zip([0.222, 0.707, 0.071]) {
        assert!((v - expect).abs() < 0.0006, "{l:?}");
    }
}
