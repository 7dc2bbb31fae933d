#!/usr/bin/env python3
"""An independent reference for `hybrid-geom`, written from DESIGN.md and the paper only.

It answers the same scenario contract (issue #2 item 3): a JSON scenario object, or an array
of them, in; one result object, or an array, out. Standard library only.

Why it is trustworthy as a second opinion rather than a copy:
  * The geometry is EXACT. Every input double is turned into a `fractions.Fraction` (which
    holds the binary value exactly), and clipping, vertex enumeration, the near-plane tests
    and the coverage area are done in rational arithmetic. Only the final square root of E
    and the conversion to double round. Ties ("a vertex on a near plane counts as in front",
    a face of the workspace lying on a frustum plane, a quad exactly touching the frustum)
    are therefore decided by the mathematics, not by rounding.
  * It uses different algorithms from a clipping implementation:
      - W's vertices: every triple of W's 12 bounding planes is intersected; the feasible
        intersections are W's vertices. A double-precision pass only prunes triples that are
        clearly infeasible; every kept vertex is recomputed and checked exactly.
      - Update region and coverage: the real image rectangle is clipped in its own pixel
        coordinates (u, v) by the 5 virtual-frustum half-planes restricted to the plane
        z_c = d (sides first, near plane last). The region is the bounding box of that
        polygon; coverage is the exact area of its image under the plane->screen homography.
        (Clipping by the frustum sides in 3D is the same as clipping to the screen after
        projection, because the sides pass through the virtual camera centre.)
      - E uses a factored closed form instead of the difference of two projections:
        with p the virtual-camera coordinates of X, c those of the real camera centre and
        s = d / z_c, the point X'' is c + s (p - c) and
            u' - u''' = fx_o (1 - s) (p_x c_z - c_x p_z) / (p_z z''),
        so E vanishes on the plane exactly and never suffers cancellation.

Conventions (DESIGN.md): OpenCV axes, u = fx x / z + cx; poses camera-to-world, R row-major,
t the camera centre; images span [0, width] x [0, height].
"""

from __future__ import annotations

import itertools
import json
import math
import sys
from dataclasses import dataclass
from fractions import Fraction as Q

DEFAULT_NEAR_M = 0.01
INF = math.inf


class ScenarioError(ValueError):
    """A malformed scenario; the message names the field."""


# ----------------------------------------------------------------------------- parsing


def _number(obj, key, where, positive=False, default=None):
    if key not in obj:
        if default is not None:
            return default
        raise ScenarioError(f"{where}.{key}: missing (expected a number)")
    value = obj[key]
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ScenarioError(f"{where}.{key}: expected a number, got {value!r}")
    if not math.isfinite(value):
        raise ScenarioError(f"{where}.{key}: expected a finite number, got {value!r}")
    if positive and not value > 0:
        raise ScenarioError(f"{where}.{key}: expected a positive number, got {value!r}")
    return value


def _vector(obj, key, n, where):
    if key not in obj:
        raise ScenarioError(f"{where}.{key}: missing (expected {n} numbers)")
    value = obj[key]
    if not isinstance(value, list) or len(value) != n:
        raise ScenarioError(f"{where}.{key}: expected an array of {n} numbers")
    return [_number({"v": x}, "v", f"{where}.{key}[{i}]") for i, x in enumerate(value)]


@dataclass
class Camera:
    fx: Q
    fy: Q
    cx: Q
    cy: Q
    width: Q
    height: Q
    R: list  # 3x3 of Q, camera-to-world, R[row][col]
    t: list  # 3 of Q, camera centre

    def col(self, j):
        return [self.R[0][j], self.R[1][j], self.R[2][j]]

    def to_camera(self, X):
        """R^T (X - t): the camera-frame coordinates of world point X."""
        d = [X[0] - self.t[0], X[1] - self.t[1], X[2] - self.t[2]]
        return [self.R[0][i] * d[0] + self.R[1][i] * d[1] + self.R[2][i] * d[2] for i in range(3)]


