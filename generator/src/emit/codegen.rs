//! Writes the runtime's `tables.rs` from a scene's [`Model`]: `const` items with doc comments
//! and a header naming the inputs and their checksums (no timestamp, so the output only changes
//! when an input does). The model holds every value as the runtime's f32 (`as f32` of the
//! derivation's f64), printed here with Rust's shortest round-trip formatting, so the baked
//! constant is exactly that f32. The items are laid out as rustfmt lays them out, at most 100
//! columns wide (`layout`), so that a person can read what a scene bakes.

use std::fmt::Write as _;
use std::string::{String, ToString};
use std::vec::Vec;

use super::layout::{self, f32s, lit, Expr};
use super::lists::{all_tables_rs, names_rs, Constant};
use super::model::{Model, Rule, Samples, Set, Transfer, CHANNEL_NAMES};
use super::transfer_tables::gamma_encoders_rs;

fn matrix(m: &[[f32; 3]; 3]) -> Expr {
    Expr::Array(m.iter().map(|r| f32s(r)).collect())
}

/// A `const` or `static` item with its doc comment, at block indent `indent`.
fn item(o: &mut String, indent: usize, doc: &str, lhs: &str, value: &Expr) {
    o.push_str(&layout::comment(indent, "///", doc, 0));
    o.push_str(&layout::item(indent, lhs, value));
    o.push('\n');
}

/// `checked(made)`: a checked constructor's `Result`, unwrapped in constant evaluation (the
/// generated file's `checked`, which stops the build with the refusal's sentence).
pub(crate) fn checked(made: Expr) -> Expr {
    Expr::Call("checked".into(), std::vec![made])
}

fn set_literal(set: &Set) -> Expr {
    checked(Expr::Call(
        "WavelengthSet::new".into(),
        std::vec![
            f32s(&set.wavelengths_nm),
            weights(&set.weights),
            samples_literal(&set.samples),
        ],
    ))
}

fn weights(w: &[Vec<f32>; 3]) -> Expr {
    Expr::Array(w.iter().map(|r| f32s(r)).collect())
}

/// The runtime's `Samples` value.
fn samples_literal(samples: &Samples) -> Expr {
    match samples {
        Samples::Readings { sensor, light } => Expr::Struct(
            "Samples::Readings".into(),
            std::vec![
                ("sensor".into(), quoted(sensor)),
                (
                    "light".into(),
                    Expr::atom(match light {
                        Some(l) => std::format!("Some({l:?})"),
                        None => "None".into(),
                    }),
                ),
            ],
        ),
        Samples::Reflectance { light } => Expr::Struct(
            "Samples::Reflectance".into(),
            std::vec![("light".into(), quoted(light))],
        ),
        Samples::Radiance => Expr::atom("Samples::Radiance"),
    }
}

fn rule_literal(channel: usize, rule: &Rule) -> Expr {
    checked(Expr::Call(
        "GaussRule::new".into(),
        std::vec![
            Expr::atom(std::format!("Channel::{}", CHANNEL_NAMES[channel])),
            Expr::atom(rule.order.to_string()),
            Expr::atom(std::format!("RuleStatus::{}", rule.status)),
            f32s(&rule.nodes_nm).by_ref(),
            f32s(&rule.weights).by_ref(),
        ],
    ))
}

