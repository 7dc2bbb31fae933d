#!/usr/bin/env python3
"""Frame time (draw + swap) p99 inside a camera outage and outside it, from a hybrid-station run's
outputs (issue 11: "within 1 ms"). A timing figure, so a script beside the test, not an assertion.

    python3 scripts/outage-frame-times.py OUT_DIR [--seconds 4]

The outage is the longest of the first camera's unusable_intervals in OUT_DIR/summary.json, its
first `--seconds` of frames (by the station's rate); the first 30 frames (warm-up) are left out.
"""
import argparse
import csv
import json
import math
import sys


def p99(values):
    if not values:
        return float("nan")
    v = sorted(values)
    k = max(1, min(len(v), math.ceil(0.99 * len(v))))
    return v[k - 1]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out_dir")
    ap.add_argument("--seconds", type=float, default=4.0)
    a = ap.parse_args()
    summary = json.load(open(f"{a.out_dir}/summary.json"))
    intervals = [u for c in summary["cameras"] for u in c.get("unusable_intervals", [])]
    if not intervals:
        sys.exit(f"{a.out_dir}/summary.json: no camera was ever unusable")
    longest = max(intervals, key=lambda u: (u["to_frame"] if u["to_frame"] is not None else 10**12)
                  - u["from_frame"])
    first = longest["from_frame"]
    last = first + int(round(a.seconds * summary["rate_hz"]))
    inside, outside = [], []
    with open(f"{a.out_dir}/latency.csv") as f:
        for r in csv.DictReader(f):
            frame = int(r["frame"])
            if frame < 30:
                continue
            ms = (int(r["swap_ns"]) - int(r["render_start_ns"])) * 1e-6
            (inside if first <= frame < last else outside).append(ms)
    print(f"frame time (draw + swap) p99: outage {p99(inside):.3f} ms ({len(inside)} frames, "
          f"frames {first}..{last - 1}), outside {p99(outside):.3f} ms ({len(outside)} frames); "
          f"difference {p99(inside) - p99(outside):+.3f} ms")


if __name__ == "__main__":
    main()
