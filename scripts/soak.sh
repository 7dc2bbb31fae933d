#!/usr/bin/env bash
# Soak of the simulated station (a benchmark, not CI): builds, runs the default scene headless at
# 90 Hz for --minutes N (default 60) with its motion looped (--loop: the head goes away from the
# camera and back every 20 s for the whole run, so every lap exercises video, hybrid and
# synthetic and the transitions between them), samples the process's VmRSS every 10 s from
# /proc/<pid>/status into a CSV, and at the end prints RSS at start / end, the least-squares RSS
# slope, and the missed-deadline rate from the run's summary.json.
#
#   scripts/soak.sh [--minutes N] [--out DIR] [--build DIR] [--scene FILE] [-- extra run options]
set -euo pipefail
cd "$(dirname "$0")/.."
minutes=60
out=out/soak
build=build
scene=scenes/default.yaml
extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --minutes) minutes="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --build) build="$2"; shift 2 ;;
    --scene) scene="$2"; shift 2 ;;
    --) shift; extra=("$@"); break ;;
    *) echo "soak.sh: unknown option $1 (--minutes N, --out DIR, --build DIR, --scene FILE)" >&2
       exit 2 ;;
  esac
done
if ! [[ "$minutes" =~ ^[0-9]+([.][0-9]+)?$ ]]; then
  echo "soak.sh: --minutes expects a number, got '$minutes'" >&2
  exit 2
fi

export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo > /dev/null
cmake --build "$build" -j"$(nproc)" --target hybrid-station
mkdir -p "$out"
seconds=$(python3 -c "print(float('$minutes') * 60)")
rss_csv="$out/rss.csv"

echo "== soak: $scene, ${minutes} min at 90 Hz, headless; RSS every 10 s -> $rss_csv =="
"./$build/bin/hybrid-station" run --scene "$scene" --headless --rate 90 --seconds "$seconds" \
  --loop --out "$out" "${extra[@]}" > "$out/run.log" 2>&1 &
pid=$!
trap 'kill "$pid" 2>/dev/null || true' INT TERM
echo "t_s,vmrss_kb" > "$rss_csv.tmp"
samples=0
start=$(date +%s.%N)
while kill -0 "$pid" 2>/dev/null; do
  # Sample every 10 s from t = 10 s (a sample at 0 s would be the process before it set up), but
  # notice the end of the run within a second.
  for _ in $(seq 10); do kill -0 "$pid" 2>/dev/null || break; sleep 1; done
  rss=$(awk '/^VmRSS:/ {print $2}' "/proc/$pid/status" 2>/dev/null || true)
  if [ -n "$rss" ]; then
    now=$(date +%s.%N)
    printf '%.1f,%s\n' "$(python3 -c "print($now - $start)")" "$rss" >> "$rss_csv.tmp"
    samples=$((samples + 1))
    # Once a minute, the station's own progress line (frames, missed deadlines, variants).
    if [ $((samples % 6)) -eq 0 ]; then grep '] frames ' "$out/run.log" | tail -1 || true; fi
  fi
done
rc=0
wait "$pid" || rc=$?
mv "$rss_csv.tmp" "$rss_csv"
if [ "$rc" -ne 0 ]; then
  echo "soak.sh: hybrid-station exited with $rc; its output:" >&2
  tail -20 "$out/run.log" >&2
  exit "$rc"
fi
tail -16 "$out/run.log"

python3 - "$rss_csv" "$out/summary.json" <<'PY'
import csv, json, sys
rows = [(float(r["t_s"]), float(r["vmrss_kb"])) for r in csv.DictReader(open(sys.argv[1]))]
s = json.load(open(sys.argv[2]))
print("== soak result ==")
if len(rows) >= 2:
    n = len(rows)
    mt = sum(t for t, _ in rows) / n
    mr = sum(r for _, r in rows) / n
    var = sum((t - mt) ** 2 for t, _ in rows)
    slope = sum((t - mt) * (r - mr) for t, r in rows) / var if var > 0 else 0.0
    # After warm-up (first minute), where a leak would show as a steady slope.
    late = [(t, r) for t, r in rows if t >= 60.0]
    late_slope = float("nan")
    if len(late) >= 2:
        lt = sum(t for t, _ in late) / len(late)
        lr = sum(r for _, r in late) / len(late)
        lv = sum((t - lt) ** 2 for t, _ in late)
        late_slope = sum((t - lt) * (r - lr) for t, r in late) / lv if lv > 0 else 0.0
    print(f"RSS samples {n} over {rows[-1][0]:.0f} s: start {rows[0][1]/1024:.1f} MiB, "
          f"end {rows[-1][1]/1024:.1f} MiB, max {max(r for _, r in rows)/1024:.1f} MiB")
    print(f"RSS slope (least squares, all samples): {slope*3600/1024:+.2f} MiB/h; "
          f"after the first minute: {late_slope*3600/1024:+.2f} MiB/h")
else:
    print("RSS: fewer than 2 samples (run shorter than 10 s)")
print(f"frames {s['frames']} in {s['seconds']:.1f} s; missed deadlines {s['missed_deadlines']} "
      f"({100*s['missed_deadline_rate']:.2f} %), skipped slots {s['skipped_slots']}; "
      f"render-thread allocations after warm-up {s['allocations_after_warmup']}")
v = s["variant_frames"]
print(f"variants: video {v['video']}, hybrid {v['hybrid']}, synthetic {v['synthetic']} frames; "
      f"camera switches {s['camera_switches']}; model updates {s['model_updates']}")
for c in s["cameras"]:
    print(f"camera {c['name']}: new frames shown {c['frames_shown']}, lost by the device "
          f"{c['frames_lost']}, rejected {c['frames_rejected']}")
for k in ("motion_to_photon_display", "video_age", "model_age"):
    l = s["latency"][k]
    print(f"{k}: p50 {l['p50_ms']:.2f} ms, p99 {l['p99_ms']:.2f} ms, max {l['max_ms']:.2f} ms")
PY
