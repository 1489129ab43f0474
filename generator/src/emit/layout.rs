//! Lays the generated Rust out as `rustfmt --edition 2021` does with its default settings, so
//! that the baked `tables.rs` reads like hand-formatted code (at most 100 columns) without
//! running rustfmt, syn or prettyplease at build time: a downstream build runs the generator at
//! Cargo's default opt-level 0 and must stay cheap.
//!
//! Only the forms the tables use are laid out: tokens that never break (numbers, strings,
//! paths), arrays, tuples, `&`, struct literals and function calls, each with rustfmt's rules
//! and widths (`array_width` 60, `fn_call_width` 60, `struct_lit_width` 18,
//! `short_array_element_width_threshold` 10), and `const`/`static` items
//! whose value goes on the next line where that reads better, as rustfmt decides it. Comments,
//! which rustfmt leaves as they are, are wrapped at spaces. `tests/codegen.rs` checks the baked
//! tables with `rustfmt --check` where rustfmt is installed. An f32 is written in Rust's shortest
//! round-trip form ([`lit`]), the one literal every formatter writes for it.

use std::string::String;
use std::vec::Vec;

use crate::base::error::Error;

/// The literal for an f64 rounded to f32 (`as f32`), which must be finite.
pub(crate) fn f32_literal(v: f64) -> Result<String, Error> {
    let x = v as f32;
    if !x.is_finite() {
        return Err(Error::Literal {
            value: v,
            language: "Rust",
        });
    }
    Ok(lit(x))
}

/// The literal of an f32 of the model (finite): Rust's shortest round-trip form, with a `.` or
/// an exponent.
pub(crate) fn lit(x: f32) -> String {
    let mut s = std::format!("{x:?}");
    if !s.contains(['.', 'e', 'E']) {
        s.push_str(".0");
    }
    s
}

/// An array of f32 values.
pub(crate) fn f32s(values: &[f32]) -> Expr {
    Expr::Array(values.iter().map(|&v| Expr::Atom(lit(v))).collect())
}

/// rustfmt's `max_width`.
pub(crate) const MAX_WIDTH: usize = 100;
/// rustfmt's `tab_spaces`: one level of block indent.
const TAB: usize = 4;
/// The widest array laid out on one line (rustfmt's `array_width`).
const ARRAY_WIDTH: usize = 60;
/// The widest tuple laid out on one line (rustfmt's `fn_call_width`).
const TUPLE_WIDTH: usize = 60;
/// The widest body of a struct literal laid out on one line (rustfmt's `struct_lit_width`).
const STRUCT_LIT_WIDTH: usize = 18;
/// Arrays of simple items this short fill their lines (rustfmt's
/// `short_array_element_width_threshold`) instead of taking one line each.
const SHORT_ITEM: usize = 10;

/// An expression of the generated tables.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Expr {
    /// A token never broken: a number, a string, a path (`Samples::Radiance`), a short call
    /// (`Some("C")`). A string may hold `\`-newline continuations (its lines then stand as
    /// they are).
    Atom(String),
    /// `&expr`.
    Ref(std::boxed::Box<Expr>),
    /// `[a, b, …]`.
    Array(Vec<Expr>),
    /// `(a, b, …)`.
    Tuple(Vec<Expr>),
    /// `Path { field: value, … }`.
    Struct(String, Vec<(String, Expr)>),
    /// `path(a, b, …)`: a function call, its arguments laid out as a tuple's (rustfmt's
    /// `fn_call_width`), without a tuple's trailing comma after a single argument.
    Call(String, Vec<Expr>),
}

impl Expr {
    /// A token.
    pub(crate) fn atom(s: impl Into<String>) -> Expr {
        Expr::Atom(s.into())
    }

    /// `&self`.
    pub(crate) fn by_ref(self) -> Expr {
        Expr::Ref(std::boxed::Box::new(self))
    }

    /// A function call, or `&` of one (rustfmt's nested calls).
    fn is_nested_call(&self) -> bool {
        match self {
            Expr::Call(..) => true,
            Expr::Ref(e) => e.is_nested_call(),
            _ => false,
        }
    }

