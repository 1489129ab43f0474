//! The `upsampling` module of `tables.rs`: one `Upsampling` const per set and display a scene
//! asks for ([`crate::upsampling`]), its table of 16-bit codes laid out as rustfmt would.

use std::string::{String, ToString};
use std::vec::Vec;

use super::layout::{self, Expr};
use crate::base::error::Error;
use crate::derivation::evaluate::builtin_lights;
use crate::scenes::scene::Resolved;
use crate::upsampling::TRAINING_FILES;

/// The const name of the upsampling of `set` for `display`: `<SET>_<DISPLAY>`.
pub fn const_name(set: &str, display: &str) -> String {
    std::format!("{set}_{display}")
}

/// The data files (labels `data/<file>`) the scene's upsamplings are made from: the training
/// reflectances and each built-in reference light. Empty when there are none.
pub(crate) fn input_files(scene: &Resolved) -> Vec<String> {
    if scene.upsamplings.is_empty() {
        return Vec::new();
    }
    let mut files: Vec<String> = TRAINING_FILES.iter().map(|f| f.to_string()).collect();
    for u in &scene.upsamplings {
        let file = std::format!("data/illuminant_{}.csv", u.light);
        if builtin_lights().contains(&u.light.as_str()) && !files.contains(&file) {
            files.push(file);
        }
    }
    files
}

/// The module's source and the bytes of its tables (two per code), or an empty string and 0
/// when the scene asks for no upsampling. `f32_literal`: the Rust literal of an f64 rounded to
/// f32 (`codegen`'s, so that every baked f32 is written one way).
pub(crate) fn upsampling_rs(
    scene: &Resolved,
    f32_literal: &dyn Fn(f64) -> Result<String, Error>,
) -> Result<(String, usize), Error> {
    if scene.upsamplings.is_empty() {
        return Ok((String::new(), 0));
    }
    let mut o = String::new();
    let mut bytes = 0;
    o.push_str(&layout::comment(
        0,
        "///",
        "RGB materials: each upsampling maps the display's linear RGB, white-balanced under the set's reference light, to the set's node reflectances in [0, 1] (see `docs/upsampling.md`). Named `<SET>_<DISPLAY>`.",
        0,
    ));
    o.push_str("pub mod upsampling {\n    use crate::Upsampling;\n");
    for u in &scene.upsamplings {
        let (spec, _) = scene
            .displays
            .iter()
            .find(|(s, _)| s.name == u.display)
            .ok_or_else(|| Error::UnknownDisplay {
                name: u.display.clone(),
                valid: scene.displays.iter().map(|(s, _)| s.name.clone()).collect(),
            })?;
        let n = u.wavelengths_nm.len();
        let rows: Vec<Expr> = u
            .codes
            .iter()
            .map(|c| Expr::Array(c.iter().map(|v| Expr::atom(v.to_string())).collect()))
            .collect();
        bytes += 2 * n * rows.len();
        let f32s = |v: &[f64]| -> Result<Expr, Error> {
            v.iter()
                .map(|&x| f32_literal(x).map(Expr::Atom))
                .collect::<Result<Vec<_>, _>>()
                .map(Expr::Array)
        };
        let quoted = |s: &str| Expr::atom(std::format!("{s:?}"));
        let value = Expr::Struct(
            "Upsampling".into(),
            std::vec![
                ("set".into(), quoted(&u.set)),
                ("display".into(), quoted(&spec.label)),
                ("light".into(), quoted(&u.light)),
                ("wavelengths_nm".into(), f32s(&u.wavelengths_nm)?),
                ("lipschitz".into(), Expr::Atom(f32_literal(u.lipschitz)?)),
                (
                    "max_round_trip_delta_e00".into(),
                    Expr::Atom(f32_literal(u.max_round_trip_de00)?)
                ),
                (
                    "reachable_share".into(),
                    Expr::Atom(f32_literal(u.reachable_share())?)
                ),
                ("grid".into(), Expr::atom(u.grid.to_string())),
                ("table".into(), Expr::Array(rows).by_ref()),
            ],
        );
        let doc = std::format!(
            "[`{set}`](super::{set}) for [`{disp}`](super::displays::{disp}): linear {label} RGB white-balanced under {light} → {n} node reflectances, a {g}×{g}×{g} grid ({bytes} bytes); {share:.1} % of the grid reachable; Lipschitz {lip:.3}; round trip within {rt:.4} ΔE00 at the reachable grid points.",
            set = u.set,
            disp = u.display,
            label = spec.label,
            light = u.light,
            g = u.grid,
            bytes = 2 * n * u.codes.len(),
            share = 100.0 * u.reachable_share(),
            lip = u.lipschitz,
            rt = u.max_round_trip_de00,
        );
        o.push_str(&layout::comment(4, "///", &doc, 0));
        o.push_str(&layout::item(
            4,
            &std::format!(
                "pub const {}: Upsampling<{n}> =",
                const_name(&u.set, &u.display)
            ),
            &value,
        ));
        o.push('\n');
    }
    o.push_str("}\n\n");
    Ok((o, bytes))
}
