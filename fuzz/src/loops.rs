//! The batch and planar loops at every shape, one level of loops forced per target: bytes → a
//! width N, a pixel count, a display and mapping, weights, the placement of every plane and
//! output, samples (the first from the bytes, the rest from a generator the bytes seed) and a
//! length to get wrong.
//!
//! - N ∈ {0, 1, 2, 3, 4, 5, 6, 8, 12, 16, 28, 64}: the baked widths, the AVX2 loops' passes of
//!   four planes with a last pass of one to four, the scalar loop's written-out steps and its
//!   loop, no planes at all, the first width at which `linear_rgb_batch` and `ac1c2_batch` run
//!   four pixels side by side on x86-64, and `MAX_WAVELENGTHS`.
//! - 0 to 4351 pixels: below a group, whole groups and chunks and partial ones, the AVX2
//!   loops' blocks of 1024 pixels and their ends.
//! - Every plane and output in an allocation of its own that ends where it ends (so that the
//!   sanitizer cargo-fuzz builds with reports any access past it), starting 0 to 15 elements
//!   past a 64-byte boundary, each at its own offset: the accelerated loops choose where their
//!   groups start from these offsets.
//!
//! - One input in four instead takes a light-group set (`LightGroupSet<N, L>`: L lights of N
//!   nodes, L · N = 3 to 64, and one beyond the loops' 64 that goes pixel by pixel), its
//!   planes in allocations of their own placed as above.
//!
//! Checked, with the level capped by `__fuzzing::force`: the loop that ran is the forced one;
//! `linear_rgb_planar` and `linear_rgb_batch` equal `linear_rgb` bit for bit (NaN payloads
//! aside) on every pixel; `encode_u8_planar_to_interleaved` and `encode_u8_batch` equal `encode_u8` and the
//! scalar route `display.encode_u8(linear_rgb(s))` on every pixel; `encode_u16_batch` and
//! `ac1c2_batch` equal their per-pixel functions; one plane or output shorter or longer is
//! `Err(LengthMismatch)` with the lengths the docs name, and writes nothing. For light-group
//! sets the same: `linear_rgb_planar` equal to `linear_rgb` bit for bit, the 8-bit planar and
//! batch forms (and `encode_u8_planar`'s three planes) equal to `encode_u8`, and to the display's
//! encoding of `linear_rgb`.

use std::alloc::{self, Layout};
use std::ptr::NonNull;

use spectral_quadrature::__fuzzing::{force, take_ran, Loops};
use spectral_quadrature::tables::displays;
use spectral_quadrature::{
    Display, Error, FoldedSet, GamutMapping, LengthOf, LightGroupSet, WavelengthSet,
};

use super::{same, step_ulps, Bytes, FOLDED_ROW1, FOLDED_ROW2, INTERESTING, MAPPINGS};

/// The most pixels an input asks for: four blocks of the AVX2 loops in passes, and a part.
pub const MAX_PIXELS: usize = 4351;

/// Says once, at the start of a run, which level of loops the target forces and which one this
/// CPU runs under that cap (`.ci/fuzz` prints it with the run's counts).
pub fn announce(level: Loops) {
    let got = force(level);
    if got == level {
        eprintln!("forced loops: {}", level.name());
    } else {
        eprintln!(
            "forced loops: {} NOT AVAILABLE on this CPU; fuzzing {} instead",
            level.name(),
            got.name()
        );
    }
}

/// One input, with the loops capped at `level`.
pub fn run(level: Loops, data: &[u8]) {
    let level = force(level);
    let mut b = Bytes::new(data);
    let pick = b.u8();
    if pick >= 0xC0 {
        match pick % 8 {
            0 => groups::<1, 3>(level, &mut b),
            1 => groups::<4, 2>(level, &mut b),
            2 => groups::<8, 4>(level, &mut b),
            3 => groups::<5, 2>(level, &mut b),
            4 => groups::<3, 1>(level, &mut b),
            5 => groups::<16, 4>(level, &mut b),
            6 => groups::<6, 3>(level, &mut b),
            _ => groups::<17, 4>(level, &mut b),
        }
        return;
    }
    match pick % 12 {
        0 => shape::<0>(level, &mut b),
        1 => shape::<1>(level, &mut b),
        2 => shape::<2>(level, &mut b),
        3 => shape::<3>(level, &mut b),
        4 => shape::<4>(level, &mut b),
        5 => shape::<5>(level, &mut b),
        6 => shape::<6>(level, &mut b),
        7 => shape::<8>(level, &mut b),
        8 => shape::<12>(level, &mut b),
        9 => shape::<16>(level, &mut b),
        10 => shape::<28>(level, &mut b),
        _ => shape::<64>(level, &mut b),
    }
}

