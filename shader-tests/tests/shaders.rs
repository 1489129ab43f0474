//! The shader snippets of `tables::shaders`: naga parses and validates both languages for the
//! default scene and every example scene; their constants are the Rust tables' f32s bit for bit;
//! the text holds only what the scene names; and both run on a Vulkan device through wgpu and
//! agree with the runtime on every output.
//!
//! The run on a device needs a Vulkan driver, so it is ignored by default and `.ci/run` runs it:
//! `cargo test -p spectral-quadrature-shader-tests -- --ignored --nocapture` prints the adapter
//! and the largest differences. Without a GPU, the Vulkan device is Mesa's software driver
//! lavapipe (Debian: `apt-get install mesa-vulkan-drivers libvulkan1`); run that way without any
//! adapter, the test fails.

/// The data files the derivation reads (the runtime crate's `data/`).
const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../data");

use spectral_quadrature::tables::{self, displays, folded, shaders};
use spectral_quadrature::{f32_budget, quantize_u8, Display, GamutMapping, TransferFunction};

use spectral_quadrature_generator::scene::{Resolved, Scene};
use spectral_quadrature_generator::shader::{snippet, Language};

// ---------------------------------------------------------------------------------------------
// Kernels that call every function of a snippet.

/// A colour set of a snippet and the displays it is folded for.
struct SetUse {
    name: String,
    n: usize,
    displays: Vec<String>,
}

impl SetUse {
    fn of(scene: &Resolved) -> Vec<SetUse> {
        scene
            .colour_sets
            .iter()
            .map(|s| SetUse {
                name: s.name.clone(),
                n: s.len(),
                displays: scene.displays.iter().map(|(d, _)| d.name.clone()).collect(),
            })
            .collect()
    }

    /// Floats written per pixel: A, C1, C2, then linear and encoded RGB per display.
    fn outputs(&self) -> usize {
        3 + 6 * self.displays.len()
    }
}

/// Samples per pixel in the input buffer; each set reads its first N.
const STRIDE: usize = 16;

/// A compute shader (WGSL, or GLSL 4.50) around `snippet`: invocation i reads pixel i's samples
/// and writes, for each set, `<set>_ac1c2`, then per display `<set>_<display>_linear` and
/// `<display>_encode` of it.
fn kernel(lang: Language, snippet: &str, sets: &[SetUse], pixels: usize) -> String {
    let outs: usize = sets.iter().map(SetUse::outputs).sum();
    let mut body = String::new();
    let mut k = 0;
    for (j, set) in sets.iter().enumerate() {
        let lower = set.name.to_ascii_lowercase();
        let reads: Vec<String> = (0..set.n).map(|i| format!("samples[b + {i}u]")).collect();
        let (arr, vec3) = match lang {
            Language::Wgsl => (
                format!(
                    "    let s{j} = array<f32, {n}>({});\n",
                    reads.join(", "),
                    n = set.n
                ),
                "let",
            ),
            Language::Glsl => (
                format!(
                    "    float s{j}[{n}] = float[{n}]({});\n",
                    reads.join(", "),
                    n = set.n
                ),
                "vec3",
            ),
        };
        body.push_str(&arr);
        body.push_str(&format!("    put(o + {k}u, {lower}_ac1c2(s{j}));\n"));
        k += 3;
        for d in &set.displays {
            let dl = d.to_ascii_lowercase();
            body.push_str(&format!(
                "    {vec3} l{j}_{dl} = {lower}_{dl}_linear(s{j});\n    put(o + {k}u, l{j}_{dl});\n    put(o + {}u, {dl}_encode(l{j}_{dl}));\n",
                k + 3
            ));
            k += 6;
        }
    }
    match lang {
        Language::Wgsl => format!(
            "{snippet}
@group(0) @binding(0) var<storage, read> samples: array<f32>;
@group(0) @binding(1) var<storage, read_write> results: array<f32>;

fn put(at: u32, v: vec3<f32>) {{
    results[at] = v.x;
    results[at + 1u] = v.y;
    results[at + 2u] = v.z;
}}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {{
    let i = id.x;
    if (i >= {pixels}u) {{
        return;
    }}
    let b = i * {STRIDE}u;
    let o = i * {outs}u;
{body}}}
"
        ),
        Language::Glsl => format!(
            "#version 450
{snippet}
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Samples {{ float samples[]; }};
layout(std430, set = 0, binding = 1) buffer Results {{ float results[]; }};

void put(uint at, vec3 v) {{
    results[at] = v.x;
    results[at + 1u] = v.y;
    results[at + 2u] = v.z;
}}

void main() {{
    uint i = gl_GlobalInvocationID.x;
    if (i >= {pixels}u) {{
        return;
    }}
    uint b = i * {STRIDE}u;
    uint o = i * {outs}u;
{body}}}
"
        ),
    }
}

fn naga_module(lang: Language, source: &str) -> naga::Module {
    match lang {
        Language::Wgsl => naga::front::wgsl::parse_str(source)
            .unwrap_or_else(|e| panic!("WGSL: {}\n{source}", e.emit_to_string(source))),
        Language::Glsl => naga::front::glsl::Frontend::default()
            .parse(
                &naga::front::glsl::Options::from(naga::ShaderStage::Compute),
                source,
            )
            .unwrap_or_else(|e| panic!("GLSL: {}\n{source}", e.emit_to_string(source))),
    }
}

/// Parses and validates with naga; no optional capabilities, so any WebGPU or Vulkan device
/// takes it.
fn validate(lang: Language, source: &str) -> naga::Module {
    let module = naga_module(lang, source);
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{lang:?} invalid: {}\n{source}", e.emit_to_string(source)));
    module
}

/// The derivation and resolved scene of a scene file in examples/scenes.
fn example_scene(file: &str) -> (spectral_quadrature_generator::Derivation, Resolved) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(file);
    let text = std::fs::read_to_string(&path).unwrap();
    let scene = Scene::parse(
        &path.display().to_string(),
        &text,
        std::path::Path::new(DATA_DIR),
    )
    .unwrap();
    let d = spectral_quadrature_generator::derive(&scene.settings).unwrap();
    let resolved = scene.resolve(&d).unwrap();
    (d, resolved)
}

fn default_scene() -> (spectral_quadrature_generator::Derivation, Resolved) {
    let d = spectral_quadrature_generator::derive(&spectral_quadrature_generator::Settings::new(
        DATA_DIR,
    ))
    .unwrap();
    let resolved = Scene::default_scene(std::path::Path::new(DATA_DIR))
        .resolve(&d)
        .unwrap();
    (d, resolved)
}

