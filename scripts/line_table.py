#!/usr/bin/env python3
"""Every column's beta* over the paper's six diagrams, as the markdown table of docs/line.md.

For each diagram it reads the refined export (data/paper/refined-L{L}-sigma{s}.csv) where there
is one, else the adaptive one, through `cellsweep fit --format json`, and prints per column with
a crossing (or one the grid's last beta leaves open): the model's beta* and 95% interval, the
interval's width (bold above the target), the paper's interpolation, the points the model
read, and the collisions at the crossing still needed for the target width (from
Var(beta*) ~ 1 / (k^2 sum n p (1 - p)): a collision at p = 1/2 adds 1/4). Last, the columns'
deviances pooled: their sum over their summed degrees of freedom is the dispersion the points
show about their curves (1 for binomial scatter; above 1 if, say, the prep a point's replicates
share spread the points more than their counts allow).

Usage: scripts/line_table.py [CELLSWEEP] [WIDTH]
"""
import json
import os
import subprocess
import sys

binary = sys.argv[1] if len(sys.argv) > 1 else "target/release/cellsweep"
width = float(sys.argv[2]) if len(sys.argv) > 2 else 1.0

print("| L | sigma | alpha | beta* (model) [95%] | width | interpolated | points | still needed | data |")
print("|---|---|---|---|---|---|---|---|---|")
total = 0.0
deviance, df = 0.0, 0
for sigma in (5, 0):
    for L in (90, 80, 70):
        path = f"data/paper/refined-L{L}-sigma{sigma}.csv"
        if not os.path.exists(path):
            path = f"data/paper/adaptive-L{L}-sigma{sigma}.csv"
        fit = json.loads(
            subprocess.check_output([binary, "fit", "--data", path, "--format", "json"])
        )
        for c in fit["columns"]:
            interp = c.get("interpolated")
            interp = f"{interp:.2f}" if interp is not None else "-"
            head = f"| {L} | {sigma} | {c['alpha']:.2f} |"
            data = os.path.basename(path).split("-")[0]
            if c["beta_star"] is None:
                if "last beta" in (c.get("skipped") or ""):
                    print(f"{head} open above beta = 50 | - | {interp} | | | {data} |")
                continue
            lo, hi = c["beta_ci"]
            w = hi - lo
            model = c["model"]
            deviance += model["deviance"]
            df += model["df"]
            k = model["slope"]
            # The information the interval implies, and what a width of `width` needs
            # (aiming 3% below it, as the rounds stop at the first width under it).
            info = (3.92 / (k * w)) ** 2
            need = max(0.0, info * ((w / (0.97 * width)) ** 2 - 1) / 0.25) if w > width else 0.0
            total += need
            shown = f"**{w:.2f}**" if w > width else f"{w:.2f}"
            # A separated column (training at one row, walk-past at the next) is as wide as
            # the gap between its rows whatever its replicates: it needs betas in the gap.
            needed = f"{need:,.0f}" if need >= 1 or w <= width else "betas in the gap"
            print(
                f"{head} {c['beta_star']:.2f} [{lo:.2f}, {hi:.2f}] | {shown} | {interp} | "
                f"{model['points']} | {needed} | {data} |"
            )
print(f"\nstill needed in all: about {total:,.0f} collisions near the crossings")
print(
    f"pooled deviance of the column models: {deviance:.1f} on {df} df "
    f"(dispersion {deviance / df:.2f})"
)
