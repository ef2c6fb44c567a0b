"""Draws a random office, lab or school floor: hallways, rooms, doors, furniture, the robot's start.

The floor is a grid of bands (building frame, metres): along x and along y, blocks of rooms
alternate with hallway bands. A hallway band's cell between two blocks is a hallway segment;
where two hallway bands cross is a junction. A random spanning tree over the junctions, plus extra
segments (loops) and stubs to the outer wall (dead ends), decides which segments exist, so that L,
T and + junctions, loops and dead ends all arise. Each block is filled with rows of rooms whose
doors open onto the hallways beside it; an absent segment next to a hallway becomes a room with a
door in the hallway's end wall. On top: suites (rooms reachable only through another room), rooms
with two or three hallway doors, double doors, doors as close as 1.2 m, a hallway that changes
width, an open lobby, a wing at 30-60 degrees, a curved outer wall, furniture and pillars. The
whole building is then turned by a random yaw. See BuildingOptions for every range.

Every range is a stated building assumption for office, lab and school floors:
hallways 1.5-4.0 m wide, doors 0.7-1.2 m (single) and 1.4-1.8 m (double), rooms 2.6-10 m along the
hallway and 3.5-8 m deep, lobbies at least 8 x 8 m.
"""

import math
import random

from building_geometry import arc_points, hallway_openings, polygon_area, rotate, walls_from_regions

SNAP = 0.05  # m: coordinates are drawn on a 5 cm raster, as a floor plan is dimensioned


def snap(x):
    return round(round(x / SNAP) * SNAP, 3)


class BuildingOptions:
    """The ranges a building is drawn from, per size (m unless stated)."""

    SIZES = {
        # hallway bands along x plus along y (at least one each); rooms wanted (a building outside
    # this range is drawn again from the same generator); block widths between two hallways and
    # at the boundary
        'small': dict(halls=(2, 2), rooms=(6, 16), inner_block=(9.0, 13.0), outer_block=(5.0, 10.0)),
        'medium': dict(halls=(3, 4), rooms=(12, 36), inner_block=(9.0, 14.0), outer_block=(5.0, 11.0)),
        'large': dict(halls=(4, 6), rooms=(40, 140), inner_block=(9.0, 14.0), outer_block=(5.0, 11.0)),
    }
    hall_width = (1.5, 4.0)
    single_door = (0.7, 1.2)
    double_door = (1.4, 1.8)
    double_door_p = 0.15
    room_width = (2.6, 7.0)       # along the hallway
    wide_room = (7.0, 10.0)       # rooms that get two or three hallway doors
    wide_room_p = 0.15
    min_row_depth = 3.5
    end_room_depth = (3.0, 6.0)   # a room behind a hallway's end wall
    suite_min_depth = 10.0        # a one-sided block this deep gets a back row reachable through rooms
    lobby_min = 8.0               # both sides of a lobby
    loop_p = 0.35                 # an extra segment between two junctions (makes a loop)
    stub_p = 0.4                  # a segment from a junction to the outer wall (a dead end)
    narrowing_p = 0.3             # a segment narrower than its band: the hallway changes width
    lobby_p = 0.5
    wing_p = 0.5
    wing_angle = (30.0, 60.0)     # deg, to the hallway it leaves
    wing_length = (10.0, 18.0)
    curve_p = 0.5
    pillar_p = 0.5
    furnish_p = 0.75              # per room
    row_suite_p = 0.3             # per row of three or more rooms: one room only through its neighbour
    connecting_p = 0.1            # per divider: a door between two rooms that both have hallway doors
    near_pair_p = 0.25            # per divider: the two rooms' doors as close to it as their jambs allow
    jamb = 0.2                    # m from a door's edge to a dividing wall's centre line (0.15 m jamb + half wall)
    door_keep_out = 1.1           # m: no furniture within this of a door's centre (the robot's way in)


class Region:
    def __init__(self, name, kind, poly, tags=()):
        self.name, self.kind = name, kind
        self.poly = [(round(p[0], 6), round(p[1], 6)) for p in poly]
        self.tags = set(tags)


class RoomFrame:
    """A room's frame: origin on its hallway wall, u along that wall, v into the room."""

    def __init__(self, origin, u, v, width, depth):
        self.origin, self.u, self.v, self.width, self.depth = origin, u, v, width, depth

    def pt(self, a, b):
        return (self.origin[0] + a * self.u[0] + b * self.v[0], self.origin[1] + a * self.u[1] + b * self.v[1])

    def yaw(self):
        return math.atan2(self.u[1], self.u[0])


