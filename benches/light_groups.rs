//! Light-group sets against a folded set, at N = 8: the cost of summing L lights' groups.
//!
//! A `LightGroupSet<8, L>` runs L folded 3×8 products per pixel and one encoder; a
//! `FoldedSet<8>` one product and one encoder. Timed: samples → 8-bit sRGB (`Clip`).
//!
//! Inputs: 4096 pixels of deterministic reflectance-like values in 0..1 (an LCG), one
//! accumulator of 8 per light; the folded set takes light 0's.
//!
//! Benchmark ids:
//! - `light_groups/per_pixel/encode_u8_srgb/<set>`: one pixel per iteration, cycling through
//!   the 4096 pixels, the input through `black_box`; the set is a const and the mapping a
//!   literal, as in an application's pixel loop.
//! - `light_groups/batch_4096/encode_u8_srgb/<set>`: one batch call over all 4096 pixels, with
//!   `Throughput::Elements(4096)`; ns/pixel = time / 4096. `<set>_pixel_by_pixel` is the same
//!   4096 pixels through the per-pixel `encode_u8` in a loop, what the batch call did before it
//!   had vector loops: the two in one run.
//! - `light_groups/planar_4096/encode_u8_srgb/<set>` and `light_groups/planar_4096/linear/<set>`:
//!   the same pixels as planes (one `Vec<f32>` of 4096 values per light and node, each an
//!   allocation of its own), `encode_u8_planar_to_interleaved` and `linear_rgb_planar` over all
//!   of them per iteration; `l4_n8_pixel_by_pixel`, each pixel's groups gathered from the planes
//!   and passed to the per-pixel function, what the planar calls did before.
//!
//! Sets: `folded_n8` (`KQ_C_8_SRGB`), `l2_n8` and `l4_n8` (it and made-up lights at its nodes).
//!
//! Run with `cargo bench --bench light_groups`.

use std::hint::black_box;
use std::time::Duration;

use criterion::measurement::WallTime;
use criterion::{criterion_group, criterion_main, BenchmarkGroup, Criterion, Throughput};
use spectral_quadrature::tables::folded::KQ_C_8_SRGB;
use spectral_quadrature::{FoldedSet, GamutMapping, LightGroupSet, Samples};

/// Pixels in the input set (a power of two, so the per-pixel index wraps with a mask).
const PIXELS: usize = 4096;

/// `KQ_C_8_SRGB` with its weights scaled per node by `1 − k/8 + k·i/32`: another light's
/// matrix at the same nodes (made up; a scene bakes real ones).
const fn light(k: usize, name: &'static str) -> FoldedSet<8> {
    let mut w = KQ_C_8_SRGB.weights();
    let mut c = 0;
    while c < 3 {
        let mut i = 0;
        while i < 8 {
            w[c][i] *= 1.0 - k as f32 / 8.0 + (k * i) as f32 / 32.0;
            i += 1;
        }
        c += 1;
    }
    match FoldedSet::new(
        KQ_C_8_SRGB.wavelengths_nm(),
        w,
        Samples::Reflectance { light: name },
        KQ_C_8_SRGB.display(),
    ) {
        Ok(set) => set,
        Err(_) => panic!("finite weights"),
    }
}

const FOLDED: FoldedSet<8> = KQ_C_8_SRGB;
const L2: LightGroupSet<8, 2> = match LightGroupSet::from_members([KQ_C_8_SRGB, light(1, "A")]) {
    Ok(set) => set,
    Err(_) => panic!("members share nodes and display"),
};
const L4: LightGroupSet<8, 4> =
    match LightGroupSet::from_members([KQ_C_8_SRGB, light(1, "A"), light(2, "B"), light(3, "F11")])
    {
        Ok(set) => set,
        Err(_) => panic!("members share nodes and display"),
    };

/// Deterministic groups: L accumulators of 8 values in 0..1 per pixel (a 64-bit LCG).
fn groups<const L: usize>(seed: u64) -> Vec<[[f32; 8]; L]> {
    let mut s = seed;
    let mut next = move || {
        s = s
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (s >> 40) as f32 / (1u64 << 24) as f32
    };
    (0..PIXELS)
        .map(|_| std::array::from_fn(|_| std::array::from_fn(|_| next())))
        .collect()
}

fn per_pixel<T, R>(
    group: &mut BenchmarkGroup<'_, WallTime>,
    id: &str,
    inputs: &[T],
    f: impl Fn(&T) -> R,
) {
    let inputs: &[T; PIXELS] = inputs.try_into().expect("one input per pixel");
    let f = &f;
    group.bench_function(id, |b| {
        let mut i = 0usize;
        b.iter(move || {
            let s = black_box(&inputs[i]);
            i = (i + 1) % PIXELS;
            f(s)
        })
    });
}