// ---------------------------------------------------------------------------------------------
// Validation, bit identity, scene-following.

#[test]
fn naga_parses_and_validates_both_languages_for_every_scene() {
    // The baked snippets alone (WGSL is complete module-scope code), and inside a kernel that
    // calls every function, for the default scene...
    let (_, default) = default_scene();
    validate(Language::Wgsl, shaders::WGSL);
    validate(
        Language::Glsl,
        &format!(
            "#version 450\n{}\nlayout(local_size_x = 1) in;\nvoid main() {{}}\n",
            shaders::GLSL
        ),
    );
    let sets = SetUse::of(&default);
    validate(
        Language::Wgsl,
        &kernel(Language::Wgsl, shaders::WGSL, &sets, 1),
    );
    validate(
        Language::Glsl,
        &kernel(Language::Glsl, shaders::GLSL, &sets, 1),
    );
    // ...and for every example scene, generated as the build would for it.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/scenes");
    let mut scenes = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let (d, resolved) = example_scene(path.to_str().unwrap());
        for lang in [Language::Wgsl, Language::Glsl] {
            let text = snippet(&d, &resolved, lang).unwrap();
            validate(lang, &kernel(lang, &text, &SetUse::of(&resolved), 1));
        }
        scenes += 1;
    }
    assert!(scenes >= 3, "{scenes} scenes");
    // No example uses a linear transfer function: a scene that does.
    let text = "sets = [\"TABLE2_ROW1\"]\ndisplays = [\"SRGB\", \"REC2020\"]\n[transfer]\nSRGB = \"linear\"\n";
    let scene = Scene::parse("linear.toml", text, std::path::Path::new(DATA_DIR)).unwrap();
    let d = spectral_quadrature_generator::derive(&scene.settings).unwrap();
    let resolved = scene.resolve(&d).unwrap();
    for lang in [Language::Wgsl, Language::Glsl] {
        let text = snippet(&d, &resolved, lang).unwrap();
        assert!(text.contains("sq_clip01(rgb.x)") && text.contains("sq_power_curve"));
        validate(lang, &kernel(lang, &text, &SetUse::of(&resolved), 1));
    }
}

/// The f32 values of a constant expression, in order (arrays and vectors flattened).
fn values(module: &naga::Module, h: naga::Handle<naga::Expression>, out: &mut Vec<f32>) {
    use naga::{Expression, Literal, TypeInner};
    match &module.global_expressions[h] {
        Expression::Literal(Literal::F32(x)) => out.push(*x),
        Expression::Compose { components, .. } => {
            for &c in components {
                values(module, c, out);
            }
        }
        Expression::Constant(c) => values(module, module.constants[*c].init, out),
        Expression::Splat { size, value } => {
            for _ in 0..(*size as usize) {
                values(module, *value, out);
            }
        }
        Expression::ZeroValue(ty) => {
            let n = match module.types[*ty].inner {
                TypeInner::Scalar(_) => 1,
                TypeInner::Vector { size, .. } => size as usize,
                ref other => panic!("zero value of {other:?}"),
            };
            out.extend(std::iter::repeat_n(0.0, n));
        }
        other => panic!("unexpected constant expression {other:?}"),
    }
}

fn constant(module: &naga::Module, name: &str) -> Vec<f32> {
    let (_, c) = module
        .constants
        .iter()
        .find(|(_, c)| c.name.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("no constant {name}"));
    let mut out = Vec::new();
    values(module, c.init, &mut out);
    out
}

/// A baked table by name: `<SET>`, a colour set's wavelengths; `<SET>.weights`, its AC1C2
/// rows; `folded::<SET>_<DISPLAY>.weights`, a folded set's RGB rows (rows one after the other),
/// from the lists of what the scene bakes (`tables::sets::all!`, `tables::folded::all!`).
fn table(name: &str) -> &'static [f32] {
    static TABLES: std::sync::OnceLock<Vec<(String, Vec<f32>)>> = std::sync::OnceLock::new();
    let all = TABLES.get_or_init(|| {
        let mut all = Vec::new();
        macro_rules! sets {
            ($($set:ident,)*) => {
                $(
                    all.push((stringify!($set).to_string(), tables::sets::$set.wavelengths_nm().to_vec()));
                    all.push((
                        concat!(stringify!($set), ".weights").to_string(),
                        tables::sets::$set.weights().as_flattened().to_vec(),
                    ));
                )*
            };
        }
        tables::sets::all!(sets);
        macro_rules! folded {
            ($($set:ident,)*) => {
                $(
                    all.push((
                        concat!("folded::", stringify!($set), ".weights").to_string(),
                        folded::$set.weights().as_flattened().to_vec(),
                    ));
                )*
            };
        }
        folded::all!(folded);
        all
    });
    all.iter()
        .find(|(n, _)| *n == name)
        .unwrap_or_else(|| panic!("no table {name}"))
        .1
        .as_slice()
}

/// A 3×N row-major table as N columns of 3, flattened: the shaders' `vec3` per wavelength.
fn columns(rows: &[f32]) -> Vec<f32> {
    let n = rows.len() / 3;
    (0..n)
        .flat_map(|i| [rows[i], rows[n + i], rows[2 * n + i]])
        .collect()
}

#[test]
fn shader_constants_are_the_rust_tables_bit_for_bit() {
    let (_, default) = default_scene();
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<u32>>();
    for (lang, source) in [
        (Language::Wgsl, shaders::WGSL.to_string()),
        (
            Language::Glsl,
            format!(
                "#version 450\n{}\nlayout(local_size_x = 1) in;\nvoid main() {{}}\n",
                shaders::GLSL
            ),
        ),
    ] {
        let module = naga_module(lang, &source);
        let mut checked = 0;
        for set in &default.colour_sets {
            let n = &set.name;
            assert_eq!(
                bits(&constant(&module, &format!("{n}_WL"))),
                bits(table(n)),
                "{lang:?} {n}_WL"
            );
            assert_eq!(
                bits(&constant(&module, &format!("{n}_AC1C2"))),
                bits(&columns(table(&format!("{n}.weights")))),
                "{lang:?} {n}_AC1C2"
            );
            for (d, _) in &default.displays {
                let f = format!("{n}_{}", d.name);
                assert_eq!(
                    bits(&constant(&module, &f)),
                    bits(&columns(table(&format!("folded::{f}.weights")))),
                    "{lang:?} {f}"
                );
                checked += 1;
            }
        }
        assert_eq!(
            checked,
            default.colour_sets.len() * default.displays.len(),
            "every colour set of the default scene folded for every display"
        );
        assert_eq!(
            checked, 24,
            "Table 2's two sets and four shared sets, four displays"
        );
    }
}

