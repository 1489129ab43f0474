//! The C header of a scene (`tables::c::HEADER` in the runtime): every item of the baked model
//! as `static const` tables, and the runtime's per-pixel paths as `static inline` functions that
//! give the runtime's bits, C99 and C++11 alike. A formatter of the [`Model`] like the Rust and
//! shader ones: it reads the model's lists in their order and writes each kind; what it computes
//! beyond syntax is what the runtime computes in constant evaluation from the same f32 values
//! (the sRGB and linear 8-bit thresholds, the integer sets' fixed-point weights and the
//! thresholds on their scales), with the runtime's own arithmetic, so that a test can hold the
//! two to the same bits.
//!
//! The naming rule: a baked constant `tables::<module>::<NAME>` (or `tables::<NAME>`) becomes
//! `sq_<module>_<name>` in lower case; its data are `sq_<module>_<name>_<accessor>` after the
//! Rust accessor (`wavelengths_nm`, `weights`, ...) and its methods `sq_<module>_<name>_<method>`
//! (`linear_rgb`, `encode_u8`, ...). A free function of the runtime keeps its name after `sq_`
//! (`sq_srgb8_from_linear`, `sq_uv_from_xyz`); a method of a runtime type on values the caller
//! holds is `sq_<type>_<method>` with the type in snake case (`sq_count_calibration_apply`).
//! Enumerations are `SQ_<TYPE>_<VARIANT>` in upper case. Arrays of the Rust API are C arrays in
//! the same order (`[[f32; N]; 3]` is `float [3][N]`); a function writes its results to its last
//! argument.

use std::fmt::Write as _;
use std::string::{String, ToString};
use std::vec::Vec;

use super::layout::lit;
use super::model::{ceil_f32_bits, Display, Model, Samples, Transfer};

/// The header for the model: one text, C99 and C++11.
pub(crate) fn header_of(m: &Model) -> String {
    let mut o = String::new();
    o.push_str(&top_comment(m));
    o.push_str(PRELUDE);
    opponent(&mut o, m);
    curves(&mut o, m);
    if let Some(l) = &m.locus {
        locus(&mut o, l);
    }
    extras(&mut o, m);
    for s in &m.rule_sets {
        set(&mut o, "rules", s);
    }
    for s in &m.colour_sets {
        set(&mut o, "sets", s);
    }
    for d in &m.displays {
        display(&mut o, m, d);
    }
    for f in &m.folded {
        folded(&mut o, m, f);
    }
    for g in &m.groups {
        group(&mut o, m, g);
    }
    for l in &m.lights {
        let set = &m.colour_sets[l.set];
        let name = std::format!("sq_lights_{}_at_{}", lower(&l.light), lower(&set.name));
        writeln!(
            o,
            "/* tables::lights::{}_AT_{}: the light {} at {}'s nodes. */",
            l.light, set.name, l.light, set.name
        )
        .ok();
        floats(&mut o, &name, &l.values);
        o.push('\n');
    }
    if let Some(max) = m.upsamplings.iter().map(|u| u.n).max() {
        writeln!(o, "#define SQ_UPSAMPLING_MAX_LEN {max}\n").ok();
        o.push_str(UPSAMPLING_HELPER);
        o.push_str(ROUND_TRIP_HELPER);
    }
    for u in &m.upsamplings {
        upsampling(&mut o, u);
    }
    for s in &m.sensors {
        sensor(&mut o, s);
    }
    for i in &m.integer {
        integer(&mut o, m, i);
    }
    o.push_str(EPILOGUE);
    o
}

/// `name` in lower case: the C name of a Rust constant's part.
fn lower(name: &str) -> String {
    name.to_ascii_lowercase()
}

/// A C literal of an f32: Rust's shortest round-trip form with the `f` suffix, which a C or C++
/// compiler reads as that very f32 (decimal: C++11 has no hexadecimal floats).
fn c_float(x: f32) -> String {
    lit(x) + "f"
}

fn joined<T>(v: &[T], f: impl Fn(&T) -> String) -> String {
    let mut o = String::new();
    for (i, x) in v.iter().enumerate() {
        if i > 0 {
            o.push_str(if i % 8 == 0 { ",\n    " } else { ", " });
        }
        o.push_str(&f(x));
    }
    o
}

fn floats(o: &mut String, name: &str, v: &[f32]) {
    writeln!(
        o,
        "static const float {name}[{}] = {{\n    {}\n}};",
        v.len(),
        joined(v, |&x| c_float(x))
    )
    .ok();
}

fn rows3(o: &mut String, name: &str, w: &[Vec<f32>; 3]) {
    let n = w[0].len();
    writeln!(o, "static const float {name}[3][{n}] = {{").ok();
    for row in w {
        writeln!(o, "    {{ {} }},", joined(row, |&x| c_float(x))).ok();
    }
    o.push_str("};\n");
}

fn matrix(o: &mut String, name: &str, m: &[[f32; 3]; 3]) {
    writeln!(o, "static const float {name}[3][3] = {{").ok();
    for row in m {
        writeln!(o, "    {{ {} }},", joined(row, |&x| c_float(x))).ok();
    }
    o.push_str("};\n");
}

fn u32s(o: &mut String, name: &str, v: &[u32]) {
    writeln!(
        o,
        "static const uint32_t {name}[{}] = {{\n    {}\n}};",
        v.len(),
        joined(v, |x| std::format!("0x{x:08x}u"))
    )
    .ok();
}

fn u64s(o: &mut String, name: &str, v: &[u64]) {
    writeln!(
        o,
        "static const uint64_t {name}[{}] = {{\n    {}\n}};",
        v.len(),
        joined(v, |x| std::format!("UINT64_C(0x{x:016x})"))
    )
    .ok();
}

fn top_comment(m: &Model) -> String {
    let mut o = String::from("/*\n");
    for line in m.provenance.header.lines() {
        // The Rust tables name their generator; this file's is emit/c.rs, from the same model.
        let line = line.replace("emit/codegen.rs", "emit/c.rs");
        writeln!(o, " * {line}").ok();
    }
    writeln!(
        o,
        " * Made by spectral-quadrature {} (crate spectral-quadrature-generator {}).",
        env!("CARGO_PKG_VERSION"),
        env!("CARGO_PKG_VERSION")
    )
    .ok();
    o.push_str(USAGE);
    o.push_str(" */\n");
    o
}

const USAGE: &str = r#" *
 * spectral-quadrature's baked tables and per-pixel paths for C99 and C++11, one header: include
 * it where you need it (every item is `static`, so any number of translation units may). It
 * allocates nothing and has no state. Docs: docs/c-and-cpp.md of the crate.
 *
 * Names: a constant `tables::<module>::<NAME>` of the Rust crate is `sq_<module>_<name>` (lower
 * case); its data `sq_<module>_<name>_<accessor>` and its methods `sq_<module>_<name>_<method>`,
 * after the Rust ones; free functions `sq_<function>`; a method of a runtime type on values you
 * hold `sq_<type>_<method>`; enumerations `SQ_<TYPE>_<VARIANT>`. Arrays are in the Rust order
 * (`[[f32; N]; 3]` is `float [3][N]`) and each function writes its results to its last argument.
 *
 * Bits: every function gives the Rust runtime's bits and bytes for every input (NaN, infinities,
 * subnormals, huge and negative values included), except the 16-bit encoders of the sRGB curve
 * and of power laws, which call the C library's `powf`: where it differs from the runtime's
 * (Rust `libm`), a channel may differ by one step of 65 535 (the runtime's own U16_MAX_ERROR
 * against the exact curve). That needs IEEE single precision evaluated as single
 * (FLT_EVAL_METHOD 0: checked below; on 32-bit x86 compile with -msse2 -mfpmath=sse), no
 * contraction of a*b+c into a fused multiply-add (GCC contracts by default in its GNU modes and
 * clang may: the header turns it off for its own functions, with `#pragma STDC FP_CONTRACT OFF`
 * on clang and `#pragma GCC optimize ("fp-contract=off")` on GCC; GCC does not then inline the
 * header's functions into code built with other options: compile with -ffp-contract=off and
 * define SQ_NO_OPTIMIZE_PRAGMA to let it), and no -ffast-math (nor -ffinite-math-only,
 * -funsafe-math-optimizations, -fno-signed-zeros). Subnormals must not be flushed to zero.
 *
 * The C library: `powf` (the 16-bit encoders of sRGB and power laws) and `sqrtf` (CCT and Duv),
 * from <math.h>; link with -lm where the platform needs it. The integer path (the
 * `sq_integer_*` functions and the count calibrations) uses no floating point but for
 * `*_counts_as_f32`.
"#;

const PRELUDE: &str = r#"
#ifndef SPECTRAL_QUADRATURE_H
#define SPECTRAL_QUADRATURE_H

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#if !defined(FLT_EVAL_METHOD) || FLT_EVAL_METHOD != 0
#error "spectral_quadrature.h: float expressions must be evaluated in float (FLT_EVAL_METHOD 0); on 32-bit x86 compile with -msse2 -mfpmath=sse"
#endif
#if defined(__FAST_MATH__) || defined(__FINITE_MATH_ONLY__) && __FINITE_MATH_ONLY__
#error "spectral_quadrature.h: -ffast-math or -ffinite-math-only changes the runtime's results (NaN and infinities are inputs it handles)"
#endif