/// The generated Rust source for a scene's model. It is laid out as rustfmt lays it out: at most
/// 100 columns, one array item a line, or short numbers filling their lines. Each section has its
/// emitter below (or in its own module), in the order the file holds them.
pub(crate) fn tables_rs(m: &Model) -> String {
    let mut t = Tables::default();
    provenance_rs(&mut t, m);
    opponent_rs(&mut t, m);
    if let Some(locus) = &m.locus {
        t.o.push_str(&super::planckian::planckian_rs(locus, &mut t.consts));
        writeln!(t.o).ok();
    }
    sensitivities_rs(&mut t, m);
    rules_rs(&mut t, m);
    rule_sets_rs(&mut t, m);
    colour_sets_rs(&mut t, m);
    displays_rs(&mut t, m);
    folded_rs(&mut t, m);
    groups_rs(&mut t, m);
    lights_rs(&mut t, m);
    t.o.push_str(&super::upsampling::upsampling_rs(m, &mut t.consts));
    t.o.push_str(&super::sensors::sensors_rs(&m.sensors, &mut t.consts));
    t.o.push_str(&super::fixed_point::integer_rs(m, &mut t.consts));
    // Declared in every scene, empty where no display has a power law.
    t.baked(
        "GAMMA_ENCODERS",
        std::format!("[crate::encode::GammaEncoder8; {}]", m.gamma_encoders.len()),
    );
    t.o.push_str(&all_tables_rs(&t.consts));
    t.o.push_str(&gamma_encoders_rs(&m.gamma_encoders));
    t.o
}

/// The text written so far and every constant of numbers it bakes (for `ALL_TABLES`).
#[derive(Default)]
struct Tables {
    o: String,
    consts: Vec<Constant>,
}

impl Tables {
    /// A constant of numbers of type `ty` at `path` in `tables`, written: one entry of
    /// `ALL_TABLES`.
    fn baked(&mut self, path: impl Into<String>, ty: impl Into<String>) {
        self.consts.push(Constant::new(path, ty));
    }
}

/// A quoted string literal.
fn quoted(s: &str) -> Expr {
    Expr::atom(std::format!("{s:?}"))
}

/// The file's leading comment, the imports, and the provenance consts: `SCENE`, `OBSERVER`,
/// `SETTINGS`, `HEADER` and `INPUTS`.
fn provenance_rs(t: &mut Tables, m: &Model) {
    let o = &mut t.o;
    let p = &m.provenance;
    o.push_str(&layout::comment(0, "//", p.header.trim_end(), 4));
    writeln!(o).ok();
    writeln!(
        o,
        "#[allow(unused_imports)]\nuse crate::{{Channel, GaussRule, RuleStatus, Samples, WavelengthSet}};\n"
    )
    .ok();
    o.push_str(&layout::comment(
        0,
        "///",
        "A baked constant from its checked constructor: the value, or, where the constructor refuses it, a compile-time error with the refusal's sentence ([`Error::summary`](crate::Error::summary)). Every constant below that a type of the crate holds is made so.",
        0,
    ));
    o.push_str("#[allow(dead_code)]\nconst fn checked<T: Copy>(made: Result<T, crate::Error>) -> T {\n    match made {\n        Ok(value) => value,\n        Err(e) => panic!(\"{}\", e.summary()),\n    }\n}\n\n");
    item(
        o,
        0,
        "The scene these tables were baked for (`default`, or the file named by `SPECTRAL_QUADRATURE_SCENE`).",
        "pub const SCENE: &str =",
        &quoted(&p.scene),
    );
    item(
        o,
        0,
        "The observer the tables were derived from.",
        "pub const OBSERVER: &str =",
        &quoted(&p.observer),
    );
    item(
        o,
        0,
        "The derivation's settings, as one line.",
        "pub const SETTINGS: &str =",
        &quoted(&p.settings),
    );
    let header_lhs = "pub const HEADER: &str =";
    item(
        o,
        0,
        "The header of the generated tables: the generator, the settings, the scene, and every input file with its SHA-256 (the provenance a firmware can log at start-up).",
        header_lhs,
        &Expr::atom(layout::string_literal(&p.header, header_lhs.len() + 1)),
    );
    let inputs_lit: Vec<Expr> = p
        .inputs
        .iter()
        .map(|(f, h)| Expr::Tuple(std::vec![quoted(f), quoted(h)]))
        .collect();
    item(
        o,
        0,
        "The input files (relative to the crate root, or as the scene names them) and their SHA-256 checksums: the observer, the scene and any file it names, and every data file a baked set was made from (a shared set's training reflectances, light and node cache).",
        "pub const INPUTS: &[(&str, &str)] =",
        &Expr::Array(inputs_lit).by_ref(),
    );
}