/// xorshift64*, seeded by the input: the samples past those the bytes give.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Mostly reflectance-like values in and out of gamut, some negative, tiny, any bit
    /// pattern, or a landmark moved by a few ulps.
    fn sample(&mut self) -> f32 {
        let r = self.next();
        match r % 16 {
            0 => -self.unit(),
            1 => f32::from_bits((r >> 32) as u32),
            2 => step_ulps(
                INTERESTING[(r >> 8) as usize % INTERESTING.len()],
                ((r >> 16) % 16) as i32 - 8,
            ),
            3 => self.unit() * 1e-3,
            _ => 1.2 * self.unit(),
        }
    }

    /// The bytes' next value while they last, then the generator's.
    fn sample_after(&mut self, b: &mut Bytes) -> f32 {
        if b.is_empty() {
            self.sample()
        } else {
            b.value()
        }
    }
}

/// `values` in an allocation of their own that ends where they end and starts `lead` elements
/// before them, at a 64-byte boundary: the values start `lead · size_of::<T>()` bytes past
/// it. The lead elements hold `values[0]`'s type's `fill`, and are never part of a slice.
pub struct Placed<T: Copy> {
    ptr: NonNull<T>,
    lead: usize,
    len: usize,
    layout: Option<Layout>,
}

impl<T: Copy> Placed<T> {
    pub fn new(values: &[T], lead: usize, fill: T) -> Self {
        let total = lead + values.len();
        let size = total * std::mem::size_of::<T>();
        if size == 0 {
            return Placed {
                ptr: NonNull::dangling(),
                lead: 0,
                len: values.len(),
                layout: None,
            };
        }
        let layout = Layout::from_size_align(size, 64.max(std::mem::align_of::<T>()))
            .expect("a layout of at most a few MiB");
        // SAFETY: `layout` has a non-zero size.
        let raw = unsafe { alloc::alloc(layout) }.cast::<T>();
        let Some(ptr) = NonNull::new(raw) else {
            alloc::handle_alloc_error(layout)
        };
        for i in 0..total {
            let v = if i < lead { fill } else { values[i - lead] };
            // SAFETY: i < total, inside the allocation of `total` elements of T, aligned.
            unsafe { ptr.as_ptr().add(i).write(v) };
        }
        Placed {
            ptr,
            lead,
            len: values.len(),
            layout: Some(layout),
        }
    }

    pub fn get(&self) -> &[T] {
        // SAFETY: elements lead..lead + len were written in `new` and live as long as `self`;
        // without an allocation, len elements of a zero-sized type or none.
        unsafe { std::slice::from_raw_parts(self.ptr.as_ptr().add(self.lead), self.len) }
    }

    pub fn get_mut(&mut self) -> &mut [T] {
        // SAFETY: as in `get`, and `&mut self` makes the borrow unique.
        unsafe { std::slice::from_raw_parts_mut(self.ptr.as_ptr().add(self.lead), self.len) }
    }
}

impl<T: Copy> Drop for Placed<T> {
    fn drop(&mut self) {
        if let Some(layout) = self.layout {
            // SAFETY: allocated in `new` with this layout.
            unsafe { alloc::dealloc(self.ptr.as_ptr().cast(), layout) };
        }
    }
}

