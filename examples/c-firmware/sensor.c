/* The sensor firmware (examples/sensor-firmware/src/main.rs) in C, through the header the build
 * writes for its scene (spectral_quadrature.h, `tables --c-header --scene
 * examples/sensor-firmware/scene.toml`) and its simulated device (simulated.h, made by
 * simulated.py from the Rust firmware's build script's simulated.rs): the same inputs, the same
 * `res` lines. The device is calibrated from its dark and white readings against the golden
 * white (sq_sensors_as7341_white), in f32 and for counts, and the lux scale from the white tile
 * at 1000 lx; each ColorChecker patch's counts then go to XYZ, CCT and Duv, lux and sRGB8 (the
 * integer path); 50 000 pseudo-random pixels through the integer path at N = 4, 5, 6 and 8 (the
 * sets of 5 and 6 channels made at run time, sq_integer_set_new) into checksums; CCT and Duv on
 * and off the Planckian locus and on NaN, infinite, zero, negative, huge and subnormal XYZ; both
 * calibrations and the lux scale on fixed inputs. `.ci/c-firmware` compares the lines with the
 * Rust firmware's on the host.
 *
 * The Rust firmware also checks its batch encoder (`encode_u8_batch`) against the per-pixel one;
 * the header has no batch encoder, so that line's checksums are the per-pixel encoder's over the
 * same chunks, and its batch instruction counts have no C counterpart.
 *
 * On a microcontroller it then counts the instructions per call of each step (`bench` lines,
 * named as the Rust firmware names them), with SysTick under QEMU's -icount shift=0, and how
 * much of the stack it used (`ram`). Built for the host it prints the results alone. */
#include <stddef.h>
#include <stdint.h>

#include "print.h"
#include "spectral_quadrature.h"
#include "simulated.h"

/* The illuminance on the chart, as a reference meter beside the white tile reads it. */
#define CHART_LUX 1000.0f

/* An f32 in decimal with `decimals` decimals, rounded half away from zero from an integer, as
 * the Rust firmware's Decimal: `x * 10^decimals ± 0.5` in f32, converted as Rust's `as i64`
 * converts (truncated, saturating). */
static void decimal(float x, unsigned decimals) {
    uint64_t unit = 1, magnitude;
    float scaled, r;
    int64_t n;
    unsigned i;
    if (sq_is_nan(x)) {
        s("nan");
        return;
    }
    if (sq_is_infinite(x)) {
        s("inf");
        return;
    }
    for (i = 0; i < decimals; i++) {
        unit *= 10u;
    }
    scaled = x * (float)unit;
    r = scaled < 0.0f ? scaled - 0.5f : scaled + 0.5f;
    if (r >= 9223372036854775808.0f) {
        n = INT64_MAX;
    } else if (r <= -9223372036854775808.0f) {
        n = INT64_MIN;
    } else {
        n = (int64_t)r;
    }
    magnitude = n < 0 ? 0u - (uint64_t)n : (uint64_t)n;
    if (n < 0) {
        s("-");
    }
    u64(magnitude / unit);
    if (decimals) {
        uint64_t frac = magnitude % unit, d;
        s(".");
        for (d = unit / 10u; d > 1u && frac < d; d /= 10u) {
            s("0");
        }
        u64(frac);
    }
}

/* A CCT and Duv as bits, then in decimals (K, and Duv to 10^-5), or `none`. */
static void cct_line(int ok, const sq_cct *c) {
    if (!ok) {
        s("none");
        return;
    }
    bits(c->kelvin);
    s(" ");
    bits(c->duv);
    s(" (");
    decimal(c->kelvin, 0);
    s(" K, Duv ");
    decimal(c->duv, 5);
    s(")");
}

/* Rust's Debug of an array of integers: [a, b, c]. */
static void list(const uint32_t *v, size_t n) {
    size_t i;
    s("[");
    for (i = 0; i < n; i++) {
        if (i) {
            s(", ");
        }
        u(v[i]);
    }
    s("]");
}

static void list16(const uint16_t *v, size_t n) {
    uint32_t w[CHANNELS];
    size_t i;
    for (i = 0; i < n; i++) {
        w[i] = v[i];
    }
    list(w, n);
}

/* An error of a calibration made in C: the header says which channel, not which problem, so
 * this line differs from the Rust firmware's wherever a calibration fails. */
