//! The `upsampling` module of `tables.rs`: one `Upsampling` const per set and display a scene
//! asks for ([`crate::upsampling`]), its table of 16-bit codes laid out as rustfmt would.

use std::string::{String, ToString};
use std::vec::Vec;

use super::layout::{self, lit, Expr};
use super::lists::{names_rs, Constant};
use super::model::{Model, Upsampling};

/// The const name of the upsampling of `set` for `display`: `<SET>_<DISPLAY>`.
pub(crate) fn const_name(set: &str, display: &str) -> String {
    std::format!("{set}_{display}")
}

/// The module's source, each upsampling registered in `consts` with its table and edge cells
/// (two bytes a code, four an edge cells' word), or an empty string when the scene asks for no
/// upsampling. Each is made by `Upsampling::new` and given its measured figures by
/// `with_measured`, both checked.
pub(crate) fn upsampling_rs(m: &Model, consts: &mut Vec<Constant>) -> String {
    if m.upsamplings.is_empty() {
        return String::new();
    }
    let mut o = String::new();
    let mut names = Vec::new();
    o.push_str(&layout::comment(
        0,
        "///",
        "RGB materials: each upsampling maps the display's linear RGB, white-balanced under the set's reference light, to the set's node reflectances in [0, 1] (see `docs/upsampling.md`). Named `<SET>_<DISPLAY>`.",
        0,
    ));
    o.push_str(
        "pub mod upsampling {\n    use super::checked;\n    use crate::{RoundTrip, Upsampling};\n\n",
    );
    o.push_str(&layout::comment(
        4,
        "///",
        "An upsampling from its checked constructor, given the figures the build measured of it (`[lipschitz, max_round_trip_delta_e00, reachable_share]`), checked too.",
        0,
    ));
    o.push_str("    const fn measured<const N: usize>(\n        made: Result<Upsampling<N>, crate::Error>,\n        figures: [f32; 3],\n    ) -> Upsampling<N> {\n        checked(checked(made).with_measured(figures[0], figures[1], figures[2]))\n    }\n\n");
    for u in &m.upsamplings {
        let n = u.n;
        let rows: Vec<Expr> = u
            .codes
            .iter()
            .map(|c| Expr::Array(c.iter().map(|v| Expr::atom(v.to_string())).collect()))
            .collect();
        let rows_f32 = |m: &[Vec<f32>]| -> Expr {
            Expr::Array(
                m.iter()
                    .map(|row| Expr::Array(row.iter().map(|&x| Expr::Atom(lit(x))).collect()))
                    .collect(),
            )
        };
        let to_xyz: Vec<Vec<f32>> = u.rgb_to_xyz.iter().map(|r| r.to_vec()).collect();
        let round_trip = Expr::Call(
            "Some".into(),
            std::vec![Expr::Call(
                "RoundTrip::new".into(),
                std::vec![
                    rows_f32(&u.encoding),
                    rows_f32(&to_xyz),
                    Expr::Array(
                        u.edge_cells
                            .iter()
                            .map(|w| Expr::atom(std::format!("0x{w:08x}")))
                            .collect()
                    )
                    .by_ref(),
                ],
            )],
        );
        // The folded set of the same name (`folded_rs` bakes every colour set for every
        // display): the display, the nodes and the reference light are the set's.
        let folded = Expr::atom(std::format!(
            "super::folded::{}",
            const_name(&u.set, &u.display)
        ));
        let value = Expr::Call(
            "measured".into(),
            std::vec![
                Expr::Call(
                    "Upsampling::new".into(),
                    std::vec![
                        folded,
                        Expr::atom(u.grid.to_string()),
                        Expr::Array(rows).by_ref(),
                        round_trip,
                    ],
                ),
                Expr::Array(u.figures.iter().map(|&x| Expr::Atom(lit(x))).collect()),
            ],
        );
        let doc = std::format!(
            "[`{set}`](super::{set}) for [`{disp}`](super::displays::{disp}): linear {label} RGB white-balanced under {light} → {n} node reflectances, a {g}×{g}×{g} grid ({bytes} bytes); {share:.1} % of the grid reachable; Lipschitz {lip:.3}; round trip within {rt:.4} ΔE00 at the reachable grid points.",
            set = u.set,
            disp = u.display,
            label = u.display_label,
            light = u.light,
            g = u.grid,
            bytes = 2 * n * u.codes.len(),
            share = 100.0 * u.measured.reachable_share,
            lip = u.measured.lipschitz,
            rt = u.measured.max_round_trip_de00,
        );
        o.push_str(&layout::comment(4, "///", &doc, 0));
        let name = u.name();
        o.push_str(&layout::item(
            4,
            &std::format!("pub const {name}: Upsampling<{n}> ="),
            &value,
        ));
        o.push('\n');
        consts.push(
            Constant::new(
                std::format!("upsampling::{name}"),
                std::format!("crate::Upsampling<{n}>"),
            )
            .with_slices(2 * n * u.codes.len() + 4 * u.edge_cells.len()),
        );
        names.push(name.clone());
        for (lang, ext, decl, where_) in [
            (
                "WGSL",
                "wgsl",
                std::format!("@group(G) @binding(B) var<storage, read> {name}_CODES: array<u32>;"),
                "",
            ),
            (
                "GLSL",
                "glsl",
                std::format!(
                    "layout(std430, binding = B) readonly buffer {name}_Buffer {{ uint {name}_CODES[]; }};"
                ),
                " before the functions (GLSL 4.30 or ES 3.10)",
            ),
        ] {
            let doc = std::format!(
                "[`{name}`]'s `{lower}_reflectance(rgb)` in {lang}: [`Upsampling::reflectance`] (and `{lower}_interpolate(rgb)`: [`Upsampling::interpolate`]). The shader declares the table, `{decl}`{where_}, and the application fills it with [`Upsampling::shader_words`] (see `docs/shaders.md`).",
                lower = name.to_ascii_lowercase(),
            );
            o.push_str(&layout::comment(4, "///", &doc, 0));
            // As rustfmt lays it out: the call on the next line where its argument fits in
            // rustfmt's `fn_call_width` (60 columns), else that argument's own arguments one
            // per line.
            let file = shader_file(&u.set, &u.display, ext);
            let arg = std::format!("concat!(env!(\"OUT_DIR\"), \"/{file}\")");
            if arg.len() <= 60 {
                let call = std::format!("include_str!({arg});");
                o.push_str(&std::format!(
                    "    pub const {name}_{lang}: &str =\n        {call}\n"
                ));
            } else {
                o.push_str(&std::format!(
                    "    pub const {name}_{lang}: &str = include_str!(concat!(\n        env!(\"OUT_DIR\"),\n        \"/{file}\"\n    ));\n"
                ));
            }
        }
    }
    o.push_str(&names_rs("upsampling", "upsampling", &names));
    o.push_str("}\n\n");
    o
}

