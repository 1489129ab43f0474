#!/usr/bin/env python3
"""The independent reference for the crate's CCT and Duv: colour-science's Ohno (2013) on the
standard locus (colour-science's own CIE 1931 2° table, 360-830 nm at 1 nm, and its
`planck_law` with c2 = 1.4388e-2 m·K: CIE 015's definition), for the CIE illuminants whose
literals `tests/cct.rs` holds (`the_cie_illuminants_against_colour_science`).

The XYZ fed to it is computed here the way the test computes it, by a plain method: each light's
5 nm file linearly interpolated to every nm from 360 to 830, zero outside the file's range,
times data/cmf_cie1931_2deg_1nm.csv (identical to colour-science's table: the script checks),
summed (dλ = 1 nm). The script prints those XYZ, the CCT and Duv as the test's Rust literals.

Settings: `uv_to_CCT_Ohno2013(uv, cmfs, start=900, end=120000, spacing=1.00003)`. The default
spacing (1.001) errs by up to 5e-4 mired on the locus; at 1.00003, with the table's ends moved
beyond 1000-100 000 K (colour-science's table steps 1 K at its start, coarse there), it gives
the temperature of 40 blackbodies (1000-100 000 K, log-spaced, uv from colour-science's
`CCT_to_uv_Planck1900`) within 5e-7 mired and Duv within 1e-10. A second, plain check of each
light's answer: golden-section search for the nearest point of the same locus (distance in uv
as a function of mired, colour-science's `CCT_to_uv_Planck1900`), which the script prints
beside it; the two agree within the printed bounds.

Usage: python3 tools/scripts/cct_colour_science.py   (needs `pip install colour-science`;
colour-science 0.4.7 from PyPI gave the literals in tests/cct.rs)
"""

import math
import os
import sys
import warnings

import numpy as np

warnings.filterwarnings("ignore")
try:
    import colour
except ImportError:
    sys.exit("needs colour-science: pip install colour-science")

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
LIGHTS = ["A", "D50", "D65", "F2", "F11", "LED_B2"]
OHNO = dict(start=900, end=120000, spacing=1.00003)


def read_csv(path):
    """The rows of a data/ CSV file (wavelength first), after its header line."""
    return np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)


def cmfs():
    """colour-science's CIE 1931 2° table (360-830 nm, 1 nm), checked against data/'s copy."""
    c = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    data = read_csv(os.path.join(ROOT, "data", "cmf_cie1931_2deg_1nm.csv"))
    assert c.shape.start == 360 and c.shape.end == 830 and c.shape.interval == 1
    assert np.array_equal(data[:, 0], c.wavelengths)
    assert np.array_equal(data[:, 1:], c.values), "data/ and colour-science's tables differ"
    return c


def xyz_of(light, c):
    """XYZ of a light's file: linear interpolation to 1 nm over 360-830 nm, zero outside the
    file's range, a plain sum against x̄ȳz̄."""
    data = read_csv(os.path.join(ROOT, "data", f"illuminant_{light}.csv"))
    grid = c.wavelengths
    power = np.interp(grid, data[:, 0], data[:, 1], left=0.0, right=0.0)
    return (c.values * power[:, None]).sum(axis=0)


def uv_of(xyz):
    x, y, z = xyz
    d = x + 15 * y + 3 * z
    return np.array([4 * x / d, 6 * y / d])


def golden(uv, c, cct):
    """The nearest point of colour-science's locus to uv by golden-section search in mired
    around `cct` (±1 mired), and the signed distance (positive above the locus)."""
    def dist(mired):
        p = colour.temperature.CCT_to_uv_Planck1900(1e6 / mired, c)
        return math.hypot(uv[0] - p[0], uv[1] - p[1])

    m = 1e6 / cct
    lo, hi = m - 1.0, m + 1.0
    g = (math.sqrt(5) - 1) / 2
    a, b = hi - g * (hi - lo), lo + g * (hi - lo)
    fa, fb = dist(a), dist(b)
    while hi - lo > 1e-9:
        if fa < fb:
            hi, b, fb = b, a, fa
            a = hi - g * (hi - lo)
            fa = dist(a)
        else:
            lo, a, fa = a, b, fb
            b = lo + g * (hi - lo)
            fb = dist(b)
    m = 0.5 * (lo + hi)
    p = colour.temperature.CCT_to_uv_Planck1900(1e6 / m, c)
    q = colour.temperature.CCT_to_uv_Planck1900(1e6 / (m + 1e-3), c)
    # The tangent (toward lower T) turned anticlockwise points up, toward green.
    t = q - p
    side = (uv[1] - p[1]) * t[0] - (uv[0] - p[0]) * t[1]
    return 1e6 / m, math.copysign(dist(m), side)


def main():
    c = cmfs()
    ts = np.geomspace(1000, 100000, 40)
    r = colour.temperature.uv_to_CCT_Ohno2013(
        colour.temperature.CCT_to_uv_Planck1900(ts, c), c, **OHNO
    )
    print(
        f"# colour-science {colour.__version__}, Ohno 2013 {OHNO} on 40 blackbodies: "
        f"max |Δμ| {np.abs(1e6 / r[:, 0] - 1e6 / ts).max():.1e} mired, "
        f"max |Duv| {np.abs(r[:, 1]).max():.1e}"
    )
    for light in LIGHTS:
        xyz = xyz_of(light, c)
        uv = uv_of(xyz)
        cct, duv = colour.temperature.uv_to_CCT_Ohno2013(uv, c, **OHNO)
        g_cct, g_duv = golden(uv, c, cct)
        print(
            f"# {light}: golden-section {g_cct:.6f} K, {g_duv:.10f}: "
            f"Δμ {abs(1e6 / g_cct - 1e6 / cct):.1e} mired, ΔDuv {abs(g_duv - duv):.1e}"
        )
        print(
            f'    ("{light}", [{xyz[0]:.10e}, {xyz[1]:.10e}, {xyz[2]:.10e}], '
            f"{cct:.6f}, {duv:.10f}),"
        )


if __name__ == "__main__":
    main()