/// Planes, pixels and weights of one input.
struct Case<const N: usize> {
    set: FoldedSet<N>,
    mapping: GamutMapping,
    pixels: Vec<[f32; N]>,
    /// Each plane's lead (elements before it in its allocation).
    leads: [usize; N],
    /// The outputs' leads: red, green and blue planes, the 8-bit pixels.
    out_leads: [usize; 4],
    /// Which length to get wrong (a plane, or an output), and how.
    wrong: u8,
}

fn case<const N: usize>(b: &mut Bytes) -> Case<N> {
    let size = b.u8();
    // Mostly short runs (up to 255 pixels, or up to 31), now and then up to MAX_PIXELS.
    let pixels = match size >> 5 {
        0..=3 => usize::from(size),
        4 | 5 => usize::from(size & 31),
        _ => (usize::from(size & 31) << 8 | usize::from(b.u8())) % (MAX_PIXELS + 1),
    };
    let look = b.u8();
    // The fast paths (sRGB or Display P3 with `Clip`) three times in four.
    let (display, mapping): (&Display, GamutMapping) = if look < 0xC0 {
        (&displays::ALL[usize::from(look & 1)], GamutMapping::Clip)
    } else {
        (
            &displays::ALL[usize::from(look) % displays::ALL.len()],
            MAPPINGS[usize::from(look >> 2) % 2],
        )
    };
    let mut rng = Rng(u64::from_le_bytes(std::array::from_fn(|_| b.u8())) | 1);
    let weights: [[f32; N]; 3] = match b.u8() % 4 {
        // Weights from the input: any value, NaN and infinities included.
        0 => std::array::from_fn(|_| std::array::from_fn(|_| b.value())),
        // A baked folded set where one has this width.
        1 if N == 4 => {
            std::array::from_fn(|c| std::array::from_fn(|i| FOLDED_ROW2[0].weights()[c][i]))
        }
        1 if N == 6 => {
            std::array::from_fn(|c| std::array::from_fn(|i| FOLDED_ROW1[0].weights()[c][i]))
        }
        // Random weights of either sign, scaled to the folded sets' range.
        _ => std::array::from_fn(|_| std::array::from_fn(|_| (2.0 * rng.unit() - 0.6) / N as f32)),
    };
    let wavelengths_nm = std::array::from_fn(|i| 400.0 + i as f32);
    let samples = FOLDED_ROW2[0].samples();
    let set = match FoldedSet::new(wavelengths_nm, weights, samples, *display) {
        Ok(set) => set,
        // Non-finite weights: the checked constructor refuses them, and the public way to them
        // is `fold` with a scale that is not finite (the first such value the bytes gave).
        Err(_) => {
            let scale = weights
                .iter()
                .flatten()
                .copied()
                .find(|w| !w.is_finite())
                .unwrap_or(f32::NAN);
            let finite = weights.map(|row| row.map(|w| if w.is_finite() { w } else { 1.0 }));
            WavelengthSet::new(wavelengths_nm, finite, samples)
                .expect("finite weights at ascending wavelengths")
                .fold(display, scale)
        }
    };
    let leads = std::array::from_fn(|_| usize::from(b.u8() % 16));
    let out_leads = std::array::from_fn(|_| usize::from(b.u8() % 16));
    let wrong = b.u8();
    // The first samples from the bytes, the rest from the generator.
    let pixels = (0..pixels)
        .map(|_| std::array::from_fn(|_| rng.sample_after(b)))
        .collect();
    Case {
        set,
        mapping,
        pixels,
        leads,
        out_leads,
        wrong,
    }
}