#[test]
fn shader_text_follows_the_scene() {
    let (d, minimal) = example_scene("examples/scenes/minimal.toml");
    for lang in [Language::Wgsl, Language::Glsl] {
        let text = snippet(&d, &minimal, lang).unwrap();
        for present in [
            "TABLE2_ROW2_WL",
            "TABLE2_ROW2_AC1C2",
            "TABLE2_ROW2_SRGB",
            "table2_row2_ac1c2",
            "table2_row2_srgb_linear",
            "srgb_encode",
            "sq_srgb_curve",
        ] {
            assert!(
                text.contains(present),
                "{lang:?}: missing {present}\n{text}"
            );
        }
        for absent in [
            "ROW1",
            "row1",
            "DISPLAY_P3",
            "display_p3",
            "REC2020",
            "rec2020",
            "MEYER",
            "meyer",
            "sq_power_curve",
            "sq_clip01",
            "A_3",
            "UNIFORM",
            "uniform",
        ] {
            assert!(
                !text.contains(absent),
                "{lang:?}: {absent} is not in the scene\n{text}"
            );
        }
    }
    // A scene with a gamma display and a per-channel rule: the power curve only, and no rule.
    let (d, panel) = example_scene("examples/scenes/led_panel.toml");
    let text = snippet(&d, &panel, Language::Wgsl).unwrap();
    assert!(
        text.contains("fn ac1c2_3_2_2_display_p3_linear(s: array<f32, 7>)"),
        "{text}"
    );
    assert!(
        text.contains("sq_power_curve") && !text.contains("sq_srgb_curve"),
        "{text}"
    );
    assert!(!text.contains("A_4") && !text.contains("SRGB"), "{text}");
    // The default scene has everything, and the baked consts are its text.
    let (d, default) = default_scene();
    assert_eq!(
        snippet(&d, &default, Language::Wgsl).unwrap(),
        shaders::WGSL
    );
    assert_eq!(
        snippet(&d, &default, Language::Glsl).unwrap(),
        shaders::GLSL
    );
    for name in ["table2_row1", "table2_row2"] {
        for display in ["srgb", "display_p3", "rec2020", "meyer_1987"] {
            let f = format!("{name}_{display}_linear");
            assert!(
                shaders::WGSL.contains(&format!("fn {f}(")),
                "WGSL lacks {f}"
            );
            assert!(
                shaders::GLSL.contains(&format!("vec3 {f}(")),
                "GLSL lacks {f}"
            );
        }
    }
    // Includable as it is: no `#version` line, and ASCII only, which every GLSL compiler takes.
    assert!(!shaders::GLSL.contains("#version"));
    assert!(shaders::WGSL.is_ascii() && shaders::GLSL.is_ascii());
}

// ---------------------------------------------------------------------------------------------
// Execution on a Vulkan device.

/// One folded set of the default scene with the runtime's functions for it.
struct Case {
    set: &'static str,
    display_name: &'static str,
    n: usize,
    ac1c2: fn(&[f32]) -> [f32; 3],
    linear: fn(&[f32]) -> [f32; 3],
    display: Display,
}

macro_rules! case {
    ($set:ident, $folded:ident, $display:ident) => {
        Case {
            set: stringify!($set),
            display_name: stringify!($display),
            n: tables::$set.wavelengths_nm().len(),
            ac1c2: |s| tables::$set.ac1c2(s.try_into().unwrap()),
            linear: |s| folded::$folded.linear_rgb(s.try_into().unwrap()),
            display: displays::$display,
        }
    };
}

fn cases() -> Vec<Case> {
    vec![
        case!(TABLE2_ROW1, TABLE2_ROW1_SRGB, SRGB),
        case!(TABLE2_ROW1, TABLE2_ROW1_DISPLAY_P3, DISPLAY_P3),
        case!(TABLE2_ROW1, TABLE2_ROW1_REC2020, REC2020),
        case!(TABLE2_ROW1, TABLE2_ROW1_MEYER_1987, MEYER_1987),
        case!(TABLE2_ROW2, TABLE2_ROW2_SRGB, SRGB),
        case!(TABLE2_ROW2, TABLE2_ROW2_DISPLAY_P3, DISPLAY_P3),
        case!(TABLE2_ROW2, TABLE2_ROW2_REC2020, REC2020),
        case!(TABLE2_ROW2, TABLE2_ROW2_MEYER_1987, MEYER_1987),
        case!(KQ_C_4, KQ_C_4_SRGB, SRGB),
        case!(KQ_C_4, KQ_C_4_DISPLAY_P3, DISPLAY_P3),
        case!(KQ_C_4, KQ_C_4_REC2020, REC2020),
        case!(KQ_C_4, KQ_C_4_MEYER_1987, MEYER_1987),
        case!(KQ_C_6, KQ_C_6_SRGB, SRGB),
        case!(KQ_C_6, KQ_C_6_DISPLAY_P3, DISPLAY_P3),
        case!(KQ_C_6, KQ_C_6_REC2020, REC2020),
        case!(KQ_C_6, KQ_C_6_MEYER_1987, MEYER_1987),
        case!(KQ_C_8, KQ_C_8_SRGB, SRGB),
        case!(KQ_C_8, KQ_C_8_DISPLAY_P3, DISPLAY_P3),
        case!(KQ_C_8, KQ_C_8_REC2020, REC2020),
        case!(KQ_C_8, KQ_C_8_MEYER_1987, MEYER_1987),
        case!(KQ_F11_6, KQ_F11_6_SRGB, SRGB),
        case!(KQ_F11_6, KQ_F11_6_DISPLAY_P3, DISPLAY_P3),
        case!(KQ_F11_6, KQ_F11_6_REC2020, REC2020),
        case!(KQ_F11_6, KQ_F11_6_MEYER_1987, MEYER_1987),
    ]
}

/// The sets of `cases`, in the kernel's order.
fn set_uses(cases: &[Case]) -> Vec<SetUse> {
    let mut sets: Vec<SetUse> = Vec::new();
    for c in cases {
        match sets.iter_mut().find(|s| s.name == c.set) {
            Some(s) => s.displays.push(c.display_name.into()),
            None => sets.push(SetUse {
                name: c.set.into(),
                n: c.n,
                displays: vec![c.display_name.into()],
            }),
        }
    }
    sets
}

