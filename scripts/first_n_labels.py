#!/usr/bin/env python3
"""Labels of an adaptive export against the same sweep cut to its first N replicates.

An adaptive point holds exactly the first n replicates of the fixed sweep with the same seed,
so where n >= N the first N rows are the fixed N-replicate sweep's, row for row. Prints, per
point, the final label and the label at N (SPEC section 6), and a summary.

Usage: scripts/first_n_labels.py EXPORT.csv [N]
"""
import csv
import sys
from collections import defaultdict

path, N = sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 24
rows = defaultdict(dict)
with open(path) as f:
    for r in csv.DictReader(line for line in f if not line.startswith("#")):
        rows[(float(r["alpha"]), float(r["beta"]))][int(r["replicate"])] = r


def label(reps):
    n = len(reps)
    verdicts = {r["verdict"] for r in reps}
    if verdicts != {"ok"}:
        return verdicts.pop() if len(verdicts) == 1 else "mixed-verdict"
    c = defaultdict(int)
    for r in reps:
        c[r["outcome"]] += 1
    for o in ("train", "walk_past", "reversal", "undetermined"):
        if c[o] >= 0.55 * n:
            return o
    w, t = c["walk_past"], c["train"]
    if abs(w - t) < 0.1 * n and w + t >= 0.5 * n:
        return "coexist"
    return "mixed"


same = differ = short = 0
for (a, b), reps in sorted(rows.items()):
    ordered = [reps[k] for k in sorted(reps)]
    final = label(ordered)
    if len(ordered) >= N and sorted(reps)[:N] == list(range(N)):
        at_n = label(ordered[:N])
        same += at_n == final
        differ += at_n != final
        mark = "" if at_n == final else "  <- differs"
        print(f"alpha {a:<5} beta {b:<4} n {len(ordered):>3}  final {final:<12} first {N}: {at_n}{mark}")
    else:
        short += 1
print(f"points with n >= {N}: {same + differ} ({same} same label, {differ} different); "
      f"{short} settled before {N}")