    /// A literal or a path, or `&` of one (rustfmt's simple expressions): arrays of short
    /// simple items fill their lines.
    fn is_simple(&self) -> bool {
        match self {
            Expr::Atom(s) => !s.contains('(') && !s.contains('\n'),
            Expr::Ref(e) => e.is_simple(),
            _ => false,
        }
    }
}

/// Where an expression goes: the column its first line starts at, the width left there, and
/// the block indent its inner lines are indented from.
#[derive(Debug, Clone, Copy)]
struct Shape {
    indent: usize,
    col: usize,
    width: usize,
}

impl Shape {
    /// A block at `indent`, the whole line left to it less `overhead` (a closing `;` or `,`).
    fn block(indent: usize, overhead: usize) -> Shape {
        Shape {
            indent,
            col: indent,
            width: MAX_WIDTH.saturating_sub(indent + overhead),
        }
    }

    /// `n` more columns used on the first line.
    fn offset_left(self, n: usize) -> Option<Shape> {
        Some(Shape {
            col: self.col + n,
            width: self.width.checked_sub(n)?,
            ..self
        })
    }

    fn sub_width(self, n: usize) -> Option<Shape> {
        Some(Shape {
            width: self.width.checked_sub(n)?,
            ..self
        })
    }
}

fn width(s: &str) -> usize {
    s.chars().count()
}

fn first_line(s: &str) -> &str {
    s.split('\n').next().unwrap_or("")
}

fn last_line(s: &str) -> &str {
    s.rsplit('\n').next().unwrap_or("")
}

fn newlines(s: &str) -> usize {
    s.matches('\n').count()
}

fn spaces(n: usize) -> String {
    " ".repeat(n)
}

/// Whether a laid-out expression fits `shape`: its first line in the width, its other lines
/// in the maximum width, its last line before the end of the shape (rustfmt's `wrap_str`).
fn fits(s: &str, shape: Shape) -> bool {
    if width(first_line(s)) > shape.width {
        return false;
    }
    if !s.contains('\n') {
        return true;
    }
    s.split('\n').skip(1).all(|l| width(l) <= MAX_WIDTH)
        && width(last_line(s)) <= shape.col + shape.width
}

