//! Runtime cost per pixel: spectral samples → colour.
//!
//! The renderer hands us samples; sampling is not timed. Timed is samples → colour for Table 2's
//! merged sets (4 and 6 wavelengths) and, as the reference a renderer would otherwise run, the
//! full 1 nm integration over 380..=770 nm (391 samples) with x̄ȳz̄ followed by the same
//! XYZ → sRGB encode.
//!
//! Inputs are 4096 deterministic, smooth, reflectance-like spectra (a base level plus gaussians
//! and sigmoids drawn from an LCG, clamped to 0..=1).
//!
//! Benchmark ids:
//! - `per_pixel/<op>/<set>`: one pixel per iteration, cycling through the 4096 spectra; the
//!   input goes through `black_box`, so nothing is hoisted or vectorised across pixels. The set
//!   is a baked const and the gamut mapping a literal, as in an application's pixel loop, so the
//!   weights stay in registers. `per_pixel/harness/table2_row2` times the loop alone (the
//!   input fetched and its four samples returned): what every other `per_pixel` figure
//!   includes besides the call.
//! - `batch_4096/<op>/<set>`: one batch call over all 4096 pixels per iteration, with
//!   `Throughput::Elements(4096)`; ns/pixel = time / 4096.
//!
//! Sets: `table2_row2` (4 wavelengths), `table2_row1` (6), `full_1nm` (391 samples, in-order f32
//! accumulation like the crate's own 3×N product) and `full_1nm_8acc` (the same sums with 8
//! partial accumulators per channel, which the compiler can vectorise: a faster reference).
//!
//! - `bandwidth/...`: the planar (structure-of-arrays) batch path against the memory bound, all
//!   in one run; see [`bandwidth`]. `cargo bench --bench runtime -- bandwidth` runs only these.
//!   `bandwidth/rounds/...` alternates the bound and the planar sRGB path in rounds and prints
//!   the median of the per-round shares; see [`rounds_against_bound`].
//!
//! Run with `cargo bench --bench runtime`.

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::measurement::WallTime;
use criterion::{
    criterion_group, criterion_main, BenchmarkGroup, Criterion, SamplingMode, Throughput,
};
use spectral_quadrature::tables::{self, displays::SRGB, folded};
use spectral_quadrature::{Display, FoldedSet, GamutMapping, WavelengthSet, SRGB8_MAX_ERROR};

/// Pixels in the input set (a power of two, so the per-pixel index wraps with a mask).
const PIXELS: usize = 4096;
/// Samples of the 1 nm reference: 380..=770 nm.
const FULL_LEN: usize = 391;
const FULL_START_NM: f64 = 380.0;
/// The reference's sample spacing, dλ in nm.
const DLAMBDA_NM: f64 = 1.0;

// ---------------------------------------------------------------------------------------------
// Inputs (not timed)

/// A 64-bit LCG (Knuth's MMIX constants); deterministic across platforms.
struct Lcg(u64);

impl Lcg {
    fn next_f64(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }
}

#[derive(Clone, Copy)]
enum Bump {
    /// `amp · exp(-½ ((λ - mu) / sigma)²)`.
    Gauss { amp: f64, mu: f64, sigma: f64 },
    /// `amp / (1 + exp(-(λ - edge) / width))`; a negative width makes it fall.
    Sigmoid { amp: f64, edge: f64, width: f64 },
}

/// A smooth reflectance-like spectrum: a base level plus 1 to 3 bumps, clamped to 0..=1.
#[derive(Clone)]
struct Reflectance {
    base: f64,
    bumps: Vec<Bump>,
}

impl Reflectance {
    fn random(rng: &mut Lcg) -> Self {
        let base = rng.range(0.02, 0.25);
        let n = 1 + (rng.next_f64() * 3.0) as usize;
        let bumps = (0..n)
            .map(|_| {
                if rng.next_f64() < 0.5 {
                    Bump::Gauss {
                        amp: rng.range(-0.2, 0.8),
                        mu: rng.range(400.0, 720.0),
                        sigma: rng.range(15.0, 90.0),
                    }
                } else {
                    let width = rng.range(8.0, 40.0);
                    Bump::Sigmoid {
                        amp: rng.range(0.1, 0.8),
                        edge: rng.range(430.0, 680.0),
                        width: if rng.next_f64() < 0.5 { width } else { -width },
                    }
                }
            })
            .collect();
        Reflectance { base, bumps }
    }

    fn at(&self, nm: f64) -> f32 {
        let mut r = self.base;
        for bump in &self.bumps {
            r += match *bump {
                Bump::Gauss { amp, mu, sigma } => {
                    let t = (nm - mu) / sigma;
                    amp * (-0.5 * t * t).exp()
                }
                Bump::Sigmoid { amp, edge, width } => amp / (1.0 + (-(nm - edge) / width).exp()),
            };
        }
        r.clamp(0.0, 1.0) as f32
    }
}

fn spectra() -> Vec<Reflectance> {
    let mut rng = Lcg(0x5EC7_5A10_BADC_0DE0);
    (0..PIXELS).map(|_| Reflectance::random(&mut rng)).collect()
}

/// Samples at a set's wavelengths, one `[f32; N]` per pixel.
fn sample_at<const N: usize>(spectra: &[Reflectance], nm: &[f32; N]) -> Vec<[f32; N]> {
    spectra
        .iter()
        .map(|s| nm.map(|l| s.at(f64::from(l))))
        .collect()
}

/// Samples at 380, 381, ..., 770 nm, one `[f32; 391]` per pixel.
fn sample_1nm(spectra: &[Reflectance]) -> Vec<[f32; FULL_LEN]> {
    spectra
        .iter()
        .map(|s| core::array::from_fn(|i| s.at(FULL_START_NM + i as f64 * DLAMBDA_NM)))
        .collect()
}

// ---------------------------------------------------------------------------------------------
// The 1 nm reference

/// x̄ȳz̄ at 1 nm (times dλ = 1 nm), scaled so that a spectrum of constant 1 has Y = 1 (the
/// normalisation of the baked folded sets).
struct Full1nm {
    xyz_weights: [[f32; FULL_LEN]; 3],
}

impl Full1nm {
    /// Linear interpolation of the 5 nm opponent sensitivities (`tables::SENSITIVITIES`) to
    /// 1 nm, turned into x̄ȳz̄ with `tables::AC1C2_TO_XYZ`, in f64.
    fn new() -> Self {
        let grid = &tables::GRID_NM;
        let sens = &tables::SENSITIVITIES;
        let m = tables::AC1C2_TO_XYZ;
        let mut xyz = [[0.0f64; FULL_LEN]; 3];
        for i in 0..FULL_LEN {
            let nm = FULL_START_NM + i as f64 * DLAMBDA_NM;
            let k = grid
                .iter()
                .rposition(|&g| f64::from(g) <= nm)
                .unwrap()
                .min(grid.len() - 2);
            let (g0, g1) = (f64::from(grid[k]), f64::from(grid[k + 1]));
            let t = (nm - g0) / (g1 - g0);
            let opp: [f64; 3] = core::array::from_fn(|c| {
                (1.0 - t) * f64::from(sens[k][c]) + t * f64::from(sens[k + 1][c])
            });
            for (r, row) in xyz.iter_mut().enumerate() {
                row[i] = (0..3).map(|c| f64::from(m[r][c]) * opp[c]).sum::<f64>() * DLAMBDA_NM;
            }
        }
        let y_sum: f64 = xyz[1].iter().sum();
        let xyz_weights = xyz.map(|row| row.map(|w| (w / y_sum) as f32));
        Full1nm { xyz_weights }
    }