#if defined(__clang__)
/* Inside each function: no fused multiply-add where the runtime rounds twice. */
#define SQ_FP_EXACT _Pragma("STDC FP_CONTRACT OFF")
#else
#define SQ_FP_EXACT
#endif
#if defined(__GNUC__) && !defined(__clang__) && !defined(SQ_NO_OPTIMIZE_PRAGMA)
#pragma GCC push_options
#pragma GCC optimize ("fp-contract=off")
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* GamutMapping: how an encoder brings a colour into 0..=1. */
typedef enum sq_gamut_mapping {
    /* GamutMapping::Clip: each channel clamped to 0..=1. */
    SQ_GAMUT_MAPPING_CLIP = 0,
    /* GamutMapping::PreserveA: toward grey at the same A (luminance), then clamped. */
    SQ_GAMUT_MAPPING_PRESERVE_A = 1
} sq_gamut_mapping;

/* Cct: the correlated colour temperature in kelvin and Duv. */
typedef struct sq_cct {
    float kelvin;
    float duv;
} sq_cct;

/* f32::to_bits. */
static inline uint32_t sq_f32_bits(float x) {
    uint32_t b;
    memcpy(&b, &x, sizeof b);
    return b;
}

/* f32::from_bits. */
static inline float sq_f32_from_bits(uint32_t b) {
    float x;
    memcpy(&x, &b, sizeof x);
    return x;
}

/* f32::is_nan, from the bits (whatever the compiler's flags). */
static inline int sq_is_nan(float x) {
    return (sq_f32_bits(x) & 0x7fffffffu) > 0x7f800000u;
}

/* f32::is_infinite. */
static inline int sq_is_infinite(float x) {
    return (sq_f32_bits(x) & 0x7fffffffu) == 0x7f800000u;
}

/* 0..=1, NaN to 0. */
static inline float sq_clamp01(float x) {
    return x > 0.0f ? (x < 1.0f ? x : 1.0f) : 0.0f;
}

/* quantize_u8: 0..=1 to 0..=255, rounded to nearest; NaN to 0, out of range clamped. */
static inline uint8_t sq_quantize_u8(float e) {
    SQ_FP_EXACT
    return (uint8_t)(sq_clamp01(e) * 255.0f + 0.5f);
}

/* quantize_u16: 0..=1 to 0..=65535, rounded to nearest; NaN to 0, out of range clamped. */
static inline uint16_t sq_quantize_u16(float e) {
    SQ_FP_EXACT
    return (uint16_t)(sq_clamp01(e) * 65535.0f + 0.5f);
}

/* The weights (3 rows of n) times the n samples, each row summed in index order from 0. */
static inline void sq_mat_vec(size_t n, const float *w, const float *s, float out[3]) {
    SQ_FP_EXACT
    float a = 0.0f, b = 0.0f, c = 0.0f;
    size_t i;
    for (i = 0; i < n; i++) {
        float x = s[i];
        a += w[i] * x;
        b += w[n + i] * x;
        c += w[2 * n + i] * x;
    }
    out[0] = a;
    out[1] = b;
    out[2] = c;
}

/* A 3x3 matrix times a vector (out may be v). */
static inline void sq_mat3_vec(const float m[3][3], const float v[3], float out[3]) {
    SQ_FP_EXACT
    float r0 = m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2];
    float r1 = m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2];
    float r2 = m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2];
    out[0] = r0;
    out[1] = r1;
    out[2] = r2;
}

/* An 8-bit encoder from its thresholds (the f32 bits where each code starts): the code of x
 * clamped to 0..=1 (NaN to 0), in 8 comparisons. */
static inline uint8_t sq_encode8(const uint32_t t[256], float x) {
    uint32_t bits = sq_f32_bits(sq_clamp01(x));
    unsigned k = 0, step;
    for (step = 128; step > 0; step >>= 1) {
        if (t[(k + step) & 255u] <= bits) {
            k += step;
        }
    }
    return (uint8_t)k;
}

/* The number of thresholds k = 1..=255 at or below v. */
static inline uint8_t sq_count64(const uint64_t t[256], uint64_t v) {
    unsigned k = 0, step;
    for (step = 128; step > 0; step >>= 1) {
        if (t[(k + step) & 255u] <= v) {
            k += step;
        }
    }
    return (uint8_t)k;
}

/* The sRGB curve in f32 with powf, held at the join's value above it; clamped input, output in
 * 0..=1 (the runtime's 16-bit sRGB encoder before quantizing). */
static inline float sq_srgb_f32(float linear) {
    SQ_FP_EXACT
    float x = sq_clamp01(linear), e, floor_;
    if (x == 0.0f || x == 1.0f) {
        return x;
    }
    if (x <= 0.0031308f) {
        e = 12.92f * x;
    } else {
        e = 1.055f * powf(x, 1.0f / 2.4f) - 0.055f;
        floor_ = 12.92f * 0.0031308f;
        e = e > floor_ ? e : floor_;
    }
    return sq_clamp01(e);
}

/* x^(1/g) in f32 with powf; a g that is not finite and positive is linear. */
static inline float sq_gamma_f32(float g, float linear) {
    SQ_FP_EXACT
    float x = sq_clamp01(linear);
    if (x == 0.0f || x == 1.0f || !(g > 0.0f) || sq_is_infinite(g)) {
        return x;
    }
    return sq_clamp01(powf(x, 1.0f / g));
}

/* Display::map_gamut with PreserveA for a colour without NaN or infinity. */
static inline void sq_preserve_a(const float a_rgb[3], const float rgb[3], float out[3]) {
    SQ_FP_EXACT
    float a_white = a_rgb[0] + a_rgb[1] + a_rgb[2];
    float a = a_rgb[0] * rgb[0] + a_rgb[1] * rgb[1] + a_rgb[2] * rgb[2];
    float level = a / a_white;
    float d[3], t = 1.0f, q;
    int c;
    if (sq_is_nan(level) || level <= 0.0f) {
        out[0] = out[1] = out[2] = 0.0f;
        return;
    }
    if (level >= 1.0f) {
        out[0] = out[1] = out[2] = 1.0f;
        return;
    }
    for (c = 0; c < 3; c++) {
        d[c] = rgb[c] - level;
    }
    for (c = 0; c < 3; c++) {
        if (d[c] > 0.0f) {
            q = (1.0f - level) / d[c];
            t = q < t ? q : t;
        } else if (d[c] < 0.0f) {
            q = level / -d[c];
            t = q < t ? q : t;
        }
    }
    for (c = 0; c < 3; c++) {
        out[c] = sq_clamp01(level + t * d[c]);
    }
}

/* Display::map_gamut: any NaN channel gives black; Clip clamps each channel; PreserveA moves
 * toward grey at the same A (a colour with an infinite channel is clipped). */
static inline void sq_map_gamut(const float a_rgb[3], sq_gamut_mapping mapping, const float rgb[3], float out[3]) {
    int c;
    if (sq_is_nan(rgb[0]) || sq_is_nan(rgb[1]) || sq_is_nan(rgb[2])) {
        out[0] = out[1] = out[2] = 0.0f;
        return;
    }
    if (mapping == SQ_GAMUT_MAPPING_PRESERVE_A && !sq_is_infinite(rgb[0]) && !sq_is_infinite(rgb[1]) && !sq_is_infinite(rgb[2])) {
        sq_preserve_a(a_rgb, rgb, out);
        return;
    }
    for (c = 0; c < 3; c++) {
        out[c] = sq_clamp01(rgb[c]);
    }
}

/* Cct, LuxScale and the calibrations: on values the caller holds. */

/* LuxScale::lux: lux_per_y times Y. */
static inline float sq_lux_scale_lux(float lux_per_y, const float xyz[3]) {
    return lux_per_y * xyz[1];
}

/* Calibration::apply: (reading - dark) * gain per channel, n channels. */
static inline void sq_calibration_apply(size_t n, const float *dark, const float *gain, const float *readings, float *out) {
    SQ_FP_EXACT
    size_t k;
    for (k = 0; k < n; k++) {
        out[k] = (readings[k] - dark[k]) * gain[k];
    }
}

/* CountCalibration::apply: (counts - dark, saturating at 0) * gain_q16 / 2^16 rounded, at most
 * 65535; integers only. */
static inline void sq_count_calibration_apply(size_t n, const uint16_t *dark, const uint32_t *gain_q16, const uint16_t *counts, uint16_t *out) {
    size_t k;
    for (k = 0; k < n; k++) {
        uint32_t x = counts[k] > dark[k] ? (uint32_t)(counts[k] - dark[k]) : 0u;
        uint32_t g = gain_q16[k];
        uint32_t high = x * (g >> 16);
        uint32_t low = (x * (g & 0xffffu) + 0x8000u) >> 16;
        uint32_t sum = high + low;
        out[k] = (uint16_t)(sum < 65535u ? sum : 65535u);
    }
}

/* CountCalibration::from_dark_white: each channel's gain in 16 fractional bits so that the white
 * reading (less dark) becomes the reference. Returns 0, or k + 1 for the first channel k with no
 * signal (white at or below dark) or a reference of 0 (gain_q16 then undefined). */
static inline size_t sq_count_calibration_from_dark_white(size_t n, const uint16_t *dark, const uint16_t *white, const uint16_t *reference, uint32_t *gain_q16) {
    size_t k;
    for (k = 0; k < n; k++) {
        uint32_t signal = white[k] > dark[k] ? (uint32_t)(white[k] - dark[k]) : 0u;
        if (signal == 0u || reference[k] == 0u) {
            return k + 1;
        }
        gain_q16[k] = (((uint32_t)reference[k] << 16) + signal / 2u) / signal;
    }
    return 0;
}

