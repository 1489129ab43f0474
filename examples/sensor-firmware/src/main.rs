//! A colour sensor's firmware: the example 8-channel sensor (the AS7341 model of
//! `data/sensor_as7341_gaussian.csv`) reads each of the 24 ColorChecker patches under
//! illuminant C as u16 counts (simulated at build time, `build.rs`), and the firmware turns
//! them into XYZ (the f32 set, [`tables::AS7341`]) and 8-bit sRGB (the integer path,
//! [`integer::AS7341_SRGB`]: integer arithmetic only). Lines starting with `res` are results;
//! on the host the same program prints the same `res` lines, and `.ci/sensor-firmware` compares
//! them with those of the Cortex-M0 (QEMU's `microbit`: 16 kB of RAM) and the Cortex-M4F
//! (`mps2-an386`) builds.
//!
//! On the microcontroller it also counts the instructions each step takes per pixel (lines
//! starting with `bench`), with SysTick under QEMU's `-icount shift=0`: every instruction
//! advances the virtual clock by 1 ns, SysTick counts the processor clock, and the program
//! measures how many instructions a tick is with a loop of known length. Then it prints how much
//! of the stack it used (`ram`).
#![cfg_attr(target_os = "none", no_std)]
#![cfg_attr(target_os = "none", no_main)]

use core::fmt::Write;
use core::hint::black_box;

use spectral_quadrature::tables::{self, folded, integer};
use spectral_quadrature::GamutMapping;

// The simulated device's readings are for the calibration steps.
#[allow(dead_code)]
mod simulated {
    include!(concat!(env!("OUT_DIR"), "/simulated.rs"));
}
use simulated::{CHANNELS, GOLDEN_COUNTS, PATCHES, PATCH_NAMES, SAMPLE_UNIT};

/// An f32 as its bits in hex, or `nan` for any NaN (its sign is not specified by IEEE 754).
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
    let sensor = integer::AS7341_SRGB;
    writeln!(
        out,
        "res scene {} sensor AS7341 frac_bits {} sample_unit {}",
        tables::SCENE.rsplit('/').next().unwrap_or(""),
        sensor.frac_bits(),
        Bits(sensor.sample_unit())
    )?;
    // The build's scale and the firmware's agree.
    if sensor.sample_unit() != SAMPLE_UNIT {
        writeln!(out, "res sample unit differs from the simulation's")?;
    }
    for (p, counts) in GOLDEN_COUNTS.iter().enumerate() {
        write!(out, "res patch {p:2} counts")?;
        for c in counts {
            write!(out, " {c}")?;
        }
        // XYZ from the readings (f32), 8-bit sRGB from the counts (integers only) with the
        // exact fixed-point sums behind it, and the f32 path's 8-bit sRGB beside it.
        let samples = sensor.samples_f32(counts);
        let [x, y, z] = tables::AS7341.xyz(&samples).map(Bits);
        let [r, g, b] = sensor.encode_u8(counts);
        let [fr, fg, fb] = sensor.linear_fixed(counts);
        let [rf, gf, bf] = folded::AS7341_SRGB.encode_u8(GamutMapping::Clip, &samples);
        writeln!(
            out,
            " xyz {x} {y} {z} srgb8 {r} {g} {b} fixed {fr} {fg} {fb} f32 {rf} {gf} {bf} {}",
            PATCH_NAMES[p]
        )?;
    }
    // Many more counts through the integer path, summed up in a checksum: the same on every
    // target, or the lines differ.
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        // Every magnitude: a count shifted right by 0 to 15 bits.
        ((state >> 48) as u16) >> (state % 16)
    };
    let (mut sum4, mut sum8) = (Fnv::new(), Fnv::new());
    for _ in 0..PIXELS {
        let x4: [u16; 4] = core::array::from_fn(|_| next());
        sum4.add(&integer::TABLE2_ROW2_SRGB.encode_u8(&x4));
        let x8: [u16; CHANNELS] = core::array::from_fn(|_| next());
        sum8.add(&sensor.encode_u8(&x8));
    }
    writeln!(
        out,
        "res checksum {PIXELS} pixels N=4 {:016x} N=8 {:016x}",
        sum4.0, sum8.0
    )?;
    Ok(())
}

/// Pseudo-random pixels the checksum covers.
const PIXELS: usize = 50_000;