    /// `[X, Y, Z]`: the 3×391 product accumulated in index order in f32, as the crate does for
    /// its own sets.
    #[inline]
    fn xyz(&self, samples: &[f32; FULL_LEN]) -> [f32; 3] {
        let mut out = [0.0f32; 3];
        for (o, row) in out.iter_mut().zip(&self.xyz_weights) {
            let mut acc = 0.0f32;
            for (w, s) in row.iter().zip(samples) {
                acc += w * s;
            }
            *o = acc;
        }
        out
    }

    /// `[X, Y, Z]` with 8 partial sums per channel: the compiler may vectorise this.
    #[inline]
    fn xyz_8acc(&self, samples: &[f32; FULL_LEN]) -> [f32; 3] {
        let mut out = [0.0f32; 3];
        for (o, row) in out.iter_mut().zip(&self.xyz_weights) {
            let mut acc = [0.0f32; 8];
            let (w8, w_rest) = row.as_chunks::<8>();
            let (s8, s_rest) = samples.as_chunks::<8>();
            for (w, s) in w8.iter().zip(s8) {
                for ((a, w), s) in acc.iter_mut().zip(w).zip(s) {
                    *a += w * s;
                }
            }
            let mut sum =
                ((acc[0] + acc[4]) + (acc[1] + acc[5])) + ((acc[2] + acc[6]) + (acc[3] + acc[7]));
            for (w, s) in w_rest.iter().zip(s_rest) {
                sum += w * s;
            }
            *o = sum;
        }
        out
    }

    #[inline]
    fn linear_rgb(&self, display: &Display, samples: &[f32; FULL_LEN]) -> [f32; 3] {
        display.linear_from_xyz(self.xyz(samples))
    }

    #[inline]
    fn encode_u8(
        &self,
        display: &Display,
        mapping: GamutMapping,
        samples: &[f32; FULL_LEN],
    ) -> [u8; 3] {
        display.encode_u8(mapping, display.linear_from_xyz(self.xyz(samples)))
    }

    #[inline]
    fn encode_u8_8acc(
        &self,
        display: &Display,
        mapping: GamutMapping,
        samples: &[f32; FULL_LEN],
    ) -> [u8; 3] {
        display.encode_u8(mapping, display.linear_from_xyz(self.xyz_8acc(samples)))
    }

    /// The batch loop a renderer would write around [`encode_u8`](Self::encode_u8).
    fn encode_u8_batch(
        &self,
        display: &Display,
        mapping: GamutMapping,
        samples: &[[f32; FULL_LEN]],
        out: &mut [[u8; 3]],
    ) {
        assert_eq!(samples.len(), out.len());
        for (o, s) in out.iter_mut().zip(samples) {
            *o = self.encode_u8(display, mapping, s);
        }
    }

