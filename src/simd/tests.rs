//! Every loop against the scalar per-pixel form, forced one by one (the public functions
//! pick one by the CPU, so on an AVX2 machine they would never run the portable loops on
//! whole chunks): bit for bit for linear output (NaN against NaN), byte for byte for sRGB.

use crate::pixel::{mat_vec, mat_vec_for_encoding};
use crate::simd::forced::{force, take_ran, Loops, Ran};
use crate::tables::folded::{KQ_C_8_SRGB, TABLE2_ROW1_SRGB, TABLE2_ROW2_SRGB};
use crate::test_inputs::{skipped, Rng, EDGES};
use crate::GamutMapping;

/// A sample: mostly reflectance-like, the rest negative, any bit pattern, or an edge.
fn sample(rng: &mut Rng) -> f32 {
    match rng.next() % 10 {
        0 => -rng.unit(),
        1 => f32::from_bits(rng.next() as u32),
        2 => EDGES[(rng.next() % EDGES.len() as u64) as usize],
        _ => 1.2 * rng.unit(),
    }
}

/// What the loops compute, for a folded set (one light) and a light-group set (L lights): the
/// weights light by light, the per-pixel functions, the scalar references and the public batch
/// and planar functions, so that one check runs every loop on either.
trait Subject<const N: usize, const L: usize> {
    fn weights(&self) -> &[[[f32; N]; 3]; L];
    /// The per-pixel sRGB 8-bit function (`Clip`; SSE2 on x86-64).
    fn encode_u8(&self, px: &[[f32; N]; L]) -> [u8; 3];
    fn encode_u16(&self, px: &[[f32; N]; L]) -> [u16; 3];
    /// The scalar reference, as on a target without vector code: each light's product (light 0
    /// from its first product, `pixel::mat_vec_for_encoding`, the others from 0.0,
    /// `pixel::mat_vec`), added in light order, then the scalar `Display::encode_u8`.
    fn reference(&self, px: &[[f32; N]; L]) -> [u8; 3];
    fn encode_u8_planar(&self, planes: [[&[f32]; N]; L], out: &mut [[u8; 3]]);
    fn encode_u8_batch(&self, px: &[[[f32; N]; L]], out: &mut [[u8; 3]]);
    fn encode_u16_batch(&self, px: &[[[f32; N]; L]], out: &mut [[u16; 3]]);
    fn linear_rgb_planar(&self, planes: [[&[f32]; N]; L], out: [&mut [f32]; 3]);
}

/// The scalar sum of the lights' products: light 0's by `first`, the others' by
/// `pixel::mat_vec`, added in light order.
fn sum_lights<const N: usize, const L: usize>(
    weights: &[[[f32; N]; 3]; L],
    px: &[[f32; N]; L],
    first: fn(&[[f32; N]; 3], &[f32; N]) -> [f32; 3],
) -> [f32; 3] {
    let mut rgb = [0.0f32; 3];
    for (l, (w, s)) in weights.iter().zip(px).enumerate() {
        let c = if l == 0 { first(w, s) } else { mat_vec(w, s) };
        rgb = if l == 0 {
            c
        } else {
            [rgb[0] + c[0], rgb[1] + c[1], rgb[2] + c[2]]
        };
    }
    rgb
}

/// The linear reference: `pixel::mat_vec` of every light from 0.0, added in light order.
fn linear_reference<const N: usize, const L: usize>(
    weights: &[[[f32; N]; 3]; L],
    px: &[[f32; N]; L],
) -> [f32; 3] {
    sum_lights(weights, px, mat_vec)
}

impl<const N: usize> Subject<N, 1> for crate::FoldedSet<N> {
    fn weights(&self) -> &[[[f32; N]; 3]; 1] {
        core::array::from_ref(self.weights_ref())
    }
    fn encode_u8(&self, px: &[[f32; N]; 1]) -> [u8; 3] {
        crate::FoldedSet::encode_u8(self, GamutMapping::Clip, &px[0])
    }
    fn encode_u16(&self, px: &[[f32; N]; 1]) -> [u16; 3] {
        crate::FoldedSet::encode_u16(self, GamutMapping::Clip, &px[0])
    }
    fn reference(&self, px: &[[f32; N]; 1]) -> [u8; 3] {
        self.display_ref().encode_u8(
            GamutMapping::Clip,
            mat_vec_for_encoding(self.weights_ref(), &px[0]),
        )
    }
    fn encode_u8_planar(&self, planes: [[&[f32]; N]; 1], out: &mut [[u8; 3]]) {
        let [planes] = planes;
        self.encode_u8_planar_to_interleaved(GamutMapping::Clip, planes, out)
            .unwrap();
    }
    fn encode_u8_batch(&self, px: &[[[f32; N]; 1]], out: &mut [[u8; 3]]) {
        crate::FoldedSet::encode_u8_batch(self, GamutMapping::Clip, px.as_flattened(), out)
            .unwrap();
    }
    fn encode_u16_batch(&self, px: &[[[f32; N]; 1]], out: &mut [[u16; 3]]) {
        crate::FoldedSet::encode_u16_batch(self, GamutMapping::Clip, px.as_flattened(), out)
            .unwrap();
    }
    fn linear_rgb_planar(&self, planes: [[&[f32]; N]; 1], out: [&mut [f32]; 3]) {
        let [planes] = planes;
        crate::FoldedSet::linear_rgb_planar(self, planes, out).unwrap();
    }
}