/// The range, the grid step, the AC1C2 matrices (Eq. 9), the eigenvalues (Eq. 10) and the unit
/// spectrum's Y.
fn opponent_rs(t: &mut Tables, m: &Model) {
    let o = &mut t.o;
    let p = &m.opponent;
    item(
        o,
        0,
        "The spectrum's limits in nm (Eq. 2).",
        "pub const RANGE_NM: [f32; 2] =",
        &f32s(&p.range_nm),
    );
    item(
        o,
        0,
        "The grid step in nm: weights are for dλ in nm.",
        "pub const STEP_NM: f32 =",
        &Expr::Atom(lit(p.step_nm)),
    );
    item(
        o,
        0,
        "Eq. 9: `[A, C1, C2] = XYZ_TO_AC1C2 · [X, Y, Z]` (rows scaled to unit peak sensitivity).",
        "pub const XYZ_TO_AC1C2: [[f32; 3]; 3] =",
        &matrix(&p.xyz_to_ac1c2),
    );
    item(
        o,
        0,
        "The inverse of [`XYZ_TO_AC1C2`]: `[X, Y, Z] = AC1C2_TO_XYZ · [A, C1, C2]`.",
        "pub const AC1C2_TO_XYZ: [[f32; 3]; 3] =",
        &matrix(&p.ac1c2_to_xyz),
    );
    item(
        o,
        0,
        "Eq. 10: eigenvalues of the covariance matrix of Eq. 4 for A, C1, C2 (largest first).",
        "pub const EIGENVALUES: [f32; 3] =",
        &f32s(&p.eigenvalues),
    );
    item(
        o,
        0,
        "∫ ȳ dλ over the grid (dλ in nm): the luminance Y of a spectrum of constant 1 with these weights' units. The folded sets divide by it.",
        "pub const UNIT_SPECTRUM_Y: f32 =",
        &Expr::Atom(lit(p.unit_spectrum_y)),
    );
    writeln!(o).ok();
    for (path, ty) in [
        ("RANGE_NM", "[f32; 2]"),
        ("STEP_NM", "f32"),
        ("XYZ_TO_AC1C2", "[[f32; 3]; 3]"),
        ("AC1C2_TO_XYZ", "[[f32; 3]; 3]"),
        ("EIGENVALUES", "[f32; 3]"),
        ("UNIT_SPECTRUM_Y", "f32"),
    ] {
        t.baked(path, ty);
    }
}

/// The `sensitivities` extra: the grid and the opponent sensitivities on it (Fig. 4).
fn sensitivities_rs(t: &mut Tables, m: &Model) {
    let Some(s) = &m.sensitivities else {
        return;
    };
    let o = &mut t.o;
    let n_grid = s.grid_nm.len();
    item(
        o,
        0,
        "The number of grid wavelengths.",
        "pub const GRID_LEN: usize =",
        &Expr::atom(n_grid.to_string()),
    );
    item(
        o,
        0,
        "The grid wavelengths in nm.",
        "pub const GRID_NM: [f32; GRID_LEN] =",
        &f32s(&s.grid_nm),
    );
    item(
        o,
        0,
        "The opponent sensitivities `[ā, c̄1, c̄2]` at each grid wavelength (Fig. 4).",
        "pub const SENSITIVITIES: [[f32; 3]; GRID_LEN] =",
        &Expr::Array(s.rows.iter().map(|r| f32s(r)).collect()),
    );
    writeln!(o).ok();
    t.baked("GRID_NM", "[f32; GRID_LEN]");
    t.baked("SENSITIVITIES", "[[f32; 3]; GRID_LEN]");
}

