//! The runtime on a microcontroller: prints, for a fixed list of inputs (NaN, negative, huge,
//! subnormal among them), the pixels of every baked display with both gamut mappings (8 and 16
//! bits, per pixel and planar), AC1C2 and linear RGB (as f32 bits). Lines starting with `res`
//! are results; on the host the same program prints the same `res` lines, and `.ci/firmware`
//! compares the two.
//!
//! On the microcontroller it also counts the instructions each path takes per pixel (lines
//! starting with `bench`), with SysTick under QEMU's `-icount shift=0`: every instruction
//! advances the virtual clock by 1 ns, and SysTick counts the 25 MHz processor clock of the
//! mps2 boards, so one tick is 40 instructions; the program measures that ratio itself with a
//! loop of known length.
//!
//! Output goes through semihosting (text), or with the `defmt` feature through defmt over
//! semihosting (binary frames, decoded on the host by `defmt-print`).
#![cfg_attr(target_os = "none", no_std)]
#![cfg_attr(target_os = "none", no_main)]

use core::fmt::Write;
use core::hint::black_box;

use spectral_quadrature::tables::{self, displays, folded};
use spectral_quadrature::{srgb8_from_linear, Display, FoldedSet, GamutMapping};

/// Pixels of the fixed input list: the specials below, then a deterministic sweep.
const PIXELS: usize = 48;
const MAPPINGS: [GamutMapping; 2] = [GamutMapping::Clip, GamutMapping::PreserveA];

/// The inputs every build prints results for (N = 4 samples per pixel).
fn inputs() -> [[f32; 4]; PIXELS] {
    let nan = f32::NAN;
    let inf = f32::INFINITY;
    let sub = f32::from_bits(1); // the smallest subnormal, 1.4e-45
    let specials: [[f32; 4]; 16] = [
        [0.0; 4],
        [1.0; 4],
        [0.5, 0.4, 0.3, 0.2],
        [0.02, 0.9, 0.1, 0.0],
        [0.9, 0.05, 0.05, 0.9],
        [nan, 0.5, 0.5, 0.5],
        [0.5, 0.5, 0.5, nan],
        [-1.0, 0.5, 0.5, 0.5],
        [-0.0, -1e-3, -0.5, -2.0],
        [1e30, 1e30, 1e30, 1e30],
        [f32::MAX, 0.0, 0.0, 0.0],
        [inf, 0.5, 0.5, 0.5],
        [-inf, -inf, -inf, -inf],
        [sub, sub, sub, sub],
        [1e-40, 1e-38, 1.2e-38, 3e-39],
        [0.003, 0.0031, 0.004, 0.0005],
    ];
    let mut out = [[0.0f32; 4]; PIXELS];
    for (p, px) in out.iter_mut().enumerate() {
        *px = match specials.get(p) {
            Some(s) => *s,
            // A sweep over 12 octaves, each sample on its own phase: values from 2⁻¹² to 2
            // (some out of gamut), crossing the transfer curves' steep low end.
            None => core::array::from_fn(|i| {
                let k = ((p * 37 + i * 11) % 97) as f32 / 97.0;
                let octave = ((p * 5 + i * 3) % 13) as i32 - 12;
                (1.0 + k) * pow2(octave)
            }),
        };
    }
    out
}

/// 2^e for small e, exactly, without a power function.
fn pow2(e: i32) -> f32 {
    f32::from_bits(((127 + e) as u32) << 23)
}

fn mapping_name(m: GamutMapping) -> &'static str {
    m.name()
}

/// An f32 as its bits in hex, or `nan` for any NaN: IEEE 754 leaves a NaN result's sign and
/// payload open, and they differ (x86's default NaN is negative, Arm's positive).
struct Bits(f32);

impl core::fmt::Display for Bits {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        if self.0.is_nan() {
            f.write_str("nan")
        } else {
            write!(f, "{:08x}", self.0.to_bits())
        }
    }
}

/// Prints every result line.
fn results(out: &mut impl Write) -> core::fmt::Result {
    let px = inputs();
    let set = tables::TABLE2_ROW2;
    writeln!(out, "res scene {}", tables::SCENE)?;
    for (p, s) in px.iter().enumerate() {
        let [a, c1, c2] = set.ac1c2(s).map(Bits);
        writeln!(out, "res ac1c2 {p} {a} {c1} {c2}")?;
    }
    for display in displays::ALL {
        // Every baked display, folded at run time (f32) for the set above; the baked folded
        // sets of the scene are the same fold in f64.
        let f = set.fold(&display, 1.0 / tables::UNIT_SPECTRUM_Y);
        print_display(out, &display, &f, &px)?;
    }
    Ok(())
}

