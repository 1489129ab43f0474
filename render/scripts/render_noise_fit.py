#!/usr/bin/env python3
"""Fits e² = b² + σ²/spp to each method's curve in the render tool's error_vs_render_time.csv
(least squares in e² against 1/spp over the levels of at least --min-spp paths a pixel) and
prints, per scene, b and σ of RGB, the 8-node fixed set and the random-wavelength methods at 4
a path, with each random method's σ over the 8-node set's.

Where a curve stops (`render/src/render/curves.rs`: its mean fell by less than 5 % over the last
doubling), σ²/spp = x·b² with x = 0.228; an unbiased method at the same paths has error
σ_r/√spp = (σ_r/σ_8)·√x·b, which is below the fixed set's b·√(1 + x) when σ_r/σ_8 < 2.32: the
random method then passes below the fixed set before the fixed set's curve has flattened,
whatever its bias b.

    python3 render/scripts/render_noise_fit.py docs/render-time/error_vs_render_time.csv
"""
import argparse
import collections
import csv
import math

# The flattening criterion's noise share: (1 + x) / (1 + x/2) = 1.05², solved for x.
X = (1.05**2 - 1) / (1 - 1.05**2 / 2)
LIMIT = math.sqrt((1 + X) / X)


def fit(points, min_spp):
    pts = [(1.0 / spp, e * e) for spp, e in points if spp >= min_spp]
    n = len(pts)
    mx = sum(x for x, _ in pts) / n
    my = sum(y for _, y in pts) / n
    s2 = sum((x - mx) * (y - my) for x, y in pts) / sum((x - mx) ** 2 for x, _ in pts)
    return math.sqrt(max(my - s2 * mx, 0.0)), math.sqrt(max(s2, 0.0))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("csv")
    parser.add_argument("--min-spp", type=int, default=32)
    args = parser.parse_args()
    curves = collections.defaultdict(list)
    with open(args.csv, newline="") as f:
        for row in csv.DictReader(f):
            key = (row["scene"], row["light"], row["method"])
            curves[key].append((int(row["spp"]), float(row["mean_de00"])))
    print(f"flattening leaves noise x = {X:.3f} of b²; a random method passes first when its σ is below {LIMIT:.2f} × the fixed set's")
    print("scene\tlight\tmethod\tb\tsigma\tsigma / fixed 8's")
    for scene, light in sorted({(s, l) for s, l, _ in curves}):
        fixed = curves.get((scene, light, "fixed 8"))
        if not fixed:
            continue
        _, s8 = fit(fixed, args.min_spp)
        for method in ["RGB", "fixed 8", "pbrt-v4 visible ×4", "hero ×4"]:
            points = curves.get((scene, light, method))
            if not points:
                continue
            b, s = fit(points, args.min_spp)
            print(f"{scene}\t{light}\t{method}\t{b:.3f}\t{s:.1f}\t{s / s8:.2f}")


if __name__ == "__main__":
    main()