impl<const N: usize, const L: usize> Subject<N, L> for crate::LightGroupSet<N, L> {
    fn weights(&self) -> &[[[f32; N]; 3]; L] {
        self.weights_ref()
    }
    fn encode_u8(&self, px: &[[f32; N]; L]) -> [u8; 3] {
        crate::LightGroupSet::encode_u8(self, GamutMapping::Clip, px)
    }
    fn encode_u16(&self, px: &[[f32; N]; L]) -> [u16; 3] {
        crate::LightGroupSet::encode_u16(self, GamutMapping::Clip, px)
    }
    fn reference(&self, px: &[[f32; N]; L]) -> [u8; 3] {
        let rgb = sum_lights(self.weights_ref(), px, mat_vec_for_encoding);
        self.display_ref().encode_u8(GamutMapping::Clip, rgb)
    }
    fn encode_u8_planar(&self, planes: [[&[f32]; N]; L], out: &mut [[u8; 3]]) {
        self.encode_u8_planar_to_interleaved(GamutMapping::Clip, planes, out)
            .unwrap();
    }
    fn encode_u8_batch(&self, px: &[[[f32; N]; L]], out: &mut [[u8; 3]]) {
        crate::LightGroupSet::encode_u8_batch(self, GamutMapping::Clip, px, out).unwrap();
    }
    fn encode_u16_batch(&self, px: &[[[f32; N]; L]], out: &mut [[u16; 3]]) {
        crate::LightGroupSet::encode_u16_batch(self, GamutMapping::Clip, px, out).unwrap();
    }
    fn linear_rgb_planar(&self, planes: [[&[f32]; N]; L], out: [&mut [f32]; 3]) {
        crate::LightGroupSet::linear_rgb_planar(self, planes, out).unwrap();
    }
}

fn same_f32(a: f32, b: f32) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

/// The index in `buf` of the float `k % 16` floats past `buf`'s first 64-byte boundary:
/// where the tests put a plane that starts at that offset within a line (`buf` holds 31
/// floats more than the plane).
#[cfg(target_arch = "x86_64")]
fn past_line(buf: &[f32], k: usize) -> usize {
    buf.as_ptr().align_offset(64) + k % 16
}

/// One x86-64 form of the accelerated loops, as the tests force them.
#[cfg(target_arch = "x86_64")]
struct X86Loops<const N: usize, const L: usize> {
    name: &'static str,
    /// What `SPECTRAL_QUADRATURE_REQUIRE` calls the CPU feature the loops need.
    capability: &'static str,
    available: bool,
    /// Pixels per group of the sRGB loops.
    group: usize,
    planar: PlanarLoop<N, L>,
    batch: BatchLoop<N, L>,
    /// Whether the interleaved loop takes width N with L lights (it returns 0 for others).
    batch_takes: fn(usize, usize) -> bool,
    linear: LinearLoop<N, L>,
}

/// The accelerated planar sRGB loops' signature.
#[cfg(target_arch = "x86_64")]
type PlanarLoop<const N: usize, const L: usize> =
    unsafe fn(&[[[f32; N]; 3]; L], [[&[f32]; N]; L], &mut [u8]) -> usize;
/// The accelerated interleaved sRGB loops' signature.
#[cfg(target_arch = "x86_64")]
type BatchLoop<const N: usize, const L: usize> =
    unsafe fn(&[[[f32; N]; 3]; L], &[[[f32; N]; L]], &mut [u8]) -> usize;
/// The accelerated planar linear loops' signature (the last argument: `stream`).
#[cfg(target_arch = "x86_64")]
type LinearLoop<const N: usize, const L: usize> =
    unsafe fn(&[[[f32; N]; 3]; L], [[&[f32]; N]; L], [&mut [f32]; 3], bool) -> usize;