/// Deterministic samples: mostly reflectance-like values in 0..1, plus zeros, ones, one-hot
/// vectors, negative values, dim values around the sRGB curve's linear segment, and very
/// large and very small magnitudes (kept normal: shaders may flush subnormals to zero, and
/// below 1e34 no product or sum overflows).
fn samples(pixels: usize) -> Vec<f32> {
    let mut state = 0x853c_49e6_748f_ea9b_u64;
    let mut uniform = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    let mut out = Vec::with_capacity(pixels * STRIDE);
    for p in 0..pixels {
        for i in 0..STRIDE {
            let u = uniform();
            let v = match p % 16 {
                0 => 0.0,
                1 => 1.0,
                2 => f32::from(u8::from(i == (p / 16) % 7)),
                3 => 2.0 * u - 0.5,
                4 => 0.01 * u,
                5 => 1e-3 * u,
                6 => 1e30 * u,
                7 => 1e-30 * (u + 0.01),
                8 => 10f32.powf(60.0 * u - 30.0),
                9 => 4.0 * u,
                _ => u,
            };
            out.push(v);
        }
    }
    out
}

/// One unit in the last place of an f32 of magnitude |v| (2⁻¹⁴⁹ below the normal range).
fn ulp(v: f64) -> f64 {
    let v = v.abs();
    if v < f64::from(f32::MIN_POSITIVE) {
        return 2f64.powi(-149);
    }
    2f64.powi(v.log2().floor() as i32 - 23)
}

/// The largest error of the shader's f32 `pow(x, y32)` against the exact x^y (0 < x < 1,
/// y > 0), from the precision WGSL ("Floating Point Accuracy") and Vulkan ("Precision and
/// Operation of SPIR-V Instructions") require: pow is inherited from exp2(y · log2(x)); log2 is
/// within 2⁻²¹ absolute on [0.5, 2] and 3 ULP elsewhere; the product rounds once (½ ULP) and
/// uses y32, the f32 literal, where the runtime uses y in f64; exp2(t) is within 3 + 2|t| ULP.
fn pow_bound(x: f64, y32: f64, y: f64) -> f64 {
    let l = x.log2();
    let e_log = if (0.5..=2.0).contains(&x) {
        2f64.powi(-21)
    } else {
        3.0 * ulp(l)
    };
    let t = y * l;
    let e_t = y32 * e_log + 0.5 * ulp(t) + l.abs() * (y32 - y).abs();
    let p = t.exp2();
    // An argument off by e_t moves exp2 by the factor 2^±e_t; exp2's own ULPs are those of a
    // result up to p · 2^e_t.
    p * (e_t.exp2() - 1.0) + (3.0 + 2.0 * (t.abs() + e_t)) * ulp(p * e_t.exp2())
}

/// The largest difference between the shader's `<display>_encode` and the runtime's
/// `TransferFunction::encode` on the same linear value x.
fn encode_bound(transfer: TransferFunction, x: f32) -> f64 {
    if x.is_nan() || x <= 0.0 || x >= 1.0 {
        return 0.0; // both return exactly 0 or 1
    }
    if x < f32::MIN_POSITIVE {
        // The device may read a subnormal as 0 and encode it as 0.
        return f64::from(transfer.encode(spectral_quadrature::Rgb::R, x));
    }
    let xf = f64::from(x);
    match transfer {
        TransferFunction::Linear => 0.0,
        TransferFunction::Srgb => {
            if x <= 0.003_130_8 {
                return 0.0; // 12.92 · x, the same correctly rounded product
            }
            let y = 1.0 / 2.4;
            let p = xf.powf(y);
            let e = 1.055 * p - 0.055;
            // 1.055 · pow: the pow error scaled; the f32 literals 1.055 and 0.055 are within
            // 2⁻²⁴ (relative) of the runtime's f64 constants; the shader's product and
            // difference round (½ ULP each, or less when fused) and so does the runtime's
            // final conversion to f32 (½ ULP).
            1.055 * pow_bound(xf, f64::from(y as f32), y)
                + 2f64.powi(-24) * (1.055 * p + 0.055)
                + 0.5 * ulp(1.055 * p)
                + ulp(e)
        }
        TransferFunction::Gamma(g) => {
            let y = 1.0 / f64::from(g);
            // The pow error, and the runtime's conversion of its f64 power to f32 (½ ULP).
            pow_bound(xf, f64::from(y as f32), y) + 0.5 * ulp(xf.powf(y))
        }
        _ => unreachable!("scenes have no lookup-table transfers"),
    }
}

/// The largest difference and its share of the bound, over every compared value.
#[derive(Default)]
struct Worst {
    diff: f64,
    ratio: f64,
    compared: usize,
    equal: usize,
}

impl Worst {
    fn add(&mut self, what: &str, device: f32, runtime: f32, bound: f64) {
        let diff = (f64::from(device) - f64::from(runtime)).abs();
        assert!(
            diff <= bound,
            "{what}: device {device:e}, runtime {runtime:e}, difference {diff:e} > bound {bound:e}"
        );
        self.diff = self.diff.max(diff);
        if bound > 0.0 {
            self.ratio = self.ratio.max(diff / bound);
        }
        self.compared += 1;
        self.equal += usize::from(device.to_bits() == runtime.to_bits());
    }

    fn line(&self, name: &str) -> String {
        format!(
            "{name:<34} max |Δ| = {:.3e}, {:.3} of its bound; {} of {} bit-identical",
            self.diff, self.ratio, self.equal, self.compared
        )
    }
}

/// The f32 budget of one channel of an N-term product with weights `row`, for the runtime's
/// sum and the device's: each lies within γ_N · Σ|wᵢ·sᵢ| of the exact product of the f32
/// weights (γ_N = Nu/(1 − Nu), u = 2⁻²⁴), whatever the summation order and whether products
/// are fused into FMA, so they differ by at most 2γ_N · Σ|wᵢ·sᵢ| ≤ `f32_budget(N, Σ|wᵢ·sᵢ|)`.
/// A device may also flush subnormal products and partial sums to zero: 2N · 2⁻¹²⁶ more.
fn product_budget(row: &[f32], s: &[f32]) -> f64 {
    let abs_sum: f64 = row
        .iter()
        .zip(s)
        .map(|(w, s)| (f64::from(*w) * f64::from(*s)).abs())
        .sum();
    f32_budget(row.len(), abs_sum) + 2.0 * row.len() as f64 * f64::from(f32::MIN_POSITIVE)
}

