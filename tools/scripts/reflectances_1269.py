#!/usr/bin/env python3
"""A large input for timing the report: 1,269 reflectances (as many as the Munsell Book's
matte chips, which the repository does not ship), made from the measured sets in data/.

- The 228 measured reflectances, each once: the ColorChecker (Ohta, 24), the CIE test colour
  samples 1-14 and the 190 rawtoaces training patches, on 380-780 nm every 5 nm (the rows all
  three files have; the CIE file's rows outside are dropped). Values below 0 (rounding noise of
  about -7e-18 in the rawtoaces file) are written as 0.
- 1,041 mixtures: for k = 1..1041, two different measured reflectances a and b drawn uniformly
  and a weight t uniform in [0, 1], all from Python's `random.Random(SEED)` (Mersenne Twister,
  the same stream on every Python 3), written as t·a + (1 - t)·b: the reflectance of a surface
  whose area is covered by a in fraction t and by b in the rest (a halftone of the two), so
  each is a physically possible reflectance within the measured ones' range.

Every value is written with 6 decimals. The file is about 1 MB: it is made on demand, not
kept in the repository.

Usage: python3 tools/scripts/reflectances_1269.py [OUT]   (default target/reflectances_1269.csv,
from the repository's root); then
`cargo run --release -p spectral-quadrature-tools --bin report -- --reflectances target/reflectances_1269.csv`.
"""

import csv
import pathlib
import random
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent.parent
DATA = ROOT / "data"
SEED = 1269
TOTAL = 1269
GRID = list(range(380, 781, 5))
SOURCES = [
    ("cc", "reflectance_colorchecker_ohta.csv"),
    ("tcs", "reflectance_cie_tcs.csv"),
    ("r2a", "reflectance_rawtoaces_190.csv"),
]


def read(prefix, name):
    """The file's spectra on GRID, as (name, values), in column order."""
    with open(DATA / name, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    by_nm = {round(float(r[0])): r[1:] for r in body}
    missing = [nm for nm in GRID if nm not in by_nm]
    if missing:
        sys.exit(f"{name}: no row at {missing} nm")
    return [
        (f"{prefix} {col}", [max(0.0, float(by_nm[nm][k])) for nm in GRID])
        for k, col in enumerate(header[1:])
    ]


def main():
    out = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "target" / "reflectances_1269.csv"
    measured = [s for prefix, name in SOURCES for s in read(prefix, name)]
    rng = random.Random(SEED)
    spectra = list(measured)
    for k in range(1, TOTAL - len(measured) + 1):
        i, j = rng.sample(range(len(measured)), 2)
        t = rng.random()
        (na, a), (nb, b) = measured[i], measured[j]
        spectra.append(
            (f"mix{k:04} {t:.3f} {na} + {nb}", [t * x + (1.0 - t) * y for x, y in zip(a, b)])
        )
    out.parent.mkdir(parents=True, exist_ok=True)
    with open(out, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["wavelength_nm"] + [n for n, _ in spectra])
        for row, nm in enumerate(GRID):
            w.writerow([nm] + [f"{v[row]:.6f}" for _, v in spectra])
    print(f"{out}: {len(spectra)} reflectances ({len(measured)} measured, "
          f"{len(spectra) - len(measured)} mixtures, seed {SEED}), {GRID[0]}-{GRID[-1]} nm")


if __name__ == "__main__":
    main()
