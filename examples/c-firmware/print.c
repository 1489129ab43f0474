/* The output of main.c and sensor.c (print.h). */
#include <stddef.h>
#include <string.h>

#include "print.h"

static char line[192];
static size_t len;

#if defined(__arm__) && !defined(__linux__)
#include "firmware.h"
static void put_line(void) {
    fw_write(line);
}
#else
#include <stdio.h>
static void put_line(void) {
    fputs(line, stdout);
}
#endif

void s(const char *text) {
    while (*text) {
        /* A full buffer is written as it is: a longer line is written in parts. */
        if (len + 1 == sizeof line) {
            put_line();
            len = 0;
        }
        line[len++] = *text++;
        line[len] = '\0';
    }
}

void u64(uint64_t v) {
    char digits[21];
    int n = 0;
    do {
        digits[n++] = (char)('0' + v % 10u);
        v /= 10u;
    } while (v);
    while (n) {
        char one[2] = { digits[--n], '\0' };
        s(one);
    }
}

void u(uint32_t v) {
    u64(v);
}

void i64(int64_t v) {
    if (v < 0) {
        s("-");
        u64(0u - (uint64_t)v);
    } else {
        u64((uint64_t)v);
    }
}

static void hex(uint64_t v, int digits) {
    static const char xdigit[] = "0123456789abcdef";
    char out[17];
    int i;
    for (i = digits - 1; i >= 0; i--) {
        out[i] = xdigit[v & 15u];
        v >>= 4;
    }
    out[digits] = '\0';
    s(out);
}

void hex64(uint64_t v) {
    hex(v, 16);
}

void bits(float x) {
    uint32_t b;
    memcpy(&b, &x, sizeof b);
    if ((b & 0x7fffffffu) > 0x7f800000u) {
        s("nan");
        return;
    }
    hex(b, 8);
}

void end(void) {
    s("\n");
    put_line();
    len = 0;
    line[0] = '\0';
}