/// `product_budget` covers what a shader compiler may do to the runtime's sums: fuse each
/// multiply-add into an FMA, or add the terms in another order.
#[test]
fn the_product_budget_covers_fused_and_reordered_sums() {
    const PIXELS: usize = 4096;
    let input = samples(PIXELS);
    let (mut worst, mut differ, mut compared) = (0.0f64, 0usize, 0usize);
    for p in 0..PIXELS {
        for case in cases() {
            let s = &input[p * STRIDE..p * STRIDE + case.n];
            for (rows, rust) in [
                (table(&format!("{}.weights", case.set)), (case.ac1c2)(s)),
                (
                    table(&format!(
                        "folded::{}_{}.weights",
                        case.set, case.display_name
                    )),
                    (case.linear)(s),
                ),
            ] {
                for c in 0..3 {
                    let row = &rows[c * case.n..(c + 1) * case.n];
                    let terms = row.iter().zip(s);
                    let fused = terms.clone().fold(0.0f32, |acc, (w, x)| w.mul_add(*x, acc));
                    let reversed = terms.clone().rev().fold(0.0f32, |acc, (w, x)| acc + w * x);
                    let fused_reversed = terms.rev().fold(0.0f32, |acc, (w, x)| w.mul_add(*x, acc));
                    let budget = product_budget(row, s);
                    for other in [fused, reversed, fused_reversed] {
                        let diff = (f64::from(other) - f64::from(rust[c])).abs();
                        assert!(
                            diff <= budget,
                            "pixel {p} {}: {other:e} vs {:e}",
                            case.set,
                            rust[c]
                        );
                        worst = worst.max(diff / budget);
                        differ += usize::from(other != rust[c]);
                        compared += 1;
                    }
                }
            }
        }
    }
    println!(
        "fused and reordered sums: {differ} of {compared} differ from the runtime's, by at most {worst:.3} of the budget"
    );
    assert!(differ > 0, "the inputs never tell the orders apart");
}

struct Gpu {
    device: wgpu::Device,
    queue: wgpu::Queue,
}

fn gpu() -> Gpu {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
    desc.backends = wgpu::Backends::VULKAN;
    let instance = wgpu::Instance::new(desc);
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        ..Default::default()
    }))
    .unwrap_or_else(|e| {
        panic!(
            "no Vulkan adapter ({e}): the shader test needs a Vulkan driver. Without a GPU, install \
             Mesa's software driver lavapipe and the Vulkan loader (Debian/Ubuntu: \
             `apt-get install mesa-vulkan-drivers libvulkan1`; .ci/run does this)"
        )
    });
    let info = adapter.get_info();
    println!(
        "adapter: {} ({:?}, {:?}), driver {} {}",
        info.name, info.device_type, info.backend, info.driver, info.driver_info
    );
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("spectral-quadrature shaders test"),
        ..Default::default()
    }))
    .unwrap_or_else(|e| panic!("the adapter {} gave no device: {e}", info.name));
    Gpu { device, queue }
}

impl Gpu {
    /// Runs `source` over `input` with one invocation per pixel; returns the results buffer.
    fn run(
        &self,
        source: wgpu::ShaderSource<'_>,
        input: &[f32],
        pixels: usize,
        outs: usize,
    ) -> Vec<f32> {
        self.run_with(source, input, &[], pixels, outs)
    }

    /// [`run`](Self::run) with read-only storage buffers of words at bindings 2, 3, ….
    fn run_with(
        &self,
        source: wgpu::ShaderSource<'_>,
        input: &[f32],
        extra: &[&[u32]],
        pixels: usize,
        outs: usize,
    ) -> Vec<f32> {
        use wgpu::util::DeviceExt;
        let d = &self.device;
        let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: None,
            source,
        });
        let pipeline = d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: None,
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        let bytes: Vec<u8> = input.iter().flat_map(|v| v.to_le_bytes()).collect();
        let samples = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents: &bytes,
            usage: wgpu::BufferUsages::STORAGE,
        });
        let size = (pixels * outs * 4) as u64;
        let results = d.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readback = d.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let extra: Vec<wgpu::Buffer> = extra
            .iter()
            .map(|words| {
                let bytes: Vec<u8> = words.iter().flat_map(|v| v.to_le_bytes()).collect();
                d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: None,
                    contents: &bytes,
                    usage: wgpu::BufferUsages::STORAGE,
                })
            })
            .collect();
        let mut entries = vec![
            wgpu::BindGroupEntry {
                binding: 0,
                resource: samples.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: results.as_entire_binding(),
            },
        ];
        for (i, b) in extra.iter().enumerate() {
            entries.push(wgpu::BindGroupEntry {
                binding: 2 + i as u32,
                resource: b.as_entire_binding(),
            });
        }
        let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        let mut encoder = d.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups(pixels.div_ceil(64) as u32, 1, 1);
        }
        encoder.copy_buffer_to_buffer(&results, 0, &readback, 0, size);
        self.queue.submit([encoder.finish()]);
        let slice = readback.slice(..);
        slice.map_async(wgpu::MapMode::Read, |r| r.expect("map the results"));
        d.poll(wgpu::PollType::wait_indefinitely())
            .expect("the device finishes");
        let view = slice.get_mapped_range().expect("the mapped results");
        view.chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect()
    }
}