def _camera(obj, where):
    if not isinstance(obj, dict):
        raise ScenarioError(f"{where}: missing or not an object")
    fx = _number(obj, "fx", where, positive=True)
    fy = _number(obj, "fy", where, positive=True)
    cx = _number(obj, "cx", where)
    cy = _number(obj, "cy", where)
    width = _number(obj, "width", where, positive=True)
    height = _number(obj, "height", where, positive=True)
    r = _vector(obj, "R", 9, where)
    t = _vector(obj, "t", 3, where)
    # A rotation, to the precision JSON doubles can carry.
    for i in range(3):
        for j in range(3):
            dot = math.fsum(r[3 * k + i] * r[3 * k + j] for k in range(3))
            if abs(dot - (1.0 if i == j else 0.0)) > 1e-6:
                raise ScenarioError(f"{where}.R: not orthonormal (column {i} . column {j} = {dot})")
    det = (
        r[0] * (r[4] * r[8] - r[5] * r[7])
        - r[1] * (r[3] * r[8] - r[5] * r[6])
        + r[2] * (r[3] * r[7] - r[4] * r[6])
    )
    if det < 0:
        raise ScenarioError(f"{where}.R: a reflection (det < 0), expected a rotation")
    return Camera(
        Q(fx), Q(fy), Q(cx), Q(cy), Q(width), Q(height),
        [[Q(r[3 * i + j]) for j in range(3)] for i in range(3)],
        [Q(x) for x in t],
    )


@dataclass
class Scenario:
    real: Camera
    virtual: Camera
    d: Q
    near: Q
    box_min: list
    box_max: list
    points: list
    blend: tuple | None
    pixels: list


def parse_scenario(obj, where="scenario"):
    if not isinstance(obj, dict):
        raise ScenarioError(f"{where}: expected an object")
    real = _camera(obj.get("real"), f"{where}.real")
    virtual = _camera(obj.get("virtual"), f"{where}.virtual")
    d = _number(obj, "d", where, positive=True)
    near = _number(obj, "near", where, positive=True, default=DEFAULT_NEAR_M)
    ws = obj.get("workspace")
    if not isinstance(ws, dict):
        raise ScenarioError(f"{where}.workspace: missing or not an object")
    box_min = _vector(ws, "min", 3, f"{where}.workspace")
    box_max = _vector(ws, "max", 3, f"{where}.workspace")
    points = []
    for i, p in enumerate(obj.get("points", [])):
        points.append([Q(x) for x in _vector({"p": p}, "p", 3, f"{where}.points[{i}]")])
    blend = None
    if "blend" in obj:
        b = obj["blend"]
        if not isinstance(b, dict):
            raise ScenarioError(f"{where}.blend: expected an object")
        m_t = _number(b, "m_t", f"{where}.blend")
        eps = _number(b, "eps", f"{where}.blend")
        if eps < 0:
            raise ScenarioError(f"{where}.blend.eps: expected >= 0, got {eps}")
        blend = (m_t, eps)
    pixels = []
    for i, p in enumerate(obj.get("pixels", [])):
        pixels.append(_vector({"p": p}, "p", 2, f"{where}.pixels[{i}]"))
    return Scenario(
        real, virtual, Q(d), Q(near), [Q(x) for x in box_min], [Q(x) for x in box_max],
        points, blend, pixels,
    )


# ----------------------------------------------------------------------------- E


