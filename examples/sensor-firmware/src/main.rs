//! A colour sensor's firmware: the example 8-channel sensor (the AS7341 model of
//! `data/sensor_as7341_gaussian.csv`) reads each of the 24 ColorChecker patches under
//! illuminant C as u16 counts, simulated at build time (`build.rs`) for a device with its own
//! dark offsets, channel gains and read noise. The firmware calibrates the device from its dark
//! and white readings against the golden device's white (`tables::sensors::AS7341_WHITE`), then
//! turns each calibrated reading into XYZ (the f32 set [`tables::AS7341`]), CCT and Duv
//! ([`tables::PLANCKIAN_LOCUS`]), lux ([`LuxScale`]) and 8-bit sRGB (the integer path,
//! [`integer::AS7341_SRGB`]: integer arithmetic only). It also prints CCT and Duv for points on
//! and off the Planckian locus and for NaN, infinite, zero, negative, huge and subnormal XYZ,
//! and both calibrations on fixed counts. Lines starting with `res` are results; on the host the
//! same program prints the same `res` lines, and `.ci/sensor-firmware` compares them with those
//! of the Cortex-M0 (QEMU's `microbit`: 16 kB of RAM) and the Cortex-M4F (`mps2-an386`) builds.
//!
//! On the microcontroller it also counts the instructions of each step (lines starting with
//! `bench`), with SysTick under QEMU's `-icount shift=0`: every instruction advances the virtual
//! clock by 1 ns, SysTick counts the processor clock, and the program measures how many
//! instructions a tick is with a loop of known length. Then it prints how much of the stack it
//! used (`ram`).
#![cfg_attr(target_os = "none", no_std)]
#![cfg_attr(target_os = "none", no_main)]

use core::fmt::Write;
use core::hint::black_box;

use spectral_quadrature::tables::{self, folded, integer, sensors, PLANCKIAN_LOCUS as LOCUS};
use spectral_quadrature::{
    uv_from_xyz, Calibration, Cct, CountCalibration, FoldedSet, GamutMapping, IntegerSet, LuxScale,
};

#[allow(dead_code)]
mod simulated {
    include!(concat!(env!("OUT_DIR"), "/simulated.rs"));
}
use simulated::{
    CHANNELS, DEVICE_COUNTS, DEVICE_DARK, DEVICE_WHITE, GOLDEN_COUNTS, PATCHES, PATCH_NAMES,
    SAMPLE_UNIT,
};

/// The integer sets, each in one place: every call then passes the same address, and the
/// compiler can build the weights into the code as constants (a copy per function on the stack
/// would be read through a pointer instead).
static SENSOR: IntegerSet<CHANNELS> = integer::AS7341_SRGB;
#[cfg(not(feature = "set4-p46"))]
static SET4: IntegerSet<4> = integer::TABLE2_ROW2_SRGB;
/// With the feature `set4-p46`: Table 2's row 2 for counts of half the sample, 46 fractional
/// bits where the baked set has 45 (each P has its own code in the integer path).
#[cfg(feature = "set4-p46")]
static SET4: IntegerSet<4> = match IntegerSet::new(
    &folded::TABLE2_ROW2_SRGB,
    integer::TABLE2_ROW2_SRGB.sample_unit() / 2.0,
) {
    Ok(set) => set,
    Err(_) => panic!("Table 2's row 2 has a fixed-point form for half its sample"),
};
#[cfg(feature = "set4-p46")]
const _: () = assert!(SET4.frac_bits() == 46);
/// Sets of the sensor's first 5 and 6 channels: on Armv7E-M the integer path sums the samples
/// in pairs, two pairs a step, so these reach its last lone pair and a last unpaired sample,
/// beside N = 4 and 8 (whole steps).
static SET5: IntegerSet<5> = first_channels();
static SET6: IntegerSet<6> = first_channels();