fn print_display(
    out: &mut impl Write,
    display: &Display,
    f: &FoldedSet<4>,
    px: &[[f32; 4]; PIXELS],
) -> core::fmt::Result {
    let name = display.name();
    for (p, s) in px.iter().enumerate() {
        let [r, g, b] = f.linear_rgb(s).map(Bits);
        writeln!(out, "res {name} linear {p} {r} {g} {b}")?;
    }
    let planes: [[f32; PIXELS]; 4] = core::array::from_fn(|i| core::array::from_fn(|p| px[p][i]));
    for mapping in MAPPINGS {
        let m = mapping_name(mapping);
        for (p, s) in px.iter().enumerate() {
            let [r, g, b] = f.encode_u8(mapping, s);
            let [r16, g16, b16] = f.encode_u16(mapping, s);
            writeln!(
                out,
                "res {name} {m} {p} u8 {r} {g} {b} u16 {r16} {g16} {b16}"
            )?;
        }
        let mut planar = [[0u8; 3]; PIXELS];
        let ok = f
            .encode_u8_planar_to_interleaved(
                mapping,
                planes.each_ref().map(|p| &p[..]),
                &mut planar,
            )
            .is_ok();
        writeln!(out, "res {name} {m} planar ok {ok}")?;
        for (p, [r, g, b]) in planar.iter().enumerate() {
            writeln!(out, "res {name} {m} {p} planar {r} {g} {b}")?;
        }
    }
    Ok(())
}

/// Instruction counts per pixel, measured by `ticks` (a clock that counts one tick per
/// `per_tick` instructions) around loops over many pixels. Integer arithmetic only, so that
/// printing them links no float formatting.
#[cfg_attr(not(target_os = "none"), allow(dead_code))]
fn benches(
    out: &mut impl Write,
    ticks: &mut impl FnMut() -> u32,
    per_tick: u32,
) -> core::fmt::Result {
    const P: usize = 512;
    let px = inputs();
    // The sweep's pixels (in gamut and out, no specials): what a renderer mostly sends.
    let sweep = &px[16..];
    let samples: [[f32; 4]; P] = core::array::from_fn(|p| sweep[p % sweep.len()]);
    let set = folded::TABLE2_ROW2_SRGB;
    let mut measure = |name: &str, per: usize, f: &mut dyn FnMut()| -> core::fmt::Result {
        let t0 = ticks();
        f();
        let t1 = ticks();
        let n = (t1.wrapping_sub(t0) & 0x00FF_FFFF) * per_tick;
        // Rounded to the nearest instruction per pixel.
        writeln!(out, "bench {name} {}", (n + per as u32 / 2) / per as u32)
    };
    let mut rgb = [[0u8; 3]; P];
    let mut rgb16 = [[0u16; 3]; P];
    let mut acc = [[0.0f32; 3]; P];
    // The loops below each cost P · (their body) + the loop itself; the empty loop's count is
    // printed so a reader can subtract it (it is a few instructions per pixel).
    measure("empty_loop", P, &mut || {
        for (o, s) in rgb.iter_mut().zip(&samples) {
            *o = black_box([s[0].to_bits() as u8, 0, 0]);
        }
    })?;
    measure("ac1c2", P, &mut || {
        for (o, s) in acc.iter_mut().zip(&samples) {
            *o = black_box(tables::TABLE2_ROW2.ac1c2(black_box(s)));
        }
    })?;
    measure("linear_rgb", P, &mut || {
        for (o, s) in acc.iter_mut().zip(&samples) {
            *o = black_box(set.linear_rgb(black_box(s)));
        }
    })?;
    measure("srgb8_from_linear x3", P, &mut || {
        for (o, s) in rgb.iter_mut().zip(&samples) {
            let s = black_box(s);
            *o = black_box([s[0], s[1], s[2]].map(srgb8_from_linear));
        }
    })?;
    for mapping in MAPPINGS {
        let m = mapping_name(mapping);
        let mut line = heapless_name::<40>("encode_u8 sRGB ", m);
        measure(line.as_str(), P, &mut || {
            for (o, s) in rgb.iter_mut().zip(&samples) {
                *o = black_box(set.encode_u8(mapping, black_box(s)));
            }
        })?;
        line = heapless_name::<40>("encode_u16 sRGB ", m);
        measure(line.as_str(), P, &mut || {
            for (o, s) in rgb16.iter_mut().zip(&samples) {
                *o = black_box(set.encode_u16(mapping, black_box(s)));
            }
        })?;
    }
    for display in displays::ALL {
        let f = tables::TABLE2_ROW2.fold(&display, 1.0 / tables::UNIT_SPECTRUM_Y);
        let line = heapless_name::<40>("encode_u8 Clip ", display.name());
        measure(line.as_str(), P, &mut || {
            for (o, s) in rgb.iter_mut().zip(&samples) {
                *o = black_box(f.encode_u8(GamutMapping::Clip, black_box(s)));
            }
        })?;
    }
    let planes: [[f32; P]; 4] = core::array::from_fn(|i| core::array::from_fn(|p| samples[p][i]));
    measure("planar encode_u8 sRGB Clip", P, &mut || {
        let _ = black_box(set.encode_u8_planar_to_interleaved(
            GamutMapping::Clip,
            black_box(planes.each_ref().map(|p| &p[..])),
            &mut rgb,
        ));
    })?;
    measure("encode_u8_batch sRGB Clip", P, &mut || {
        let _ = black_box(set.encode_u8_batch(GamutMapping::Clip, black_box(&samples), &mut rgb));
    })?;
    #[cfg(feature = "f64-costs")]
    {
        let display = displays::SRGB;
        let mut lin = [[0.0f32; 3]; P];
        measure("encode (f32 out, f64 inside) sRGB Clip", P, &mut || {
            for (o, s) in lin.iter_mut().zip(&samples) {
                let rgb = set.linear_rgb(black_box(s));
                *o = black_box(display.encode(GamutMapping::Clip, rgb));
            }
        })?;
        let mut de = [0.0f64; P];
        measure("delta_e2000 (f64)", P, &mut || {
            for (o, s) in de.iter_mut().zip(&samples) {
                let s = black_box(s);
                let lab1 = [
                    f64::from(s[0]) * 100.0,
                    f64::from(s[1]) * 50.0,
                    f64::from(s[2]) * 50.0,
                ];
                let lab2 = [
                    f64::from(s[3]) * 100.0,
                    f64::from(s[2]) * 40.0,
                    f64::from(s[1]) * 60.0,
                ];
                *o = black_box(spectral_quadrature::delta_e2000(lab1, lab2));
            }
        })?;
        black_box((&lin, &de));
    }
    #[cfg(feature = "upsampling-costs")]
    {
        use spectral_quadrature::tables::upsampling as up;
        // RGB triples spread over the cube (an LCG), and saturated ones (one channel near 0, one
        // near 1) near the cube's faces, where the cells at the edge of what KQ_C_4 and KQ_C_6
        // reach lie and the round-trip correction runs.
        let mut state = 0x2545_f491_u32;
        let mut next = move || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 8) as f32 / (1u32 << 24) as f32
        };
        let cube: [[f32; 3]; P] = core::array::from_fn(|_| [next(), next(), next()]);
        let edge: [[f32; 3]; P] = core::array::from_fn(|i| {
            let mut p = [next(), next(), next()];
            p[i % 3] *= 0.1;
            p[(i + 1) % 3] = 1.0 - 0.1 * p[(i + 1) % 3];
            p
        });
        upsampling_costs(&mut measure, "KQ_C_4", &up::KQ_C_4_SRGB, &cube, &edge)?;
        upsampling_costs(&mut measure, "KQ_C_6", &up::KQ_C_6_SRGB, &cube, &edge)?;
        upsampling_costs(&mut measure, "KQ_C_8", &up::KQ_C_8_SRGB, &cube, &edge)?;
    }
    black_box((&rgb, &rgb16, &acc));
    Ok(())
}

