#!/usr/bin/python3
"""rostest: the building generator (scripts/generate_building) and the ground-truth rules the
benchmark scores with (see the .test). No simulator."""
import math
import os
import subprocess
import sys
import tempfile
import unittest

import rostest
import yaml

SCRIPTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'scripts')
sys.path.insert(0, SCRIPTS)
from building_layout import BuildingOptions, draw_building  # noqa: E402
from building_raster import WorldRaster, robot_radius  # noqa: E402
from evaluate_exploration import into_polygon  # noqa: E402
from building_world import to_world, unblock, world_dict  # noqa: E402

SEEDS = range(1, 21)
# What the benchmark's variety promises (scripts/generate_building's doc): each in at least 2 of 20.
FEATURES = ('loop', 'suite', 'multi_door_room', 'double_door', 'close_doors', 'end_wall_door', 'lobby', 'wing',
            'curved_wall', 'width_change', 'pillar', 'furniture', 'rotated')


def segment_distance(p, a, b):
    dx, dy = b[0] - a[0], b[1] - a[1]
    t = max(0.0, min(1.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy)))
    return math.hypot(a[0] + t * dx - p[0], a[1] + t * dy - p[1])


class Generator(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.buildings = {s: draw_building(s, 'medium') for s in SEEDS}

    def test_a_seed_gives_the_same_world_file(self):
        a, b = to_world(draw_building(7, 'medium')).emit(), to_world(draw_building(7, 'medium')).emit()
        self.assertEqual(a, b)
        self.assertNotEqual(a, to_world(draw_building(8, 'medium')).emit())

    def test_twenty_buildings_hold_every_feature_at_least_twice(self):
        for f in FEATURES:
            n = sum(f in b.features for b in self.buildings.values())
            self.assertGreaterEqual(n, 2, '%s in %d of 20 buildings' % (f, n))

    def test_room_door_widths_lie_in_the_stated_range(self):
        lo, hi = BuildingOptions.single_door[0], BuildingOptions.double_door[1]
        for s, b in self.buildings.items():
            kinds = {r.name: r.kind for r in b.regions}
            for a, c, centre, width in b.doors:
                if kinds[a] == 'room' or kinds[c] == 'room':
                    self.assertTrue(lo - 1e-9 <= width <= hi + 1e-9, 'seed %d: door %s/%s %.2f m' % (s, a, c, width))

    def test_no_wall_crosses_a_doorway(self):
        for s, b in self.buildings.items():
            for a, c, centre, width in b.doors:
                near = min(segment_distance(centre, p, q) for p, q in b.walls)
                self.assertGreater(near, min(width / 2.0, 0.35) - 0.01, 'seed %d: a wall through door %s/%s' % (s, a, c))

    def test_regions_do_not_overlap(self):
        for s in (1, 5, 9, 13, 17):
            raster = WorldRaster(world_dict(self.buildings[s]), robot_radius(), resolution=0.1)
            masks = [raster.region_mask(r.poly) for r in self.buildings[s].regions]
            total = sum(m.astype(int) for m in masks)
            # shared edges are drawn into both polygons' masks: two cells of overlap along an edge at most
            inner = (total > 1).sum() * 0.01
            edges = sum(sum(math.dist(r.poly[i], r.poly[(i + 1) % len(r.poly)]) for i in range(len(r.poly)))
                        for r in self.buildings[s].regions)
            self.assertLess(inner, edges * 0.2 + 1.0, 'seed %d: regions overlap by %.1f m2' % (s, inner))

    def test_every_room_is_reachable_by_the_robot_and_the_start_is_free(self):
        for s in SEEDS:
            b = draw_building(s, 'medium')
            self.assertEqual(unblock(b, robot_radius()), [], 'seed %d' % s)

    def test_the_oracle_enters_every_room_and_is_shorter_than_visiting_them_in_turn(self):
        b = draw_building(3, 'medium')
        unblock(b, robot_radius())
        raster = WorldRaster(world_dict(b), robot_radius())
        length, order = raster.oracle_route()
        self.assertEqual(sorted(order), sorted(r.name for r in b.regions if r.kind == 'room'))
        targets = raster.room_targets()
        pts = [tuple(b.start[:2])] + [targets[n] for n in sorted(targets)]
        straight = sum(math.dist(p, q) for p, q in zip(pts, pts[1:]))
        self.assertGreater(length, 0.0)
        self.assertLess(length, 3.0 * straight)

    def test_the_written_file_names_its_seed_and_holds_only_the_formats_keys(self):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, 'b.yaml')
            subprocess.run([sys.executable, os.path.join(SCRIPTS, 'generate_building'), '--seed', '4', '--out', out],
                           check=True, stdout=subprocess.DEVNULL)
            with open(out) as f:
                w = yaml.safe_load(f)
            self.assertEqual(w['name'], 'building_medium_4')
            self.assertEqual(set(w), {'name', 'wall_thickness', 'wall_height', 'colors', 'walls', 'boxes', 'cylinders',
                                      'robot', 'regions', 'doors'})
            self.assertEqual(set(w['colors']), {'floor', 'ceiling', 'wall_ends'})

    def test_the_heading_into_a_room_behind_a_wall_at_37_degrees(self):
        t = math.radians(37.0)
        u, n = (math.cos(t), math.sin(t)), (-math.sin(t), math.cos(t))
        room = [(0.0, 0.0), (4 * u[0], 4 * u[1]), (4 * u[0] + 3 * n[0], 4 * u[1] + 3 * n[1]), (3 * n[0], 3 * n[1])]
        door = (2 * u[0], 2 * u[1])
        self.assertAlmostEqual(into_polygon(room, door), t + math.pi / 2.0, places=6)


if __name__ == '__main__':
    rostest.rosrun('hybrid_slam', 'building_generator', Generator)
