//! WGSL and GLSL snippets of a scene: its colour sets, their folded weights and its displays'
//! encodings, written from the scene's model, the same f32 values `codegen` bakes, so a shader
//! constant is the very f32 of its Rust counterpart.
//!
//! For each colour set `<SET>` (lower case `<set>`) and display `<DISPLAY>` (`<display>`):
//!
//! - `<SET>_WL`: the wavelengths in nm, the order in which to pass samples;
//! - `<SET>_AC1C2`: the weights for A, C1, C2, one `vec3` per wavelength;
//! - `<SET>_<DISPLAY>`: the folded weights for linear RGB, one `vec3` per wavelength;
//! - `<set>_ac1c2(s)` and `<set>_<display>_linear(s)`: the runtime's `WavelengthSet::ac1c2` and
//!   `FoldedSet::linear_rgb`, the products summed in the runtime's order;
//! - `<display>_encode(rgb)`: the runtime's `Display::encode` with `GamutMapping::Clip`: clip to
//!   0..=1, then the display's transfer function;
//!
//! For each light group `<GROUP>` of L lights and N wavelengths: `<GROUP>_WL`, `<GROUP>_<DISPLAY>`
//! (each light's folded weights in turn, L·N `vec3`s) and `<group>_<display>_linear(s)`, the
//! runtime's `LightGroupSet::linear_rgb` of the L·N samples, light k's at `s[k·N + i]`.
//!
//! The upsamplings' functions are not here: each reads its table from a storage buffer the
//! shader declares, and comes as its own text (`tables::upsampling::<SET>_<DISPLAY>_WGSL`,
//! `emit/upsampling.rs`).
//!
//! Helpers start with `sq_`. Per-channel rule sets are left out: alone they give no colour.
//! The WGSL text is complete module-scope code to prepend to a shader; the GLSL text has no
//! `#version` line and needs GLSL 3.30 or ES 3.00 (constant arrays).

use std::fmt::Write as _;
use std::string::String;
use std::vec::Vec;

use super::layout::f32_literal;
use super::model::{Model, Samples, Transfer};
use crate::base::error::Error;
use crate::derivation::derive::Derivation;
use crate::scenes::scene::Resolved;

/// A shading language the snippets are written in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Language {
    /// WebGPU Shading Language.
    Wgsl,
    /// OpenGL Shading Language (4.50 core, 3.30 core and ES 3.00 accept it).
    Glsl,
}

/// The sRGB curve's constants, as the runtime's `TransferFunction::encode` uses them
/// (src/display.rs): the end of the linear segment and its slope, in f32.
const SRGB_LINEAR_MAX: f32 = 0.003_130_8;
const SRGB_SLOPE: f32 = 12.92;

