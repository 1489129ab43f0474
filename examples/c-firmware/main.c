/* The runtime's per-pixel paths from C on a microcontroller, through the header the build writes
 * (spectral_quadrature.h, `tables --c-header`, the default scene). It prints the `res` lines of
 * the Rust firmware (examples/firmware/src/main.rs) for the same inputs, NaN, negative, huge and
 * subnormal among them: AC1C2 of TABLE2_ROW2, and for every display the set folded at run time
 * (`sq_sets_table2_row2_fold`), its linear RGB, and its 8- and 16-bit pixels with both gamut
 * mappings, per pixel and from planes. `.ci/c-firmware` compares them with the Rust firmware's
 * on the host. On a microcontroller it then counts the instructions per pixel of each path
 * (`bench` lines), with SysTick under QEMU's -icount shift=0, for N = 4 (TABLE2_ROW2) and N = 8
 * (KQ_C_8), the float paths and the integer path. Built for the host it prints the results
 * alone. */
#include <stddef.h>
#include <stdint.h>

#include "print.h"
#include "spectral_quadrature.h"

#define PIXELS 48

static float px[PIXELS][4];

/* 2^e for small e, exactly. */
static float pow2(int e) {
    return sq_f32_from_bits((uint32_t)(127 + e) << 23);
}

/* The Rust firmware's inputs(): 16 specials, then a sweep over 12 octaves. */
static void inputs(void) {
    const float nan = sq_f32_from_bits(0x7fc00000u), inf = sq_f32_from_bits(0x7f800000u);
    const float sub = sq_f32_from_bits(1u);
    const float specials[16][4] = {
        { 0.0f, 0.0f, 0.0f, 0.0f },
        { 1.0f, 1.0f, 1.0f, 1.0f },
        { 0.5f, 0.4f, 0.3f, 0.2f },
        { 0.02f, 0.9f, 0.1f, 0.0f },
        { 0.9f, 0.05f, 0.05f, 0.9f },
        { nan, 0.5f, 0.5f, 0.5f },
        { 0.5f, 0.5f, 0.5f, nan },
        { -1.0f, 0.5f, 0.5f, 0.5f },
        { -0.0f, -1e-3f, -0.5f, -2.0f },
        { 1e30f, 1e30f, 1e30f, 1e30f },
        { 3.40282347e38f, 0.0f, 0.0f, 0.0f },
        { inf, 0.5f, 0.5f, 0.5f },
        { -inf, -inf, -inf, -inf },
        { sub, sub, sub, sub },
        { 1e-40f, 1e-38f, 1.2e-38f, 3e-39f },
        { 0.003f, 0.0031f, 0.004f, 0.0005f },
    };
    int p, i;
    for (p = 0; p < PIXELS; p++) {
        for (i = 0; i < 4; i++) {
            if (p < 16) {
                px[p][i] = specials[p][i];
            } else {
                float k = (float)((p * 37 + i * 11) % 97) / 97.0f;
                int octave = (p * 5 + i * 3) % 13 - 12;
                px[p][i] = (1.0f + k) * pow2(octave);
            }
        }
    }
}

/* The default scene's displays, in the order of tables::displays::ALL. */
struct display {
    const char *name;
    const float (*xyz_to_rgb)[3];
    void (*encode_u8)(sq_gamut_mapping, const float *, uint8_t *);
    void (*encode_u16)(sq_gamut_mapping, const float *, uint16_t *);
};

static const struct display displays[] = {
    { sq_displays_srgb_name, sq_displays_srgb_xyz_to_rgb, sq_displays_srgb_encode_u8, sq_displays_srgb_encode_u16 },
    { sq_displays_display_p3_name, sq_displays_display_p3_xyz_to_rgb, sq_displays_display_p3_encode_u8, sq_displays_display_p3_encode_u16 },
    { sq_displays_rec2020_name, sq_displays_rec2020_xyz_to_rgb, sq_displays_rec2020_encode_u8, sq_displays_rec2020_encode_u16 },
    { sq_displays_meyer_1987_name, sq_displays_meyer_1987_xyz_to_rgb, sq_displays_meyer_1987_encode_u8, sq_displays_meyer_1987_encode_u16 },
};

static const sq_gamut_mapping mappings[2] = { SQ_GAMUT_MAPPING_CLIP, SQ_GAMUT_MAPPING_PRESERVE_A };
static const char *const mapping_names[2] = { "clip", "preserve-a" };