/// The sensor's set on its first M channels, in fixed point (at compile time).
const fn first_channels<const M: usize>() -> IntegerSet<M> {
    let all = folded::AS7341_SRGB;
    let mut wavelengths_nm = [0.0; M];
    let mut weights = [[0.0; M]; 3];
    let mut i = 0;
    while i < M {
        wavelengths_nm[i] = all.wavelengths_nm()[i];
        let mut c = 0;
        while c < 3 {
            weights[c][i] = all.weights()[c][i];
            c += 1;
        }
        i += 1;
    }
    let folded = match FoldedSet::new(wavelengths_nm, weights, all.samples(), all.display()) {
        Ok(set) => set,
        Err(_) => panic!("the first channels of a baked set are a set"),
    };
    match IntegerSet::new(&folded, SAMPLE_UNIT) {
        Ok(set) => set,
        Err(_) => panic!("the sensor's first channels have no fixed-point form"),
    }
}

/// The illuminance on the chart, as a reference meter beside the white tile reads it: the one
/// reading of a known light that calibrates lux.
const CHART_LUX: f32 = 1000.0;

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

/// An f32 in decimal with `.1` decimals, rounded (half away from zero), for a reader: the
/// digits come from integers, so that printing links no float formatting.
struct Decimal(f32, u32);

impl core::fmt::Display for Decimal {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let Decimal(x, decimals) = *self;
        if !x.is_finite() {
            return f.write_str(if x.is_nan() { "nan" } else { "inf" });
        }
        let scaled = x * 10u32.pow(decimals) as f32;
        // `as` saturates: beyond ±2⁶³ the digits are the largest i64's.
        let n = if scaled < 0.0 {
            scaled - 0.5
        } else {
            scaled + 0.5
        } as i64;
        let unit = 10u64.pow(decimals);
        let sign = if n < 0 { "-" } else { "" };
        let (whole, frac) = (n.unsigned_abs() / unit, n.unsigned_abs() % unit);
        if decimals == 0 {
            write!(f, "{sign}{whole}")
        } else {
            write!(f, "{sign}{whole}.{frac:0width$}", width = decimals as usize)
        }
    }
}

/// A CCT and Duv as bits then in decimals (K, and Duv to 10⁻⁵), or `none`.
struct CctBits(Option<Cct>);

impl core::fmt::Display for CctBits {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self.0 {
            Some(c) => write!(
                f,
                "{} {} ({} K, Duv {})",
                Bits(c.kelvin),
                Bits(c.duv),
                Decimal(c.kelvin, 0),
                Decimal(c.duv, 5)
            ),
            None => f.write_str("none"),
        }
    }
}

/// The device as the firmware sets it up once: its calibration, in f32 (golden readings out)
/// and for counts (the integer path's counts out), and the lux scale.
#[derive(Clone, Copy)]
struct Device {
    float: Calibration<CHANNELS>,
    counts: CountCalibration<CHANNELS>,
    lux: LuxScale,
}

/// The golden device's white in the integer path's counts: 65 535 in its largest channel.
fn white_counts() -> [u16; CHANNELS] {
    sensors::AS7341_WHITE.map(|w| (w / SAMPLE_UNIT + 0.5).min(65_535.0) as u16)
}

/// Calibrates the simulated device from its dark and white readings: `None` if a channel saw
/// no light or the calibration does not fit the counts' range.
fn device() -> Option<Device> {
    let float = Calibration::from_dark_white(
        &DEVICE_DARK.map(f32::from),
        &DEVICE_WHITE.map(f32::from),
        &sensors::AS7341_WHITE,
    )
    .ok()?;
    // The same calibration for counts: one count is the integer set's sample unit.
    let counts = float.to_counts(SENSOR.sample_unit()).ok()?;
    // The white tile, calibrated, is the reading of the known light.
    let white = tables::AS7341.xyz(&float.apply(&DEVICE_WHITE.map(f32::from)));
    let lux = LuxScale::from_reading(white[1], CHART_LUX).ok()?;
    Some(Device { float, counts, lux })
}