/// FNV-1a, 64 bits: a checksum of bytes.
struct Fnv(u64);

impl Fnv {
    fn new() -> Fnv {
        Fnv(0xcbf2_9ce4_8422_2325)
    }

    fn add(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
}

/// Pixels per measurement.
const P: usize = 240;

/// N = 4 counts for the instruction counts: a fixed pseudo-random sweep whose pixels span every
/// magnitude (each count shifted right by 0 to 7 bits), dark pixels included.
static SWEEP4: [[u16; 4]; P] = {
    let mut out = [[0u16; 4]; P];
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut p = 0;
    while p < P {
        let mut i = 0;
        while i < 4 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            out[p][i] = ((state >> 48) as u16) >> (state % 8);
            i += 1;
        }
        p += 1;
    }
    out
};

/// The patches' counts, ten times over (N = 8).
static PATCH_COUNTS: [[u16; CHANNELS]; P] = {
    let mut out = [[0u16; CHANNELS]; P];
    let mut p = 0;
    while p < P {
        out[p] = GOLDEN_COUNTS[p % PATCHES];
        p += 1;
    }
    out
};

/// The same inputs as f32 samples, for the f32 path.
const fn samples_f32<const N: usize>(counts: &[[u16; N]; P], unit: f32) -> [[f32; N]; P] {
    let mut out = [[0.0f32; N]; P];
    let mut p = 0;
    while p < P {
        let mut i = 0;
        while i < N {
            out[p][i] = counts[p][i] as f32 * unit;
            i += 1;
        }
        p += 1;
    }
    out
}
static SWEEP4_F32: [[f32; 4]; P] = samples_f32(&SWEEP4, integer::TABLE2_ROW2_SRGB.sample_unit());
static PATCH_F32: [[f32; CHANNELS]; P] = samples_f32(&PATCH_COUNTS, SAMPLE_UNIT);