/* Calibration::from_dark_white: each channel's gain, reference / (white - dark), in f32, so that
 * the white reading (less dark) becomes the reference; the calibration is then (dark, gain).
 * Returns 0, or k + 1 for the first channel k where the signal white - dark is not finite and
 * positive or dark is not finite (NoSignal), the reference is not finite and positive
 * (Reference), or the gain is not finite (OutOfRange); gain is then undefined from k on. */
static inline size_t sq_calibration_from_dark_white(size_t n, const float *dark, const float *white, const float *reference, float *gain) {
    SQ_FP_EXACT
    size_t k;
    for (k = 0; k < n; k++) {
        float signal = white[k] - dark[k], g;
        if (!(signal > 0.0f) || sq_is_infinite(signal) || sq_is_nan(dark[k]) || sq_is_infinite(dark[k])) {
            return k + 1;
        }
        if (!(reference[k] > 0.0f) || sq_is_infinite(reference[k])) {
            return k + 1;
        }
        g = reference[k] / signal;
        if (sq_is_nan(g) || sq_is_infinite(g)) {
            return k + 1;
        }
        gain[k] = g;
    }
    return 0;
}

/* Calibration::to_counts: the calibration (dark, gain) for counts of sample_unit each: dark
 * rounded (dark + 0.5, truncated) and gain / sample_unit in 16 fractional bits (times 65536,
 * + 0.5, truncated). Returns 0, or k + 1 for the first channel k where sample_unit is not finite
 * and positive, dark + 0.5 is outside 0..65536 or the gain outside 0..2^32 (OutOfRange); the
 * outputs are then undefined from k on. */
static inline size_t sq_calibration_to_counts(size_t n, const float *dark, const float *gain, float sample_unit, uint16_t *dark_counts, uint32_t *gain_q16) {
    SQ_FP_EXACT
    size_t k;
    for (k = 0; k < n; k++) {
        float d, g;
        if (!(sample_unit > 0.0f) || sq_is_infinite(sample_unit)) {
            return k + 1;
        }
        d = dark[k] + 0.5f;
        g = gain[k] / sample_unit * 65536.0f + 0.5f;
        if (!(d >= 0.0f && d < 65536.0f && g >= 0.0f && g < 4294967296.0f)) {
            return k + 1;
        }
        dark_counts[k] = (uint16_t)d;
        gain_q16[k] = (uint32_t)g;
    }
    return 0;
}

/* LuxScale::from_reading: the scale lux / y from the luminance y a set gives for a light of `lux`
 * lux. Returns 1, or 0 (InvalidLuxScale; lux_per_y untouched) where y or lux is not finite and
 * positive, or their quotient is not. */
static inline int sq_lux_scale_from_reading(float y, float lux, float *lux_per_y) {
    float s;
    if (!(y > 0.0f && lux > 0.0f) || sq_is_infinite(y) || sq_is_infinite(lux)) {
        return 0;
    }
    s = lux / y;
    if (!(s > 0.0f) || sq_is_infinite(s)) {
        return 0;
    }
    *lux_per_y = s;
    return 1;
}

/* w * q * 2^p rounded to the nearest integer (ties away from zero), exactly (the product of two
 * 24-bit significands is exact in 48 bits); 0 where w or q is not finite or the result reaches
 * 2^62. */
static inline int sq_fixed_point(float w, float q, int p, int64_t *out) {
    uint32_t bw = sq_f32_bits(w), bq = sq_f32_bits(q);
    int xw = (int)((bw >> 23) & 0xffu), xq = (int)((bq >> 23) & 0xffu), e;
    uint64_t mw = bw & 0x7fffffu, mq = bq & 0x7fffffu, m, magnitude;
    if (xw == 0xff || xq == 0xff) {
        return 0;
    }
    mw |= xw ? 0x800000u : 0u;
    mq |= xq ? 0x800000u : 0u;
    m = mw * mq;
    if (m == 0u) {
        *out = 0;
        return 1;
    }
    e = (xw ? xw - 150 : -149) + (xq ? xq - 150 : -149) + p;
    if (e >= 0) {
        if (e >= 14 || (m << e) >= (uint64_t)1 << 62) {
            return 0;
        }
        magnitude = m << e;
    } else if (-e >= 64) {
        magnitude = 0;
    } else {
        magnitude = (m + ((uint64_t)1 << (-e - 1))) >> -e;
    }
    *out = ((bw ^ bq) >> 31) ? -(int64_t)magnitude : (int64_t)magnitude;
    return 1;
}

/* IntegerSet::new for a set folded at run time (weights: 3 rows of n, for a display whose
 * 8-bit curve is q63, one of the header's sq_*8_q63 tables): each weight times sample_unit in
 * fixed point, V = round(w * sample_unit * 2^P) exactly (ties away from zero), into `fixed`
 * (3 rows of n), with the largest P from 46 down for which every channel's sum over u16 counts
 * stays inside int32 (the runtime's rule). Returns P, or 0 where the runtime gives an error:
 * a weight or sample_unit not finite, sample_unit not positive, weights too large
 * (IntegerRange), or a curve whose last threshold lies above the encoder's clamp
 * (IntegerTransfer; none of the header's curves). Integers only. */
static inline unsigned sq_integer_set_new(size_t n, const float *weights, float sample_unit, const uint64_t q63[256], int32_t *fixed) {
    int64_t margin = (int64_t)n * 65535, v, a, sum;
    uint32_t unit = sq_f32_bits(sample_unit);
    int p;
    size_t c, i;
    /* Finite and positive, from the bits: no sign, not zero, not Inf or NaN. */
    if ((unit >> 31) != 0u || unit == 0u || (unit >> 23) == 0xffu) {
        return 0;
    }
    for (p = 46; p > 16 && ((int64_t)1 << (p - 16)) > margin; p--) {
        int fits = 1;
        /* The encoder clamps a coarse sum below 1.0 to 1 - 2^(16 - P): the last threshold must
         * not lie above it. */
        if (q63[255] > (((uint64_t)1 << (p - 16)) - 1u) << (79 - p)) {
            return 0;
        }
        /* And the encoder settles a sum at or above 1.0 by the last stretch of 2^-12 in linear
         * light, which must hold no threshold. */
        if (q63[255] > (uint64_t)4095 << 51) {
            return 0;
        }
        for (c = 0; c < 3 && fits; c++) {
            sum = margin;
            for (i = 0; i < n && fits; i++) {
                if (!sq_fixed_point(weights[c * n + i], sample_unit, p, &v)) {
                    fits = 0;
                    break;
                }
                a = v >= 0 ? v / 65536 : -((-v + 65535) / 65536);
                sum += (a < 0 ? -a : a) * 65535;
                if (sum > INT32_MAX) {
                    fits = 0;
                    break;
                }
                fixed[c * n + i] = (int32_t)v;
            }
        }
        if (fits) {
            return (unsigned)p;
        }
    }
    return 0;
}

/* IntegerSet::linear_fixed of a set made by sq_integer_set_new: each channel's exact sum of the
 * fixed-point weights (3 rows of n) times the counts (2^P is 1.0). */
static inline void sq_integer_set_linear_fixed(size_t n, const int32_t *fixed, const uint16_t *counts, int64_t out[3]) {
    size_t c, i;
    for (c = 0; c < 3; c++) {
        int64_t f = 0;
        for (i = 0; i < n; i++) {
            f += (int64_t)fixed[c * n + i] * (int64_t)counts[i];
        }
        out[c] = f;
    }
}

/* IntegerSet::encode_u8 of a set made by sq_integer_set_new (P its return value, q63 the
 * display's curve it was made for): the exact sums rounded on the curve, integers only. */
static inline void sq_integer_set_encode_u8(size_t n, unsigned p, const int32_t *fixed, const uint64_t q63[256], const uint16_t *counts, uint8_t out[3]) {
    int64_t f[3];
    size_t c;
    sq_integer_set_linear_fixed(n, fixed, counts, f);
    for (c = 0; c < 3; c++) {
        if (f[c] <= 0) {
            out[c] = 0;
        } else if (f[c] >= (int64_t)1 << p) {
            out[c] = 255;
        } else {
            out[c] = sq_count64(q63, (uint64_t)f[c] << (63u - p));
        }
    }
}

/* uv_from_xyz: CIE 1960 (u, v) of XYZ; 0 (and out untouched) where NaN or infinite, or where
 * X + 15Y + 3Z is not positive. */
static inline int sq_uv_from_xyz(const float xyz[3], float out[2]) {
    SQ_FP_EXACT
    uint32_t e0 = (sq_f32_bits(xyz[0]) >> 23) & 0xffu;
    uint32_t e1 = (sq_f32_bits(xyz[1]) >> 23) & 0xffu;
    uint32_t e2 = (sq_f32_bits(xyz[2]) >> 23) & 0xffu;
    uint32_t e = e0 > e1 ? e0 : e1;
    float scale, x, y, z, d;
    e = e > e2 ? e : e2;
    if (e == 0xffu) {
        return 0;
    }
    scale = e > 127u + 100u ? sq_f32_from_bits((127u - 64u) << 23) : e < 127u - 60u ? sq_f32_from_bits((127u + 64u) << 23) : 1.0f;
    x = xyz[0] * scale;
    y = xyz[1] * scale;
    z = xyz[2] * scale;
    d = x + 15.0f * y + 3.0f * z;
    if (d <= 0.0f || sq_is_nan(d)) {
        return 0;
    }
    out[0] = 4.0f * x / d;
    out[1] = 6.0f * y / d;
    return 1;
}

