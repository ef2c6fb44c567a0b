#!/usr/bin/env python3
"""Generate the `large_floor` simulator world (and its scripted tour).

    python3 scripts/generate_large_floor.py          > worlds/large_floor.yaml
    python3 scripts/generate_large_floor.py --tour   > config/tours/large_floor.yaml

The output is deterministic (a fixed-seed linear congruential generator, no
`random` module) and only the Python standard library is used; the YAML text is
written by hand in the format that the simulator's world loader expects (see the
"World files" section of DESIGN.md).

Layout (100 m x 60 m, all coordinates in metres, walls on their centre lines):

    y 53.6..60.0   row 7: rooms, doors to hall_3
    y 51.4..53.6   hall_3 (east-west, 2.2 m wide, whole width)
    y 38.6..51.4   rows 6 and 5 back to back, cut by three north-south hallways
    y 36.4..38.6   hall_2
    y 23.6..36.4   rows 4 and 3, cut by the north-south hallways
    y 21.4..23.6   hall_1
    y  8.6..21.4   rows 2 and 1, cut by the north-south hallways
    y  6.4.. 8.6   hall_0
    y  0.0.. 6.4   row 0: rooms, doors to hall_0

The north-south hallways (x 24.0..26.2, 49.0..51.2, 74.0..76.2) join the four
east-west hallways into a ladder with six hallway loops.  Each piece of a
north-south hallway between two east-west hallways is its own region
(`vhall_<k>_<j>`), and each junction opening between hallway regions is listed
as a door whose width is the hallway width.  Every room is 6.4 m deep and
about 4-6 m wide, has one door (0.9-1.2 m) to its hallway, and a few pairs of
neighbouring rooms share an extra connecting door.

The small `World` / `RoomFrame` helpers below are generic: the hand-designed
worlds (institute, small_loop) were laid out with the same conventions.
"""

import math
import sys


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
        self.cylinders = []  # (group, center, radius, comment)
        self.regions = []    # (group, name, kind, polygon, comment)
        self.doors = []      # (group, a, b, center, width, comment)
        self.start = None
        self.header = []

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

    def cylinder(self, center, radius, group="", comment=""):
        self.cylinders.append((group, tuple(center), radius, comment))

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
        o.append("boxes:")
        last = None
        for g, c, s, yaw, com in self.boxes:
            group_comment(g)
            last = g
            o.append("  - {center: %s, size: %s, yaw: %s}%s"
                     % (fpt(c), fpt(s), fmt(yaw), ("  # " + com) if com else ""))
        o.append("cylinders:")
        last = None
        for g, c, r, com in self.cylinders:
            group_comment(g)
            last = g
            o.append("  - {center: %s, radius: %s}%s"
                     % (fpt(c), fmt(r), ("  # " + com) if com else ""))
        o.append("robot:")
        o.append("  start: [%s, %s, %s]" % tuple(fmt(v) for v in self.start))
        o.append("# Ground truth for evaluation only - never read by mapping or localization:")
        o.append("regions:")
        last = None
        for g, n, k, poly, com in self.regions:
            group_comment(g)
            last = g
            o.append("  - {name: %s, kind: %s, polygon: [%s]}%s"
                     % (n, k, ", ".join(fpt(p) for p in poly), ("  # " + com) if com else ""))
        o.append("doors:")
        last = None
        for g, a, b, c, w, com in self.doors:
            group_comment(g)
            last = g
            o.append("  - {between: [%s, %s], center: %s, width: %s}%s"
                     % (a, b, fpt(c), fmt(w), ("  # " + com) if com else ""))
        return "\n".join(o) + "\n"


class RoomFrame:
    """A right-handed frame for placing furniture in a rectangular room.

    v is the depth into the room measured from the wall with the room's
    hallway door ('N', 'S', 'E' or 'W' side of the rectangle), u runs along
    that wall, from its left end as seen by a robot looking into the room.
    Placing the same (u, v) furniture in two rooms of equal size with doors on
    the same side gives rooms that look alike from their doors.
    """

    DIRS = {"N": (0.0, -1.0), "S": (0.0, 1.0), "E": (-1.0, 0.0), "W": (1.0, 0.0)}

    def __init__(self, x0, y0, x1, y1, side):
        self.rect = (x0, y0, x1, y1)
        self.side = side
        self.d = self.DIRS[side]
        self.r = (self.d[1], -self.d[0])
        self.origin = {"N": (x1, y1), "S": (x0, y0), "E": (x1, y0), "W": (x0, y1)}[side]
        if side in ("N", "S"):
            self.W, self.D = x1 - x0, y1 - y0
        else:
            self.W, self.D = y1 - y0, x1 - x0

    def pt(self, u, v):
        return (round(self.origin[0] + u * self.r[0] + v * self.d[0], 4),
                round(self.origin[1] + u * self.r[1] + v * self.d[1], 4))

    def size(self, su, sv):
        return (su, sv) if self.side in ("N", "S") else (sv, su)

    def center(self):
        x0, y0, x1, y1 = self.rect
        return ((x0 + x1) / 2.0, (y0 + y1) / 2.0)