/// The instructions per pixel of one upsampling: `interpolate` and `reflectance` over the
/// cube, and `reflectance` over saturated colours.
#[cfg(feature = "upsampling-costs")]
fn upsampling_costs<const N: usize>(
    measure: &mut dyn FnMut(&str, usize, &mut dyn FnMut()) -> core::fmt::Result,
    name: &str,
    u: &spectral_quadrature::Upsampling<N>,
    cube: &[[f32; 3]],
    edge: &[[f32; 3]],
) -> core::fmt::Result {
    let mut out = [[0.0f32; N]; 512];
    let line = heapless_name::<48>("upsampling interpolate cube ", name);
    measure(line.as_str(), cube.len(), &mut || {
        for (o, p) in out.iter_mut().zip(cube) {
            *o = black_box(u.interpolate(black_box(*p)));
        }
    })?;
    let line = heapless_name::<48>("upsampling reflectance cube ", name);
    measure(line.as_str(), cube.len(), &mut || {
        for (o, p) in out.iter_mut().zip(cube) {
            *o = black_box(u.reflectance(black_box(*p)));
        }
    })?;
    let line = heapless_name::<48>("upsampling reflectance saturated ", name);
    measure(line.as_str(), edge.len(), &mut || {
        for (o, p) in out.iter_mut().zip(edge) {
            *o = black_box(u.reflectance(black_box(*p)));
        }
    })?;
    black_box(&out);
    Ok(())
}