"#;

const EPILOGUE: &str = r#"#ifdef __cplusplus
}
#endif

#if defined(__GNUC__) && !defined(__clang__) && !defined(SQ_NO_OPTIMIZE_PRAGMA)
#pragma GCC pop_options
#endif

#endif /* SPECTRAL_QUADRATURE_H */
"#;

fn opponent(o: &mut String, m: &Model) {
    let p = &m.opponent;
    o.push_str("/* The opponent space (tables::RANGE_NM, STEP_NM, XYZ_TO_AC1C2, AC1C2_TO_XYZ, EIGENVALUES, UNIT_SPECTRUM_Y). */\n");
    floats(o, "sq_range_nm", &p.range_nm);
    writeln!(o, "static const float sq_step_nm = {};", c_float(p.step_nm)).ok();
    matrix(o, "sq_xyz_to_ac1c2", &p.xyz_to_ac1c2);
    matrix(o, "sq_ac1c2_to_xyz", &p.ac1c2_to_xyz);
    floats(o, "sq_eigenvalues", &p.eigenvalues);
    writeln!(
        o,
        "static const float sq_unit_spectrum_y = {};",
        c_float(p.unit_spectrum_y)
    )
    .ok();
    writeln!(
        o,
        "/* tables::SCENE: the scene the tables were made for. */\nstatic const char sq_scene[] = {};",
        c_string(&m.provenance.scene)
    )
    .ok();
    o.push_str(
        "\n/* xyz_from_ac1c2 and ac1c2_from_xyz. */\n\
         static inline void sq_xyz_from_ac1c2(const float ac1c2[3], float out[3]) {\n    sq_mat3_vec(sq_ac1c2_to_xyz, ac1c2, out);\n}\n\n\
         static inline void sq_ac1c2_from_xyz(const float xyz[3], float out[3]) {\n    sq_mat3_vec(sq_xyz_to_ac1c2, xyz, out);\n}\n\n",
    );
    o.push_str(FOLD);
}

/// The 8-bit thresholds the scene's displays need (sRGB, and each power law's from the model),
/// and their forms on the integer path's 2⁶³ scale where an integer set encodes with them.
fn curves(o: &mut String, m: &Model) {
    let uses = |f: fn(&Transfer) -> bool| m.displays.iter().any(|d| f(&d.transfer));
    let integer_uses = |f: fn(&Transfer) -> bool| {
        m.integer
            .iter()
            .any(|i| f(&m.displays[m.folded[i.folded].display].transfer))
    };
    if uses(|t| matches!(t, Transfer::Srgb)) {
        let t = srgb_thresholds();
        o.push_str("/* srgb8_from_linear's table (the runtime's encode.rs): an f32 clamped to 2^-13..=1 is split by\n * its top bits into segments, each holding at most one code's threshold (the smallest f32 whose\n * exact sRGB encoding, in f64, times 255 rounds to the code); entry s is the code at segment s's\n * start, arranged so that adding the f32's position in the segment carries into the code at the\n * threshold. */\n");
        u32s(o, "sq_srgb8_segments", &srgb_segment_table(&t));
        o.push_str(
            "\n/* srgb8_from_linear: linear light to 8-bit sRGB, the exact curve rounded to nearest; NaN,\n * negative and tiny values give 0, values at or above 1 give 255. A clamp, a table look-up and\n * an addition. */\n\
             static inline uint8_t sq_srgb8_from_linear(float x) {\n    const float lo = sq_f32_from_bits(0x39000000u); /* 2^-13 */\n    uint32_t v;\n    x = x > lo ? x : lo;\n    x = x < 1.0f ? x : 1.0f;\n    v = sq_f32_bits(x) - 0x39000000u;\n    return (uint8_t)((sq_srgb8_segments[(v >> 16) & 2047u] + (v << 8)) >> 24);\n}\n\n",
        );
        if integer_uses(|t| matches!(t, Transfer::Srgb)) {
            u64s(o, "sq_srgb8_q63", &q63(&t));
            o.push('\n');
        }
    }
    if integer_uses(|t| matches!(t, Transfer::Linear)) {
        o.push_str(
            "/* The linear 8-bit thresholds (quantize_u8) on the integer path's 2^63 scale. */\n",
        );
        u64s(o, "sq_linear8_q63", &q63(&linear_thresholds()));
        o.push('\n');
    }
    for (k, e) in m.gamma_encoders.iter().enumerate() {
        writeln!(
            o,
            "/* The 8-bit encoder of the power law with gamma {} (tables::GAMMA_ENCODERS[{k}]): entry k is the\n * bits of the smallest f32 x with x^(1/gamma) * 255 >= k - 1/2 (in f64). */",
            c_float(e.gamma)
        )
        .ok();
        u32s(
            o,
            &std::format!("sq_gamma_encoders_{k}_thresholds"),
            &e.thresholds,
        );
        let bits = e.gamma.to_bits();
        let used = m.integer.iter().any(|i| {
            matches!(m.displays[m.folded[i.folded].display].transfer,
                Transfer::Gamma { gamma, .. } if gamma.to_bits() == bits)
        });
        if used {
            u64s(
                o,
                &std::format!("sq_gamma_encoders_{k}_q63"),
                &q63(&e.thresholds),
            );
        }
        o.push('\n');
    }
}

fn locus(o: &mut String, l: &super::model::Locus) {
    let k = l.nodes.len();
    writeln!(
        o,
        "/* tables::PLANCKIAN_LOCUS: {k} nodes of the Planckian locus for the {} observer, mired {:.3} to {:.3}. */",
        l.observer[0], l.mired_ends[0], l.mired_ends[1]
    )
    .ok();
    writeln!(o, "#define SQ_PLANCKIAN_LOCUS_LEN {k}").ok();
    let col = |f: &dyn Fn(&super::model::LocusNode) -> String| joined(&l.nodes, |n| f(n));
    writeln!(
        o,
        "static const float sq_planckian_locus_mired[{k}] = {{\n    {}\n}};",
        col(&|n| c_float(n.mired))
    )
    .ok();
    for (field, get) in [
        (
            "uv",
            (|n: &super::model::LocusNode| n.uv) as fn(&_) -> [f32; 2],
        ),
        ("tangent", |n| n.tangent),
        ("chord", |n| n.chord),
    ] {
        writeln!(
            o,
            "static const float sq_planckian_locus_{field}[{k}][2] = {{\n    {}\n}};",
            col(&|n| {
                let v = get(n);
                std::format!("{{ {}, {} }}", c_float(v[0]), c_float(v[1]))
            })
        )
        .ok();
    }
    writeln!(
        o,
        "static const int16_t sq_planckian_locus_unit_tangent_q14[{k}][2] = {{\n    {}\n}};",
        col(&|n| std::format!("{{ {}, {} }}", n.unit_tangent_q14[0], n.unit_tangent_q14[1]))
    )
    .ok();
    writeln!(
        o,
        "static const int32_t sq_planckian_locus_along_q30[{k}] = {{\n    {}\n}};",
        col(&|n| std::format!("{}", n.along_q30))
    )
    .ok();
    o.push_str(CCT);
}

const FOLD: &str = r#"/* WavelengthSet::fold: n weights per channel (3 rows) folded for a display's xyz_to_rgb and a
 * scale, in f32: out = scale * (xyz_to_rgb * AC1C2_TO_XYZ) * w, 3 rows of n. */
static inline void sq_fold(size_t n, const float *w, const float xyz_to_rgb[3][3], float scale, float *out) {
    SQ_FP_EXACT
    float m[3][3];
    size_t r, j, i;
    for (r = 0; r < 3; r++) {
        for (j = 0; j < 3; j++) {
            m[r][j] = xyz_to_rgb[r][0] * sq_ac1c2_to_xyz[0][j] + xyz_to_rgb[r][1] * sq_ac1c2_to_xyz[1][j] + xyz_to_rgb[r][2] * sq_ac1c2_to_xyz[2][j];
        }
    }
    for (r = 0; r < 3; r++) {
        for (i = 0; i < n; i++) {
            out[r * n + i] = scale * (m[r][0] * w[i] + m[r][1] * w[n + i] + m[r][2] * w[2 * n + i]);
        }
    }
}

"#;

/// A C string literal of `s`: printable ASCII as it is (`"` and `\` escaped), anything else
/// in octal escapes of its UTF-8 bytes.
fn c_string(s: &str) -> String {
    let mut o = String::from("\"");
    for b in s.bytes() {
        match b {
            b'"' | b'\\' => {
                o.push('\\');
                o.push(char::from(b));
            }
            0x20..=0x7e => o.push(char::from(b)),
            _ => o.push_str(&std::format!("\\{b:03o}")),
        }
    }
    o.push('"');
    o
}

const CCT: &str = r#"
/* PlanckianLocus::cct_from_uv's helpers: x to 16 fractional bits (0 where the result is not
 * below 1 or x is negative, NaN or infinite, which *ok says), and the clamp to -0.1..=1.1. */
static inline int32_t sq_q16(float x, int *ok) {
    uint32_t bits = sq_f32_bits(x), exponent, mantissa, shift;
    *ok = 1;
    if (bits == 0x80000000u) {
        return 0;
    }
    exponent = bits >> 23;
    if (exponent >= 127u) {
        *ok = 0;
        return 0;
    }
    mantissa = (bits & 0x007fffffu) | (exponent > 0u ? 0x00800000u : 0u);
    shift = 134u - exponent;
    if (shift > 24u) {
        return 0;
    }
    return (int32_t)((mantissa + (1u << (shift - 1u))) >> shift);
}