/// The AVX-512 and the AVX2 loops.
#[cfg(target_arch = "x86_64")]
fn x86_loops<const N: usize, const L: usize>() -> [X86Loops<N, L>; 2] {
    use super::{avx2, avx512};
    [
        X86Loops {
            name: "AVX-512",
            capability: capability(Loops::Avx512),
            available: avx512::available(),
            group: avx512::LANES,
            planar: avx512::encode_srgb8_planar::<N, L>,
            // The interleaved AVX-512 loop takes a folded set's pixels (one light).
            batch: |weights, px, out| match (L, weights.first()) {
                // SAFETY: the caller checked that the CPU has the loop's features.
                (1, Some(w)) => unsafe {
                    avx512::encode_srgb8_batch(w, px.as_flattened().as_flattened(), out)
                },
                _ => 0,
            },
            batch_takes: |n, l| l == 1 && avx512::BATCH_WIDTHS.contains(&n),
            linear: avx512::linear_planar::<N, L>,
        },
        X86Loops {
            name: "AVX2",
            capability: capability(Loops::Avx2),
            available: avx2::available(),
            group: avx2::LANES,
            planar: avx2::encode_srgb8_planar::<N, L>,
            batch: avx2::encode_srgb8_batch::<N, L, [[f32; N]; L]>,
            batch_takes: |_, _| true,
            linear: avx2::linear_planar::<N, L>,
        },
    ]
}

/// `pixels` random pixels of `set` (the edge inputs in every sample position of every light
/// first, the other samples random).
fn random_pixels<const N: usize, const L: usize>(
    pixels: usize,
    seed: u64,
) -> std::vec::Vec<[[f32; N]; L]> {
    let mut rng = Rng(seed);
    (0..pixels)
        .map(|p| {
            let mut s: [[f32; N]; L] =
                core::array::from_fn(|_| core::array::from_fn(|_| sample(&mut rng)));
            // Pixels 0..22·N·L: edge e in position k (light k / N, sample k % N).
            let positions = N * L;
            if positions > 0 && p < EDGES.len() * positions {
                let k = p % positions;
                s[k / N][k % N] = EDGES[p / positions];
            }
            s
        })
        .collect()
}

/// The pixels as planes, light by light.
fn to_planes<const N: usize, const L: usize>(
    aos: &[[[f32; N]; L]],
) -> [[std::vec::Vec<f32>; N]; L] {
    core::array::from_fn(|l| core::array::from_fn(|i| aos.iter().map(|s| s[l][i]).collect()))
}

/// References to planes, light by light.
fn plane_refs<const N: usize, const L: usize>(
    planes: &[[std::vec::Vec<f32>; N]; L],
) -> [[&[f32]; N]; L] {
    planes.each_ref().map(|l| l.each_ref().map(|p| &p[..]))
}

