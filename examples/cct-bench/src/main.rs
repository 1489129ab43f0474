//! Colour temperature, Duv, lux and per-device calibration on a microcontroller: prints, for a
//! fixed list of inputs (points on and off the Planckian locus over the whole table, and NaN,
//! infinite, zero, negative, huge and subnormal XYZ), the CCT and Duv as f32 bits, and the
//! calibrated readings of a fixed list of counts. Lines starting with `res` are results; on the
//! host the same program prints the same lines, and `.ci/cct-bench` compares them.
//!
//! On the microcontroller it also counts the instructions of each call (lines starting with
//! `bench`), with SysTick under QEMU's `-icount shift=0`, where every instruction advances the
//! virtual clock by 1 ns: the program measures how many instructions a SysTick tick is (62.5 on
//! the microbit's 16 MHz clock, 40 on the mps2 boards' 25 MHz) with a loop of known length, in
//! thousandths, and converts.
#![cfg_attr(target_os = "none", no_std)]
#![cfg_attr(target_os = "none", no_main)]

use core::fmt::Write;
use core::hint::black_box;

use spectral_quadrature::tables::PLANCKIAN_LOCUS as LOCUS;
use spectral_quadrature::{uv_from_xyz, Calibration, CountCalibration, LuxScale};

/// The sweep's points: near the locus (|Duv| ≤ 0.06, some beyond the 0.05 limit) over the
/// whole table, and a few beyond its ends.
const SWEEP: usize = 96;
/// The special inputs before the sweep.
const SPECIALS: usize = 12;

/// XYZ (Y = 1) of CIE 1960 (u, v), in f32: x = 3u / (2u − 8v + 4), y = 2v / (2u − 8v + 4).
fn xyz_from_uv([u, v]: [f32; 2]) -> [f32; 3] {
    let d = 2.0 * u - 8.0 * v + 4.0;
    let (x, y) = (3.0 * u / d, 2.0 * v / d);
    [x / y, 1.0, (1.0 - x - y) / y]
}

/// The inputs every build prints results for.
fn inputs() -> [[f32; 3]; SPECIALS + SWEEP] {
    let nan = f32::NAN;
    let inf = f32::INFINITY;
    let sub = f32::from_bits(1);
    let specials: [[f32; 3]; SPECIALS] = [
        [95.047, 100.0, 108.883], // D65
        [109.85, 100.0, 35.585],  // A
        [0.0, 0.0, 0.0],
        [nan, 1.0, 1.0],
        [1.0, inf, 1.0],
        [-1.0, -1.0, -1.0],
        [0.95, 1.0, -0.01],
        [f32::MAX, f32::MAX, f32::MAX],
        [sub, sub, sub],
        [3e-39, 3.1e-39, 3.3e-39],
        [0.3, 0.6, 0.1],
        [1e30, 1.1e30, 0.9e30],
    ];
    let k = LOCUS.mired.len();
    let mut out = [[0.0f32; 3]; SPECIALS + SWEEP];
    for (i, xyz) in out.iter_mut().enumerate() {
        *xyz = match specials.get(i) {
            Some(s) => *s,
            None => {
                // Along a segment of the table (t in sixteenths), off the locus along a rough
                // normal (the tangent turned a quarter, scaled by |tu| + |tv|): Duv up to ±0.06.
                let p = i - SPECIALS;
                let j = (p * 7) % (k - 1);
                let t = ((p * 13) % 16) as f32 / 16.0;
                let off = ((p * 5) % 13) as f32 / 100.0 - 0.06;
                let [tu, tv] = LOCUS.tangent[j];
                let scale = off / (tu.abs() + tv.abs());
                let u = LOCUS.uv[j][0] + t * LOCUS.chord[j][0] - scale * tv;
                let v = LOCUS.uv[j][1] + t * LOCUS.chord[j][1] + scale * tu;
                xyz_from_uv([u, v])
            }
        };
    }
    out
}

/// An f32 as its bits in hex, or `nan` for any NaN (its sign and payload differ by target).
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