/// What the firmware reports for one raw reading.
struct Reading {
    /// The calibrated counts (the integer path's input).
    counts: [u16; CHANNELS],
    xyz: [f32; 3],
    cct: Option<Cct>,
    lux: f32,
    /// sRGB8 by the integer path.
    srgb8: [u8; 3],
}

/// One raw reading through the calibration to XYZ, CCT, Duv, lux (f32) and sRGB8 (integers).
fn read(device: &Device, raw: &[u16; CHANNELS]) -> Reading {
    let counts = device.counts.apply(raw);
    let srgb8 = SENSOR.encode_u8(&counts);
    let xyz = tables::AS7341.xyz(&device.float.apply(&raw.map(f32::from)));
    Reading {
        counts,
        xyz,
        cct: LOCUS.cct(xyz),
        lux: device.lux.lux(xyz),
        srgb8,
    }
}

/// Prints every result line.
fn results(out: &mut impl Write) -> core::fmt::Result {
    writeln!(
        out,
        "res scene {} sensor AS7341 frac_bits {} sample_unit {}",
        tables::SCENE.rsplit('/').next().unwrap_or(""),
        SENSOR.frac_bits(),
        Bits(SENSOR.sample_unit())
    )?;
    // The build's scale and the firmware's agree.
    if SENSOR.sample_unit() != SAMPLE_UNIT {
        writeln!(out, "res sample unit differs from the simulation's")?;
    }
    let Some(device) = device() else {
        return writeln!(out, "res the device's calibration failed");
    };
    write!(out, "res device dark")?;
    for d in device.counts.dark() {
        write!(out, " {d}")?;
    }
    write!(out, " gain_q16")?;
    for g in device.counts.gain_q16() {
        write!(out, " {g}")?;
    }
    writeln!(out, " lux_per_y {}", Bits(device.lux.lux_per_y()))?;
    // The white tile: CCT and Duv of the light (C: 6771 K, Duv −0.0021) as the sensor sees it.
    let w = read(&device, &DEVICE_WHITE);
    let [x, y, z] = w.xyz.map(Bits);
    writeln!(
        out,
        "res white counts {:?} xyz {x} {y} {z} cct {} lux {} ({} lx) srgb8 {:?}",
        w.counts,
        CctBits(w.cct),
        Bits(w.lux),
        Decimal(w.lux, 1),
        w.srgb8
    )?;
    for p in 0..PATCHES {
        let r = read(&device, &DEVICE_COUNTS[p]);
        write!(out, "res patch {p:2} raw")?;
        for c in DEVICE_COUNTS[p] {
            write!(out, " {c}")?;
        }
        write!(out, " calibrated")?;
        for c in r.counts {
            write!(out, " {c}")?;
        }
        let [x, y, z] = r.xyz.map(Bits);
        let [sr, sg, sb] = r.srgb8;
        // The f32 path on the calibrated counts, and the golden device's reading through the
        // integer path, with the exact fixed-point sums behind it.
        let [rf, gf, bf] =
            folded::AS7341_SRGB.encode_u8(GamutMapping::Clip, &SENSOR.counts_as_f32(&r.counts));
        let golden = &GOLDEN_COUNTS[p];
        let [gr, gg, gb] = SENSOR.encode_u8(golden);
        let [fr, fg, fb] = SENSOR.linear_fixed(golden);
        writeln!(
            out,
            " xyz {x} {y} {z} cct {} lux {} ({} lx) srgb8 {sr} {sg} {sb} f32 {rf} {gf} {bf} golden {gr} {gg} {gb} fixed {fr} {fg} {fb} {}",
            CctBits(r.cct),
            Bits(r.lux),
            Decimal(r.lux, 1),
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
    let mut sums = [const { Fnv::new() }; 4];
    // The batch encoder on the same pixels, a chunk at a time: the same bytes.
    let mut batch_sums = [const { Fnv::new() }; 2];
    const CHUNK: usize = 16;
    for _ in 0..PIXELS / CHUNK {
        let mut x4 = [[0u16; 4]; CHUNK];
        let mut x8 = [[0u16; CHANNELS]; CHUNK];
        for (x4, x8) in x4.iter_mut().zip(&mut x8) {
            *x4 = core::array::from_fn(|_| next());
            sums[0].add(&SET4.encode_u8(x4));
            *x8 = core::array::from_fn(|_| next());
            sums[3].add(&SENSOR.encode_u8(x8));
            let x5: [u16; 5] = core::array::from_fn(|_| next());
            sums[1].add(&SET5.encode_u8(&x5));
            let x6: [u16; 6] = core::array::from_fn(|_| next());
            sums[2].add(&SET6.encode_u8(&x6));
        }
        let mut rgb = [[0u8; 3]; CHUNK];
        let ok = SET4.encode_u8_batch(&x4, &mut rgb).is_ok();
        rgb.iter().for_each(|p| batch_sums[0].add(p));
        let ok = ok && SENSOR.encode_u8_batch(&x8, &mut rgb).is_ok();
        rgb.iter().for_each(|p| batch_sums[1].add(p));
        if !ok {
            return writeln!(out, "res checksum: a batch failed");
        }
    }
    let [s4, s5, s6, s8] = sums.map(|s| s.0);
    writeln!(
        out,
        "res checksum {PIXELS} pixels N=4 {s4:016x} N=5 {s5:016x} N=6 {s6:016x} N=8 {s8:016x}"
    )?;
    writeln!(
        out,
        "res checksum batch N=4 {:016x} N=8 {:016x}",
        batch_sums[0].0, batch_sums[1].0
    )?;
    locus_results(out)?;
    calibration_results(out)
}

/// Pseudo-random pixels the checksum covers.
const PIXELS: usize = 50_000;

/// FNV-1a, 64 bits: a checksum of bytes.
struct Fnv(u64);

impl Fnv {
    const fn new() -> Fnv {
        Fnv(0xcbf2_9ce4_8422_2325)
    }

    fn add(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
}

/// The locus sweep's points: near the locus (|Duv| ≤ 0.06, some beyond the 0.05 limit) over
/// the whole table, and a few beyond its ends.
const SWEEP: usize = 96;
/// The special inputs before the sweep.
const SPECIALS: usize = 12;

/// XYZ (Y = 1) of CIE 1960 (u, v), in f32: x = 3u / (2u − 8v + 4), y = 2v / (2u − 8v + 4).
fn xyz_from_uv([u, v]: [f32; 2]) -> [f32; 3] {
    let d = 2.0 * u - 8.0 * v + 4.0;
    let (x, y) = (3.0 * u / d, 2.0 * v / d);
    [x / y, 1.0, (1.0 - x - y) / y]
}

/// The XYZ inputs of the CCT lines.
fn locus_inputs() -> [[f32; 3]; SPECIALS + SWEEP] {
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
    let k = LOCUS.mired().len();
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
                let [tu, tv] = LOCUS.tangent()[j];
                let scale = off / (tu.abs() + tv.abs());
                let u = LOCUS.uv()[j][0] + t * LOCUS.chord()[j][0] - scale * tv;
                let v = LOCUS.uv()[j][1] + t * LOCUS.chord()[j][1] + scale * tu;
                xyz_from_uv([u, v])
            }
        };
    }
    out
}