/// `pixels` random pixels (the edge inputs in every sample position first) through every
/// loop of `set`.
fn check<const N: usize, const L: usize>(set: &impl Subject<N, L>, pixels: usize, seed: u64) {
    let aos = random_pixels::<N, L>(pixels, seed);
    let planes = to_planes(&aos);
    let planes = plane_refs(&planes);
    let weights = set.weights();
    let want: std::vec::Vec<[u8; 3]> = aos.iter().map(|s| set.reference(s)).collect();
    let want_linear: std::vec::Vec<[f32; 3]> =
        aos.iter().map(|s| linear_reference(weights, s)).collect();

    let compare = |what: &str, got: &[[u8; 3]]| {
        for (p, (g, w)) in got.iter().zip(&want).enumerate() {
            assert_eq!(g, w, "{what}, N = {N}, L = {L}, pixel {p}: {:?}", aos[p]);
        }
    };
    let compare_linear = |what: &str, got: &[std::vec::Vec<f32>; 3]| {
        for (p, w) in want_linear.iter().enumerate().take(got[0].len()) {
            for c in 0..3 {
                assert!(
                    same_f32(got[c][p], w[c]),
                    "{what}, N = {N}, L = {L}, pixel {p}, channel {c}: {} against {} for {:?}",
                    got[c][p],
                    w[c],
                    aos[p]
                );
            }
        }
    };

    // The per-pixel function (SSE2 on x86-64).
    let got: std::vec::Vec<[u8; 3]> = aos.iter().map(|s| set.encode_u8(s)).collect();
    compare("encode_u8", &got);

    // The portable planar loops.
    let mut got = std::vec![[0u8; 3]; pixels];
    crate::planar::portable::encode_srgb8_planar_portable(weights, planes, &mut got);
    compare("portable planar", &got);
    let mut got = std::vec![[0u8; 3]; pixels];
    crate::planar::portable::encode_srgb8_batch_portable(weights, &aos, &mut got);
    compare("portable batch", &got);
    let mut lin = [0, 1, 2].map(|_| std::vec![0.0f32; pixels]);
    {
        let [r, g, b] = &mut lin;
        crate::planar::portable::linear_planar_portable(weights, planes, [r, g, b]);
    }
    compare_linear("portable planar linear", &lin);

    // The AVX-512 and AVX2 loops, where this CPU has them: every whole group (of 16 and of
    // 8 pixels; the AVX2 sRGB loops a lone group too, as their pipeline runs only the stages
    // whose group exists; the AVX-512 interleaved loop only at its widths, else nothing).
    // Linear output with and without `stream` (with AVX2, at most four planes or more than one
    // light, `stream` changes nothing), into output planes starting 0 to 15 floats past a
    // 64-byte boundary (different for each plane and seed), so that the streamed copies'
    // ordinary head and tail stores are used too; nothing outside the output planes may change.
    #[cfg(target_arch = "x86_64")]
    for x86 in x86_loops::<N, L>() {
        if !x86.available {
            skipped(
                x86.capability,
                &std::format!("the {} loops, N = {N}, L = {L}", x86.name),
                "this CPU does not have them",
            );
            continue;
        }
        let name = x86.name;
        let srgb8_done = pixels / x86.group * x86.group;
        // The planar loops on copies of the planes starting 0 to 15 floats past a 64-byte
        // boundary, planes 2k and 2k + 1 (counted over all lights) at the same offset (which
        // depends on the seed): where the loops start their groups depends on those offsets
        // (`on_lines`). They must leave fewer pixels than a step, and write nothing past those
        // they report.
        let flat = planes.as_flattened();
        let mut copies: std::vec::Vec<std::vec::Vec<f32>> = flat
            .iter()
            .map(|_| std::vec![0.0f32; pixels + 32])
            .collect();
        let starts: std::vec::Vec<usize> = (0..flat.len())
            .map(|k| past_line(&copies[k], seed as usize + 7 * (k / 2)))
            .collect();
        for ((c, p), &o) in copies.iter_mut().zip(flat).zip(&starts) {
            c[o..o + pixels].copy_from_slice(p);
        }
        let shifted: [[&[f32]; N]; L] = core::array::from_fn(|l| {
            core::array::from_fn(|i| {
                let k = l * N + i;
                &copies[k][starts[k]..starts[k] + pixels]
            })
        });
        let mut got = std::vec![[0xA5u8; 3]; pixels];
        // SAFETY: the CPU has the loop's features (`available`).
        let done = unsafe { (x86.planar)(weights, shifted, got.as_flattened_mut()) };
        assert!(
            done <= pixels && done + x86.group > pixels,
            "{name} planar: {done} of {pixels}"
        );
        compare(&std::format!("{name} planar"), &got[..done]);
        assert!(
            got[done..].iter().all(|p| *p == [0xA5; 3]),
            "{name} planar: written past {done}"
        );
        let mut got = std::vec![[0u8; 3]; pixels];
        // SAFETY: the CPU has the loop's features (`available`).
        let done = unsafe { (x86.batch)(weights, &aos, got.as_flattened_mut()) };
        let batch_done = if (x86.batch_takes)(N, L) {
            srgb8_done
        } else {
            0
        };
        assert_eq!(done, batch_done, "{name} batch");
        compare(&std::format!("{name} batch"), &got[..done]);
        for stream in [false, true] {
            let mut buf = [0, 1, 2].map(|_| std::vec![0.0f32; pixels + 32]);
            let offset = |c: usize, b: &[f32]| past_line(b, 5 * c + seed as usize);
            let [r, g, b] = &mut buf;
            let (or, og, ob) = (offset(0, r), offset(1, g), offset(2, b));
            let out = [
                &mut r[or..or + pixels],
                &mut g[og..og + pixels],
                &mut b[ob..ob + pixels],
            ];
            // SAFETY: the CPU has the loop's features (`available`).
            let done = unsafe { (x86.linear)(weights, shifted, out, stream) };
            // Steps of 16 pixels.
            assert!(
                done <= pixels && done + 16 > pixels,
                "{name} planar linear: {done} of {pixels}"
            );
            let lin = [(r, or), (g, og), (b, ob)].map(|(c, o)| c[o..o + done].to_vec());
            compare_linear(&std::format!("{name} planar linear, {stream}"), &lin);
            for (c, o) in [(&buf[0], or), (&buf[1], og), (&buf[2], ob)] {
                let untouched = c[..o].iter().chain(&c[o + done..]);
                assert!(
                    untouched.copied().all(|v| v == 0.0),
                    "{name}: written outside"
                );
            }
        }
    }

    // The public functions, whichever loops they pick.
    let mut got = std::vec![[0u8; 3]; pixels];
    set.encode_u8_planar(planes, &mut got);
    compare("encode_u8_planar_to_interleaved", &got);
    let mut got = std::vec![[0u8; 3]; pixels];
    set.encode_u8_batch(&aos, &mut got);
    compare("encode_u8_batch", &got);
    let mut lin = [0, 1, 2].map(|_| std::vec![0.0f32; pixels]);
    {
        let [r, g, b] = &mut lin;
        set.linear_rgb_planar(planes, [r, g, b]);
    }
    compare_linear("linear_rgb_planar", &lin);
    let mut got16 = std::vec![[0u16; 3]; pixels];
    set.encode_u16_batch(&aos, &mut got16);
    for (p, (g, s)) in got16.iter().zip(&aos).enumerate() {
        assert_eq!(*g, set.encode_u16(s), "u16, N = {N}, L = {L}, {p}");
    }
}

