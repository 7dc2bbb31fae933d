#!/usr/bin/env python3
"""Agreement test: `hybrid-geom` against the independent reference in reference_geom.py.

  compare_geom.py PATH/TO/hybrid-geom   run 300 random, 60 exact-tie, 40 near-degenerate and 49 named
                                        hard scenarios through both (one JSON array), compare
  compare_geom.py --self-test           check the reference itself on closed forms and on
                                        independent numerical methods (raster, direct projection)
  compare_geom.py --dump FILE           write the scenario array (to replay by hand)
  compare_geom.py --mutation-check      show the scenario set catches plausible mistakes (~1 min)

Tolerances (issue #2 "Done when"): E, E_max, m relative 1e-6 with an absolute floor of 1e-9
(|a - b| <= 1e-6 * max(|a|, |b|) + 1e-9, so values that are 0 up to rounding compare equal);
coverage absolute 1e-7; update_region 1e-4 px per coordinate; w_video, kappa, w2 absolute 1e-9.
null means +inf or undefined; null only matches null. There is no whitelist: every scenario counts.
"""

from __future__ import annotations

import json
import math
import os
import random
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import reference_geom as ref  # noqa: E402

SEED = 20261122
N_RANDOM = 300
N_TIE = 60
N_NUDGE = 40

# ----------------------------------------------------------------------------- small math