/// CCT, Duv and (u, v) of every locus input.
fn locus_results(out: &mut impl Write) -> core::fmt::Result {
    for (i, xyz) in locus_inputs().iter().enumerate() {
        writeln!(out, "res cct {i} {}", CctBits(LOCUS.cct(*xyz)))?;
        match uv_from_xyz(*xyz) {
            Some([u, v]) => writeln!(out, "res uv {i} {} {}", Bits(u), Bits(v))?,
            None => writeln!(out, "res uv {i} none")?,
        }
    }
    Ok(())
}

/// Eight channels of counts for the calibrations' edge cases: a dark frame (one channel at 0),
/// a white frame (one channel barely above its dark, one at full scale), and a reference with
/// a channel at 1; then readings to correct.
const DARK: [u16; 8] = [412, 1023, 97, 640, 815, 1500, 0, 33];
const WHITE: [u16; 8] = [41_210, 52_003, 30_097, 64_000, 48_815, 1501, 65_535, 40_033];
const REFERENCE: [u16; 8] = [40_000, 50_000, 35_000, 60_000, 50_000, 65_535, 45_000, 1];

fn counts(p: usize) -> [u16; 8] {
    core::array::from_fn(|k| ((p * 7919 + k * 104_729) % 65_536) as u16)
}

