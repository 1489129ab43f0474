//! `TABLE_BYTES` and `ALL_TABLES` against the baked constants themselves, for any scene: the
//! constants a generated `tables.rs` declares (read from its text), each one's size
//! (`size_of_val` of the value `ALL_TABLES` links) and the slices it points to (a rule's nodes and
//! weights, an upsampling's table and edge cells, found by their types), summed. `codegen.rs` runs it on the default scene's
//! tables, `.ci/tables-check` on every example scene's, each compiled against the runtime, so
//! it names nothing of one scene.

use std::any::Any;
use std::collections::HashSet;

use spectral_quadrature::{GaussRule, Upsampling};

/// One entry of `ALL_TABLES`: a constant's path, its size and a reference to it.
pub type Entry = (&'static str, usize, &'static (dyn Any + Sync));

/// The paths of the constants of numbers a generated `tables.rs` declares: every `pub const` and
/// `static` item at its top and in its modules (`folded::KQ_C_4_SRGB`), but the text (types
/// holding `str`: the provenance, the shader sources, the lists of names), the lengths that type
/// the tables (`usize`: `GRID_LEN`, `MAX_ORDER`, and `TABLE_BYTES`) and the list itself
/// (`ALL_TABLES`). rustfmt writes every item's `NAME: TYPE =` on one line, at column 0 or 4.
pub fn declared(source: &str) -> Vec<String> {
    let mut module: Option<String> = None;
    let mut out = Vec::new();
    for line in source.lines() {
        if let Some(name) = line
            .strip_prefix("pub mod ")
            .and_then(|l| l.strip_suffix(" {"))
        {
            module = Some(name.to_string());
            continue;
        }
        if line == "}" {
            module = None;
            continue;
        }
        let item = line.trim_start();
        let Some(decl) = ["pub const ", "pub static ", "pub(crate) static "]
            .iter()
            .find_map(|p| item.strip_prefix(p))
        else {
            continue;
        };
        let Some((name, rest)) = decl.split_once(": ") else {
            continue;
        };
        let ty = rest.split(" =").next().unwrap_or("").trim();
        if ty.contains("str") || ty == "usize" {
            continue;
        }
        out.push(match &module {
            Some(m) => format!("{m}::{name}"),
            None => name.to_string(),
        });
    }
    out
}

/// The bytes of the slices `value` points to: a `[GaussRule; K]`'s or
/// `[[GaussRule; K]; 3]`'s nodes and weights, an `Upsampling<N>`'s table and its round trip's
/// edge cells (for K and N up to 64, `MAX_WAVELENGTHS`); none for any other type.
fn slices(value: &dyn Any) -> usize {
    fn rule(r: &GaussRule) -> usize {
        std::mem::size_of_val(r.wavelengths_nm()) + std::mem::size_of_val(r.weights())
    }
    macro_rules! by_length {
        ($($n:literal)*) => {
            $(
                if let Some(rules) = value.downcast_ref::<[GaussRule; $n]>() {
                    return rules.iter().map(rule).sum();
                }
                if let Some(rules) = value.downcast_ref::<[[GaussRule; $n]; 3]>() {
                    return rules.iter().flatten().map(rule).sum();
                }
                if let Some(map) = value.downcast_ref::<Upsampling<$n>>() {
                    let edge = map.round_trip().map_or(0, |rt| std::mem::size_of_val(rt.edge_cells()));
                    return std::mem::size_of_val(map.table()) + edge;
                }
            )*
        };
    }
    by_length!(
        1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24 25 26 27 28 29 30 31 32
        33 34 35 36 37 38 39 40 41 42 43 44 45 46 47 48 49 50 51 52 53 54 55 56 57 58 59 60 61 62
        63 64
    );
    0
}

/// Checks `all` (`ALL_TABLES`) against the constants `source` (the generated `tables.rs`)
/// declares, and `table_bytes` (`TABLE_BYTES`) against their sizes: `all` lists each declared
/// constant once and nothing else; each entry's size is its value's `size_of_val` plus the
/// bytes of the slices it points to; and the sizes sum to `table_bytes`. `Ok` with the number
/// of constants and the bytes counted in slices, else the first disagreement.
pub fn check(all: &[Entry], table_bytes: usize, source: &str) -> Result<(usize, usize), String> {
    let declared = declared(source);
    let listed: Vec<&str> = all.iter().map(|(path, _, _)| *path).collect();
    for path in &declared {
        if !listed.contains(&path.as_str()) {
            return Err(format!("{path} is declared but not in ALL_TABLES"));
        }
    }
    let mut seen_paths = HashSet::new();
    for path in &listed {
        if !declared.iter().any(|d| d == path) {
            return Err(format!(
                "ALL_TABLES lists {path}, which tables.rs does not declare"
            ));
        }
        if !seen_paths.insert(*path) {
            return Err(format!("ALL_TABLES lists {path} twice"));
        }
    }
    let (mut sum, mut in_slices) = (0, 0);
    for &(path, bytes, value) in all {
        let own = slices(value);
        let expected = std::mem::size_of_val(value) + own;
        if bytes != expected {
            return Err(format!(
                "ALL_TABLES gives {path} {bytes} bytes; its type has {} and its slices {own}",
                std::mem::size_of_val(value)
            ));
        }
        sum += expected;
        in_slices += own;
    }
    if sum != table_bytes {
        return Err(format!(
            "TABLE_BYTES is {table_bytes}, the baked constants hold {sum}"
        ));
    }
    Ok((all.len(), in_slices))
}