def _error_exact(sc: Scenario, X, query: bool):
    """E at world point X (exact Fractions). None = undefined (query point not in front of both
    cameras); INF = X'' not in front of the virtual camera (DESIGN.md 3)."""
    pc = sc.real.to_camera(X)
    po = sc.virtual.to_camera(X)
    if query and (pc[2] <= sc.near or po[2] <= sc.near):
        return None
    # Vertices of W satisfy both near planes exactly (exact arithmetic), so pc[2] > 0 here.
    c = sc.virtual.to_camera(sc.real.t)
    s = sc.d / pc[2]
    z2 = c[2] + s * (po[2] - c[2])  # depth of X'' in the virtual camera
    # "Not in front" means z <= near, as for query points (issue #2: "(z <= near)").
    if z2 <= sc.near:
        return INF
    k = (1 - s) / (po[2] * z2)
    du = sc.virtual.fx * k * (po[0] * c[2] - c[0] * po[2])
    dv = sc.virtual.fy * k * (po[1] * c[2] - c[1] * po[2])
    return math.hypot(float(du), float(dv))


def error_at(sc: Scenario, X):
    """E at a query point (a list of 3 Fractions or floats)."""
    return _error_exact(sc, [Q(x) for x in X], query=True)


# ----------------------------------------------------------------------------- W


def _w_planes(sc: Scenario):
    """W's 12 bounding half-spaces as (a, b): a . X + b >= 0, exact, world frame."""
    planes = []
    o, r = sc.virtual, sc.real

    def through(a, centre, offset=Q(0)):
        return (a, -(a[0] * centre[0] + a[1] * centre[1] + a[2] * centre[2]) - offset)

    x, y, z = o.col(0), o.col(1), o.col(2)
    comb = lambda s1, v1, s2, v2: [s1 * v1[i] + s2 * v2[i] for i in range(3)]  # noqa: E731
    planes.append(through(comb(o.fx, x, o.cx, z), o.t))  # u >= 0
    planes.append(through(comb(o.width - o.cx, z, -o.fx, x), o.t))  # u <= width
    planes.append(through(comb(o.fy, y, o.cy, z), o.t))  # v >= 0
    planes.append(through(comb(o.height - o.cy, z, -o.fy, y), o.t))  # v <= height
    planes.append(through(z, o.t, sc.near))  # z_o >= near
    planes.append(through(r.col(2), r.t, sc.near))  # z_c >= near
    for i in range(3):
        e = [Q(0)] * 3
        e[i] = Q(1)
        planes.append((e, -sc.box_min[i]))
        ne = [Q(0)] * 3
        ne[i] = Q(-1)
        planes.append((ne, sc.box_max[i]))
    return planes


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _solve3(p1, p2, p3):
    """The point where three planes a.X + b = 0 meet, or None if they do not meet in a point."""
    (a1, b1), (a2, b2), (a3, b3) = p1, p2, p3
    c23 = _cross(a2, a3)
    det = _dot(a1, c23)
    if det == 0:
        return None
    c31, c12 = _cross(a3, a1), _cross(a1, a2)
    return [-(b1 * c23[i] + b2 * c31[i] + b3 * c12[i]) / det for i in range(3)]


def w_vertices(sc: Scenario):
    """W's vertices, exact. Empty list when W is empty."""
    planes = _w_planes(sc)
    # Work relative to the workspace centre so the double pre-pass is well conditioned.
    centre = [(sc.box_min[i] + sc.box_max[i]) / 2 for i in range(3)]
    centre = [Q(float(v)) for v in centre]
    fplanes = []
    for a, b in planes:
        af = [float(v) for v in a]
        n = math.sqrt(math.fsum(v * v for v in af))
        bf = float(b + _dot(a, centre))
        fplanes.append(([v / n for v in af], bf / n) if n > 0 else (af, bf))
    scale = 1.0 + max(abs(b) for _, b in fplanes)
    loose_tol = 1e-6 * scale
    vertices = set()
    for i, j, k in itertools.combinations(range(len(planes)), 3):
        (a1, b1), (a2, b2), (a3, b3) = fplanes[i], fplanes[j], fplanes[k]
        c23 = _cross(a2, a3)
        det = _dot(a1, c23)
        if abs(det) >= 1e-6:
            c31, c12 = _cross(a3, a1), _cross(a1, a2)
            y = [-(b1 * c23[n] + b2 * c31[n] + b3 * c12[n]) / det for n in range(3)]
            if any(_dot(a, y) + b < -loose_tol for a, b in fplanes):
                continue  # clearly outside W; no rounding can make it a vertex
        # Near-singular or plausibly feasible: decide exactly.
        X = _solve3(planes[i], planes[j], planes[k])
        if X is None:
            continue
        if all(_dot(a, X) + b >= 0 for a, b in planes):
            vertices.add(tuple(X))
    return [list(v) for v in vertices]


