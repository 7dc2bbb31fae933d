#!/usr/bin/env bash
# The test command (scripts/test.sh) with the CPUs saturated by another load, as a loaded CI
# machine would have them: a test that passes here does not depend on how fast the machine is.
#   bash scripts/test-under-load.sh [--runs N] [--load-per-cpu K]
# runs scripts/test.sh N times in a row (default 1) beside `stress-ng --cpu (K x nproc)` (default
# K = 1), and ctest with twice as many jobs as cores; it stops at the first failing run.
set -euo pipefail
cd "$(dirname "$0")/.."
runs=1
per_cpu=1
while [ $# -gt 0 ]; do
  case "$1" in
    --runs) runs="$2"; shift 2 ;;
    --load-per-cpu) per_cpu="$2"; shift 2 ;;
    -h|--help) sed -n '2,7p' "$0"; exit 0 ;;
    *) echo "test-under-load: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
bash scripts/setup.sh
workers=$(( $(nproc) * per_cpu ))
stress-ng --cpu "$workers" --timeout 0 --quiet &
stress_pid=$!
trap 'kill "$stress_pid" 2>/dev/null || true; wait "$stress_pid" 2>/dev/null || true' EXIT
echo "test-under-load: stress-ng --cpu $workers running beside the tests (pid $stress_pid)"
for i in $(seq 1 "$runs"); do
  start=$(date +%s)
  echo "== run $i of $runs under load (uptime: $(uptime | sed 's/.*load average/load average/')) =="
  HD_TEST_JOBS=$(( 2 * $(nproc) )) bash scripts/test.sh
  echo "== run $i passed in $(( $(date +%s) - start )) s =="
done