static void calibration_error(size_t bad) {
    s("Err(Calibration { channel_index: ");
    u((uint32_t)(bad - 1));
    s(" })");
}

/* The device as the firmware sets it up once: its calibration in f32 and for counts, and the
 * lux scale. */
struct device {
    float dark[CHANNELS], gain[CHANNELS];
    uint16_t count_dark[CHANNELS];
    uint32_t gain_q16[CHANNELS];
    float lux_per_y;
};

static void as_f32(const uint16_t *counts, float *out, size_t n) {
    size_t i;
    for (i = 0; i < n; i++) {
        out[i] = (float)counts[i];
    }
}

/* Calibrates the simulated device from its dark and white readings: 0 if a channel saw no light
 * or the calibration does not fit the counts' range. */
static int device(struct device *d) {
    float white[CHANNELS], calibrated[CHANNELS], xyz[3];
    as_f32(DEVICE_DARK, d->dark, CHANNELS);
    as_f32(DEVICE_WHITE, white, CHANNELS);
    if (sq_calibration_from_dark_white(CHANNELS, d->dark, white, sq_sensors_as7341_white, d->gain)) {
        return 0;
    }
    /* The same calibration for counts: one count is the integer set's sample unit. */
    if (sq_calibration_to_counts(CHANNELS, d->dark, d->gain, sq_integer_as7341_srgb_sample_unit, d->count_dark, d->gain_q16)) {
        return 0;
    }
    /* The white tile, calibrated, is the reading of the known light. */
    sq_calibration_apply(CHANNELS, d->dark, d->gain, white, calibrated);
    sq_sets_as7341_xyz(calibrated, xyz);
    return sq_lux_scale_from_reading(xyz[1], CHART_LUX, &d->lux_per_y);
}

/* What the firmware reports for one raw reading. */
struct reading {
    uint16_t counts[CHANNELS];
    float xyz[3];
    int has_cct;
    sq_cct cct;
    float lux;
    uint8_t srgb8[3];
};

/* One raw reading through the calibration to XYZ, CCT, Duv, lux (f32) and sRGB8 (integers). */
static void read_device(const struct device *d, const uint16_t raw[CHANNELS], struct reading *r) {
    float readings[CHANNELS], calibrated[CHANNELS];
    sq_count_calibration_apply(CHANNELS, d->count_dark, d->gain_q16, raw, r->counts);
    sq_integer_as7341_srgb_encode_u8(r->counts, r->srgb8);
    as_f32(raw, readings, CHANNELS);
    sq_calibration_apply(CHANNELS, d->dark, d->gain, readings, calibrated);
    sq_sets_as7341_xyz(calibrated, r->xyz);
    r->has_cct = sq_planckian_locus_cct(r->xyz, &r->cct);
    r->lux = sq_lux_scale_lux(d->lux_per_y, r->xyz);
}

static void xyz_bits(const float xyz[3]) {
    s(" xyz ");
    bits(xyz[0]);
    s(" ");
    bits(xyz[1]);
    s(" ");
    bits(xyz[2]);
}

static void counts_line(const char *label, const uint16_t *v, size_t n) {
    size_t i;
    s(label);
    for (i = 0; i < n; i++) {
        s(" ");
        u(v[i]);
    }
}

/* The sensor's set on its first M channels (M = 5, 6), made at run time: on Armv7E-M the Rust
 * runtime sums samples in pairs, and these reach its last lone pair and a last unpaired sample. */
struct run_time_set {
    size_t n;
    unsigned frac_bits;
    int32_t fixed[3 * 6];
};

static int first_channels(size_t m, struct run_time_set *set) {
    float w[3 * 6];
    size_t c, i;
    for (c = 0; c < 3; c++) {
        for (i = 0; i < m; i++) {
            w[c * m + i] = sq_folded_as7341_srgb_weights[c][i];
        }
    }
    set->n = m;
    set->frac_bits = sq_integer_set_new(m, w, SAMPLE_UNIT, sq_srgb8_q63, set->fixed);
    return set->frac_bits != 0;
}

/* FNV-1a, 64 bits: a checksum of bytes. */
static void fnv(uint64_t *h, const uint8_t rgb[3]) {
    int i;
    for (i = 0; i < 3; i++) {
        *h = (*h ^ rgb[i]) * UINT64_C(0x00000100000001b3);
    }
}