class Building:
    """The drawn building: regions, doors (name_a, name_b, centre, width), furniture, start."""

    def __init__(self, name):
        self.name = name
        self.regions = []
        self.doors = []          # (a, b, centre, width): room doors; hallway openings are added at the end
        self.frames = {}         # room name -> RoomFrame (for furniture)
        self.boxes = []          # (centre, (sx, sy), yaw, comment)
        self.cylinders = []      # (centre, radius, comment)
        self.walls = []          # (p, q) wall centre lines
        self.start = None
        self.features = set()    # what this building has (suite, lobby, wing, ...), for the benchmark's table
        self.yaw = 0.0

    def region(self, name):
        return next(r for r in self.regions if r.name == name)

    def add_door(self, a, b, centre, width):
        self.doors.append((a, b, (round(centre[0], 6), round(centre[1], 6)), snap(width)))


def rect(axis, a0, a1, d0, d1):
    """Rectangle with [a0, a1] along `axis` ('x' or 'y') and [d0, d1] across it."""
    if axis == 'x':
        return [(a0, d0), (a1, d0), (a1, d1), (a0, d1)]
    return [(d0, a0), (d1, a0), (d1, a1), (d0, a1)]


def axis_point(axis, a, d):
    return (a, d) if axis == 'x' else (d, a)