static void results(void) {
    size_t d, p, k;
    s("res scene ");
    s(sq_scene);
    end();
    for (p = 0; p < PIXELS; p++) {
        float a[3];
        sq_sets_table2_row2_ac1c2(px[p], a);
        s("res ac1c2 ");
        u((uint32_t)p);
        for (k = 0; k < 3; k++) {
            s(" ");
            bits(a[k]);
        }
        end();
    }
    for (d = 0; d < sizeof displays / sizeof displays[0]; d++) {
        const struct display *dp = &displays[d];
        float w[3][4], planes[4][PIXELS];
        size_t m, i;
        sq_sets_table2_row2_fold(dp->xyz_to_rgb, 1.0f / sq_unit_spectrum_y, w);
        for (p = 0; p < PIXELS; p++) {
            float rgb[3];
            sq_mat_vec(4, &w[0][0], px[p], rgb);
            s("res ");
            s(dp->name);
            s(" linear ");
            u((uint32_t)p);
            for (k = 0; k < 3; k++) {
                s(" ");
                bits(rgb[k]);
            }
            end();
        }
        for (i = 0; i < 4; i++) {
            for (p = 0; p < PIXELS; p++) {
                planes[i][p] = px[p][i];
            }
        }
        for (m = 0; m < 2; m++) {
            uint8_t planar[PIXELS][3];
            for (p = 0; p < PIXELS; p++) {
                float rgb[3];
                uint8_t b8[3];
                uint16_t b16[3];
                sq_mat_vec(4, &w[0][0], px[p], rgb);
                dp->encode_u8(mappings[m], rgb, b8);
                dp->encode_u16(mappings[m], rgb, b16);
                s("res ");
                s(dp->name);
                s(" ");
                s(mapping_names[m]);
                s(" ");
                u((uint32_t)p);
                s(" u8");
                for (k = 0; k < 3; k++) {
                    s(" ");
                    u(b8[k]);
                }
                s(" u16");
                for (k = 0; k < 3; k++) {
                    s(" ");
                    u(b16[k]);
                }
                end();
            }
            /* From planes: each pixel's samples gathered from the four planes. */
            for (p = 0; p < PIXELS; p++) {
                float sample[4], rgb[3];
                for (i = 0; i < 4; i++) {
                    sample[i] = planes[i][p];
                }
                sq_mat_vec(4, &w[0][0], sample, rgb);
                dp->encode_u8(mappings[m], rgb, planar[p]);
            }
            s("res ");
            s(dp->name);
            s(" ");
            s(mapping_names[m]);
            s(" planar ok true");
            end();
            for (p = 0; p < PIXELS; p++) {
                s("res ");
                s(dp->name);
                s(" ");
                s(mapping_names[m]);
                s(" ");
                u((uint32_t)p);
                s(" planar");
                for (k = 0; k < 3; k++) {
                    s(" ");
                    u(planar[p][k]);
                }
                end();
            }
        }
    }
}

#if defined(__arm__) && !defined(__linux__)
#include "firmware.h"

#define P 96

/* Keeps the compiler from dropping or hoisting work: the memory at ptr may be read here. */
#define KEEP(ptr) __asm__ volatile("" : : "r"(ptr) : "memory")

static float samples4[P][4], samples8[P][8], acc[P][3];
static uint16_t counts4[P][4], counts8[P][8];
static uint8_t out8[P][3];
static uint16_t out16[P][3];
/* SysTick ticks of a loop of 200 000 instructions (fw_loop_ticks). */
static uint32_t loop_ticks;

static void bench_line(const char *name, uint32_t t0, uint32_t t1) {
    /* Instructions = ticks * 200 000 / loop_ticks, per pixel, rounded. */
    uint64_t n = (uint64_t)((t1 - t0) & 0x00FFFFFFu) * 200000u;
    uint64_t d = (uint64_t)loop_ticks * P;
    s("bench ");
    s(name);
    s(" ");
    u((uint32_t)((n + d / 2u) / d));
    end();
}

#define MEASURE(name, body)                                                                        \
    do {                                                                                           \
        size_t p_;                                                                                 \
        uint32_t t0_, t1_;                                                                         \
        KEEP(samples4);                                                                            \
        t0_ = fw_ticks();                                                                          \
        for (p_ = 0; p_ < P; p_++) {                                                               \
            body;                                                                                  \
        }                                                                                          \
        KEEP(acc);                                                                                 \
        t1_ = fw_ticks();                                                                          \
        bench_line(name, t0_, t1_);                                                                \
    } while (0)