/* Pseudo-random pixels the checksum covers, a chunk at a time. */
#define PIXELS 50000
#define CHUNK 16

static uint64_t state;

/* xorshift64; a count shifted right by 0 to 15 bits (every magnitude). */
static uint16_t next_count(void) {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return (uint16_t)((uint16_t)(state >> 48) >> (state % 16u));
}

static int checksums(void) {
    struct run_time_set set5, set6;
    uint64_t sums[4], batch[2];
    uint16_t x4[CHUNK][4], x8[CHUNK][8], x5[5], x6[6];
    uint8_t rgb[3];
    size_t chunk, p, i;
    if (!first_channels(5, &set5) || !first_channels(6, &set6)) {
        s("res the sensor's first channels have no fixed-point form");
        end();
        return 0;
    }
    state = UINT64_C(0x9e3779b97f4a7c15);
    for (i = 0; i < 4; i++) {
        sums[i] = UINT64_C(0xcbf29ce484222325);
    }
    batch[0] = batch[1] = UINT64_C(0xcbf29ce484222325);
    for (chunk = 0; chunk < PIXELS / CHUNK; chunk++) {
        for (p = 0; p < CHUNK; p++) {
            for (i = 0; i < 4; i++) {
                x4[p][i] = next_count();
            }
            sq_integer_table2_row2_srgb_encode_u8(x4[p], rgb);
            fnv(&sums[0], rgb);
            for (i = 0; i < 8; i++) {
                x8[p][i] = next_count();
            }
            sq_integer_as7341_srgb_encode_u8(x8[p], rgb);
            fnv(&sums[3], rgb);
            for (i = 0; i < 5; i++) {
                x5[i] = next_count();
            }
            sq_integer_set_encode_u8(5, set5.frac_bits, set5.fixed, sq_srgb8_q63, x5, rgb);
            fnv(&sums[1], rgb);
            for (i = 0; i < 6; i++) {
                x6[i] = next_count();
            }
            sq_integer_set_encode_u8(6, set6.frac_bits, set6.fixed, sq_srgb8_q63, x6, rgb);
            fnv(&sums[2], rgb);
        }
        /* The Rust firmware's batch encoder on the chunk; here the per-pixel encoder again. */
        for (p = 0; p < CHUNK; p++) {
            sq_integer_table2_row2_srgb_encode_u8(x4[p], rgb);
            fnv(&batch[0], rgb);
        }
        for (p = 0; p < CHUNK; p++) {
            sq_integer_as7341_srgb_encode_u8(x8[p], rgb);
            fnv(&batch[1], rgb);
        }
    }
    s("res checksum ");
    u(PIXELS);
    s(" pixels N=4 ");
    hex64(sums[0]);
    s(" N=5 ");
    hex64(sums[1]);
    s(" N=6 ");
    hex64(sums[2]);
    s(" N=8 ");
    hex64(sums[3]);
    end();
    s("res checksum batch N=4 ");
    hex64(batch[0]);
    s(" N=8 ");
    hex64(batch[1]);
    end();
    return 1;
}

/* The locus sweep's points: near the locus (|Duv| <= 0.06, some beyond the 0.05 limit) over the
 * whole table, and a few beyond its ends; the special inputs before them. */
#define SWEEP 96
#define SPECIALS 12

/* XYZ (Y = 1) of CIE 1960 (u, v), in f32. */
static void xyz_from_uv(float u_, float v, float out[3]) {
    float d = 2.0f * u_ - 8.0f * v + 4.0f;
    float x = 3.0f * u_ / d, y = 2.0f * v / d;
    out[0] = x / y;
    out[1] = 1.0f;
    out[2] = (1.0f - x - y) / y;
}

static float absf(float x) {
    return sq_f32_from_bits(sq_f32_bits(x) & 0x7fffffffu);
}

