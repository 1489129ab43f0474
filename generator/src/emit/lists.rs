//! The lists of the baked items in `tables.rs`, each emitted from the same loops as the items,
//! so that no list is kept by hand: `NAMES` and the macro `all!` at the end of `sets`, `folded`,
//! `groups`, `integer` and `upsampling` (the runtime's tests visit every baked set through
//! them), and `ALL_TABLES` with `TABLE_BYTES`, every constant of numbers the file bakes
//! ([`Constant`], which each emitter registers as it writes the item).

use std::fmt::Write as _;
use std::string::String;

use super::layout::{self, Expr};

/// The list of a module's baked items, emitted at the end of `pub mod <module>` (`folded`,
/// `integer`, `upsampling`): `NAMES`, their names in the module's order, and the macro `all!`,
/// which passes every name to the caller's macro, so that code generic over a set's length
/// can visit them all without allocating. `what` names one item in the docs.
pub(crate) fn names_rs(module: &str, what: &str, names: &[String]) -> String {
    let mut o = layout::comment(
        4,
        "///",
        &std::format!("The name of every {what} above, in their order: what [`all!`] passes on."),
        0,
    );
    o.push_str(&layout::item(
        4,
        &std::format!("pub const NAMES: [&str; {}] =", names.len()),
        &Expr::Array(
            names
                .iter()
                .map(|n| Expr::atom(std::format!("{n:?}")))
                .collect(),
        ),
    ));
    o.push('\n');
    let hidden = std::format!("__tables_{module}_all");
    o.push_str(&layout::comment(
        4,
        "///",
        &std::format!(
            "Passes the name of every {what} above to a `macro_rules!` macro of yours, `m`, in scope where this is called: `{module}::all!(m)` expands to `m! {{ NAME, NAME, ... }}`, the names in the order of [`NAMES`], each followed by a comma (match them with `($($name:ident,)*)`). `m` sees the items as `{module}::$name`: code generic over the length `N` visits every {what} so, in `no_std` and without allocating (see `docs/using-the-tables.md`)."
        ),
        0,
    ));
    writeln!(
        o,
        "    #[doc(hidden)]\n    #[macro_export]\n    macro_rules! {hidden} {{"
    )
    .ok();
    writeln!(o, "        ($m:ident) => {{\n            $m! {{").ok();
    for n in names {
        writeln!(o, "                {n},").ok();
    }
    writeln!(o, "            }}\n        }};\n    }}").ok();
    writeln!(o, "    #[doc(inline)]\n    pub use {hidden} as all;").ok();
    o
}

/// One baked constant of the numbers a scene bakes, as the Rust tables name it: every emitter
/// registers each such item it writes, so that [`all_tables_rs`] lists them all from the one
/// list the items were written from.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Constant {
    /// Its path in `tables` (`KQ_C_4`, `folded::KQ_C_4_SRGB`).
    pub(crate) path: String,
    /// Its type, as the item declares it.
    pub(crate) ty: String,
    /// The bytes of the slices it points to (a rule's nodes and weights, an upsampling's table
    /// and edge cells).
    pub(crate) slice_bytes: usize,
}

impl Constant {
    /// A constant of `ty` at `path` that points to no slice of its own.
    pub(crate) fn new(path: impl Into<String>, ty: impl Into<String>) -> Constant {
        Constant {
            path: path.into(),
            ty: ty.into(),
            slice_bytes: 0,
        }
    }

    /// The same, with `bytes` of slices of its own.
    pub(crate) fn with_slices(self, bytes: usize) -> Constant {
        Constant {
            slice_bytes: bytes,
            ..self
        }
    }
}

/// `ALL_TABLES`, every constant of `constants` by its path with its size (its type's, plus its
/// slices') and a reference to it, and `TABLE_BYTES`, their sum.
pub(crate) fn all_tables_rs(constants: &[Constant]) -> String {
    let entries = constants
        .iter()
        .map(|c| {
            let size = if c.slice_bytes == 0 {
                std::format!("size_of::<{}>()", c.ty)
            } else {
                std::format!("size_of::<{}>() + {}", c.ty, c.slice_bytes)
            };
            Expr::Tuple(std::vec![
                Expr::atom(std::format!("{:?}", c.path)),
                Expr::atom(size),
                Expr::atom(std::format!("&{}", c.path)),
            ])
        })
        .collect();
    let mut o = layout::comment(
        0,
        "///",
        "Every constant of this file that holds the scene's numbers, by its path in `tables`, with its size in bytes and a reference to it. The size is what the constant costs linked alone: its type's size (`size_of`) plus the bytes of the slices it points to (a rule's nodes and weights, an upsampling's table and edge cells), so that the rules' nodes and weights count in each channel's array of rules and again in the array of all three. Not here: the text (the provenance, the shader sources, the lists of names) and the `usize` lengths that type the tables. A program that names this links every table the scene bakes (see `examples/size_probe.rs`).",
        0,
    );
    o.push_str(&layout::item(
        0,
        "pub static ALL_TABLES: &[(&str, usize, &(dyn core::any::Any + Sync))] =",
        &Expr::Array(entries).by_ref(),
    ));
    o.push('\n');
    o.push_str(&layout::comment(
        0,
        "///",
        "The bytes the scene bakes: the sum of the sizes in [`ALL_TABLES`], each constant's as if linked alone.",
        0,
    ));
    o.push_str(
        "pub const TABLE_BYTES: usize = {\n    let mut bytes = 0;\n    let mut i = 0;\n    while i < ALL_TABLES.len() {\n        bytes += ALL_TABLES[i].1;\n        i += 1;\n    }\n    bytes\n};\n",
    );
    o
}
