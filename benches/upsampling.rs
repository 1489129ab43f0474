//! Cost per pixel of the RGB upsampling: linear RGB → N node reflectances through the default
//! scene's baked tables (`tables::upsampling`, 9³ grids), N = 4, 6 and 8.
//!
//! Inputs are 4096 deterministic RGB triples spread over the unit cube (an LCG). Benchmark ids:
//! - `upsampling/per_pixel/<set>`: one pixel per iteration, the input through `black_box`;
//! - `upsampling/batch_4096/<set>`: one `reflectance_batch` call over all 4096 pixels, with
//!   `Throughput::Elements(4096)`: ns/pixel = time / 4096.
//!
//! - `upsampling/interpolate/<set>`: `interpolate` (the table alone), one pixel per iteration;
//! - `upsampling/edge_unreachable/<set>`: `reflectance` on 4096 RGB triples that node values in
//!   [0, 1] do not reach or that lie in a cell at the edge of what the set reaches (saturated
//!   colours near the cube's faces), where the round-trip correction runs.
//!
//! Run with `cargo bench --bench upsampling`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use spectral_quadrature::tables::upsampling;
use spectral_quadrature::Upsampling;

const PIXELS: usize = 4096;

fn inputs() -> Vec<[f32; 3]> {
    let mut state = 0x2545_f491_u32;
    let mut next = move || {
        state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (state >> 8) as f32 / (1u32 << 24) as f32
    };
    (0..PIXELS).map(|_| [next(), next(), next()]).collect()
}

/// Saturated colours: one channel near 0, one near 1, the third anywhere.
fn saturated() -> Vec<[f32; 3]> {
    let mut state = 0x1234_5678_u32;
    let mut next = move || {
        state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (state >> 8) as f32 / (1u32 << 24) as f32
    };
    (0..PIXELS)
        .map(|i| {
            let mut p = [next(), next(), next()];
            p[i % 3] *= 0.1;
            p[(i + 1) % 3] = 1.0 - 0.1 * p[(i + 1) % 3];
            p
        })
        .collect()
}

fn bench_one<const N: usize>(c: &mut Criterion, name: &str, up: &Upsampling<N>, rgb: &[[f32; 3]]) {
    let mut g = c.benchmark_group("upsampling/interpolate");
    g.bench_function(name, |b| {
        let mut i = 0;
        b.iter(|| {
            i = (i + 1) % PIXELS;
            black_box(up.interpolate(black_box(rgb[i])))
        })
    });
    g.finish();
    let edge = saturated();
    let mut g = c.benchmark_group("upsampling/edge_unreachable");
    g.bench_function(name, |b| {
        let mut i = 0;
        b.iter(|| {
            i = (i + 1) % PIXELS;
            black_box(up.reflectance(black_box(edge[i])))
        })
    });
    g.finish();
    let mut g = c.benchmark_group("upsampling/per_pixel");
    g.bench_function(name, |b| {
        let mut i = 0;
        b.iter(|| {
            i = (i + 1) % PIXELS;
            black_box(up.reflectance(black_box(rgb[i])))
        })
    });
    g.finish();
    let mut g = c.benchmark_group("upsampling/batch_4096");
    g.throughput(Throughput::Elements(PIXELS as u64));
    let mut out = vec![[0.0f32; N]; PIXELS];
    g.bench_function(name, |b| {
        b.iter(|| {
            up.reflectance_batch(black_box(rgb), &mut out)
                .expect("lengths agree");
            black_box(&mut out);
        })
    });
    g.finish();
}

fn upsampling_cost(c: &mut Criterion) {
    let rgb = inputs();
    bench_one(c, "kq_c_4_srgb", &upsampling::KQ_C_4_SRGB, &rgb);
    bench_one(c, "kq_c_6_srgb", &upsampling::KQ_C_6_SRGB, &rgb);
    bench_one(c, "kq_c_8_srgb", &upsampling::KQ_C_8_SRGB, &rgb);
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2))
        .sample_size(50);
    targets = upsampling_cost
}
criterion_main!(benches);