fn shape<const N: usize>(level: Loops, b: &mut Bytes) {
    let c = case::<N>(b);
    let n = c.pixels.len();
    let set = &c.set;
    let planes: [Placed<f32>; N] = std::array::from_fn(|i| {
        let plane: Vec<f32> = c.pixels.iter().map(|s| s[i]).collect();
        Placed::new(&plane, c.leads[i], f32::NAN)
    });
    let samples: [&[f32]; N] = std::array::from_fn(|i| planes[i].get());
    let fast = set.display().transfer() == spectral_quadrature::TransferFunction::Srgb
        && c.mapping == GamutMapping::Clip;

    // Linear planar: every loop writes linear output, whatever the display.
    let mut lin: [Placed<f32>; 3] =
        std::array::from_fn(|k| Placed::new(&vec![-7.5; n], c.out_leads[k], 0.0));
    {
        let [r, g, bl] = &mut lin;
        let out = [r.get_mut(), g.get_mut(), bl.get_mut()];
        assert_eq!(
            set.linear_rgb_planar(samples, out),
            Ok(()),
            "linear_rgb_planar N={N}"
        );
    }
    let ran = take_ran().expect("linear_rgb_planar records its loop");
    // Without vector units the linear loop is the portable one too.
    assert_eq!(
        ran.loops,
        level.max(Loops::Portable),
        "linear_rgb_planar N={N}: {ran:?}"
    );
    let per_pixel: Vec<[f32; 3]> = c.pixels.iter().map(|s| set.linear_rgb(s)).collect();
    for (p, one) in per_pixel.iter().enumerate() {
        let got = [lin[0].get()[p], lin[1].get()[p], lin[2].get()[p]];
        assert!(
            (0..3).all(|k| same(got[k], one[k])),
            "linear_rgb_planar {level:?} N={N} pixel {p} of {n}: {got:?} != linear_rgb {one:?}; \
             samples {:?}",
            c.pixels[p]
        );
    }

    // 8-bit planar.
    let mut out8 = Placed::new(&vec![[0xA5u8; 3]; n], c.out_leads[3], [0x5A; 3]);
    assert_eq!(
        set.encode_u8_planar_to_interleaved(c.mapping, samples, out8.get_mut()),
        Ok(()),
        "encode_u8_planar_to_interleaved N={N}"
    );
    if fast {
        let ran = take_ran().expect("encode_u8_planar_to_interleaved records its loop");
        assert_eq!(
            ran.loops, level,
            "encode_u8_planar_to_interleaved N={N}: {ran:?}"
        );
    }
    let want8: Vec<[u8; 3]> = c
        .pixels
        .iter()
        .map(|s| set.encode_u8(c.mapping, s))
        .collect();
    for (p, (s, one)) in c.pixels.iter().zip(&want8).enumerate() {
        let scalar = set.display().encode_u8(c.mapping, per_pixel[p]);
        assert_eq!(
            *one,
            scalar,
            "encode_u8 {} {:?} N={N} pixel {p}: differs from the display's encode_u8 of \
             linear_rgb; samples {s:?}",
            set.display().name(),
            c.mapping
        );
        assert_eq!(
            out8.get()[p],
            *one,
            "encode_u8_planar_to_interleaved {level:?} {} {:?} N={N} pixel {p} of {n}; samples {s:?}",
            set.display().name(),
            c.mapping
        );
    }

    // Interleaved.
    let aos = Placed::new(
        &c.pixels,
        c.leads.first().copied().unwrap_or(0),
        [f32::NAN; N],
    );
    let mut batch8 = Placed::new(&vec![[0xA5u8; 3]; n], c.out_leads[0], [0x5A; 3]);
    assert_eq!(
        set.encode_u8_batch(c.mapping, aos.get(), batch8.get_mut()),
        Ok(())
    );
    if fast {
        let ran = take_ran().expect("encode_u8_batch records its loop");
        // The AVX-512 interleaved loop takes some widths; the AVX2 loop the others.
        let ok = ran.loops == level || (level == Loops::Avx512 && ran.loops == Loops::Avx2);
        assert!(ok, "encode_u8_batch {level:?} N={N}: {ran:?}");
    }
    assert!(
        batch8.get() == &want8[..],
        "encode_u8_batch {level:?} {} {:?} N={N}: pixel {:?} of {n} differs",
        set.display().name(),
        c.mapping,
        batch8.get().iter().zip(&want8).position(|(a, b)| a != b)
    );
    let mut rows = vec![[-7.5f32; 3]; n];
    assert_eq!(set.linear_rgb_batch(aos.get(), &mut rows), Ok(()));
    for (p, (o, one)) in rows.iter().zip(&per_pixel).enumerate() {
        assert!(
            (0..3).all(|k| same(o[k], one[k])),
            "linear_rgb_batch N={N} pixel {p}: {o:?} != {one:?}"
        );
    }
    let mut rows16 = vec![[7u16; 3]; n];
    assert_eq!(
        set.encode_u16_batch(c.mapping, aos.get(), &mut rows16),
        Ok(())
    );
    for (p, (o, s)) in rows16.iter().zip(&c.pixels).enumerate() {
        assert_eq!(
            *o,
            set.encode_u16(c.mapping, s),
            "encode_u16_batch N={N} pixel {p}"
        );
    }
    // The same weights as an AC1C2 set, where they are finite (the only sets there are).
    if let Ok(unfolded) = WavelengthSet::new(set.wavelengths_nm(), set.weights(), set.samples()) {
        let mut ac = vec![[-7.5f32; 3]; n];
        assert_eq!(unfolded.ac1c2_batch(aos.get(), &mut ac), Ok(()));
        for (p, (o, s)) in ac.iter().zip(&c.pixels).enumerate() {
            let one = unfolded.ac1c2(s);
            assert!(
                (0..3).all(|k| same(o[k], one[k])),
                "ac1c2_batch N={N} pixel {p}"
            );
        }
    }

    mismatches(&c, &planes);
}

