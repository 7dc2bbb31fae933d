#!/usr/bin/env bash
# Bandwidth follows the view (issue 12 item 5; docs/network.md): the default scene as two
# processes on loopback (hybrid-remote --scene scenes/default.yaml -> hybrid-station run
# --cameras-from), twice: with the station's view feedback followed, then with
# `hybrid-remote --full-rate` (every camera at full rate). Prints bytes per second per camera from
# the station's counters (summary.json network_cameras.bytes over the run's seconds) and the
# frames shown as video. Needs a build (cmake --build build --target hybrid-station hybrid-remote).
#
#   bash scripts/view-bandwidth.sh [OUT_DIR]      # default out/view-bandwidth
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/view-bandwidth}
mkdir -p "$out"
. scripts/lib/two-process.sh
port=$(free_udp_block 6600 7600)
[ -n "$port" ] || { echo "view-bandwidth: no 16 free UDP ports on 127.0.0.1" >&2; exit 1; }
trap stop_remote EXIT
for mode in follow full; do
  flag=""
  [ "$mode" = full ] && flag="--full-rate"
  epoch=$(python3 -c 'import time; print("%.3f" % (time.time() + 4))')
  ./build/bin/hybrid-remote --scene scenes/default.yaml --to "rtp://127.0.0.1:$port" \
    --scene-epoch "$epoch" --seconds 300 $flag >"$out/remote-$mode.log" 2>&1 &
  remote_pid=$!
  ./build/bin/hybrid-station run --scene scenes/default.yaml --headless --rate 90 \
    --cameras-from "rtp://127.0.0.1:$port" --scene-epoch "$epoch" --out "$out/$mode" \
    >"$out/station-$mode.log" 2>&1
  stop_remote
done
python3 - "$out" <<'PY'
import json, sys
out = sys.argv[1]
runs = {m: json.load(open(f"{out}/{m}/summary.json")) for m in ("follow", "full")}
# The load moves both runs' absolute rates (a loaded sender sends fewer frames of every camera),
# so each camera is also given relative to camera 0 of the same run: cam0 and its stereo twin are
# kept at full rate (the model updater reconstructs from them), so the relative figure shows what
# following the view saved.
print("| camera | bytes/s, view followed | bytes/s, every camera at full rate "
      "| / camera 0, view followed | / camera 0, full rate | need changes |")
print("|---|---|---|---|---|---|")
tot = {"follow": 0.0, "full": 0.0}
rate = {m: [n["bytes"] / r["seconds"] for n in r["network_cameras"]] for m, r in runs.items()}
for i, n in enumerate(runs["follow"]["network_cameras"]):
    f, a = rate["follow"][i], rate["full"][i]
    tot["follow"] += f
    tot["full"] += a
    print(f"| {n['camera']} | {f:,.0f} | {a:,.0f} | {f / rate['follow'][0]:.2f} "
          f"| {a / rate['full'][0]:.2f} | {n.get('need_changes', 0)} |")
print(f"| all | {tot['follow']:,.0f} | {tot['full']:,.0f} | {tot['follow'] / rate['follow'][0]:.2f} "
      f"| {tot['full'] / rate['full'][0]:.2f} | |")
for m, r in runs.items():
    v = r["variant_frames"]
    print(f"{m}: {r['seconds']:.1f} s, {r['frames']} station frames; variant frames {v}")
PY