/// `expr` laid out in `shape`, or `None` where it cannot fit.
fn rewrite(expr: &Expr, shape: Shape) -> Option<String> {
    match expr {
        Expr::Atom(s) => fits(s, shape).then(|| s.clone()),
        Expr::Ref(e) => rewrite(e, shape.offset_left(1)?).map(|s| std::format!("&{s}")),
        Expr::Array(items) => list(items, "[", "]", ARRAY_WIDTH, false, shape),
        Expr::Tuple(items) => list(items, "(", ")", TUPLE_WIDTH, items.len() == 1, shape),
        Expr::Struct(path, fields) => struct_lit(path, fields, shape),
        Expr::Call(path, args) => list(
            args,
            "(",
            ")",
            TUPLE_WIDTH,
            false,
            shape.offset_left(width(path))?,
        )
        .map(|a| std::format!("{path}{a}")),
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Tactic {
    Horizontal,
    Vertical,
    Mixed,
}

/// rustfmt's `definitive_tactic` with a width limit: one line if every item is one line and
/// they fit `limit` with their `, ` separators.
fn one_line_or_vertical(items: &[String], limit: usize) -> Tactic {
    let total: usize =
        items.iter().map(|s| width(s)).sum::<usize>() + 2 * items.len().saturating_sub(1);
    if total <= limit && items.iter().all(|s| !s.contains('\n')) {
        Tactic::Horizontal
    } else {
        Tactic::Vertical
    }
}

/// A bracketed list (an array or a tuple), as rustfmt's `overflow` module lays one out:
/// on one line within `max_item_width`; else, for a single item, that item opening on the
/// bracket's line where its first line fits there; else short simple items filling their lines;
/// else one item a line, each followed by a comma.
fn list(
    items: &[Expr],
    open: &str,
    close: &str,
    max_item_width: usize,
    force_trailing_comma: bool,
    shape: Shape,
) -> Option<String> {
    let one_line_width = shape.width.saturating_sub(2);
    let nested = Shape::block(shape.indent + TAB, 1);
    let mut laid: Vec<String> = items
        .iter()
        .map(|e| rewrite(e, nested))
        .collect::<Option<Vec<_>>>()?;
    let own_lines = laid.clone();
    // A single item may open on the bracket's line and overflow below it; a nested call does so
    // within the list's item width (rustfmt's `last_item_shape`), so that a call of calls
    // breaks the inner call's arguments rather than running past that width.
    let mut overflowed = None;
    if items.len() == 1 {
        let one_line_shape = shape
            .offset_left(1)
            .and_then(|s| s.sub_width(1))
            .map(|s| match items[0].is_nested_call() {
                true => Shape {
                    width: s.width.min(max_item_width),
                    ..s
                },
                false => s,
            });
        if let Some(rw) = one_line_shape.and_then(|s| rewrite(&items[0], s)) {
            laid[0] = first_line(&rw).into();
            overflowed = Some(rw);
        }
    }
    let mut tactic = one_line_or_vertical(&laid, one_line_width.min(max_item_width));
    match (tactic, overflowed) {
        (Tactic::Horizontal, Some(rw)) => {
            laid[0] = if newlines(&rw) == 1 && !own_lines[0].contains('\n') {
                own_lines[0].clone()
            } else {
                rw
            };
        }
        _ if !items.is_empty() => {
            laid = own_lines;
            if items.len() == 1
                && one_line_width != 0
                && !laid[0].contains('\n')
                && width(&laid[0]) <= one_line_width
            {
                tactic = Tactic::Horizontal;
            } else {
                tactic = one_line_or_vertical(&laid, one_line_width.min(max_item_width));
                if tactic == Tactic::Vertical
                    && items.iter().all(Expr::is_simple)
                    && laid.iter().all(|s| width(s) <= SHORT_ITEM)
                {
                    tactic = Tactic::Mixed;
                }
            }
        }
        _ => {}
    }
    let body = match tactic {
        Tactic::Horizontal => {
            let mut b = laid.join(", ");
            if force_trailing_comma {
                b.push(',');
            }
            b
        }
        Tactic::Vertical => {
            let mut b = laid.join(&std::format!(",\n{}", spaces(nested.indent)));
            b.push(',');
            b
        }
        Tactic::Mixed => {
            // Each item counts with its comma, except the last one on the first line: rustfmt
            // counts a trailing comma only once the list has broken a line.
            let mut b = String::new();
            let mut line = 0;
            let mut broke = false;
            for (k, item) in laid.iter().enumerate() {
                let w = width(item) + usize::from(k + 1 < laid.len() || broke);
                if line > 0 && line + 1 + w > nested.width {
                    b.push('\n');
                    b.push_str(&spaces(nested.indent));
                    line = 0;
                    broke = true;
                } else if line > 0 {
                    b.push(' ');
                    line += 1;
                }
                b.push_str(item);
                b.push(',');
                line += w;
            }
            b
        }
    };
    let one_line = tactic == Tactic::Horizontal && width(first_line(&body)) < shape.width;
    if one_line || body.is_empty() {
        Some(std::format!("{open}{body}{close}"))
    } else {
        Some(std::format!(
            "{open}\n{}{body}\n{}{close}",
            spaces(nested.indent),
            spaces(shape.indent)
        ))
    }
}

/// A struct literal, as rustfmt lays one out: on one line if its fields fit
/// [`STRUCT_LIT_WIDTH`] columns; else one field a line. A field's value goes on the field's line,
/// or below it, indented, where it does not fit there.
fn struct_lit(path: &str, fields: &[(String, Expr)], shape: Shape) -> Option<String> {
    // 2 = ` {` after the path.
    if width(path) + 2 > shape.width {
        return None;
    }
    let v_shape = Shape::block(shape.indent + TAB, 0);
    let field_shape = v_shape.sub_width(1)?;
    let laid = fields
        .iter()
        .map(|(name, value)| {
            let overhead = width(name) + 2;
            let same_line = field_shape
                .offset_left(overhead)
                .and_then(|s| rewrite(value, s));
            match same_line {
                Some(v) => Some(std::format!("{name}: {v}")),
                None => {
                    let below = Shape::block(field_shape.indent + TAB, 0);
                    rewrite(value, below)
                        .map(|v| std::format!("{name}:\n{}{v}", spaces(below.indent)))
                }
            }
        })
        .collect::<Option<Vec<String>>>()?;
    let h_width = shape
        .width
        .checked_sub(width(path) + 3 + 2)
        .map(|w| w.min(STRUCT_LIT_WIDTH));
    let tactic = match h_width {
        Some(w) => one_line_or_vertical(&laid, w),
        None => Tactic::Vertical,
    };
    if tactic == Tactic::Horizontal {
        let body = laid.join(", ");
        if h_width.is_some_and(|w| width(&body) <= w) {
            return Some(std::format!("{path} {{ {body} }}"));
        }
    }
    let body = laid.join(&std::format!(",\n{}", spaces(v_shape.indent)));
    Some(std::format!(
        "{path} {{\n{}{body},\n{}}}",
        spaces(v_shape.indent),
        spaces(shape.indent)
    ))
}

/// `lhs = rhs;` at block indent `indent`, as rustfmt lays out a `const` or `static` item: the
/// value on `lhs`'s line where it fits there on one line; else below it, indented, where it
/// fits there on one line, or takes fewer lines, or does not otherwise fit; else on `lhs`'s
/// line. A value that fits nowhere is left on `lhs`'s line as it is, as rustfmt leaves it.
pub(crate) fn item(indent: usize, lhs: &str, rhs: &Expr) -> String {
    let shape = Shape::block(indent, 1);
    let same = shape.offset_left(width(lhs) + 1);
    let orig = same.and_then(|s| rewrite(rhs, s));
    let rhs_str = match orig {
        Some(ref o) if !o.contains('\n') => std::format!(" {o}"),
        _ => {
            let next_shape = Shape::block(indent + TAB, 1);
            let next = rewrite(rhs, next_shape);
            let below = |n: &str| std::format!("\n{}{n}", spaces(next_shape.indent));
            match (orig, next) {
                (Some(o), Some(n)) if !fits(&n, next_shape) => std::format!(" {o}"),
                (Some(o), Some(n)) if prefer_next_line(&o, &n) => below(&n),
                (None, Some(n)) => below(&n),
                (Some(o), _) => std::format!(" {o}"),
                (None, None) => std::format!(" {}", unformatted(rhs)),
            }
        }
    };
    std::format!("{}{lhs}{rhs_str};", spaces(indent))
}

/// rustfmt's choice between a value on the line of its `=` and one below it.
fn prefer_next_line(orig: &str, next: &str) -> bool {
    let ends = |s: &str, c: char| first_line(s).ends_with(c);
    !next.contains('\n')
        || newlines(orig) > newlines(next) + 1
        || ['(', '{', '[']
            .iter()
            .any(|&c| ends(orig, c) && !ends(next, c))
}

/// An expression on one line, for a value no layout fits.
fn unformatted(e: &Expr) -> String {
    fn join(items: &[Expr]) -> String {
        items.iter().map(unformatted).collect::<Vec<_>>().join(", ")
    }
    match e {
        Expr::Atom(s) => s.clone(),
        Expr::Ref(e) => std::format!("&{}", unformatted(e)),
        Expr::Array(items) => std::format!("[{}]", join(items)),
        Expr::Tuple(items) if items.len() == 1 => std::format!("({},)", join(items)),
        Expr::Tuple(items) => std::format!("({})", join(items)),
        Expr::Struct(path, fields) => {
            let f: Vec<String> = fields
                .iter()
                .map(|(n, v)| std::format!("{n}: {}", unformatted(v)))
                .collect();
            std::format!("{path} {{ {} }}", f.join(", "))
        }
        Expr::Call(path, args) => std::format!("{path}({})", join(args)),
    }
}

/// A string literal of `text` (Rust's `{:?}` escapes) that breaks into lines of at most
/// [`MAX_WIDTH`] columns, the first starting at column `col`, its last leaving room for `";`.
/// Each break is a `\` continuation, which the string's value does not contain: the next line's
/// leading whitespace is skipped, so a line breaks only after a space or a `\n` escape that is
/// followed by something else than a space.
pub(crate) fn string_literal(text: &str, col: usize) -> String {
    let quoted = std::format!("{text:?}");
    let mut out = String::new();
    let mut line_start = col;
    let mut rest = quoted.as_str();
    // 2: `";` after the last line, or ` \` after a break's space.
    while line_start + width(rest) > MAX_WIDTH - 2 {
        let budget = MAX_WIDTH - 2 - line_start;
        let breaks = rest.char_indices().filter_map(|(i, c)| {
            let end = match c {
                ' ' => i + 1,
                // An escape when an odd number of backslashes precede it.
                'n' if rest[..i].chars().rev().take_while(|&b| b == '\\').count() % 2 == 1 => i + 1,
                _ => return None,
            };
            let next = rest[end..].chars().next();
            next.is_some_and(|n| n != ' ').then_some(end)
        });
        let Some(cut) = breaks
            .take_while(|&end| width(&rest[..end]) <= budget)
            .last()
        else {
            break;
        };
        out.push_str(&rest[..cut]);
        out.push_str("\\\n");
        out.push_str(&spaces(TAB));
        line_start = TAB;
        rest = &rest[cut..];
    }
    out.push_str(rest);
    out
}

/// Comment lines (`prefix` is `//` or `///`) at block indent `indent` holding `text`, wrapped
/// at spaces into lines of at most [`MAX_WIDTH`] columns. A line's leading spaces are kept; its
/// continuations are indented `hang` more, and with a hang a line broken once is broken where
/// its two halves come out most even.
pub(crate) fn comment(indent: usize, prefix: &str, text: &str, hang: usize) -> String {
    let mut out = String::new();
    for line in text.split('\n') {
        let lead = line.len() - line.trim_start_matches(' ').len();
        let first = std::format!("{}{prefix} {}", spaces(indent), &line[..lead]);
        let next = std::format!("{}{prefix} {}", spaces(indent), spaces(lead + hang));
        let words: Vec<&str> = line[lead..].split(' ').collect();
        let mut lines = fill(&words, &first, &next);
        if hang > 0 && lines.len() == 2 {
            lines = (1..words.len())
                .map(|k| {
                    std::vec![
                        std::format!("{first}{}", words[..k].join(" ")),
                        std::format!("{next}{}", words[k..].join(" ")),
                    ]
                })
                .filter(|ls| ls.iter().all(|l| width(l) <= MAX_WIDTH))
                .min_by_key(|ls| ls.iter().map(|l| width(l)).max())
                .unwrap_or(lines);
        }
        for l in lines {
            out.push_str(l.trim_end());
            out.push('\n');
        }
    }
    out
}

/// `words` filled into lines of at most [`MAX_WIDTH`] columns, the first starting with `first`,
/// the others with `next` (a word longer than a line has a line of its own).
fn fill(words: &[&str], first: &str, next: &str) -> Vec<String> {
    let mut lines = Vec::new();
    let mut current = String::from(first);
    let mut empty = true;
    for word in words {
        if !empty && width(&current) + 1 + width(word) > MAX_WIDTH {
            lines.push(core::mem::replace(&mut current, String::from(next)));
            empty = true;
        }
        if !empty {
            current.push(' ');
        }
        current.push_str(word);
        empty = false;
    }
    lines.push(current);
    lines
}
