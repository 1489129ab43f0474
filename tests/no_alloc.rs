//! The runtime never allocates: a counting global allocator wraps `System` and counts every
//! `alloc`, `alloc_zeroed` and `realloc` made by the current thread while counting is switched
//! on for it (a thread-local flag and a thread-local counter, so the test harness's other threads
//! and the other tests cannot disturb a measurement). Inputs and outputs are prepared before
//! counting starts and pass through `black_box`, so nothing is optimized away.

mod common;

use common::{FOLDED_ROW1, FOLDED_ROW2, MAPPINGS};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::fmt::Write as _;
use std::hint::black_box;

use spectral_quadrature::tables::{self, displays, folded, rules};
use spectral_quadrature::{
    ac1c2_from_xyz, quantize_u16, quantize_u8, xyz_from_ac1c2, Channel, ChannelLuts, Display,
    DisplayError, DynamicSet, Error, FoldedSet, GamutMapping, LengthOf, Rgb, TransferFunction,
};

struct Counting;

thread_local! {
    /// Whether this thread's allocations are being counted.
    static ACTIVE: Cell<bool> = const { Cell::new(false) };
    /// This thread's count of alloc / alloc_zeroed / realloc calls while ACTIVE.
    static COUNT: Cell<usize> = const { Cell::new(0) };
}

fn note_allocation() {
    // `try_with`: never panic inside the allocator (e.g. during thread-local destruction).
    if ACTIVE.try_with(Cell::get).unwrap_or(false) {
        let _ = COUNT.try_with(|c| c.set(c.get() + 1));
    }
}