/// Both calibrations and the lux scale on fixed inputs, their edges included.
fn calibration_results(out: &mut impl Write) -> core::fmt::Result {
    let count_cal = CountCalibration::from_dark_white(&DARK, &WHITE, &REFERENCE);
    let float_cal = Calibration::from_dark_white(
        &DARK.map(f32::from),
        &WHITE.map(f32::from),
        &REFERENCE.map(|r| f32::from(r) / 50_000.0),
    );
    writeln!(
        out,
        "res calibration counts {:?}",
        count_cal.map(|c| c.gain_q16())
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
        let to_counts = f.to_counts(1.0 / 50_000.0).map(|c| c.gain_q16());
        writeln!(out, "res to_counts {to_counts:?}")?;
    }
    // The golden white in counts against the device's own white, in integers only.
    let direct = CountCalibration::from_dark_white(&DEVICE_DARK, &DEVICE_WHITE, &white_counts());
    writeln!(
        out,
        "res device integer gains {:?}",
        direct.map(|c| c.gain_q16())
    )?;
    let lux = LuxScale::from_reading(0.0125, 500.0);
    writeln!(
        out,
        "res lux {:?} {}",
        lux.map(|l| l.lux_per_y().to_bits()),
        Bits(lux.map_or(f32::NAN, |l| l.lux([0.1, 0.004, 0.2])))
    )?;
    for (y, lx) in [(0.0, 500.0), (-1.0, 500.0), (f32::NAN, 1.0), (1e-30, 1e30)] {
        writeln!(
            out,
            "res lux scale {:?}",
            LuxScale::from_reading(y, lx).map(|l| l.lux_per_y().to_bits())
        )?;
    }
    Ok(())
}

/// Pixels per measurement of the per-pixel paths.
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

/// The golden device's counts of the patches, ten times over (N = 8).
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
const fn counts_as_f32<const N: usize>(counts: &[[u16; N]; P], unit: f32) -> [[f32; N]; P] {
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
static SWEEP4_F32: [[f32; 4]; P] = counts_as_f32(&SWEEP4, integer::TABLE2_ROW2_SRGB.sample_unit());
static PATCH_F32: [[f32; CHANNELS]; P] = counts_as_f32(&PATCH_COUNTS, SAMPLE_UNIT);

/// Instruction counts per call: `ticks` counts SysTick ticks, and `ratio` (instructions,
/// ticks) is how many instructions a number of ticks is. Integer arithmetic only, so that
/// printing them links no float formatting.
#[cfg_attr(not(target_os = "none"), allow(dead_code))]
struct Bench<'a, W, T> {
    out: &'a mut W,
    ticks: &'a mut T,
    ratio: (u32, u32),
}

#[cfg_attr(not(target_os = "none"), allow(dead_code))]
impl<W: Write, T: FnMut() -> u32> Bench<'_, W, T> {
    /// Runs `f`, which makes `calls` calls, and prints the instructions per call.
    fn measure(&mut self, name: &str, calls: usize, f: &mut dyn FnMut()) -> core::fmt::Result {
        let t0 = (self.ticks)();
        f();
        let t1 = (self.ticks)();
        let t = u64::from(t1.wrapping_sub(t0) & 0x00FF_FFFF);
        // Instructions, then per call, rounded to the nearest.
        let n = t * u64::from(self.ratio.0);
        let d = u64::from(self.ratio.1) * calls as u64;
        writeln!(self.out, "bench {name} {}", (n + d / 2) / d)
    }
}

