//! The coarse sums with the DSP extension's `SMLAD` (Armv7E-M: Cortex-M4, M7, M33 with DSP), a
//! dual 16 × 16-bit multiply-accumulate that stable Rust reaches only by inline assembly: the
//! weights packed for it (part of every set, so that a set means the same on every target), the
//! assembly (cfg `arm_dsp`, which the build script sets for thumbv7em targets, where the
//! instruction always exists), and in the tests its portable model.

// Unsafe code only in the two functions of inline assembly, on Armv7E-M.
#![deny(unsafe_code)]

#[cfg(arm_dsp)]
use super::curve::INDEX_LEN;
#[cfg(arm_dsp)]
use core::arch::asm;

/// The coarse weights `cᵢ = Vᵢ >> 16` packed for a dual 16 × 16-bit multiply-accumulate
/// (Armv7E-M's `SMLAD`), which multiplies signed halves. The counts are unsigned, so they go in
/// as `xᵢ − 32768` (a u16 with its top bit flipped, read as i16), and the head adds back what
/// that took away: `Σᵢ cᵢ xᵢ = 32768 · Σᵢ cᵢ + Σᵢ cᵢ (xᵢ − 32768)`. Nothing overflows: |cᵢ| <
/// 2¹⁵ (so cᵢ is an i16), |xᵢ − 32768| ≤ 2¹⁵, and every partial sum, in any order, is
/// `Σ cᵢ xᵢ` over the samples taken plus `32768 · Σ cᵢ` over the others, at most
/// `Σᵢ |cᵢ| · 65535` in magnitude: inside the bound new() proved for `h`. Likewise the total's.
#[repr(C, align(4))]
#[derive(Debug, Clone, Copy)]
pub(super) struct Packed<const N: usize> {
    /// `32768 · Σᵢ cᵢ` per channel (R, G, B), then `32768 · n`, the start of `Σᵢ xᵢ` (to which
    /// a multiply-accumulate by 1 adds each `xᵢ − 32768`), over the n = 2 · ⌊N / 2⌋ samples
    /// in pairs (an odd N's last sample is added as it is).
    head: [i32; 4],
    /// In pairs of samples (2k, 2k + 1), for k below N / 2: three words, R, G and B, each
    /// `c₂ₖ` in its low half and `c₂ₖ₊₁` in its high half, as halves `6k + 2·channel + 0/1`
    /// of this array read flat (three halves per entry). An odd N's last sample is not here.
    halves: [[i16; 3]; N],
}

impl<const N: usize> Packed<N> {
    pub(super) const fn new(coarse: &[[i32; N]; 3]) -> Packed<N> {
        let mut head = [0i32; 4];
        let mut halves = [[0i16; 3]; N];
        let mut c = 0;
        while c < 3 {
            let mut i = 0;
            while i < N {
                // |cᵢ| < 2¹⁵ (new()'s bound), so both casts are exact and |Σᵢ cᵢ| · 32768 is
                // within the same bound.
                if i < N / 2 * 2 {
                    head[c] += coarse[c][i] * 32768;
                    let flat = 6 * (i / 2) + 2 * c + i % 2;
                    halves[flat / 3][flat % 3] = coarse[c][i] as i16;
                }
                i += 1;
            }
            c += 1;
        }
        head[3] = (N / 2 * 2) as i32 * 32768;
        Packed { head, halves }
    }

    /// Word `3k + channel` of the pairs (k < N / 2), as `SMLAD` reads it from memory.
    #[cfg(test)]
    fn pair_word(&self, k: usize, c: usize) -> u32 {
        let half = |flat: usize| u32::from(self.halves[flat / 3][flat % 3] as u16);
        let flat = 6 * k + 2 * c;
        half(flat) | half(flat + 1) << 16
    }
}