/// Instruction counts per pixel: `ticks` counts SysTick ticks, and `ratio` (instructions,
/// ticks) is how many instructions a number of ticks is. Integer arithmetic only, so that
/// printing them links no float formatting.
#[cfg_attr(not(target_os = "none"), allow(dead_code))]
fn benches(
    out: &mut impl Write,
    ticks: &mut impl FnMut() -> u32,
    ratio: (u32, u32),
) -> core::fmt::Result {
    let mut rgb = [[0u8; 3]; P];
    let mut xyz = [0.0f32; 3];
    let mut measure = |name: &str, f: &mut dyn FnMut()| -> core::fmt::Result {
        let t0 = ticks();
        f();
        let t1 = ticks();
        let t = u64::from(t1.wrapping_sub(t0) & 0x00FF_FFFF);
        // Instructions, then per pixel, rounded to the nearest.
        let n = t * u64::from(ratio.0);
        let d = u64::from(ratio.1) * P as u64;
        writeln!(out, "bench {name} {}", (n + d / 2) / d)
    };
    let int4 = integer::TABLE2_ROW2_SRGB;
    let f4 = folded::TABLE2_ROW2_SRGB;
    let int8 = integer::AS7341_SRGB;
    let f8 = folded::AS7341_SRGB;
    // The loops below each cost P · (their body) + the loop itself; the empty loop's count is
    // printed so a reader can subtract it.
    measure("empty_loop", &mut || {
        for (o, s) in rgb.iter_mut().zip(&SWEEP4) {
            *o = black_box([s[0] as u8, 0, 0]);
        }
    })?;
    measure("N=4 integer encode_u8", &mut || {
        for (o, s) in rgb.iter_mut().zip(&SWEEP4) {
            *o = black_box(int4.encode_u8(black_box(s)));
        }
    })?;
    measure("N=4 integer encode_u8_batch", &mut || {
        let _ = black_box(int4.encode_u8_batch(black_box(&SWEEP4), &mut rgb));
    })?;
    measure("N=4 f32 encode_u8", &mut || {
        for (o, s) in rgb.iter_mut().zip(&SWEEP4_F32) {
            *o = black_box(f4.encode_u8(GamutMapping::Clip, black_box(s)));
        }
    })?;
    measure("N=8 integer encode_u8", &mut || {
        for (o, s) in rgb.iter_mut().zip(&PATCH_COUNTS) {
            *o = black_box(int8.encode_u8(black_box(s)));
        }
    })?;
    measure("N=8 integer encode_u8_batch", &mut || {
        let _ = black_box(int8.encode_u8_batch(black_box(&PATCH_COUNTS), &mut rgb));
    })?;
    measure("N=8 f32 encode_u8", &mut || {
        for (o, s) in rgb.iter_mut().zip(&PATCH_F32) {
            *o = black_box(f8.encode_u8(GamutMapping::Clip, black_box(s)));
        }
    })?;
    measure("N=8 f32 xyz", &mut || {
        for s in &PATCH_F32 {
            xyz = black_box(tables::AS7341.xyz(black_box(s)));
        }
    })?;
    black_box((&rgb, &xyz));
    Ok(())
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
            cortex_m_semihosting::hprint!("{}", line);
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

    /// (instructions, ticks) of a loop of two instructions per round (`subs`, `bne`).
    fn instructions_per_ticks(ticks: &mut impl FnMut() -> u32) -> (u32, u32) {
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
        (2 * ROUNDS, (t1.wrapping_sub(t0) & 0x00FF_FFFF).max(1))
    }

    /// The stack's lowest address and the word the stack is painted with before `main` runs.
    const PAINT: u32 = 0x5a5a_5a5a;

    extern "C" {
        static mut __sheap: u32;
        static _stack_start: u32;
    }

    /// Paints the free RAM between the end of the statics and the stack pointer, so that
    /// `stack_used` can see how deep the stack went.
    fn paint_stack() {
        let here = cortex_m::register::msp::read();
        // SAFETY: `__sheap` is the first free word after .bss and .data (cortex-m-rt's link.x);
        // below the current stack pointer (less a margin for this function's own frame) no live
        // data is stored, so writing there changes nothing the program uses.
        unsafe {
            let mut p = core::ptr::addr_of_mut!(__sheap);
            while (p as u32) < here - 64 {
                p.write_volatile(PAINT);
                p = p.add(1);
            }
        }
    }

    /// Bytes of stack used so far: from the top of RAM down to the lowest word changed since
    /// `paint_stack`.
    fn stack_used() -> u32 {
        // SAFETY: reads of the RAM `paint_stack` painted, word by word, from its start.
        unsafe {
            let mut p = core::ptr::addr_of!(__sheap);
            while p.read_volatile() == PAINT {
                p = p.add(1);
            }
            core::ptr::addr_of!(_stack_start) as u32 - p as u32
        }
    }

    #[entry]
    fn main() -> ! {
        paint_stack();
        let mut out = Lines {
            buf: [0; 160],
            len: 0,
        };
        let Some(mut p) = cortex_m::Peripherals::take() else {
            debug::exit(EXIT_FAILURE);
            halt();
        };
        p.SYST.set_clock_source(SystClkSource::Core);
        p.SYST.set_reload(0x00FF_FFFF);
        p.SYST.clear_current();
        p.SYST.enable_counter();
        // SysTick counts down from 2²⁴ − 1; elapsed ticks = earlier − later (mod 2²⁴). Each
        // measured loop stays well under 2²⁴ ticks.
        let mut ticks = || (0x00FF_FFFF - SYST::get_current()) & 0x00FF_FFFF;
        let ok = results(&mut out).is_ok();
        let ratio = instructions_per_ticks(&mut ticks);
        let _ = writeln!(out, "bench instructions_per_ticks {} {}", ratio.0, ratio.1);
        let ok = ok && benches(&mut out, &mut ticks, ratio).is_ok();
        // The linker script's symbols: only their addresses are read.
        let statics = core::ptr::addr_of!(__sheap) as u32 - 0x2000_0000;
        let ram = core::ptr::addr_of!(_stack_start) as u32 - 0x2000_0000;
        let _ = writeln!(out, "ram statics {statics} stack {} of {ram}", stack_used());
        let _ = writeln!(out, "done");
        debug::exit(if ok { EXIT_SUCCESS } else { EXIT_FAILURE });
        halt();
    }

    /// After the semihosting exit (which QEMU does not return from), sleep.
    fn halt() -> ! {
        loop {
            cortex_m::asm::wfi();
        }
    }

    #[panic_handler]
    fn panic(_: &core::panic::PanicInfo) -> ! {
        cortex_m_semihosting::hprintln!("panic");
        debug::exit(EXIT_FAILURE);
        halt();
    }
}