/// The `rules` extra: every channel's Gauss rules as `GaussRule`s, defined or not.
fn rules_rs(t: &mut Tables, m: &Model) {
    let Some(rules) = &m.rules else {
        return;
    };
    let o = &mut t.o;
    item(
        o,
        0,
        "Rules were formed for orders 1..=MAX_ORDER in each channel.",
        "pub const MAX_ORDER: usize =",
        &Expr::atom(rules.max_order.to_string()),
    );
    for (c, name) in CHANNEL_NAMES.iter().enumerate() {
        let items = rules.channels[c]
            .iter()
            .map(|r| rule_literal(c, r))
            .collect();
        item(
            o,
            0,
            &std::format!("Channel {name}'s Gauss rules, `{name}_RULES[n - 1]` of order n: nodes and weights, or why the order is undefined."),
            &std::format!("pub const {name}_RULES: [GaussRule; MAX_ORDER] ="),
            &Expr::Array(items),
        );
        // Each defined rule's nodes and weights: two slices of `order` f32.
        let floats: usize = rules.channels[c]
            .iter()
            .map(|r| r.nodes_nm.len() + r.weights.len())
            .sum();
        t.consts.push(
            Constant::new(std::format!("{name}_RULES"), "[GaussRule; MAX_ORDER]")
                .with_slices(4 * floats),
        );
    }
    item(
        o,
        0,
        "All rules, indexed `[channel][order - 1]` with channels A, C1, C2.",
        "pub const RULES: [[GaussRule; MAX_ORDER]; 3] =",
        &Expr::Array(std::vec![
            Expr::atom("A_RULES"),
            Expr::atom("C1_RULES"),
            Expr::atom("C2_RULES")
        ]),
    );
    writeln!(o).ok();
    // `RULES` holds the three channels' rules, and so points to their slices too.
    let floats: usize = rules
        .channels
        .iter()
        .flatten()
        .map(|r| r.nodes_nm.len() + r.weights.len())
        .sum();
    t.consts
        .push(Constant::new("RULES", "[[GaussRule; MAX_ORDER]; 3]").with_slices(4 * floats));
}

/// `pub mod rules`: the scene's per-channel rules as wavelength sets.
fn rule_sets_rs(t: &mut Tables, m: &Model) {
    if m.rule_sets.is_empty() {
        return;
    }
    let o = &mut t.o;
    o.push_str(&layout::comment(0, "///", "Per-channel Gauss rules as [`WavelengthSet`]s (the other two rows zero), named `<channel>_<order>`.", 0));
    writeln!(
        o,
        "pub mod rules {{\n    use super::checked;\n    use crate::{{Samples, WavelengthSet}};"
    )
    .ok();
    for set in &m.rule_sets {
        item(
            o,
            4,
            &set.doc,
            &std::format!("pub const {}: WavelengthSet<{}> =", set.name, set.len()),
            &set_literal(set),
        );
        t.consts.push(Constant::new(
            std::format!("rules::{}", set.name),
            std::format!("WavelengthSet<{}>", set.len()),
        ));
    }
    writeln!(o, "}}\n").ok();
}

/// The scene's colour sets, at the top level.
fn colour_sets_rs(t: &mut Tables, m: &Model) {
    for set in &m.colour_sets {
        item(
            &mut t.o,
            0,
            &set.doc,
            &std::format!("pub const {}: WavelengthSet<{}> =", set.name, set.len()),
            &set_literal(set),
        );
        t.baked(&set.name, std::format!("WavelengthSet<{}>", set.len()));
    }
    if !m.colour_sets.is_empty() {
        let names: Vec<String> = m.colour_sets.iter().map(|s| s.name.clone()).collect();
        writeln!(t.o).ok();
        t.o.push_str(&layout::comment(0, "///", "The colour sets above, at the top of `tables`, re-exported here with their list: `sets::<SET>` is `<SET>`.", 0));
        writeln!(t.o, "pub mod sets {{").ok();
        // One `use` a set, in rustfmt's order: byte order, the names being upper snake case.
        let mut sorted = names.clone();
        sorted.sort();
        for n in &sorted {
            writeln!(t.o, "    pub use super::{n};").ok();
        }
        writeln!(t.o).ok();
        t.o.push_str(&names_rs("sets", "colour set", &names));
        writeln!(t.o, "}}").ok();
    }
}

