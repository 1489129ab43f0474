//! What the AVX2 and AVX-512 loops share: where the planar loops start their steps, so that a
//! group reads each plane's cache lines once ([`on_lines`]), the drivers that run a loop's
//! steps from there ([`srgb8_from_lines`], [`linear_from_lines`]), and the fence that orders
//! the streaming loops' non-temporal stores ([`StoreFence`]). A leaf below both loops: they
//! import nothing from `mod.rs`, whose dispatch calls them.

/// Orders the non-temporal stores made before it is dropped (`sfence`), on every way out of
/// the scope that holds it, a panic's unwinding included. The streaming loops hold one from
/// their first non-temporal store on: nothing between that store and the end of the loop is
/// meant to panic (the only panics there are `debug_assert!`s of invariants), and the guard
/// makes that matter not at all, so that no store is left unordered whatever happens.
pub(super) struct StoreFence;

impl Drop for StoreFence {
    #[inline]
    fn drop(&mut self) {
        // Non-temporal stores are weakly ordered: this orders them before every store that
        // follows, as ordinary stores are (another thread that synchronizes with this one
        // afterwards sees the output).
        // SAFETY: `sfence` is an SSE instruction, and SSE is part of x86-64.
        unsafe { core::arch::x86_64::_mm_sfence() };
    }
}

/// Runs an accelerated planar sRGB 8-bit loop, `steps` (whole steps of `unit` pixels from the
/// start of the planes and output it is given; it returns how many pixels it wrote), once at
/// the planes' start and then from [`on_lines`]. The planes are light by light (L = 1 for a
/// folded set's N planes; a light-group set's N planes per light). Returns how many pixels were
/// written in all: all but fewer than `unit`, or 0 below `unit`. The pixels in between are
/// computed twice, to the same values.
#[inline]
pub(super) fn srgb8_from_lines<const N: usize, const L: usize>(
    planes: [[&[f32]; N]; L],
    out: &mut [u8],
    unit: usize,
    line: usize,
    mut steps: impl FnMut([[&[f32]; N]; L], &mut [u8]) -> usize,
) -> usize {
    let pixels = planes
        .as_flattened()
        .iter()
        .map(|p| p.len())
        .fold(out.len() / 3, usize::min);
    let head = on_lines(planes.as_flattened(), pixels, unit, line);
    if head > 0 {
        steps(cut(planes, 0, unit), &mut out[..3 * unit]);
    }
    head + steps(cut(planes, head, usize::MAX), &mut out[3 * head..])
}

/// As [`srgb8_from_lines`], for a planar linear loop: `steps`' last argument is whether it
/// runs the step at the planes' start (which is not worth streaming).
#[inline]
pub(super) fn linear_from_lines<const N: usize, const L: usize>(
    planes: [[&[f32]; N]; L],
    out: [&mut [f32]; 3],
    unit: usize,
    line: usize,
    mut steps: impl FnMut([[&[f32]; N]; L], [&mut [f32]; 3], bool) -> usize,
) -> usize {
    let pixels = planes
        .as_flattened()
        .iter()
        .map(|p| p.len())
        .fold(out.iter().map(|o| o.len()).min().unwrap_or(0), usize::min);
    let head = on_lines(planes.as_flattened(), pixels, unit, line);
    let [r, g, b] = out;
    if head > 0 {
        let first = [&mut r[..unit], &mut g[..unit], &mut b[..unit]];
        steps(cut(planes, 0, unit), first, true);
    }
    let rest = [&mut r[head..], &mut g[head..], &mut b[head..]];
    head + steps(cut(planes, head, usize::MAX), rest, false)
}

/// Every plane from `from` on, at most `len` values of it. The callers' `from` and `len` lie
/// inside every plane (below the number of pixels they found).
#[inline]
fn cut<const N: usize, const L: usize>(
    planes: [[&[f32]; N]; L],
    from: usize,
    len: usize,
) -> [[&[f32]; N]; L] {
    planes.map(|light| light.map(|p| &p[from..from.saturating_add(len).min(p.len())]))
}

/// Where an accelerated planar loop starts its steps of `unit` pixels: the pixel from which
/// the most planes start a `line`-byte boundary (0, or the first such pixel in plane order,
/// where several tie), where that is below `unit` and `pixels` holds a step after it; else 0.
///
/// A 64-byte line of a plane read from such a boundary is read by one group of pixels, not
/// two. Planes in separate allocations (which start 16 bytes past a page with glibc) are read
/// faster that way from memory at every width, while the streaming bound over the same bytes
/// does not change (`soa/srgb_u8_aligned` in the bench; docs/performance.md has the figures).
#[inline]
fn on_lines(planes: &[&[f32]], pixels: usize, unit: usize, line: usize) -> usize {
    // Pixels to each plane's first boundary (f32 are 4-byte aligned: 0..line / 4, below 16
    // for the lines of 32 and 64 bytes the loops take), and how many planes have each.
    let to_line = |p: &&[f32]| p.as_ptr().align_offset(line);
    let mut votes = [0usize; 16];
    for h in planes.iter().map(to_line) {
        if let Some(v) = votes.get_mut(h) {
            *v += 1;
        }
    }
    let votes = |h: usize| votes.get(h).copied().unwrap_or(0);
    let head = planes
        .iter()
        .map(to_line)
        .fold(0, |best, h| if votes(h) > votes(best) { h } else { best });
    if head < unit && pixels >= head + unit {
        head
    } else {
        0
    }
}
