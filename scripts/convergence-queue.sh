#!/usr/bin/env bash
# Run the convergence sweeps of sweeps/convergence/ (issue 48, docs/convergence.md), each in a
# store of its own (so they share the machine instead of waiting for one another), at idle priority, one
# worker each, exporting each to data/convergence/ every 10 minutes and at its end.
# Resumable: run it again after any stop. On a new machine, first bring back what was exported:
#   for f in data/convergence/conv-*.csv; do cellsweep import "$f" --db STORE_DIR/$(basename "$f" .csv).sqlite; done
#
# Usage: scripts/convergence-queue.sh STORE_DIR [SWEEP...] (SWEEP: a file name under
# sweeps/convergence/ without .toml; default every file there). CELLSWEEP names the binary;
# SWEEPS and DATA another folder of sweep files and of exports (the extensions of open
# columns: SWEEPS=sweeps/extended DATA=data/extended).
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${1:?usage: convergence-queue.sh STORE_DIR [SWEEP...]}
shift
exe=${CELLSWEEP:-target/release/cellsweep}
sweeps=${SWEEPS:-sweeps/convergence}
data=${DATA:-data/convergence}
mkdir -p "$dir" "$data"
# SCHED_IDLE: the workers take only what nothing else wants (nice 19 under setsid still took
# ~70% of a core each from a build); nice where chrt is missing.
if chrt --idle 0 true 2>/dev/null; then idle="chrt --idle 0"; else idle="nice -n 19"; fi
queue=("$@")
[ ${#queue[@]} -gt 0 ] || queue=($(cd "$sweeps" && ls *.toml | sed 's/\.toml$//'))
export_one() { # name store
  "$exe" export --db "$2" --sweep "$1" --out "$data/$1.csv.tmp" >/dev/null 2>&1 &&
    mv "$data/$1.csv.tmp" "$data/$1.csv" || rm -f "$data/$1.csv.tmp"
}
for s in "${queue[@]}"; do
  name=$(sed -n 's/^name = "\(.*\)"/\1/p' "$sweeps/$s.toml")
  db="$dir/$name.sqlite"
  (
    $idle "$exe" run "$sweeps/$s.toml" --db "$db" --workers 1 > "$dir/$name.log" 2>&1 &
    pid=$!
    while kill -0 "$pid" 2>/dev/null; do
      for _ in $(seq 60); do kill -0 "$pid" 2>/dev/null || break; sleep 10; done
      export_one "$name" "$db"
    done
    export_one "$name" "$db"
  ) &
done
wait