/* The i-th XYZ input of the CCT lines. */
static void locus_input(size_t i, float out[3]) {
    const float nan = sq_f32_from_bits(0x7fc00000u), inf = sq_f32_from_bits(0x7f800000u);
    const float sub = sq_f32_from_bits(1u), max = sq_f32_from_bits(0x7f7fffffu);
    const float specials[SPECIALS][3] = {
        { 95.047f, 100.0f, 108.883f }, /* D65 */
        { 109.85f, 100.0f, 35.585f },  /* A */
        { 0.0f, 0.0f, 0.0f },
        { nan, 1.0f, 1.0f },
        { 1.0f, inf, 1.0f },
        { -1.0f, -1.0f, -1.0f },
        { 0.95f, 1.0f, -0.01f },
        { max, max, max },
        { sub, sub, sub },
        { 3e-39f, 3.1e-39f, 3.3e-39f },
        { 0.3f, 0.6f, 0.1f },
        { 1e30f, 1.1e30f, 0.9e30f },
    };
    if (i < SPECIALS) {
        out[0] = specials[i][0];
        out[1] = specials[i][1];
        out[2] = specials[i][2];
    } else {
        /* Along a segment of the table (t in sixteenths), off the locus along a rough normal (the
         * tangent turned a quarter, scaled by |tu| + |tv|): Duv up to +-0.06. */
        size_t p = i - SPECIALS;
        size_t j = (p * 7) % (SQ_PLANCKIAN_LOCUS_LEN - 1);
        float t = (float)((p * 13) % 16) / 16.0f;
        float off = (float)((p * 5) % 13) / 100.0f - 0.06f;
        float tu = sq_planckian_locus_tangent[j][0], tv = sq_planckian_locus_tangent[j][1];
        float scale = off / (absf(tu) + absf(tv));
        float u_ = sq_planckian_locus_uv[j][0] + t * sq_planckian_locus_chord[j][0] - scale * tv;
        float v = sq_planckian_locus_uv[j][1] + t * sq_planckian_locus_chord[j][1] + scale * tu;
        xyz_from_uv(u_, v, out);
    }
}

static void locus_results(void) {
    size_t i;
    for (i = 0; i < SPECIALS + SWEEP; i++) {
        float xyz[3], uv[2];
        sq_cct c;
        int ok;
        locus_input(i, xyz);
        ok = sq_planckian_locus_cct(xyz, &c);
        s("res cct ");
        u((uint32_t)i);
        s(" ");
        cct_line(ok, &c);
        end();
        s("res uv ");
        u((uint32_t)i);
        if (sq_uv_from_xyz(xyz, uv)) {
            s(" ");
            bits(uv[0]);
            s(" ");
            bits(uv[1]);
        } else {
            s(" none");
        }
        end();
    }
}

/* Eight channels of counts for the calibrations' edge cases: a dark frame (one channel at 0), a
 * white frame (one channel barely above its dark, one at full scale), and a reference with a
 * channel at 1; then readings to correct. */
static const uint16_t DARK[8] = { 412, 1023, 97, 640, 815, 1500, 0, 33 };
static const uint16_t WHITE[8] = { 41210, 52003, 30097, 64000, 48815, 1501, 65535, 40033 };
static const uint16_t REFERENCE[8] = { 40000, 50000, 35000, 60000, 50000, 65535, 45000, 1 };

/* The golden device's white in the integer path's counts: 65 535 in its largest channel. */
static void white_counts(uint16_t out[CHANNELS]) {
    size_t k;
    for (k = 0; k < CHANNELS; k++) {
        float w = sq_sensors_as7341_white[k] / SAMPLE_UNIT + 0.5f;
        out[k] = (uint16_t)(w < 65535.0f ? w : 65535.0f);
    }
}

static void lux_scale_line(float y, float lux) {
    float l;
    if (sq_lux_scale_from_reading(y, lux, &l)) {
        s("Ok(");
        u(sq_f32_bits(l));
        s(")");
    } else {
        s("Err(InvalidLuxScale)");
    }
}

