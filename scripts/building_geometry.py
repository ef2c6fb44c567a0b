"""Plane geometry of generated buildings: walls derived from region polygons, and rigid transforms.

A building is drawn as regions (rooms and hallways, simple polygons whose shared edges coincide).
Its walls are every region edge, merged where edges of two regions lie on one line, minus the
openings: the whole shared edge of two hallway regions (a junction, a lobby opening onto a
hallway) and a door's width centred on each door. Standard library only.
"""

import math

# Two edges lie on one carrier line when their directions agree within ANGLE_TOL (rad) and their
# offsets within OFFSET_TOL (m): far below any wall thickness, far above float round-off.
ANGLE_TOL, OFFSET_TOL = 1e-5, 1e-4
MIN_WALL = 0.02  # m: shorter leftovers of a subtraction are round-off, not walls


class Carrier:
    """An infinite line: unit direction (cos t, sin t) with t in [0, pi), offset d = n . p."""

    def __init__(self, t, d):
        self.t, self.d = t, d
        self.u = (math.cos(t), math.sin(t))
        self.n = (-self.u[1], self.u[0])
        self.solid = []  # (lo, hi) along u: wall before openings
        self.open = []   # (lo, hi) along u: openings
        self.hallway_edges = []  # (lo, hi, region name) of hallway regions on this line

    def along(self, p):
        return p[0] * self.u[0] + p[1] * self.u[1]

    def point(self, s):
        return (self.u[0] * s + self.n[0] * self.d, self.u[1] * s + self.n[1] * self.d)


def carrier_key(p, q):
    """(t, d) of the line through p and q, t in [0, pi)."""
    t = math.atan2(q[1] - p[1], q[0] - p[0])
    if t < 0.0:
        t += math.pi
    if t >= math.pi - ANGLE_TOL:
        t -= math.pi
    d = -math.sin(t) * p[0] + math.cos(t) * p[1]
    return t, d


class CarrierSet:
    """Groups collinear edges (tolerance-based, so rotated edges computed twice still meet)."""

    def __init__(self):
        self.lines = []

    def find(self, p, q, create=True):
        t, d = carrier_key(p, q)
        for c in self.lines:
            dt = abs(c.t - t)
            if min(dt, math.pi - dt) < ANGLE_TOL and abs(c.d - d) < OFFSET_TOL:
                return c
            if min(dt, math.pi - dt) < ANGLE_TOL and math.pi - dt < ANGLE_TOL and abs(c.d + d) < OFFSET_TOL:
                return c
        if not create:
            return None
        c = Carrier(t, d)
        self.lines.append(c)
        return c


def merge(intervals):
    out = []
    for lo, hi in sorted(intervals):
        if out and lo <= out[-1][1] + 1e-9:
            out[-1] = (out[-1][0], max(out[-1][1], hi))
        else:
            out.append((lo, hi))
    return out


def subtract(solid, holes):
    out = []
    holes = merge(holes)
    for lo, hi in merge(solid):
        s = lo
        for hlo, hhi in holes:
            if hhi <= s or hlo >= hi:
                continue
            if hlo - s > MIN_WALL:
                out.append((s, hlo))
            s = max(s, hhi)
        if hi - s > MIN_WALL:
            out.append((s, hi))
    return out


def edges(poly):
    return [(poly[i], poly[(i + 1) % len(poly)]) for i in range(len(poly))]


def hallway_openings(regions):
    """Shared edge pieces of two hallway regions: [(name_a, name_b, centre, width)], widths > 0.3 m."""
    lines = CarrierSet()
    for r in regions:
        if r.kind != 'hallway':
            continue
        for p, q in edges(r.poly):
            c = lines.find(p, q)
            a, b = sorted((c.along(p), c.along(q)))
            c.hallway_edges.append((a, b, r.name))
    out = []
    for c in lines.lines:
        e = c.hallway_edges
        for i in range(len(e)):
            for j in range(i + 1, len(e)):
                if e[i][2] == e[j][2]:
                    continue
                lo, hi = max(e[i][0], e[j][0]), min(e[i][1], e[j][1])
                if hi - lo > 0.3:
                    out.append((e[i][2], e[j][2], c.point(0.5 * (lo + hi)), hi - lo))
    return out


def walls_from_regions(regions, doors):
    """Wall segments [(p, q)]: region edges merged per line, minus hallway-to-hallway shared edges
    and a door's width at each door ((centre, width) pairs lying on a region edge)."""
    lines = CarrierSet()
    for r in regions:
        for p, q in edges(r.poly):
            c = lines.find(p, q)
            c.solid.append(tuple(sorted((c.along(p), c.along(q)))))
    for a, b, centre, width in hallway_openings(regions):
        c = nearest_carrier(lines, centre)
        s = c.along(centre)
        c.open.append((s - width / 2.0, s + width / 2.0))
    for centre, width in doors:
        c = nearest_carrier(lines, centre)
        s = c.along(centre)
        c.open.append((s - width / 2.0, s + width / 2.0))
    out = []
    for c in lines.lines:
        for lo, hi in subtract(c.solid, c.open):
            out.append((c.point(lo), c.point(hi)))
    return out


def nearest_carrier(lines, p):
    """The carrier line with a solid piece through p (a door's or an opening's centre)."""
    best = None
    for c in lines.lines:
        off = abs(c.n[0] * p[0] + c.n[1] * p[1] - c.d)
        s = c.along(p)
        if off < OFFSET_TOL * 10 and any(lo - 1e-6 <= s <= hi + 1e-6 for lo, hi in c.solid):
            if best is None or off < best[0]:
                best = (off, c)
    if best is None:
        raise ValueError('opening at (%.3f, %.3f) lies on no region edge' % p)
    return best[1]


def rotate(p, yaw, about=(0.0, 0.0)):
    c, s = math.cos(yaw), math.sin(yaw)
    x, y = p[0] - about[0], p[1] - about[1]
    return (about[0] + c * x - s * y, about[1] + s * x + c * y)


def polygon_area(poly):
    return 0.5 * abs(sum(p[0] * q[1] - q[0] * p[1] for p, q in edges(poly)))


def arc_points(a, b, outward, sagitta, n=10):
    """Points strictly between a and b on the circular arc through a and b that bulges by `sagitta`
    towards the unit vector `outward` (perpendicular to a-b)."""
    chord = math.hypot(b[0] - a[0], b[1] - a[1])
    radius = (sagitta ** 2 + (chord / 2.0) ** 2) / (2.0 * sagitta)
    mid = ((a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0)
    centre = (mid[0] - outward[0] * (radius - sagitta), mid[1] - outward[1] * (radius - sagitta))
    ta = math.atan2(a[1] - centre[1], a[0] - centre[0])
    tb = math.atan2(b[1] - centre[1], b[0] - centre[0])
    span = math.atan2(math.sin(tb - ta), math.cos(tb - ta))
    return [(centre[0] + radius * math.cos(ta + span * k / n), centre[1] + radius * math.sin(ta + span * k / n))
            for k in range(1, n)]
