"""A world file as a robot of the URDF's radius sees it (ground truth, for generation and scoring).

WorldRaster draws the walls, boxes and cylinders of a world (as yaml.safe_load gives it) on a grid,
grows them by the robot's radius (the configuration space) and answers: which rooms the robot can
reach from its start, and the oracle's route: a short walk from the start that enters every
reachable room, the floor for what any explorer must travel. Uses numpy, OpenCV (drawing,
distance transform) and SciPy (shortest paths on the grid).
"""

import math
import os
import xml.etree.ElementTree as ET

import cv2
import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

URDF = os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'urdf', 'robot.urdf')
RESOLUTION = 0.05  # m per cell: a quarter of the narrowest door's clearance for the robot
ROUTE_RESOLUTION = 0.10  # m per cell for the oracle's shortest paths (10 cm on a 20 m route is < 1 %)
ENTER_DEPTH = 1.0  # m: the oracle enters a room to a point this far past its doorway


def robot_radius(urdf=URDF):
    """The footprint radius: base_link's cylinder collision in the URDF, as the simulator reads it."""
    root = ET.parse(urdf).getroot()
    for link in root.iter('link'):
        if link.get('name') == 'base_link':
            cyl = link.find('collision/geometry/cylinder')
            if cyl is not None:
                return float(cyl.get('radius'))
    raise ValueError('%s: base_link has no cylinder collision' % urdf)