/// `pub mod displays`: each display's primaries, white, matrices and transfer, and `ALL`.
fn displays_rs(t: &mut Tables, m: &Model) {
    if m.displays.is_empty() {
        return;
    }
    let o = &mut t.o;
    // One blank line before the displays, also where the rule sets' module ends in one.
    if !o.ends_with("\n\n") {
        writeln!(o).ok();
    }
    o.push_str(&layout::comment(0, "///", "Displays: primaries, white and transfer function, with matrices derived in f64 (white at Y = 1).", 0));
    writeln!(
        o,
        "pub mod displays {{\n    use super::checked;\n    use crate::{{Display, TransferFunction}};"
    )
    .ok();
    let mut names = Vec::new();
    for d in &m.displays {
        let transfer = match d.transfer {
            Transfer::Linear => "TransferFunction::Linear".to_string(),
            Transfer::Srgb => "TransferFunction::Srgb".to_string(),
            Transfer::Gamma { gamma, .. } => {
                std::format!("TransferFunction::Gamma({})", lit(gamma))
            }
        };
        let display = checked(Expr::Call(
            "Display::from_matrices".into(),
            std::vec![
                quoted(&d.label),
                Expr::Array(d.primaries_xy.iter().map(|p| f32s(p)).collect()),
                f32s(&d.white_xy),
                matrix(&d.rgb_to_xyz),
                matrix(&d.xyz_to_rgb),
                f32s(&d.a_from_rgb),
                Expr::Atom(transfer),
            ],
        ));
        item(
            o,
            4,
            &std::format!(
                "{} White balance Y_r : Y_g : Y_b = {:.4} : {:.4} : {:.4}; matrix condition number {:.2}.",
                d.doc, d.luminance[0], d.luminance[1], d.luminance[2], d.condition
            ),
            &std::format!("pub const {}: Display =", d.name),
            &display,
        );
        t.consts.push(Constant::new(
            std::format!("displays::{}", d.name),
            "crate::Display",
        ));
        names.push(Expr::atom(d.name.clone()));
    }
    item(
        o,
        4,
        "Every display above.",
        &std::format!("pub const ALL: [Display; {}] =", names.len()),
        &Expr::Array(names),
    );
    t.consts.push(Constant::new(
        "displays::ALL",
        std::format!("[crate::Display; {}]", m.displays.len()),
    ));
    writeln!(o, "}}\n").ok();
}

/// `pub mod folded`: each colour set folded for each display, and their list (`lists`).
fn folded_rs(t: &mut Tables, m: &Model) {
    if m.folded.is_empty() {
        return;
    }
    let o = &mut t.o;
    o.push_str(&layout::comment(0, "///", "Each colour set folded for each display: samples → linear RGB in one 3×N product, a spectrum of constant 1 at Y = 1. Named `<SET>_<DISPLAY>`.", 0));
    writeln!(
        o,
        "pub mod folded {{\n    use super::checked;\n    use crate::{{FoldedSet, Samples}};"
    )
    .ok();
    let mut names = Vec::new();
    for f in &m.folded {
        let set = &m.colour_sets[f.set];
        let display = &m.displays[f.display].name;
        let folded = checked(Expr::Call(
            "FoldedSet::new".into(),
            std::vec![
                f32s(&set.wavelengths_nm),
                weights(&f.weights),
                samples_literal(&set.samples),
                Expr::atom(std::format!("super::displays::{display}")),
            ],
        ));
        item(
            o,
            4,
            &std::format!(
                "[`{}`](super::{}) folded for [`{display}`](super::displays::{display}).",
                set.name,
                set.name,
            ),
            &std::format!(
                "pub const {}_{display}: FoldedSet<{}> =",
                set.name,
                set.len()
            ),
            &folded,
        );
        t.consts.push(Constant::new(
            std::format!("folded::{}", m.folded_name(f)),
            std::format!("crate::FoldedSet<{}>", set.len()),
        ));
        names.push(m.folded_name(f));
    }
    o.push_str(&names_rs("folded", "folded set", &names));
    writeln!(o, "}}\n").ok();
}

