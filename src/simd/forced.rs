//! Which loops the batch and planar paths may take, for the unit tests and the fuzz targets
//! only (`cfg(test)`, and `cfg(fuzzing)`, which cargo-fuzz sets): the public functions pick
//! their loops by the CPU and the target, so on a CPU with AVX-512 the AVX2, portable and
//! scalar loops would never run through them. Capping the loops per thread makes every loop
//! reachable through the public API on one machine, as a CPU or a target without the faster
//! ones would run it.
//!
//! Not part of the crate's API: ordinary builds do not compile this module, and the dispatch
//! there reads no switch.

use core::cell::Cell;

/// A level of loops, from the slowest to the fastest. The dispatch takes the fastest level that
/// both the CPU (or target) has and the cap of this thread allows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Loops {
    /// As on a target without f32 vector units (a microcontroller): the planar sRGB 8-bit
    /// encode in `planar/scalar.rs`, the interleaved one pixel by pixel; the linear planar
    /// loop is the portable one there too.
    Scalar,
    /// The portable chunked loops of `planar/portable.rs`, as on an x86-64 CPU with neither
    /// AVX2 nor AVX-512 (SSE2 code there) or on aarch64 (NEON).
    Portable,
    /// The AVX2 loops (`simd/avx2.rs`), as on an x86-64 CPU without the AVX-512 subsets.
    Avx2,
    /// The AVX-512 loops (`simd/avx512.rs`) where they apply, the AVX2 loop for the widths
    /// the interleaved AVX-512 loop does not take: what such a CPU runs.
    Avx512,
}

impl Loops {
    /// Every level, slowest first.
    pub const ALL: [Loops; 4] = [Loops::Scalar, Loops::Portable, Loops::Avx2, Loops::Avx512];

    /// A name for messages and logs.
    pub const fn name(self) -> &'static str {
        match self {
            Loops::Scalar => "scalar (the microcontroller loop)",
            Loops::Portable => "portable (SSE2 code on x86-64)",
            Loops::Avx2 => "AVX2",
            Loops::Avx512 => "AVX-512",
        }
    }

    /// The fastest level this CPU and target have.
    pub fn best() -> Loops {
        #[cfg(target_arch = "x86_64")]
        {
            if super::avx512::available() {
                return Loops::Avx512;
            }
            if super::avx2::available() {
                return Loops::Avx2;
            }
        }
        if super::target::VECTOR_UNITS {
            Loops::Portable
        } else {
            Loops::Scalar
        }
    }
}

/// What the last batch or planar call of this thread ran on its fast path (the sRGB 8-bit
/// encode with `Clip`, or linear output): the level of its loop, and whether that loop wrote
/// with non-temporal stores.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Ran {
    /// The loop's level.
    pub loops: Loops,
    /// Whether it streamed its output (non-temporal stores, 2²⁰ pixels and more).
    pub streamed: bool,
}

std::thread_local! {
    static CAP: Cell<Loops> = const { Cell::new(Loops::Avx512) };
    static RAN: Cell<Option<Ran>> = const { Cell::new(None) };
}

/// Caps this thread's loops at `cap`; returns the level the dispatch now takes: `cap`, or a
/// slower one where this CPU or target lacks it.
pub fn force(cap: Loops) -> Loops {
    CAP.with(|c| c.set(cap));
    cap.min(Loops::best())
}

/// Whether this thread's cap allows `level`.
#[inline]
pub(crate) fn allows(level: Loops) -> bool {
    CAP.with(|c| c.get() >= level)
}

/// Records the loop a fast path chose.
#[inline]
pub(crate) fn note(loops: Loops, streamed: bool) {
    RAN.with(|r| r.set(Some(Ran { loops, streamed })));
}

/// What the last fast path of this thread ran, and forgets it.
pub fn take_ran() -> Option<Ran> {
    RAN.with(|r| r.take())
}
