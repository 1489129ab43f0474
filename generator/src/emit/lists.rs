//! The lists of a module's baked items in `tables.rs`: `NAMES` and the macro `all!` at the end
//! of `folded`, `integer` and `upsampling`, emitted from the same loops as the items, so that
//! no list is kept by hand (the runtime's tests visit every baked set through them).

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