/// `pub mod groups`: each light group folded for each display, and their list (`lists`).
fn groups_rs(t: &mut Tables, m: &Model) {
    if m.groups.is_empty() || m.displays.is_empty() {
        return;
    }
    let o = &mut t.o;
    o.push_str(&layout::comment(0, "///", "Each light group folded for each display: one node set shared by several lights, a weight matrix per light (samples: the reflectance products a path carries from that light; the light is in its weights), summed into linear RGB, a reflectance of 1 under every light at Y = 1 per light. Named `<GROUP>_<DISPLAY>`.", 0));
    writeln!(
        o,
        "pub mod groups {{\n    use super::checked;\n    use crate::LightGroupSet;"
    )
    .ok();
    let mut names = Vec::new();
    for group in &m.groups {
        let name = &group.name;
        let n = group.wavelengths_nm.len();
        let lights = &group.lights;
        for (display, members) in m.displays.iter().zip(&group.folded) {
            let value = checked(Expr::Call(
                "LightGroupSet::new".into(),
                std::vec![
                    f32s(&group.wavelengths_nm),
                    Expr::Array(members.iter().map(weights).collect()),
                    Expr::Array(lights.iter().map(|l| quoted(l)).collect()),
                    Expr::atom(std::format!("super::displays::{}", display.name)),
                ],
            ));
            item(
                o,
                4,
                &std::format!(
                    "Light group of {} sharing {n} wavelengths (nodes searched for the {} ratio to each light's own folded set; each light's weights fitted by least squares on the crate's reflectances{}, white pinned), folded for [`{}`](super::displays::{}). Accumulators in this order.",
                    lights.join(", "),
                    group.objective,
                    if group.bounces {
                        " and their bounce forms"
                    } else {
                        ""
                    },
                    display.name,
                    display.name
                ),
                &std::format!(
                    "pub const {name}_{}: LightGroupSet<{n}, {}> =",
                    display.name,
                    lights.len()
                ),
                &value,
            );
            t.consts.push(Constant::new(
                std::format!("groups::{name}_{}", display.name),
                std::format!("crate::LightGroupSet<{n}, {}>", lights.len()),
            ));
            names.push(std::format!("{name}_{}", display.name));
        }
    }
    o.push_str(&names_rs("groups", "light group", &names));
    writeln!(o, "}}\n").ok();
}

/// `pub mod lights`: each scene light's fitted samples at each colour set for radiances, for
/// relighting a material's node values under it.
fn lights_rs(t: &mut Tables, m: &Model) {
    if m.lights.is_empty() {
        return;
    }
    let o = &mut t.o;
    o.push_str(&layout::comment(0, "///", "Each scene light at each set for radiances, for relighting a material: `<LIGHT>_AT_<SET>`, the values `l` with which samples `r ⊙ l` of a reflectance r at the set's nodes give, through the set ([`FoldedSet::linear_rgb_under`](crate::FoldedSet::linear_rgb_under)), r's colour under the light. Fitted, not the light's values at the nodes: the least-squares fit on the CIE test colours of their colours under the light, with a reflectance of 1 pinned to the light's own white at Y = 1.", 0));
    writeln!(o, "pub mod lights {{").ok();
    for l in &m.lights {
        let set = &m.colour_sets[l.set];
        item(
            o,
            4,
            &std::format!(
                "Light {} at [`{}`](super::{})'s nodes: a reflectance of 1 gives the light's white, Y = 1.",
                l.light, set.name, set.name
            ),
            &std::format!(
                "pub const {}_AT_{}: [f32; {}] =",
                l.light,
                set.name,
                set.len()
            ),
            &f32s(&l.values),
        );
        t.consts.push(Constant::new(
            std::format!("lights::{}_AT_{}", l.light, set.name),
            std::format!("[f32; {}]", set.len()),
        ));
    }
    writeln!(o, "}}\n").ok();
}
