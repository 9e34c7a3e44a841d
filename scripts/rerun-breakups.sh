#!/usr/bin/env bash
# Rerun what a change of the breakup rule can change in committed exports, and nothing else
# (SPEC section 5, docs/model.md): import the exports of one sweep file into a fresh store
# (every prep recomputed and checked), put back the stored breakups (`reset --breakups`), run
# the sweep again (the rest keeps its results; adaptive points grow as their rule says), and
# export it over the file. Resumable: run it again after any stop (an existing store is reused).
#
# Usage: scripts/rerun-breakups.sh STORE_DIR SWEEP_FILE EXPORT... (the exports of that sweep,
# e.g. sweeps/refined/L70-sigma5.toml data/paper/refined-L70-sigma5.csv). CELLSWEEP names the
# binary; WORKERS the number of workers (2).
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${1:?usage: rerun-breakups.sh STORE_DIR SWEEP_FILE EXPORT...}
sweep_file=${2:?usage: rerun-breakups.sh STORE_DIR SWEEP_FILE EXPORT...}
shift 2
exe=${CELLSWEEP:-target/release/cellsweep}
mkdir -p "$dir"
name=$(sed -n 's/^name = "\(.*\)"/\1/p' "$sweep_file")
for export in "$@"; do
  db="$dir/$(basename "$export" .csv).sqlite"
  if [ ! -e "$db.imported" ]; then
    rm -f "$db" "$db.lock"
    # Rows decided by a prep that broke up are left out of the import: the rule may decide
    # that prep otherwise now (its recomputed hash would refuse the file), and they are
    # exactly what `reset --breakups` puts back; the run computes their prep again.
    python3 - "$export" "$db.rows.csv" <<'PY'
import csv, sys
src, dst = sys.argv[1], sys.argv[2]
with open(src, newline="") as f:
    lines = f.readlines()
head, body = lines[:2], lines[2:]
rows = list(csv.reader(body))
k = rows[0].index("verdict")
with open(dst, "w", newline="") as f:
    f.writelines(head)
    w = csv.writer(f, lineterminator="\n")
    w.writerow(rows[0])
    w.writerows(r for r in rows[1:] if r[k] != "breakup")
PY
    "$exe" import "$db.rows.csv" --db "$db"
    rm -f "$db.rows.csv"
    "$exe" reset --db "$db" --sweep "$name" --breakups
    touch "$db.imported"
  fi
  "$exe" run "$sweep_file" --db "$db" --workers "${WORKERS:-2}"
  "$exe" export --db "$db" --sweep "$name" --out "$export.tmp"
  mv "$export.tmp" "$export"
done