/// A set with `N` random weights of either sign, on the sRGB display: the widths the baked
/// sets do not have (1, 3, 5: the SSE2 product's remainder columns; 16: more weights than
/// registers).
fn random_set<const N: usize>(seed: u64) -> crate::FoldedSet<N> {
    let mut rng = Rng(seed);
    crate::FoldedSet::new(
        core::array::from_fn(|i| 400.0 + i as f32),
        [0, 1, 2].map(|_| core::array::from_fn(|_| 2.0 * rng.unit() - 0.6)),
        TABLE2_ROW2_SRGB.samples(),
        TABLE2_ROW2_SRGB.display(),
    )
    .unwrap()
}

/// Pixels per block of the planar loops in passes (`avx2::BLOCK_GROUPS` groups of 8), so
/// that the counts of the test below fall on and around the blocks' ends.
const BLOCK: usize = 1024;
#[cfg(target_arch = "x86_64")]
const _: () = assert!(BLOCK == super::avx2::BLOCK_GROUPS * super::avx2::LANES);

#[test]
fn the_loops_in_passes_give_the_per_pixel_bytes_around_their_blocks() {
    // More than four planes: passes of four planes over blocks of 1024 pixels, the last
    // pass with one (N = 5, 9), two (6), three (7) or four planes (8, 12, 16). One block,
    // a block and a group, two blocks less a group, two and a part, three and a pair.
    for (k, pixels) in [
        BLOCK,
        BLOCK + 8,
        2 * BLOCK - 8,
        2 * BLOCK + 21,
        3 * BLOCK + 16,
    ]
    .into_iter()
    .enumerate()
    {
        let seed = 100 * (k as u64 + 2);
        check(&random_set::<5>(seed), pixels, seed + 1);
        check(&random_set::<6>(seed), pixels, seed + 2);
        check(&random_set::<7>(seed), pixels, seed + 3);
        check(&KQ_C_8_SRGB, pixels, seed + 4);
        check(&random_set::<9>(seed), pixels, seed + 5);
        check(&random_set::<12>(seed), pixels, seed + 6);
        check(&random_set::<16>(seed), pixels, seed + 7);
    }
}

#[test]
fn every_loop_gives_the_per_pixel_bytes_on_a_million_pixels() {
    // 2²⁰ + 13 pixels: a partial group of 8 and a partial chunk of 16 at the end.
    check(&TABLE2_ROW2_SRGB, (1 << 20) + 13, 1);
    check(&TABLE2_ROW1_SRGB, (1 << 20) + 5, 2);
}

#[test]
fn every_loop_gives_the_per_pixel_bytes_for_other_widths() {
    check(&KQ_C_8_SRGB, 100_003, 3);
    check(&random_set::<1>(4), 100_001, 5);
    check(&random_set::<3>(6), 100_007, 7);
    check(&random_set::<5>(8), 100_009, 9);
    check(&random_set::<16>(10), 100_011, 11);
    // The largest width a set may have.
    check(&random_set::<{ crate::MAX_WAVELENGTHS }>(20), 10_007, 21);
    // Fewer pixels than one group: the tails alone; one group and a part (the pipeline's
    // shortest run, where no two stages overlap); two, three and five groups, and one step
    // of the linear loop and a part.
    check(&TABLE2_ROW2_SRGB, 7, 12);
    check(&TABLE2_ROW2_SRGB, 0, 13);
    for (pixels, seed) in [(9, 14), (16, 15), (17, 16), (24, 17), (40, 18), (31, 19)] {
        check(&TABLE2_ROW2_SRGB, pixels, seed);
        check(&random_set::<16>(seed), pixels, seed + 100);
    }
}

/// Forces `level` on this thread for `f`, then lifts the cap; says so and skips `f` where this
/// CPU or target does not have that level.
fn with_loops(level: Loops, f: impl FnOnce()) {
    let got = force(level);
    if got == level {
        f();
    } else {
        skipped(
            capability(level),
            &std::format!("the public functions with the {} loops", level.name()),
            &std::format!("this CPU's fastest loops are {}", got.name()),
        );
    }
    force(Loops::Avx512);
}

/// What a CPU needs for `level`'s loops, as `SPECTRAL_QUADRATURE_REQUIRE` names it (the scalar
/// and portable loops need nothing).
fn capability(level: Loops) -> &'static str {
    match level {
        Loops::Avx512 => "avx512",
        Loops::Avx2 => "avx2",
        Loops::Scalar | Loops::Portable => "",
    }
}