    fn encode_u8_batch_8acc(
        &self,
        display: &Display,
        mapping: GamutMapping,
        samples: &[[f32; FULL_LEN]],
        out: &mut [[u8; 3]],
    ) {
        assert_eq!(samples.len(), out.len());
        for (o, s) in out.iter_mut().zip(samples) {
            *o = self.encode_u8_8acc(display, mapping, s);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Harness helpers

/// One pixel per iteration, cycling through `inputs`; the input reference goes through
/// `black_box` so the work cannot be hoisted, and criterion black-boxes the returned colour.
fn per_pixel<T, R>(
    group: &mut BenchmarkGroup<'_, WallTime>,
    id: &str,
    inputs: &[T],
    f: impl Fn(&T) -> R,
) {
    let inputs: &[T; PIXELS] = inputs.try_into().expect("one input per pixel");
    let f = &f;
    group.bench_function(id, |b| {
        // The index is the routine's own (moved in), so it stays in a register: the loop
        // around the call is an increment and a mask, not a store and reload through memory.
        let mut i = 0usize;
        b.iter(move || {
            let s = black_box(&inputs[i]);
            i = (i + 1) % PIXELS;
            f(s)
        })
    });
}

/// Checks (untimed) that the reference and the quadrature sets agree roughly, so the benchmark
/// compares like with like; prints the mean |Δ| in 8-bit code values.
fn sanity(full: &Full1nm, s1nm: &[[f32; FULL_LEN]], row2: &[[f32; 4]], row1: &[[f32; 6]]) {
    let ones = [1.0f32; FULL_LEN];
    let y = full.xyz(&ones)[1];
    assert!((y - 1.0).abs() < 1e-4, "unit spectrum Y = {y}");
    let (mut d2, mut d1, mut d8) = (0u64, 0u64, 0u64);
    let diff = |a: [u8; 3], b: [u8; 3]| -> u64 {
        a.iter().zip(b).map(|(x, y)| u64::from(x.abs_diff(y))).sum()
    };
    for ((s, r2), r1) in s1nm.iter().zip(row2).zip(row1) {
        let r = full.encode_u8(&SRGB, GamutMapping::Clip, s);
        d8 += diff(r, full.encode_u8_8acc(&SRGB, GamutMapping::Clip, s));
        d2 += diff(
            r,
            folded::TABLE2_ROW2_SRGB.encode_u8(GamutMapping::Clip, r2),
        );
        d1 += diff(
            r,
            folded::TABLE2_ROW1_SRGB.encode_u8(GamutMapping::Clip, r1),
        );
    }
    let n = (3 * PIXELS) as f64;
    eprintln!(
        "sanity: mean |Δ| in sRGB u8 code values vs full_1nm over {PIXELS} spectra: \
         table2_row2 {:.2}, table2_row1 {:.2}, full_1nm_8acc {:.3}",
        d2 as f64 / n,
        d1 as f64 / n,
        d8 as f64 / n
    );
    assert!(d8 as f64 / n < 0.01);
}

// ---------------------------------------------------------------------------------------------
// Benchmarks

fn runtime(c: &mut Criterion) {
    let refl = spectra();
    let row2: &WavelengthSet<4> = &tables::TABLE2_ROW2;
    let row1: &WavelengthSet<6> = &tables::TABLE2_ROW1;
    // The per-pixel closures name the baked consts and `GamutMapping::Clip` directly, as a
    // pixel loop in an application would, so the compiler sees them as constants.
    const ROW2_SRGB: &FoldedSet<4> = &folded::TABLE2_ROW2_SRGB;
    const ROW1_SRGB: &FoldedSet<6> = &folded::TABLE2_ROW1_SRGB;
    assert_eq!(row2.wavelengths_nm(), ROW2_SRGB.wavelengths_nm());
    assert_eq!(row1.wavelengths_nm(), ROW1_SRGB.wavelengths_nm());

    let s_row2 = sample_at(&refl, &row2.wavelengths_nm());
    let s_row1 = sample_at(&refl, &row1.wavelengths_nm());
    let s_1nm = sample_1nm(&refl);
    let full = Full1nm::new();
    sanity(&full, &s_1nm, &s_row2, &s_row1);

    let display = &SRGB;
    let clip = GamutMapping::Clip;

    // The harness alone: the input's reference through `black_box`, its samples copied out.
    let mut g = c.benchmark_group("per_pixel/harness");
    per_pixel(&mut g, "table2_row2", &s_row2, |s| *s);
    g.finish();

    // (a) samples → A, C1, C2.
    let mut g = c.benchmark_group("per_pixel/ac1c2");
    per_pixel(&mut g, "table2_row2", &s_row2, |s| {
        tables::TABLE2_ROW2.ac1c2(s)
    });
    per_pixel(&mut g, "table2_row1", &s_row1, |s| {
        tables::TABLE2_ROW1.ac1c2(s)
    });
    g.finish();

    // (b) samples → linear sRGB: one folded 3×N product (the 1 nm reference: 3×391 → XYZ → RGB).
    let mut g = c.benchmark_group("per_pixel/linear_rgb");
    per_pixel(&mut g, "table2_row2", &s_row2, |s| ROW2_SRGB.linear_rgb(s));
    per_pixel(&mut g, "table2_row1", &s_row1, |s| ROW1_SRGB.linear_rgb(s));
    per_pixel(&mut g, "full_1nm", &s_1nm, |s| full.linear_rgb(display, s));
    g.finish();

    // (c) samples → 8-bit sRGB (Clip).
    let mut g = c.benchmark_group("per_pixel/encode_u8_srgb");
    per_pixel(&mut g, "table2_row2", &s_row2, |s| {
        ROW2_SRGB.encode_u8(GamutMapping::Clip, s)
    });
    per_pixel(&mut g, "table2_row1", &s_row1, |s| {
        ROW1_SRGB.encode_u8(GamutMapping::Clip, s)
    });
    // The set and the mapping passed through `black_box` on every call, as where they are
    // chosen at run time and the call is not inlined into the pixel loop: the weights are
    // loaded and the mapping tested per pixel.
    per_pixel(&mut g, "table2_row2_runtime", &s_row2, |s| {
        black_box(ROW2_SRGB).encode_u8(black_box(GamutMapping::Clip), s)
    });
    per_pixel(&mut g, "full_1nm", &s_1nm, |s| {
        full.encode_u8(display, clip, s)
    });
    per_pixel(&mut g, "full_1nm_8acc", &s_1nm, |s| {
        full.encode_u8_8acc(display, clip, s)
    });
    g.finish();

    // (d) the batch API over all 4096 pixels.
    let mut out = vec![[0u8; 3]; PIXELS];
    let mut g = c.benchmark_group(format!("batch_{PIXELS}/encode_u8_srgb"));
    g.throughput(Throughput::Elements(PIXELS as u64));
    g.bench_function("table2_row2", |b| {
        b.iter(|| {
            ROW2_SRGB
                .encode_u8_batch(clip, black_box(&s_row2), black_box(&mut out))
                .unwrap()
        })
    });
    g.bench_function("table2_row1", |b| {
        b.iter(|| {
            ROW1_SRGB
                .encode_u8_batch(clip, black_box(&s_row1), black_box(&mut out))
                .unwrap()
        })
    });
    g.bench_function("full_1nm", |b| {
        b.iter(|| full.encode_u8_batch(display, clip, black_box(&s_1nm), black_box(&mut out)))
    });
    g.bench_function("full_1nm_8acc", |b| {
        b.iter(|| full.encode_u8_batch_8acc(display, clip, black_box(&s_1nm), black_box(&mut out)))
    });
    g.finish();
    black_box(&out);
}

// ---------------------------------------------------------------------------------------------
// Bandwidth: the planar batch path against the memory bound

/// Pixels of the large planar inputs: 2²⁵ (33.5 million). One plane is 128 MiB, so N = 4 reads
/// 512 MiB and N = 16 reads 2 GiB per pass, against a 32 MiB last-level cache on the machine
/// the README's figures come from: every pass streams from memory.
const BIG_PIXELS: usize = 1 << 25;
/// Pixels of the per-pixel API and the 1 nm integrations, which are far from the memory bound:
/// the first 65 536 of the large inputs (16 copies of the 4096 spectra).
const SMALL_PIXELS: usize = 1 << 16;
/// Padding in f32 between the planes of the `_spaced` cases: 8 KiB.
const SPACING: usize = 2048;
/// Pixels of the in-cache planar case: N · 4 KiB of samples and 3 KiB out fit the 48 KiB
/// first-level data cache for N ≤ 8.
const IN_CACHE_PIXELS: usize = 1 << 10;

/// A uniform set of `N` wavelengths folded for sRGB, built from the 1 nm reference: the 391
/// samples split into `N` equal bins, one node at each bin's centre, its weights the sum of the
/// 1 nm weights in the bin (a box filter). Stands in for the sets of 8 and 16 wavelengths,
/// which the default scene does not bake.
fn uniform_set<const N: usize>(full: &Full1nm, display: &Display) -> FoldedSet<N> {
    let mut weights = [[0.0f64; N]; 3];
    for i in 0..FULL_LEN {
        let bin = i * N / FULL_LEN;
        let xyz: [f64; 3] = core::array::from_fn(|r| f64::from(full.xyz_weights[r][i]));
        for (c, row) in weights.iter_mut().enumerate() {
            row[bin] += (0..3)
                .map(|k| f64::from(display.xyz_to_rgb()[c][k]) * xyz[k])
                .sum::<f64>();
        }
    }
    let wavelengths_nm = core::array::from_fn(|b| {
        let first = (b * FULL_LEN).div_ceil(N);
        let last = ((b + 1) * FULL_LEN).div_ceil(N) - 1;
        (FULL_START_NM + (first + last) as f64 / 2.0 * DLAMBDA_NM) as f32
    });
    FoldedSet::new(
        wavelengths_nm,
        weights.map(|row| row.map(|w| w as f32)),
        spectral_quadrature::Samples::Radiance,
        SRGB,
    )
    .unwrap()
}

/// Planar samples of the 4096 spectra at `nm`, repeated to `BIG_PIXELS` pixels: `[plane][pixel]`.
fn planes<const N: usize>(refl: &[Reflectance], nm: &[f32; N]) -> Vec<Vec<f32>> {
    nm.iter()
        .map(|&l| {
            let one: Vec<f32> = refl.iter().map(|s| s.at(f64::from(l))).collect();
            let mut plane = Vec::with_capacity(BIG_PIXELS);
            while plane.len() < BIG_PIXELS {
                plane.extend_from_slice(&one);
            }
            plane
        })
        .collect()
}

fn plane_refs<const N: usize>(planes: &[Vec<f32>]) -> [&[f32]; N] {
    core::array::from_fn(|i| &planes[i][..])
}

/// Copies of planes in one allocation: plane i at `first + i · stride` f32 into it.
struct OneAllocation {
    all: Vec<f32>,
    first: usize,
    stride: usize,
    len: usize,
}

impl OneAllocation {
    /// `planes` (of one length) copied `stride` f32 apart, with `slack` f32 more allocated in
    /// front of the first; `first` picks where in that slack the first plane starts, from the
    /// allocation's start address.
    fn new<const N: usize>(
        planes: [&[f32]; N],
        stride: usize,
        slack: usize,
        first: impl FnOnce(*const f32) -> usize,
    ) -> Self {
        let len = planes[0].len();
        assert!(len <= stride && planes.iter().all(|p| p.len() == len));
        let mut all = vec![0.0f32; slack + (N - 1) * stride + len];
        let first = first(all.as_ptr());
        assert!(first <= slack);
        for (i, plane) in planes.iter().enumerate() {
            all[first + i * stride..][..len].copy_from_slice(plane);
        }
        Self {
            all,
            first,
            stride,
            len,
        }
    }

    fn planes<const N: usize>(&self) -> [&[f32]; N] {
        core::array::from_fn(|i| &self.all[self.first + i * self.stride..][..self.len])
    }
}

/// Case `soa/srgb_u8_in_cache<layout>/N<n>`: `encode_u8_planar_to_interleaved` (sRGB, `Clip`) on `planes` of
/// `IN_CACHE_PIXELS` pixels each, into the front of `out`.
fn planar_in_cache<const N: usize>(
    g: &mut BenchmarkGroup<'_, WallTime>,
    layout: &str,
    set: &FoldedSet<N>,
    planes: [&[f32]; N],
    out: &mut [[u8; 3]],
) {
    g.bench_function(format!("soa/srgb_u8_in_cache{layout}/N{N}"), |b| {
        b.iter(|| {
            set.encode_u8_planar_to_interleaved(
                GamutMapping::Clip,
                black_box(planes),
                &mut out[..IN_CACHE_PIXELS],
            )
            .unwrap();
            black_box(&mut *out);
        })
    });
}

/// Cases `stream/read_write_3B<layout>/N<n>` and `soa/srgb_u8<layout>/N<n>`: the streaming
/// bound for sRGB u8 on `planes`, then `encode_u8_planar_to_interleaved` (sRGB, `Clip`) on the same planes,
/// both into the first `planes[0].len()` pixels of `out`.
fn planar_against_bound<const N: usize>(
    g: &mut BenchmarkGroup<'_, WallTime>,
    layout: &str,
    set: &FoldedSet<N>,
    planes: [&[f32]; N],
    out: &mut [[u8; 3]],
) {
    let out = &mut out[..planes[0].len()];
    let bound = format!("stream/read_write_3B{layout}/N{N}");
    g.bench_function(&bound, |b| {
        ran(&bound);
        b.iter(|| stream::<N, 3>(black_box(planes), black_box(out.as_flattened_mut())))
    });
    let path = format!("soa/srgb_u8{layout}/N{N}");
    g.bench_function(&path, |b| {
        ran(&path);
        b.iter(|| {
            set.encode_u8_planar_to_interleaved(
                GamutMapping::Clip,
                black_box(planes),
                black_box(&mut *out),
            )
            .unwrap()
        })
    });
}

/// Settings of the `bandwidth` group: each case's warm-up and measurement time (10 samples).
const BANDWIDTH_WARM_UP: Duration = Duration::from_secs(1);
/// See [`BANDWIDTH_WARM_UP`].
const BANDWIDTH_TIME: Duration = Duration::from_secs(3);
/// Measurement time of each `rounds/...` case: criterion fits into it ten samples of one round
/// or more each, so a case runs at least ten rounds, and more where a round is shorter than
/// the tenth of this (about 90 at N = 4 and 25 at N = 16 on the machine of
/// docs/performance.md).
const ROUNDS_TIME: Duration = Duration::from_secs(6);

/// Case `rounds/soa_srgb_u8/N<n>`: the streaming bound for sRGB u8 (`stream::<N, 3>`, as in
/// `stream/read_write_3B/N<n>`) and `encode_u8_planar_to_interleaved` (sRGB, `Clip`, as in `soa/srgb_u8/N<n>`)
/// on the same `planes` and `out`, alternating in rounds of one pass each, the bound first.
/// A round's share of the bound is the bound's time over the path's (the definition of every
/// `ratio` line); [`print_rounds`] prints the median of the rounds' shares and their spread.
///
/// Separate cases measure the bound and the path seconds apart, and the speed of a shared
/// virtual machine drifts in between (the bound alone moved by a third from run to run on the
/// machine of docs/performance.md); within a round both passes see the same machine, so the
/// drift moves both alike and the median of the shares keeps little of it.
///
/// Criterion times each round's pass of the path (its `time:` line is the path's time per pass,
/// measured between passes of the bound) and picks how many rounds go into each of its ten
/// samples from a first round ([`ROUNDS_TIME`]). One untimed round comes before every other:
/// it maps the output's pages, which the allocator hands out untouched.
fn rounds_against_bound<const N: usize>(
    g: &mut BenchmarkGroup<'_, WallTime>,
    set: &FoldedSet<N>,
    planes: [&[f32]; N],
    out: &mut [[u8; 3]],
) {
    let id = format!("rounds/soa_srgb_u8/N{N}");
    let out = &mut out[..planes[0].len()];
    let mut round = || {
        let start = Instant::now();
        stream::<N, 3>(black_box(planes), black_box(out.as_flattened_mut()));
        let bound = start.elapsed();
        let start = Instant::now();
        set.encode_u8_planar_to_interleaved(
            GamutMapping::Clip,
            black_box(planes),
            black_box(&mut *out),
        )
        .unwrap();
        (bound, start.elapsed())
    };
    let mut shares: Vec<[Duration; 2]> = Vec::new();
    let mut primed = false;
    g.warm_up_time(Duration::from_nanos(1))
        .sampling_mode(SamplingMode::Flat)
        .measurement_time(ROUNDS_TIME);
    g.bench_function(&id, |b| {
        if !primed {
            round();
            primed = true;
        }
        b.iter_custom(|rounds| {
            let mut path_total = Duration::ZERO;
            for _ in 0..rounds {
                let (bound, path) = round();
                shares.push([bound, path]);
                path_total += path;
            }
            path_total
        })
    });
    g.warm_up_time(BANDWIDTH_WARM_UP)
        .sampling_mode(SamplingMode::Auto)
        .measurement_time(BANDWIDTH_TIME);
    if !shares.is_empty() {
        ROUNDS.lock().unwrap().push((id, shares));
    }
}

/// The rounds of each `rounds/...` case this process ran: its id and, per round, the bound's
/// and the path's time.
static ROUNDS: std::sync::Mutex<Vec<(String, Vec<[Duration; 2]>)>> =
    std::sync::Mutex::new(Vec::new());

/// Prints, for each `rounds/...` case of set width `n` this process ran, the median of its
/// rounds' shares of the bound (bound time over path time), the middle half and the whole
/// range of those shares, and the median times of the bound and the path, as
/// `rounds bandwidth/<path>/N<n>: … % of the memory bound, median of … rounds`.
fn print_rounds(n: usize) {
    /// The median of `v` (sorted here), and its lower and upper quartiles (the values a quarter
    /// of the way in from either end).
    fn quartiles(v: &mut [f64]) -> [f64; 3] {
        v.sort_by(f64::total_cmp);
        let len = v.len();
        let median = (v[(len - 1) / 2] + v[len / 2]) / 2.0;
        [v[(len - 1) / 4], median, v[len - 1 - (len - 1) / 4]]
    }
    let suffix = format!("/N{n}");
    for (id, rounds) in ROUNDS.lock().unwrap().iter() {
        if !id.ends_with(&suffix) {
            continue;
        }
        let ms = |d: Duration| d.as_secs_f64() * 1e3;
        let mut shares: Vec<f64> = rounds
            .iter()
            .map(|[b, p]| 100.0 * b.as_secs_f64() / p.as_secs_f64())
            .collect();
        let [low, median, high] = quartiles(&mut shares);
        let (min, max) = (shares[0], shares[shares.len() - 1]);
        let [_, bound, _] = quartiles(&mut rounds.iter().map(|r| ms(r[0])).collect::<Vec<_>>());
        let [_, path, _] = quartiles(&mut rounds.iter().map(|r| ms(r[1])).collect::<Vec<_>>());
        let path_name = id.trim_start_matches("rounds/").replacen('_', "/", 1);
        eprintln!(
            "rounds bandwidth/{path_name}: {median:.1} % of the memory bound, median of {} rounds \
             (middle half {low:.1} to {high:.1} %, all {min:.1} to {max:.1} %; bound {bound:.2} ms, \
             path {path:.2} ms median)",
            rounds.len()
        );
    }
}

/// The streaming bound: reads every sample of every plane once and writes `B` bytes per pixel
/// taken from what it read. Nothing else: any conversion must read and write at least this
/// much.
///
/// The bits of each chunk of 16 pixels are xored into one running accumulator, and the
/// accumulator's bytes (repeated) are the chunk's output. Carrying it from chunk to chunk keeps
/// the loop over chunks from being vectorized: built for AVX-512 (`-C target-cpu`), a loop with
/// independent chunks was turned into gathers across 16 chunks at a time, about 27 % slower
/// than plain loads, which would have made every ratio to it look better than it is.
fn stream<const N: usize, const B: usize>(planes: [&[f32]; N], out: &mut [u8]) {
    const CHUNK: usize = 16;
    let pixels = planes[0].len();
    assert!(
        pixels.is_multiple_of(CHUNK)
            && out.len() == B * pixels
            && planes.iter().all(|p| p.len() == pixels)
    );
    let full: [&[[f32; CHUNK]]; N] = planes.map(|p| p.as_chunks::<CHUNK>().0);
    let mut acc = [0u32; CHUNK];
    for (j, o) in out.chunks_exact_mut(B * CHUNK).enumerate() {
        for plane in &full {
            for (a, x) in acc.iter_mut().zip(&plane[j]) {
                *a ^= x.to_bits();
            }
        }
        write_repeated(&acc, o);
    }
}

/// The 64 bytes of 16 values (little-endian), repeated, into `o`: a chunk's `B · 16` output
/// bytes in the streaming bounds.
#[inline]
fn write_repeated(values: &[u32; 16], o: &mut [u8]) {
    let mut bytes = [0u8; 64];
    for (b, v) in bytes.chunks_exact_mut(4).zip(values) {
        b.copy_from_slice(&v.to_le_bytes());
    }
    for o in o.chunks_mut(64) {
        let n = o.len();
        o.copy_from_slice(&bytes[..n]);
    }
}

/// As [`stream`], writing 4 bytes per pixel into each of three planes: the bound for planar
/// f32 output, with the same buffers as `linear_rgb_planar`. It differs from the interleaved
/// 12-byte bound in the layout alone: seven streams (four in, three out) whose buffers, each a
/// large allocation of its own, start at the same offset within a page. On the machine of the
/// README's figures it is the slower of the two (1.96 against 1.48 ns/pixel at N = 4).
fn stream_planes<const N: usize>(planes: [&[f32]; N], out: [&mut [f32]; 3]) {
    const CHUNK: usize = 16;
    let pixels = planes[0].len();
    assert!(
        pixels.is_multiple_of(CHUNK)
            && out.iter().all(|o| o.len() == pixels)
            && planes.iter().all(|p| p.len() == pixels)
    );
    let full: [&[[f32; CHUNK]]; N] = planes.map(|p| p.as_chunks::<CHUNK>().0);
    let [r, g, b] = out;
    let chunks = r
        .as_chunks_mut::<CHUNK>()
        .0
        .iter_mut()
        .zip(g.as_chunks_mut::<CHUNK>().0)
        .zip(b.as_chunks_mut::<CHUNK>().0);
    let mut acc = [0u32; CHUNK];
    for (j, ((r, g), b)) in chunks.enumerate() {
        for plane in &full {
            for (a, x) in acc.iter_mut().zip(&plane[j]) {
                *a ^= x.to_bits();
            }
        }
        let v = acc.map(f32::from_bits);
        *r = v;
        *g = v;
        *b = v;
    }
}

/// The reads of [`stream`] and [`stream_planes`] in the order of the planar loops above four
/// planes: blocks of `PASS_BLOCK` pixels, and within a block the planes four at a time, 16
/// pixels of each in turn, their bits xored into the block's values (on the stack); then
/// `emit(first pixel, values)` writes the block's output. Neither order was the faster at
/// every width on the CPU of the README's figures, so the bound above four planes is the
/// faster of the two.
fn xor_in_passes<const N: usize>(planes: [&[f32]; N], mut emit: impl FnMut(usize, &[u32])) {
    const CHUNK: usize = 16;
    const PASS_PLANES: usize = 4;
    const PASS_BLOCK: usize = 1024;
    let pixels = planes[0].len();
    assert!(pixels.is_multiple_of(CHUNK) && planes.iter().all(|p| p.len() == pixels));
    let mut values = [0u32; PASS_BLOCK];
    for first in (0..pixels).step_by(PASS_BLOCK) {
        let values = &mut values[..PASS_BLOCK.min(pixels - first)];
        for (k, pass) in planes.chunks(PASS_PLANES).enumerate() {
            let (chunks, _) = values.as_chunks_mut::<CHUNK>();
            for (c, v) in chunks.iter_mut().enumerate() {
                let at = first + c * CHUNK;
                // In a local array, from 0 in the first pass: the loop then vectorizes.
                let mut acc = if k == 0 { [0; CHUNK] } else { *v };
                for plane in pass {
                    // Each line asked for 256 bytes ahead, as the planar loops do: without it,
                    // reads that stop at every block's end for other planes wait for memory.
                    #[cfg(target_arch = "x86_64")]
                    // SAFETY: a prefetch is a hint; it reads nothing and any address is allowed.
                    unsafe {
                        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
                        _mm_prefetch::<_MM_HINT_T0>(plane.as_ptr().wrapping_add(at + 64).cast());
                    }
                    let (x, _) = plane[at..].split_first_chunk::<CHUNK>().unwrap();
                    for (a, x) in acc.iter_mut().zip(x) {
                        *a ^= x.to_bits();
                    }
                }
                *v = acc;
            }
        }
        emit(first, values);
    }
}

/// [`stream`] with the reads of [`xor_in_passes`]: each block's values, repeated, are its
/// `B` bytes per pixel.
fn stream_in_passes<const N: usize, const B: usize>(planes: [&[f32]; N], out: &mut [u8]) {
    assert_eq!(out.len(), B * planes[0].len());
    xor_in_passes(planes, |first, values| {
        let o = &mut out[B * first..B * (first + values.len())];
        let (chunks, _) = values.as_chunks::<16>();
        for (o, v) in o.chunks_exact_mut(B * 16).zip(chunks) {
            write_repeated(v, o);
        }
    });
}

/// [`stream_planes`] with the reads of [`xor_in_passes`].
fn stream_planes_in_passes<const N: usize>(planes: [&[f32]; N], out: [&mut [f32]; 3]) {
    assert!(out.iter().all(|o| o.len() == planes[0].len()));
    let [r, g, b] = out;
    xor_in_passes(planes, |first, values| {
        let range = first..first + values.len();
        for o in [&mut r[range.clone()], &mut g[range.clone()], &mut b[range]] {
            for (o, v) in o.iter_mut().zip(values) {
                *o = f32::from_bits(*v);
            }
        }
    });
}

/// One set's part of the bandwidth group: the streaming bounds for its input, the planar path
/// into linear f32 and into sRGB u8 (all on `BIG_PIXELS` pixels), the sRGB u8 path again on the
/// first `IN_CACHE_PIXELS`, and the per-pixel API on the first `SMALL_PIXELS`.
fn bandwidth_set<const N: usize>(
    g: &mut BenchmarkGroup<'_, WallTime>,
    refl: &[Reflectance],
    set: &FoldedSet<N>,
) {
    let planes = planes(refl, &set.wavelengths_nm());
    let samples = plane_refs::<N>(&planes);
    let clip = GamutMapping::Clip;

    // Untimed: the planar path agrees with the per-pixel one on the first pixels.
    let mut check = vec![[0u8; 3]; SMALL_PIXELS];
    let head: [&[f32]; N] = samples.map(|p| &p[..SMALL_PIXELS]);
    set.encode_u8_planar_to_interleaved(clip, head, &mut check)
        .unwrap();
    let mut differ = 0;
    for (p, o) in check.iter().enumerate() {
        let one = set.encode_u8(clip, &core::array::from_fn(|i| samples[i][p]));
        // SRGB8_MAX_ERROR is 0: the same bytes.
        assert!(
            (0..3).all(|c| u16::from(o[c].abs_diff(one[c])) <= u16::from(SRGB8_MAX_ERROR)),
            "pixel {p}: {o:?} {one:?}"
        );
        differ += usize::from(*o != one);
    }
    eprintln!("bandwidth N{N}: planar sRGB u8 differs from encode_u8 on {differ} of {SMALL_PIXELS} pixels (by 1 step)");

    g.throughput(Throughput::Elements(BIG_PIXELS as u64));
    let mut bytes = vec![0u8; 3 * BIG_PIXELS];
    g.bench_function(format!("stream/read_write_3B/N{N}"), |b| {
        ran(&format!("stream/read_write_3B/N{N}"));
        b.iter(|| stream::<N, 3>(black_box(samples), black_box(&mut bytes)))
    });
    if N > 4 {
        g.bench_function(format!("stream/read_write_3B_passes/N{N}"), |b| {
            ran(&format!("stream/read_write_3B_passes/N{N}"));
            b.iter(|| stream_in_passes::<N, 3>(black_box(samples), black_box(&mut bytes)))
        });
    }
    drop(bytes);
    let mut bytes = vec![0u8; 12 * BIG_PIXELS];
    g.bench_function(format!("stream/read_write_12B/N{N}"), |b| {
        ran(&format!("stream/read_write_12B/N{N}"));
        b.iter(|| stream::<N, 12>(black_box(samples), black_box(&mut bytes)))
    });
    drop(bytes);

    let mut lin = [0, 1, 2].map(|_| vec![0.0f32; BIG_PIXELS]);
    g.bench_function(format!("stream/read_write_3x4B/N{N}"), |b| {
        ran(&format!("stream/read_write_3x4B/N{N}"));
        b.iter(|| {
            let [r, gr, bl] = &mut lin;
            stream_planes::<N>(black_box(samples), [r, gr, bl]);
            black_box(&mut lin);
        })
    });
    if N > 4 {
        g.bench_function(format!("stream/read_write_3x4B_passes/N{N}"), |b| {
            ran(&format!("stream/read_write_3x4B_passes/N{N}"));
            b.iter(|| {
                let [r, gr, bl] = &mut lin;
                stream_planes_in_passes::<N>(black_box(samples), [r, gr, bl]);
                black_box(&mut lin);
            })
        });
    }
    g.bench_function(format!("soa/linear/N{N}"), |b| {
        ran(&format!("soa/linear/N{N}"));
        b.iter(|| {
            let [r, gr, bl] = &mut lin;
            set.linear_rgb_planar(black_box(samples), [r, gr, bl])
                .unwrap();
            black_box(&mut lin);
        })
    });
    drop(lin);
    // The same with the output planes shifted against each other by `c` cache lines (at
    // different offsets within a page): the layout's share of the gap to the bound.
    let mut shifted = [0, 1, 2].map(|_| vec![0.0f32; BIG_PIXELS + 32]);
    g.bench_function(format!("soa/linear_offset/N{N}"), |b| {
        ran(&format!("soa/linear_offset/N{N}"));
        b.iter(|| {
            let [r, gr, bl] = &mut shifted;
            let [r, gr, bl] =
                [(r, 0), (gr, 1), (bl, 2)].map(|(p, c)| &mut p[16 * c..16 * c + BIG_PIXELS]);
            set.linear_rgb_planar(black_box(samples), [r, gr, bl])
                .unwrap();
            black_box(&mut shifted);
        })
    });
    drop(shifted);
    let mut out = vec![[0u8; 3]; BIG_PIXELS];
    g.bench_function(format!("soa/srgb_u8/N{N}"), |b| {
        ran(&format!("soa/srgb_u8/N{N}"));
        b.iter(|| {
            set.encode_u8_planar_to_interleaved(clip, black_box(samples), black_box(&mut out))
                .unwrap()
        })
    });
    rounds_against_bound(g, set, samples, &mut out);

    // The same planes, each from its first 64-byte boundary on, over 2²⁵ - 16 pixels (so that
    // every plane holds them): a plane that starts off a boundary has each 64-byte line read
    // by two groups of 16 pixels, one that starts on it by one. (Large blocks from the system
    // allocator start 16 bytes past a page on glibc.) The bound on the same bytes runs first.
    let lines: [&[f32]; N] = samples.map(|p| {
        let skip = p.as_ptr().align_offset(64);
        &p[skip..skip + BIG_PIXELS - 16]
    });
    planar_against_bound(g, "_aligned", set, lines, &mut out);

    // The same planes in one allocation, each starting 8 KiB past the end of the one before.
    // Separate allocations of 2²⁵ f32 (the planes above) come from the system allocator 128 MiB
    // and 4 KiB apart, and planes that far apart slow the streaming loads on the CPU of the
    // README's figures (AMD Zen 3): the bound and the path are measured again on these, each
    // against the other.
    let spaced = OneAllocation::new(samples, BIG_PIXELS + SPACING, 0, |_| 0);
    planar_against_bound(g, "_spaced", set, spaced.planes(), &mut out);
    drop(spaced);

    // The same pixels interleaved, one `[f32; N]` each (`encode_u8_batch`): the same bytes
    // read and written as the planar case, so the same streaming bound.
    drop(out);
    let aos: Vec<[f32; N]> = (0..BIG_PIXELS)
        .map(|p| core::array::from_fn(|i| samples[i][p]))
        .collect();
    let mut out = vec![[0u8; 3]; BIG_PIXELS];
    g.bench_function(format!("aos/srgb_u8/N{N}"), |b| {
        ran(&format!("aos/srgb_u8/N{N}"));
        b.iter(|| {
            set.encode_u8_batch(clip, black_box(&aos), black_box(&mut out))
                .unwrap()
        })
    });
    drop(aos);

    // The same on the first `IN_CACHE_PIXELS`, whose planes stay in the first-level cache:
    // the cost of the work itself, without waiting for memory.
    g.throughput(Throughput::Elements(IN_CACHE_PIXELS as u64));
    let head: [&[f32]; N] = samples.map(|p| &p[..IN_CACHE_PIXELS]);
    planar_in_cache(g, "", set, head, &mut out);
    // The same samples copied into one allocation, plane after plane, each 64 bytes past a
    // multiple of 4 KiB from the last: the planes of `soa/srgb_u8_in_cache` start at the same
    // offset within a page, as separate large allocations of one size do.
    let copied = OneAllocation::new(head, IN_CACHE_PIXELS + 16, 0, |_| 0);
    let copies: [&[f32]; N] = copied.planes();
    planar_in_cache(g, "_offset", set, copies, &mut out);
    drop(copied);
    // The same samples in one allocation, each plane 16 KiB after the last, so at the same
    // offset within a page as the planes of `soa/srgb_u8_in_cache`: these differ from those
    // only in how far apart they lie (separate allocations of 2²⁵ f32 lie 128 MiB and 4 KiB
    // apart).
    let page_offset = |p: *const f32| p as usize % 4096;
    // In f32, from the allocation's start to the first f32 at the offset of `head[0]`; both
    // addresses are multiples of 4, so their difference is too.
    let close = OneAllocation::new(head, 4096, 1024, |start| {
        (page_offset(head[0].as_ptr()) + 4096 - page_offset(start)) % 4096 / 4
    });
    let close_planes: [&[f32]; N] = close.planes();
    assert!(close_planes
        .iter()
        .zip(&head)
        .all(|(c, h)| page_offset(c.as_ptr()) == page_offset(h.as_ptr())));
    planar_in_cache(g, "_close", set, close_planes, &mut out);
    drop(close);

    // The per-pixel API on the same samples, as a renderer would call it per pixel.
    g.throughput(Throughput::Elements(SMALL_PIXELS as u64));
    g.bench_function(format!("per_pixel/srgb_u8/N{N}"), |b| {
        b.iter(|| {
            let samples = black_box(samples);
            for (p, o) in out[..SMALL_PIXELS].iter_mut().enumerate() {
                *o = set.encode_u8(clip, &core::array::from_fn(|i| samples[i][p]));
            }
            black_box(&mut out);
        })
    });
}

/// Criterion ids (within the `bandwidth` group) of the cases this process has run: the ratios
/// are printed only between cases measured in the same run.
static RAN: std::sync::Mutex<Vec<String>> = std::sync::Mutex::new(Vec::new());

/// Records that case `id` of the `bandwidth` group runs in this process (criterion calls a
/// case's closure only when the filter selects it).
fn ran(id: &str) {
    let mut ran = RAN.lock().unwrap();
    if !ran.iter().any(|r| r == id) {
        ran.push(id.to_owned());
    }
}

/// The median time of case `id` of the `bandwidth` group from criterion's estimates file, if it
/// ran in this process.
fn median_ns(id: &str) -> Option<f64> {
    if !RAN.lock().unwrap().iter().any(|r| r == id) {
        return None;
    }
    // Where criterion writes: the workspace's target directory (cargo runs a bench in its
    // package's directory, benches/).
    let dir = std::env::var_os("CARGO_TARGET_DIR").map_or_else(
        || std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../target")),
        std::path::PathBuf::from,
    );
    let path = dir
        .join("criterion/bandwidth")
        .join(id.replace('/', "_"))
        .join("new/estimates.json");
    let text = std::fs::read_to_string(&path).ok()?;
    let json: serde_json::Value = serde_json::from_str(&text).ok()?;
    json["median"]["point_estimate"].as_f64()
}

/// Prints, for set width `n`, each path's median against its streaming bound's: the share of
/// the memory bound it reaches (the bound's time over the path's).
fn print_ratios(n: usize) {
    let cases = [
        ("soa/srgb_u8", "stream/read_write_3B"),
        ("soa/srgb_u8", "stream/read_write_3B_passes"),
        ("soa/srgb_u8_spaced", "stream/read_write_3B_spaced"),
        ("soa/srgb_u8_aligned", "stream/read_write_3B_aligned"),
        ("soa/linear", "stream/read_write_3x4B"),
        ("soa/linear", "stream/read_write_3x4B_passes"),
        ("soa/linear", "stream/read_write_12B"),
        ("soa/linear_offset", "stream/read_write_12B"),
        ("aos/srgb_u8", "stream/read_write_3B"),
        ("aos/srgb_u8", "stream/read_write_3B_passes"),
    ];
    for (path, bound) in cases {
        let (Some(p), Some(b)) = (
            median_ns(&format!("{path}/N{n}")),
            median_ns(&format!("{bound}/N{n}")),
        ) else {
            continue;
        };
        eprintln!(
            "ratio bandwidth/{path}/N{n}: {:.1} % of the memory bound ({bound}: {:.2} ms, path: {:.2} ms median, {:.3} ns/pixel)",
            100.0 * b / p,
            b / 1e6,
            p / 1e6,
            p / BIG_PIXELS as f64
        );
    }
}

/// Everything the README's Performance section quotes, in one run: for N = 4 (Table 2 row 2),
/// 6 (row 1), 8 and 16 (uniform sets, see [`uniform_set`]):
///
/// - `stream/read_write_3B/N<n>`: read N·4 bytes per pixel, write 3 (the bound for sRGB u8);
///   `stream/read_write_12B/N<n>`: write 12, interleaved; `stream/read_write_3x4B/N<n>`: write
///   4 into each of three planes, the buffers of `soa/linear` (the bound for planar linear f32;
///   see [`stream_planes`]); above four planes also `stream/read_write_3B_passes/N<n>` and
///   `stream/read_write_3x4B_passes/N<n>`, the same bytes read four planes at a time over
///   blocks of pixels, as the planar loops read them there (see [`xor_in_passes`]): the bound
///   is the faster of the two;
/// - `soa/linear/N<n>`: `linear_rgb_planar`, N planes → 3 planes of f32;
///   `soa/linear_offset/N<n>`: the same into output planes shifted by 0, 1 and 2 cache lines;
/// - `soa/srgb_u8/N<n>`: `encode_u8_planar_to_interleaved` (sRGB, Clip) → interleaved `[u8; 3]`;
///   `aos/srgb_u8/N<n>`: `encode_u8_batch` on the same pixels interleaved (`[f32; N]` each);
///   `soa/srgb_u8_spaced/N<n>`: the same planes copied into one allocation 8 KiB apart,
///   against `stream/read_write_3B_spaced/N<n>`, the bound on those planes;
///   `soa/srgb_u8_aligned/N<n>`: the same planes each from its first 64-byte boundary on,
///   against `stream/read_write_3B_aligned/N<n>`, the bound on those bytes;
///   `soa/srgb_u8_in_cache/N<n>`: the same on the first `IN_CACHE_PIXELS` only, in cache;
///   `soa/srgb_u8_in_cache_offset/N<n>`: those samples copied to planes 64 bytes apart modulo
///   4 KiB; `soa/srgb_u8_in_cache_close/N<n>`: copied to planes 16 KiB apart, at the same
///   offset within a page as the bench's planes;
/// - `rounds/soa_srgb_u8/N<n>`: the bound of `stream/read_write_3B/N<n>` and the path of
///   `soa/srgb_u8/N<n>` alternating in rounds (see [`rounds_against_bound`]);
/// - `per_pixel/srgb_u8/N<n>`: `encode_u8` per pixel on the same planes;
/// - `full_1nm/srgb_u8`, `full_1nm_8acc/srgb_u8`: the 1 nm integration of the same spectra
///   (in-order sums, and 8 partial sums that vectorize), then the same encode.
///
/// Sizes: the stream and `soa` cases run over `BIG_PIXELS` = 2²⁵ pixels (the 4096 spectra
/// repeated), 512 MiB to 2 GiB of input, beyond the last-level cache; the in-cache case over
/// `IN_CACHE_PIXELS` = 1024. The per-pixel and 1 nm cases take 180 to 1000 ns per pixel, far
/// from any memory bound, and run over the first `SMALL_PIXELS` = 65 536 of them (1 nm:
/// 100 MiB of samples). Throughput is in pixels, so criterion's time per element is ns/pixel.
///
/// At the end it prints, for each path, its median against its bound's from this run, as
/// `ratio bandwidth/<path>/N<n>: … % of the memory bound`, and for each `rounds` case the
/// median of its rounds' shares (see [`print_rounds`]).
fn bandwidth(c: &mut Criterion) {
    // Which of the crate's x86-64 loops this CPU takes (the crate detects the same features).
    #[cfg(target_arch = "x86_64")]
    {
        let loops = if std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512bw")
            && std::arch::is_x86_feature_detected!("avx512vbmi")
        {
            "AVX-512 loops (avx512f, avx512bw, avx512vbmi: planar, and interleaved at N = 4)"
        } else if std::arch::is_x86_feature_detected!("avx2") {
            "AVX2 loops"
        } else {
            "portable loops (SSE2)"
        };
        eprintln!("bandwidth: this CPU runs the crate's {loops}");
    }
    let refl = spectra();
    let full = Full1nm::new();
    let mut g = c.benchmark_group("bandwidth");
    g.sample_size(10)
        .warm_up_time(BANDWIDTH_WARM_UP)
        .measurement_time(BANDWIDTH_TIME);
    bandwidth_set(&mut g, &refl, &folded::TABLE2_ROW2_SRGB);
    bandwidth_set(&mut g, &refl, &folded::TABLE2_ROW1_SRGB);
    bandwidth_set(&mut g, &refl, &uniform_set::<8>(&full, &SRGB));
    bandwidth_set(&mut g, &refl, &uniform_set::<16>(&full, &SRGB));

    // The 1 nm integration of the same spectra: 16 copies of the 4096.
    let one = sample_1nm(&refl);
    let s_1nm: Vec<[f32; FULL_LEN]> = one.iter().cycle().take(SMALL_PIXELS).copied().collect();
    drop(one);
    let mut out = vec![[0u8; 3]; SMALL_PIXELS];
    g.throughput(Throughput::Elements(SMALL_PIXELS as u64));
    g.bench_function("full_1nm/srgb_u8", |b| {
        b.iter(|| {
            full.encode_u8_batch(
                &SRGB,
                GamutMapping::Clip,
                black_box(&s_1nm),
                black_box(&mut out),
            )
        })
    });
    g.bench_function("full_1nm_8acc/srgb_u8", |b| {
        b.iter(|| {
            full.encode_u8_batch_8acc(
                &SRGB,
                GamutMapping::Clip,
                black_box(&s_1nm),
                black_box(&mut out),
            )
        })
    });
    g.finish();
    for n in [4, 6, 8, 16] {
        print_ratios(n);
        print_rounds(n);
    }
}

/// The 8-bit sRGB encoders side by side, on the same linear values: the linear RGB of the
/// first `SMALL_PIXELS` pixels of Table 2 row 2 (3 · 65 536 values, in cache), one value per
/// call, throughput in values:
///
/// - `encoder/srgb8_from_linear`: the crate's table encoder, correctly rounded;
/// - `encoder/fast_srgb8`: the `fast-srgb8` crate's `f32_to_srgb8`, and `encoder/fast_srgb8_x4`
///   its four-at-a-time `f32x4_to_srgb8`;
/// - `encoder/powf`: the sRGB formula with f32 `powf`, times 255, rounded.
///
/// Untimed, it prints on how many of the values each differs from the crate's (which
/// `tests/planar.rs` checks against the exact curve for every f32).
fn encoders(c: &mut Criterion) {
    let refl = spectra();
    let set = &folded::TABLE2_ROW2_SRGB;
    let planes = planes(&refl, &set.wavelengths_nm());
    let samples: [&[f32]; 4] = core::array::from_fn(|i| &planes[i][..SMALL_PIXELS]);
    let mut lin = [0, 1, 2].map(|_| vec![0.0f32; SMALL_PIXELS]);
    {
        let [r, g, b] = &mut lin;
        set.linear_rgb_planar(samples, [r, g, b]).unwrap();
    }
    drop(planes);
    let values: Vec<f32> = lin.concat();
    let powf = |x: f32| -> u8 {
        let x = x.clamp(0.0, 1.0);
        let e = if x <= 0.003_130_8 {
            12.92 * x
        } else {
            1.055 * x.powf(1.0 / 2.4) - 0.055
        };
        (e * 255.0 + 0.5) as u8
    };
    let ours: Vec<u8> = values
        .iter()
        .map(|&x| spectral_quadrature::srgb8_from_linear(x))
        .collect();
    let differ = |f: &dyn Fn(f32) -> u8| {
        values
            .iter()
            .zip(&ours)
            .filter(|(x, o)| f(**x) != **o)
            .count()
    };
    eprintln!(
        "encoder: of {} values, fast_srgb8 differs from the correctly rounded code on {}, powf on {}",
        values.len(),
        differ(&fast_srgb8::f32_to_srgb8),
        differ(&powf)
    );

    let mut g = c.benchmark_group("encoder");
    g.throughput(Throughput::Elements(values.len() as u64));
    let mut out = vec![0u8; values.len()];
    g.bench_function("srgb8_from_linear", |b| {
        b.iter(|| {
            for (o, x) in out.iter_mut().zip(black_box(&values)) {
                *o = spectral_quadrature::srgb8_from_linear(*x);
            }
            black_box(&mut out);
        })
    });
    g.bench_function("fast_srgb8", |b| {
        b.iter(|| {
            for (o, x) in out.iter_mut().zip(black_box(&values)) {
                *o = fast_srgb8::f32_to_srgb8(*x);
            }
            black_box(&mut out);
        })
    });
    g.bench_function("fast_srgb8_x4", |b| {
        b.iter(|| {
            let (o4, _) = out.as_chunks_mut::<4>();
            let (v4, _) = black_box(&values).as_chunks::<4>();
            for (o, x) in o4.iter_mut().zip(v4) {
                *o = fast_srgb8::f32x4_to_srgb8(*x);
            }
            black_box(&mut out);
        })
    });
    g.bench_function("powf", |b| {
        b.iter(|| {
            for (o, x) in out.iter_mut().zip(black_box(&values)) {
                *o = powf(*x);
            }
            black_box(&mut out);
        })
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2))
        .sample_size(50);
    targets = runtime, bandwidth, encoders
}
criterion_main!(benches);
