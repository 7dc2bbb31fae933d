#!/usr/bin/env bash
# The main job: installs what is needed, builds, and runs the default simulated scene
# (scenes/default.yaml: a pick-and-place seen by three simulated cameras, two of them a stereo pair
# that reconstructs the moved block into the model, the head moving away from camera 0 and back
# over 20 s, so the view goes video -> hybrid -> synthetic -> hybrid -> video) as two processes on
# loopback: hybrid-remote renders the cameras and sends them as RTP H.264 (x264enc, rtpbin), and
# hybrid-station receives, decodes and shows them (rtp://, avdec_h264) with the head, the model and
# the reconstruction from the received stereo pair; both on one scene clock (--scene-epoch).
# Outputs land in out/demo/ (README.md "What the demo leaves").
#
#   bash scripts/demo.sh                    # the two processes (the real path: encode, RTP, decode)
#   bash scripts/demo.sh --single-process   # the station alone, the cameras simulated in-process
set -euo pipefail
cd "$(dirname "$0")/.."
single=0
case "${1:-}" in
  --single-process) single=1 ;;
  "") ;;
  *)
    echo "usage: bash scripts/demo.sh [--single-process]" >&2
    exit 2
    ;;
esac
bash scripts/setup.sh
. scripts/lib/two-process.sh
export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo
cmake --build build -j"$(nproc)" --target hybrid-station hybrid-remote hybrid-geom hybrid-fig3
mkdir -p out/demo

if [ "$single" = 1 ]; then
  rm -f out/demo/remote.log  # a previous two-process run's: not this run's
  echo "== station: scenes/default.yaml, 20 s at 90 Hz, stereo, CPU compositor, headless, cameras simulated in-process =="
  ./build/bin/hybrid-station run --scene scenes/default.yaml --headless --rate 90 --out out/demo
else
  # Camera i goes to PORT + 2 i (RTCP on the next port).
  port=$(free_udp_block 5600 6600)
  [ -n "$port" ] || { echo "demo: no 16 free UDP ports on 127.0.0.1 in 5600..6599" >&2; exit 1; }
  # Scene t = 0 a few seconds ahead on CLOCK_REALTIME, given to both: the station's head and the
  # objects the remote's cameras see follow one scene clock, and both programs are up by then.
  epoch=$(python3 -c 'import time; print("%.3f" % (time.time() + 4))')
  trap stop_remote EXIT
  trap 'exit 130' INT TERM
  echo "== remote: hybrid-remote --scene scenes/default.yaml -> rtp://127.0.0.1:$port (+2 per camera), log out/demo/remote.log =="
  # --seconds only bounds a remote whose script was killed before it could stop it.
  ./build/bin/hybrid-remote --scene scenes/default.yaml --to "rtp://127.0.0.1:$port" \
    --scene-epoch "$epoch" --seconds 300 >out/demo/remote.log 2>&1 &
  remote_pid=$!
  echo "== station: scenes/default.yaml, cameras from rtp://127.0.0.1:$port, until scene t = 20 s at 90 Hz, stereo, CPU compositor, headless =="
  ./build/bin/hybrid-station run --scene scenes/default.yaml --headless --rate 90 \
    --cameras-from "rtp://127.0.0.1:$port" --scene-epoch "$epoch" --out out/demo
  stop_remote
  tail -n 4 out/demo/remote.log
fi

echo "== geometry what-if (hybrid-geom) on scenes/geom-example.json =="
./build/bin/hybrid-geom --indent 1 scenes/geom-example.json | tee out/geom-example.result.json

echo "== the paper's Fig. 3 =="
./build/bin/hybrid-fig3 --out out/fig3.png

echo "demo outputs: out/demo/{contact_sheet.png,trace.png,latency.png,latency.csv,frames.csv,summary.json}" \
  "$([ "$single" = 1 ] || echo out/demo/remote.log) out/fig3.png out/geom-example.result.json"