/// `[Σᵢ c_Rᵢ xᵢ, Σᵢ c_Gᵢ xᵢ, Σᵢ c_Bᵢ xᵢ, Σᵢ xᵢ]` over the samples in pairs (an odd N's last
/// sample is left to the caller), exactly: see [`Packed`] for why nothing overflows.
#[cfg(arm_dsp)]
#[allow(unsafe_code)]
#[inline(always)]
pub(super) fn pair_sums<const N: usize>(packed: &Packed<N>, x: &[u16; N]) -> [i32; 4] {
    let mut p = (packed as *const Packed<N>).cast::<u32>();
    let (mut h0, mut h1, mut h2, mut t): (i32, i32, i32, i32);
    // SAFETY: reads the head, the first 16 bytes at p (a 4-byte aligned `Packed`, head
    // first), and leaves p at the pairs; no store, no stack, no flags.
    unsafe {
        asm!(
            "ldrd {h0}, {h1}, [{p}], #8",
            "ldrd {h2}, {t}, [{p}], #8",
            p = inout(reg) p,
            h0 = out(reg) h0,
            h1 = out(reg) h1,
            h2 = out(reg) h2,
            t = out(reg) t,
            options(pure, readonly, nostack, preserves_flags),
        );
    }
    let ones = 0x0001_0001u32;
    // Both counts of a pair less 32768: the top bit of each half flipped.
    let biased = |pair: &[u16; 2]| (u32::from(pair[0]) | u32::from(pair[1]) << 16) ^ 0x8000_8000;
    let (quads, rest) = x.as_chunks::<4>();
    for quad in quads {
        let (x01, x23) = (biased(&[quad[0], quad[1]]), biased(&[quad[2], quad[3]]));
        // SAFETY: reads two pairs' six words at p (24 bytes: N / 2 pairs follow the
        // head, and this loop and the next take them in order, all 4-byte aligned) and
        // leaves p at the next pair; no store, no stack. SMLAD sets only the Q flag (on
        // overflow, which cannot happen here).
        unsafe {
            asm!(
                "ldrd {w0}, {w1}, [{p}], #8",
                "smlad {h0}, {x01}, {w0}, {h0}",
                "smlad {h1}, {x01}, {w1}, {h1}",
                "ldrd {w0}, {w1}, [{p}], #8",
                "smlad {h2}, {x01}, {w0}, {h2}",
                "smlad {h0}, {x23}, {w1}, {h0}",
                "ldrd {w0}, {w1}, [{p}], #8",
                "smlad {h1}, {x23}, {w0}, {h1}",
                "smlad {h2}, {x23}, {w1}, {h2}",
                "smlad {t}, {x01}, {ones}, {t}",
                "smlad {t}, {x23}, {ones}, {t}",
                p = inout(reg) p,
                x01 = in(reg) x01,
                x23 = in(reg) x23,
                ones = in(reg) ones,
                h0 = inout(reg) h0,
                h1 = inout(reg) h1,
                h2 = inout(reg) h2,
                t = inout(reg) t,
                w0 = out(reg) _,
                w1 = out(reg) _,
                options(pure, readonly, nostack),
            );
        }
    }
    for pair in rest.as_chunks::<2>().0 {
        let x01 = biased(pair);
        // SAFETY: reads the pair's three words at p (as above) and leaves p after them.
        unsafe {
            asm!(
                "ldrd {w0}, {w1}, [{p}], #8",
                "ldr {w2}, [{p}], #4",
                "smlad {h0}, {x01}, {w0}, {h0}",
                "smlad {h1}, {x01}, {w1}, {h1}",
                "smlad {h2}, {x01}, {w2}, {h2}",
                "smlad {t}, {x01}, {ones}, {t}",
                p = inout(reg) p,
                x01 = in(reg) x01,
                ones = in(reg) ones,
                h0 = inout(reg) h0,
                h1 = inout(reg) h1,
                h2 = inout(reg) h2,
                t = inout(reg) t,
                w0 = out(reg) _,
                w1 = out(reg) _,
                w2 = out(reg) _,
                options(pure, readonly, nostack),
            );
        }
    }
    [h0, h1, h2, t]
}

/// `limits[clamp(h >> S, 0, 4095)]`: the limit of the stretch of a coarse sum `h` on the
/// scale `2^(S + 12)` (P = S + 28), in two instructions (USAT clamps after the shift).
#[cfg(arm_dsp)]
#[allow(unsafe_code)]
#[inline(always)]
pub(super) fn limit<const S: u32>(limits: &[i32; INDEX_LEN], h: i32) -> i32 {
    let limit: i32;
    // SAFETY: USAT leaves j in 0..=4095, so the load reads one of the 4096 entries of
    // `limits` (4-byte aligned); no store, no stack. USAT sets only the Q flag.
    unsafe {
        asm!(
            "usat {j}, #12, {h}, asr #{s}",
            "ldr {limit}, [{base}, {j}, lsl #2]",
            h = in(reg) h,
            base = in(reg) limits.as_ptr(),
            j = out(reg) _,
            limit = lateout(reg) limit,
            s = const S,
            options(pure, readonly, nostack),
        );
    }
    limit
}