def _norm(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _matmul(A, B):
    return [[sum(A[i][k] * B[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def rodrigues(axis, angle_rad):
    x, y, z = _norm(axis)
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    C = 1 - c
    return [
        [c + x * x * C, x * y * C - z * s, x * z * C + y * s],
        [y * x * C + z * s, c + y * y * C, y * z * C - x * s],
        [z * x * C - y * s, z * y * C + x * s, c + z * z * C],
    ]


def look_at(pos, target, rng):
    """Camera-to-world R whose z axis points from pos to target, with a random roll."""
    z = _norm([target[i] - pos[i] for i in range(3)])
    a = [rng.uniform(-1, 1) for _ in range(3)]
    x = _norm(_cross(z, a))
    y = _cross(z, x)
    return [[x[i], y[i], z[i]] for i in range(3)]


def flat(R):
    return [R[i][j] for i in range(3) for j in range(3)]


IDENTITY = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
RY90 = [[0, 0, 1], [0, 1, 0], [-1, 0, 0]]  # looks along +x
RY180 = [[-1, 0, 0], [0, 1, 0], [0, 0, -1]]  # looks along -z


def cam(fx, fy, cx, cy, w, h, R=IDENTITY, t=(0, 0, 0)):
    return {"fx": fx, "fy": fy, "cx": cx, "cy": cy, "width": w, "height": h,
            "R": flat(R), "t": list(t)}


REAL = cam(2000, 2000, 800, 600, 1600, 1200)
VIRT = cam(1000, 1000, 400, 300, 800, 600, t=(0.02, 0, 0))
BOX = {"min": [-0.5, -0.5, 0.2], "max": [0.5, 0.5, 1.0]}
PIXELS = [[800, 600], [0, 0], [1600, 1200], [0, 600], [1200, 900], [1550, 1150], [100, 600]]


def scenario(real=REAL, virtual=VIRT, d=0.5, near=0.01, ws=BOX, points=None, blend=None,
             pixels=None, **extra):
    s = {"real": real, "virtual": virtual, "d": d, "workspace": ws}
    if near is not None:
        s["near"] = near
    s["points"] = points if points is not None else [[0, 0, 1.0], [0.1, -0.05, 0.3]]
    s["blend"] = blend if blend is not None else {"m_t": 40, "eps": 10}
    s["pixels"] = pixels if pixels is not None else PIXELS
    s.update(extra)
    return s


# ----------------------------------------------------------------------------- scenarios


def random_intrinsics(rng):
    f = math.exp(rng.uniform(math.log(100), math.log(20000)))
    w = rng.randint(64, 4000)
    h = rng.randint(48, 3000)
    return {"fx": f, "fy": f * rng.uniform(0.9, 1.1), "cx": w * rng.uniform(0.3, 0.7),
            "cy": h * rng.uniform(0.3, 0.7), "width": w, "height": h}


def random_scenario(rng):
    o = [rng.uniform(-1, 1) for _ in range(3)]
    half = [math.exp(rng.uniform(math.log(0.05), math.log(1.0))) for _ in range(3)]
    box = {"min": [o[i] - half[i] for i in range(3)], "max": [o[i] + half[i] for i in range(3)]}
    dist = rng.uniform(0.3, 5.0)
    pos_c = [o[i] + dist * v for i, v in enumerate(_norm([rng.gauss(0, 1) for _ in range(3)]))]
    aim = [o[i] + rng.uniform(-1, 1) * half[i] for i in range(3)]
    R_c = look_at(pos_c, aim, rng)
    real = random_intrinsics(rng) | {"R": flat(R_c), "t": pos_c}
    if rng.random() < 0.7:  # operator near the camera: the interesting regime
        shift = math.exp(rng.uniform(math.log(1e-3), math.log(0.5)))
        pos_o = [pos_c[i] + shift * v for i, v in enumerate(_norm([rng.gauss(0, 1) for _ in range(3)]))]
        turn = rodrigues([rng.gauss(0, 1) for _ in range(3)], math.radians(rng.uniform(0, 40)))
        R_o = _matmul(R_c, turn)
    else:
        dist_o = rng.uniform(0.3, 5.0)
        pos_o = [o[i] + dist_o * v for i, v in enumerate(_norm([rng.gauss(0, 1) for _ in range(3)]))]
        R_o = look_at(pos_o, [o[i] + rng.uniform(-1, 1) * half[i] for i in range(3)], rng)
    virtual = random_intrinsics(rng) | {"R": flat(R_o), "t": pos_o}
    s = {"real": real, "virtual": virtual,
         "d": math.exp(rng.uniform(math.log(0.05), math.log(50))), "workspace": box}
    if rng.random() < 0.5:
        s["near"] = math.exp(rng.uniform(math.log(1e-3), math.log(0.2)))
    pts = [[o[i] + 1.5 * half[i] * rng.uniform(-1, 1) for i in range(3)]
           for _ in range(rng.randint(0, 5))]
    if rng.random() < 0.5:  # a point on the projection plane, along a real ray
        z = [R_c[i][2] for i in range(3)]
        pts.append([pos_c[i] + s["d"] * z[i] for i in range(3)])
    s["points"] = pts
    m_t = math.exp(rng.uniform(0, math.log(2000)))
    s["blend"] = {"m_t": m_t, "eps": 0.0 if rng.random() < 0.2 else rng.uniform(0, m_t)}
    s["pixels"] = [[rng.uniform(0, real["width"]), rng.uniform(0, real["height"])]
                   for _ in range(rng.randint(0, 5))]
    return s


def _axis_rotations():
    """The 24 rotations that map axes to axes: exact in binary, so planes coincide exactly."""
    import itertools
    out = []
    for perm in itertools.permutations(range(3)):
        for signs in itertools.product((1, -1), repeat=3):
            R = [[0] * 3 for _ in range(3)]
            for i in range(3):
                R[i][perm[i]] = signs[i]
            det = (R[0][0] * (R[1][1] * R[2][2] - R[1][2] * R[2][1])
                   - R[0][1] * (R[1][0] * R[2][2] - R[1][2] * R[2][0])
                   + R[0][2] * (R[1][0] * R[2][1] - R[1][1] * R[2][0]))
            if det == 1:
                out.append(R)
    return out


AXIS_ROTATIONS = _axis_rotations()


def tie_scenario(rng):
    """Hard by construction: every number is dyadic and every rotation axis-aligned, so box faces,
    near planes, the projection plane, frustum sides and camera centres coincide EXACTLY and often
    (faces on near planes, cameras on the plane, flat boxes, quads touching the frustum)."""
    eighth = lambda lo, hi: rng.randint(lo, hi) / 8  # noqa: E731

    def intrinsics():
        w = rng.choice([256, 512, 1024])
        h = rng.choice([256, 512, 1024])
        f = rng.choice([128, 256, 512, 1024, 2048])
        return {"fx": f, "fy": rng.choice([f, f * 2]), "cx": rng.choice([w / 2, w / 4, 0, w]),
                "cy": rng.choice([h / 2, h / 4, h]), "width": w, "height": h}

    R_c = rng.choice(AXIS_ROTATIONS)
    t_c = [eighth(-8, 8) for _ in range(3)]
    R_o = R_c if rng.random() < 0.5 else rng.choice(AXIS_ROTATIONS)
    t_o = [t_c[i] + (eighth(-4, 4) if rng.random() < 0.6 else 0.0) for i in range(3)]
    depth = eighth(0, 16)
    centre = [t_c[i] + depth * R_c[i][2] for i in range(3)]
    lo = [centre[i] - eighth(0, 4) for i in range(3)]
    hi = [lo[i] + eighth(0, 8) for i in range(3)]
    s = {"real": intrinsics() | {"R": flat(R_c), "t": t_c},
         "virtual": intrinsics() | {"R": flat(R_o), "t": t_o},
         "d": rng.choice([0.125, 0.25, 0.5, 1.0, 2.0]), "workspace": {"min": lo, "max": hi}}
    near = rng.choice([1 / 64, 0.125, 0.25, None])
    if near is not None:
        s["near"] = near
    s["points"] = [[centre[i] + eighth(-4, 4) for i in range(3)] for _ in range(3)]
    s["blend"] = {"m_t": rng.choice([10, 40, 100]), "eps": rng.choice([0, 5, 20])}
    s["pixels"] = [[s["real"]["width"] * rng.randint(0, 8) / 8, s["real"]["height"] * rng.randint(0, 8) / 8]
                   for _ in range(3)]
    return s


def near_degenerate_scenario(rng):
    """A degenerate setup nudged by 1e-12 .. 1e-3 (angle or position): the regime where a
    floating-point implementation is ill-conditioned and the exact reference is ground truth."""
    nudge = 10 ** rng.uniform(-12, -3)
    sign = rng.choice([-1, 1])
    kind = rng.randrange(5)
    if kind == 0:  # virtual axis almost in the projection plane, centre almost on it
        R = rodrigues([0, 1, 0], math.pi / 2 + sign * nudge)
        v = cam(1000, 1000, 400, 300, 800, 600, R=R, t=(-0.25, 0, 0.5 + rng.choice([-1, 1]) * nudge))
        return scenario(virtual=v)
    if kind == 1:  # virtual centre almost on the plane, looking along the real axis
        return scenario(virtual=cam(1000, 1000, 400, 300, 800, 600, t=(0.01, 0, 0.5 + sign * nudge)),
                        points=[[0, 0, 0.9]])
    if kind == 2:  # box face almost on the virtual near plane
        return scenario(near=0.25, ws={"min": [-0.5, -0.5, -1.0], "max": [0.5, 0.5, 0.25 + sign * nudge]})
    if kind == 3:  # quad almost touching the frustum side
        return scenario(real=cam(2048, 2048, 512, 512, 1024, 1024),
                        virtual=cam(2048, 2048, 512, 512, 1024, 1024, t=(0.5 + sign * nudge, 0, 0)), d=1.0,
                        ws={"min": [-1, -1, 0.5], "max": [1, 1, 2]}, pixels=[[512, 512]])
    # workspace almost flat, frustum almost parallel to a box face
    R = rodrigues([1, 0, 0], math.radians(rng.uniform(0, 20)))
    lo = [-0.3, -0.3, 0.6]
    return scenario(virtual=cam(1000, 1000, 400, 300, 800, 600, R=R, t=(0.02, 0.01, 0)),
                    ws={"min": lo, "max": [0.3, 0.3, 0.6 + nudge]})


def hard_scenarios():
    """DESIGN.md "Principles": the hard cases, each named."""
    H = []

    def add(name, s):
        H.append((name, s))

    lat_points = [[0, 0, 0.2], [0, 0, 0.5], [0, 0, 1.0], [0, 0, 3.0]]
    add("issue example", scenario(points=[[0, 0, 1.0]], pixels=[[800, 600]]))
    add("identical cameras", scenario(virtual=REAL, points=[[0, 0, 1.0], [0.1, 0.1, 0.3], [0, 0, 0.5]]))
    add("same pose, other intrinsics (zoom)", scenario(virtual=cam(700, 650, 300, 260, 640, 480)))
    add("pure rotation 10 deg about y",
        scenario(virtual=cam(1000, 1000, 400, 300, 800, 600, R=rodrigues([0, 1, 0], math.radians(10)))))
    add("pure rotation about a skew axis 35 deg",
        scenario(virtual=cam(1000, 1000, 400, 300, 800, 600, R=rodrigues([1, -2, 0.5], math.radians(35)))))
    add("lateral translation b=0.05 (x)",
        scenario(virtual=cam(2000, 2000, 800, 600, 1600, 1200, t=(0.05, 0, 0)), points=lat_points))
    add("lateral translation b=0.03 (y), fx != fy",
        scenario(real=cam(1500, 1800, 800, 600, 1600, 1200),
                 virtual=cam(1500, 1800, 800, 600, 1600, 1200, t=(0, 0.03, 0)), points=lat_points))
    Rg = rodrigues([0.3, 1, 0.2], math.radians(25))
    add("points on the plane, general pose",
        scenario(virtual=cam(1000, 1000, 400, 300, 800, 600, R=Rg, t=(0.05, -0.02, 0.1)),
                 points=[[0, 0, 0.5], [0.1, 0.05, 0.5], [-0.2, 0.1, 0.5]]))
    add("plane on a box face (d = z_min)",
        scenario(ws={"min": [-0.5, -0.5, 0.5], "max": [0.5, 0.5, 1.0]}, points=[[0.05, 0.05, 0.5]]))
    add("grazing: virtual turned 89.9 deg",
        scenario(virtual=cam(1000, 1000, 400, 300, 800, 600, R=rodrigues([0, 1, 0], math.radians(89.9)),
                             t=(-0.3, 0, 0.45))))
    add("grazing: virtual turned 90.1 deg",
        scenario(virtual=cam(1000, 1000, 400, 300, 800, 600, R=rodrigues([0, 1, 0], math.radians(90.1)),
                             t=(-0.3, 0, 0.45))))
    add("parallel: virtual on the plane, axis in the plane (exact 90 deg)",
        scenario(virtual=cam(1000, 1000, 400, 300, 800, 600, R=RY90, t=(-0.25, 0, 0.5))))
    add("virtual camera on the plane, looking along the real axis",
        scenario(virtual=cam(1000, 1000, 400, 300, 800, 600, t=(0, 0, 0.5)), points=[[0, 0, 0.9]]))
    add("virtual camera behind the plane",
        scenario(virtual=cam(1000, 1000, 400, 300, 800, 600, t=(0, 0, 0.75)), points=[[0, 0, 0.9]]))
    add("virtual beyond the plane looking back",
        scenario(virtual=cam(1000, 1000, 400, 300, 800, 600, R=RY180, t=(0.05, 0, 1.5)),
                 points=[[0, 0, 0.6], [0.1, 0, 0.3]]))
    add("real camera looking away from the workspace",
        scenario(real=cam(2000, 2000, 800, 600, 1600, 1200, R=RY180)))
    add("real camera on the plane of a box face (z_c >= near face)",
        scenario(near=0.125, ws={"min": [-0.5, -0.5, 0.0], "max": [0.5, 0.5, 0.125]}))
    add("empty W: workspace behind the virtual camera",
        scenario(ws={"min": [-0.5, -0.5, -1.0], "max": [0.5, 0.5, -0.2]}))
    add("empty W: workspace outside the virtual frustum",
        scenario(ws={"min": [5.0, 5.0, 0.2], "max": [6.0, 6.0, 1.0]}))
    add("flat workspace (z_min = z_max)",
        scenario(ws={"min": [-0.5, -0.5, 0.7], "max": [0.5, 0.5, 0.7]}))
    add("flat workspace (segment along z)",
        scenario(ws={"min": [0.05, -0.01, 0.1], "max": [0.05, -0.01, 2.0]}))
    add("flat workspace (single point)",
        scenario(ws={"min": [0.01, 0.02, 0.6], "max": [0.01, 0.02, 0.6]}))
    add("W flat on the virtual near plane (box face on it)",
        scenario(virtual=cam(1000, 1000, 400, 300, 800, 600, t=(0.02, 0, 0)), near=0.25,
                 ws={"min": [-0.5, -0.5, -1.0], "max": [0.5, 0.5, 0.25]}))
    add("box face on the virtual near plane",
        scenario(near=0.25, ws={"min": [-0.5, -0.5, 0.25], "max": [0.5, 0.5, 1.0]}))
    add("huge d = 1e4", scenario(d=1e4))
    add("huge d = 1e6", scenario(d=1e6, points=[[0, 0, 1.0], [0, 0, 5e5]]))
    add("tiny d = 1e-3 below near", scenario(d=1e-3))
    add("tiny d = 1e-3, near 1e-4", scenario(d=1e-3, near=1e-4))
    add("tiny d = 1e-6, near 1e-7", scenario(d=1e-6, near=1e-7,
                                             ws={"min": [-1e-6, -1e-6, 1e-7], "max": [1e-6, 1e-6, 1e-5]}))
    add("extreme focal 1e6 (narrow)",
        scenario(real=cam(1e6, 1e6, 800, 600, 1600, 1200),
                 virtual=cam(1e6, 1e6, 400, 300, 800, 600, t=(0.001, 0, 0))))
    add("extreme focal 10 (180 deg wide)",
        scenario(real=cam(10, 10, 800, 600, 1600, 1200),
                 virtual=cam(10, 10, 400, 300, 800, 600, t=(0.02, 0, 0))))
    add("extreme focal 1 (wide) with rotation",
        scenario(real=cam(1, 1, 800, 600, 1600, 1200),
                 virtual=cam(1, 1, 400, 300, 800, 600, R=rodrigues([0, 1, 0], 0.3), t=(0.02, 0, 0))))
    add("kappa = 0 (w_video = 1)", scenario(blend={"m_t": 1e6, "eps": 10}))
    add("kappa = 1 (w_video = 0)", scenario(blend={"m_t": 1, "eps": 0.5}))
    add("kappa in (0,1), corners and edges",
        scenario(blend={"m_t": 63, "eps": 20},
                 pixels=PIXELS + [[1500, 1100], [1580, 50], [30, 1190], [1600, 600], [800, 0]]))
    add("eps = 0, m below m_t", scenario(blend={"m_t": 100, "eps": 0}))
    add("eps = 0, m above m_t", scenario(blend={"m_t": 50, "eps": 0}))
    add("virtual looking away",
        scenario(virtual=cam(1000, 1000, 400, 300, 800, 600, R=RY180, t=(0.02, 0, 0))))
    add("X'' between virtual centre and near plane (near 0.3)",
        scenario(virtual=cam(1000, 1000, 400, 300, 800, 600, t=(0, 0, 0.3)), near=0.3,
                 points=[[0, 0, 0.9], [0.05, 0, 0.7]]))
    # Dyadic numbers so both sides represent the geometry exactly: the quad [-0.25, 0.25] (x) at
    # d = 1 touches the virtual frustum's left plane x = 0.5 - 0.25 along one edge.
    add("quad touches the virtual frustum along an edge",
        scenario(real=cam(2048, 2048, 512, 512, 1024, 1024),
                 virtual=cam(2048, 2048, 512, 512, 1024, 1024, t=(0.5, 0, 0)), d=1.0,
                 ws={"min": [-1, -1, 0.5], "max": [1, 1, 2]}, pixels=[[512, 512]]))
    add("non-square pixels, principal point outside the image",
        scenario(real=cam(1800, 2400, -100, 1300, 1600, 1200),
                 virtual=cam(900, 700, 850, -40, 800, 600, R=rodrigues([1, 1, 0], 0.2), t=(0.03, 0.01, -0.02))))
    far = [1000.0, -2000.0, 500.0]
    Rf = rodrigues([0.2, 0.9, -0.4], 1.1)
    add("rig far from the origin, rotated",
        scenario(real=cam(2000, 2000, 800, 600, 1600, 1200, R=Rf, t=far),
                 virtual=cam(1000, 1000, 400, 300, 800, 600, R=_matmul(Rf, rodrigues([0, 1, 0], 0.1)),
                             t=[far[i] + 0.02 * Rf[i][0] for i in range(3)]),
                 ws={"min": [far[i] - 1 for i in range(3)], "max": [far[i] + 1 for i in range(3)]},
                 points=[[far[i] + Rf[i][2] for i in range(3)]]))
    add("tiny workspace (1e-4 m)",
        scenario(ws={"min": [0.01, 0.01, 0.6], "max": [0.0101, 0.0101, 0.6001]}))
    add("near omitted (default 0.01), point at z = 0.005",
        scenario(near=None, points=[[0, 0, 0.005], [0, 0, 0.02]]))
    s = scenario()
    for k in ("points", "pixels", "blend"):
        del s[k]
    add("no points, pixels or blend", s)
    add("virtual rotated 90 deg at the real centre (pure rotation, grazing)",
        scenario(virtual=cam(1000, 1000, 400, 300, 800, 600, R=RY90)))
    add("virtual close to the plane, oblique: near clips the quad",
        scenario(virtual=cam(1000, 1000, 400, 300, 800, 600, R=rodrigues([0, 1, 0], math.radians(60)),
                             t=(-0.1, 0.02, 0.49)), near=0.02))
    add("virtual inside the workspace",
        scenario(virtual=cam(800, 800, 400, 300, 800, 600, R=rodrigues([1, 0, 0], 0.4), t=(0.1, 0.1, 0.6))))
    add("real camera inside the workspace",
        scenario(ws={"min": [-1, -1, -1], "max": [1, 1, 1]}, points=[[0, 0, -0.5], [0, 0, 0.5]]))
    return H


def all_scenarios():
    rng = random.Random(SEED)
    named = [(f"random #{i}", random_scenario(rng)) for i in range(N_RANDOM)]
    named += [(f"exact-tie #{i}", tie_scenario(rng)) for i in range(N_TIE)]
    named += [(f"near-degenerate #{i}", near_degenerate_scenario(rng)) for i in range(N_NUDGE)]
    return named + hard_scenarios()


# ----------------------------------------------------------------------------- comparison


def _close_rel(a, b):
    if a is None or b is None:
        return a is None and b is None
    return abs(a - b) <= 1e-6 * max(abs(a), abs(b)) + 1e-9


def _close_abs(tol):
    def f(a, b):
        if a is None or b is None:
            return a is None and b is None
        return abs(a - b) <= tol
    return f


def _region_close(a, b):
    if a is None or b is None:
        return a is None and b is None
    return len(a) == 4 and len(b) == 4 and all(abs(x - y) <= 1e-4 for x, y in zip(a, b))


def _difference(field, a, b):
    """How much of its tolerance a finite pair uses (1.0 = at the limit), for the report."""
    try:
        if field == "update_region":
            return max(abs(x - y) for x, y in zip(a, b)) / 1e-4
        if field in ("E", "E_max", "m"):
            return abs(a - b) / (1e-6 * max(abs(a), abs(b)) + 1e-9)
        return abs(a - b) / (1e-7 if field == "coverage" else 1e-9)
    except (TypeError, ValueError):
        return None


def compare(named, got, want, worst=None):
    """Returns (fields compared, list of mismatch strings). `worst` (a dict) collects the
    largest difference per field kind among the pairs that are both finite."""
    fields = 0
    bad = []
    for idx, ((name, _), g, w) in enumerate(zip(named, got, want)):
        def check(field, gv, wv, ok):
            nonlocal fields
            fields += 1
            if not ok(gv, wv):
                bad.append(f"scenario {idx} ({name}): {field}: hybrid-geom={gv!r} reference={wv!r}")
            if worst is not None and gv is not None and wv is not None:
                kind = field.split("[")[0]
                diff = _difference(kind, gv, wv)
                if diff is not None and diff > worst.get(kind, (-1.0, ""))[0]:
                    worst[kind] = (diff, f"scenario {idx} ({name})")

        if not isinstance(g, dict):
            bad.append(f"scenario {idx} ({name}): hybrid-geom result is not an object: {g!r}")
            continue
        ge, we = g.get("E") or [], w["E"]
        if len(ge) != len(we):
            bad.append(f"scenario {idx} ({name}): E has {len(ge)} entries, expected {len(we)}")
        else:
            for i, (a, b) in enumerate(zip(ge, we)):
                check(f"E[{i}]", a, b, _close_rel)
        check("E_max", g.get("E_max", "missing"), w["E_max"], _close_rel)
        check("coverage", g.get("coverage", "missing"), w["coverage"], _close_abs(1e-7))
        check("m", g.get("m", "missing"), w["m"], _close_rel)
        check("update_region", g.get("update_region", "missing"), w["update_region"], _region_close)
        if "w_video" in w:
            check("w_video", g.get("w_video", "missing"), w["w_video"], _close_abs(1e-9))
            check("kappa", g.get("kappa", "missing"), w["kappa"], _close_abs(1e-9))
            gw, ww = g.get("w2") or [], w["w2"]
            if len(gw) != len(ww):
                bad.append(f"scenario {idx} ({name}): w2 has {len(gw)} entries, expected {len(ww)}")
            else:
                for i, (a, b) in enumerate(zip(gw, ww)):
                    check(f"w2[{i}]", a, b, _close_abs(1e-9))
    return fields, bad


def _safe(ok):
    """Comparators must not crash on a wrong type from the program; a wrong type is a mismatch."""
    def f(a, b):
        try:
            return ok(a, b)
        except TypeError:
            return False
    return f


_close_rel = _safe(_close_rel)
_region_close = _safe(_region_close)


def _malformed():
    """(what, file text, field the message must name) -- inputs both sides must reject."""
    def edit(fn):
        s = json.loads(json.dumps(scenario()))
        fn(s)
        return json.dumps(s)

    return [
        ("missing d", edit(lambda s: s.pop("d")), "d"),
        ("d = 0", edit(lambda s: s.update(d=0.0)), "d"),
        ("near < 0", edit(lambda s: s.update(near=-0.01)), "near"),
        ("point with 2 coordinates", edit(lambda s: s.update(points=[[1, 2]])), "points[0]"),
        ("fx a string", edit(lambda s: s["virtual"].update(fx="abc")), "virtual.fx"),
        ("eps < 0", edit(lambda s: s["blend"].update(eps=-1)), "blend.eps"),
        ("width 0", edit(lambda s: s["real"].update(width=0)), "real.width"),
        ("R not a rotation", edit(lambda s: s["real"].update(R=[1, 0, 0, 0, 1, 0, 0, 0, 2])), "real.R"),
        ("R with 8 numbers", edit(lambda s: s["virtual"].update(R=[1, 0, 0, 0, 1, 0, 0, 0])), "virtual.R"),
        ("workspace missing", edit(lambda s: s.pop("workspace")), "workspace"),
        ("not JSON", '{"real": ', ""),
    ]


def malformed_probes(binary):
    """Issue #2 item 3: malformed input -> message naming the field on stderr, exit 2, empty
    stdout. The reference must reject the same inputs (so the contract is one contract)."""
    bad = []
    with tempfile.TemporaryDirectory(prefix="compare_geom_bad_") as tmp:
        for what, text, field in _malformed():
            path = os.path.join(tmp, "bad.json")
            with open(path, "w", encoding="utf-8") as f:
                f.write(text)
            p = subprocess.run([binary, path], capture_output=True, text=True, timeout=30)
            if p.returncode != 2 or p.stdout != "" or field not in p.stderr:
                bad.append(f"malformed input ({what}): hybrid-geom exit {p.returncode}, "
                           f"stdout {p.stdout[:80]!r}, stderr {p.stderr.strip()[:160]!r} "
                           f"(expected exit 2, no stdout, a message naming {field!r})")
            try:
                ref.evaluate_json(json.loads(text))
                bad.append(f"malformed input ({what}): the reference accepted it")
            except (ref.ScenarioError, json.JSONDecodeError):
                pass
    return bad


def run_comparison(binary):
    named = all_scenarios()
    scenarios = [s for _, s in named]
    with tempfile.TemporaryDirectory(prefix="compare_geom_") as tmp:
        path = os.path.join(tmp, "scenarios.json")
        with open(path, "w", encoding="utf-8") as f:
            json.dump(scenarios, f, allow_nan=False)
        proc = subprocess.run([binary, path], capture_output=True, text=True, timeout=120)
    if proc.returncode != 0:
        print(f"FAIL: {binary} exited with {proc.returncode}; stderr:\n{proc.stderr}")
        return 1
    try:
        got = json.loads(proc.stdout)
    except json.JSONDecodeError as e:
        print(f"FAIL: {binary} printed no valid JSON ({e}); first 500 chars:\n{proc.stdout[:500]}")
        return 1
    if not isinstance(got, list) or len(got) != len(scenarios):
        print(f"FAIL: expected an array of {len(scenarios)} results, got "
              f"{type(got).__name__} of {len(got) if isinstance(got, list) else '-'}")
        return 1
    want = [ref.evaluate(ref.parse_scenario(s, f"[{i}]")) for i, s in enumerate(scenarios)]
    worst = {}
    fields, bad = compare(named, got, want, worst)
    bad += malformed_probes(binary)
    n_hard = len(named) - N_RANDOM - N_TIE - N_NUDGE
    print(f"{len(named)} scenarios ({N_RANDOM} random, {N_TIE} exact-tie, {N_NUDGE} near-degenerate, "
          f"{n_hard} named hard), "
          f"{fields} fields compared, {len(_malformed())} malformed inputs probed, {len(bad)} mismatches")
    for kind, (used, where) in sorted(worst.items()):
        print(f"  largest {kind} difference: {100 * used:.3g}% of its tolerance ({where})")
    for line in bad:
        print("MISMATCH " + line)
    return 1 if bad else 0


# ----------------------------------------------------------------------------- self-test


class SelfTest:
    def __init__(self):
        self.checks = 0
        self.failures = []

    def expect(self, ok, what):
        self.checks += 1
        if not ok:
            self.failures.append(what)

    def near(self, a, b, tol, what):
        self.expect(a is not None and b is not None and abs(a - b) <= tol, f"{what}: {a!r} vs {b!r} (tol {tol})")


def _direct_error(s, X):
    """E by the textbook route (DESIGN.md 3), in doubles: project X, find X'' on the real ray,
    project X''. Used to check the reference's factored exact formula."""
    def to_cam(c, P):
        R = c["R"]
        d = [P[i] - c["t"][i] for i in range(3)]
        return [sum(R[3 * k + i] * d[k] for k in range(3)) for i in range(3)]

    def proj(c, p):
        return (c["fx"] * p[0] / p[2] + c["cx"], c["fy"] * p[1] / p[2] + c["cy"])

    real, virt = s["real"], s["virtual"]
    pc = to_cam(real, X)
    sc = s["d"] / pc[2]
    X2 = [real["t"][i] + sc * (X[i] - real["t"][i]) for i in range(3)]
    a = proj(virt, to_cam(virt, X))
    b = proj(virt, to_cam(virt, X2))
    return math.hypot(a[0] - b[0], a[1] - b[1])


def _in_w(s, X, tol):
    """Membership in W by projecting into both cameras (doubles), independent of the plane list."""
    def to_cam(c, P):
        R = c["R"]
        d = [P[i] - c["t"][i] for i in range(3)]
        return [sum(R[3 * k + i] * d[k] for k in range(3)) for i in range(3)]

    near = s.get("near", ref.DEFAULT_NEAR_M)
    lo, hi = s["workspace"]["min"], s["workspace"]["max"]
    if any(X[i] < lo[i] - tol or X[i] > hi[i] + tol for i in range(3)):
        return False
    pc = to_cam(s["real"], X)
    po = to_cam(s["virtual"], X)
    if pc[2] < near - tol or po[2] < near - tol:
        return False
    v = s["virtual"]
    # u in [0, w] scaled by z so a vertex on the near plane is tested without division
    x, y, z = po
    return (v["fx"] * x + v["cx"] * z >= -tol * (v["fx"] + abs(v["cx"]))
            and (v["width"] - v["cx"]) * z - v["fx"] * x >= -tol * (v["fx"] + abs(v["width"] - v["cx"]))
            and v["fy"] * y + v["cy"] * z >= -tol * (v["fy"] + abs(v["cy"]))
            and (v["height"] - v["cy"]) * z - v["fy"] * y >= -tol * (v["fy"] + abs(v["height"] - v["cy"])))


def _raster_coverage(s, n):
    """Fraction of an n x n grid of screen samples whose virtual ray meets the video quad
    (in front of the near plane). Independent of the reference's clipping."""
    real, virt = s["real"], s["virtual"]
    near = s.get("near", ref.DEFAULT_NEAR_M)
    Rc, Ro = real["R"], virt["R"]
    zc = [Rc[2], Rc[5], Rc[8]]  # real camera's z axis in the world
    hits = 0
    for i in range(n):
        for j in range(n):
            u = (i + 0.5) * virt["width"] / n
            v = (j + 0.5) * virt["height"] / n
            dcam = [(u - virt["cx"]) / virt["fx"], (v - virt["cy"]) / virt["fy"], 1.0]
            dw = [sum(Ro[3 * r + k] * dcam[k] for k in range(3)) for r in range(3)]
            # plane: zc . (X - t_c) = d, X = t_o + lam * dw
            den = sum(zc[k] * dw[k] for k in range(3))
            if den == 0:
                continue
            lam = (s["d"] - sum(zc[k] * (virt["t"][k] - real["t"][k]) for k in range(3))) / den
            if lam < near:  # lam is the virtual depth because dcam has z = 1
                continue
            X = [virt["t"][k] + lam * dw[k] for k in range(3)]
            p = [sum(Rc[3 * k + r] * (X[k] - real["t"][k]) for k in range(3)) for r in range(3)]
            uc = real["fx"] * p[0] / p[2] + real["cx"]
            vc = real["fy"] * p[1] / p[2] + real["cy"]
            if 0 <= uc <= real["width"] and 0 <= vc <= real["height"]:
                hits += 1
    return hits / (n * n)


def self_test():
    T = SelfTest()
    ev = lambda s: ref.evaluate(ref.parse_scenario(s))  # noqa: E731

    # 1. The worked example.
    r = ev(scenario(points=[[0, 0, 1.0]], pixels=[[800, 600]]))
    T.near(r["E"][0], 20.0, 1e-9, "example E")
    T.near(r["E_max"], 60.0, 1e-9, "example E_max")
    T.near(r["coverage"], 0.95, 1e-12, "example coverage")
    T.expect(r["update_region"] is not None and all(
        abs(a - b) < 1e-9 for a, b in zip(r["update_region"], [80, 0, 1600, 1200])), f"example region {r['update_region']}")
    T.near(r["m"], 60 / 0.95, 1e-9, "example m")
    T.near(r["w_video"], 0.0, 0, "example w_video")

    rng = random.Random(7)
    # 2. Lateral translation b, point on the real optical axis at depth Z: E = f b |1/Z - 1/d|.
    for _ in range(40):
        f = math.exp(rng.uniform(math.log(100), math.log(20000)))
        b = rng.uniform(0.001, 0.3)
        d = math.exp(rng.uniform(math.log(0.05), math.log(50)))
        Z = rng.uniform(0.05, 60)
        axis = rng.choice([0, 1])
        t = [0.0, 0.0, 0.0]
        t[axis] = b
        c = cam(f, f, 640, 480, 1280, 960)
        s = scenario(real=c, virtual=cam(f, f, 640, 480, 1280, 960, t=t), d=d, points=[[0, 0, Z]])
        want = f * b * abs(1 / Z - 1 / d)
        T.near(ev(s)["E"][0], want, 1e-9 * want + 1e-9, f"lateral f={f} b={b} d={d} Z={Z}")

    # 3. Pure rotation: E = 0 everywhere, so E_max = 0.
    for _ in range(20):
        Rv = rodrigues([rng.gauss(0, 1) for _ in range(3)], rng.uniform(0, 1.2))
        pts = [[rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0.1, 3)] for _ in range(5)]
        s = scenario(virtual=cam(900, 950, 420, 310, 800, 600, R=Rv, t=(0.1, -0.2, 0.3)),
                     real=cam(2000, 2000, 800, 600, 1600, 1200, R=IDENTITY, t=(0.1, -0.2, 0.3)),
                     points=pts, ws={"min": [-1, -1, 0.5], "max": [1, 1, 3]})
        r = ev(s)
        T.expect(all(e in (None, 0.0) for e in r["E"]) and r["E_max"] == 0.0, f"pure rotation {r['E']} {r['E_max']}")

    # 4. Identical cameras: coverage 1, region = the whole image, E = 0.
    for _ in range(20):
        c = random_intrinsics(rng) | {"R": flat(rodrigues([rng.gauss(0, 1) for _ in range(3)], rng.uniform(0, 3))),
                                      "t": [rng.uniform(-2, 2) for _ in range(3)]}
        s = scenario(real=c, virtual=c, d=rng.uniform(0.05, 50))
        r = ev(s)
        T.near(r["coverage"], 1.0, 1e-12, "identical cameras coverage")
        # R is orthonormal only to double precision, so R_o^T R_c = I only to ~1e-16.
        T.expect(r["update_region"] is not None and all(
            abs(a - b) <= 1e-9 * max(1.0, b) for a, b in zip(r["update_region"], [0, 0, c["width"], c["height"]])),
            f"identical cameras region {r['update_region']}")
        T.expect(r["E_max"] == 0.0, f"identical cameras E_max {r['E_max']}")

    # 5. E: exact factored formula vs direct projection in doubles, at random points.
    for k in range(60):
        s = random_scenario(rng)
        sc = ref.parse_scenario(s)
        for X in s["points"]:
            e = ref.error_at(sc, X)
            if e is None or e == math.inf:
                continue
            direct = _direct_error(s, X)
            T.near(e, direct, 1e-7 * max(e, 1.0), f"random #{k} E factored vs direct at {X}")

    # 6. Coverage vs a raster count (sampling error <= perimeter / n <= 4 / n in screen units).
    n = 120
    for k in range(25):
        s = random_scenario(rng) if k >= 5 else scenario(
            virtual=cam(1000, 1000, 400, 300, 800, 600, R=rodrigues([0.2, 1, 0.1], 0.3 * k), t=(0.02, 0, 0.1 * k)))
        cov = ev(s)["coverage"]
        T.near(cov, _raster_coverage(s, n), 4.0 / n, f"coverage vs raster (case {k})")

    # 7. W is the box when the box is inside both frusta: E_max = max of E over the 8 corners.
    box = {"min": [-0.05, -0.04, 0.6], "max": [0.05, 0.04, 0.9]}
    s = scenario(ws=box, virtual=cam(1000, 1000, 400, 300, 800, 600, R=rodrigues([0, 1, 0], 0.02), t=(0.03, 0.01, 0)))
    corners = [[box["min" if (i >> a) & 1 == 0 else "max"][a] for a in range(3)] for i in range(8)]
    T.near(ev(s)["E_max"], max(_direct_error(s, X) for X in corners), 1e-9, "E_max = max over box corners")
    T.expect(len(ref.w_vertices(ref.parse_scenario(s))) == 8, "W = box has 8 vertices")

    # 7b. W's vertices by a second route: every vertex passes an independent membership test
    #     (projection into both cameras), and no sampled point of W lies beyond the vertices in
    #     any direction (a missing vertex would show up as a sample past the hull's support).
    checked = 0
    inside_total = 0
    while checked < 12:
        s = random_scenario(rng)
        sc = ref.parse_scenario(s)
        verts = [[float(c) for c in v] for v in ref.w_vertices(sc)]
        if not verts:
            continue
        checked += 1
        lo, hi = s["workspace"]["min"], s["workspace"]["max"]
        size = max(hi[i] - lo[i] for i in range(3))
        T.expect(all(_in_w(s, v, 1e-9 * (1 + size)) for v in verts), f"W vertex outside W (case {checked})")
        samples = [[rng.uniform(lo[i], hi[i]) for i in range(3)] for _ in range(3000)]
        inside = [p for p in samples if _in_w(s, p, 0.0)]
        inside_total += len(inside)
        for _ in range(8):
            n = _norm([rng.gauss(0, 1) for _ in range(3)])
            support = max(sum(n[i] * v[i] for i in range(3)) for v in verts)
            T.expect(all(sum(n[i] * p[i] for i in range(3)) <= support + 1e-9 * (1 + size) for p in inside),
                     f"W sample beyond the vertices' support (case {checked})")

    T.expect(inside_total >= 1000, f"too few samples inside W ({inside_total}) for the support test")
    print(f"W support test: {inside_total} samples inside W over {checked} scenarios")

    # 7c. Moving the whole rig rigidly changes nothing: E at the moved points, coverage and the
    #     region under any rotation G and shift g; E_max too under a pure shift (the box stays
    #     axis-aligned only then).
    for k in range(15):
        s = random_scenario(rng)
        G = rodrigues([rng.gauss(0, 1) for _ in range(3)], rng.uniform(0, 3))
        g = [rng.uniform(-3, 3) for _ in range(3)]
        move = lambda P: [sum(G[i][j] * P[j] for j in range(3)) + g[i] for i in range(3)]  # noqa: E731
        m = json.loads(json.dumps(s))
        for c in ("real", "virtual"):
            R = [s[c]["R"][3 * i:3 * i + 3] for i in range(3)]
            m[c]["R"] = flat(_matmul(G, R))
            m[c]["t"] = move(s[c]["t"])
        m["points"] = [move(P) for P in s["points"]]
        a, b = ev(s), ev(m)
        for i, (ea, eb) in enumerate(zip(a["E"], b["E"])):
            T.expect((ea is None) == (eb is None) and (ea is None or abs(ea - eb) <= 1e-7 * max(ea, 1.0)),
                     f"rigid motion #{k}: E[{i}] {ea} vs {eb}")
        T.near(a["coverage"], b["coverage"], 1e-9, f"rigid motion #{k}: coverage")
        T.expect((a["update_region"] is None) == (b["update_region"] is None) and (
            a["update_region"] is None or max(abs(x - y) for x, y in zip(a["update_region"], b["update_region"])) < 1e-6),
            f"rigid motion #{k}: region {a['update_region']} vs {b['update_region']}")
        shifted = json.loads(json.dumps(s))
        for c in ("real", "virtual"):
            shifted[c]["t"] = [s[c]["t"][i] + g[i] for i in range(3)]
        shifted["workspace"] = {key: [s["workspace"][key][i] + g[i] for i in range(3)] for key in ("min", "max")}
        ea, eb = a["E_max"], ev(shifted)["E_max"]
        T.expect((ea is None) == (eb is None) and (ea is None or abs(ea - eb) <= 1e-7 * max(ea, 1.0)),
                 f"rigid shift #{k}: E_max {ea} vs {eb}")

    # 8. Empty W: E_max = 0.
    r = ev(scenario(ws={"min": [-0.5, -0.5, -1.0], "max": [0.5, 0.5, -0.2]}))
    T.expect(r["E_max"] == 0.0 and r["m"] == 0.0, f"empty W: E_max {r['E_max']}, m {r['m']}")

    # 9. Blending closed forms.
    T.near(ref.w_video(40.0, 40.0, 10.0), 0.5, 1e-15, "w_video at m_t")
    T.near(ref.w_video(30.0, 40.0, 10.0), 1.0, 0, "w_video at m_t - eps")
    T.near(ref.w_video(50.0, 40.0, 10.0), 0.0, 0, "w_video at m_t + eps")
    T.near(ref.w_video(35.0, 40.0, 10.0), 0.75, 1e-15, "w_video linear")
    T.expect(ref.w_video(39.9, 40.0, 0.0) == 1.0 and ref.w_video(40.1, 40.0, 0.0) == 0.0, "eps = 0 switch")
    T.expect(ref.w_video(math.inf, 40.0, 10.0) == 0.0, "m = inf -> synthetic")
    W_, H_ = 1600.0, 1200.0
    for kappa in (0.1, 0.3, 0.5, 1.0):
        T.near(ref.w2(800, 600, W_, H_, kappa), 1.0, 0, f"w2 centre kappa={kappa}")
        T.near(ref.w2(0, 600, W_, H_, kappa), 0.0, 1e-15, f"w2 left edge kappa={kappa}")
        # x' = 1 - kappa/2 -> w'2 = 0.5 -> w2 = 0.5 (paper case 3)
        x = (1 - (1 - kappa / 2)) * W_ / 2
        T.near(ref.w2(x, 600, W_, H_, kappa), 0.5, 1e-12, f"w2 mid-border kappa={kappa}")
        # corner arc: distance kappa/2 from (1-kappa, 1-kappa) along the diagonal -> 0.5
        q = 1 - kappa + kappa / (2 * math.sqrt(2))
        T.near(ref.w2((1 - q) * W_ / 2, (1 - q) * H_ / 2, W_, H_, kappa), 0.5, 1e-12, f"w2 corner arc kappa={kappa}")
        # the paper's linear cases, through the sinusoid
        xp = 1 - kappa / 3
        wl = (1 - xp) / kappa
        T.near(ref.w2((1 - xp) * W_ / 2, 600, W_, H_, kappa), (math.sin((wl - 0.5) * math.pi) + 1) / 2, 1e-12,
               f"w2 paper case 3 kappa={kappa}")
        for _ in range(20):
            x, y = rng.uniform(0, W_), rng.uniform(0, H_)
            w = ref.w2(x, y, W_, H_, kappa)
            T.expect(0.0 <= w <= 1.0, "w2 in [0,1]")
            T.near(w, ref.w2(W_ - x, y, W_, H_, kappa), 1e-12, "w2 symmetric in x")
            T.near(w, ref.w2(x, H_ - y, W_, H_, kappa), 1e-12, "w2 symmetric in y")
            # non-increasing toward the border along the ray from the centre
            T.expect(ref.w2(800 + 1.05 * (x - 800), 600 + 1.05 * (y - 600), W_, H_, kappa) <= w + 1e-15,
                     "w2 non-increasing outward")
    T.expect(all(ref.w2(x, y, W_, H_, 0.0) == 1.0 for x, y in PIXELS), "kappa = 0 -> w2 = 1")

    # 10. The command-line contract: the example, and a malformed file naming the field.
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "reference_geom.py")
    with tempfile.TemporaryDirectory(prefix="reference_geom_") as tmp:
        good = os.path.join(tmp, "good.json")
        with open(good, "w", encoding="utf-8") as f:
            json.dump([scenario(points=[[0, 0, 1.0]], pixels=[[800, 600]])] * 2, f)
        p = subprocess.run([sys.executable, here, good], capture_output=True, text=True)
        T.expect(p.returncode == 0 and len(json.loads(p.stdout)) == 2, f"CLI on example array: {p.returncode} {p.stderr}")
        bad = os.path.join(tmp, "bad.json")
        s = scenario()
        del s["d"]
        with open(bad, "w", encoding="utf-8") as f:
            json.dump(s, f)
        p = subprocess.run([sys.executable, here, bad], capture_output=True, text=True)
        T.expect(p.returncode == 2 and p.stdout == "" and "scenario.d" in p.stderr,
                 f"CLI on malformed: rc={p.returncode} out={p.stdout!r} err={p.stderr!r}")

    # 11. The comparator itself can fail: perturbations just outside each tolerance are flagged,
    #     ones just inside are not, and null never matches a number.
    base = scenario(points=[[0, 0, 1.0], [0, 0, 0.5]], pixels=[[1200, 900]], blend={"m_t": 60, "eps": 10})
    named = [("comparator probe", base)]
    want = ev(base)
    T.expect(compare(named, [want], [want]) == (9, []), "comparator: identical results agree")

    def perturbed(field, fn):
        g = json.loads(json.dumps(want))
        if isinstance(g[field], list):
            g[field] = [fn(v) for v in g[field]]
        else:
            g[field] = fn(g[field])
        return len(compare(named, [g], [want])[1])

    cases = [("E", lambda v: v * (1 + 3e-6), "E relative"), ("E", lambda v: v + 2e-9, "E floor at 0"),
             ("E_max", lambda v: v * (1 + 3e-6), "E_max"), ("m", lambda v: v * (1 - 3e-6), "m"),
             ("coverage", lambda v: v + 2e-7, "coverage"), ("update_region", lambda v: v + 2e-4, "region"),
             ("w_video", lambda v: v + 2e-9, "w_video"), ("kappa", lambda v: v - 2e-9, "kappa"),
             ("w2", lambda v: v - 2e-9, "w2"), ("E_max", lambda v: None, "E_max null vs number"),
             ("update_region", lambda v: None, "region null vs box")]
    for field, fn, what in cases:
        T.expect(perturbed(field, fn) > 0, f"comparator misses a {what} perturbation outside tolerance")
    inside = [("E", lambda v: v * (1 + 5e-7)), ("coverage", lambda v: v + 5e-8),
              ("update_region", lambda v: v + 5e-5), ("w2", lambda v: v - 5e-10)]
    for field, fn in inside:
        T.expect(perturbed(field, fn) == 0, f"comparator flags a {field} perturbation inside tolerance")

    print(f"reference self-test: {T.checks} checks, {len(T.failures)} failures")
    for fl in T.failures:
        print("FAIL " + fl)
    return 1 if T.failures else 0


def mutation_check():
    """Is the scenario set sharp enough? Plausible mistakes (the paper's printed formulas, a
    missing plane, a different 'in front' test) are patched into the reference one at a time;
    each must produce mismatches against the unpatched reference. Not a ctest (about a minute)."""
    named = all_scenarios()
    want = [ref.evaluate(ref.parse_scenario(s)) for _, s in named]

    def front_above_zero(sc, X, query):
        pc, po = sc.real.to_camera(X), sc.virtual.to_camera(X)
        if query and (pc[2] <= sc.near or po[2] <= sc.near):
            return None
        c = sc.virtual.to_camera(sc.real.t)
        s = sc.d / pc[2]
        z2 = c[2] + s * (po[2] - c[2])
        if z2 <= 0:
            return math.inf
        k = (1 - s) / (po[2] * z2)
        return math.hypot(float(sc.virtual.fx * k * (po[0] * c[2] - c[0] * po[2])),
                          float(sc.virtual.fy * k * (po[1] * c[2] - c[1] * po[2])))

    def printed_corner(x, y, W, H, k):
        if k == 0:
            return 1.0
        xp, yp = abs(1 - 2 * x / W), abs(1 - 2 * y / H)
        if xp <= 1 - k and yp <= 1 - k:
            w = 1.0
        elif yp <= 1 - k:
            w = (1 - xp) / k
        elif xp <= 1 - k:
            w = (1 - yp) / k
        else:
            w = 1 - math.sqrt((k - 1 - xp) ** 2 + (k - 1 - yp) ** 2) / k
        w = min(max(w, 0.0), 1.0)
        return (math.sin((w - 0.5) * math.pi) + 1) / 2

    def printed_w1(m, m_t, eps):
        if m == math.inf:
            return 0.0
        if eps == 0:
            return 1.0 if m <= m_t else 0.0
        return min(max((m - m_t + eps) / (2 * eps), 0.0), 1.0)

    planes = ref._w_planes
    emax = ref.e_max
    mutants = [
        ("X'' in front when z'' > 0", "_error_exact", front_above_zero),
        ("W without the real near plane", "_w_planes", lambda sc: planes(sc)[:5] + planes(sc)[6:]),
        ("E_max ignores infinite vertices", "e_max", lambda sc: (lambda v: 0.0 if v == math.inf else v)(emax(sc))),
        ("w2 with the paper's printed corner term", "w2", printed_corner),
        ("the paper's printed w1 (sign reversed)", "w_video", printed_w1),
    ]
    missed = 0
    for what, attr, patch in mutants:
        saved = getattr(ref, attr)
        setattr(ref, attr, patch)
        try:
            got = [ref.evaluate(ref.parse_scenario(s)) for _, s in named]
        finally:
            setattr(ref, attr, saved)
        n = len(compare(named, got, want)[1])
        missed += n == 0
        print(f"mutant '{what}': {n} mismatching fields")
    return 1 if missed else 0


def main(argv):
    if len(argv) == 2 and argv[1] == "--self-test":
        return self_test()
    if len(argv) == 2 and argv[1] == "--mutation-check":
        return mutation_check()
    if len(argv) == 3 and argv[1] == "--dump":
        with open(argv[2], "w", encoding="utf-8") as f:
            json.dump([s for _, s in all_scenarios()], f, indent=1, allow_nan=False)
        return 0
    if len(argv) == 2:
        return run_comparison(argv[1])
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