impl Language {
    /// `"WGSL"` or `"GLSL"`.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Language::Wgsl => "WGSL",
            Language::Glsl => "GLSL",
        }
    }

    /// A literal for `v` rounded to f32, the same f32 that [`f32_literal`] bakes. The decimal
    /// text must give that f32 whether a compiler parses it straight to f32 or to f64 first
    /// (WGSL's abstract floats, many GLSL front ends); when the shortest text would not, the
    /// f32's exact value in shortest f64 form is used instead.
    pub(crate) fn float(self, v: f64) -> Result<String, Error> {
        let x = v as f32;
        let mut s = f32_literal(v)?;
        let same = |t: &str| {
            t.parse::<f32>().map(f32::to_bits) == Ok(x.to_bits())
                && t.parse::<f64>().map(|y| (y as f32).to_bits()) == Ok(x.to_bits())
        };
        if !same(&s) {
            s = std::format!("{:?}", f64::from(x));
            if !s.contains(['.', 'e', 'E']) {
                s.push_str(".0");
            }
            if !same(&s) {
                return Err(Error::Literal {
                    value: v,
                    language: self.name(),
                });
            }
        }
        // WGSL: the suffix makes the literal an f32 (parsed straight to f32), not an abstract
        // float. A GLSL literal without suffix is a float.
        if self == Language::Wgsl {
            s.push('f');
        }
        Ok(s)
    }

    fn vec3(self, v: [f64; 3]) -> Result<String, Error> {
        let head = match self {
            Language::Wgsl => "vec3<f32>",
            Language::Glsl => "vec3",
        };
        Ok(std::format!(
            "{head}({}, {}, {})",
            self.float(v[0])?,
            self.float(v[1])?,
            self.float(v[2])?
        ))
    }

    /// `const NAME: array<T, N> = array<T, N>(items);` or its GLSL form.
    fn const_array(self, name: &str, ty: &str, items: &[String]) -> String {
        let n = items.len();
        let body = items.join(",\n    ");
        match self {
            Language::Wgsl => std::format!(
                "const {name}: array<{ty}, {n}> = array<{ty}, {n}>(\n    {body},\n);\n"
            ),
            Language::Glsl => {
                std::format!("const {ty} {name}[{n}] = {ty}[{n}](\n    {body}\n);\n")
            }
        }
    }

    fn scalar(self) -> &'static str {
        match self {
            Language::Wgsl => "f32",
            Language::Glsl => "float",
        }
    }

    fn vec3_type(self) -> &'static str {
        match self {
            Language::Wgsl => "vec3<f32>",
            Language::Glsl => "vec3",
        }
    }

    /// A function header: `fn name(args) -> ret {` or `ret name(args) {`; each argument as
    /// its WGSL and its GLSL declaration.
    fn function(self, name: &str, args: &[(String, String)], ret: &str) -> String {
        match self {
            Language::Wgsl => {
                let a: Vec<String> = args.iter().map(|(w, _)| w.clone()).collect();
                std::format!("fn {name}({}) -> {ret} {{\n", a.join(", "))
            }
            Language::Glsl => {
                let a: Vec<String> = args.iter().map(|(_, g)| g.clone()).collect();
                std::format!("{ret} {name}({}) {{\n", a.join(", "))
            }
        }
    }

    fn let_var(self, name: &str, init: &str) -> String {
        match self {
            Language::Wgsl => std::format!("    var {name} = {init};\n"),
            Language::Glsl => std::format!("    vec3 {name} = {init};\n"),
        }
    }
}

/// `out = Σ_i w[i] · s[i]` over N samples, one statement per term in index order, as the
/// runtime's `mat_vec` accumulates.
fn product_body(lang: Language, weights: &str, n: usize) -> String {
    let mut b = lang.let_var("acc", &std::format!("{weights}[0] * s[0]"));
    for i in 1..n {
        writeln!(b, "    acc = acc + {weights}[{i}] * s[{i}];").ok();
    }
    b.push_str("    return acc;\n}\n");
    b
}

fn samples_arg(n: usize) -> (String, String) {
    (
        std::format!("s: array<f32, {n}>"),
        std::format!("float s[{n}]"),
    )
}

/// The weights as one `vec3` per wavelength (the columns of the 3×N matrix).
fn columns(lang: Language, w: &[Vec<f32>; 3]) -> Result<Vec<String>, Error> {
    (0..w[0].len())
        .map(|i| lang.vec3([w[0][i], w[1][i], w[2][i]].map(f64::from)))
        .collect()
}

/// The per-channel curve helpers a scene's displays use, in a fixed order.
fn helpers(lang: Language, m: &Model) -> Result<String, Error> {
    let uses = |f: fn(&Transfer) -> bool| m.displays.iter().any(|d| f(&d.transfer));
    let f = lang.scalar();
    let x = (std::format!("x: {f}"), String::from("float x"));
    let lit = |v: f64| lang.float(v);
    // Each curve returns exactly 0 for x ≤ 0 (and for NaN, where the implementation keeps
    // NaN) and exactly 1 for x ≥ 1, as the runtime does.
    let ends = std::format!(
        "    if (!(x > {zero})) {{\n        return {zero};\n    }}\n    if (x >= {one}) {{\n        return {one};\n    }}\n",
        zero = lit(0.0)?,
        one = lit(1.0)?
    );
    let mut o = String::new();
    if uses(|t| matches!(t, Transfer::Linear)) {
        o.push_str("// Linear light clipped to 0..=1.\n");
        o.push_str(&lang.function("sq_clip01", core::slice::from_ref(&x), f));
        o.push_str(&ends);
        o.push_str("    return x;\n}\n\n");
    }
    if uses(|t| matches!(t, Transfer::Srgb)) {
        // The runtime holds the power branch at the join's value, 12.92 · 0.0031308 in f32.
        let join = SRGB_SLOPE * SRGB_LINEAR_MAX;
        o.push_str("// The sRGB curve (IEC 61966-2-1) of linear light clipped to 0..=1.\n");
        o.push_str(&lang.function("sq_srgb_curve", core::slice::from_ref(&x), f));
        o.push_str(&ends);
        writeln!(
            o,
            "    if (x <= {}) {{\n        return {} * x;\n    }}\n    return min(max({} * pow(x, {}) - {}, {}), {});\n}}\n",
            lit(f64::from(SRGB_LINEAR_MAX))?,
            lit(f64::from(SRGB_SLOPE))?,
            lit(1.055)?,
            lit(1.0 / 2.4)?,
            lit(0.055)?,
            lit(f64::from(join))?,
            lit(1.0)?,
        )
        .ok();
    }
    if uses(|t| matches!(t, Transfer::Gamma { .. })) {
        o.push_str("// A pure power law, linear^(1/gamma) = linear^inv_gamma, of linear light clipped to 0..=1.\n");
        o.push_str(&lang.function(
            "sq_power_curve",
            &[
                x.clone(),
                (std::format!("inv_gamma: {f}"), "float inv_gamma".into()),
            ],
            f,
        ));
        o.push_str(&ends);
        writeln!(o, "    return min(pow(x, inv_gamma), {});\n}}\n", lit(1.0)?).ok();
    }
    Ok(o)
}