/// `a` followed by `b` in a fixed-size buffer (the firmware has no allocator).
fn heapless_name<const L: usize>(a: &str, b: &str) -> Name<L> {
    let mut n = Name {
        buf: [0; L],
        len: 0,
    };
    let _ = n.write_str(a);
    let _ = n.write_str(b);
    n
}

struct Name<const L: usize> {
    buf: [u8; L],
    len: usize,
}

impl<const L: usize> Name<L> {
    fn as_str(&self) -> &str {
        core::str::from_utf8(&self.buf[..self.len]).unwrap_or("?")
    }
}

impl<const L: usize> Write for Name<L> {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        let end = (self.len + s.len()).min(L);
        let n = end - self.len;
        self.buf[self.len..end].copy_from_slice(&s.as_bytes()[..n]);
        self.len = end;
        Ok(())
    }
}

#[cfg(not(target_os = "none"))]
fn main() {
    struct Stdout;
    impl Write for Stdout {
        fn write_str(&mut self, s: &str) -> core::fmt::Result {
            print!("{s}");
            Ok(())
        }
    }
    results(&mut Stdout).expect("stdout");
}

#[cfg(target_os = "none")]
mod firmware {
    use super::*;
    use cortex_m::peripheral::{syst::SystClkSource, SYST};
    use cortex_m_rt::entry;
    use cortex_m_semihosting::debug::{self, EXIT_FAILURE, EXIT_SUCCESS};

    /// Collects a line and sends it whole (one semihosting call per line).
    struct Lines {
        buf: [u8; 160],
        len: usize,
    }

    impl Lines {
        fn flush(&mut self) {
            let line = core::str::from_utf8(&self.buf[..self.len]).unwrap_or("<bad utf-8>\n");
            #[cfg(not(feature = "defmt"))]
            cortex_m_semihosting::hprint!("{}", line);
            #[cfg(feature = "defmt")]
            defmt::println!("{=str}", line.trim_end());
            self.len = 0;
        }
    }

    impl Write for Lines {
        fn write_str(&mut self, s: &str) -> core::fmt::Result {
            for &b in s.as_bytes() {
                if self.len == self.buf.len() {
                    self.flush();
                }
                self.buf[self.len] = b;
                self.len += 1;
                if b == b'\n' {
                    self.flush();
                }
            }
            Ok(())
        }
    }

    /// Instructions per SysTick tick: a loop of two instructions per round (`subs`, `bne`),
    /// timed. Under `-icount shift=0` on the mps2 boards this is 40.
    fn instructions_per_tick(ticks: &mut impl FnMut() -> u32) -> u32 {
        const ROUNDS: u32 = 100_000;
        let t0 = ticks();
        // SAFETY: a counted loop on one register, no memory access.
        unsafe {
            core::arch::asm!(
                "2:",
                "subs {n}, #1",
                "bne 2b",
                n = inout(reg) ROUNDS => _,
                options(nomem, nostack),
            );
        }
        let t1 = ticks();
        let t = (t1.wrapping_sub(t0) & 0x00FF_FFFF).max(1);
        (2 * ROUNDS + t / 2) / t
    }

    #[entry]
    fn main() -> ! {
        let mut out = Lines {
            buf: [0; 160],
            len: 0,
        };
        #[cfg(feature = "defmt")]
        {
            defmt::info!("set {}", folded::TABLE2_ROW2_SRGB);
        }
        let Some(mut p) = cortex_m::Peripherals::take() else {
            debug::exit(EXIT_FAILURE);
            loop {}
        };
        p.SYST.set_clock_source(SystClkSource::Core);
        p.SYST.set_reload(0x00FF_FFFF);
        p.SYST.clear_current();
        p.SYST.enable_counter();
        // SysTick counts down from 2²⁴ − 1; elapsed ticks = earlier − later (mod 2²⁴). Each
        // measured loop stays well under 2²⁴ ticks.
        let mut ticks = || (0x00FF_FFFF - SYST::get_current()) & 0x00FF_FFFF;
        let ok = results(&mut out).is_ok();
        let per_tick = instructions_per_tick(&mut ticks);
        let _ = writeln!(out, "bench instructions_per_tick {per_tick}");
        let ok = ok && benches(&mut out, &mut ticks, per_tick).is_ok();
        let _ = writeln!(out, "done");
        debug::exit(if ok { EXIT_SUCCESS } else { EXIT_FAILURE });
        loop {}
    }

    #[panic_handler]
    fn panic(_: &core::panic::PanicInfo) -> ! {
        cortex_m_semihosting::hprintln!("panic");
        debug::exit(EXIT_FAILURE);
        loop {}
    }

    #[cfg(feature = "defmt")]
    use defmt_semihosting as _;
}