/// Every instruction count: the per-pixel paths at N = 4 and 8, integer and f32, here; then
/// the colour temperature and the calibrations, each in a function of its own so that their
/// inputs and outputs (a few kB each; the nRF51 has 16 kB of RAM) do not share a stack frame.
#[cfg_attr(not(target_os = "none"), allow(dead_code))]
fn benches(
    out: &mut impl Write,
    ticks: &mut impl FnMut() -> u32,
    ratio: (u32, u32),
) -> core::fmt::Result {
    let mut b = Bench { out, ticks, ratio };
    let mut rgb = [[0u8; 3]; P];
    let mut xyz = [0.0f32; 3];
    let f4 = folded::TABLE2_ROW2_SRGB;
    let f8 = folded::AS7341_SRGB;
    // The loops below each cost P · (their body) + the loop itself; the empty loop's count is
    // printed so a reader can subtract it.
    b.measure("empty_loop", P, &mut || {
        for (o, s) in rgb.iter_mut().zip(&SWEEP4) {
            *o = black_box([s[0] as u8, 0, 0]);
        }
    })?;
    b.measure("N=4 integer encode_u8", P, &mut || {
        for (o, s) in rgb.iter_mut().zip(&SWEEP4) {
            *o = black_box(SET4.encode_u8(black_box(s)));
        }
    })?;
    b.measure("N=4 integer encode_u8_batch", P, &mut || {
        let _ = black_box(SET4.encode_u8_batch(black_box(&SWEEP4), &mut rgb));
    })?;
    b.measure("N=4 f32 encode_u8", P, &mut || {
        for (o, s) in rgb.iter_mut().zip(&SWEEP4_F32) {
            *o = black_box(f4.encode_u8(GamutMapping::Clip, black_box(s)));
        }
    })?;
    b.measure("N=8 integer encode_u8", P, &mut || {
        for (o, s) in rgb.iter_mut().zip(&PATCH_COUNTS) {
            *o = black_box(SENSOR.encode_u8(black_box(s)));
        }
    })?;
    b.measure("N=8 integer encode_u8_batch", P, &mut || {
        let _ = black_box(SENSOR.encode_u8_batch(black_box(&PATCH_COUNTS), &mut rgb));
    })?;
    b.measure("N=8 f32 encode_u8", P, &mut || {
        for (o, s) in rgb.iter_mut().zip(&PATCH_F32) {
            *o = black_box(f8.encode_u8(GamutMapping::Clip, black_box(s)));
        }
    })?;
    b.measure("N=8 f32 xyz", P, &mut || {
        for s in &PATCH_F32 {
            xyz = black_box(tables::AS7341.xyz(black_box(s)));
        }
    })?;
    black_box((&rgb, &xyz));
    locus_benches(&mut b)?;
    calibration_benches(&mut b)
}