# ---------------------------------------------------------------------------
# large_floor
# ---------------------------------------------------------------------------

WIDTH, HEIGHT = 100.0, 60.0
HALL_W = 2.2
ROOM_D = 6.4
# (y_south, y_north) of the four east-west hallways
HALLS = [(6.4, 8.6), (21.4, 23.6), (36.4, 38.6), (51.4, 53.6)]
# x_west of the three north-south hallways (each HALL_W wide)
VHALLS = [24.0, 49.0, 74.0]
# rows of rooms: (y0, y1, hallway index, door side of the room)
ROWS = [
    (0.0, 6.4, 0, "N"),
    (8.6, 15.0, 0, "S"),
    (15.0, 21.4, 1, "N"),
    (23.6, 30.0, 1, "S"),
    (30.0, 36.4, 2, "N"),
    (38.6, 45.0, 2, "S"),
    (45.0, 51.4, 3, "N"),
    (53.6, 60.0, 3, "S"),
]
# rooms the scripted tour visits: (row, index in row), and connected pairs it crosses
TOUR_ROOMS = [(0, 2), (1, 6), (3, 9), (4, 15), (5, 4), (6, 12), (7, 16), (2, 17), (7, 3)]


def hall_name(j):
    return "hall_%d" % j


def vhall_name(k, j):
    return "vhall_%d_%d" % (k, j)


def row_blocks(row):
    """x intervals of a row not taken by north-south hallways."""
    if row in (0, 7):
        return [(0.0, WIDTH)]
    edges = [0.0]
    for xv in VHALLS:
        edges += [xv, xv + HALL_W]
    edges.append(WIDTH)
    return [(edges[i], edges[i + 1]) for i in range(0, len(edges), 2)]


def split_block(rng, x0, x1):
    width = x1 - x0
    n = max(1, int(math.ceil(width / 5.4)))
    weights = [1.0 + rng.uniform(-0.1, 0.1) for _ in range(n)]
    total = sum(weights)
    xs, acc = [x0], 0.0
    for w in weights[:-1]:
        acc += w
        xs.append(snap(x0 + width * acc / total))
    xs.append(x1)
    return list(zip(xs, xs[1:]))


def furnish(world, rng, f, ud, wd, group, connected_sides):
    """Desk at the back wall, then maybe a cabinet or table and a plant.

    Keeps a lane 0.7 m either side of the door axis free up to 1 m from the
    back wall, so that a robot can drive straight in, and keeps the middle
    depth band free in rooms with a connecting door in a side wall.
    """
    W, D = f.W, f.D
    mirror = ud > W / 2.0

    def M(u):
        return W - u if mirror else u

    # desk against the back wall, on the far side from the door
    du = snap(rng.uniform(max(0.95, ud + 0.3), W - 0.95)) if not mirror else \
        snap(rng.uniform(0.95, min(W - 0.95, ud - 0.3)))
    world.box(f.pt(du, D - 0.5), f.size(1.6, 0.8), 0.0, group, "desk")
    opts = rng.rand()
    far_side = "right" if not mirror else "left"
    if far_side in connected_sides:
        pass
    elif opts < 0.4:
        world.box(f.pt(M(W - 0.35), D * 0.45), f.size(0.5, 1.2), 0.0, group, "cabinet")
    elif opts < 0.75 and M(ud) + 0.7 < W - 2.4:
        world.box(f.pt(M(W - 1.6), D * 0.5), f.size(1.6, 0.9), 0.0, group, "table")
    if rng.rand() < 0.35 and M(ud) + wd / 2.0 + 0.2 < W - 0.6:
        world.cylinder(f.pt(M(W - 0.35), 0.35), 0.18, group, "plant")