#[test]
#[ignore = "needs a Vulkan driver (lavapipe on a machine without a GPU): .ci/run runs it with --ignored"]
fn wgsl_and_glsl_run_on_vulkan_and_agree_with_the_runtime() {
    const PIXELS: usize = 4096;
    let cases = cases();
    // Every folded set the default scene bakes is here.
    let baked = folded::NAMES.len();
    assert_eq!(
        cases.len(),
        baked,
        "add the scene's new folded sets to cases()"
    );
    let sets = set_uses(&cases);
    let outs: usize = sets.iter().map(SetUse::outputs).sum();
    let input = samples(PIXELS);
    let gpu = gpu();
    let wgsl = kernel(Language::Wgsl, shaders::WGSL, &sets, PIXELS);
    let glsl = kernel(Language::Glsl, shaders::GLSL, &sets, PIXELS);
    for (lang, source) in [
        (
            Language::Wgsl,
            wgpu::ShaderSource::Wgsl(wgsl.as_str().into()),
        ),
        (
            Language::Glsl,
            wgpu::ShaderSource::Glsl {
                shader: glsl.as_str().into(),
                stage: wgpu::naga::ShaderStage::Compute,
                defines: &[],
            },
        ),
    ] {
        let out = gpu.run(source, &input, PIXELS, outs);
        let (mut ac1c2, mut linear, mut encoded, mut full) = (
            Worst::default(),
            Worst::default(),
            Worst::default(),
            Worst::default(),
        );
        let mut u8_differ = 0usize;
        for p in 0..PIXELS {
            let s = &input[p * STRIDE..(p + 1) * STRIDE];
            let mut k = p * outs;
            for set in &sets {
                let set_cases: Vec<&Case> = cases.iter().filter(|c| c.set == set.name).collect();
                let s = &s[..set.n];
                let rust = (set_cases[0].ac1c2)(s);
                let rows = table(&format!("{}.weights", set.name));
                for c in 0..3 {
                    let row = &rows[c * set.n..(c + 1) * set.n];
                    ac1c2.add(
                        &format!("{lang:?} {} ac1c2[{c}] pixel {p} {s:?}", set.name),
                        out[k + c],
                        rust[c],
                        product_budget(row, s),
                    );
                }
                k += 3;
                for case in set_cases {
                    let name = format!("{}_{}", case.set, case.display_name);
                    let rows = table(&format!("folded::{name}.weights"));
                    let rust = (case.linear)(s);
                    let device_linear = [out[k], out[k + 1], out[k + 2]];
                    let device_encoded = [out[k + 3], out[k + 4], out[k + 5]];
                    let rust_encoded = case.display.encode(GamutMapping::Clip, device_linear);
                    let rust_u8 = case.display.encode_u8(GamutMapping::Clip, rust);
                    let rust_full = case.display.encode(GamutMapping::Clip, rust);
                    for c in 0..3 {
                        let row = &rows[c * set.n..(c + 1) * set.n];
                        let what = format!("{lang:?} {name} channel {c} pixel {p} {s:?}");
                        linear.add(&what, device_linear[c], rust[c], product_budget(row, s));
                        encoded.add(
                            &what,
                            device_encoded[c],
                            rust_encoded[c],
                            encode_bound(case.display.transfer(), device_linear[c]),
                        );
                        // The whole path, samples to encoded values: the encode bound plus the
                        // curve's change across the linear difference; quantized, at most one
                        // code apart (asserted below).
                        let curve_shift =
                            (f64::from(rust_encoded[c]) - f64::from(rust_full[c])).abs();
                        full.add(
                            &what,
                            device_encoded[c],
                            rust_full[c],
                            encode_bound(case.display.transfer(), device_linear[c]) + curve_shift,
                        );
                        let q = quantize_u8(device_encoded[c]);
                        assert!(
                            q.abs_diff(rust_u8[c]) <= 1,
                            "{what}: u8 {q} vs {}",
                            rust_u8[c]
                        );
                        u8_differ += usize::from(q != rust_u8[c]);
                    }
                    k += 6;
                }
            }
        }
        println!(
            "{lang:?}, {PIXELS} sample vectors, {} folded sets:",
            cases.len()
        );
        println!("  {}", ac1c2.line("samples → AC1C2 (f32 budget)"));
        println!("  {}", linear.line("samples → linear RGB (f32 budget)"));
        println!("  {}", encoded.line("linear → encoded (pow bound)"));
        println!("  {}", full.line("samples → encoded"));
        println!(
            "  8-bit codes (encode_u8): {u8_differ} of {} differ, none by more than one",
            full.compared
        );
    }
}

// ---------------------------------------------------------------------------------------------
// The upsamplings (`<set>_<display>_reflectance`): each reads its table from a storage buffer
// the kernel declares (binding 2 on), filled with `Upsampling::shader_words`.

/// A kernel that writes, per invocation, every upsampling's node values of one RGB triple.
fn upsampling_kernel(lang: Language, ups: &[Up], pixels: usize) -> String {
    let outs: usize = ups.iter().map(|u| 2 * u.n).sum();
    let mut decls = String::new();
    let mut body = String::new();
    let mut k = 0;
    for (j, u) in ups.iter().enumerate() {
        let (name, n) = (u.name, u.n);
        let lower = name.to_ascii_lowercase();
        let binding = j + 2;
        match lang {
            Language::Wgsl => {
                decls.push_str(&format!(
                    "@group(0) @binding({binding}) var<storage, read> {name}_CODES: array<u32>;\n{}\n",
                    u.wgsl
                ));
                body.push_str(&format!(
                    "    let r{j} = {lower}_reflectance(rgb);\n    let q{j} = {lower}_interpolate(rgb);\n"
                ));
            }
            Language::Glsl => {
                decls.push_str(&format!(
                    "layout(std430, set = 0, binding = {binding}) readonly buffer {name}_Buffer {{ uint {name}_CODES[]; }};\n{}\n",
                    u.glsl
                ));
                body.push_str(&format!(
                    "    float r{j}[{n}] = {lower}_reflectance(rgb);\n    float q{j}[{n}] = {lower}_interpolate(rgb);\n"
                ));
            }
        }
        for i in 0..n {
            body.push_str(&format!("    results[o + {}u] = r{j}[{i}];\n", k + i));
            body.push_str(&format!("    results[o + {}u] = q{j}[{i}];\n", k + n + i));
        }
        k += 2 * n;
    }
    match lang {
        Language::Wgsl => format!(
            "{decls}
@group(0) @binding(0) var<storage, read> samples: array<f32>;
@group(0) @binding(1) var<storage, read_write> results: array<f32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {{
    let i = id.x;
    if (i >= {pixels}u) {{
        return;
    }}
    let rgb = vec3<f32>(samples[3u * i], samples[3u * i + 1u], samples[3u * i + 2u]);
    let o = i * {outs}u;
{body}}}
"
        ),
        Language::Glsl => format!(
            "#version 450
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Samples {{ float samples[]; }};
layout(std430, set = 0, binding = 1) buffer Results {{ float results[]; }};
{decls}
void main() {{
    uint i = gl_GlobalInvocationID.x;
    if (i >= {pixels}u) {{
        return;
    }}
    vec3 rgb = vec3(samples[3u * i], samples[3u * i + 1u], samples[3u * i + 2u]);
    uint o = i * {outs}u;
{body}}}
"
        ),
    }
}

/// One upsampling of the default scene: its name, N, shader texts, table words and its
/// runtime `interpolate`.
struct Up {
    name: &'static str,
    n: usize,
    wgsl: &'static str,
    glsl: &'static str,
    words: Vec<u32>,
    interpolate: Box<dyn Fn([f32; 3]) -> Vec<f32>>,
    reflectance: Box<dyn Fn([f32; 3]) -> Vec<f32>>,
}