static void benches(void) {
    size_t p, i;
    /* The sweep's pixels (no specials), and for N = 8 and the integer path the same values
     * spread over 8 samples and as counts. */
    for (p = 0; p < P; p++) {
        const float *x = px[16 + p % (PIXELS - 16)];
        for (i = 0; i < 4; i++) {
            samples4[p][i] = x[i];
            samples8[p][i] = x[i];
            samples8[p][4 + i] = x[3 - i];
        }
        for (i = 0; i < 8; i++) {
            float v = samples8[p][i] * 30000.0f;
            uint16_t c = v < 65535.0f ? (uint16_t)v : 65535u;
            if (i < 4) {
                counts4[p][i] = c;
            }
            counts8[p][i] = c;
        }
    }
    MEASURE("empty_loop", out8[p_][0] = (uint8_t)sq_f32_bits(samples4[p_][0]));
    MEASURE("ac1c2 N=4", sq_sets_table2_row2_ac1c2(samples4[p_], acc[p_]));
    MEASURE("ac1c2 N=8", sq_sets_kq_c_8_ac1c2(samples8[p_], acc[p_]));
    MEASURE("linear_rgb N=4", sq_folded_table2_row2_srgb_linear_rgb(samples4[p_], acc[p_]));
    MEASURE("linear_rgb N=8", sq_folded_kq_c_8_srgb_linear_rgb(samples8[p_], acc[p_]));
    MEASURE("srgb8_from_linear x3", {
        out8[p_][0] = sq_srgb8_from_linear(samples4[p_][0]);
        out8[p_][1] = sq_srgb8_from_linear(samples4[p_][1]);
        out8[p_][2] = sq_srgb8_from_linear(samples4[p_][2]);
    });
    MEASURE("encode_u8 sRGB clip N=4", sq_folded_table2_row2_srgb_encode_u8(SQ_GAMUT_MAPPING_CLIP, samples4[p_], out8[p_]));
    MEASURE("encode_u8 sRGB clip N=8", sq_folded_kq_c_8_srgb_encode_u8(SQ_GAMUT_MAPPING_CLIP, samples8[p_], out8[p_]));
    MEASURE("encode_u8 sRGB preserve-a N=4", sq_folded_table2_row2_srgb_encode_u8(SQ_GAMUT_MAPPING_PRESERVE_A, samples4[p_], out8[p_]));
    MEASURE("encode_u8 sRGB preserve-a N=8", sq_folded_kq_c_8_srgb_encode_u8(SQ_GAMUT_MAPPING_PRESERVE_A, samples8[p_], out8[p_]));
    MEASURE("encode_u8 Rec. 2020 clip N=4", sq_folded_table2_row2_rec2020_encode_u8(SQ_GAMUT_MAPPING_CLIP, samples4[p_], out8[p_]));
    MEASURE("encode_u8 Meyer 1987 clip N=4", sq_folded_table2_row2_meyer_1987_encode_u8(SQ_GAMUT_MAPPING_CLIP, samples4[p_], out8[p_]));
    MEASURE("encode_u16 sRGB clip N=4", sq_folded_table2_row2_srgb_encode_u16(SQ_GAMUT_MAPPING_CLIP, samples4[p_], out16[p_]));
    MEASURE("encode_u16 sRGB clip N=8", sq_folded_kq_c_8_srgb_encode_u16(SQ_GAMUT_MAPPING_CLIP, samples8[p_], out16[p_]));
    MEASURE("integer encode_u8 sRGB N=4", sq_integer_table2_row2_srgb_encode_u8(counts4[p_], out8[p_]));
    MEASURE("integer encode_u8 sRGB N=8", sq_integer_kq_c_8_srgb_encode_u8(counts8[p_], out8[p_]));
    KEEP(out8);
    KEEP(out16);
}

int main(void) {
    inputs();
    results();
    loop_ticks = fw_loop_ticks();
    s("bench instructions_per_tick ");
    u((200000u + loop_ticks / 2u) / loop_ticks);
    end();
    benches();
    s("done");
    end();
    return 0;
}

#else

int main(void) {
    inputs();
    results();
    return 0;
}

#endif
