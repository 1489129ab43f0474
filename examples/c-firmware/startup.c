/* The C firmware's start on a Cortex-M (QEMU's microbit, a Cortex-M0, and mps2-an386, a
 * Cortex-M4F): the vector table, the reset handler (.data copied, .bss zeroed, the FPU enabled
 * where there is one, then main), semihosting output and exit, and SysTick as the clock the
 * firmware counts instructions with. No C library start-up code: newlib gives memcpy, powf and
 * sqrtf. */
#include <stdint.h>

#include "firmware.h"

extern uint32_t _estack, _sidata, _sdata, _edata, _sbss, _ebss;
int main(void);

static int semihost(int op, const void *arg) {
    register int r0 __asm__("r0") = op;
    register const void *r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

/* Standard output: ":tt" opened for writing (SYS_OPEN, mode "w"), as the Rust firmware's
 * semihosting crate does; QEMU writes it to its standard output. */
static int stdout_handle = -1;

void fw_write(const char *text) {
    uint32_t args[3];
    uint32_t n = 0;
    while (text[n] != '\0') {
        n++;
    }
    if (stdout_handle < 0) {
        args[0] = (uint32_t)(uintptr_t)":tt";
        args[1] = 4u;
        args[2] = 3u;
        stdout_handle = semihost(0x01, args); /* SYS_OPEN */
    }
    args[0] = (uint32_t)stdout_handle;
    args[1] = (uint32_t)(uintptr_t)text;
    args[2] = n;
    semihost(0x05, args); /* SYS_WRITE */
}

void fw_exit(int ok) {
    /* SYS_EXIT with ADP_Stopped_ApplicationExit (QEMU exits 0) or RunTimeErrorUnknown (1). */
    semihost(0x18, (const void *)(uintptr_t)(ok ? 0x20026u : 0x20023u));
    for (;;) {
    }
}

#define SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018u)

uint32_t fw_ticks(void) {
    return (0x00FFFFFFu - SYST_CVR) & 0x00FFFFFFu;
}

uint32_t fw_loop_ticks(void) {
    uint32_t rounds = 100000u, t0, t1, t;
    t0 = fw_ticks();
    __asm__ volatile(".syntax unified\n1:\n\tsubs %0, %0, #1\n\tbne 1b" : "+l"(rounds) : : "cc");
    t1 = fw_ticks();
    t = (t1 - t0) & 0x00FFFFFFu;
    return t ? t : 1u;
}

void fw_reset(void);
void fw_reset(void) {
    uint32_t *src = &_sidata, *dst;
    for (dst = &_sdata; dst < &_edata;) {
        *dst++ = *src++;
    }
    for (dst = &_sbss; dst < &_ebss;) {
        *dst++ = 0u;
    }
#if defined(__ARM_FP)
    /* CPACR: full access to CP10 and CP11, the FPU. */
    *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20;
    __asm__ volatile("dsb\n\tisb" ::: "memory");
#endif
    SYST_RVR = 0x00FFFFFFu;
    SYST_CVR = 0u;
    SYST_CSR = 5u; /* enabled, the processor clock, no interrupt */
    fw_exit(main() == 0);
}

static void fw_fault(void) {
    fw_write("fault\n");
    fw_exit(0);
}

/* The vector table: the initial stack pointer, then the reset, NMI and hard fault handlers. */
struct vector_table {
    uint32_t *stack;
    void (*handlers[15])(void);
};

__attribute__((section(".vectors"), used)) static const struct vector_table vectors = {
    &_estack,
    { fw_reset, fw_fault, fw_fault },
};