/// The level whose loop an interleaved sRGB call at width `n` with `l` lights takes under a
/// cap of `level`: the AVX-512 interleaved loop takes a folded set (one light) at N = 4 alone,
/// and the AVX2 loop the others.
fn batch_level(level: Loops, n: usize, l: usize) -> Loops {
    #[cfg(target_arch = "x86_64")]
    if level == Loops::Avx512 && !(l == 1 && super::avx512::BATCH_WIDTHS.contains(&n)) {
        return Loops::Avx2;
    }
    let _ = (n, l);
    level
}

/// Whether the linear planar loop of `level` writes with non-temporal stores at width `n` with
/// `l` lights from `STREAM_MIN_PIXELS` on: the AVX-512 loop always, the AVX2 loop for a folded
/// set above four planes.
fn streams(level: Loops, n: usize, l: usize) -> bool {
    // Only the x86-64 arm reads the width.
    let _ = (n, l);
    match level {
        Loops::Avx512 => true,
        #[cfg(target_arch = "x86_64")]
        Loops::Avx2 => l == 1 && n > super::avx2::PASS_PLANES,
        _ => false,
    }
}

/// Each level through the public functions, on `pixels` pixels (random, the edge inputs in
/// every position first): the loop that ran is the forced one, streamed where it streams at
/// that size, and every output equals the per-pixel function's.
fn public_functions_at<const N: usize, const L: usize>(
    set: &impl Subject<N, L>,
    pixels: usize,
    seed: u64,
) {
    let aos = random_pixels::<N, L>(pixels, seed);
    let planes = to_planes(&aos);
    let planes = plane_refs(&planes);
    let want: std::vec::Vec<[u8; 3]> = aos.iter().map(|s| set.reference(s)).collect();
    #[cfg(target_arch = "x86_64")]
    let stream_from = super::STREAM_MIN_PIXELS;
    #[cfg(not(target_arch = "x86_64"))]
    let stream_from = usize::MAX;
    for level in Loops::ALL {
        with_loops(level, || {
            let ran = |loops, streamed| Some(Ran { loops, streamed });
            let mut lin = [0, 1, 2].map(|_| std::vec![0.0f32; pixels]);
            {
                let [r, g, b] = &mut lin;
                set.linear_rgb_planar(planes, [r, g, b]);
            }
            // Without vector units the linear planar path is the portable loop too.
            let linear_level = level.max(Loops::Portable);
            let streamed = pixels >= stream_from && streams(level, N, L);
            assert_eq!(
                take_ran(),
                ran(linear_level, streamed),
                "linear, {level:?}, N = {N}, L = {L}"
            );
            for (p, s) in aos.iter().enumerate() {
                let one = linear_reference(set.weights(), s);
                assert!(
                    (0..3).all(|c| same_f32(lin[c][p], one[c])),
                    "linear_rgb_planar, {level:?}, N = {N}, L = {L}, pixel {p}: {s:?}"
                );
            }
            let mut got = std::vec![[0xA5u8; 3]; pixels];
            set.encode_u8_planar(planes, &mut got);
            assert_eq!(
                take_ran(),
                ran(level, false),
                "planar, {level:?}, N = {N}, L = {L}"
            );
            let bad = got.iter().zip(&want).position(|(g, w)| g != w);
            assert_eq!(
                bad, None,
                "encode_u8_planar_to_interleaved, {level:?}, N = {N}, L = {L}"
            );
            let mut got = std::vec![[0xA5u8; 3]; pixels];
            set.encode_u8_batch(&aos, &mut got);
            let batch = batch_level(level, N, L);
            assert_eq!(
                take_ran(),
                ran(batch, false),
                "batch, {level:?}, N = {N}, L = {L}"
            );
            let bad = got.iter().zip(&want).position(|(g, w)| g != w);
            assert_eq!(bad, None, "encode_u8_batch, {level:?}, N = {N}, L = {L}");
        });
    }
}

#[test]
fn each_loop_through_the_public_functions_reaches_the_streaming_path() {
    // 2²⁰ + 13 pixels: from `STREAM_MIN_PIXELS` on, the AVX-512 linear loop streams at every
    // width and the AVX2 one above four planes (N = 6); a partial group and chunk at the end.
    let pixels = (1 << 20) + 13;
    public_functions_at(&TABLE2_ROW2_SRGB, pixels, 31);
    public_functions_at(&TABLE2_ROW1_SRGB, pixels, 32);
}

#[test]
fn each_loop_through_the_public_functions_at_small_sizes() {
    // Under Miri (the portable and scalar loops alone there), fewer and shorter runs.
    let sizes: &[usize] = if cfg!(miri) {
        &[0, 17, 33]
    } else {
        &[0, 1, 7, 15, 16, 17, 33, 100, 1029]
    };
    for (k, &pixels) in sizes.iter().enumerate() {
        let seed = 40 + k as u64;
        public_functions_at(&TABLE2_ROW2_SRGB, pixels, seed);
        public_functions_at(&random_set::<1>(seed), pixels, seed);
        public_functions_at(&random_set::<5>(seed), pixels, seed);
        public_functions_at(&random_set::<16>(seed), pixels, seed);
    }
}