#[cfg(test)]
mod tests {
    use crate::integer::curve::INDEX_SHIFT;
    use crate::integer::fixed_point::mac;
    use crate::{FoldedSet, IntegerSet};

    /// On Armv7E-M the stretch is `USAT #12` of `h >> (P − 28)` (`dsp::limit`), elsewhere the
    /// key's top bits: the same entry for every h, at P = 45 and 46 (the two it is used for).
    #[test]
    fn the_clamped_shift_finds_the_keys_stretch() {
        for p in [45u32, 46] {
            let one = 1i32 << (p - 16);
            let usat12 = |h: i32| (h >> (p - 28)).clamp(0, 4095) as usize;
            let by_key =
                |h: i32| (((h.clamp(0, one - 1) as u32) << (47 - p)) >> INDEX_SHIFT) as usize;
            let mut state = 0x243f_6a88_85a3_08d3u64;
            let mut values = std::vec![
                i32::MIN,
                i32::MIN + 1,
                -one,
                -1,
                0,
                1,
                one - 1,
                one,
                one + 1
            ];
            values.extend([
                i32::MAX - 1,
                i32::MAX,
                (one >> 12) - 1,
                one >> 12,
                one >> 12 | 1,
            ]);
            // Miri runs about a million times slower: fewer there.
            for _ in 0..if cfg!(miri) { 300 } else { 100_000 } {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                values.push(state as i32 >> (state >> 59));
            }
            for h in values {
                assert_eq!(usat12(h), by_key(h), "P {p}, h {h}");
            }
        }
    }

    /// `SMLAD` as the Arm architecture defines it: `acc` plus the products of the signed low
    /// halves and of the signed high halves, computed exactly; the result must fit i32 (else
    /// the instruction would wrap and set the Q flag).
    fn smlad(a: u32, b: u32, acc: i32) -> i32 {
        let half = |v: u32, k: u32| i64::from((v >> (16 * k)) as u16 as i16);
        let r = i64::from(acc) + half(a, 0) * half(b, 0) + half(a, 1) * half(b, 1);
        i32::try_from(r).expect("SMLAD overflows")
    }

    /// `dsp::pair_sums` in portable Rust: the same words, the same instructions in the same
    /// order (the quads' interleaving, then a last pair, then an odd N's last sample).
    fn pair_sums_emulated<const N: usize>(set: &IntegerSet<N>, x: &[u16; N]) -> ([i32; 3], i32) {
        let packed = &set.packed;
        let [mut h0, mut h1, mut h2, mut t] = packed.head;
        let ones = 0x0001_0001;
        let biased = |i: usize| (u32::from(x[i]) | u32::from(x[i + 1]) << 16) ^ 0x8000_8000;
        let w = |k: usize, c: usize| packed.pair_word(k, c);
        for q in 0..N / 4 {
            let (x01, x23) = (biased(4 * q), biased(4 * q + 2));
            h0 = smlad(x01, w(2 * q, 0), h0);
            h1 = smlad(x01, w(2 * q, 1), h1);
            h2 = smlad(x01, w(2 * q, 2), h2);
            h0 = smlad(x23, w(2 * q + 1, 0), h0);
            h1 = smlad(x23, w(2 * q + 1, 1), h1);
            h2 = smlad(x23, w(2 * q + 1, 2), h2);
            t = smlad(x01, ones, t);
            t = smlad(x23, ones, t);
        }
        if N % 4 >= 2 {
            let k = N / 2 - 1;
            let x01 = biased(2 * k);
            h0 = smlad(x01, w(k, 0), h0);
            h1 = smlad(x01, w(k, 1), h1);
            h2 = smlad(x01, w(k, 2), h2);
            t = smlad(x01, ones, t);
        }
        let mut acc = [h0, h1, h2, t];
        if N % 2 == 1 {
            let [w0, w1, w2] = &set.coarse;
            mac(&mut acc, x[N - 1], w0[N - 1], w1[N - 1], w2[N - 1]);
        }
        ([acc[0], acc[1], acc[2]], acc[3])
    }