/// The file in `OUT_DIR` that holds the shader source of the upsampling of `set` for `display`
/// in the language whose extension is `ext` (`wgsl`, `glsl`): `tables.rs` includes it.
pub(crate) fn shader_file(set: &str, display: &str, ext: &str) -> String {
    std::format!(
        "upsampling_{}.{ext}",
        const_name(set, display).to_ascii_lowercase()
    )
}

/// The scene's upsamplings' shader files: name in `OUT_DIR` ([`shader_file`]) and text, WGSL
/// then GLSL for each.
pub(crate) fn shader_files(m: &Model) -> Vec<(String, String)> {
    let mut files = Vec::new();
    for u in &m.upsamplings {
        for (ext, wgsl) in [("wgsl", true), ("glsl", false)] {
            files.push((
                shader_file(&u.set, &u.display, ext),
                shader_snippet(u, wgsl),
            ));
        }
    }
    files
}

/// The shader source of one upsampling `<SET>_<DISPLAY>`: the functions
/// `<set>_<display>_interpolate(rgb)` and `<set>_<display>_reflectance(rgb)`, the runtime's
/// `Upsampling::interpolate` and `reflectance` with their f32 operations in the same order,
/// reading the table (two codes to a word, low half first) and the round trip's data (the edge
/// cells' bits, then the weights, RGB → XYZ and the rounding as f32 bits) from
/// `<SET>_<DISPLAY>_CODES`, a storage buffer of `u32` the shader declares and the application
/// fills with `Upsampling::shader_words`. `wgsl`: WGSL, else GLSL.
pub(crate) fn shader_snippet(u: &Upsampling, wgsl: bool) -> String {
    // Rust's shortest round-trip form of the f32 ("8.0", "1.5259022e-5"): a float literal in
    // WGSL and GLSL alike.
    let float = |v: f64| std::format!("{:?}", v as f32);
    let mut o = String::new();
    {
        let name = u.name();
        let lower = name.to_ascii_lowercase();
        let n = u.n;
        let g = u.grid;
        let (uint, float_t, vec3) = if wgsl {
            ("u32", "f32", "vec3<f32>")
        } else {
            ("uint", "float", "vec3")
        };
        o.push_str(&std::format!(
            "// {name}: linear RGB (white-balanced under {}) -> {n} node reflectances in [0, 1] (Upsampling::interpolate): a {g}x{g}x{g} grid of 16-bit codes, two to a word, read from {name}_CODES from word 0.\n",
            u.light
        ));
        let (zero, one) = (float(0.0), float(1.0));
        let cells = float((g - 1) as f64);
        // The runtime's scale, 1 / 65535 rounded to f32 by an f32 division.
        let scale = float(f64::from(1.0f32 / 65535.0f32));
        let clamp = |c: &str| std::format!("select({zero}, min(rgb.{c}, {one}), rgb.{c} > {zero})");
        let clamp_glsl =
            |c: &str| std::format!("(rgb.{c} > {zero} ? min(rgb.{c}, {one}) : {zero})");
        let c3 =
            |f: &dyn Fn(&str) -> String| std::format!("{vec3}({}, {}, {})", f("x"), f("y"), f("z"));
        let v = if wgsl { c3(&clamp) } else { c3(&clamp_glsl) };
        let (decl, uvec3, let_) = if wgsl {
            (
                std::format!("fn {lower}_interpolate(rgb: vec3<f32>) -> array<f32, {n}> {{\n"),
                "vec3<u32>",
                "let",
            )
        } else {
            (
                std::format!("float[{n}] {lower}_interpolate(vec3 rgb) {{\n"),
                "uvec3",
                "",
            )
        };
        let lets = |name: &str, ty: &str, value: &str| {
            if wgsl {
                std::format!("    {let_} {name} = {value};\n")
            } else {
                std::format!("    {ty} {name} = {value};\n")
            }
        };
        o.push_str(&decl);
        o.push_str(
            "    // Each channel clamped to [0, 1] (NaN to 0), its cell and the position in it.\n",
        );
        o.push_str(&lets("x", vec3, &std::format!("{v} * {cells}")));
        o.push_str(&lets(
            "cell",
            uvec3,
            &std::format!("min({uvec3}(x), {uvec3}({}u))", g - 2),
        ));
        o.push_str(&lets("f", vec3, &std::format!("x - {vec3}(cell)")));
        o.push_str(
            "    // The tetrahedron: the axes in decreasing order of f (strides of r, g, b).\n",
        );
        let (sr, sg, sb) = (g * g, g, 1);
        let var = |name: &str, ty: &str| {
            if wgsl {
                std::format!("    var {name}: {ty};\n")
            } else {
                std::format!("    {ty} {name};\n")
            }
        };
        o.push_str(&var("s", uvec3));
        o.push_str(&var("fs", vec3));
        let branch = |a: usize, b: usize, c: usize| {
            let stride = [sr, sg, sb];
            let comp = ["x", "y", "z"];
            std::format!(
                "s = {uvec3}({}u, {}u, {}u); fs = {vec3}(f.{}, f.{}, f.{});",
                stride[a],
                stride[b],
                stride[c],
                comp[a],
                comp[b],
                comp[c]
            )
        };
        o.push_str(&std::format!(
            "    if (f.x >= f.y) {{\n        if (f.y >= f.z) {{ {} }} else if (f.x >= f.z) {{ {} }} else {{ {} }}\n    }} else if (f.x >= f.z) {{ {} }} else if (f.y >= f.z) {{ {} }} else {{ {} }}\n",
            branch(0, 1, 2),
            branch(0, 2, 1),
            branch(2, 0, 1),
            branch(1, 0, 2),
            branch(1, 2, 0),
            branch(2, 1, 0)
        ));
        o.push_str(&lets(
            "i0",
            uint,
            &std::format!("((cell.x * {g}u + cell.y) * {g}u + cell.z) * {n}u"),
        ));
        o.push_str(&lets("i1", uint, &std::format!("i0 + s.x * {n}u")));
        o.push_str(&lets("i2", uint, &std::format!("i1 + s.y * {n}u")));
        o.push_str(&lets("i3", uint, &std::format!("i2 + s.z * {n}u")));
        o.push_str(&lets("w0", float_t, &std::format!("{one} - fs.x")));
        o.push_str(&lets("w1", float_t, "fs.x - fs.y"));
        o.push_str(&lets("w2", float_t, "fs.y - fs.z"));
        o.push_str(&lets("w3", float_t, "fs.z"));
        o.push_str(&var(
            "nodes",
            &if wgsl {
                std::format!("array<f32, {n}>")
            } else {
                std::format!("float[{n}]")
            },
        ));
        let code = |idx: &str| {
            std::format!(
                "{float_t}(({name}_CODES[({idx} + k) >> 1u] >> ((({idx} + k) & 1u) * 16u)) & 0xffffu)"
            )
        };
        let loop_head = if wgsl {
            std::format!("    for (var k = 0u; k < {n}u; k = k + 1u) {{\n")
        } else {
            std::format!("    for (uint k = 0u; k < {n}u; k++) {{\n")
        };
        o.push_str(&loop_head);
        o.push_str(&std::format!(
            "        {}acc = w0 * {} + w1 * {} + w2 * {} + w3 * {};\n",
            if wgsl { "let " } else { "float " },
            code("i0"),
            code("i1"),
            code("i2"),
            code("i3")
        ));
        o.push_str(&std::format!(
            "        nodes[k] = clamp(acc * {scale}, {zero}, {one});\n    }}\n    return nodes;\n}}\n\n"
        ));
        // The round-trip correction: the runtime's `RoundTrip::correct` step for step, its
        // constants (`src/upsample/round_trip.rs`) as the same f32 values.
        let template = if wgsl {
            include_str!("upsampling_round_trip.wgsl")
        } else {
            include_str!("upsampling_round_trip.glsl")
        };
        let codes = (g * g * g * n).div_ceil(2);
        let edge_words = u.edge_cells.len();
        let f = |x: f32| std::format!("{x:?}");
        let d = 6.0f32 / 29.0;
        let text = template
            .replace("@NAME@", &name)
            .replace("@lower@", &lower)
            .replace("@N@", &n.to_string())
            .replace("@NF@", &f(n as f32))
            .replace("@E@", &codes.to_string())
            .replace("@F@", &(codes + edge_words).to_string())
            .replace("@XYZ@", &(3 * n).to_string())
            .replace("@ROUND@", &(3 * n + 9).to_string())
            .replace("@STEPS@", &(3 * n + 3).to_string())
            .replace("@KEEP@", &f(1.5))
            .replace("@FULL@", &f(3.0))
            .replace("@MU@", &f(1.0e6))
            .replace("@ISQMU@", &f((1.0f32 / 1.0e6).sqrt()))
            .replace("@TRIAL@", &f(1.0 / 1024.0))
            .replace("@D3@", &f(d * d * d))
            .replace("@LIN@", &f(1.0 / (3.0 * d * d)))
            .replace("@THIRD@", &f(1.0 / 3.0))
            .replace("@CLAMP@", &v)
            .replace("@CELLS@", &cells)
            .replace("@G2@", &(g - 2).to_string())
            .replace("@G1@", &(g - 1).to_string());
        o.push_str(&text);
    }
    o
}