def build_large_floor():
    rng = Lcg(20010927)
    w = World("large_floor")
    w.header = [
        "large_floor: a 100 m x 60 m office floor for scaling tests (generated, do not edit:",
        "  python3 scripts/generate_large_floor.py > worlds/large_floor.yaml).",
        "Four east-west hallways (hall_0..hall_3, 2.2 m wide, the whole width) at",
        "y = 6.4, 21.4, 36.4, 51.4 (south walls); three north-south hallways at",
        "x = 24.0, 49.0, 74.0 (west walls) join them into a ladder with six loops.",
        "Rooms are 6.4 m deep and %s m wide, in eight rows, each with one door",
        "to its hallway; some neighbouring rooms also share a connecting door.",
        "Junction openings between hallway regions are listed as doors (width 2.2).",
    ]
    w.start = (1.5, (HALLS[0][0] + HALLS[0][1]) / 2.0, 0.0)
    w.polyline([(0, 0), (WIDTH, 0), (WIDTH, HEIGHT), (0, HEIGHT), (0, 0)], "outer walls")

    # east-west hallway walls (the outer walls close their ends)
    for j, (ys, yn) in enumerate(HALLS):
        w.wall((0, ys), (WIDTH, ys), "%s walls" % hall_name(j))
        w.wall((0, yn), (WIDTH, yn), "%s walls" % hall_name(j))
    # north-south hallway walls, one piece between each pair of east-west hallways
    for k, xv in enumerate(VHALLS):
        for j in range(len(HALLS) - 1):
            y0, y1 = HALLS[j][1], HALLS[j + 1][0]
            g = "%s walls" % vhall_name(k, j)
            w.wall((xv, y0), (xv, y1), g)
            w.wall((xv + HALL_W, y0), (xv + HALL_W, y1), g)
    # walls between back-to-back rows
    for r in (1, 3, 5):
        y = ROWS[r][1]
        for (x0, x1) in row_blocks(r):
            w.wall((x0, y), (x1, y), "walls between rows %d and %d" % (r, r + 1))

    # hallway regions and junction openings
    for j, (ys, yn) in enumerate(HALLS):
        w.region_rect(hall_name(j), "hallway", 0, ys, WIDTH, yn, "hallways")
    for k, xv in enumerate(VHALLS):
        for j in range(len(HALLS) - 1):
            y0, y1 = HALLS[j][1], HALLS[j + 1][0]
            w.region_rect(vhall_name(k, j), "hallway", xv, y0, xv + HALL_W, y1, "hallways")
            cx = xv + HALL_W / 2.0
            w.door(vhall_name(k, j), hall_name(j), (cx, y0), HALL_W,
                   "hallway junctions", junction=True)
            w.door(vhall_name(k, j), hall_name(j + 1), (cx, y1), HALL_W,
                   "hallway junctions", junction=True)

    rooms, widths = {}, []
    for r, (y0, y1, hj, side) in enumerate(ROWS):
        rects = []
        for (bx0, bx1) in row_blocks(r):
            rects += split_block(rng, bx0, bx1)
        # partition walls inside the row (block ends are hallway or outer walls)
        ends = set()
        for (bx0, bx1) in row_blocks(r):
            ends.update((bx0, bx1))
        for (x0, _) in rects:
            if x0 not in ends:
                w.wall((x0, y0), (x0, y1), "row %d partitions" % r)
        # which neighbours share a connecting door (never two in a row)
        links, prev_linked = [], False
        for i in range(len(rects) - 1):
            same_block = rects[i][1] == rects[i + 1][0] and rects[i][1] not in ends
            if same_block and not prev_linked and rng.rand() < 0.15:
                links.append(i)
                prev_linked = True
            else:
                prev_linked = False
        for i, (x0, x1) in enumerate(rects):
            name = "room_%d_%02d" % (r, i)
            f = RoomFrame(x0, y0, x1, y1, side)
            wd = rng.choice([0.9, 0.9, 1.0, 1.1, 1.2])
            ud = snap(rng.uniform(0.85 + wd / 2.0, f.W - 0.85 - wd / 2.0))
            rooms[(r, i)] = dict(name=name, frame=f, ud=ud, wd=wd, hall=hj, row=r)
            w.region_rect(name, "room", x0, y0, x1, y1, "row %d rooms" % r)
            widths.append(x1 - x0)
        for i in links:
            rooms[(r, i)]["link"] = i + 1
            rooms[(r, i + 1)]["link"] = i
        for i in range(len(rects)):
            room = rooms[(r, i)]
            f = room["frame"]
            w.door(room["name"], hall_name(hj), f.pt(room["ud"], 0.0), room["wd"],
                   "row %d doors" % r)
        for i in links:
            a, b = rooms[(r, i)], rooms[(r, i + 1)]
            x = rects[i][1]
            w.door(a["name"], b["name"], (x, (y0 + y1) / 2.0), 0.9,
                   "connecting doors", "connecting door")
        for i in range(len(rects)):
            room = rooms[(r, i)]
            f = room["frame"]
            # sides (as seen from the door) that have a connecting door
            sides = set()
            if "link" in room:
                east = room["link"] > i
                # for doors on the south wall u grows eastwards, on the north wall westwards
                right_is_east = (side == "S")
                sides.add("right" if east == right_is_east else "left")
            furnish(w, rng, f, room["ud"], room["wd"], "%s" % room["name"], sides)
    w.header = [h % ("%s-%s" % (fmt(min(widths)), fmt(max(widths)))) if "%s" in h else h
                for h in w.header]
    w.header.insert(8, "%d rooms, %d doors (%d connecting doors between rooms)."
                    % (len(widths), len(w.doors),
                       sum(1 for d in w.doors if d[1].startswith("room") and d[2].startswith("room"))))
    return w, rooms


