#!/usr/bin/env python3
"""Do the columns' beta* depend on their far points? An independent check of the column model.

For each column with a crossing in the six refined exports (data/paper/refined-L{L}-sigma{s}.csv)
it reads the replicates straight from the CSV, counts walk-past and training per beta, and fits
p_walk = 1 / (1 + exp(-(b0 + b1 (beta - m)))) by Newton's method (a transcription apart from
crates/stats), first over the whole column, then only over the points within 6 and within 4 of
`cellsweep fit`'s beta*. beta* = m - b0 / b1 with its delta-method sd. If the curve were not
logistic, the far points would pull the whole-column crossing and the windows would move it by
more than its sd. "no fit" where Newton's method does not converge to a finite slope (walk-past
and training separated within the window, or a whole column that crosses back, which the model
cuts at `cut_at` and this script does not).

Usage: scripts/crossing_windows.py [CELLSWEEP]
"""
import collections
import csv
import json
import math
import subprocess
import sys

binary = sys.argv[1] if len(sys.argv) > 1 else "target/release/cellsweep"


def logistic(points):
    """beta*, its sd, from (beta, walk, train) points; None where separated."""
    m = sum(b * (w + t) for b, w, t in points) / sum(w + t for _, w, t in points)
    b0, b1 = 0.0, 0.3
    for _ in range(200):
        g0 = g1 = h00 = h01 = h11 = 0.0
        for b, w, t in points:
            n = w + t
            z = max(-700.0, min(700.0, b0 + b1 * (b - m)))
            p = 1.0 / (1.0 + math.exp(-z))
            r, v = w - n * p, n * p * (1 - p)
            g0 += r
            g1 += r * (b - m)
            h00 += v
            h01 += v * (b - m)
            h11 += v * (b - m) ** 2
        det = h00 * h11 - h01 * h01
        if det <= 1e-12:
            return None
        d0, d1 = (h11 * g0 - h01 * g1) / det, (h00 * g1 - h01 * g0) / det
        b0, b1 = b0 + d0, b1 + d1
        if abs(d0) + abs(d1) < 1e-10:
            break
    else:
        return None
    if abs(b1) < 1e-9 or abs(b1) > 50:
        return None
    c00, c11, c01 = h11 / det, h00 / det, -h01 / det
    g = (-1.0 / b1, b0 / b1**2)
    var = g[0] ** 2 * c00 + 2 * g[0] * g[1] * c01 + g[1] ** 2 * c11
    return m - b0 / b1, math.sqrt(var)


print("| L | sigma | alpha | cellsweep fit | whole column | within 6 | within 4 |")
print("|---|---|---|---|---|---|---|")
for sigma in (5, 0):
    for L in (90, 80, 70):
        path = f"data/paper/refined-L{L}-sigma{sigma}.csv"
        fit = json.loads(
            subprocess.check_output([binary, "fit", "--data", path, "--format", "json"])
        )
        counts = collections.defaultdict(lambda: [0, 0])
        with open(path) as f:
            for r in csv.DictReader(line for line in f if not line.startswith("#")):
                key = (float(r["alpha"]), float(r["beta"]))
                if r["outcome"] == "walk_past":
                    counts[key][0] += 1
                elif r["outcome"] == "train":
                    counts[key][1] += 1
        for c in fit["columns"]:
            if c["beta_star"] is None:
                continue
            star = c["beta_star"]
            lo, hi = c["beta_ci"]
            pts = [(b, w, t) for (a, b), (w, t) in counts.items() if abs(a - c["alpha"]) < 1e-9]
            cells = []
            for window in (math.inf, 6, 4):
                got = logistic([p for p in pts if abs(p[0] - star) <= window])
                cells.append(f"{got[0]:.2f} ± {got[1]:.2f}" if got else "no fit")
            print(
                f"| {L} | {sigma} | {c['alpha']:.2f} | {star:.2f} ± {(hi - lo) / 3.92:.2f} | "
                + " | ".join(cells)
                + " |"
            )