/// Eight channels of counts: a dark frame, a white frame, and what the golden device reads on
/// the white, in counts; then readings to correct.
const DARK: [u16; 8] = [412, 1023, 97, 640, 815, 1500, 0, 33];
const WHITE: [u16; 8] = [41_210, 52_003, 30_097, 64_000, 48_815, 1501, 65_535, 40_033];
const REFERENCE: [u16; 8] = [40_000, 50_000, 35_000, 60_000, 50_000, 65_535, 45_000, 1];

fn counts(p: usize) -> [u16; 8] {
    core::array::from_fn(|k| ((p * 7919 + k * 104_729) % 65_536) as u16)
}

/// Prints every result line.
fn results(out: &mut impl Write) -> core::fmt::Result {
    for (i, xyz) in inputs().iter().enumerate() {
        match LOCUS.cct(*xyz) {
            Some(c) => writeln!(out, "res cct {i} {} {}", Bits(c.kelvin), Bits(c.duv))?,
            None => writeln!(out, "res cct {i} none")?,
        }
        match uv_from_xyz(*xyz) {
            Some([u, v]) => writeln!(out, "res uv {i} {} {}", Bits(u), Bits(v))?,
            None => writeln!(out, "res uv {i} none")?,
        }
    }
    let count_cal = CountCalibration::from_dark_white(&DARK, &WHITE, &REFERENCE);
    let float_cal = Calibration::from_dark_white(
        &DARK.map(f32::from),
        &WHITE.map(f32::from),
        &REFERENCE.map(|r| f32::from(r) / 50_000.0),
    );
    writeln!(
        out,
        "res calibration counts {:?}",
        count_cal.map(|c| c.gain_q16)
    )?;
    writeln!(out, "res calibration floats {}", float_cal.is_ok())?;
    if let (Ok(c), Ok(f)) = (count_cal, float_cal) {
        for p in 0..16 {
            let x = counts(p);
            writeln!(out, "res apply counts {p} {:?}", c.apply(&x))?;
            let y = f.apply(&x.map(f32::from));
            write!(out, "res apply floats {p}")?;
            for v in y {
                write!(out, " {}", Bits(v))?;
            }
            writeln!(out)?;
        }
        let to_counts = f.to_counts(50_000.0).map(|c| c.gain_q16);
        writeln!(out, "res to_counts {to_counts:?}")?;
    }
    let lux = LuxScale::from_reading(0.0125, 500.0);
    writeln!(
        out,
        "res lux {:?} {}",
        lux.map(|l| l.lux_per_y.to_bits()),
        Bits(lux.map_or(f32::NAN, |l| l.lux([0.1, 0.004, 0.2])))
    )?;
    Ok(())
}

