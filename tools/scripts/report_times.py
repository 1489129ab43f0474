#!/usr/bin/env python3
"""How long each section of the report takes: wall-clock seconds and CPU seconds (user + system,
all threads, from /proc/<pid>/stat), per step of its progress lines (`[k/N] ...`).

The CPU seconds are what a section costs whatever else the machine runs; the wall-clock seconds
are what a user waits, and grow when other work shares the cores. The load average before and
after is printed with them.

Usage (Linux), from the repository's root, after a release build:

    python3 tools/scripts/report_times.py target/release/report --reflectances target/reflectances_1269.csv --out target/r1269

The report's own standard output goes to <out>.txt beside --out (or report.txt), its standard
error is echoed. Prints one line per step, then the totals.
"""

import os
import subprocess
import sys
import time


def cpu_seconds(pid):
    """User + system CPU seconds of the process (every thread), or None once it has ended."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
    except OSError:
        return None
    # Fields 14 and 15 of stat (utime, stime), counted after the command's name.
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def main():
    cmd = sys.argv[1:]
    if not cmd:
        sys.exit(__doc__)
    out = "report"
    if "--out" in cmd:
        out = cmd[cmd.index("--out") + 1]
    load_before = os.getloadavg()
    start = time.monotonic()
    with open(out.rstrip("/") + ".txt", "w") as stdout:
        p = subprocess.Popen(cmd, stdout=stdout, stderr=subprocess.PIPE, text=True)
        marks = []  # (step, wall, cpu)
        last_cpu = 0.0
        for line in p.stderr:
            sys.stderr.write(line)
            cpu = cpu_seconds(p.pid)
            if cpu is not None:
                last_cpu = cpu
            if line.startswith("[") and "/" in line.split("]")[0]:
                marks.append((line.split("] ", 1)[1].rsplit(" (", 1)[0], time.monotonic() - start, last_cpu))
        # The children's times once it has exited: every thread's CPU seconds, to the end.
        _, status, usage = os.wait4(p.pid, 0)
        wall = time.monotonic() - start
        total_cpu = usage.ru_utime + usage.ru_stime
    print(f"load average before {load_before[0]:.2f}, after {os.getloadavg()[0]:.2f} (1 min)")
    print(f"{'step':<74} {'wall s':>8} {'CPU s':>8}")
    for k, (step, w, c) in enumerate(marks):
        w1, c1 = (marks[k + 1][1], marks[k + 1][2]) if k + 1 < len(marks) else (wall, total_cpu)
        print(f"{step[:74]:<74} {w1 - w:>8.1f} {c1 - c:>8.1f}")
    print(f"{'total':<74} {wall:>8.1f} {total_cpu:>8.1f}")
    sys.exit(os.waitstatus_to_exitcode(status))


if __name__ == "__main__":
    main()