/// CCT and Duv, and lux.
#[inline(never)]
#[cfg_attr(not(target_os = "none"), allow(dead_code))]
fn locus_benches<W: Write, T: FnMut() -> u32>(b: &mut Bench<'_, W, T>) -> core::fmt::Result {
    // Colour temperature: the sweep's points the table covers (what a sensor mostly sees:
    // light near the locus), many times over.
    let px = locus_inputs();
    let mut near = [[0.0f32; 3]; SWEEP];
    let mut n = 0;
    for xyz in &px[SPECIALS..] {
        if LOCUS.cct(*xyz).is_some() {
            near[n] = *xyz;
            n += 1;
        }
    }
    let near = &near[..n];
    const ROUNDS: usize = 20;
    let mut sink = [0u32; SWEEP];
    b.measure("locus_empty_loop", ROUNDS * near.len(), &mut || {
        for _ in 0..ROUNDS {
            for (o, xyz) in sink.iter_mut().zip(near) {
                *o = black_box(xyz[0].to_bits());
            }
        }
    })?;
    b.measure("PlanckianLocus::cct", ROUNDS * near.len(), &mut || {
        for _ in 0..ROUNDS {
            for (o, xyz) in sink.iter_mut().zip(near) {
                *o = black_box(LOCUS.cct(*black_box(xyz))).map_or(0, |c| c.kelvin.to_bits());
            }
        }
    })?;
    b.measure("uv_from_xyz", ROUNDS * near.len(), &mut || {
        for _ in 0..ROUNDS {
            for (o, xyz) in sink.iter_mut().zip(near) {
                *o = black_box(uv_from_xyz(*black_box(xyz))).map_or(0, |uv| uv[0].to_bits());
            }
        }
    })?;
    let uvs: [[f32; 2]; SWEEP] = core::array::from_fn(|i| {
        near.get(i)
            .and_then(|x| uv_from_xyz(*x))
            .unwrap_or([0.2, 0.3])
    });
    b.measure(
        "PlanckianLocus::cct_from_uv",
        ROUNDS * near.len(),
        &mut || {
            for _ in 0..ROUNDS {
                for (o, uv) in sink.iter_mut().zip(&uvs[..near.len()]) {
                    *o =
                        black_box(LOCUS.cct_from_uv(*black_box(uv))).map_or(0, |c| c.duv.to_bits());
                }
            }
        },
    )?;
    let Some(device) = device() else {
        return writeln!(b.out, "bench the device's calibration failed");
    };
    b.measure("LuxScale::lux", ROUNDS * near.len(), &mut || {
        for _ in 0..ROUNDS {
            for (o, xyz) in sink.iter_mut().zip(near) {
                *o = black_box(device.lux.lux(*black_box(xyz))).to_bits();
            }
        }
    })?;
    black_box(&sink);
    Ok(())
}

/// Both calibrations, and a whole reading.
#[inline(never)]
#[cfg_attr(not(target_os = "none"), allow(dead_code))]
fn calibration_benches<W: Write, T: FnMut() -> u32>(b: &mut Bench<'_, W, T>) -> core::fmt::Result {
    let Some(device) = device() else {
        return writeln!(b.out, "bench the device's calibration failed");
    };
    let mut calibrated = [[0u16; CHANNELS]; PATCHES];
    b.measure("CountCalibration<8>::apply", 10 * PATCHES, &mut || {
        for _ in 0..10 {
            for (o, x) in calibrated.iter_mut().zip(&DEVICE_COUNTS) {
                *o = black_box(device.counts.apply(black_box(x)));
            }
        }
    })?;
    let raw_f32: [[f32; CHANNELS]; PATCHES] = DEVICE_COUNTS.map(|c| c.map(f32::from));
    let mut calibrated_f32 = [[0.0f32; CHANNELS]; PATCHES];
    b.measure("Calibration<8>::apply", 10 * PATCHES, &mut || {
        for _ in 0..10 {
            for (o, x) in calibrated_f32.iter_mut().zip(&raw_f32) {
                *o = black_box(device.float.apply(black_box(x)));
            }
        }
    })?;
    let mut gains = [0u32; CHANNELS];
    let reference = white_counts();
    b.measure("CountCalibration<8>::from_dark_white", 64, &mut || {
        for _ in 0..64 {
            if let Ok(c) = CountCalibration::from_dark_white(
                black_box(&DEVICE_DARK),
                black_box(&DEVICE_WHITE),
                black_box(&reference),
            ) {
                gains = black_box(c.gain_q16());
            }
        }
    })?;
    // A whole reading, raw counts to what the firmware reports (`read`): both calibrations,
    // the integer sRGB8, XYZ, CCT, Duv and lux.
    let mut reports = [0u32; PATCHES];
    b.measure(
        "read (raw counts to XYZ, CCT, Duv, lux, sRGB8)",
        10 * PATCHES,
        &mut || {
            for _ in 0..10 {
                for (o, x) in reports.iter_mut().zip(&DEVICE_COUNTS) {
                    let r = read(&device, black_box(x));
                    *o = black_box(r.cct.map_or(0, |c| c.kelvin.to_bits()) ^ u32::from(r.srgb8[0]));
                }
            }
        },
    )?;
    black_box((&calibrated, &calibrated_f32, &gains, &reports));
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