/* Both calibrations and the lux scale on fixed inputs, their edges included. */
static void calibration_results(void) {
    uint32_t gain_q16[8], to_counts_q16[8];
    uint16_t to_counts_dark[8], white[CHANNELS];
    float dark[8], whitef[8], reference[8], gain[8];
    size_t k, p, count_bad, float_bad, bad;
    for (k = 0; k < 8; k++) {
        dark[k] = (float)DARK[k];
        whitef[k] = (float)WHITE[k];
        reference[k] = (float)REFERENCE[k] / 50000.0f;
    }
    count_bad = sq_count_calibration_from_dark_white(8, DARK, WHITE, REFERENCE, gain_q16);
    float_bad = sq_calibration_from_dark_white(8, dark, whitef, reference, gain);
    s("res calibration counts ");
    if (count_bad) {
        calibration_error(count_bad);
    } else {
        s("Ok(");
        list(gain_q16, 8);
        s(")");
    }
    end();
    s("res calibration floats ");
    s(float_bad ? "false" : "true");
    end();
    if (!count_bad && !float_bad) {
        for (p = 0; p < 16; p++) {
            uint16_t x[8], c[8];
            float xf[8], y[8];
            for (k = 0; k < 8; k++) {
                x[k] = (uint16_t)((p * 7919u + k * 104729u) % 65536u);
            }
            sq_count_calibration_apply(8, DARK, gain_q16, x, c);
            s("res apply counts ");
            u((uint32_t)p);
            s(" ");
            list16(c, 8);
            end();
            as_f32(x, xf, 8);
            sq_calibration_apply(8, dark, gain, xf, y);
            s("res apply floats ");
            u((uint32_t)p);
            for (k = 0; k < 8; k++) {
                s(" ");
                bits(y[k]);
            }
            end();
        }
        bad = sq_calibration_to_counts(8, dark, gain, 1.0f / 50000.0f, to_counts_dark, to_counts_q16);
        s("res to_counts ");
        if (bad) {
            calibration_error(bad);
        } else {
            s("Ok(");
            list(to_counts_q16, 8);
            s(")");
        }
        end();
    }
    /* The golden white in counts against the device's own white, in integers only. */
    white_counts(white);
    bad = sq_count_calibration_from_dark_white(CHANNELS, DEVICE_DARK, DEVICE_WHITE, white, gain_q16);
    s("res device integer gains ");
    if (bad) {
        calibration_error(bad);
    } else {
        s("Ok(");
        list(gain_q16, CHANNELS);
        s(")");
    }
    end();
    {
        static const float xyz[3] = { 0.1f, 0.004f, 0.2f };
        float l;
        int ok = sq_lux_scale_from_reading(0.0125f, 500.0f, &l);
        s("res lux ");
        lux_scale_line(0.0125f, 500.0f);
        s(" ");
        bits(ok ? sq_lux_scale_lux(l, xyz) : sq_f32_from_bits(0x7fc00000u));
        end();
    }
    {
        const float cases[4][2] = { { 0.0f, 500.0f }, { -1.0f, 500.0f }, { sq_f32_from_bits(0x7fc00000u), 1.0f }, { 1e-30f, 1e30f } };
        for (k = 0; k < 4; k++) {
            s("res lux scale ");
            lux_scale_line(cases[k][0], cases[k][1]);
            end();
        }
    }
}

/* Every result line. */
static void results(void) {
    const char *scene = sq_scene, *c;
    struct device d;
    struct reading w;
    size_t p;
    for (c = sq_scene; *c; c++) {
        if (*c == '/') {
            scene = c + 1;
        }
    }
    s("res scene ");
    s(scene);
    s(" sensor AS7341 frac_bits ");
    u(SQ_INTEGER_AS7341_SRGB_FRAC_BITS);
    s(" sample_unit ");
    bits(sq_integer_as7341_srgb_sample_unit);
    end();
    /* The build's scale and the firmware's agree. */
    if (sq_f32_bits(sq_integer_as7341_srgb_sample_unit) != sq_f32_bits(SAMPLE_UNIT)) {
        s("res sample unit differs from the simulation's");
        end();
    }
    if (!device(&d)) {
        s("res the device's calibration failed");
        end();
        return;
    }
    counts_line("res device dark", d.count_dark, CHANNELS);
    s(" gain_q16");
    for (p = 0; p < CHANNELS; p++) {
        s(" ");
        u(d.gain_q16[p]);
    }
    s(" lux_per_y ");
    bits(d.lux_per_y);
    end();
    /* The white tile: CCT and Duv of the light as the sensor sees it. */
    read_device(&d, DEVICE_WHITE, &w);
    s("res white counts ");
    list16(w.counts, CHANNELS);
    xyz_bits(w.xyz);
    s(" cct ");
    cct_line(w.has_cct, &w.cct);
    s(" lux ");
    bits(w.lux);
    s(" (");
    decimal(w.lux, 1);
    s(" lx) srgb8 [");
    u(w.srgb8[0]);
    s(", ");
    u(w.srgb8[1]);
    s(", ");
    u(w.srgb8[2]);
    s("]");
    end();
    for (p = 0; p < PATCHES; p++) {
        struct reading r;
        float samples[CHANNELS];
        uint8_t f32_rgb[3], golden[3];
        int64_t fixed[3];
        size_t k;
        read_device(&d, DEVICE_COUNTS[p], &r);
        s(p < 10 ? "res patch  " : "res patch ");
        u((uint32_t)p);
        counts_line(" raw", DEVICE_COUNTS[p], CHANNELS);
        counts_line(" calibrated", r.counts, CHANNELS);
        xyz_bits(r.xyz);
        s(" cct ");
        cct_line(r.has_cct, &r.cct);
        s(" lux ");
        bits(r.lux);
        s(" (");
        decimal(r.lux, 1);
        s(" lx) srgb8");
        for (k = 0; k < 3; k++) {
            s(" ");
            u(r.srgb8[k]);
        }
        /* The f32 path on the calibrated counts, and the golden device's reading through the
         * integer path, with the exact fixed-point sums behind it. */
        sq_integer_as7341_srgb_counts_as_f32(r.counts, samples);
        sq_folded_as7341_srgb_encode_u8(SQ_GAMUT_MAPPING_CLIP, samples, f32_rgb);
        sq_integer_as7341_srgb_encode_u8(GOLDEN_COUNTS[p], golden);
        sq_integer_as7341_srgb_linear_fixed(GOLDEN_COUNTS[p], fixed);
        s(" f32");
        for (k = 0; k < 3; k++) {
            s(" ");
            u(f32_rgb[k]);
        }
        s(" golden");
        for (k = 0; k < 3; k++) {
            s(" ");
            u(golden[k]);
        }
        s(" fixed");
        for (k = 0; k < 3; k++) {
            s(" ");
            i64(fixed[k]);
        }
        s(" ");
        s(PATCH_NAMES[p]);
        end();
    }
    if (!checksums()) {
        return;
    }
    locus_results();
    calibration_results();
}