/// One plane or output (chosen by `wrong`) shorter or longer by 1 to 8: an error naming the
/// lengths, and nothing written. The pixel count is plane 0's length, or, without planes, the
/// first output's.
fn mismatches<const N: usize>(c: &Case<N>, planes: &[Placed<f32>; N]) {
    let n = c.pixels.len();
    let set = &c.set;
    let by = usize::from(c.wrong >> 5) % 4 + 1;
    let longer = c.wrong & 16 != 0;
    let other = if longer || n < by { n + by } else { n - by };
    let which = usize::from(c.wrong & 15) % (N + 3);
    // Planes `which` (< N) longer or shorter, or output `which − N` (red, green, blue; the
    // 8-bit output for the last).
    let len_of = |i: usize| if i == which { other } else { n };
    let values: [Vec<f32>; N] = std::array::from_fn(|i| {
        planes[i]
            .get()
            .iter()
            .copied()
            .chain(std::iter::repeat(0.5))
            .take(len_of(i))
            .collect()
    });
    let moved: [Placed<f32>; N] =
        std::array::from_fn(|i| Placed::new(&values[i], c.leads[i], f32::NAN));
    let samples: [&[f32]; N] = std::array::from_fn(|i| moved[i].get());
    let out_len = |k: usize| {
        if which >= N && which - N == k {
            other
        } else {
            n
        }
    };
    // What the docs say: `expected` is plane 0's length (the first output's without planes),
    // `got` the first length that differs from it, planes first (`InputPlane`), then outputs in
    // order (`output`: `OutputPlane` for planes, `Output` for interleaved pixels).
    let expect = |output: LengthOf, outputs: &[usize]| {
        let lengths: Vec<usize> = (0..N).map(len_of).chain(outputs.iter().copied()).collect();
        let expected = lengths[0];
        lengths
            .iter()
            .enumerate()
            .find(|&(_, &l)| l != expected)
            .map(|(i, &got)| {
                let what = if i < N { LengthOf::InputPlane } else { output };
                Err(Error::LengthMismatch {
                    what,
                    expected,
                    got,
                })
            })
            .unwrap_or(Ok(()))
    };

    let mut lin: [Placed<f32>; 3] =
        std::array::from_fn(|k| Placed::new(&vec![-7.5; out_len(k)], c.out_leads[k], 0.0));
    let want = expect(LengthOf::OutputPlane, &[out_len(0), out_len(1), out_len(2)]);
    {
        let [r, g, b] = &mut lin;
        let got = set.linear_rgb_planar(samples, [r.get_mut(), g.get_mut(), b.get_mut()]);
        assert_eq!(
            got, want,
            "linear_rgb_planar N={N}, {n} pixels, which {which}, other {other}"
        );
    }
    if want.is_err() {
        assert!(lin.iter().all(|o| o.get().iter().all(|v| *v == -7.5)));
    }
    // The 8-bit output's length is wrong where `which` names the last output; the linear
    // outputs' lengths play no part.
    let len8 = if which == N + 2 { other } else { n };
    let mut out8 = Placed::new(&vec![[9u8; 3]; len8], c.out_leads[3], [0x5A; 3]);
    let want = expect(LengthOf::Output, &[len8]);
    let got = set.encode_u8_planar_to_interleaved(c.mapping, samples, out8.get_mut());
    assert_eq!(
        got, want,
        "encode_u8_planar_to_interleaved N={N}, {n} pixels, which {which}"
    );
    if want.is_err() {
        assert!(out8.get().iter().all(|o| *o == [9; 3]));
    }
    // Interleaved: the output shorter or longer.
    let mut bad = vec![[9u8; 3]; other];
    assert_eq!(
        set.encode_u8_batch(c.mapping, &c.pixels, &mut bad),
        Err(Error::LengthMismatch {
            what: LengthOf::Output,
            expected: n,
            got: other
        })
    );
    assert!(bad.iter().all(|o| *o == [9; 3]));
    let mut bad = vec![[-7.5f32; 3]; other];
    assert_eq!(
        set.linear_rgb_batch(&c.pixels, &mut bad),
        Err(Error::LengthMismatch {
            what: LengthOf::Output,
            expected: n,
            got: other
        })
    );
    assert!(bad.iter().flatten().all(|v| *v == -7.5));
}