def build_tour(w, rooms):
    """Waypoints driving every hallway end to end and visiting a few rooms."""
    hy = [(ys + yn) / 2.0 for ys, yn in HALLS]
    vx = [xv + HALL_W / 2.0 for xv in VHALLS]
    x_w, x_e = 1.2, WIDTH - 1.2
    wps = []
    visits = {}
    for (r, i) in TOUR_ROOMS:
        visits.setdefault(ROWS[r][2], []).append(rooms[(r, i)])

    def goto(p):
        p = (round(p[0], 3), round(p[1], 3))
        if not wps or wps[-1] != p:
            wps.append(p)

    def visit_room(room):
        f = room["frame"]
        door = f.pt(room["ud"], 0.0)
        here = wps[-1]
        goto((door[0], here[1]))
        inner = f.pt(room["ud"], f.D / 2.0)
        goto(inner)
        if "link" in room and not room.get("done_link"):
            other = rooms[(room["row"], room["link"])]
            f2 = other["frame"]
            other["done_link"] = room["done_link"] = True
            goto(f2.pt(other["ud"], f2.D / 2.0))
            door2 = f2.pt(other["ud"], 0.0)
            goto((door2[0], here[1]))
        else:
            goto((door[0], here[1]))

    def drive_hall(j, x_to):
        """Drive along hall j to x_to, visiting the tour's rooms passed on the way."""
        x_from = wps[-1][0]
        todo = [rm for rm in visits.get(j, []) if not rm.get("visited")]
        lo, hi = min(x_from, x_to), max(x_from, x_to)
        on_way = [rm for rm in todo if lo <= rm["frame"].pt(rm["ud"], 0)[0] <= hi]
        on_way.sort(key=lambda rm: rm["frame"].pt(rm["ud"], 0)[0], reverse=x_to < x_from)
        for rm in on_way:
            rm["visited"] = True
            visit_room(rm)
        goto((x_to, hy[j]))

    # hall_0 west to east, back to the east ladder rung, up through all halls
    goto((x_w + 0.5, hy[0]))
    drive_hall(0, x_e)
    goto((vx[2], hy[0]))
    goto((vx[2], hy[3]))
    # hall_3 end to end, then down the west rung to hall_0
    drive_hall(3, x_e)
    drive_hall(3, x_w)
    goto((vx[0], hy[3]))
    goto((vx[0], hy[0]))
    # hall_0 to the middle rung, up to hall_1; hall_1 end to end
    goto((vx[1], hy[0]))
    goto((vx[1], hy[1]))
    drive_hall(1, x_w)
    drive_hall(1, x_e)
    # middle rung up to hall_2; hall_2 end to end; then up to hall_3 and home
    goto((vx[1], hy[1]))
    goto((vx[1], hy[2]))
    drive_hall(2, x_e)
    drive_hall(2, x_w)
    goto((vx[1], hy[2]))
    goto((vx[1], hy[3]))
    goto((vx[1], hy[0]))
    drive_hall(0, x_w + 0.5)
    missing = [rm["name"] for rs in visits.values() for rm in rs if not rm.get("visited")]
    if missing:
        raise RuntimeError("tour misses rooms %s" % missing)
    return wps


def emit_tour(w, wps, visited):
    length, prev = 0.0, w.start[:2]
    for p in wps:
        length += math.hypot(p[0] - prev[0], p[1] - prev[1])
        prev = p
    o = [
        "# Scripted tour of worlds/large_floor.yaml (generated, do not edit:",
        "#   python3 scripts/generate_large_floor.py --tour > config/tours/large_floor.yaml).",
        "# Waypoints [x, y] in world metres; starting at the world's robot.start the robot",
        "# drives straight from one waypoint to the next (turning on the spot at each), never",
        "# closer than 0.35 m to a wall, box or cylinder.  It drives all four east-west",
        "# hallways end to end and every piece of the three north-south hallways, and enters",
        "# these rooms through the door centre, perpendicular to the wall:",
        "#   %s" % ", ".join(visited),
        "# Length from the start pose: %.1f m." % length,
        "waypoints:",
    ]
    for p in wps:
        o.append("  - %s" % fpt(p))
    return "\n".join(o) + "\n"


def main(argv):
    w, rooms = build_large_floor()
    if "--tour" in argv[1:]:
        wps = build_tour(w, rooms)
        visited = [rooms[k]["name"] for k in TOUR_ROOMS]
        for k in TOUR_ROOMS:
            if "link" in rooms[k]:
                visited.append(rooms[(k[0], rooms[k]["link"])]["name"] + " (connecting door)")
        sys.stdout.write(emit_tour(w, wps, visited))
    else:
        sys.stdout.write(w.emit())
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
