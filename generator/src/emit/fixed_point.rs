//! The integer path's tables: each folded set in fixed point, for integer samples (`tables::integer`
//! in the runtime). The runtime's `const fn IntegerSet::new` converts the folded set's f32
//! weights exactly and proves the 32-bit sums free of overflow, so the compiler checks every
//! baked set; what the generator chooses is the scale of the counts: 65 535 is the samples of
//! white.

use std::string::String;
use std::vec::Vec;

use super::layout::{self, Expr};
use super::lists::{names_rs, Constant};
use super::model::Model;

pub use super::model::{sample_unit, FULL_SCALE};

/// The Rust source of `pub mod integer`: one `IntegerSet<N>` per folded set, named as in
/// `folded`, each registered in `consts`; empty when the scene bakes no folded set.
pub(crate) fn integer_rs(m: &Model, consts: &mut Vec<Constant>) -> String {
    if m.integer.is_empty() {
        return String::new();
    }
    let mut o = layout::comment(
        0,
        "///",
        "Each folded set in fixed point, for integer samples (u16 counts, 65535 the samples of white): `IntegerSet::new` of the set in `folded`, checked when the crate compiles. Named `<SET>_<DISPLAY>`.",
        0,
    );
    o.push_str(
        "pub mod integer {\n    use super::{checked, folded};\n    use crate::IntegerSet;\n\n",
    );
    let mut items = Vec::new();
    let mut names = Vec::new();
    for i in &m.integer {
        let f = &m.folded[i.folded];
        let set = &m.colour_sets[f.set];
        // Rust's shortest round-trip form, with a `.` or an exponent: the literal is the f32.
        let unit_lit = std::format!("{:?}", i.sample_unit);
        let white = if i.sensor_white {
            std::format!(
                "the largest of the sensor's readings of white (one count is {:.6e})",
                i.sample_unit_f64
            )
        } else {
            "the samples of white".into()
        };
        let name = m.folded_name(f);
        let doc = std::format!("[`folded::{name}`] in fixed point: 65535 counts are {white}.");
        items.push(
            layout::comment(4, "///", &doc, 0)
                + &layout::item(
                    4,
                    &std::format!("pub const {name}: IntegerSet<{}> =", set.len()),
                    &Expr::Call(
                        "checked".into(),
                        std::vec![Expr::Call(
                            "IntegerSet::new".into(),
                            std::vec![
                                Expr::atom(std::format!("folded::{name}")).by_ref(),
                                Expr::atom(unit_lit),
                            ],
                        )],
                    ),
                )
                + "\n",
        );
        consts.push(Constant::new(
            std::format!("integer::{name}"),
            std::format!("crate::IntegerSet<{}>", set.len()),
        ));
        names.push(name);
    }
    o.push_str(&items.concat());
    o.push_str(&names_rs("integer", "integer set", &names));
    o.push_str("}\n\n");
    o
}