#if defined(__arm__) && !defined(__linux__)
#include "firmware.h"

/* Pixels per measurement of the per-pixel paths, as in the Rust firmware. */
#define P 240
#define ROUNDS 20

/* Keeps the compiler from dropping or hoisting work: the memory at ptr may be read here. */
#define KEEP(ptr) __asm__ volatile("" : : "r"(ptr) : "memory")

/* The inputs of one measurement at a time (the nRF51 has 16 kB of RAM; the Rust firmware keeps
 * them in flash, computed at compile time). */
static union {
    struct {
        uint16_t counts[P][4];
        float samples[P][4];
    } n4;
    uint16_t counts8[P][8];
    float samples8[P][8];
    struct {
        float near[SWEEP][3];
        float uv[SWEEP][2];
        uint32_t sink[SWEEP];
    } locus;
    struct {
        uint16_t calibrated[PATCHES][CHANNELS];
        float raw[PATCHES][CHANNELS];
        float calibrated_f32[PATCHES][CHANNELS];
        uint32_t reports[PATCHES];
    } cal;
} in;
static uint8_t rgb[P][3];
static float xyz_out[3];
/* SysTick ticks of a loop of 200 000 instructions (fw_loop_ticks). */
static uint32_t loop_ticks;
static uint32_t t0;

static void start(void) {
    KEEP(&in);
    t0 = fw_ticks();
}

/* Prints the instructions per call of what ran since start(), `calls` calls, rounded. */
static void stop(const char *name, uint32_t calls) {
    uint32_t t1 = fw_ticks();
    uint64_t n = (uint64_t)((t1 - t0) & 0x00FFFFFFu) * 200000u;
    uint64_t d = (uint64_t)loop_ticks * calls;
    KEEP(&in);
    KEEP(rgb);
    s("bench ");
    s(name);
    s(" ");
    u((uint32_t)((n + d / 2u) / d));
    end();
}