static inline float sq_extended(float x) {
    x = x > -0.1f ? x : -0.1f;
    return x < 1.1f ? x : 1.1f;
}

/* PlanckianLocus::cct_from_uv on tables::PLANCKIAN_LOCUS: 1 and the CCT and Duv of (u, v), or 0
 * (out untouched) beyond the table's ends, farther than 0.05 from the locus, or NaN. */
static inline int sq_planckian_locus_cct_from_uv(const float uv[2], sq_cct *out) {
    SQ_FP_EXACT
    const int k_last = SQ_PLANCKIAN_LOCUS_LEN - 1;
    int ok_u, ok_v, lo = 0, hi = k_last, i, step;
    int32_t pu = sq_q16(uv[0], &ok_u), pv = sq_q16(uv[1], &ok_v);
    float s_lo, s_hi, h, q[2], cu[3], cv[3], t, r[2] = { 0.0f, 0.0f }, d1[2] = { 0.0f, 0.0f };
    float distance, duv;
    if (SQ_PLANCKIAN_LOCUS_LEN < 2 || !ok_u || !ok_v) {
        return 0;
    }
    if (pu >= 39322 || pv >= 32768) {
        return 0;
    }
#define SQ_SIDE(i) (pu * (int32_t)sq_planckian_locus_unit_tangent_q14[i][0] + pv * (int32_t)sq_planckian_locus_unit_tangent_q14[i][1] - sq_planckian_locus_along_q30[i])
    if (SQ_SIDE(0) < 0) {
        hi = 1;
    } else if (SQ_SIDE(k_last) >= 0) {
        lo = k_last - 1;
    }
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (SQ_SIDE(mid) >= 0) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
#undef SQ_SIDE
    s_lo = (uv[0] - sq_planckian_locus_uv[lo][0]) * sq_planckian_locus_tangent[lo][0]
        + (uv[1] - sq_planckian_locus_uv[lo][1]) * sq_planckian_locus_tangent[lo][1];
    s_hi = (uv[0] - sq_planckian_locus_uv[hi][0]) * sq_planckian_locus_tangent[hi][0]
        + (uv[1] - sq_planckian_locus_uv[hi][1]) * sq_planckian_locus_tangent[hi][1];
    h = sq_planckian_locus_mired[hi] - sq_planckian_locus_mired[lo];
    q[0] = uv[0] - sq_planckian_locus_uv[lo][0];
    q[1] = uv[1] - sq_planckian_locus_uv[lo][1];
    for (i = 0; i < 2; i++) {
        float d = sq_planckian_locus_chord[lo][i];
        float ma = h * sq_planckian_locus_tangent[lo][i], mb = h * sq_planckian_locus_tangent[hi][i];
        float *c = i == 0 ? cu : cv;
        c[0] = ma;
        c[1] = 3.0f * d - 2.0f * ma - mb;
        c[2] = ma + mb - 2.0f * d;
    }
    t = sq_extended(s_lo / (s_lo - s_hi));
    for (step = 0; step < 2; step++) {
        float d2[2], f, df, next, dt;
        r[0] = q[0] - ((cu[2] * t + cu[1]) * t + cu[0]) * t;
        r[1] = q[1] - ((cv[2] * t + cv[1]) * t + cv[0]) * t;
        d1[0] = (3.0f * cu[2] * t + 2.0f * cu[1]) * t + cu[0];
        d1[1] = (3.0f * cv[2] * t + 2.0f * cv[1]) * t + cv[0];
        d2[0] = 6.0f * cu[2] * t + 2.0f * cu[1];
        d2[1] = 6.0f * cv[2] * t + 2.0f * cv[1];
        f = r[0] * d1[0] + r[1] * d1[1];
        df = r[0] * d2[0] + r[1] * d2[1] - (d1[0] * d1[0] + d1[1] * d1[1]);
        next = sq_extended(t - f / df);
        dt = next - t;
        r[0] = r[0] - dt * d1[0];
        r[1] = r[1] - dt * d1[1];
        t = next;
        if ((dt < 0.0f ? -dt : dt) < 3e-4f) {
            break;
        }
    }
    distance = sqrtf(r[0] * r[0] + r[1] * r[1]);
    duv = r[1] * d1[0] - r[0] * d1[1] < 0.0f ? -distance : distance;
    if ((lo == 0 && t < 0.0f) || (hi == k_last && t > 1.0f) || sq_is_nan(duv) || (duv < 0.0f ? -duv : duv) > 0.05f) {
        return 0;
    }
    out->kelvin = 1e6f / (sq_planckian_locus_mired[lo] + t * h);
    out->duv = duv;
    return 1;
}

/* PlanckianLocus::cct on tables::PLANCKIAN_LOCUS: uv_from_xyz, then cct_from_uv. */
static inline int sq_planckian_locus_cct(const float xyz[3], sq_cct *out) {
    float uv[2];
    if (!sq_uv_from_xyz(xyz, uv)) {
        return 0;
    }
    return sq_planckian_locus_cct_from_uv(uv, out);
}

"#;

fn extras(o: &mut String, m: &Model) {
    if let Some(s) = &m.sensitivities {
        o.push_str("/* tables::GRID_NM and SENSITIVITIES: the grid and [a, c1, c2] at each of its wavelengths. */\n");
        writeln!(o, "#define SQ_GRID_LEN {}", s.grid_nm.len()).ok();
        floats(o, "sq_grid_nm", &s.grid_nm);
        writeln!(
            o,
            "static const float sq_sensitivities[{}][3] = {{\n    {}\n}};\n",
            s.rows.len(),
            joined(&s.rows, |r| std::format!(
                "{{ {}, {}, {} }}",
                c_float(r[0]),
                c_float(r[1]),
                c_float(r[2])
            ))
        )
        .ok();
    }
    if let Some(r) = &m.rules {
        o.push_str("/* tables::A_RULES, C1_RULES and C2_RULES: each channel's Gauss rules of orders 1..=MAX_ORDER (nodes\n * and weights, none where the rule is not defined), as sq_<channel>_rules_order<k>_nodes_nm and\n * _weights. */\n");
        writeln!(o, "#define SQ_MAX_ORDER {}", r.max_order).ok();
        for (c, rules) in r.channels.iter().enumerate() {
            let channel = lower(super::model::CHANNEL_NAMES[c]);
            for rule in rules {
                if rule.nodes_nm.is_empty() {
                    writeln!(
                        o,
                        "/* {} rule of order {}: {} */",
                        super::model::CHANNEL_NAMES[c],
                        rule.order,
                        rule.status
                    )
                    .ok();
                    continue;
                }
                floats(
                    o,
                    &std::format!("sq_{channel}_rules_order{}_nodes_nm", rule.order),
                    &rule.nodes_nm,
                );
                floats(
                    o,
                    &std::format!("sq_{channel}_rules_order{}_weights", rule.order),
                    &rule.weights,
                );
            }
        }
        o.push('\n');
    }
}

fn samples_doc(s: &Samples) -> String {
    match s {
        Samples::Radiance => "radiances".into(),
        Samples::Reflectance { light } => std::format!("reflectances under {light}"),
        Samples::Readings { sensor, light } => match light {
            Some(l) => std::format!("{sensor} readings, fitted under {l}"),
            None => std::format!("{sensor} readings"),
        },
    }
}

fn set(o: &mut String, module: &str, s: &super::model::Set) {
    let n = s.len();
    let name = std::format!("sq_{module}_{}", lower(&s.name));
    writeln!(
        o,
        "/* tables::{module}::{}: {} ({n} samples of {}). */",
        s.name,
        s.doc.replace("*/", "* /"),
        samples_doc(&s.samples)
    )
    .ok();
    writeln!(o, "#define {}_LEN {n}", name.to_ascii_uppercase()).ok();
    floats(o, &std::format!("{name}_wavelengths_nm"), &s.wavelengths_nm);
    rows3(o, &std::format!("{name}_weights"), &s.weights);
    writeln!(
        o,
        "\n/* WavelengthSet::ac1c2 and xyz. */\n\
         static inline void {name}_ac1c2(const float samples[{n}], float out[3]) {{\n    sq_mat_vec({n}, &{name}_weights[0][0], samples, out);\n}}\n\n\
         static inline void {name}_xyz(const float samples[{n}], float out[3]) {{\n    {name}_ac1c2(samples, out);\n    sq_xyz_from_ac1c2(out, out);\n}}\n\n\
         /* WavelengthSet::fold: the weights folded for a display (its xyz_to_rgb) and a scale, in f32;\n * sq_mat_vec({n}, &out[0][0], samples, rgb) is then FoldedSet::linear_rgb. */\n\
         static inline void {name}_fold(const float xyz_to_rgb[3][3], float scale, float out[3][{n}]) {{\n    sq_fold({n}, &{name}_weights[0][0], xyz_to_rgb, scale, &out[0][0]);\n}}\n"
    )
    .ok();
}

/// The display's 8-bit encoding of a colour without NaN, per channel: the C expression for
/// channel `c` of `m`.
fn encode8_expr(m: &Model, d: &Display, arg: &str) -> String {
    match d.transfer {
        Transfer::Srgb => std::format!("sq_srgb8_from_linear({arg})"),
        Transfer::Linear => std::format!("sq_quantize_u8({arg})"),
        Transfer::Gamma { gamma, .. } => match m
            .gamma_encoders
            .iter()
            .position(|e| e.gamma.to_bits() == gamma.to_bits())
        {
            Some(k) => std::format!("sq_encode8(sq_gamma_encoders_{k}_thresholds, {arg})"),
            None => std::format!("sq_quantize_u8(sq_gamma_f32({}, {arg}))", c_float(gamma)),
        },
    }
}