class WorldRaster:
    def __init__(self, world, radius, resolution=RESOLUTION):
        self.world, self.radius, self.res = world, radius, resolution
        pts = [p for w in world.get('walls', []) for p in w['points']]
        pts += [p for r in world.get('regions', []) for p in r['polygon']]
        for b in world.get('boxes', []):  # a world made of boxes alone (scripts/world_from_map)
            reach = math.hypot(*b['size']) / 2.0
            pts += [(b['center'][0] - reach, b['center'][1] - reach), (b['center'][0] + reach, b['center'][1] + reach)]
        for c in world.get('cylinders', []):
            pts += [(c['center'][0] - c['radius'], c['center'][1] - c['radius']),
                    (c['center'][0] + c['radius'], c['center'][1] + c['radius'])]
        xs, ys = [p[0] for p in pts], [p[1] for p in pts]
        self.x0, self.y0 = min(xs) - 1.0, min(ys) - 1.0
        self.w = int(math.ceil((max(xs) + 1.0 - self.x0) / resolution))
        self.h = int(math.ceil((max(ys) + 1.0 - self.y0) / resolution))
        occ = np.zeros((self.h, self.w), np.uint8)
        default_t = world.get('wall_thickness', 0.1)
        for wall in world.get('walls', []):
            t = wall.get('thickness', default_t)
            p = wall['points']
            for a, b in zip(p, p[1:]):
                self.fill_box(occ, ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2), (math.dist(a, b), t),
                              math.atan2(b[1] - a[1], b[0] - a[0]))
        for box in world.get('boxes', []):
            self.fill_box(occ, box['center'], box['size'], box.get('yaw', 0.0))
        for c in world.get('cylinders', []):
            cv2.circle(occ, self.cell(c['center']), max(1, int(round(c['radius'] / resolution))), 1, -1)
        self.occupied = occ
        # free for the robot's centre: farther than its radius from every obstacle
        clearance = cv2.distanceTransform((1 - occ).astype(np.uint8), cv2.DIST_L2, 5) * resolution
        self.clearance = clearance
        self.free = clearance > radius
        self.reach = self.flood(world['robot']['start'])

    def cell(self, p):
        return (int(round((p[0] - self.x0) / self.res)), int(round((p[1] - self.y0) / self.res)))

    def fill_box(self, occ, centre, size, yaw):
        c, s = math.cos(yaw), math.sin(yaw)
        hx, hy = size[0] / 2.0, size[1] / 2.0
        corners = [(centre[0] + c * x - s * y, centre[1] + s * x + c * y) for x, y in
                   ((-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy))]
        cv2.fillPoly(occ, [np.array([self.cell(p) for p in corners], np.int32)], 1)

    def flood(self, start):
        n, labels = cv2.connectedComponents(self.free.astype(np.uint8), connectivity=8)
        cx, cy = self.cell(start)
        if not self.free[cy, cx]:
            raise ValueError('the start (%.2f, %.2f) is closer than the robot radius to an obstacle' % tuple(start[:2]))
        return labels == labels[cy, cx]

    def region_mask(self, polygon):
        m = np.zeros((self.h, self.w), np.uint8)
        cv2.fillPoly(m, [np.array([self.cell(p) for p in polygon], np.int32)], 1)
        return m.astype(bool)

    def rooms(self):
        return [r for r in self.world.get('regions', []) if r['kind'] == 'room']

    def unreachable_rooms(self, min_area=0.25):
        """Rooms where the robot's centre reaches less than min_area m2."""
        out = []
        for r in self.rooms():
            if (self.region_mask(r['polygon']) & self.reach).sum() * self.res ** 2 < min_area:
                out.append(r['name'])
        return out

    def room_targets(self):
        """Per reachable room, a reachable point ENTER_DEPTH past one of its doorways (or its most
        open reachable point when no door point qualifies)."""
        targets = {}
        doors = self.world.get('doors', [])
        for r in self.rooms():
            inside = self.region_mask(r['polygon']) & self.reach
            if not inside.any():
                continue
            ys, xs = np.nonzero(inside)
            px, py = self.x0 + xs * self.res, self.y0 + ys * self.res
            best = None
            for d in doors:
                if r['name'] not in d['between']:
                    continue
                dist = np.hypot(px - d['center'][0], py - d['center'][1])
                k = int(np.argmin(np.abs(dist - ENTER_DEPTH)))
                if best is None or abs(dist[k] - ENTER_DEPTH) < best[0]:
                    best = (abs(dist[k] - ENTER_DEPTH), (float(px[k]), float(py[k])))
            if best is None:
                k = int(np.argmax(self.clearance[ys, xs]))
                best = (0.0, (float(px[k]), float(py[k])))
            targets[r['name']] = best[1]
        return targets

    def oracle_route(self):
        """(length m, [room names in visiting order]) of a short open walk from the start through
        every room target: nearest neighbour, then 2-opt, on shortest paths in the free space."""
        targets = self.room_targets()
        names = sorted(targets)
        pts = [tuple(self.world['robot']['start'][:2])] + [targets[n] for n in names]
        dist = self.path_lengths(pts)
        order = [0]
        left = set(range(1, len(pts)))
        while left:
            nxt = min(left, key=lambda k: dist[order[-1], k])
            order.append(nxt)
            left.remove(nxt)

        def length(o):
            return sum(dist[a, b] for a, b in zip(o, o[1:]))

        improved = True
        while improved:
            improved = False
            for i in range(1, len(order) - 1):
                for j in range(i + 1, len(order)):
                    cand = order[:i] + order[i:j + 1][::-1] + order[j + 1:]
                    if length(cand) < length(order) - 1e-9:
                        order, improved = cand, True
        return length(order), [names[k - 1] for k in order[1:]]

    def path_lengths(self, pts):
        """Shortest-path lengths (m) between the points through the free space (8-connected grid)."""
        step = max(1, int(round(ROUTE_RESOLUTION / self.res)))
        free = self.reach[::step, ::step]
        h, w = free.shape
        idx = -np.ones((h, w), np.int64)
        idx[free] = np.arange(int(free.sum()))
        rows, cols, vals = [], [], []
        res = self.res * step
        for dy, dx in ((0, 1), (1, 0), (1, 1), (1, -1)):
            ya, yb, xa, xb = max(0, -dy), h - max(0, dy), max(0, -dx), w - max(0, dx)
            a = idx[ya:yb, xa:xb]
            b = idx[ya + dy:yb + dy, xa + dx:xb + dx]
            ok = (a >= 0) & (b >= 0)
            rows.append(a[ok])
            cols.append(b[ok])
            vals.append(np.full(int(ok.sum()), res * math.hypot(dx, dy)))
        n = int(free.sum())
        graph = coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)).tocsr()
        sources = []
        for p in pts:
            cx, cy = self.cell(p)
            cx, cy = cx // step, cy // step
            ys, xs = np.nonzero(free)
            k = int(np.argmin((xs - cx) ** 2 + (ys - cy) ** 2))
            sources.append(int(idx[ys[k], xs[k]]))
        d = dijkstra(graph, directed=False, indices=sources)
        return d[:, sources]
