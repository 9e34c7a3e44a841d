#!/usr/bin/env bash
# The headless browser of the report's test: Debian's chromium, installed if it is missing.
#
#   scripts/chromium-local.sh up    install chromium (apt, as root) unless one is on this
#                                   machine; idempotent; prints the browser's path
#
# The test (tests/report.rs) runs this itself, as the Slurm tests run scripts/slurm-local.sh,
# so `cargo test --release --workspace` needs nothing installed beforehand beyond Rust.
set -euo pipefail

log() { echo "chromium-local: $*" >&2; }

find_browser() {
  local b
  for b in "${CELLSWEEP_BROWSER:-}" /usr/bin/chromium /usr/bin/chromium-browser /usr/bin/google-chrome; do
    [ -n "$b" ] && [ -x "$b" ] && { echo "$b"; return 0; }
  done
  return 1
}

up() {
  if find_browser; then return 0; fi
  if [ "$(id -u)" != 0 ]; then
    log "no chromium here and not root: install Debian's chromium (sudo apt-get install chromium) or set CELLSWEEP_BROWSER"
    return 1
  fi
  log "installing chromium (Debian)"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends chromium fonts-dejavu-core >/dev/null
  find_browser || { log "chromium installed but not found at /usr/bin/chromium"; return 1; }
}

case "${1:-}" in
  up) up ;;
  *) echo "usage: $0 up" >&2; exit 2 ;;
esac
