"""Writes simulator world files (the "World files" format of DESIGN.md) from walls, doors, furniture
and ground-truth regions: the shared writer of scripts/generate_large_floor.py and
scripts/generate_building. Standard library only; the YAML text is written by hand so that comments
can group the walls, rooms and doors of one part of the building."""

import math


def fmt(x):
    """Shortest readable form of a coordinate, rounded to the millimetre."""
    v = round(float(x), 3)
    if v == 0:
        v = 0.0
    s = "%.3f" % v
    s = s.rstrip("0").rstrip(".")
    return s if s not in ("", "-") else "0"


def fpt(p):
    return "[%s, %s]" % (fmt(p[0]), fmt(p[1]))


class Lcg:
    """Tiny deterministic pseudo-random generator (Numerical Recipes LCG)."""

    def __init__(self, seed):
        self.state = seed & 0xFFFFFFFF

    def rand(self):
        self.state = (1664525 * self.state + 1013904223) & 0xFFFFFFFF
        return self.state / 4294967296.0

    def uniform(self, a, b):
        return a + (b - a) * self.rand()

    def choice(self, seq):
        return seq[min(int(self.rand() * len(seq)), len(seq) - 1)]


def snap(x, step=0.05):
    return round(round(x / step) * step, 3)


class World:
    """Collects walls, doors, furniture and ground-truth regions; writes YAML.

    Walls are straight lines; a door registered with `door()` cuts a gap of
    exactly its width, centred on the door, into the wall line it lies on (a
    hallway junction opening usually lies on no wall and cuts nothing).
    """

    def __init__(self, name, wall_thickness=0.10, wall_height=2.0):
        self.name = name
        self.wall_thickness = wall_thickness
        self.wall_height = wall_height
        self.lines = []      # dicts: p0, p1, thickness, group, gaps
        self.polylines = []  # (group, points, thickness): walls without doors
        self.boxes = []      # (group, center, size, yaw, comment)
        self.cylinders = []  # (group, center, radius, height or None, comment)
        self.regions = []    # (group, name, kind, polygon, comment)
        self.doors = []      # (group, a, b, center, width, comment)
        self.start = None
        self.header = []
        self.colors = {}     # the camera's: floor, ceiling, wall_ends -> (r, g, b), 0-255

    # -- walls ------------------------------------------------------------
    def polyline(self, points, group, thickness=None):
        self.polylines.append((group, [tuple(p) for p in points], thickness))

    def wall(self, p0, p1, group, thickness=None):
        self.lines.append(dict(p0=tuple(p0), p1=tuple(p1), thickness=thickness,
                               group=group, gaps=[]))

    def _line_param(self, line, c):
        (x0, y0), (x1, y1) = line["p0"], line["p1"]
        dx, dy = x1 - x0, y1 - y0
        length = math.hypot(dx, dy)
        ux, uy = dx / length, dy / length
        t = (c[0] - x0) * ux + (c[1] - y0) * uy
        off = -(c[0] - x0) * uy + (c[1] - y0) * ux
        return t, off, length

    # -- doors and regions ---------------------------------------------------
    def door(self, a, b, center, width, group="", comment="", junction=False):
        hits = []
        for line in self.lines:
            t, off, length = self._line_param(line, center)
            if abs(off) < 1e-6 and -1e-6 <= t <= length + 1e-6:
                hits.append((line, t, length))
        if len(hits) > 1:
            raise ValueError("door %s/%s at %s lies on %d wall lines"
                             % (a, b, center, len(hits)))
        if hits:
            line, t, length = hits[0]
            lo, hi = t - width / 2.0, t + width / 2.0
            if lo < -1e-6 or hi > length + 1e-6:
                raise ValueError("door %s/%s at %s does not fit in its wall"
                                 % (a, b, center))
            line["gaps"].append((max(lo, 0.0), min(hi, length)))
        elif not junction:
            raise ValueError("door %s/%s at %s lies on no wall" % (a, b, center))
        self.doors.append((group, a, b, tuple(center), width, comment))

    def region_rect(self, name, kind, x0, y0, x1, y1, group="", comment=""):
        poly = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]  # counter-clockwise
        self.regions.append((group, name, kind, poly, comment))

    def region_poly(self, name, kind, poly, group="", comment=""):
        self.regions.append((group, name, kind, [tuple(p) for p in poly], comment))

    # -- furniture --------------------------------------------------------
    def box(self, center, size, yaw=0.0, group="", comment=""):
        self.boxes.append((group, tuple(center), tuple(size), yaw, comment))

    def cylinder(self, center, radius, group="", comment="", height=None):
        """height: m (None: the file says none, a pillar up to the wall's height)."""
        self.cylinders.append((group, tuple(center), radius, height, comment))

    # -- output ----------------------------------------------------------
    def _wall_segments(self, line):
        (x0, y0), (x1, y1) = line["p0"], line["p1"]
        length = math.hypot(x1 - x0, y1 - y0)
        ux, uy = (x1 - x0) / length, (y1 - y0) / length
        gaps = sorted(line["gaps"])
        for (lo1, hi1), (lo2, _) in zip(gaps, gaps[1:]):
            if lo2 < hi1 - 1e-9:
                raise ValueError("overlapping doors on wall %s-%s" % (line["p0"], line["p1"]))
        out, t = [], 0.0
        for lo, hi in gaps + [(length, length)]:
            if lo - t > 1e-6:
                out.append(((x0 + ux * t, y0 + uy * t), (x0 + ux * lo, y0 + uy * lo)))
            t = hi
        return out

    def emit(self):
        o = []
        for h in self.header:
            o.append(("# " + h).rstrip())
        o.append("name: %s" % self.name)
        o.append("wall_thickness: %s" % fmt(self.wall_thickness))
        o.append("wall_height: %s" % fmt(self.wall_height))
        if self.colors:
            o.append("colors: {%s}" % ", ".join("%s: [%d, %d, %d]" % ((k,) + tuple(v)) for k, v in sorted(self.colors.items())))
        o.append("walls:")
        last = None

        def group_comment(g):
            if g and g != last:
                o.append("  # %s" % g)

        for g, pts, th in self.polylines:
            group_comment(g)
            last = g
            o.append("  - points: [%s]" % ", ".join(fpt(p) for p in pts))
            if th is not None:
                o.append("    thickness: %s" % fmt(th))
        for line in self.lines:
            for s in self._wall_segments(line):
                group_comment(line["group"])
                last = line["group"]
                o.append("  - points: [%s, %s]" % (fpt(s[0]), fpt(s[1])))
                if line["thickness"] is not None:
                    o.append("    thickness: %s" % fmt(line["thickness"]))
        def section(title, items, text):
            o.append(title)
            previous = None
            for item in items:
                if item[0] and item[0] != previous:
                    o.append("  # %s" % item[0])
                previous = item[0]
                o.append(text(*item[1:]))

        def note(com):
            return ("  # " + com) if com else ""

        section("boxes:", self.boxes, lambda c, s, yaw, com: "  - {center: %s, size: %s, yaw: %s}%s"
                % (fpt(c), fpt(s), fmt(yaw), note(com)))
        section("cylinders:", self.cylinders, lambda c, r, h, com: "  - {center: %s, radius: %s%s}%s"
                % (fpt(c), fmt(r), "" if h is None else ", height: %s" % fmt(h), note(com)))
        o.append("robot:")
        o.append("  start: [%s, %s, %s]" % tuple(fmt(v) for v in self.start))
        o.append("# Ground truth for evaluation only - never read by mapping or localization:")
        section("regions:", self.regions, lambda n, k, poly, com: "  - {name: %s, kind: %s, polygon: [%s]}%s"
                % (n, k, ", ".join(fpt(p) for p in poly), note(com)))
        section("doors:", self.doors, lambda a, b, c, w, com: "  - {between: [%s, %s], center: %s, width: %s}%s"
                % (a, b, fpt(c), fmt(w), note(com)))
        return "\n".join(o) + "\n"
