/* What main.c and sensor.c print with: one line at a time, built in a buffer and written whole
 * (to standard output on the host, through semihosting on a microcontroller), with the numbers
 * formatted from integers, so that printing links no float formatting. */
#ifndef PRINT_H
#define PRINT_H
#include <stdint.h>

/* Appends text to the line. */
void s(const char *text);
/* Appends an unsigned integer in decimal. */
void u(uint32_t v);
/* Appends a 64-bit integer in decimal, signed or not. */
void u64(uint64_t v);
void i64(int64_t v);
/* Appends a 64-bit integer as 16 hex digits. */
void hex64(uint64_t v);
/* Appends an f32 as its bits in 8 hex digits, or `nan` for any NaN (IEEE 754 does not specify
 * its sign and payload). */
void bits(float x);
/* Ends the line and writes it. */
void end(void);

#endif