/* The per-pixel paths at N = 4 and 8, integer and f32. */
static void pixel_benches(void) {
    uint64_t st = UINT64_C(0x2545f4914f6cdd1d);
    size_t p, i;
    /* N = 4 counts: a fixed pseudo-random sweep whose pixels span every magnitude (each count
     * shifted right by 0 to 7 bits), the Rust firmware's SWEEP4. */
    for (p = 0; p < P; p++) {
        for (i = 0; i < 4; i++) {
            st ^= st << 13;
            st ^= st >> 7;
            st ^= st << 17;
            in.n4.counts[p][i] = (uint16_t)((uint16_t)(st >> 48) >> (st % 8u));
            in.n4.samples[p][i] = (float)in.n4.counts[p][i] * sq_integer_table2_row2_srgb_sample_unit;
        }
    }
    start();
    for (p = 0; p < P; p++) {
        rgb[p][0] = (uint8_t)in.n4.counts[p][0];
        rgb[p][1] = rgb[p][2] = 0;
        KEEP(rgb[p]);
    }
    stop("empty_loop", P);
    start();
    for (p = 0; p < P; p++) {
        sq_integer_table2_row2_srgb_encode_u8(in.n4.counts[p], rgb[p]);
        KEEP(rgb[p]);
    }
    stop("N=4 integer encode_u8", P);
    start();
    for (p = 0; p < P; p++) {
        sq_folded_table2_row2_srgb_encode_u8(SQ_GAMUT_MAPPING_CLIP, in.n4.samples[p], rgb[p]);
        KEEP(rgb[p]);
    }
    stop("N=4 f32 encode_u8", P);
    /* N = 8: the golden device's counts of the patches, ten times over. */
    for (p = 0; p < P; p++) {
        for (i = 0; i < 8; i++) {
            in.counts8[p][i] = GOLDEN_COUNTS[p % PATCHES][i];
        }
    }
    start();
    for (p = 0; p < P; p++) {
        sq_integer_as7341_srgb_encode_u8(in.counts8[p], rgb[p]);
        KEEP(rgb[p]);
    }
    stop("N=8 integer encode_u8", P);
    for (p = 0; p < P; p++) {
        for (i = 0; i < 8; i++) {
            in.samples8[p][i] = (float)GOLDEN_COUNTS[p % PATCHES][i] * SAMPLE_UNIT;
        }
    }
    start();
    for (p = 0; p < P; p++) {
        sq_folded_as7341_srgb_encode_u8(SQ_GAMUT_MAPPING_CLIP, in.samples8[p], rgb[p]);
        KEEP(rgb[p]);
    }
    stop("N=8 f32 encode_u8", P);
    start();
    for (p = 0; p < P; p++) {
        sq_sets_as7341_xyz(in.samples8[p], xyz_out);
        KEEP(xyz_out);
    }
    stop("N=8 f32 xyz", P);
}

/* CCT and Duv, and lux: the sweep's points the table covers, many times over. */
static void locus_benches(const struct device *d) {
    size_t n = 0, i, r;
    sq_cct c;
    for (i = SPECIALS; i < SPECIALS + SWEEP; i++) {
        float xyz[3];
        locus_input(i, xyz);
        if (sq_planckian_locus_cct(xyz, &c)) {
            in.locus.near[n][0] = xyz[0];
            in.locus.near[n][1] = xyz[1];
            in.locus.near[n][2] = xyz[2];
            n++;
        }
    }
    for (i = 0; i < SWEEP; i++) {
        if (i >= n || !sq_uv_from_xyz(in.locus.near[i], in.locus.uv[i])) {
            in.locus.uv[i][0] = 0.2f;
            in.locus.uv[i][1] = 0.3f;
        }
    }
    start();
    for (r = 0; r < ROUNDS; r++) {
        for (i = 0; i < n; i++) {
            in.locus.sink[i] = sq_f32_bits(in.locus.near[i][0]);
            KEEP(&in.locus.sink[i]);
        }
    }
    stop("locus_empty_loop", (uint32_t)(ROUNDS * n));
    start();
    for (r = 0; r < ROUNDS; r++) {
        for (i = 0; i < n; i++) {
            in.locus.sink[i] = sq_planckian_locus_cct(in.locus.near[i], &c) ? sq_f32_bits(c.kelvin) : 0u;
            KEEP(&in.locus.sink[i]);
        }
    }
    stop("PlanckianLocus::cct", (uint32_t)(ROUNDS * n));
    start();
    for (r = 0; r < ROUNDS; r++) {
        for (i = 0; i < n; i++) {
            float uv[2];
            in.locus.sink[i] = sq_uv_from_xyz(in.locus.near[i], uv) ? sq_f32_bits(uv[0]) : 0u;
            KEEP(&in.locus.sink[i]);
        }
    }
    stop("uv_from_xyz", (uint32_t)(ROUNDS * n));
    start();
    for (r = 0; r < ROUNDS; r++) {
        for (i = 0; i < n; i++) {
            in.locus.sink[i] = sq_planckian_locus_cct_from_uv(in.locus.uv[i], &c) ? sq_f32_bits(c.duv) : 0u;
            KEEP(&in.locus.sink[i]);
        }
    }
    stop("PlanckianLocus::cct_from_uv", (uint32_t)(ROUNDS * n));
    start();
    for (r = 0; r < ROUNDS; r++) {
        for (i = 0; i < n; i++) {
            in.locus.sink[i] = sq_f32_bits(sq_lux_scale_lux(d->lux_per_y, in.locus.near[i]));
            KEEP(&in.locus.sink[i]);
        }
    }
    stop("LuxScale::lux", (uint32_t)(ROUNDS * n));
}