/// One input through a light-group set of L lights at N nodes: each light's weights and the
/// display as `case` draws a folded set's (the lights' own weights, the display and mapping the
/// first light's), the planes placed as there.
fn groups<const N: usize, const L: usize>(level: Loops, b: &mut Bytes) {
    let first = case::<N>(b);
    // The first light's weights are the case's, the others drawn as it draws them; a
    // light-group set's weights are finite (its constructor refuses others).
    let finite = |w: [[f32; N]; 3]| w.map(|row| row.map(|v| if v.is_finite() { v } else { 0.5 }));
    let mut weights = [finite(first.set.weights()); L];
    for w in weights.iter_mut().skip(1) {
        *w = finite(case::<N>(b).set.weights());
    }
    let set = LightGroupSet::new(
        first.set.wavelengths_nm(),
        weights,
        ["fuzz"; L],
        first.set.display(),
    )
    .expect("finite weights at ascending wavelengths");
    let mapping = first.mapping;
    let n = first.pixels.len();
    let mut rng = Rng(u64::from(b.u8()) << 8 | u64::from(b.u8()) | 1);
    let px: Vec<[[f32; N]; L]> = first
        .pixels
        .iter()
        .map(|s| {
            std::array::from_fn(|l| {
                if l == 0 {
                    *s
                } else {
                    std::array::from_fn(|_| rng.sample_after(b))
                }
            })
        })
        .collect();
    let planes: [[Placed<f32>; N]; L] = std::array::from_fn(|l| {
        std::array::from_fn(|i| {
            let plane: Vec<f32> = px.iter().map(|g| g[l][i]).collect();
            Placed::new(&plane, (first.leads[i] + 3 * l) % 16, f32::NAN)
        })
    });
    let refs: [[&[f32]; N]; L] =
        std::array::from_fn(|l| std::array::from_fn(|i| planes[l][i].get()));
    // The vector loops take L · N up to MAX_WAVELENGTHS; beyond, pixel by pixel.
    let loops = N * L <= spectral_quadrature::MAX_WAVELENGTHS;
    let fast = set.display().transfer() == spectral_quadrature::TransferFunction::Srgb
        && mapping == GamutMapping::Clip;

    let mut lin: [Placed<f32>; 3] =
        std::array::from_fn(|k| Placed::new(&vec![-7.5; n], first.out_leads[k], 0.0));
    // Forget what an earlier input's last call ran (its three-plane `encode_u8_planar` leaves
    // a record nobody takes), so that a set beyond the loops is seen to run none.
    let _ = take_ran();
    {
        let [r, g, bl] = &mut lin;
        assert_eq!(
            set.linear_rgb_planar(refs, [r.get_mut(), g.get_mut(), bl.get_mut()]),
            Ok(())
        );
    }
    let ran = take_ran();
    if loops {
        let ran = ran.expect("linear_rgb_planar of light groups records its loop");
        assert_eq!(
            ran.loops,
            level.max(Loops::Portable),
            "groups linear N={N} L={L}"
        );
    } else {
        assert_eq!(ran, None, "groups linear N={N} L={L}: pixel by pixel");
    }
    for (p, g) in px.iter().enumerate() {
        let one = set.linear_rgb(g);
        let got = [lin[0].get()[p], lin[1].get()[p], lin[2].get()[p]];
        assert!(
            (0..3).all(|k| same(got[k], one[k])),
            "groups linear_rgb_planar {level:?} N={N} L={L} pixel {p} of {n}: {got:?} != {one:?}; {g:?}"
        );
    }

    let want8: Vec<[u8; 3]> = px.iter().map(|g| set.encode_u8(mapping, g)).collect();
    for (p, g) in px.iter().enumerate() {
        assert_eq!(
            want8[p],
            set.display().encode_u8(mapping, set.linear_rgb(g)),
            "groups encode_u8 N={N} L={L} pixel {p}: {g:?}"
        );
    }
    let mut out8 = Placed::new(&vec![[0xA5u8; 3]; n], first.out_leads[3], [0x5A; 3]);
    assert_eq!(
        set.encode_u8_planar_to_interleaved(mapping, refs, out8.get_mut()),
        Ok(())
    );
    if fast && loops {
        let ran = take_ran().expect("the light groups' planar 8-bit path records its loop");
        assert_eq!(ran.loops, level, "groups planar N={N} L={L}: {ran:?}");
    }
    assert!(
        out8.get() == &want8[..],
        "groups encode_u8_planar_to_interleaved {level:?} N={N} L={L}: pixel {:?} of {n} differs",
        out8.get().iter().zip(&want8).position(|(a, b)| a != b)
    );
    let mut batch8 = Placed::new(&vec![[0xA5u8; 3]; n], first.out_leads[0], [0x5A; 3]);
    assert_eq!(set.encode_u8_batch(mapping, &px, batch8.get_mut()), Ok(()));
    if fast && loops {
        let ran = take_ran().expect("the light groups' batch 8-bit path records its loop");
        // The interleaved AVX-512 loop takes a folded set at N = 4; light groups the AVX2 one.
        let ok = ran.loops == level || (level == Loops::Avx512 && ran.loops == Loops::Avx2);
        assert!(ok, "groups batch {level:?} N={N} L={L}: {ran:?}");
    }
    assert!(
        batch8.get() == &want8[..],
        "groups encode_u8_batch {level:?} N={N} L={L}: pixel {:?} of {n} differs",
        batch8.get().iter().zip(&want8).position(|(a, b)| a != b)
    );
    let (mut r, mut g, mut bl) = (vec![0u8; n], vec![0u8; n], vec![0u8; n]);
    assert_eq!(
        set.encode_u8_planar(mapping, refs, [&mut r, &mut g, &mut bl]),
        Ok(())
    );
    for p in 0..n {
        assert_eq!(
            [r[p], g[p], bl[p]],
            want8[p],
            "groups encode_u8_planar pixel {p}"
        );
    }
    // One plane shorter: an error naming it, and nothing written.
    if n > 0 && N > 0 {
        let short: Vec<f32> = refs[L - 1][N - 1][..n - 1].to_vec();
        let mut bad = refs;
        bad[L - 1][N - 1] = &short;
        let mut out = vec![[9u8; 3]; n];
        let got = set.encode_u8_planar_to_interleaved(mapping, bad, &mut out);
        let want = if L * N == 1 {
            Err(Error::LengthMismatch {
                what: LengthOf::Output,
                expected: n - 1,
                got: n,
            })
        } else {
            Err(Error::LengthMismatch {
                what: LengthOf::InputPlane,
                expected: n,
                got: n - 1,
            })
        };
        assert_eq!(got, want, "groups N={N} L={L}");
        assert!(out.iter().all(|o| *o == [9; 3]));
    }
}