fn up<const N: usize>(
    name: &'static str,
    u: &'static spectral_quadrature::Upsampling<N>,
    wgsl: &'static str,
    glsl: &'static str,
) -> Up {
    Up {
        name,
        n: N,
        wgsl,
        glsl,
        words: u.shader_words().collect(),
        interpolate: Box::new(move |rgb| u.interpolate(rgb).to_vec()),
        reflectance: Box::new(move |rgb| u.reflectance(rgb).to_vec()),
    }
}

/// The default scene's upsamplings: its shared sets and Table 2's rows on every display.
fn upsamplings() -> Vec<Up> {
    use spectral_quadrature::tables::upsampling as u;
    vec![
        up(
            "KQ_C_4_SRGB",
            &u::KQ_C_4_SRGB,
            u::KQ_C_4_SRGB_WGSL,
            u::KQ_C_4_SRGB_GLSL,
        ),
        up(
            "KQ_C_4_DISPLAY_P3",
            &u::KQ_C_4_DISPLAY_P3,
            u::KQ_C_4_DISPLAY_P3_WGSL,
            u::KQ_C_4_DISPLAY_P3_GLSL,
        ),
        up(
            "KQ_C_4_REC2020",
            &u::KQ_C_4_REC2020,
            u::KQ_C_4_REC2020_WGSL,
            u::KQ_C_4_REC2020_GLSL,
        ),
        up(
            "KQ_C_4_MEYER_1987",
            &u::KQ_C_4_MEYER_1987,
            u::KQ_C_4_MEYER_1987_WGSL,
            u::KQ_C_4_MEYER_1987_GLSL,
        ),
        up(
            "KQ_C_6_SRGB",
            &u::KQ_C_6_SRGB,
            u::KQ_C_6_SRGB_WGSL,
            u::KQ_C_6_SRGB_GLSL,
        ),
        up(
            "KQ_C_6_DISPLAY_P3",
            &u::KQ_C_6_DISPLAY_P3,
            u::KQ_C_6_DISPLAY_P3_WGSL,
            u::KQ_C_6_DISPLAY_P3_GLSL,
        ),
        up(
            "KQ_C_6_REC2020",
            &u::KQ_C_6_REC2020,
            u::KQ_C_6_REC2020_WGSL,
            u::KQ_C_6_REC2020_GLSL,
        ),
        up(
            "KQ_C_6_MEYER_1987",
            &u::KQ_C_6_MEYER_1987,
            u::KQ_C_6_MEYER_1987_WGSL,
            u::KQ_C_6_MEYER_1987_GLSL,
        ),
        up(
            "KQ_C_8_SRGB",
            &u::KQ_C_8_SRGB,
            u::KQ_C_8_SRGB_WGSL,
            u::KQ_C_8_SRGB_GLSL,
        ),
        up(
            "KQ_C_8_DISPLAY_P3",
            &u::KQ_C_8_DISPLAY_P3,
            u::KQ_C_8_DISPLAY_P3_WGSL,
            u::KQ_C_8_DISPLAY_P3_GLSL,
        ),
        up(
            "KQ_C_8_REC2020",
            &u::KQ_C_8_REC2020,
            u::KQ_C_8_REC2020_WGSL,
            u::KQ_C_8_REC2020_GLSL,
        ),
        up(
            "KQ_C_8_MEYER_1987",
            &u::KQ_C_8_MEYER_1987,
            u::KQ_C_8_MEYER_1987_WGSL,
            u::KQ_C_8_MEYER_1987_GLSL,
        ),
        up(
            "KQ_F11_6_SRGB",
            &u::KQ_F11_6_SRGB,
            u::KQ_F11_6_SRGB_WGSL,
            u::KQ_F11_6_SRGB_GLSL,
        ),
        up(
            "KQ_F11_6_DISPLAY_P3",
            &u::KQ_F11_6_DISPLAY_P3,
            u::KQ_F11_6_DISPLAY_P3_WGSL,
            u::KQ_F11_6_DISPLAY_P3_GLSL,
        ),
        up(
            "KQ_F11_6_REC2020",
            &u::KQ_F11_6_REC2020,
            u::KQ_F11_6_REC2020_WGSL,
            u::KQ_F11_6_REC2020_GLSL,
        ),
        up(
            "KQ_F11_6_MEYER_1987",
            &u::KQ_F11_6_MEYER_1987,
            u::KQ_F11_6_MEYER_1987_WGSL,
            u::KQ_F11_6_MEYER_1987_GLSL,
        ),
        up(
            "TABLE2_ROW1_SRGB",
            &u::TABLE2_ROW1_SRGB,
            u::TABLE2_ROW1_SRGB_WGSL,
            u::TABLE2_ROW1_SRGB_GLSL,
        ),
        up(
            "TABLE2_ROW1_DISPLAY_P3",
            &u::TABLE2_ROW1_DISPLAY_P3,
            u::TABLE2_ROW1_DISPLAY_P3_WGSL,
            u::TABLE2_ROW1_DISPLAY_P3_GLSL,
        ),
        up(
            "TABLE2_ROW1_REC2020",
            &u::TABLE2_ROW1_REC2020,
            u::TABLE2_ROW1_REC2020_WGSL,
            u::TABLE2_ROW1_REC2020_GLSL,
        ),
        up(
            "TABLE2_ROW1_MEYER_1987",
            &u::TABLE2_ROW1_MEYER_1987,
            u::TABLE2_ROW1_MEYER_1987_WGSL,
            u::TABLE2_ROW1_MEYER_1987_GLSL,
        ),
        up(
            "TABLE2_ROW2_SRGB",
            &u::TABLE2_ROW2_SRGB,
            u::TABLE2_ROW2_SRGB_WGSL,
            u::TABLE2_ROW2_SRGB_GLSL,
        ),
        up(
            "TABLE2_ROW2_DISPLAY_P3",
            &u::TABLE2_ROW2_DISPLAY_P3,
            u::TABLE2_ROW2_DISPLAY_P3_WGSL,
            u::TABLE2_ROW2_DISPLAY_P3_GLSL,
        ),
        up(
            "TABLE2_ROW2_REC2020",
            &u::TABLE2_ROW2_REC2020,
            u::TABLE2_ROW2_REC2020_WGSL,
            u::TABLE2_ROW2_REC2020_GLSL,
        ),
        up(
            "TABLE2_ROW2_MEYER_1987",
            &u::TABLE2_ROW2_MEYER_1987,
            u::TABLE2_ROW2_MEYER_1987_WGSL,
            u::TABLE2_ROW2_MEYER_1987_GLSL,
        ),
    ]
}