    /// The plain coarse sums, `Σᵢ cᵢ xᵢ` and `Σᵢ xᵢ`, in i64 (no overflow to hide).
    fn plain_sums<const N: usize>(set: &IntegerSet<N>, x: &[u16; N]) -> ([i32; 3], i32) {
        let sum = |w: &[i32; N]| {
            (0..N)
                .map(|i| i64::from(w[i]) * i64::from(x[i]))
                .sum::<i64>()
        };
        let h = set
            .coarse
            .each_ref()
            .map(|w| i32::try_from(sum(w)).unwrap());
        (h, x.iter().map(|&v| i32::from(v)).sum())
    }

    /// The packed weights and their head, through SMLAD as Armv7E-M runs it, give the plain
    /// coarse sums (and so does the portable path), with no intermediate overflow: on the
    /// extreme counts (0, 32767, 32768 and 65535 in every combination that makes a sum
    /// largest or smallest) and on random ones.
    fn check_packed<const N: usize>(name: &str, set: &IntegerSet<N>) -> usize {
        let mut inputs: std::vec::Vec<[u16; N]> = std::vec::Vec::new();
        for c in 0..3 {
            // Largest and smallest h: full scale where the weight is positive (negative).
            for sign in [1, -1] {
                inputs.push(core::array::from_fn(|i| {
                    if set.coarse[c][i] * sign > 0 {
                        u16::MAX
                    } else {
                        0
                    }
                }));
            }
        }
        for v in [0, 1, 0x7fff, 0x8000, 0x8001, u16::MAX] {
            inputs.push([v; N]);
        }
        let mut state = 0x9e37_79b9_7f4a_7c15u64 ^ N as u64;
        for _ in 0..if cfg!(miri) { 10 } else { 2_000 } {
            inputs.push(core::array::from_fn(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                let x = (state >> 48) as u16;
                // A quarter at the ends of the range, where the halves' signs flip.
                match state % 8 {
                    0 => u16::MAX - (x & 3),
                    1 => x & 3,
                    _ => x >> (state % 5),
                }
            }));
        }
        for x in &inputs {
            let plain = plain_sums(set, x);
            assert_eq!(pair_sums_emulated(set, x), plain, "{name} {x:?}");
            assert_eq!(set.coarse_sums(x), plain, "{name} {x:?}");
        }
        inputs.len()
    }

    macro_rules! check_packed_baked {
        ($($name:ident,)*) => {{
            let mut n = 0;
            $(
                check_packed(stringify!($name), &crate::tables::integer::$name);
                n += 1;
            )*
            n
        }};
    }

    #[test]
    fn the_packed_weights_give_the_coarse_sums_for_every_baked_set() {
        // The build's own list of the integer sets it baked.
        let n = crate::tables::integer::all!(check_packed_baked);
        assert_eq!(n, crate::tables::integer::NAMES.len());
        // The list holds every integer set the build baked.
        let baked = include_str!(concat!(env!("OUT_DIR"), "/tables.rs"));
        assert_eq!(baked.matches(": IntegerSet<").count(), n);
    }

    /// Sets made at run time, at other sizes (odd ones, whose last sample is not paired) and
    /// other P, with weights whose coarse form nearly fills the bound, of both signs.
    #[test]
    fn the_packed_weights_give_the_coarse_sums_for_sets_made_at_run_time() {
        fn made<const N: usize>(scale: f32, seed: u64) -> IntegerSet<N> {
            let mut state = seed;
            let weights = [0, 1, 2].map(|_| {
                core::array::from_fn(|_| {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    ((state >> 40) as f32 / (1u64 << 24) as f32 - 0.5) * scale
                })
            });
            let base = crate::tables::folded::TABLE2_ROW2_SRGB;
            // The wavelengths are not read by the integer path: any N, one value.
            let folded =
                FoldedSet::<N>::from_checked([550.0; N], weights, base.samples(), base.display());
            IntegerSet::new(&folded, 1.0 / 65535.0).unwrap()
        }
        let mut frac_bits = std::collections::BTreeSet::new();
        for (k, scale) in [0.01f32, 1.0, 3.0, 40.0, 150.0].into_iter().enumerate() {
            let seed = 0x5851_f42d_4c95_7f2d ^ k as u64;
            macro_rules! run {
                ($($n:literal),*) => {$({
                    let set = made::<$n>(scale, seed);
                    frac_bits.insert(set.frac_bits);
                    check_packed(stringify!($n), &set);
                })*};
            }
            run!(1, 2, 3, 4, 5, 6, 7, 8, 9, 12, 16);
        }
        // P from the cap down to well below the two the Armv7E-M limit has a shift for.
        assert!(frac_bits.len() >= 5, "{frac_bits:?}");
    }
}