fn encode16_expr(d: &Display, arg: &str) -> String {
    match d.transfer {
        Transfer::Srgb => std::format!("sq_quantize_u16(sq_srgb_f32({arg}))"),
        Transfer::Linear => std::format!("sq_quantize_u16({arg})"),
        Transfer::Gamma { gamma, .. } => {
            std::format!("sq_quantize_u16(sq_gamma_f32({}, {arg}))", c_float(gamma))
        }
    }
}

fn display(o: &mut String, m: &Model, d: &Display) {
    let name = std::format!("sq_displays_{}", lower(&d.name));
    let transfer = match d.transfer {
        Transfer::Linear => "linear".to_string(),
        Transfer::Srgb => "the sRGB curve".to_string(),
        Transfer::Gamma { given, .. } => std::format!("a power law, gamma {given}"),
    };
    writeln!(
        o,
        "/* tables::displays::{} ({}): {}; {transfer}. */",
        d.name,
        d.label,
        d.doc.replace("*/", "* /")
    )
    .ok();
    writeln!(
        o,
        "static const float {name}_primaries_xy[3][2] = {{ {} }};",
        joined(&d.primaries_xy, |p| std::format!(
            "{{ {}, {} }}",
            c_float(p[0]),
            c_float(p[1])
        ))
    )
    .ok();
    writeln!(
        o,
        "static const char {name}_name[] = {};",
        c_string(&d.label)
    )
    .ok();
    floats(o, &std::format!("{name}_white_xy"), &d.white_xy);
    matrix(o, &std::format!("{name}_rgb_to_xyz"), &d.rgb_to_xyz);
    matrix(o, &std::format!("{name}_xyz_to_rgb"), &d.xyz_to_rgb);
    floats(o, &std::format!("{name}_a_from_rgb"), &d.a_from_rgb);
    let e8 = |c: usize| encode8_expr(m, d, &std::format!("g[{c}]"));
    let e16 = |c: usize| encode16_expr(d, &std::format!("g[{c}]"));
    writeln!(
        o,
        "\n/* Display::linear_from_xyz and xyz_from_linear. */\n\
         static inline void {name}_linear_from_xyz(const float xyz[3], float out[3]) {{\n    sq_mat3_vec({name}_xyz_to_rgb, xyz, out);\n}}\n\n\
         static inline void {name}_xyz_from_linear(const float rgb[3], float out[3]) {{\n    sq_mat3_vec({name}_rgb_to_xyz, rgb, out);\n}}\n\n\
         /* Display::map_gamut: into 0..=1 per channel; NaN anywhere gives black. */\n\
         static inline void {name}_map_gamut(sq_gamut_mapping mapping, const float rgb[3], float out[3]) {{\n    sq_map_gamut({name}_a_from_rgb, mapping, rgb, out);\n}}\n\n\
         /* Display::encode_u8: gamut-mapped and encoded to 8 bits, the exact curve rounded to nearest\n * (sRGB and the baked power laws); NaN anywhere gives black. */\n\
         static inline void {name}_encode_u8(sq_gamut_mapping mapping, const float rgb[3], uint8_t out[3]) {{\n    float g[3];\n    sq_map_gamut({name}_a_from_rgb, mapping, rgb, g);\n    out[0] = {};\n    out[1] = {};\n    out[2] = {};\n}}\n\n\
         /* Display::encode_u16: gamut-mapped and encoded to 16 bits (the curve in f32 with powf). */\n\
         static inline void {name}_encode_u16(sq_gamut_mapping mapping, const float rgb[3], uint16_t out[3]) {{\n    float g[3];\n    sq_map_gamut({name}_a_from_rgb, mapping, rgb, g);\n    out[0] = {};\n    out[1] = {};\n    out[2] = {};\n}}\n",
        e8(0),
        e8(1),
        e8(2),
        e16(0),
        e16(1),
        e16(2)
    )
    .ok();
}

fn folded(o: &mut String, m: &Model, f: &super::model::Folded) {
    let set = &m.colour_sets[f.set];
    let d = &m.displays[f.display];
    let n = set.len();
    let rust = m.folded_name(f);
    let name = std::format!("sq_folded_{}", lower(&rust));
    let display = std::format!("sq_displays_{}", lower(&d.name));
    writeln!(
        o,
        "/* tables::folded::{rust}: {} folded for {} ({n} samples of {}). */",
        set.name,
        d.label,
        samples_doc(&set.samples)
    )
    .ok();
    writeln!(o, "#define {}_LEN {n}", name.to_ascii_uppercase()).ok();
    floats(
        o,
        &std::format!("{name}_wavelengths_nm"),
        &set.wavelengths_nm,
    );
    rows3(o, &std::format!("{name}_weights"), &f.weights);
    writeln!(
        o,
        "\n/* FoldedSet::linear_rgb, linear_rgb_under (a light's samples at the nodes, times a\n * reflectance's), encode_u8 and encode_u16. */\n\
         static inline void {name}_linear_rgb(const float samples[{n}], float out[3]) {{\n    sq_mat_vec({n}, &{name}_weights[0][0], samples, out);\n}}\n\n\
         static inline void {name}_linear_rgb_under(const float light[{n}], const float reflectance[{n}], float out[3]) {{\n    SQ_FP_EXACT\n    float s[{n}];\n    size_t i;\n    for (i = 0; i < {n}; i++) {{\n        s[i] = reflectance[i] * light[i];\n    }}\n    {name}_linear_rgb(s, out);\n}}\n\n\
         static inline void {name}_encode_u8(sq_gamut_mapping mapping, const float samples[{n}], uint8_t out[3]) {{\n    float rgb[3];\n    {name}_linear_rgb(samples, rgb);\n    {display}_encode_u8(mapping, rgb, out);\n}}\n\n\
         static inline void {name}_encode_u16(sq_gamut_mapping mapping, const float samples[{n}], uint16_t out[3]) {{\n    float rgb[3];\n    {name}_linear_rgb(samples, rgb);\n    {display}_encode_u16(mapping, rgb, out);\n}}\n"
    )
    .ok();
}

fn group(o: &mut String, m: &Model, g: &super::model::Group) {
    let n = g.wavelengths_nm.len();
    let l = g.lights.len();
    let base = std::format!("sq_groups_{}", lower(&g.name));
    for (k, d) in m.displays.iter().enumerate() {
        let name = std::format!("{base}_{}", lower(&d.name));
        let display = std::format!("sq_displays_{}", lower(&d.name));
        writeln!(
            o,
            "/* tables::groups::{}_{}: the light group {} ({} lights: {}; {n} shared nodes) folded for {}.\n * A pixel's samples are the {l} lights' in turn: light k's at samples[k * {n} + i]. */",
            g.name,
            d.name,
            g.name,
            l,
            g.lights.join(", "),
            d.label
        )
        .ok();
        writeln!(o, "#define {}_LEN {n}", name.to_ascii_uppercase()).ok();
        writeln!(o, "#define {}_LIGHTS {l}", name.to_ascii_uppercase()).ok();
        floats(o, &std::format!("{name}_wavelengths_nm"), &g.wavelengths_nm);
        writeln!(o, "static const float {name}_weights[{l}][3][{n}] = {{").ok();
        for member in &g.folded[k] {
            o.push_str("    {\n");
            for row in member {
                writeln!(o, "        {{ {} }},", joined(row, |&x| c_float(x))).ok();
            }
            o.push_str("    },\n");
        }
        o.push_str("};\n");
        writeln!(
            o,
            "\n/* LightGroupSet::linear_rgb: each light's product, summed light by light; encode_u8 and\n * encode_u16. */\n\
             static inline void {name}_linear_rgb(const float samples[{ln}], float out[3]) {{\n    SQ_FP_EXACT\n    float c[3];\n    size_t k;\n    sq_mat_vec({n}, &{name}_weights[0][0][0], samples, out);\n    for (k = 1; k < {l}; k++) {{\n        sq_mat_vec({n}, &{name}_weights[k][0][0], samples + k * {n}, c);\n        out[0] = out[0] + c[0];\n        out[1] = out[1] + c[1];\n        out[2] = out[2] + c[2];\n    }}\n}}\n\n\
             static inline void {name}_encode_u8(sq_gamut_mapping mapping, const float samples[{ln}], uint8_t out[3]) {{\n    float rgb[3];\n    {name}_linear_rgb(samples, rgb);\n    {display}_encode_u8(mapping, rgb, out);\n}}\n\n\
             static inline void {name}_encode_u16(sq_gamut_mapping mapping, const float samples[{ln}], uint16_t out[3]) {{\n    float rgb[3];\n    {name}_linear_rgb(samples, rgb);\n    {display}_encode_u16(mapping, rgb, out);\n}}\n",
            ln = l * n
        )
        .ok();
    }
}