fn light_groups(c: &mut Criterion) {
    let g4 = groups::<4>(0x5EC7_5A10_BADC_0DE0);
    let g2: Vec<[[f32; 8]; 2]> = g4.iter().map(|g| [g[0], g[1]]).collect();
    let g1: Vec<[f32; 8]> = g4.iter().map(|g| g[0]).collect();
    // Untimed: the sets give what they document (the folded set's bytes for light 0 alone).
    let one = LightGroupSet::from_members([FOLDED]).unwrap();
    for s in &g1 {
        assert_eq!(
            one.encode_u8(GamutMapping::Clip, &[*s]),
            FOLDED.encode_u8(GamutMapping::Clip, s)
        );
    }

    let mut g = c.benchmark_group("light_groups/per_pixel/encode_u8_srgb");
    g.warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    per_pixel(&mut g, "folded_n8", &g1, |s| {
        FOLDED.encode_u8(GamutMapping::Clip, s)
    });
    per_pixel(&mut g, "l2_n8", &g2, |s| {
        L2.encode_u8(GamutMapping::Clip, s)
    });
    per_pixel(&mut g, "l4_n8", &g4, |s| {
        L4.encode_u8(GamutMapping::Clip, s)
    });
    g.finish();

    let mut g = c.benchmark_group(format!("light_groups/batch_{PIXELS}/encode_u8_srgb"));
    g.warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3))
        .throughput(Throughput::Elements(PIXELS as u64));
    let mut out = vec![[0u8; 3]; PIXELS];
    g.bench_function("folded_n8", |b| {
        b.iter(|| {
            FOLDED
                .encode_u8_batch(GamutMapping::Clip, black_box(&g1), &mut out)
                .unwrap()
        })
    });
    g.bench_function("l2_n8", |b| {
        b.iter(|| {
            L2.encode_u8_batch(GamutMapping::Clip, black_box(&g2), &mut out)
                .unwrap()
        })
    });
    g.bench_function("l4_n8", |b| {
        b.iter(|| {
            L4.encode_u8_batch(GamutMapping::Clip, black_box(&g4), &mut out)
                .unwrap()
        })
    });
    g.bench_function("l4_n8_pixel_by_pixel", |b| {
        b.iter(|| {
            for (o, px) in out.iter_mut().zip(black_box(&g4)) {
                *o = L4.encode_u8(GamutMapping::Clip, px);
            }
        })
    });
    g.finish();

    let (p1, p2, p4) = (
        planes(&g1.iter().map(|s| [*s]).collect::<Vec<_>>()),
        planes(&g2),
        planes(&g4),
    );
    let (r1, r2, r4) = (refs(&p1), refs(&p2), refs(&p4));
    let mut g = c.benchmark_group(format!("light_groups/planar_{PIXELS}/encode_u8_srgb"));
    g.warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3))
        .throughput(Throughput::Elements(PIXELS as u64));
    g.bench_function("folded_n8", |b| {
        b.iter(|| {
            FOLDED
                .encode_u8_planar_to_interleaved(GamutMapping::Clip, black_box(r1[0]), &mut out)
                .unwrap()
        })
    });
    g.bench_function("l2_n8", |b| {
        b.iter(|| {
            L2.encode_u8_planar_to_interleaved(GamutMapping::Clip, black_box(r2), &mut out)
                .unwrap()
        })
    });
    g.bench_function("l4_n8", |b| {
        b.iter(|| {
            L4.encode_u8_planar_to_interleaved(GamutMapping::Clip, black_box(r4), &mut out)
                .unwrap()
        })
    });
    g.bench_function("l4_n8_pixel_by_pixel", |b| {
        b.iter(|| {
            let planes = black_box(r4);
            for (p, o) in out.iter_mut().enumerate() {
                let px = planes.map(|light| light.map(|plane| plane[p]));
                *o = L4.encode_u8(GamutMapping::Clip, &px);
            }
        })
    });
    g.finish();

    let mut lin = [0, 1, 2].map(|_| vec![0.0f32; PIXELS]);
    let mut g = c.benchmark_group(format!("light_groups/planar_{PIXELS}/linear"));
    g.warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3))
        .throughput(Throughput::Elements(PIXELS as u64));
    g.bench_function("folded_n8", |b| {
        b.iter(|| {
            let [r, gr, bl] = &mut lin;
            FOLDED
                .linear_rgb_planar(black_box(r1[0]), [r, gr, bl])
                .unwrap()
        })
    });
    g.bench_function("l2_n8", |b| {
        b.iter(|| {
            let [r, gr, bl] = &mut lin;
            L2.linear_rgb_planar(black_box(r2), [r, gr, bl]).unwrap()
        })
    });
    g.bench_function("l4_n8", |b| {
        b.iter(|| {
            let [r, gr, bl] = &mut lin;
            L4.linear_rgb_planar(black_box(r4), [r, gr, bl]).unwrap()
        })
    });
    g.finish();
}

/// The pixels as planes: `planes[l][i][p]`, one allocation per light and node.
fn planes<const L: usize>(px: &[[[f32; 8]; L]]) -> [[Vec<f32>; 8]; L] {
    std::array::from_fn(|l| std::array::from_fn(|i| px.iter().map(|g| g[l][i]).collect()))
}

/// References to the planes.
fn refs<const L: usize>(planes: &[[Vec<f32>; 8]; L]) -> [[&[f32]; 8]; L] {
    planes.each_ref().map(|l| l.each_ref().map(|p| &p[..]))
}

criterion_group!(benches, light_groups);
criterion_main!(benches);
