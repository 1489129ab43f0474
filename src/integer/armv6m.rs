//! The batch's loop on Armv6-M (Cortex-M0, M0+) at N = 4, by inline assembly (cfg `arm_v6m`,
//! which the build script sets for thumbv6m targets): each pixel's coarse sums (the weights
//! two or three an `LDM`) and each channel by the first ways of `set`'s portable
//! `encode_channel` (the limit of its stretch, and the threshold after the next); at the first
//! channel that needs `settle` it returns, for `set` to finish that pixel and call it again.
//! The compiler's own code for the same steps spills to the stack: the M0 has eight low
//! registers, and here all eight hold values (r6 and r7 saved first).

// Unsafe code only in the one function of inline assembly, on Armv6-M.
#![deny(unsafe_code)]

#[cfg(all(target_arch = "arm", arm_v6m))]
use super::curve::IntegerCurve;
#[cfg(all(target_arch = "arm", arm_v6m))]
use core::arch::asm;

/// The pixels of `counts` into `out`, from the first, each pixel's coarse sums (`h` for the
/// three channels and the total `Σᵢ xᵢ`, as `set::coarse_sums`) and, for the channels 0, 1,
/// 2 in turn, the code that `encode_channel`'s first tests settle: 255 for h at or above 1.0;
/// the low byte of the limit (of the first stretch for h below 0, of h's stretch inside) when
/// `h + total` on the 2³⁰ scale is below it; inside 0..1.0, one more when h is at or above the
/// threshold after it and `h + total` below the next (as `code_at_limit`). It stops at the
/// first channel none of these settles and returns the pixel's index and the channel's, with
/// the pixel's `[h₀, h₁, h₂, total]` in `sums` (the channels before it stored); `(n, 3)` when
/// it stored all n pixels.
///
/// `S` is `P − 28` for a set of P fractional bits, 1 ≤ S ≤ 18 (P from 29 to 46): h's stretch
/// is `h >> S`, 1.0 is `2^(S + 12)`, `h + total` shifted left by `18 − S` (wrapping, as
/// `top30`) is on the 2³⁰ scale and shifted by `19 − S` on the 2³¹ scale of the thresholds.
/// The bound `IntegerSet::new` proved (no sum overflows i32) covers every step: the partial
/// sums, in any order, are exact.
#[cfg(all(target_arch = "arm", arm_v6m))]
#[allow(unsafe_code)]
#[inline(always)]
pub(super) fn run4<const S: u32>(
    coarse: &[[i32; 4]; 3],
    curve: &IntegerCurve,
    counts: &[[u16; 4]],
    out: &mut [[u8; 3]],
    sums: &mut [i32; 4],
) -> (usize, usize) {
    let n = counts.len().min(out.len());
    if n == 0 {
        return (0, 3);
    }
    let first = counts.as_ptr();
    let stop: *const [u16; 4];
    let k: usize;
    // SAFETY: for each of the n pixels from `first` (n ≥ 1, and `out` has n too) it reads the
    // 4 counts (2-byte aligned), the 12 weights at `coarse` (4-byte aligned, contiguous, R0..R3,
    // G0..G3, B0..B3) and entries of the curve (`repr(C)`, 4-byte aligned): one of the 4096
    // limits (the index is h >> S for 0 ≤ h < 2^(S + 12), below 4096, or 0) and, after the
    // limits, entries code + 1 and code + 2 ≤ 257 of the 258 thresholds. It writes bytes 0..=2
    // of the pixel's 3 in `out`, and `sums` on leaving early. It saves r6 and r7 on the stack
    // with four words it reads there (24 bytes: the weights', the limits', the thresholds' and
    // `sums`' addresses) and restores them; every other register it changes is an output or
    // a clobber.
    unsafe {
        asm!(
            "mov r10, r4",
            "movs r4, #1",
            "lsls r4, r4, #14",
            "adds r4, r4, r3",
            "push {{r1, r3, r4, r5, r6, r7}}",
            "mov r12, r2",
            // A pixel: the counts at r0 (kept in r9), the total into lr.
            "20:",
            "mov r9, r0",
            "ldrh r2, [r0, #0]",
            "ldrh r3, [r0, #2]",
            "ldrh r4, [r0, #4]",
            "ldrh r5, [r0, #6]",
            "adds r0, r2, r3",
            "adds r0, r0, r4",
            "adds r0, r0, r5",
            "mov lr, r0",
            // R into r8: w0 x0 + w1 x1 + w2 x2 + w3 x3 (the second LDM takes G's w0 too).
            "ldr r1, [sp, #0]",
            "ldm r1!, {{r0, r6, r7}}",
            "muls r0, r2, r0",
            "muls r6, r3, r6",
            "adds r0, r0, r6",
            "muls r7, r4, r7",
            "adds r0, r0, r7",
            "ldm r1!, {{r6, r7}}",
            "muls r6, r5, r6",
            "adds r0, r0, r6",
            "mov r8, r0",
            // G in r7 (its second LDM takes B's w0 too).
            "muls r7, r2, r7",
            "ldm r1!, {{r0, r6}}",
            "muls r0, r3, r0",
            "adds r7, r7, r0",
            "muls r6, r4, r6",
            "adds r7, r7, r6",
            "ldm r1!, {{r0, r6}}",
            "muls r0, r5, r0",
            "adds r7, r7, r0",
            // B in r6.
            "muls r6, r2, r6",
            "ldm r1!, {{r0, r2}}",
            "muls r0, r3, r0",
            "adds r6, r6, r0",
            "muls r2, r4, r2",
            "adds r6, r6, r2",
            "ldr r1, [r1, #0]",
            "muls r1, r5, r1",
            "adds r6, r6, r1",
            // The channels: r1 the curve (its limits first), r3 the pixel's bytes, r5 the
            // total; h in r2, r7, r6. Outside 0..1.0, h takes 25 (35, 45).
            "ldr r1, [sp, #4]",
            "mov r3, r12",
            "mov r2, r8",
            "mov r5, lr",
            "lsrs r0, r2, #{range}",
            "bne 25f",
            "lsrs r0, r2, #{s}",
            "lsls r0, r0, #2",
            "ldr r0, [r1, r0]",
            "adds r4, r2, r5",
            "lsls r4, r4, #{top}",
            "cmp r4, r0",
            "bge 26f",
            "23:",
            "strb r0, [r3, #0]",
            "lsrs r0, r7, #{range}",
            "bne 35f",
            "lsrs r0, r7, #{s}",
            "lsls r0, r0, #2",
            "ldr r0, [r1, r0]",
            "adds r4, r7, r5",
            "lsls r4, r4, #{top}",
            "cmp r4, r0",
            "bge 36f",
            "33:",
            "strb r0, [r3, #1]",
            "lsrs r0, r6, #{range}",
            "bne 45f",
            "lsrs r0, r6, #{s}",
            "lsls r0, r0, #2",
            "ldr r0, [r1, r0]",
            "adds r4, r6, r5",
            "lsls r4, r4, #{top}",
            "cmp r4, r0",
            "bge 46f",
            "43:",
            "strb r0, [r3, #2]",
            // The next pixel.
            "adds r3, r3, #3",
            "mov r12, r3",
            "mov r0, r9",
            "adds r0, #8",
            "cmp r0, r10",
            "bne 20b",
            "movs r1, #3",
            "59:",
            "pop {{r2, r3, r4, r5, r6, r7}}",
            "b 69f",
            // Out of 0..1.0: at or above 1.0 code 255, below 0 the first stretch's limit.
            "25:",
            "cmp r2, #0",
            "blt 27f",
            "movs r0, #255",
            "b 23b",
            "27:",
            "ldr r0, [r1, #0]",
            "adds r4, r2, r5",
            "lsls r4, r4, #{top}",
            "cmp r4, r0",
            "bge 52f",
            "b 23b",
            "35:",
            "cmp r7, #0",
            "blt 37f",
            "movs r0, #255",
            "b 33b",
            "37:",
            "ldr r0, [r1, #0]",
            "adds r4, r7, r5",
            "lsls r4, r4, #{top}",
            "cmp r4, r0",
            "bge 53f",
            "b 33b",
            "45:",
            "cmp r6, #0",
            "blt 47f",
            "movs r0, #255",
            "b 43b",
            "47:",
            "ldr r0, [r1, #0]",
            "adds r4, r6, r5",
            "lsls r4, r4, #{top}",
            "cmp r4, r0",
            "bge 54f",
            "b 43b",
            // Not settled at the limit, h inside 0..1.0: the threshold after the next, with
            // r3, r4 and r5 (r3 and r5 taken back from r12 and lr). `top30` is in r4, so
            // `top` on the 2³¹ scale is r4 shifted by one more (h inside 0..1.0 and the total
            // are not negative, and `h + total` < 2 · 1.0: no bit is lost).
            "26:",
            "lsls r3, r4, #1",
            "lsls r4, r0, #24",
            "lsrs r4, r4, #22",
            "ldr r5, [sp, #8]",
            "adds r4, r4, r5",
            "ldr r5, [r4, #8]",
            "cmp r3, r5",
            "bhs 52f",
            "ldr r5, [r4, #4]",
            "lsls r3, r2, #{shift}",
            "cmp r3, r5",
            "blo 52f",
            "adds r0, r0, #1",
            "mov r3, r12",
            "mov r5, lr",
            "b 23b",
            "36:",
            "lsls r3, r4, #1",
            "lsls r4, r0, #24",
            "lsrs r4, r4, #22",
            "ldr r5, [sp, #8]",
            "adds r4, r4, r5",
            "ldr r5, [r4, #8]",
            "cmp r3, r5",
            "bhs 53f",
            "ldr r5, [r4, #4]",
            "lsls r3, r7, #{shift}",
            "cmp r3, r5",
            "blo 53f",
            "adds r0, r0, #1",
            "mov r3, r12",
            "mov r5, lr",
            "b 33b",
            "46:",
            "lsls r3, r4, #1",
            "lsls r4, r0, #24",
            "lsrs r4, r4, #22",
            "ldr r5, [sp, #8]",
            "adds r4, r4, r5",
            "ldr r5, [r4, #8]",
            "cmp r3, r5",
            "bhs 54f",
            "ldr r5, [r4, #4]",
            "lsls r3, r6, #{shift}",
            "cmp r3, r5",
            "blo 54f",
            "adds r0, r0, #1",
            "mov r3, r12",
            "mov r5, lr",
            "b 43b",
            // None settles channel c: leave with c, the pixel and its sums.
            "52:",
            "movs r1, #0",
            "b 58f",
            "53:",
            "movs r1, #1",
            "b 58f",
            "54:",
            "movs r1, #2",
            "58:",
            "ldr r4, [sp, #12]",
            "str r2, [r4, #0]",
            "str r7, [r4, #4]",
            "str r6, [r4, #8]",
            "mov r0, lr",
            "str r0, [r4, #12]",
            "mov r0, r9",
            "b 59b",
            "69:",
            range = const S + 12,
            s = const S,
            top = const 18 - S,
            shift = const 19 - S,
            inout("r0") first => stop,
            inout("r1") coarse.as_ptr() => k,
            inout("r2") out.as_mut_ptr() => _,
            inout("r3") (curve as *const IntegerCurve) => _,
            inout("r4") first.wrapping_add(n) => _,
            inout("r5") sums.as_mut_ptr() => _,
            out("r8") _,
            out("r9") _,
            out("r10") _,
            out("r12") _,
            out("lr") _,
        );
    }
    ((stop as usize - first as usize) / 8, k)
}
