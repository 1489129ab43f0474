#!/usr/bin/env python3
"""Cycles per instruction of the integer path on a Cortex-M0, from what QEMU executed.

QEMU counts instructions (`-icount shift=0`), not cycles. This runs the M0 sensor firmware
once more on `microbit` with QEMU's trace of the translated blocks (`-d in_asm,exec,nochain`),
filtered to the integer path's functions (`encode_u8`, `encode_u8_batch` with the Armv6-M
assembly inlined in it, `encode_channels_from`, `settle`, `below_zero`, every instance the
firmware links), and prices each executed instruction with the
Cortex-M0's timings (Arm's Cortex-M0 Technical Reference Manual, 3.3): 1 cycle for data
processing, 2 for a load or store, 1 + n for PUSH, POP (4 + n with PC), LDM and STM of n
registers, 3 for a taken branch and 1 for one not taken, 4 for BL, 3 for BX and BLX, and for
MULS 1 cycle (the fast multiplier) or 32 (the small one, which a part may choose instead).
A branch counts as taken when the next block traced is not the one after it.

It prints, per function and for all together, the instructions, the cycles with the 1-cycle
multiplier, cycles per instruction and multiplies per instruction: cycles per pixel are then
an instruction count of `.ci/sensor-firmware` times the cycles per instruction, and with the
32-cycle multiplier 31 more per multiply. On a Cortex-M0+ a taken branch costs 2, not 3.

Usage (after `bash .ci/sensor-firmware`, which builds the firmware):
    python3 examples/sensor-firmware/m0_cycles.py \
        examples/target/thumbv6m-none-eabi/release/spectral-quadrature-sensor-firmware
"""

import collections
import re
import subprocess
import sys
import tempfile

FUNCTIONS = ("encode_u8", "encode_u8_batch", "encode_channels_from", "settle", "below_zero")


def functions(elf):
    """(name, start, size) of every instance of the integer path's functions in `elf`."""
    out = subprocess.run(
        ["arm-none-eabi-nm", "-C", "-S", elf], check=True, capture_output=True, text=True
    ).stdout
    found = []
    for line in out.splitlines():
        parts = line.split(maxsplit=3)
        if len(parts) < 4 or "spectral_quadrature::integer::set::IntegerSet" not in parts[3]:
            continue
        name = parts[3].rsplit("::", 1)[-1]
        if name in FUNCTIONS:
            # Thumb symbols may carry the low bit; the code starts at the even address.
            found.append((f"{name}@{int(parts[0], 16) & ~1:x}", int(parts[0], 16) & ~1, int(parts[1], 16)))
    if not found:
        sys.exit(f"no function of the integer path in {elf}")
    return found


def kind(mnemonic):
    m = mnemonic.lower()
    if m.startswith("mul"):
        return "mul"
    if m.startswith(("ldm", "stm")):
        return "ldm"
    if m.startswith("push"):
        return "push"
    if m.startswith("pop"):
        return "pop"
    if m.startswith(("ldr", "str")):
        return "mem"
    if m == "bl":
        return "bl"
    if m.startswith(("bx", "blx")):
        return "bx"
    if m.startswith("b"):
        return "b"
    return "alu"


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    elf = sys.argv[1]
    funcs = functions(elf)
    ranges = ",".join(f"0x{start:x}+0x{size:x}" for _, start, size in funcs)
    with tempfile.NamedTemporaryFile(suffix=".log") as log:
        subprocess.run(
            ["timeout", "600", "qemu-system-arm", "-M", "microbit", "-nographic",
             "-semihosting-config", "enable=on,target=native", "-icount", "shift=0",
             "-kernel", elf, "-d", "in_asm,exec,nochain", "-dfilter", ranges, "-D", log.name],
            check=True, stdout=subprocess.DEVNULL,
        )
        blocks, trace, current = {}, [], None
        for line in open(log.name, encoding="utf-8", errors="replace"):
            if line.startswith("IN:"):
                current = []
                continue
            m = re.match(r"0x([0-9a-f]+):\s+([0-9a-f ]+?)\s{2,}(\S+)\s*(.*)", line)
            if m and current is not None:
                address = int(m.group(1), 16)
                size = len(m.group(2).replace(" ", "")) // 2
                if not current:
                    blocks[address] = current
                current.append((address, size, m.group(3), m.group(4)))
            elif line.startswith("Trace"):
                current = None
                trace.append(int(line.split("[")[1].split("/")[1], 16))
            elif not line.strip():
                current = None
    stats = collections.defaultdict(collections.Counter)
    for k, pc in enumerate(trace):
        block = blocks.get(pc)
        if block is None:
            continue
        name = next(n for n, start, size in funcs if start <= pc < start + size)
        s = stats[name]
        for address, size, mnemonic, operands in block:
            c = kind(mnemonic)
            registers = operands.count(",") + 1 if c in ("push", "pop", "ldm") else 0
            s["instructions"] += 1
            if c == "mul":
                s["muls"] += 1
                s["cycles"] += 1
            elif c == "mem":
                s["cycles"] += 2
            elif c in ("ldm", "push"):
                s["cycles"] += 1 + registers
            elif c == "pop":
                s["cycles"] += 3 + registers if "pc" in operands else 1 + registers
            elif c == "bl":
                s["cycles"] += 4
            elif c == "bx":
                s["cycles"] += 3
            elif c == "b":
                conditional = mnemonic.lower() not in ("b", "b.n", "b.w")
                following = trace[k + 1] if k + 1 < len(trace) else None
                taken = not conditional or (following is not None and following != address + size)
                s["cycles"] += 3 if taken else 1
            else:
                s["cycles"] += 1
    total = collections.Counter()
    print(f"{'function':<28} {'instructions':>12} {'cycles':>12} {'cycles/insn':>11} {'muls/insn':>9}")
    for name, s in sorted(stats.items()) + [("all", None)]:
        if s is None:
            s = total
        else:
            total.update(s)
        n = s["instructions"]
        print(f"{name:<28} {n:>12} {s['cycles']:>12} {s['cycles'] / n:>11.3f} {s['muls'] / n:>9.4f}")
        if name != "all":
            calls = trace.count(int(name.split("@")[1], 16))
            print(f"{'':<28} {calls:>12} calls, {n / max(calls, 1):.1f} instructions and "
                  f"{s['muls'] / max(calls, 1):.2f} multiplies a call")


if __name__ == "__main__":
    main()
