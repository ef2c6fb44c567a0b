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

`RoomFrame` below and `World` (scripts/world_writer.py) are generic: the hand-designed
worlds (institute, small_loop) were laid out with the same conventions.
"""

import math
import sys

from world_writer import Lcg, World, fmt, fpt, snap


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
        world.cylinder(f.pt(M(W - 0.35), 0.35), 0.18, group, "plant", height=1.2)


def build_large_floor():
    rng = Lcg(20010927)
    w = World("large_floor")
    w.colors = {'floor': (170, 160, 135), 'ceiling': (235, 235, 230), 'wall_ends': (90, 95, 100)}  # the camera's
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