/// Upsamplings per kernel: each reads its own storage buffer, besides the samples and the
/// results, and a device need allow no more than 8 storage buffers per shader stage (WebGPU's
/// and wgpu's default limit).
const UPSAMPLINGS_PER_KERNEL: usize = 6;

#[test]
fn upsampling_kernels_validate() {
    let ups = upsamplings();
    assert_eq!(
        ups.len(),
        default_scene().1.upsamplings.len(),
        "add the scene's new upsamplings to upsamplings()"
    );
    for group in ups.chunks(UPSAMPLINGS_PER_KERNEL) {
        validate(
            Language::Wgsl,
            &upsampling_kernel(Language::Wgsl, group, 64),
        );
        validate(
            Language::Glsl,
            &upsampling_kernel(Language::Glsl, group, 64),
        );
    }
}

/// RGB triples over the cube, its faces, edges and corners, and out-of-range values.
fn upsampling_samples(pixels: usize) -> Vec<f32> {
    let mut v = Vec::with_capacity(3 * pixels);
    let mut state = 0x9e37_79b9u32;
    let specials = [0.0f32, 1.0, 0.5, 0.125, -0.25, 1.5];
    for p in 0..pixels {
        for c in 0..3 {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let x = (state >> 8) as f32 / (1u32 << 24) as f32;
            v.push(if p % 4 == 0 {
                specials[(state as usize >> 3) % specials.len()]
            } else if c == p % 3 && p % 5 == 0 {
                x * 0.05
            } else {
                x
            });
        }
    }
    v
}

#[test]
#[ignore = "needs a Vulkan driver (lavapipe on a machine without a GPU): .ci/run runs it with --ignored"]
fn upsampling_runs_on_vulkan_and_agrees_with_the_runtime() {
    const PIXELS: usize = 4096;
    let all = upsamplings();
    let input = upsampling_samples(PIXELS);
    let gpu = gpu();
    for (lang, ups) in [Language::Wgsl, Language::Glsl]
        .into_iter()
        .flat_map(|lang| all.chunks(UPSAMPLINGS_PER_KERNEL).map(move |g| (lang, g)))
    {
        let outs: usize = ups.iter().map(|u| 2 * u.n).sum();
        let extra: Vec<&[u32]> = ups.iter().map(|u| u.words.as_slice()).collect();
        let text = upsampling_kernel(lang, ups, PIXELS);
        let source = match lang {
            Language::Wgsl => wgpu::ShaderSource::Wgsl(text.as_str().into()),
            Language::Glsl => wgpu::ShaderSource::Glsl {
                shader: text.as_str().into(),
                stage: wgpu::naga::ShaderStage::Compute,
                defines: &[],
            },
        };
        let started = std::time::Instant::now();
        let out = gpu.run_with(source, &input, &extra, PIXELS, outs);
        let elapsed = started.elapsed();
        let (mut worst_interp, mut worst_same, mut worst_corrected) = (0.0f32, 0.0f32, 0.0f32);
        let mut corrected = 0usize;
        for p in 0..PIXELS {
            let rgb = [input[3 * p], input[3 * p + 1], input[3 * p + 2]];
            let mut k = p * outs;
            for u in ups {
                let interp = (u.interpolate)(rgb);
                let refl = (u.reflectance)(rgb);
                let is_corrected = interp != refl;
                let sensitivity: Vec<f32> = if is_corrected {
                    (0..3)
                        .flat_map(|c| {
                            let mut q = rgb;
                            q[c] += 4.0 * f32::EPSILON * q[c].abs().max(f32::MIN_POSITIVE);
                            let moved = (u.reflectance)(q);
                            moved
                                .into_iter()
                                .zip(&refl)
                                .map(|(a, b)| (a - b).abs())
                                .enumerate()
                        })
                        .fold(vec![0.0f32; u.n], |mut m, (i, d)| {
                            m[i] = m[i].max(d);
                            m
                        })
                } else {
                    Vec::new()
                };
                corrected += usize::from(is_corrected);
                for i in 0..u.n {
                    let (dev_r, dev_q) = (out[k + i], out[k + u.n + i]);
                    let dq = (dev_q - interp[i]).abs();
                    let dr = (dev_r - refl[i]).abs();
                    // Four products of weights in [0, 1] and codes below 2¹⁶, summed, then
                    // scaled: each rounding within 2⁻²⁴ of the sum's size (at most 65535), so a
                    // fused or reordered sum differs by at most a few units of 2⁻²⁴ once
                    // scaled to [0, 1]: 8 of them bound it.
                    let interp_bound = 8.0 * f32::EPSILON;
                    assert!(
                        dq <= interp_bound,
                        "{lang:?} {} interpolate node {i} at {rgb:?}: {dev_q} vs {}",
                        u.name,
                        interp[i]
                    );
                    worst_interp = worst_interp.max(dq);
                    if is_corrected {
                        // The correction solves a small programme whose solution moves
                        // continuously with its data. The shader runs the runtime's steps (its
                        // cube root included), but Vulkan lets a shader's division and square
                        // root be off by 2.5 ULP, which moves the data by a few parts in 10⁷
                        // and the solution by that times the programme's conditioning (at most
                        // 9e-8 measured on lavapipe for the sRGB maps); 1e-5 leaves a factor
                        // of 100. Where the map is steeper (wide-gamut displays: Lipschitz up
                        // to 1200 in the edge cells), the conditioning is worse: the bound
                        // grows with the runtime's own change when the RGB moves by 4 ULP,
                        // with the same factor of 100.
                        let bound = 1e-5f32.max(100.0 * sensitivity[i]);
                        assert!(
                            dr <= bound,
                            "{lang:?} {} reflectance node {i} at {rgb:?}: {dev_r} vs {}",
                            u.name,
                            refl[i]
                        );
                        worst_corrected = worst_corrected.max(dr);
                    } else {
                        assert!(
                            dr <= interp_bound,
                            "{lang:?} {} reflectance node {i} at {rgb:?}: {dev_r} vs {}",
                            u.name,
                            refl[i]
                        );
                        worst_same = worst_same.max(dr);
                    }
                }
                k += 2 * u.n;
            }
        }
        println!(
            "{lang:?}: {PIXELS} RGB triples, {} upsamplings (compile and run {elapsed:.2?}): largest difference from the runtime: interpolate {worst_interp:e}; reflectance {worst_same:e} where it is the interpolation, {worst_corrected:e} where the runtime corrects ({corrected} pixel-upsamplings)",
            ups.len()
        );
    }
}
