#!/usr/bin/env bash
# The store at scale: register a sweep of about ten million jobs and time what a user does
# with it (issue 30; figures in docs/performance.md).
#
#   scripts/bench-store.sh [ALPHA_STEP] [DIR]
#
# ALPHA_STEP 0.0002 (the default) gives alpha 0.01..0.20 (951 values) x beta 10..50 step 0.4
# (101 values) = 96,051 points x 96 replicates = 9,220,896 jobs; 0.002 gives a tenth of that.
# DIR (default: a fresh folder under /tmp) keeps the store. Each step prints its wall time and
# peak memory (GNU time); the store's size is given per pending job; then `collect` of Slurm
# records (examples/bench_collect.rs in the scheduler crate). Needs the release
# binary (cargo build --release), python3 (to watch the store during a run) and curl.
set -euo pipefail
cd "$(dirname "$0")/.."
step=${1:-0.0002}
dir=${2:-$(mktemp -d /tmp/cellsweep-bench-store.XXXXXX)}
bin=$PWD/target/release/cellsweep
[ -x "$bin" ] || { echo "build first: cargo build --release" >&2; exit 1; }
mkdir -p "$dir"
db=$dir/scale.sqlite
rm -f "$db" "$db-wal" "$db-shm"
cat > "$dir/scale.toml" <<EOF
name = "scale"
seed = 1
replicates = 96
[grid]
alpha = { from = 0.01, to = 0.20, step = $step }
beta  = { from = 10, to = 50, step = 0.4 }
L     = [90]
sigma = [5]
[protocol]
precision = "f32"
EOF

timed() { # timed LABEL COMMAND...: wall seconds and peak resident memory of one command
  local label=$1; shift
  /usr/bin/time -f "%e %M" -o "$dir/time" "$@" > "$dir/out" 2>&1 || true
  read -r s kb < "$dir/time"
  printf '%-34s %8.2f s %8.0f MB\n' "$label" "$s" "$((kb / 1024))"
}

echo "store benchmark in $dir (cellsweep $("$bin" --version | cut -d' ' -f2), $(nproc) cores)"
timed "run --dry-run" "$bin" run "$dir/scale.toml" --db "$db" --dry-run
grep -m1 "jobs in the first\|points" "$dir/out" | sed 's/^/    /'

# Registration, then the first dispatch: a run that is stopped as soon as its first prep is
# running. Registration ends when `run` announces the sweep; the first dispatch when the store
# shows a prep running.
start=$(date +%s.%N)
/usr/bin/time -f "%M" -o "$dir/run.time" "$bin" run "$dir/scale.toml" --db "$db" --workers 1 \
  > "$dir/run.out" 2>&1 &
pid=$!
python3 - "$db" "$dir/run.out" "$start" <<'EOF'
import sqlite3, sys, time
db, out, start = sys.argv[1], sys.argv[2], float(sys.argv[3])
registered = None
while True:
    text = open(out).read()
    if registered is None and ("registered" in text or "resuming" in text):
        registered = time.time() - start
    if registered is not None:
        try:
            c = sqlite3.connect(f"file:{db}?mode=ro", uri=True, timeout=0.1)
            n = c.execute("SELECT COUNT(*) FROM preps WHERE state = 'running'").fetchone()[0]
            c.close()
            if n > 0:
                break
        except sqlite3.Error:
            pass
    if time.time() - start > 3600:
        sys.exit("no dispatch within an hour")
    time.sleep(0.05)
print(f"{'registration (run until announced)':<34} {registered:8.2f} s")
print(f"{'first dispatch (run start to it)':<34} {time.time() - start:8.2f} s")
EOF
t0=$(date +%s.%N)
pkill -INT -P "$pid"; wait "$pid" || true  # (the run is the child of GNU time)
printf '%-34s %8.2f s %8.0f MB (peak of the run)\n' "stop on Ctrl-C (with its summary)" \
  "$(python3 -c "import sys; print(float(sys.argv[2]) - float(sys.argv[1]))" "$t0" "$(date +%s.%N)")" \
  "$(( $(tail -1 "$dir/run.time") / 1024 ))"
# Jobs registered (planned ones included: they have no row until a run is about to send them).
read -r jobs rows < <(python3 -c "
import sqlite3, sys
c = sqlite3.connect(sys.argv[1])
print(c.execute('SELECT SUM(pending + running + done + failed) FROM point_progress').fetchone()[0],
      c.execute('SELECT COUNT(*) FROM jobs').fetchone()[0])" "$db")
bytes=$(stat -c %s "$db")
echo "    $jobs jobs ($rows of them rows); store $((bytes / 1000000)) MB = $((bytes / jobs)) bytes per job"
timed "status" "$bin" status --db "$db"
timed "status --json" "$bin" status --db "$db" --json
timed "table" "$bin" table --db "$db"
timed "export (no results yet)" "$bin" export --db "$db" --out "$dir/scale.csv"

# The live page (`cellsweep serve`): its first answer gathers a snapshot of the store (what
# every refresh after a write does), the second is served from it.
port=$(python3 -c "import socket; s = socket.socket(); s.bind(('127.0.0.1', 0)); print(s.getsockname()[1])")
"$bin" serve --db "$db" --port "$port" > "$dir/serve.out" 2>&1 &
spid=$!
for _ in $(seq 100); do grep -q serving "$dir/serve.out" 2>/dev/null && break; sleep 0.1; done
for what in "live page, a new snapshot" "live page, unchanged"; do
  printf '%-34s %8.2f s\n' "$what" \
    "$(curl -s -o /dev/null -w '%{time_total}' "http://127.0.0.1:$port/api/live?since=0")"
done
kill -INT "$spid"; wait "$spid" || true
# `collect` of Slurm records: a million at the full size (a tenth with step 0.002), made by the
# example (a million collisions would take core-years to run) and checked and committed as real
# ones are.
records=$(python3 -c "import sys; print(min(1000000, round(100000 * 0.002 / float(sys.argv[1]))))" "$step")
cargo build --release --quiet -p cellsweep-scheduler --example bench_collect
/usr/bin/time -f "%M" -o "$dir/collect.time" \
  target/release/examples/bench_collect "$records" "$dir/collect" | sed 's/^/    /'
echo "    (peak memory $(( $(tail -1 "$dir/collect.time") / 1024 )) MB)"
echo "    ($dir kept: rm -r it when done)"
