#!/usr/bin/env python3
"""Cost of a sweep in a store: collisions run, CPU time of collisions and preps (core-hours).

Usage: scripts/paper_stats.py STORE.sqlite SWEEP_NAME
"""
import sqlite3
import sys

db, name = sys.argv[1], sys.argv[2]
c = sqlite3.connect(f"file:{db}?mode=ro", uri=True)
sweep = c.execute("SELECT id FROM sweeps WHERE name = ?", (name,)).fetchone()[0]
row = c.execute(
    """SELECT COUNT(*), SUM(r.wall_s), SUM(r.outcome IS NOT NULL)
       FROM results r JOIN jobs j ON j.id = r.job_id JOIN points p ON p.id = j.point_id
       WHERE p.sweep_id = ?""",
    (sweep,),
).fetchone()
preps = c.execute(
    """SELECT COUNT(*), SUM(pr.wall_s) FROM preps pr
       WHERE pr.id IN (SELECT j.prep_id FROM jobs j JOIN points p ON p.id = j.point_id
                       WHERE p.sweep_id = ?)""",
    (sweep,),
).fetchone()
points = c.execute("SELECT COUNT(*) FROM points WHERE sweep_id = ?", (sweep,)).fetchone()[0]
print(f"{name}: {points} points, {row[0]} results, {row[2]} collisions run "
      f"({row[1] / 3600:.2f} core-hours), {preps[0]} preps ({(preps[1] or 0) / 3600:.2f} core-hours)")