// SAFETY: every call is forwarded unchanged to `System`; the bookkeeping touches only
// const-initialized thread-locals without destructors, which never allocate.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note_allocation();
        // SAFETY: the caller upholds `GlobalAlloc::alloc`'s contract, passed on as is.
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note_allocation();
        // SAFETY: as `alloc`.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note_allocation();
        // SAFETY: `ptr` and `layout` come from this allocator, i.e. from `System`.
        unsafe { System.realloc(ptr, layout, new_size) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` and `layout` come from this allocator, i.e. from `System`.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Runs `f` with counting on for this thread and returns how many allocations it made.
fn allocations_in(f: impl FnOnce()) -> usize {
    let before = COUNT.with(Cell::get);
    ACTIVE.with(|a| a.set(true));
    f();
    ACTIVE.with(|a| a.set(false));
    COUNT.with(Cell::get) - before
}

fn assert_no_alloc(what: &str, f: impl FnOnce()) {
    let n = allocations_in(f);
    assert_eq!(n, 0, "{what}: {n} allocation(s)");
}

/// Linear colours that reach every branch of the gamut mapping: in gamut, out of gamut on both
/// sides, A ≤ 0, A ≥ white, infinite and NaN channels.
const COLOURS: [[f32; 3]; 8] = [
    [0.2, 0.5, 0.7],
    [1.4, 0.3, -0.2],
    [-0.3, 0.9, 1.6],
    [-1.0, -1.0, 0.5],
    [3.0, 3.0, 2.0],
    [f32::INFINITY, 0.5, f32::NEG_INFINITY],
    [f32::NAN, 0.5, 0.5],
    [1e-45, 0.0, -0.0],
];

const LUT_R: &[f32] = &[0.0, 0.35, 0.55, 0.7, 0.82, 0.92, 1.0];
const LUT_G: &[f32] = &[0.0, 0.5, 1.0];
const LUT_B: &[f32] = &[0.0, 0.2, 0.2, 0.6, 1.0];

fn all_displays() -> Vec<Display> {
    let luts = ChannelLuts::new([LUT_R, LUT_G, LUT_B]).expect("valid tables");
    let mut v = displays::ALL.to_vec();
    v.push(displays::SRGB.with_transfer(TransferFunction::Lut(luts)));
    v
}

#[test]
fn the_counter_sees_allocations() {
    // Sanity checks: the test below would fail if the runtime allocated.
    assert!(allocations_in(|| drop(black_box(Box::new(black_box(7u64))))) >= 1);
    assert!(allocations_in(|| drop(black_box(Vec::<f32>::with_capacity(black_box(64))))) >= 1);
    let mut v: Vec<u8> = Vec::with_capacity(1);
    v.push(1);
    let n = allocations_in(|| {
        for k in 0..100u8 {
            v.push(black_box(k)); // grows: realloc
        }
    });
    assert!(n >= 1, "realloc counted: {n}");
    assert!(allocations_in(|| drop(black_box(format!("{}", black_box(12345))))) >= 1);
    // Counting is off outside `allocations_in`, and a region without allocations counts 0.
    let before = COUNT.with(Cell::get);
    drop(black_box(Box::new(1u8)));
    assert_eq!(COUNT.with(Cell::get), before);
    assert_eq!(
        allocations_in(|| {
            black_box(1u64 + black_box(2));
        }),
        0
    );
}

#[test]
fn per_pixel_paths_do_not_allocate() {
    let displays = all_displays();
    let s6 = black_box([0.2f32, 0.9, 0.4, 1.7, 0.05, 0.6]);
    let s4 = black_box([0.3f32, 0.8, 1.2, 0.1]);
    let s16 = black_box([0.5f32; 16]);
    let specials6 = black_box([f32::NAN, f32::INFINITY, -0.0, 1e-45, f32::MAX, -1.0]);
    assert_no_alloc("ac1c2 / xyz / matrices", || {
        black_box(tables::TABLE2_ROW1.ac1c2(&s6));
        black_box(tables::TABLE2_ROW1.ac1c2(&specials6));
        black_box(tables::TABLE2_ROW2.ac1c2(&s4));
        black_box(rules::A_16.ac1c2(&s16));
        black_box(tables::TABLE2_ROW1.xyz(&s6));
        black_box(tables::TABLE2_ROW2.xyz(&s4));
        black_box(xyz_from_ac1c2(black_box([100.0, -3.0, 20.0])));
        black_box(ac1c2_from_xyz(black_box([0.9, 1.0, 1.1])));
    });
    assert_no_alloc("linear_rgb / encode_u8 / encode_u16 / fold", || {
        for (j, display) in displays::ALL.iter().enumerate() {
            black_box(FOLDED_ROW1[j].linear_rgb(&s6));
            black_box(FOLDED_ROW2[j].linear_rgb(&s4));
            black_box(FOLDED_ROW1[j].linear_rgb(&specials6));
            black_box(display.linear_from_xyz(black_box([0.3, 0.4, 0.5])));
            black_box(display.xyz_from_linear(black_box([0.3, 0.4, 0.5])));
            black_box(tables::TABLE2_ROW1.fold(display, 1.0 / tables::UNIT_SPECTRUM_Y));
            for mapping in MAPPINGS {
                black_box(FOLDED_ROW1[j].encode_u8(mapping, &s6));
                black_box(FOLDED_ROW1[j].encode_u16(mapping, &specials6));
                black_box(FOLDED_ROW2[j].encode_u8(mapping, &s4));
                black_box(FOLDED_ROW2[j].encode_u16(mapping, &s4));
            }
        }
    });
    assert_no_alloc(
        "Display map_gamut / encode / encode_u8 / encode_u16",
        || {
            for display in &displays {
                for mapping in MAPPINGS {
                    for rgb in COLOURS {
                        let rgb = black_box(rgb);
                        black_box(display.map_gamut(mapping, rgb));
                        black_box(display.encode(mapping, rgb));
                        black_box(display.encode_u8(mapping, rgb));
                        black_box(display.encode_u16(mapping, rgb));
                    }
                }
            }
        },
    );
}

#[test]
fn transfer_functions_and_luts_do_not_allocate() {
    let luts = ChannelLuts::new([LUT_R, LUT_G, LUT_B]).expect("valid tables");
    let transfers = [
        TransferFunction::Linear,
        TransferFunction::Srgb,
        TransferFunction::Gamma(2.2),
        TransferFunction::Gamma(f32::NAN),
        TransferFunction::Lut(luts),
    ];
    let xs = black_box([
        f32::NAN,
        -1.0,
        0.0,
        1e-45,
        0.001,
        0.2,
        0.5,
        0.99,
        1.0,
        f32::INFINITY,
    ]);
    assert_no_alloc("encode / decode / quantize", || {
        for tf in &transfers {
            for c in Rgb::ALL {
                for &x in &xs {
                    black_box(tf.encode(c, x));
                    black_box(tf.decode(c, x));
                    black_box(quantize_u8(x));
                    black_box(quantize_u16(x));
                    #[cfg(feature = "micromath")]
                    black_box(tf.encode_fast(c, x));
                }
            }
        }
    });
    assert_no_alloc("ChannelLuts::new", || {
        black_box(ChannelLuts::new(black_box([LUT_R, LUT_G, LUT_B])).is_ok());
        black_box(ChannelLuts::new(black_box([LUT_R, &[0.5, 0.1], LUT_B])).is_err());
    });
}

#[test]
fn batch_apis_do_not_allocate() {
    let displays = all_displays();
    let set = folded::TABLE2_ROW1_SRGB;
    let pixels: Vec<[f32; 6]> = (0..256)
        .map(|p| std::array::from_fn(|i| ((p * 7 + i * 13) % 29) as f32 / 17.0 - 0.2))
        .collect();
    let mut lin = vec![[0.0f32; 3]; pixels.len()];
    let mut ac = vec![[0.0f32; 3]; pixels.len()];
    let mut out8 = vec![[0u8; 3]; pixels.len()];
    let mut out16 = vec![[0u16; 3]; pixels.len()];
    let mut short = vec![[0.0f32; 3]; pixels.len() - 1];
    let mut results: [Result<(), Error>; 5] = [Ok(()); 5];
    assert_no_alloc("batch", || {
        results[0] = set.linear_rgb_batch(&pixels, &mut lin);
        results[1] = tables::TABLE2_ROW1.ac1c2_batch(&pixels, &mut ac);
        for display in &displays {
            // The same weights with each display's transfer function, to run every encoder.
            let set = FoldedSet::new(set.wavelengths_nm(), set.weights(), set.samples(), *display)
                .unwrap();
            for mapping in MAPPINGS {
                results[2] = set.encode_u8_batch(mapping, &pixels, &mut out8);
                results[3] = set.encode_u16_batch(mapping, &pixels, &mut out16);
            }
        }
        // The error path too.
        results[4] = set.linear_rgb_batch(&pixels, &mut short);
        black_box((&lin, &ac, &out8, &out16, &results));
    });
    assert_eq!(results[..4], [Ok(()); 4]);
    assert_eq!(
        results[4],
        Err(Error::LengthMismatch {
            what: LengthOf::Output,
            expected: 256,
            got: 255
        })
    );
    // The outputs were really written.
    assert_eq!(lin[5], set.linear_rgb(&pixels[5]));
    assert_eq!(
        out16[9],
        FoldedSet::new(
            set.wavelengths_nm(),
            set.weights(),
            set.samples(),
            displays[displays.len() - 1]
        )
        .unwrap()
        .encode_u16(GamutMapping::PreserveA, &pixels[9])
    );
}

/// A fixed-size `fmt::Write` target on the stack.
struct StackText {
    buf: [u8; 128],
    len: usize,
}

impl std::fmt::Write for StackText {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        let end = self.len + s.len();
        if end > self.buf.len() {
            return Err(std::fmt::Error);
        }
        self.buf[self.len..end].copy_from_slice(s.as_bytes());
        self.len = end;
        Ok(())
    }
}

#[test]
fn dynamic_sets_and_errors_do_not_allocate() {
    let rules = black_box([tables::A_RULES[3], tables::C1_RULES[3], tables::C2_RULES[2]]);
    let samples = black_box([0.4f32; 16]);
    let mut outcome = None;
    assert_no_alloc("DynamicSet", || {
        let set = DynamicSet::<16>::from_rules(&rules).expect("11 wavelengths fit");
        let n = set.len();
        let sums = black_box(set.ac1c2(&samples[..n]));
        let mismatch = black_box(set.ac1c2(&samples[..n - 1]));
        black_box((set.wavelengths_nm(), set.weights(Channel::C1)));
        let mut small = DynamicSet::<4>::new();
        let capacity = small.add_rule(&tables::A_RULES[4]); // 5 > 4
        let undefined = small.add_rule(&tables::C1_RULES[0]);
        let added = small.add_rule(&tables::A_RULES[3]);
        outcome = Some((n, sums, mismatch, capacity, undefined, added));
    });
    let (n, sums, mismatch, capacity, undefined, added) = outcome.expect("ran");
    assert_eq!(n, 11);
    assert!(sums.expect("right length")[0] > 0.0);
    assert_eq!(
        mismatch,
        Err(Error::LengthMismatch {
            what: LengthOf::Samples,
            expected: 11,
            got: 10
        })
    );
    assert_eq!(capacity, Err(Error::Capacity { capacity: 4 }));
    assert_eq!(
        undefined,
        Err(Error::UndefinedRule {
            channel: Channel::C1,
            order: 1
        })
    );
    assert_eq!(added, Ok(()));
    // Error's Display writes without allocating (into a stack buffer).
    let mut text = StackText {
        buf: [0; 128],
        len: 0,
    };
    assert_no_alloc("Error Display", || {
        for e in [
            Error::LengthMismatch {
                what: LengthOf::InputPlane,
                expected: 1,
                got: 2,
            },
            Error::Capacity { capacity: 4 },
            Error::UndefinedRule {
                channel: Channel::C2,
                order: 4,
            },
            Error::Display(DisplayError::Gamma { gamma: -1.0 }),
            Error::InvalidLut { channel: Rgb::R },
        ] {
            text.len = 0;
            write!(text, "{e}").expect("fits in 128 bytes");
            black_box(&text.buf[..text.len]);
        }
    });
    assert_eq!(
        std::str::from_utf8(&text.buf[..text.len]).unwrap(),
        "lookup table for channel R needs 2 or more finite, non-decreasing entries in 0..=1"
    );
}

#[test]
fn planar_paths_never_allocate() {
    let set = folded::TABLE2_ROW2_SRGB;
    let planes: [Vec<f32>; 4] = [
        (0..100).map(|p| p as f32 / 100.0).collect(),
        vec![0.2; 100],
        vec![f32::NAN; 100],
        vec![0.4; 100],
    ];
    let samples = planes.each_ref().map(|p| &p[..]);
    let mut out = vec![[0u8; 3]; 100];
    let mut out16 = vec![[0u16; 3]; 100];
    let mut lin = [0, 1, 2].map(|_| vec![0.0f32; 100]);
    let mut planes8 = [0, 1, 2].map(|_| vec![0u8; 100]);
    let mut planes16 = [0, 1, 2].map(|_| vec![0u16; 100]);
    let mut bad = vec![[0u8; 3]; 99];
    let sets: Vec<FoldedSet<4>> = all_displays()
        .into_iter()
        .map(|d| FoldedSet::new(set.wavelengths_nm(), set.weights(), set.samples(), d).unwrap())
        .collect();
    assert_no_alloc("planar paths", || {
        for set in &sets {
            for mapping in MAPPINGS {
                let _ = black_box(set.encode_u8_planar_to_interleaved(
                    mapping,
                    black_box(samples),
                    &mut out,
                ));
                let [r, g, b] = &mut planes8;
                let _ = black_box(set.encode_u8_planar(mapping, black_box(samples), [r, g, b]));
                let _ = black_box(set.encode_u16_planar_to_interleaved(
                    mapping,
                    black_box(samples),
                    &mut out16,
                ));
                let [r, g, b] = &mut planes16;
                let _ = black_box(set.encode_u16_planar(mapping, black_box(samples), [r, g, b]));
            }
        }
        let [r, g, b] = &mut lin;
        let _ = black_box(set.linear_rgb_planar(black_box(samples), [r, g, b]));
        let _ =
            black_box(set.encode_u8_planar_to_interleaved(GamutMapping::Clip, samples, &mut bad));
        let [r, g, b] = &mut planes8;
        let _ = black_box(set.encode_u8_planar(GamutMapping::Clip, samples, [r, g, &mut b[..99]]));
        let _ = black_box(spectral_quadrature::srgb8_from_linear(black_box(0.5)));
    });
}

#[test]
fn upsampling_paths_never_allocate() {
    use spectral_quadrature::tables::upsampling::KQ_C_4_SRGB as UP;
    let rgb: Vec<[f32; 3]> = (0..100)
        .map(|p| [p as f32 / 99.0, f32::NAN, -f32::INFINITY])
        .chain([[0.8, 0.2, 0.1], [2.0, 1e-45, 0.5]])
        .collect();
    let planes = [0, 1, 2].map(|c| rgb.iter().map(|px| px[c]).collect::<Vec<f32>>());
    let mut nodes = vec![[0.0f32; 4]; rgb.len()];
    let mut node_planes = [0, 1, 2, 3].map(|_| vec![0.0f32; rgb.len()]);
    assert_no_alloc("Upsampling", || {
        let _ = black_box(UP.reflectance_batch(black_box(&rgb), &mut nodes));
        let [a, b, c, d] = &mut node_planes;
        let _ = black_box(UP.reflectance_interleaved_to_planar(black_box(&rgb), [a, b, c, d]));
        let [a, b, c, d] = &mut node_planes;
        let rgb_planes = planes.each_ref().map(|p| &p[..]);
        let _ = black_box(UP.reflectance_planar(black_box(rgb_planes), [a, b, c, d]));
        let [a, b, c, d] = &mut node_planes;
        let _ = black_box(UP.reflectance_planar(rgb_planes, [a, b, c, &mut d[..1]]));
    });
}

#[test]
fn colour_temperature_lux_and_calibration_do_not_allocate() {
    use spectral_quadrature::{uv_from_xyz, Calibration, CountCalibration, LuxScale};
    let xyz = black_box([
        [95.047f32, 100.0, 108.883],
        [0.0, 0.0, 0.0],
        [f32::NAN, 1.0, 1.0],
        [f32::MAX, f32::MAX, f32::MAX],
        [1e-45, 1e-45, 1e-45],
        [0.3, 0.6, 0.1],
    ]);
    let counts = black_box([[0u16, 100, 40_000, 65_535], [7, 7, 7, 7]]);
    let floats = counts.map(|c| c.map(f32::from));
    assert_no_alloc("PlanckianLocus::cct, uv_from_xyz, LuxScale", || {
        for x in &xyz {
            black_box(tables::PLANCKIAN_LOCUS.cct(black_box(*x)));
            black_box(uv_from_xyz(black_box(*x)));
            let _ = black_box(LuxScale::from_reading(black_box(x[1]), 500.0).map(|s| s.lux(*x)));
        }
    });
    assert_no_alloc("Calibration, CountCalibration", || {
        let c = CountCalibration::from_dark_white(&counts[1], &counts[0], &counts[0]);
        let _ = black_box(c.map(|c| c.apply(&counts[0])));
        let f = Calibration::from_dark_white(&floats[1], &floats[0], &floats[0]);
        let _ = black_box(f.map(|f| (f.apply(&floats[0]), f.to_counts(1.0))));
        // The errors too (a channel without signal).
        let _ = black_box(Calibration::from_dark_white(
            &floats[0], &floats[0], &floats[0],
        ));
    });
}

#[test]
fn the_integer_path_does_not_allocate() {
    use spectral_quadrature::{tables::integer, IntegerSet};
    let counts: Vec<[u16; 6]> = (0..256u32)
        .map(|p| {
            std::array::from_fn(|i| {
                p.wrapping_mul(2_654_435_761)
                    .wrapping_add(i as u32 * 40_503) as u16
            })
        })
        .collect();
    let mut out = vec![[0u8; 3]; counts.len()];
    let mut short = vec![[0u8; 3]; 3];
    let mut results: [Result<(), Error>; 2] = [Ok(()); 2];
    let mut made = Ok(integer::TABLE2_ROW1_SRGB);
    let mut one = [0u8; 3];
    let mut fixed = [0i64; 3];
    assert_no_alloc("integer path", || {
        for set in [
            integer::TABLE2_ROW1_SRGB,
            integer::TABLE2_ROW1_REC2020,
            integer::TABLE2_ROW1_MEYER_1987,
        ] {
            results[0] = set.encode_u8_batch(black_box(&counts), &mut out);
            one = set.encode_u8(black_box(&counts[7]));
            fixed = set.linear_fixed(black_box(&counts[9]));
        }
        // The error path, and a set put in fixed point at run time.
        results[1] = integer::TABLE2_ROW1_SRGB.encode_u8_batch(&counts, &mut short);
        made = IntegerSet::new(black_box(&folded::TABLE2_ROW1_DISPLAY_P3), 1.0 / 65535.0);
        black_box((&out, &one, &fixed, &results, &made));
    });
    assert_eq!(results[0], Ok(()));
    assert!(matches!(results[1], Err(Error::LengthMismatch { .. })));
    assert_eq!(
        out[5],
        integer::TABLE2_ROW1_MEYER_1987.encode_u8(&counts[5])
    );
    assert_eq!(made, Ok(integer::TABLE2_ROW1_DISPLAY_P3));
}

#[test]
fn upsampling_does_not_allocate() {
    use spectral_quadrature::tables::upsampling as up;
    // Over the cube and saturated colours, where the round-trip correction runs.
    let rgb: Vec<[f32; 3]> = (0..512)
        .map(|i| {
            let t = i as f32 / 512.0;
            if i % 2 == 0 {
                [t, (t * 7.3).fract(), (t * 3.1).fract()]
            } else {
                [0.05 * t, 1.0 - 0.05 * t, (t * 5.7).fract()]
            }
        })
        .collect();
    let mut out4 = vec![[0.0f32; 4]; rgb.len()];
    let mut out6 = vec![[0.0f32; 6]; rgb.len()];
    assert_no_alloc(
        "Upsampling::reflectance / interpolate / reflectance_batch",
        || {
            for p in &rgb {
                black_box(up::KQ_C_4_SRGB.reflectance(black_box(*p)));
                black_box(up::KQ_C_6_SRGB.interpolate(black_box(*p)));
            }
            let _ = black_box(up::KQ_C_4_SRGB.reflectance_batch(black_box(&rgb), &mut out4));
            let _ = black_box(up::KQ_F11_6_SRGB.reflectance_batch(black_box(&rgb), &mut out6));
        },
    );
}

#[test]
fn light_group_sets_do_not_allocate() {
    let c = folded::KQ_C_8_SRGB;
    let warm = FoldedSet::new(
        c.wavelengths_nm(),
        c.weights().map(|row| row.map(|w| 0.7 * w)),
        spectral_quadrature::Samples::Reflectance { light: "A" },
        c.display(),
    )
    .unwrap();
    let groups = black_box([
        [0.3f32; 8],
        [f32::NAN, 1e-45, -1.0, f32::INFINITY, 0.5, 0.5, 0.5, 2.0],
    ]);
    let pixels = black_box(vec![[[0.4f32; 8]; 2]; 20]);
    let planes: Vec<Vec<f32>> = (0..16).map(|k| vec![0.1 * k as f32; 20]).collect();
    let plane_refs: [[&[f32]; 8]; 2] =
        std::array::from_fn(|l| std::array::from_fn(|i| &planes[l * 8 + i][..]));
    let mut f = vec![[0f32; 3]; 20];
    let mut b8 = vec![[0u8; 3]; 20];
    let mut b16 = vec![[0u16; 3]; 20];
    let (mut r, mut g, mut b) = (vec![0f32; 20], vec![0f32; 20], vec![0f32; 20]);
    let (mut r8, mut g8, mut b8p) = (vec![0u8; 20], vec![0u8; 20], vec![0u8; 20]);
    let (mut r16, mut g16, mut b16p) = (vec![0u16; 20], vec![0u16; 20], vec![0u16; 20]);
    for display in all_displays() {
        let c = FoldedSet::new(c.wavelengths_nm(), c.weights(), c.samples(), display).unwrap();
        let w =
            FoldedSet::new(c.wavelengths_nm(), warm.weights(), warm.samples(), display).unwrap();
        assert_no_alloc(
            "LightGroupSet construction, per pixel, batch and planar",
            || {
                let set =
                    spectral_quadrature::LightGroupSet::from_members(black_box([c, w])).unwrap();
                black_box(set.member(1));
                black_box(set.linear_rgb(&groups));
                black_box(set.linear_rgb_batch(&pixels, &mut f)).unwrap();
                black_box(set.linear_rgb_planar(plane_refs, [&mut r, &mut g, &mut b])).unwrap();
                for mapping in MAPPINGS {
                    black_box(set.encode_u8(mapping, &groups));
                    black_box(set.encode_u16(mapping, &groups));
                    black_box(set.encode_u8_batch(mapping, &pixels, &mut b8)).unwrap();
                    black_box(set.encode_u16_batch(mapping, &pixels, &mut b16)).unwrap();
                    black_box(set.encode_u8_planar_to_interleaved(mapping, plane_refs, &mut b8))
                        .unwrap();
                    black_box(set.encode_u8_planar(
                        mapping,
                        plane_refs,
                        [&mut r8, &mut g8, &mut b8p],
                    ))
                    .unwrap();
                    black_box(set.encode_u16_planar_to_interleaved(mapping, plane_refs, &mut b16))
                        .unwrap();
                    black_box(set.encode_u16_planar(
                        mapping,
                        plane_refs,
                        [&mut r16, &mut g16, &mut b16p],
                    ))
                    .unwrap();
                }
                // Errors too: no message is formatted.
                black_box(
                    set.encode_u8_batch(GamutMapping::Clip, &pixels, &mut b8[..3])
                        .unwrap_err(),
                );
            },
        );
    }
}
