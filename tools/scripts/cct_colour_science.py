#!/usr/bin/env python3
"""A second reference for the crate's CCT and Duv: colour-science's Ohno (2013) on the same
locus (the crate's CIE 1931 2° table at 1 nm over 380-770 nm, c2 = 1.4388e-2 m·K) for every
light in data/, beside the exact values `cargo test --release --test integration -- cct:: --nocapture`
prints (docs/colour-temperature-and-calibration.md compares them).

Usage: python3 tools/scripts/cct_colour_science.py   (needs `pip install colour-science`)
"""

import glob
import os
import sys

import numpy as np

try:
    import colour
except ImportError:
    sys.exit("needs colour-science: pip install colour-science")

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
RANGE = (380, 770)


def read_csv(path):
    """The header's names and the rows of a data/ CSV file (wavelength first)."""
    with open(path) as f:
        header = [h.strip().strip('"') for h in f.readline().split(",")]
    return header, np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)


def main():
    _, cmf = read_csv(os.path.join(ROOT, "data", "cmf_cie1931_2deg_1nm.csv"))
    keep = (cmf[:, 0] >= RANGE[0]) & (cmf[:, 0] <= RANGE[1])
    grid, xyz_bar = cmf[keep, 0], cmf[keep, 1:]
    cmfs = colour.MultiSpectralDistributions(
        dict(zip(grid, xyz_bar)), name="data/cmf_cie1931_2deg_1nm.csv, 380-770 nm"
    )
    print("| light | colour-science Ohno 2013: CCT | Duv |")
    print("|---|---|---|")
    files = sorted(glob.glob(os.path.join(ROOT, "data", "illuminant_*.csv")))
    for path in files:
        name = os.path.basename(path)[len("illuminant_"):-len(".csv")]
        _, data = read_csv(path)
        power = np.interp(grid, data[:, 0], data[:, 1])
        x, y, z = (xyz_bar * power[:, None]).sum(axis=0)
        d = x + 15 * y + 3 * z
        uv = np.array([4 * x / d, 6 * y / d])
        cct, duv = colour.temperature.uv_to_CCT_Ohno2013(uv, cmfs, spacing=1.0001)
        print(f"| {name} | {cct:.3f} K | {duv:.6f} |")


if __name__ == "__main__":
    main()