/// `text` with anything but printable ASCII replaced by `?`, for comments.
fn ascii(text: &str) -> String {
    text.chars()
        .map(|c| {
            if c.is_ascii() && !c.is_ascii_control() {
                c
            } else {
                '?'
            }
        })
        .collect()
}

/// The snippet for `lang` of `scene` resolved against `d`: the scene's model baked, then
/// formatted (the build bakes the model once, for every target).
pub fn snippet(d: &Derivation, scene: &Resolved, lang: Language) -> Result<String, Error> {
    snippet_of(&Model::bake(d, &[], scene)?, lang)
}

/// The snippet for `lang`: the scene's colour sets (wavelengths, AC1C2 weights, folded
/// weights for each display) and its displays' encodings, in ASCII. Errors on a value no
/// literal of `lang` reproduces, or a set or display name that is not ASCII.
pub(crate) fn snippet_of(m: &Model, lang: Language) -> Result<String, Error> {
    let mut o = String::new();
    let v3 = lang.vec3_type();
    writeln!(
        o,
        "// spectral-quadrature tables for scene `{}` ({}).\n// @generated by build.rs (spectral-quadrature-generator, emit/shader.rs) from the values of the crate's Rust tables: do not edit.\n",
        ascii(&m.provenance.scene),
        ascii(&m.provenance.settings)
    )
    .ok();
    o.push_str(&helpers(lang, m)?);
    for display in &m.displays {
        let name = display.name.to_ascii_lowercase();
        let curve = |c: &str| -> Result<String, Error> {
            Ok(match display.transfer {
                Transfer::Linear => std::format!("sq_clip01(rgb.{c})"),
                Transfer::Srgb => std::format!("sq_srgb_curve(rgb.{c})"),
                Transfer::Gamma { gamma, .. } => {
                    // The runtime stores γ as f32 and raises to 1 / γ in f64.
                    let inv = 1.0 / f64::from(gamma);
                    std::format!("sq_power_curve(rgb.{c}, {})", lang.float(inv)?)
                }
            })
        };
        let transfer = match display.transfer {
            Transfer::Linear => "linear".into(),
            Transfer::Srgb => "the sRGB curve".into(),
            Transfer::Gamma { given, .. } => std::format!("gamma {given}"),
        };
        writeln!(
            o,
            "// {}: linear RGB clipped to 0..=1, then {transfer} (Display::encode with GamutMapping::Clip).",
            display.name
        )
        .ok();
        o.push_str(&lang.function(
            &std::format!("{name}_encode"),
            &[(std::format!("rgb: {v3}"), "vec3 rgb".into())],
            v3,
        ));
        writeln!(
            o,
            "    return {v3}({}, {}, {});\n}}\n",
            curve("x")?,
            curve("y")?,
            curve("z")?
        )
        .ok();
    }
    for (s, set) in m.colour_sets.iter().enumerate() {
        let n = set.len();
        let name = &set.name;
        let lower = name.to_ascii_lowercase();
        let arg = samples_arg(n);
        match &set.samples {
            Samples::Readings { sensor, .. } => writeln!(
                o,
                "// {name}: the readings of sensor {}'s {n} channels, in their order ({name}_WL holds each channel's peak, not wavelengths to sample at).",
                ascii(sensor)
            ),
            _ => writeln!(
                o,
                "// {name}: {n} wavelengths. Sample the spectrum at {name}_WL, in that order."
            ),
        }
        .ok();
        let wl: Result<Vec<String>, Error> = set
            .wavelengths_nm
            .iter()
            .map(|&v| lang.float(f64::from(v)))
            .collect();
        o.push_str(&lang.const_array(&std::format!("{name}_WL"), lang.scalar(), &wl?));
        writeln!(
            o,
            "// {name}'s weights for [A, C1, C2], one vector per wavelength (for integrals over wavelength in nm)."
        )
        .ok();
        o.push_str(&lang.const_array(
            &std::format!("{name}_AC1C2"),
            v3,
            &columns(lang, &set.weights)?,
        ));
        writeln!(
            o,
            "// [A, C1, C2] of samples at {name}_WL (WavelengthSet::ac1c2)."
        )
        .ok();
        o.push_str(&lang.function(
            &std::format!("{lower}_ac1c2"),
            core::slice::from_ref(&arg),
            v3,
        ));
        o.push_str(&product_body(lang, &std::format!("{name}_AC1C2"), n));
        o.push('\n');
        for f in m.folded.iter().filter(|f| f.set == s) {
            let display = &m.displays[f.display].name;
            let folded = m.folded_name(f);
            writeln!(
                o,
                "// {name} folded for {display}: linear RGB weights, one vector per wavelength; a spectrum of constant 1 has Y = 1."
            )
            .ok();
            o.push_str(&lang.const_array(&folded, v3, &columns(lang, &f.weights)?));
            writeln!(
                o,
                "// Linear RGB for {display} of samples at {name}_WL (FoldedSet::linear_rgb)."
            )
            .ok();
            o.push_str(&lang.function(
                &std::format!("{}_linear", folded.to_ascii_lowercase()),
                core::slice::from_ref(&arg),
                v3,
            ));
            o.push_str(&product_body(lang, &folded, n));
            o.push('\n');
        }
    }
    for group in &m.groups {
        let name = &group.name;
        let n = group.wavelengths_nm.len();
        let l = group.lights.len();
        writeln!(
            o,
            "// {name}: a light group of {} sharing {n} wavelengths. Sample each light's path products at {name}_WL; pass light k's samples at s[k * {n} + i].",
            ascii(&group.lights.join(", "))
        )
        .ok();
        let wl: Result<Vec<String>, Error> = group
            .wavelengths_nm
            .iter()
            .map(|&v| lang.float(f64::from(v)))
            .collect();
        o.push_str(&lang.const_array(&std::format!("{name}_WL"), lang.scalar(), &wl?));
        for (display, members) in m.displays.iter().zip(&group.folded) {
            let folded = std::format!("{name}_{}", display.name);
            writeln!(
                o,
                "// {name} folded for {}: each light's linear RGB weights in turn, one vector per wavelength.",
                display.name
            )
            .ok();
            let mut columns_all = Vec::with_capacity(n * l);
            for weights in members {
                columns_all.extend(columns(lang, weights)?);
            }
            o.push_str(&lang.const_array(&folded, v3, &columns_all));
            writeln!(
                o,
                "// Linear RGB for {} of the light groups' samples (LightGroupSet::linear_rgb: each light's products summed in index order, the lights added in order).",
                display.name
            )
            .ok();
            o.push_str(&lang.function(
                &std::format!("{}_linear", folded.to_ascii_lowercase()),
                &[samples_arg(n * l)],
                v3,
            ));
            let mut b = lang.let_var("acc", &std::format!("{folded}[0] * s[0]"));
            for i in 1..n {
                writeln!(b, "    acc = acc + {folded}[{i}] * s[{i}];").ok();
            }
            for k in 1..l {
                let base = k * n;
                b.push_str(&lang.let_var(
                    &std::format!("light{k}"),
                    &std::format!("{folded}[{base}] * s[{base}]"),
                ));
                for i in 1..n {
                    writeln!(
                        b,
                        "    light{k} = light{k} + {folded}[{j}] * s[{j}];",
                        j = base + i
                    )
                    .ok();
                }
                writeln!(b, "    acc = acc + light{k};").ok();
            }
            b.push_str("    return acc;\n}\n");
            o.push_str(&b);
            o.push('\n');
        }
    }
    // Some GLSL compilers refuse anything but ASCII, even in comments.
    if !o.is_ascii() {
        return Err(Error::NotAscii {
            language: lang.name(),
        });
    }
    Ok(o)
}