/// `FoldedSet::linear_rgb_batch` and `WavelengthSet::ac1c2_batch` give every pixel the bits of
/// the per-pixel functions (`mat_vec`), with every level of loops forced in turn (at the scalar
/// level pixel by pixel; above it, from `batch::INTERLEAVED_FROM` wavelengths, four pixels side
/// by side on x86-64): at sizes either side of that bound and at `MAX_WAVELENGTHS`, on pixel
/// counts around multiples of four, with every edge value (NaN, ±Inf, subnormals, huge) in every
/// position of the first pixels.
#[test]
fn the_linear_batches_give_each_pixel_the_per_pixel_bits() {
    fn at<const N: usize>(seed: u64) {
        let folded = random_set::<N>(seed);
        let set = crate::WavelengthSet::new(
            folded.wavelengths_nm(),
            *folded.weights_ref(),
            crate::Samples::Radiance,
        )
        .unwrap();
        // The last count puts every edge value in every position (`random_pixels`).
        let counts = if cfg!(miri) {
            std::vec![0, 5]
        } else {
            std::vec![0, 1, 3, 4, 5, 7, 8, 9, EDGES.len() * N + 3]
        };
        for pixels in counts {
            let px: std::vec::Vec<[f32; N]> = random_pixels::<N, 1>(pixels, seed)
                .into_iter()
                .map(|[p]| p)
                .collect();
            for level in Loops::ALL {
                with_loops(level, || {
                    let mut lin = std::vec![[-7.5f32; 3]; pixels];
                    assert_eq!(folded.linear_rgb_batch(&px, &mut lin), Ok(()));
                    let mut ac = std::vec![[-7.5f32; 3]; pixels];
                    assert_eq!(set.ac1c2_batch(&px, &mut ac), Ok(()));
                    for (p, s) in px.iter().enumerate() {
                        let one = mat_vec(folded.weights_ref(), s);
                        for c in 0..3 {
                            assert!(
                                same_f32(lin[p][c], one[c]) && same_f32(ac[p][c], one[c]),
                                "{level:?}, N = {N}, {pixels} pixels, pixel {p}, channel {c}: \
                                 {:?} and {:?} against {one:?}",
                                lin[p],
                                ac[p]
                            );
                        }
                    }
                });
            }
        }
    }
    at::<4>(61);
    at::<27>(62);
    at::<28>(63);
    at::<33>(64);
    at::<{ crate::MAX_WAVELENGTHS }>(65);
}

/// N = 0: no planes, so the outputs say how many pixels there are; every path, forced in turn,
/// gives black (linear: +0.0), as the interleaved path and the per-pixel functions do.
#[test]
fn no_wavelengths_give_the_colour_of_no_signal_on_every_path() {
    let set = random_set::<0>(1);
    let sizes: &[usize] = if cfg!(miri) {
        &[0, 5, 37]
    } else {
        &[0, 5, 16, 37, 1000]
    };
    for &pixels in sizes {
        for level in Loops::ALL {
            with_loops(level, || {
                let mut out = std::vec![[9u8; 3]; pixels];
                assert_eq!(
                    set.encode_u8_planar_to_interleaved(GamutMapping::Clip, [], &mut out),
                    Ok(())
                );
                assert!(out.iter().all(|o| *o == [0; 3]), "{level:?} {pixels}");
                let mut batch = std::vec![[9u8; 3]; pixels];
                let none = std::vec![[0.0f32; 0]; pixels];
                assert_eq!(
                    set.encode_u8_batch(GamutMapping::Clip, &none, &mut batch),
                    Ok(())
                );
                assert_eq!(batch, out);
                assert_eq!(set.encode_u8(GamutMapping::Clip, &[]), [0; 3]);
                let mut lin = [0, 1, 2].map(|_| std::vec![-7.5f32; pixels]);
                let [r, g, b] = &mut lin;
                assert_eq!(set.linear_rgb_planar([], [r, g, b]), Ok(()));
                assert!(lin.iter().flatten().all(|v| v.to_bits() == 0), "{level:?}");
                let mut rows = std::vec![[-7.5f32; 3]; pixels];
                assert_eq!(set.linear_rgb_batch(&none, &mut rows), Ok(()));
                assert!(rows.iter().flatten().all(|v| v.to_bits() == 0), "{level:?}");
                // Outputs of other lengths: the first output's length is the pixel count.
                let mut lin = [0, 1, 2].map(|_| std::vec![-7.5f32; pixels]);
                lin[2].push(1.0);
                let [r, g, b] = &mut lin;
                assert_eq!(
                    set.linear_rgb_planar([], [r, g, b]),
                    Err(crate::Error::LengthMismatch {
                        what: crate::LengthOf::OutputPlane,
                        expected: pixels,
                        got: pixels + 1
                    })
                );
                assert!(lin.iter().flatten().all(|v| *v == -7.5 || *v == 1.0));
            });
        }
    }
}