/// Instructions per call, measured by `ticks` (a clock that counts one tick per
/// `per_tick_milli / 1000` instructions) around loops over many calls. Integer arithmetic only,
/// so that printing links no float formatting.
#[cfg_attr(not(target_os = "none"), allow(dead_code))]
fn benches(
    out: &mut impl Write,
    ticks: &mut impl FnMut() -> u32,
    per_tick_milli: u32,
) -> core::fmt::Result {
    let px = inputs();
    // The sweep points the table covers (what a sensor mostly sees: light near the locus).
    let mut near = [[0.0f32; 3]; SWEEP];
    let mut n = 0;
    for xyz in &px[SPECIALS..] {
        if LOCUS.cct(*xyz).is_some() {
            near[n] = *xyz;
            n += 1;
        }
    }
    let near = &near[..n];
    let mut measure = |name: &str, calls: usize, f: &mut dyn FnMut()| -> core::fmt::Result {
        let t0 = ticks();
        f();
        let t1 = ticks();
        let instructions = u64::from(t1.wrapping_sub(t0) & 0x00FF_FFFF) * u64::from(per_tick_milli);
        // Rounded to the nearest instruction per call.
        let per_call = (instructions + 500 * calls as u64) / (1000 * calls as u64);
        writeln!(out, "bench {name} {per_call}")
    };
    const ROUNDS: usize = 20;
    let mut sink = [0u32; SWEEP];
    measure("empty loop", ROUNDS * near.len(), &mut || {
        for _ in 0..ROUNDS {
            for (o, xyz) in sink.iter_mut().zip(near) {
                *o = black_box(xyz[0].to_bits());
            }
        }
    })?;
    measure("PlanckianLocus::cct", ROUNDS * near.len(), &mut || {
        for _ in 0..ROUNDS {
            for (o, xyz) in sink.iter_mut().zip(near) {
                *o = black_box(LOCUS.cct(black_box(*xyz))).map_or(0, |c| c.kelvin.to_bits());
            }
        }
    })?;
    measure("uv_from_xyz", ROUNDS * near.len(), &mut || {
        for _ in 0..ROUNDS {
            for (o, xyz) in sink.iter_mut().zip(near) {
                *o = black_box(uv_from_xyz(black_box(*xyz))).map_or(0, |uv| uv[0].to_bits());
            }
        }
    })?;
    let uvs: [[f32; 2]; SWEEP] = core::array::from_fn(|i| {
        near.get(i)
            .and_then(|x| uv_from_xyz(*x))
            .unwrap_or([0.2, 0.3])
    });
    measure(
        "PlanckianLocus::cct_from_uv",
        ROUNDS * near.len(),
        &mut || {
            for _ in 0..ROUNDS {
                for (o, uv) in sink.iter_mut().zip(&uvs[..near.len()]) {
                    *o =
                        black_box(LOCUS.cct_from_uv(black_box(*uv))).map_or(0, |c| c.duv.to_bits());
                }
            }
        },
    )?;
    const CALLS: usize = 256;
    let frames: [[u16; 8]; 16] = core::array::from_fn(counts);
    if let Ok(cal) = CountCalibration::from_dark_white(&DARK, &WHITE, &REFERENCE) {
        let mut o = [[0u16; 8]; 16];
        measure("CountCalibration<8>::apply", CALLS, &mut || {
            for r in 0..CALLS / 16 {
                for (o, x) in o.iter_mut().zip(&frames) {
                    *o = black_box(cal.apply(black_box(x)));
                }
                black_box(r);
            }
        })?;
        black_box(&o);
    }
    let floats: [[f32; 8]; 16] = core::array::from_fn(|p| frames[p].map(f32::from));
    if let Ok(cal) = Calibration::from_dark_white(
        &DARK.map(f32::from),
        &WHITE.map(f32::from),
        &REFERENCE.map(f32::from),
    ) {
        let mut o = [[0.0f32; 8]; 16];
        measure("Calibration<8>::apply", CALLS, &mut || {
            for r in 0..CALLS / 16 {
                for (o, x) in o.iter_mut().zip(&floats) {
                    *o = black_box(cal.apply(black_box(x)));
                }
                black_box(r);
            }
        })?;
        black_box(&o);
    }
    let mut gains = [0u32; 8];
    measure("CountCalibration<8>::from_dark_white", 64, &mut || {
        for _ in 0..64 {
            if let Ok(c) = CountCalibration::from_dark_white(
                black_box(&DARK),
                black_box(&WHITE),
                black_box(&REFERENCE),
            ) {
                gains = black_box(c.gain_q16);
            }
        }
    })?;
    black_box((&sink, &gains));
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

    /// Instructions per SysTick tick, in thousandths: a loop of two instructions per round
    /// (`subs`, `bne`), timed. Under `-icount shift=0` this is 62 500 on the microbit and 40 000
    /// on the mps2 boards.
    fn instructions_per_tick_milli(ticks: &mut impl FnMut() -> u32) -> u32 {
        const ROUNDS: u32 = 400_000;
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
        ((2 * u64::from(ROUNDS) * 1000 + u64::from(t) / 2) / u64::from(t)) as u32
    }

    #[entry]
    fn main() -> ! {
        let mut out = Lines {
            buf: [0; 160],
            len: 0,
        };
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
        let per_tick = instructions_per_tick_milli(&mut ticks);
        let _ = writeln!(out, "bench instructions_per_tick_milli {per_tick}");
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
}