class LayoutDrawer:
    def __init__(self, seed, size):
        if size not in BuildingOptions.SIZES:
            raise ValueError('size must be one of %s' % ', '.join(BuildingOptions.SIZES))
        self.rng = random.Random(seed)
        self.opt = BuildingOptions
        self.size = BuildingOptions.SIZES[size]
        self.b = Building('building_%s_%d' % (size, seed))
        self.counter = {}

    def U(self, lo, hi):
        return self.rng.uniform(lo, hi)

    def p(self, prob):
        return self.rng.random() < prob

    def name(self, prefix):
        self.counter[prefix] = self.counter.get(prefix, 0) + 1
        return '%s_%d' % (prefix, self.counter[prefix])

    def door_width(self, room_width):
        if room_width >= 3.2 and self.p(self.opt.double_door_p):
            self.b.features.add('double_door')
            return snap(self.U(*self.opt.double_door))
        return snap(self.U(*self.opt.single_door))

    # ---- bands and hallway segments ------------------------------------------------------------

    def bands(self, n_halls):
        out, pos = [], 0.0
        for k in range(2 * n_halls + 1):
            if k % 2:
                w = snap(self.U(*self.opt.hall_width))
                out.append(('hall', pos, pos + w))
            else:
                w = snap(self.U(*(self.size['outer_block'] if k in (0, 2 * n_halls) else self.size['inner_block'])))
                out.append(('block', pos, pos + w))
            pos = round(pos + w, 3)
        return out

    def choose_segments(self):
        """The hallway segments: ('H', i, j) runs along x in y band j, ('V', i, j) along y in x band i."""
        nx, ny = len(self.xb), len(self.yb)
        junctions = [(i, j) for i in range(1, nx, 2) for j in range(1, ny, 2)]
        segs = {}
        for j in range(1, ny, 2):
            for i in range(0, nx, 2):
                ends = [(k, j) for k in (i - 1, i + 1) if 0 <= k < nx]
                segs[('H', i, j)] = ends
        for i in range(1, nx, 2):
            for j in range(0, ny, 2):
                ends = [(i, k) for k in (j - 1, j + 1) if 0 <= k < ny]
                segs[('V', i, j)] = ends
        interior = [s for s, e in segs.items() if len(e) == 2]
        stubs = [s for s, e in segs.items() if len(e) == 1]
        present, reached = set(), {self.rng.choice(junctions)}
        while len(reached) < len(junctions):  # randomized Prim: a spanning tree of the junctions
            frontier = [s for s in interior if s not in present and (segs[s][0] in reached) != (segs[s][1] in reached)]
            s = self.rng.choice(sorted(frontier))
            present.add(s)
            reached.update(segs[s])
        for s in sorted(interior):
            if s not in present and self.p(self.opt.loop_p):
                present.add(s)
                self.b.features.add('loop')
        for s in sorted(stubs):
            if self.p(self.opt.stub_p):
                present.add(s)
        rest = sorted(s for s in stubs if s not in present)
        while len(present) < 2 and rest:
            present.add(rest.pop(self.rng.randrange(len(rest))))
        self.segs, self.present = segs, present
        self.junctions = {j for s in present for j in segs[s]}

    def band_rect(self, i, j):
        return (self.xb[i][1], self.xb[i][2], self.yb[j][1], self.yb[j][2])

    # ---- hallways -------------------------------------------------------------------------------

    def draw_hallways(self):
        self.narrow = {}   # segment -> (side, delta): side -1 takes delta off the low side, +1 the high side
        self.hall_rect = {}
        self.hall_name = {}
        for s in sorted(self.present):
            kind, i, j = s
            x0, x1, y0, y1 = self.band_rect(i, j)
            w = (y1 - y0) if kind == 'H' else (x1 - x0)
            if w >= 2.8 and self.p(self.opt.narrowing_p):
                side = self.rng.choice((-1, 1))
                delta = snap(self.U(0.6, w - 1.6))
                self.narrow[s] = (side, delta)
                self.b.features.add('width_change')
                if kind == 'H':
                    y0, y1 = (y0 + delta, y1) if side < 0 else (y0, y1 - delta)
                else:
                    x0, x1 = (x0 + delta, x1) if side < 0 else (x0, x1 - delta)
            name = self.name('hall')
            self.hall_rect[s] = (x0, x1, y0, y1)
            self.hall_name[s] = name
            self.b.regions.append(Region(name, 'hallway', rect('x', x0, x1, y0, y1), ('segment',)))
        for (i, j) in sorted(self.junctions):
            x0, x1, y0, y1 = self.band_rect(i, j)
            name = self.name('junction')
            self.hall_name[('J', i, j)] = name
            self.b.regions.append(Region(name, 'hallway', rect('x', x0, x1, y0, y1), ('junction',)))

    # ---- rooms -----------------------------------------------------------------------------------

    def split(self, a0, a1):
        """Room boundaries along [a0, a1]."""
        xs = [a0]
        while a1 - xs[-1] > self.opt.room_width[1]:
            wide = self.p(self.opt.wide_room_p)
            w = self.U(*(self.opt.wide_room if wide else self.opt.room_width))
            if a1 - (xs[-1] + w) < self.opt.room_width[0]:
                w = (a1 - xs[-1]) / 2.0
            xs.append(snap(xs[-1] + w))
        xs.append(a1)
        return xs

    def room(self, poly, frame, tags=()):
        name = self.name('room')
        self.b.regions.append(Region(name, 'room', poly, tags))
        self.b.frames[name] = frame
        return name

    def row(self, axis, a0, a1, d_wall, d_far, hall, ends=()):
        """A row of rooms along `axis` over [a0, a1], their hallway wall at depth d_wall, back wall at
        d_far; `hall` the hallway region behind d_wall (None: the rooms get no hallway doors, e.g. a
        back row); `ends` = [(end, hallway name, (lo, hi))]: a hallway beside the row's first (end 0)
        or last (end 1) room over depths lo..hi, for a second door. Returns [(name, a0, a1)]."""
        xs = self.split(a0, a1)
        sign = 1.0 if d_far > d_wall else -1.0
        depth = abs(d_far - d_wall)
        rooms = []
        for lo, hi in zip(xs, xs[1:]):
            if axis == 'x':
                u, v = ((1.0, 0.0), (0.0, sign)) if sign > 0 else ((-1.0, 0.0), (0.0, sign))
                origin = (lo, d_wall) if sign > 0 else (hi, d_wall)
            else:
                u, v = ((0.0, -1.0), (sign, 0.0)) if sign > 0 else ((0.0, 1.0), (sign, 0.0))
                origin = (d_wall, hi) if sign > 0 else (d_wall, lo)
            frame = RoomFrame(origin, u, v, hi - lo, depth)
            name = self.room(rect(axis, lo, hi, min(d_wall, d_far), max(d_wall, d_far)), frame)
            rooms.append((name, lo, hi))
        if hall is None:
            return rooms
        doors = {name: self.hallway_doors(lo, hi) for name, lo, hi in rooms}
        for k in range(len(rooms) - 1):  # doors as close to a divider as their jambs allow
            (n1, _, h1), (n2, l2, _) = rooms[k], rooms[k + 1]
            if len(doors[n1]) == 1 and len(doors[n2]) == 1 and self.p(self.opt.near_pair_p):
                w1, w2 = doors[n1][0][1], doors[n2][0][1]
                doors[n1] = [(h1 - w1 / 2.0 - self.opt.jamb, w1)]
                doors[n2] = [(l2 + w2 / 2.0 + self.opt.jamb, w2)]
                self.b.features.add('close_doors')
        if len(rooms) >= 3 and self.p(self.opt.row_suite_p):
            k = self.rng.randrange(len(rooms))
            other = k - 1 if k > 0 and (k == len(rooms) - 1 or self.p(0.5)) else k + 1
            doors[rooms[k][0]] = []
            self.inner_door(axis, rooms[k], rooms[other], d_wall, d_far)
            self.b.features.add('suite')
        for k in range(len(rooms) - 1):
            if doors[rooms[k][0]] and doors[rooms[k + 1][0]] and self.p(self.opt.connecting_p):
                self.inner_door(axis, rooms[k], rooms[k + 1], d_wall, d_far)
        for name, lo, hi in rooms:
            for c, w in doors[name]:
                self.b.add_door(name, hall, axis_point(axis, c, d_wall), w)
            if len(doors[name]) > 1:
                self.b.features.add('multi_door_room')
        for end, hname, (dlo, dhi) in ends:
            name, lo, hi = rooms[0] if end == 0 else rooms[-1]
            if not doors[name] or not self.p(0.4):
                continue
            dlo, dhi = max(dlo, min(d_wall, d_far)), min(dhi, max(d_wall, d_far))
            w = self.door_width(dhi - dlo)
            if dhi - dlo < w + 2 * self.opt.jamb + 0.1:
                continue
            c = self.U(dlo + w / 2.0 + self.opt.jamb, dhi - w / 2.0 - self.opt.jamb)
            a = lo if end == 0 else hi
            self.b.add_door(name, hname, axis_point(axis, a, c), w)
            self.b.features.add('multi_door_room')
        return rooms

    def hallway_doors(self, lo, hi):
        width = hi - lo
        n = 1
        if width >= 6.5 and self.p(0.5):
            n = 3 if width >= 9.0 and self.p(0.4) else 2
        out = []
        for k in range(n):
            s0, s1 = lo + width * k / n, lo + width * (k + 1) / n
            w = self.door_width(s1 - s0)
            m = w / 2.0 + self.opt.jamb + 0.05
            if s1 - s0 < 2 * m:
                w = snap(self.opt.single_door[0])
                m = w / 2.0 + self.opt.jamb + 0.05
            out.append((self.U(s0 + m, s1 - m), w))
        return out

    def inner_door(self, axis, r1, r2, d_wall, d_far):
        """A door in the divider of two neighbouring rooms of a row."""
        a = r1[2] if r1[2] == r2[1] else r1[1]
        lo, hi = min(d_wall, d_far), max(d_wall, d_far)
        w = snap(self.U(0.8, 1.0))
        m = w / 2.0 + 0.4
        self.b.add_door(r1[0], r2[0], axis_point(axis, a, self.U(lo + m, hi - m)), w)

    def back_doors(self, axis, front, back, d_split):
        """Each back room's door into the front room it shares most of its wall with."""
        for name, lo, hi in back:
            best = max(front, key=lambda f: min(hi, f[2]) - max(lo, f[1]))
            olo, ohi = max(lo, best[1]), min(hi, best[2])
            w = snap(self.U(0.8, 1.0))
            m = w / 2.0 + self.opt.jamb + 0.05
            if ohi - olo < 2 * m:
                raise ValueError('back room %s shares too little wall with %s' % (name, best[0]))
            self.b.add_door(name, best[0], axis_point(axis, self.U(olo + m, ohi - m), d_split), w)

    def block_rect(self, i, j):
        x0, x1, y0, y1 = self.band_rect(i, j)
        for s, grow in ((('H', i, j - 1), 'y0'), (('H', i, j + 1), 'y1'), (('V', i - 1, j), 'x0'),
                        (('V', i + 1, j), 'x1')):
            if s in self.narrow:
                side, delta = self.narrow[s]
                if grow == 'y0' and side > 0:
                    y0 -= delta
                elif grow == 'y1' and side < 0:
                    y1 += delta
                elif grow == 'x0' and side > 0:
                    x0 -= delta
                elif grow == 'x1' and side < 0:
                    x1 += delta
        return x0, x1, y0, y1

    def draw_blocks(self):
        blocks = [(i, j) for i in range(0, len(self.xb), 2) for j in range(0, len(self.yb), 2)]
        sides = {}
        for i, j in blocks:
            sides[(i, j)] = {k: s for k, s in (('S', ('H', i, j - 1)), ('N', ('H', i, j + 1)),
                                                ('W', ('V', i - 1, j)), ('E', ('V', i + 1, j))) if s in self.present}
        lobby = None
        if self.p(self.opt.lobby_p):
            cands = []
            for blk in blocks:
                x0, x1, y0, y1 = self.block_rect(*blk)
                if sides[blk] and min(x1 - x0, y1 - y0) >= self.opt.lobby_min:
                    cands.append(blk)
            if cands:
                lobby = self.rng.choice(cands)
        for blk in blocks:
            if not sides[blk]:
                continue
            x0, x1, y0, y1 = self.block_rect(*blk)
            if blk == lobby:
                self.b.regions.append(Region('lobby', 'hallway', rect('x', x0, x1, y0, y1), ('lobby',)))
                self.b.features.add('lobby')
                continue
            self.fill_block(sides[blk], x0, x1, y0, y1)

    def fill_block(self, sides, x0, x1, y0, y1):
        if 'N' in sides or 'S' in sides:
            axis, (a0, a1), (lo, hi), (s_lo, s_hi), (e_lo, e_hi) = 'x', (x0, x1), (y0, y1), ('S', 'N'), ('W', 'E')
        else:
            axis, (a0, a1), (lo, hi), (s_lo, s_hi), (e_lo, e_hi) = 'y', (y0, y1), (x0, x1), ('W', 'E'), ('S', 'N')

        def ends(d0, d1):
            out = []
            for end, key in ((0, e_lo), (1, e_hi)):
                if key in sides:
                    r = self.hall_rect[sides[key]]
                    span = (r[2], r[3]) if axis == 'x' else (r[0], r[1])
                    out.append((end, self.hall_name[sides[key]], (max(span[0], d0), min(span[1], d1))))
            return out

        if s_lo in sides and s_hi in sides:
            mid = snap(0.5 * (lo + hi) + self.U(-1.0, 1.0))
            mid = min(max(mid, lo + self.opt.min_row_depth), hi - self.opt.min_row_depth)
            self.row(axis, a0, a1, lo, mid, self.hall_name[sides[s_lo]], ends(lo, mid))
            self.row(axis, a0, a1, hi, mid, self.hall_name[sides[s_hi]], ends(mid, hi))
            return
        wall, far = (lo, hi) if s_lo in sides else (hi, lo)
        hall = self.hall_name[sides[s_lo if s_lo in sides else s_hi]]
        depth = hi - lo
        if depth >= self.opt.suite_min_depth:
            front = snap(self.U(4.0, depth - 4.0))
            split = wall + front if far > wall else wall - front
            rows = self.row(axis, a0, a1, wall, split, hall, ends(min(wall, split), max(wall, split)))
            back = self.row(axis, a0, a1, split, far, None)
            self.back_doors(axis, rows, back, split)
            self.b.features.add('suite')
        else:
            self.row(axis, a0, a1, wall, far, hall, ends(lo, hi))

    def draw_end_rooms(self):
        """An absent segment beside a present junction: a room behind the hallway's end wall."""
        for s, ends in sorted(self.segs.items()):
            if s in self.present:
                continue
            kind, i, j = s
            x0, x1, y0, y1 = self.band_rect(i, j)
            axis = 'x' if kind == 'H' else 'y'
            a0, a1, d0, d1 = (x0, x1, y0, y1) if axis == 'x' else (y0, y1, x0, x1)
            live = [e for e in ends if e in self.junctions]
            if not live:
                continue
            end = self.rng.choice(live)
            at_low = (end[0] if axis == 'x' else end[1]) < (i if axis == 'x' else j)
            length = a1 - a0
            depth = snap(self.U(*self.opt.end_room_depth))
            if length - depth < 2.5:
                depth = length
            r0, r1 = (a0, a0 + depth) if at_low else (a1 - depth, a1)
            wall = a0 if at_low else a1
            width = d1 - d0
            v = (1.0, 0.0) if at_low else (-1.0, 0.0)
            if axis == 'y':
                v = (v[1], v[0])
            u = (-v[1], v[0])
            origin = axis_point(axis, wall, d0 + width / 2.0)
            frame = RoomFrame((origin[0] - u[0] * width / 2.0, origin[1] - u[1] * width / 2.0), u, v, width, depth)
            name = self.room(rect(axis, r0, r1, d0, d1), frame, ('end_room',))
            w = min(self.door_width(width), snap(width - 2 * self.opt.jamb - 0.1))
            c = self.U(d0 + w / 2.0 + self.opt.jamb, d1 - w / 2.0 - self.opt.jamb)
            self.b.add_door(name, self.hall_name[('J',) + end], axis_point(axis, wall, c), w)
            self.b.features.add('end_wall_door')

    # ---- a wing at an angle ----------------------------------------------------------------------

    def draw_wing(self):
        stubs = [s for s in sorted(self.present) if len(self.segs[s]) == 1]
        if not stubs or not self.p(self.opt.wing_p):
            return None
        s = self.rng.choice(stubs)
        kind, i, j = s
        x0, x1, y0, y1 = self.hall_rect[s]
        last_i, last_j = len(self.xb) - 1, len(self.yb) - 1
        # local frame: x out of the building through the stub's end, y to the left
        if kind == 'H' and i == last_i:
            side, origin, ex, ey, w = 'E', (x1, (y0 + y1) / 2.0), (1.0, 0.0), (0.0, 1.0), y1 - y0
        elif kind == 'H':
            side, origin, ex, ey, w = 'W', (x0, (y0 + y1) / 2.0), (-1.0, 0.0), (0.0, -1.0), y1 - y0
        elif j == last_j:
            side, origin, ex, ey, w = 'N', ((x0 + x1) / 2.0, y1), (0.0, 1.0), (-1.0, 0.0), x1 - x0
        else:
            side, origin, ex, ey, w = 'S', ((x0 + x1) / 2.0, y0), (0.0, -1.0), (1.0, 0.0), x1 - x0
        turn = self.rng.choice((-1.0, 1.0))
        phi = math.radians(self.U(*self.opt.wing_angle))

        def to_b(p):  # local (x, y) with the turn mirrored into the left-turn case
            lx, ly = p[0], p[1] * turn
            return (origin[0] + lx * ex[0] + ly * ey[0], origin[1] + lx * ex[1] + ly * ey[1])

        u, n = (math.cos(phi), math.sin(phi)), (-math.sin(phi), math.cos(phi))
        pb, pa = (0.0, w / 2.0), (0.0, -w / 2.0)
        pa2 = (pb[0] - w * n[0], pb[1] - w * n[1])
        depth = snap(self.U(4.0, 6.0))
        s0 = depth * math.tan(phi) + 0.5      # the inner row starts clear of the building's wall
        length = snap(max(self.U(*self.opt.wing_length), s0 + self.opt.room_width[0] + 1.0))

        def along(p, s, t=0.0):  # p + s u + t n
            return (p[0] + s * u[0] + t * n[0], p[1] + s * u[1] + t * n[1])

        hall = 'wing_hall'
        poly = [pa, pa2, along(pa2, length), along(pb, length), pb]
        if turn < 0:
            poly.reverse()
        self.b.regions.append(Region(hall, 'hallway', [to_b(p) for p in poly], ('wing',)))
        for base, s_from, t_sign in ((pa2, 0.0, -1.0), (pb, s0, 1.0)):
            xs = self.split(s_from, length)
            for lo, hi in zip(xs, xs[1:]):
                corners = [along(base, lo), along(base, hi), along(base, hi, t_sign * depth), along(base, lo, t_sign * depth)]
                b0, b1, b3 = to_b(corners[0]), to_b(corners[1]), to_b(corners[3])
                uf = ((b1[0] - b0[0]) / (hi - lo), (b1[1] - b0[1]) / (hi - lo))
                vb = ((b3[0] - b0[0]) / depth, (b3[1] - b0[1]) / depth)
                name = self.room([to_b(c) for c in corners], RoomFrame(b0, uf, vb, hi - lo, depth), ('wing',))
                for c, dw in self.hallway_doors(lo, hi):
                    self.b.add_door(name, hall, to_b(along(base, c)), dw)
        self.b.features.add('wing')
        return side

    # ---- a curved outer wall ---------------------------------------------------------------------

    def draw_curve(self, wing_side):
        if not self.p(self.opt.curve_p):
            return
        X0, X1 = self.xb[0][1], self.xb[-1][2]
        Y0, Y1 = self.yb[0][1], self.yb[-1][2]
        lines = {'W': ('x', X0, (-1.0, 0.0)), 'E': ('x', X1, (1.0, 0.0)), 'S': ('y', Y0, (0.0, -1.0)),
                 'N': ('y', Y1, (0.0, 1.0))}
        cands = []
        for r in self.b.regions:
            if r.kind == 'hallway' and 'lobby' not in r.tags:
                continue
            if 'wing' in r.tags or len(r.poly) != 4:
                continue
            for k in range(4):
                a, b = r.poly[k], r.poly[(k + 1) % 4]
                for side, (coord, value, out) in sorted(lines.items()):
                    if side == wing_side:
                        continue
                    ci = 0 if coord == 'x' else 1
                    if abs(a[ci] - value) < 1e-6 and abs(b[ci] - value) < 1e-6 and math.dist(a, b) >= 3.0:
                        cands.append((0 if 'lobby' in r.tags else 1, r.name, k, out))
        if not cands:
            return
        best = min(c[0] for c in cands)
        _, name, k, out = self.rng.choice([c for c in cands if c[0] == best])
        r = self.b.region(name)
        a, b = r.poly[k], r.poly[(k + 1) % 4]
        arc = arc_points(a, b, out, self.U(0.15, 0.3) * math.dist(a, b))
        r.poly = r.poly[:k + 1] + [(round(p[0], 6), round(p[1], 6)) for p in arc] + r.poly[k + 1:]
        self.b.features.add('curved_wall')

    # ---- furniture, pillars, start ---------------------------------------------------------------

    def doors_of(self, name):
        return [d[2] for d in self.b.doors if name in (d[0], d[1])]

    def clear_of_doors(self, name, centre, half):
        """A box of half-diagonal `half` at `centre` leaves the room's doorways free."""
        return all(math.dist(centre, d) > self.opt.door_keep_out + half for d in self.doors_of(name))

    def furnish(self, name):
        f = self.b.frames[name]
        W, D = f.width, f.depth
        if W < 2.6 or D < 3.0:
            return
        yaw = f.yaw()
        tag = name
        # a shelf against the back wall
        length = snap(self.U(1.0, min(3.0, W - 1.0)))
        sd = snap(self.U(0.35, 0.45))
        c = f.pt(self.U(0.1 + length / 2.0, W - 0.1 - length / 2.0), D - 0.07 - sd / 2.0)
        if self.clear_of_doors(name, c, math.hypot(length, sd) / 2.0):
            self.b.boxes.append((c, (length, sd), yaw, tag + ' shelf'))
        # a cabinet against a side wall
        if self.p(0.5):
            cw, cd = snap(self.U(0.5, 1.0)), 0.5
            side = self.rng.choice((0.07 + cd / 2.0, W - 0.07 - cd / 2.0))
            c = f.pt(side, self.U(1.0 + cw / 2.0, D - 0.5 - cw / 2.0)) if D > 2.5 + cw else None
            if c and self.clear_of_doors(name, c, math.hypot(cw, cd) / 2.0):
                self.b.boxes.append((c, (cd, cw), yaw, tag + ' cabinet'))
        # a table seen by the laser as its four legs, and chairs beside it
        if W >= 3.0 and D >= 4.0:
            tl, tw = snap(self.U(1.2, min(1.8, W - 1.6))), snap(self.U(0.7, 0.9))
            tc = (self.U(0.8 + tl / 2.0, W - 0.8 - tl / 2.0), self.U(1.6 + tw / 2.0, max(1.6 + tw / 2.0, D - 1.0 - tw / 2.0)))
            if self.clear_of_doors(name, f.pt(*tc), math.hypot(tl, tw) / 2.0):
                for sa in (-1, 1):
                    for sb in (-1, 1):
                        p = f.pt(tc[0] + sa * (tl / 2.0 - 0.05), tc[1] + sb * (tw / 2.0 - 0.05))
                        self.b.cylinders.append((p, 0.025, tag + ' table leg'))
                for k in range(self.rng.randrange(0, 3)):
                    cc = (tc[0] + self.U(-tl / 2.0 + 0.25, tl / 2.0 - 0.25), tc[1] + (tw / 2.0 + 0.35) * (1 if k else -1))
                    if self.clear_of_doors(name, f.pt(*cc), 0.3):
                        for sa in (-1, 1):
                            for sb in (-1, 1):
                                self.b.cylinders.append((f.pt(cc[0] + sa * 0.19, cc[1] + sb * 0.19), 0.015,
                                                         tag + ' chair leg'))
        self.b.features.add('furniture')

    def pillars(self):
        if not self.p(self.opt.pillar_p):
            return
        wide = [s for s in sorted(self.present) if min(self.hall_rect[s][1] - self.hall_rect[s][0],
                                                        self.hall_rect[s][3] - self.hall_rect[s][2]) >= 2.6]
        for s in self.rng.sample(wide, min(len(wide), self.rng.randint(1, 2))):
            x0, x1, y0, y1 = self.hall_rect[s]
            r = snap(self.U(0.15, 0.25))
            if s[0] == 'H':
                c = (self.U(x0 + 0.2 * (x1 - x0), x1 - 0.2 * (x1 - x0)), (y0 + y1) / 2.0)
            else:
                c = ((x0 + x1) / 2.0, self.U(y0 + 0.2 * (y1 - y0), y1 - 0.2 * (y1 - y0)))
            if all(math.dist(c, d[2]) > 1.5 for d in self.b.doors):
                self.b.cylinders.append((c, r, 'pillar in ' + self.hall_name[s]))
                self.b.features.add('pillar')

    def choose_start(self):
        segs = sorted(self.present)
        self.rng.shuffle(segs)
        for s in segs:
            x0, x1, y0, y1 = self.hall_rect[s]
            for _ in range(20):
                p = (self.U(x0 + 0.6, x1 - 0.6), self.U(y0 + 0.6, y1 - 0.6))
                if all(math.dist(p, c) > r + 0.6 for c, r, _ in self.b.cylinders):
                    return (p[0], p[1], self.U(-math.pi, math.pi))
        raise ValueError('no free start pose in any hallway')

    # ---- the whole -------------------------------------------------------------------------------

    def draw(self, yaw=None):
        for _ in range(50):
            self.b = Building(self.b.name)
            self.counter = {}
            self.draw_plan()
            rooms = sum(1 for r in self.b.regions if r.kind == 'room')
            if self.size['rooms'][0] <= rooms <= self.size['rooms'][1]:
                break
        else:
            raise ValueError('no building with %d-%d rooms in 50 draws' % self.size['rooms'])
        start = self.choose_start()
        self.b.walls = walls_from_regions(self.b.regions, [(d[2], d[3]) for d in self.b.doors])
        for a, b, centre, width in hallway_openings(self.b.regions):
            self.b.doors.append((a, b, centre, round(width, 3)))
        self.b.yaw = self.U(-math.pi, math.pi) if yaw is None else yaw
        if abs(math.remainder(self.b.yaw, math.pi / 2.0)) > math.radians(2.0):
            self.b.features.add('rotated')
        self.turn(start)
        return self.b

    def draw_plan(self):
        halls = self.rng.randint(*self.size['halls'])
        n_x = self.rng.randint(1, halls - 1)
        self.xb, self.yb = self.bands(n_x), self.bands(halls - n_x)
        self.choose_segments()
        self.draw_hallways()
        self.draw_blocks()
        self.draw_end_rooms()
        wing_side = self.draw_wing()
        self.draw_curve(wing_side)
        for r in list(self.b.regions):
            if r.kind == 'room' and self.p(self.opt.furnish_p):
                self.furnish(r.name)
        self.pillars()

    def turn(self, start):
        """Rotates the whole building by its yaw about the origin."""
        y = self.b.yaw
        for r in self.b.regions:
            r.poly = [rotate(p, y) for p in r.poly]
        self.b.doors = [(a, b, rotate(c, y), w) for a, b, c, w in self.b.doors]
        self.b.walls = [(rotate(p, y), rotate(q, y)) for p, q in self.b.walls]
        self.b.boxes = [(rotate(c, y), s, math.remainder(yaw + y, 2 * math.pi), t) for c, s, yaw, t in self.b.boxes]
        self.b.cylinders = [(rotate(c, y), r, t) for c, r, t in self.b.cylinders]
        p = rotate(start[:2], y)
        self.b.start = (p[0], p[1], math.remainder(start[2] + y, 2 * math.pi))


def draw_building(seed, size='medium', yaw=None):
    """The building of this seed and size (deterministic); yaw (rad) fixes its rotation."""
    return LayoutDrawer(seed, size).draw(yaw)


def floor_area(building):
    return sum(polygon_area(r.poly) for r in building.regions)