/* Both calibrations, and a whole reading. */
static void calibration_benches(const struct device *d) {
    uint32_t gains[CHANNELS];
    uint16_t reference[CHANNELS];
    size_t r, p;
    start();
    for (r = 0; r < 10; r++) {
        for (p = 0; p < PATCHES; p++) {
            sq_count_calibration_apply(CHANNELS, d->count_dark, d->gain_q16, DEVICE_COUNTS[p], in.cal.calibrated[p]);
            KEEP(in.cal.calibrated[p]);
        }
    }
    stop("CountCalibration<8>::apply", 10 * PATCHES);
    for (p = 0; p < PATCHES; p++) {
        as_f32(DEVICE_COUNTS[p], in.cal.raw[p], CHANNELS);
    }
    start();
    for (r = 0; r < 10; r++) {
        for (p = 0; p < PATCHES; p++) {
            sq_calibration_apply(CHANNELS, d->dark, d->gain, in.cal.raw[p], in.cal.calibrated_f32[p]);
            KEEP(in.cal.calibrated_f32[p]);
        }
    }
    stop("Calibration<8>::apply", 10 * PATCHES);
    white_counts(reference);
    start();
    for (r = 0; r < 64; r++) {
        KEEP(reference);
        if (sq_count_calibration_from_dark_white(CHANNELS, DEVICE_DARK, DEVICE_WHITE, reference, gains) == 0) {
            KEEP(gains);
        }
    }
    stop("CountCalibration<8>::from_dark_white", 64);
    /* A whole reading, raw counts to what the firmware reports: both calibrations, the integer
     * sRGB8, XYZ, CCT, Duv and lux. */
    start();
    for (r = 0; r < 10; r++) {
        for (p = 0; p < PATCHES; p++) {
            struct reading rd;
            read_device(d, DEVICE_COUNTS[p], &rd);
            in.cal.reports[p] = (rd.has_cct ? sq_f32_bits(rd.cct.kelvin) : 0u) ^ rd.srgb8[0];
            KEEP(&in.cal.reports[p]);
        }
    }
    stop("read (raw counts to XYZ, CCT, Duv, lux, sRGB8)", 10 * PATCHES);
}

/* The stack: painted from the end of the statics up to near the stack pointer before anything
 * runs, then read back for the lowest word changed. */
extern uint32_t _ebss, _estack;
#define PAINT 0x5a5a5a5au

static void paint_stack(void) {
    uint32_t *p = &_ebss, here;
    __asm__ volatile("mov %0, sp" : "=r"(here));
    while ((uint32_t)(uintptr_t)p < here - 64u) {
        *(volatile uint32_t *)p = PAINT;
        p++;
    }
}

static uint32_t stack_used(void) {
    uint32_t *p = &_ebss;
    while (*(volatile uint32_t *)p == PAINT) {
        p++;
    }
    return (uint32_t)((uintptr_t)&_estack - (uintptr_t)p);
}

int main(void) {
    struct device d;
    paint_stack();
    results();
    loop_ticks = fw_loop_ticks();
    s("bench instructions_per_tick ");
    u((200000u + loop_ticks / 2u) / loop_ticks);
    end();
    pixel_benches();
    if (device(&d)) {
        locus_benches(&d);
        calibration_benches(&d);
    }
    s("ram statics ");
    u((uint32_t)((uintptr_t)&_ebss - 0x20000000u));
    s(" stack ");
    u(stack_used());
    s(" of ");
    u((uint32_t)((uintptr_t)&_estack - 0x20000000u));
    end();
    s("done");
    end();
    return 0;
}

#else

int main(void) {
    results();
    return 0;
}

#endif
