/* What startup.c gives main.c on a microcontroller. */
#ifndef FIRMWARE_H
#define FIRMWARE_H
#include <stdint.h>

/* Writes text through semihosting. */
void fw_write(const char *text);
/* Ends the program (QEMU exits with 0 where ok, else 1). */
void fw_exit(int ok);
/* SysTick's count since it started (24 bits). */
uint32_t fw_ticks(void);
/* The SysTick ticks of a loop of 200 000 instructions (100 000 rounds of subs and bne): under
 * QEMU's -icount shift=0 every instruction takes 1 ns, so this gives instructions per tick. */
uint32_t fw_loop_ticks(void);

#endif
