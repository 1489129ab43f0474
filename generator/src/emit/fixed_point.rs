//! The integer path's tables: each folded set in fixed point, for integer samples (`tables::integer`
//! in the runtime). The runtime's `const fn IntegerSet::new` converts the folded set's f32
//! weights exactly and proves the 32-bit sums free of overflow, so the compiler checks every
//! baked set; what the generator chooses is the scale of the counts: 65 535 is the samples of
//! white.

use std::string::String;
use std::vec::Vec;

use super::layout::{self, Expr};
use super::lists::names_rs;
use crate::base::error::Error;
use crate::derivation::sets::WavelengthSet;
use crate::scenes::scene::Resolved;

/// The largest count, what the samples of white become.
pub const FULL_SCALE: f64 = 65535.0;

/// The sample one count stands for in `set`'s integer form: the largest of its white samples
/// over [`FULL_SCALE`]. White is a reflectance (or a radiance) of 1 for a wavelength set, and a
/// sensor's readings of it for a sensor set (`scene.white_samples`: the golden device's readings
/// of a perfect white, the same numbers as the sensor's `tables::sensors::<NAME>_WHITE`).
pub fn sample_unit(set: &WavelengthSet, scene: &Resolved) -> f64 {
    let white = scene
        .white_samples
        .iter()
        .find(|(name, _)| *name == set.name)
        .map_or(1.0, |(_, w)| w.iter().copied().fold(0.0, f64::max));
    white / FULL_SCALE
}

/// The Rust source of `pub mod integer`: one `IntegerSet<N>` per folded set, named as in
/// `folded`; empty when the scene bakes no folded set.
pub(crate) fn integer_rs(scene: &Resolved) -> Result<String, Error> {
    if scene.colour_sets.is_empty() || scene.displays.is_empty() {
        return Ok(String::new());
    }
    let mut o = layout::comment(
        0,
        "///",
        "Each folded set in fixed point, for integer samples (u16 counts, 65535 the samples of white): `IntegerSet::new` of the set in `folded`, checked when the crate compiles. Named `<SET>_<DISPLAY>`.",
        0,
    );
    o.push_str(
        "pub mod integer {\n    use super::folded;\n    use crate::{FoldedSet, IntegerSet};\n\n",
    );
    o.push_str(&layout::comment(
        4,
        "///",
        "A folded set in fixed point, or a compile-time error if it has none.",
        0,
    ));
    o.push_str(
        "    const fn baked<const N: usize>(set: &FoldedSet<N>, sample_unit: f32) -> IntegerSet<N> {\n        match IntegerSet::new(set, sample_unit) {\n            Ok(set) => set,\n            Err(_) => panic!(\"a baked set has no fixed-point form\"),\n        }\n    }\n\n",
    );
    let mut items = Vec::new();
    let mut names = Vec::new();
    for set in &scene.colour_sets {
        let unit = sample_unit(set, scene);
        let unit32 = unit as f32;
        if !(unit32.is_finite() && unit32 > 0.0) {
            return Err(Error::Literal {
                value: unit,
                language: "Rust",
            });
        }
        // Rust's shortest round-trip form, with a `.` or an exponent: the literal is `unit32`.
        let unit_lit = std::format!("{unit32:?}");
        let white = if scene.white_samples.iter().any(|(n, _)| *n == set.name) {
            std::format!("the largest of the sensor's readings of white (one count is {unit:.6e})")
        } else {
            "the samples of white".into()
        };
        for (spec, _) in &scene.displays {
            let name = std::format!("{}_{}", set.name, spec.name);
            let doc = std::format!("[`folded::{name}`] in fixed point: 65535 counts are {white}.");
            items.push(
                layout::comment(4, "///", &doc, 0)
                    + &layout::item(
                        4,
                        &std::format!("pub const {name}: IntegerSet<{}> =", set.len()),
                        &Expr::Call(
                            "baked".into(),
                            std::vec![
                                Expr::atom(std::format!("folded::{name}")).by_ref(),
                                Expr::atom(unit_lit.clone()),
                            ],
                        ),
                    )
                    + "\n",
            );
            names.push(name);
        }
    }
    o.push_str(&items.concat());
    o.push_str(&names_rs("integer", "integer set", &names));
    o.push_str("}\n\n");
    Ok(o)
}