fn upsampling(o: &mut String, u: &super::model::Upsampling) {
    let rust = u.name();
    let name = std::format!("sq_upsampling_{}", lower(&rust));
    let (n, g) = (u.n, u.grid);
    writeln!(
        o,
        "/* tables::upsampling::{rust}: RGB of {} to {}'s {n} node values (reflectances under {}),\n * a {g}^3 grid of codes in 65535ths, interpolated on the Kuhn tetrahedra. */",
        u.display_label, u.set, u.light
    )
    .ok();
    writeln!(o, "#define {}_GRID {g}", name.to_ascii_uppercase()).ok();
    writeln!(o, "#define {}_LEN {n}", name.to_ascii_uppercase()).ok();
    writeln!(
        o,
        "static const uint16_t {name}_table[{}][{n}] = {{\n    {}\n}};",
        u.codes.len(),
        joined(&u.codes, |c| std::format!(
            "{{ {} }}",
            c.iter()
                .map(|v| v.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ))
    )
    .ok();
    writeln!(
        o,
        "/* The round trip's data (RoundTrip: weights, rgb_to_xyz, edge_cells). */"
    )
    .ok();
    rows3(o, &std::format!("{name}_round_trip_weights"), &u.encoding);
    matrix(
        o,
        &std::format!("{name}_round_trip_rgb_to_xyz"),
        &u.rgb_to_xyz,
    );
    u32s(
        o,
        &std::format!("{name}_round_trip_edge_cells"),
        &u.edge_cells,
    );
    floats(
        o,
        &std::format!("{name}_round_trip_rounding"),
        &round_trip_rounding(&u.encoding),
    );
    writeln!(
        o,
        "\n/* Upsampling::interpolate: the grid's codes interpolated at rgb clamped to 0..=1 (NaN to 0),\n * each value clamped to 0..=1. */\n\
         static inline void {name}_interpolate(const float rgb[3], float out[{n}]) {{\n    float p[3];\n    size_t cell;\n    sq_upsampling_interpolate_at({g}, {n}, &{name}_table[0][0], rgb, out, p, &cell);\n}}\n\n\
         /* Upsampling::reflectance: interpolate, then on the cells where interpolation can miss the\n * colour (the edge cells) the round trip's correction toward node values that give it back. */\n\
         static inline void {name}_reflectance(const float rgb[3], float out[{n}]) {{\n    float p[3];\n    size_t cell;\n    sq_upsampling_interpolate_at({g}, {n}, &{name}_table[0][0], rgb, out, p, &cell);\n    if (sq_round_trip_is_edge({name}_round_trip_edge_cells, {edges}, cell)) {{\n        sq_round_trip_correct({n}, &{name}_round_trip_weights[0][0], {name}_round_trip_rgb_to_xyz, {name}_round_trip_rounding, p, out);\n    }}\n}}\n",
        edges = u.edge_cells.len()
    )
    .ok();
}

/// The round trip's `rounding`, as the runtime's `RoundTrip::new` computes it in f32: half a
/// code of 65535 of each row's absolute sum, at least the smallest normal f32.
fn round_trip_rounding(w: &[Vec<f32>; 3]) -> [f32; 3] {
    let mut out = [0.0f32; 3];
    for (o, row) in out.iter_mut().zip(w) {
        let mut sum = 0.0f32;
        for x in row {
            sum += x.abs();
        }
        let r = sum * (0.5 / 65535.0);
        *o = if r > f32::MIN_POSITIVE {
            r
        } else {
            f32::MIN_POSITIVE
        };
    }
    out
}

const UPSAMPLING_HELPER: &str = r#"/* Upsampling::interpolate for a grid of g points per axis and n values per point; p gets rgb
 * clamped to 0..=1 and *cell_index the cell's index (what the round trip reads). */
static inline void sq_upsampling_interpolate_at(size_t g, size_t n, const uint16_t *table, const float rgb[3], float *out, float p[3], size_t *cell_index) {
    SQ_FP_EXACT
    float cells = (float)(g - 1), frac[3], w0, w1, w2, w3, scale = 1.0f / 65535.0f;
    size_t cell[3], c, i, a, b, cc, base, i1, i2, i3, strides[3];
    const uint16_t *v0, *v1, *v2, *v3;
    strides[0] = g * g;
    strides[1] = g;
    strides[2] = 1;
    for (c = 0; c < 3; c++) {
        float v = rgb[c] > 0.0f ? (rgb[c] < 1.0f ? rgb[c] : 1.0f) : 0.0f;
        float x = v * cells;
        p[c] = v;
        size_t k = (size_t)x;
        if (k > g - 2) {
            k = g - 2;
        }
        cell[c] = k;
        frac[c] = x - (float)k;
    }
    if (frac[0] >= frac[1]) {
        if (frac[1] >= frac[2]) {
            a = 0; b = 1; cc = 2;
        } else if (frac[0] >= frac[2]) {
            a = 0; b = 2; cc = 1;
        } else {
            a = 2; b = 0; cc = 1;
        }
    } else if (frac[0] >= frac[2]) {
        a = 1; b = 0; cc = 2;
    } else if (frac[1] >= frac[2]) {
        a = 1; b = 2; cc = 0;
    } else {
        a = 2; b = 1; cc = 0;
    }
    *cell_index = (cell[0] * (g - 1) + cell[1]) * (g - 1) + cell[2];
    base = (cell[0] * g + cell[1]) * g + cell[2];
    i1 = base + strides[a];
    i2 = i1 + strides[b];
    i3 = i2 + strides[cc];
    w0 = 1.0f - frac[a];
    w1 = frac[a] - frac[b];
    w2 = frac[b] - frac[cc];
    w3 = frac[cc];
    v0 = table + base * n;
    v1 = table + i1 * n;
    v2 = table + i2 * n;
    v3 = table + i3 * n;
    for (i = 0; i < n; i++) {
        float acc = w0 * (float)v0[i] + w1 * (float)v1[i] + w2 * (float)v2[i] + w3 * (float)v3[i];
        float r = acc * scale;
        out[i] = r > 0.0f ? (r < 1.0f ? r : 1.0f) : (r < 0.0f ? 0.0f : r);
    }
}

"#;

/// The round trip's correction (the runtime's `upsample/round_trip.rs`), in the runtime's
/// order of operations: written once, before the first map, for maps of at most
/// `SQ_UPSAMPLING_MAX_LEN` values.
const ROUND_TRIP_HELPER: &str = include_str!("c_round_trip.h");

fn sensor(o: &mut String, s: &super::model::Sensor) {
    let name = std::format!("sq_sensors_{}", lower(&s.name));
    let n = s.white.len();
    writeln!(
        o,
        "/* tables::sensors::{}_WHITE: what the golden {} reads on a perfect white. */",
        s.name, s.name
    )
    .ok();
    floats(o, &std::format!("{name}_white"), &s.white);
    if let Some(c) = &s.calibration {
        writeln!(
            o,
            "/* tables::sensors::{}_CALIBRATION: each channel's dark offset and gain, fitted. */",
            s.name
        )
        .ok();
        floats(o, &std::format!("{name}_calibration_dark"), &c.dark);
        floats(o, &std::format!("{name}_calibration_gain"), &c.gain);
        writeln!(
            o,
            "\n/* Calibration::apply: (reading - dark) * gain per channel. */\n\
             static inline void {name}_calibration_apply(const float readings[{n}], float out[{n}]) {{\n    sq_calibration_apply({n}, {name}_calibration_dark, {name}_calibration_gain, readings, out);\n}}"
        )
        .ok();
    }
    o.push('\n');
}

fn integer(o: &mut String, m: &Model, i: &super::model::Integer) {
    let f = &m.folded[i.folded];
    let d = &m.displays[f.display];
    let rust = m.folded_name(f);
    let name = std::format!("sq_integer_{}", lower(&rust));
    let n = f.weights[0].len();
    let q63 = match d.transfer {
        Transfer::Srgb => "sq_srgb8_q63".to_string(),
        Transfer::Linear => "sq_linear8_q63".to_string(),
        Transfer::Gamma { gamma, .. } => match m
            .gamma_encoders
            .iter()
            .position(|e| e.gamma.to_bits() == gamma.to_bits())
        {
            Some(k) => std::format!("sq_gamma_encoders_{k}_q63"),
            // The runtime refuses such a set when it compiles (Error::IntegerTransfer).
            None => return,
        },
    };
    let Some((p, weights)) = integer_weights(&f.weights, i.sample_unit) else {
        // Nor one whose sums would not fit (Error::IntegerRange).
        return;
    };
    writeln!(
        o,
        "/* tables::integer::{rust}: folded::{rust} in fixed point for u16 counts (one count is {} of a\n * sample): weights with {p} fractional bits. */",
        c_float(i.sample_unit)
    )
    .ok();
    writeln!(o, "#define {}_LEN {n}", name.to_ascii_uppercase()).ok();
    writeln!(o, "#define {}_FRAC_BITS {p}", name.to_ascii_uppercase()).ok();
    writeln!(
        o,
        "static const float {name}_sample_unit = {};",
        c_float(i.sample_unit)
    )
    .ok();
    writeln!(o, "static const int32_t {name}_weights[3][{n}] = {{").ok();
    for row in &weights {
        writeln!(o, "    {{ {} }},", joined(row, |w| std::format!("{w}"))).ok();
    }
    o.push_str("};\n");
    // Each weight as its high and low 16 bits (w = high · 2¹⁶ + low, high = w >> 16 as the
    // runtime's coarse weights): the sums need 16-bit products only, no 64-bit multiply (a
    // library call on an Armv6-M), and IntegerSet::new bounded the high sum inside int32.
    writeln!(o, "static const int16_t {name}_weights_high[3][{n}] = {{").ok();
    for row in &weights {
        writeln!(
            o,
            "    {{ {} }},",
            joined(row, |w| std::format!("{}", w >> 16))
        )
        .ok();
    }
    o.push_str("};\n");
    writeln!(o, "static const uint16_t {name}_weights_low[3][{n}] = {{").ok();
    for row in &weights {
        writeln!(
            o,
            "    {{ {} }},",
            joined(row, |w| std::format!("{}", w & 0xffff))
        )
        .ok();
    }
    o.push_str("};\n");
    writeln!(
        o,
        "\n/* IntegerSet::linear_fixed: each channel's exact sum of weights times counts (2^{p} is 1.0):\n * the high halves' sum times 2^16 plus the low halves'. */\n\
         static inline void {name}_linear_fixed(const uint16_t counts[{n}], int64_t out[3]) {{\n    size_t c, i;\n    for (c = 0; c < 3; c++) {{\n        int32_t high = 0;\n        uint64_t low = 0;\n        for (i = 0; i < {n}; i++) {{\n            high += (int32_t){name}_weights_high[c][i] * (int32_t)counts[i];\n            low += (uint32_t){name}_weights_low[c][i] * (uint32_t)counts[i];\n        }}\n        out[c] = (int64_t)high * 65536 + (int64_t)low;\n    }}\n}}\n\n\
         /* IntegerSet::encode_u8: counts to the display's 8-bit code, the exact sum rounded on the\n * display's curve, integers only. */\n\
         static inline void {name}_encode_u8(const uint16_t counts[{n}], uint8_t out[3]) {{\n    int64_t f[3];\n    size_t c;\n    {name}_linear_fixed(counts, f);\n    for (c = 0; c < 3; c++) {{\n        if (f[c] <= 0) {{\n            out[c] = 0;\n        }} else if (f[c] >= (int64_t)1 << {p}) {{\n            out[c] = 255;\n        }} else {{\n            out[c] = sq_count64({q63}, (uint64_t)f[c] << {shift});\n        }}\n    }}\n}}\n\n\
         /* IntegerSet::counts_as_f32: each count times the sample unit. */\n\
         static inline void {name}_counts_as_f32(const uint16_t counts[{n}], float out[{n}]) {{\n    SQ_FP_EXACT\n    size_t i;\n    for (i = 0; i < {n}; i++) {{\n        out[i] = (float)counts[i] * {name}_sample_unit;\n    }}\n}}\n",
        shift = 63 - p
    )
    .ok();
}

/// `(k − ½) / 255` decoded with the exact sRGB curve, in f64, as the runtime's `encode.rs`
/// computes it (the fifth root by Newton's method), so that the thresholds are its bits.
fn srgb_boundary(k: usize) -> f64 {
    let v = (k as f64 - 0.5) / 255.0;
    if v <= 0.040_45 {
        v / 12.92
    } else {
        let y = (v + 0.055) / 1.055;
        let a = y * y;
        let mut r = 1.0f64;
        for _ in 0..64 {
            let r4 = r * r * r * r;
            r = 0.8 * r + a / (5.0 * r4);
        }
        a * r
    }
}

/// The runtime's `encode::THRESHOLDS`.
fn srgb_thresholds() -> [u32; 256] {
    let mut t = [0u32; 256];
    for (k, slot) in t.iter_mut().enumerate().skip(1) {
        *slot = ceil_f32_bits(srgb_boundary(k));
    }
    t
}

/// The runtime's `encode::SEGMENT_TABLE` from its thresholds: 2 048 segments of 2¹⁶ f32 from
/// 2⁻¹³ (the last ones repeating the segment of exactly 1.0), each entry the code at the
/// segment's start, minus the segment's index, plus the carry that the position of the
/// segment's threshold, if any, brings in (all in the top byte, mod 2³²).
fn srgb_segment_table(t: &[u32; 256]) -> Vec<u32> {
    const LO_BITS: u32 = (127 - 13) << 23;
    const SEGMENTS: usize = 13 * 128 + 1;
    let mut table = Vec::with_capacity(2048);
    let mut code = 0usize;
    for s in 0..2048usize {
        let seg = s.min(SEGMENTS - 1);
        let start = LO_BITS + ((seg as u32) << 16);
        let end = start + 0xFFFF;
        while code < 255 && t[code + 1] <= start {
            code += 1;
        }
        let threshold = if code < 255 && t[code + 1] <= end {
            t[code + 1] - start
        } else {
            1 << 16
        };
        let carry_in = (0x1_0000 - threshold) & 0xFFFF;
        table.push(
            ((code as u32) << 24)
                .wrapping_add(carry_in << 8)
                .wrapping_sub((s as u32) << 24),
        );
    }
    table
}

/// The thresholds of `quantize_u8` on 0..=1 (the runtime's `integer::curve::linear_thresholds`).
fn linear_thresholds() -> [u32; 256] {
    let mut t = [0u32; 256];
    for (k, slot) in t.iter_mut().enumerate().skip(1) {
        let (mut lo, mut hi) = (0u32, 0x3f80_0000u32);
        while lo < hi {
            let mid = lo + (hi - lo) / 2;
            let x = f32::from_bits(mid);
            if (x * 255.0 + 0.5) as u8 as usize >= k {
                hi = mid;
            } else {
                lo = mid + 1;
            }
        }
        *slot = lo;
    }
    t
}

/// Each threshold's f32 rounded up on the 2^63 scale (the runtime's `IntegerCurve::q63`);
/// entry 0 is 0.
fn q63(t: &[u32; 256]) -> Vec<u64> {
    t.iter()
        .enumerate()
        .map(|(k, &b)| if k == 0 { 0 } else { scaled_ceil(b, 63) })
        .collect()
}

fn scaled_ceil(bits: u32, scale: i32) -> u64 {
    let exp = ((bits >> 23) & 0xff) as i32;
    let frac = u64::from(bits & 0x7f_ffff);
    let (m, e) = if exp == 0 {
        (frac, 1)
    } else {
        (frac | 0x80_0000, exp)
    };
    if m == 0 {
        return 0;
    }
    let s = e - 150 + scale;
    if s >= 0 {
        m << s
    } else if -s >= 64 {
        1
    } else {
        let r = -s as u32;
        (m >> r) + u64::from(m & ((1u64 << r) - 1) != 0)
    }
}

/// `(negative, significand, exponent)` of a finite f32.
fn decompose(x: f32) -> Option<(bool, u64, i32)> {
    let bits = x.to_bits();
    let exp = ((bits >> 23) & 0xff) as i32;
    let frac = u64::from(bits & 0x7f_ffff);
    let negative = bits >> 31 == 1;
    match exp {
        0xff => None,
        0 => Some((negative, frac, -149)),
        _ => Some((negative, frac | 0x80_0000, exp - 150)),
    }
}

/// `w · q` on `p` fractional bits, rounded once (the runtime's `integer::fixed_point`).
fn fixed_point(w: f32, q: f32, p: i32) -> Option<i64> {
    let (nw, mw, ew) = decompose(w)?;
    let (nq, mq, eq) = decompose(q)?;
    let m = mw * mq;
    if m == 0 {
        return Some(0);
    }
    let e = ew + eq + p;
    let magnitude = if e >= 0 {
        if e >= 14 || (m << e) >= 1 << 62 {
            return None;
        }
        m << e
    } else if -e >= 64 {
        0
    } else {
        let r = -e as u32;
        (m + (1u64 << (r - 1))) >> r
    };
    let v = magnitude as i64;
    Some(if nw != nq { -v } else { v })
}

/// The fractional bits and fixed-point weights `IntegerSet::new` chooses: the largest P from 46
/// down whose coarse sums fit i32 with the margin (the runtime's `set.rs` and `split_at`).
fn integer_weights(w: &[Vec<f32>; 3], q: f32) -> Option<(i32, [Vec<i32>; 3])> {
    let n = w[0].len();
    let margin = n as i64 * 65535;
    let mut p = 46;
    while p > 16 && (1i64 << (p - 16)) > margin {
        let split = || -> Option<[Vec<i32>; 3]> {
            let mut full: [Vec<i32>; 3] = Default::default();
            for c in 0..3 {
                let mut sum = margin;
                for &x in &w[c] {
                    let v = fixed_point(x, q, p)?;
                    let a = v >> 16;
                    sum += a.abs() * 65535;
                    if sum > i64::from(i32::MAX) {
                        return None;
                    }
                    full[c].push(v as i32);
                }
            }
            Some(full)
        };
        if let Some(full) = split() {
            return Some((p, full));
        }
        p -= 1;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sRGB thresholds are increasing, inside 2⁻¹³..=1, and the boundary of code 128 is
    /// sRGB 127.5/255 decoded: 0.21223 (IEC 61966-2-1 by hand).
    #[test]
    fn srgb_thresholds_are_the_curve() {
        let t = srgb_thresholds();
        assert!(t.windows(2).skip(1).all(|w| w[0] < w[1]));
        assert!(t[1] > (127 - 13) << 23 && t[255] <= 0x3f80_0000);
        let x = f64::from(f32::from_bits(t[128]));
        let exact = ((127.5 / 255.0 + 0.055) / 1.055f64).powf(2.4);
        assert!((x - exact).abs() < 1e-7, "{x} {exact}");
    }

    /// Fixed point of 0.5 · 1.0 at 20 bits is 2¹⁹; a weight whose product does not fit is
    /// refused.
    #[test]
    fn fixed_point_scales_exactly() {
        assert_eq!(fixed_point(0.5, 1.0, 20), Some(1 << 19));
        assert_eq!(fixed_point(-0.5, 1.0, 20), Some(-(1 << 19)));
        assert_eq!(fixed_point(f32::MAX, 1.0, 20), None);
        assert_eq!(scaled_ceil(0x3f80_0000, 63), 1 << 63);
    }
}
