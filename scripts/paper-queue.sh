#!/usr/bin/env bash
# Run the paper's checks and diagrams one after another in one store, exporting each to
# data/paper/ when it is done (the sigma = 0 diagrams reuse the sigma = 5 preps: one store).
# Order: the checks first (minutes), then the diagrams in the order that tests the most of the
# paper's claims soonest (sigma 0 at L = 90: reversals and the shift; L = 70: the spacing),
# each sigma = 0 diagram right after its sigma = 5 one, whose preps it reuses.
# Resumable: run it again after any stop; finished sweeps say "nothing to run".
#
# Usage: scripts/paper-queue.sh [STORE [SWEEP...]] (default paper.sqlite and every sweep below,
# SWEEP as a path under sweeps/ without .toml); runs niced, 2 workers.
# On a new machine, first bring back what data/paper/ holds of the sweeps to run:
#   for f in data/paper/*.csv; do cellsweep import "$f" --db paper.sqlite; done
set -euo pipefail
cd "$(dirname "$0")/.."
db=${1:-paper.sqlite}
shift || true
exe=${CELLSWEEP:-target/release/cellsweep}
queue=(adaptive/L90-sigma5 check-spindle check-speed-alpha0.20 adaptive/L90-sigma0
       adaptive/L70-sigma5 adaptive/L70-sigma0 adaptive/L80-sigma5 adaptive/L80-sigma0)
[ $# -gt 0 ] && queue=("$@")
for s in "${queue[@]}"; do
  name=$(sed -n 's/^name = "\(.*\)"/\1/p' "sweeps/$s.toml")
  nice -n 19 "$exe" run "sweeps/$s.toml" --db "$db" --workers 2
  "$exe" export --db "$db" --sweep "$name" --out "data/paper/$name.csv"
done