def e_max(sc: Scenario):
    """Max of E over W's vertices; 0 when W is empty (DESIGN.md 2)."""
    best = 0.0
    for X in w_vertices(sc):
        e = _error_exact(sc, X, query=False)
        if e == INF:
            return INF
        best = max(best, e)
    return best


# ----------------------------------------------------------------------------- quad clip


def _plane_map(sc: Scenario):
    """Virtual-camera coordinates of the point of plane z_c = d seen at real pixel (u, v),
    as p = U u + V v + K (affine, exact)."""
    r, o, d = sc.real, sc.virtual, sc.d
    # M = R_o^T R_c, c = R_o^T (t_c - t_o)
    M = [[sum(o.R[k][i] * r.R[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    c = o.to_camera(r.t)
    U = [M[i][0] * d / r.fx for i in range(3)]
    V = [M[i][1] * d / r.fy for i in range(3)]
    K = [
        M[i][0] * (-d * r.cx / r.fx) + M[i][1] * (-d * r.cy / r.fy) + M[i][2] * d + c[i]
        for i in range(3)
    ]
    return U, V, K


def _clip(poly, h):
    """Sutherland-Hodgman of a convex polygon by alpha u + beta v + gamma >= 0, exact."""
    alpha, beta, gamma = h
    out = []
    n = len(poly)
    for i in range(n):
        P, Qp = poly[i], poly[(i + 1) % n]
        gp = alpha * P[0] + beta * P[1] + gamma
        gq = alpha * Qp[0] + beta * Qp[1] + gamma
        if gp >= 0:
            out.append(P)
        if (gp > 0 and gq < 0) or (gp < 0 and gq > 0):
            s = gp / (gp - gq)
            out.append((P[0] + s * (Qp[0] - P[0]), P[1] + s * (Qp[1] - P[1])))
    return out


def visible_quad(sc: Scenario):
    """The real image rectangle on plane z_c = d, clipped by the virtual frustum (4 sides, then
    the near plane), in real pixel coordinates. Empty list when nothing is visible."""
    U, V, K = _plane_map(sc)
    o = sc.virtual

    def lin(sx, vx, sz, vz, off=Q(0)):
        return tuple(sx * vx[i] + sz * vz[i] for i in range(2)) + (sx * vx[2] + sz * vz[2] - off,)

    X = (U[0], V[0], K[0])
    Y = (U[1], V[1], K[1])
    Z = (U[2], V[2], K[2])
    halfplanes = [
        lin(o.fx, X, o.cx, Z),  # u_o >= 0
        lin(-o.fx, X, o.width - o.cx, Z),  # u_o <= width
        lin(o.fy, Y, o.cy, Z),  # v_o >= 0
        lin(-o.fy, Y, o.height - o.cy, Z),  # v_o <= height
        (Z[0], Z[1], Z[2] - sc.near),  # z_o >= near
    ]
    w, h = sc.real.width, sc.real.height
    poly = [(Q(0), Q(0)), (w, Q(0)), (w, h), (Q(0), h)]
    for hp in halfplanes:
        poly = _clip(poly, hp)
        if not poly:
            break
    return poly, (U, V, K)


def coverage_and_region(sc: Scenario):
    poly, (U, V, K) = visible_quad(sc)
    if not poly:
        return 0.0, None
    o = sc.virtual
    screen = []
    for u, v in poly:
        p = [U[i] * u + V[i] * v + K[i] for i in range(3)]
        screen.append((o.fx * p[0] / p[2] + o.cx, o.fy * p[1] / p[2] + o.cy))
    twice_area = sum(
        screen[i][0] * screen[(i + 1) % len(screen)][1]
        - screen[(i + 1) % len(screen)][0] * screen[i][1]
        for i in range(len(screen))
    )
    coverage = abs(twice_area) / 2 / (o.width * o.height)
    coverage = min(max(coverage, Q(0)), Q(1))
    us = [p[0] for p in poly]
    vs = [p[1] for p in poly]
    region = [float(min(us)), float(min(vs)), float(max(us)), float(max(vs))]
    return float(coverage), region


# ----------------------------------------------------------------------------- blending


def w_video(m, m_t, eps):
    """DESIGN.md 5: clamp((m_t + eps - m) / (2 eps), 0, 1); eps = 0 switches to synthetic once m
    exceeds m_t (the paper: "when the video error measure exceeds threshold m_t")."""
    if m == INF:
        return 0.0
    if eps == 0:
        return 1.0 if m <= m_t else 0.0
    return min(max((m_t + eps - m) / (2 * eps), 0.0), 1.0)


def w2(x, y, width, height, kappa):
    """DESIGN.md 6 / paper VII: per-pixel weight with rounded corners and a sinusoidal ramp.
    The paper's four cases are one expression: the distance of (x', y') beyond the inner square
    [0, 1 - kappa]^2 (per axis, or to the corner (1 - kappa, 1 - kappa)) over kappa."""
    if kappa == 0:
        w1 = 1.0
    else:
        xp = abs(1.0 - 2.0 * x / width)
        yp = abs(1.0 - 2.0 * y / height)
        dx = max(0.0, xp - (1.0 - kappa))
        dy = max(0.0, yp - (1.0 - kappa))
        w1 = min(max(1.0 - math.hypot(dx, dy) / kappa, 0.0), 1.0)
    return (math.sin((w1 - 0.5) * math.pi) + 1.0) / 2.0


# ----------------------------------------------------------------------------- driver


def _json_number(x):
    return None if x is None or x == INF else x


def evaluate(sc: Scenario):
    E = [error_at(sc, X) for X in sc.points]
    emax = e_max(sc)
    cov, region = coverage_and_region(sc)
    m = INF if (cov == 0 or emax == INF) else emax / cov
    out = {
        "E": [_json_number(e) for e in E],
        "E_max": _json_number(emax),
        "coverage": cov,
        "m": _json_number(m),
        "update_region": region,
    }
    if sc.blend is not None:
        wv = w_video(m, *sc.blend)
        kappa = 1.0 - wv
        out["w_video"] = wv
        out["kappa"] = kappa
        out["w2"] = [
            w2(x, y, float(sc.real.width), float(sc.real.height), kappa) for x, y in sc.pixels
        ]
    return out


def evaluate_json(doc):
    """A scenario object or an array of them -> result object or array (same order)."""
    if isinstance(doc, list):
        scenarios = [parse_scenario(s, f"[{i}]") for i, s in enumerate(doc)]
        return [evaluate(s) for s in scenarios]
    return evaluate(parse_scenario(doc))


def main(argv):
    try:
        if len(argv) > 1 and argv[1] != "-":
            with open(argv[1], encoding="utf-8") as f:
                text = f.read()
            source = argv[1]
        else:
            text = sys.stdin.read()
            source = "<stdin>"
        try:
            doc = json.loads(text)
        except json.JSONDecodeError as e:
            raise ScenarioError(f"{source}: not JSON ({e})") from e
        result = evaluate_json(doc)
    except (ScenarioError, OSError) as e:
        print(f"reference_geom: {e}", file=sys.stderr)
        return 2
    print(json.dumps(result, allow_nan=False))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