/// A light-group set of L lights with N random weights each, of either sign, on the sRGB
/// display.
fn random_groups<const N: usize, const L: usize>(seed: u64) -> crate::LightGroupSet<N, L> {
    crate::LightGroupSet::new(
        core::array::from_fn(|i| 400.0 + i as f32),
        core::array::from_fn(|l| random_set::<N>(seed + 1000 * l as u64).weights()),
        [""; L],
        TABLE2_ROW2_SRGB.display(),
    )
    .unwrap()
}

#[test]
fn every_loop_gives_the_per_pixel_bytes_for_light_groups() {
    // The bench's shape (L = 4, N = 8), the AVX-512 interleaved width with two lights, a light
    // alone (the folded set's loops), the widths of the remainder columns, and L · N = 64, the
    // largest the loops take; a partial group and chunk at the end of each (N = 0, no planes,
    // through the public functions below).
    check(&random_groups::<8, 4>(1), 100_003, 61);
    check(&random_groups::<4, 2>(2), 100_001, 62);
    check(&random_groups::<6, 1>(3), 10_005, 63);
    check(&random_groups::<1, 3>(4), 10_007, 64);
    check(&random_groups::<5, 2>(5), 10_009, 65);
    check(&random_groups::<16, 4>(6), 10_011, 66);
    // One light: the folded set's bytes and bits on every loop.
    let one = random_groups::<8, 1>(8);
    let member = one.member(0).unwrap();
    check(&member, 10_013, 68);
    check(&one, 10_013, 68);
    // Fewer pixels than one group, one group and a part, several groups.
    for (pixels, seed) in [(0, 70), (7, 71), (9, 72), (17, 73), (24, 74), (40, 75)] {
        check(&random_groups::<8, 4>(seed), pixels, seed);
        check(&random_groups::<4, 3>(seed), pixels, seed + 100);
    }
}

#[test]
fn each_light_group_loop_through_the_public_functions() {
    // Under Miri (the portable and scalar loops alone there), fewer and shorter runs.
    let sizes: &[usize] = if cfg!(miri) {
        &[0, 17, 33]
    } else {
        &[0, 1, 7, 15, 16, 17, 33, 100, 1029]
    };
    for (k, &pixels) in sizes.iter().enumerate() {
        let seed = 80 + k as u64;
        public_functions_at(&random_groups::<8, 4>(seed), pixels, seed);
        public_functions_at(&random_groups::<4, 2>(seed), pixels, seed);
        public_functions_at(&random_groups::<3, 1>(seed), pixels, seed);
        public_functions_at(&random_groups::<0, 3>(seed), pixels, seed);
    }
}

#[test]
fn light_group_loops_reach_the_streaming_path() {
    // 2²⁰ + 13 pixels: the AVX-512 linear loop streams; the AVX2 one, one pass over the
    // lights' planes, does not.
    public_functions_at(&random_groups::<4, 2>(90), (1 << 20) + 13, 91);
}

/// Above L · N = `MAX_WAVELENGTHS` the batch and planar functions go pixel by pixel (no loop
/// runs), with the same bytes and bits.
#[test]
fn light_groups_beyond_the_loops_go_pixel_by_pixel() {
    let set = random_groups::<17, 4>(92);
    let aos = random_pixels::<17, 4>(37, 93);
    let planes = to_planes(&aos);
    let planes = plane_refs(&planes);
    let want: std::vec::Vec<[u8; 3]> = aos.iter().map(|s| set.reference(s)).collect();
    for level in Loops::ALL {
        with_loops(level, || {
            let mut got = std::vec![[0u8; 3]; aos.len()];
            Subject::encode_u8_batch(&set, &aos, &mut got);
            assert_eq!(got, want, "batch, {level:?}");
            Subject::encode_u8_planar(&set, planes, &mut got);
            assert_eq!(got, want, "planar, {level:?}");
            let mut lin = [0, 1, 2].map(|_| std::vec![0.0f32; aos.len()]);
            {
                let [r, g, b] = &mut lin;
                Subject::linear_rgb_planar(&set, planes, [r, g, b]);
            }
            for (p, s) in aos.iter().enumerate() {
                let one = linear_reference(set.weights_ref(), s);
                assert!((0..3).all(|c| same_f32(lin[c][p], one[c])), "{level:?} {p}");
            }
            assert_eq!(take_ran(), None, "{level:?}");
        });
    }
}
