#!/usr/bin/python3
"""rostest: scripts/world_from_map (a map_server map -> a world file) and scripts/map_from_world on
maps the test draws. No simulator."""
import importlib.machinery
import math
import os
import subprocess
import sys
import tempfile
import unittest

import cv2
import numpy as np
import rostest
import yaml

SCRIPTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'scripts')
WORLDS = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'worlds')
sys.path.insert(0, SCRIPTS)
from building_raster import WorldRaster, robot_radius  # noqa: E402
from occupancy_map import FREE, OCCUPIED, UNKNOWN, read_map  # noqa: E402

wfm = importlib.machinery.SourceFileLoader('world_from_map', os.path.join(SCRIPTS, 'world_from_map')).load_module()
RES = 0.05


def two_rooms():
    """A 10 x 6 m floor of two rooms (6 m and 4 m wide) joined by a 1 m door, walls 0.1 m thick,
    unknown around it, as a map_server image (row 0 at the top): 0 occupied, 254 free, 205 unknown."""
    h, w = int(8 / RES), int(12 / RES)  # 1 m of unknown around the building
    img = np.full((h, w), 205, np.uint8)

    def box(x0, y0, x1, y1, v):  # metres in the map frame, origin at the image's bottom-left corner
        img[h - int(round(y1 / RES)):h - int(round(y0 / RES)), int(round(x0 / RES)):int(round(x1 / RES))] = v
    box(1.0, 1.0, 11.0, 7.0, 0)
    box(1.1, 1.1, 10.9, 6.9, 254)
    box(7.0, 1.1, 7.1, 6.9, 0)   # the wall between the rooms, x 7.0-7.1
    box(7.0, 3.0, 7.1, 4.0, 254)  # its door, y 3-4
    return img


class Conversion(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix='world_from_map_')

    def write_map(self, img, name='floor', image_name=None, **meta):
        image_name = image_name or name + '.pgm'
        if img is not None:
            cv2.imwrite(os.path.join(self.dir, image_name), img)
        fields = dict(image=image_name, resolution=RES, origin=[0.0, 0.0, 0.0], negate=0,
                      occupied_thresh=0.65, free_thresh=0.196)
        fields.update(meta)
        fields = {k: v for k, v in fields.items() if v is not None}
        path = os.path.join(self.dir, name + '.yaml')
        with open(path, 'w') as f:
            yaml.safe_dump(fields, f)
        return path

    def run_tool(self, map_path, *extra):
        out = os.path.join(self.dir, 'world.yaml')
        if os.path.exists(out):
            os.remove(out)
        p = subprocess.run([sys.executable, os.path.join(SCRIPTS, 'world_from_map'), map_path, out] + list(extra),
                           capture_output=True, text=True)
        world = None
        if os.path.exists(out):
            with open(out) as f:
                world = yaml.safe_load(f)
        return p, world

    def test_boxes_cover_exactly_the_obstacle_cells(self):
        rng = np.random.default_rng(3)
        mask = rng.random((40, 50)) < 0.3
        mask[5:20, 10:30] = True
        painted = np.zeros(mask.shape, int)
        for c0, c1, r0, r1 in wfm.merge_into_boxes(mask):
            painted[r0:r1, c0:c1] += 1
        np.testing.assert_array_equal(painted, mask.astype(int))

    def test_two_rooms_become_walls_a_start_in_the_open_and_both_rooms_reachable(self):
        p, world = self.run_tool(self.write_map(two_rooms()))
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(world['name'], 'floor')
        # the boxes cover every occupied cell and no free cell
        grid = read_map(os.path.join(self.dir, 'floor.yaml'))
        painted = np.zeros(grid.cells.shape, bool)
        for b in world['boxes']:
            self.assertEqual(b['yaw'], 0)
            c0, r0 = grid.to_cell(b['center'][0] - b['size'][0] / 2 + RES / 2, b['center'][1] - b['size'][1] / 2 + RES / 2)
            c1, r1 = grid.to_cell(b['center'][0] + b['size'][0] / 2 - RES / 2, b['center'][1] + b['size'][1] / 2 - RES / 2)
            painted[r0:r1 + 1, c0:c1 + 1] = True
        self.assertTrue(painted[grid.cells == OCCUPIED].all())
        self.assertFalse(painted[grid.cells == FREE].any())
        # unknown cells next to the building are walls, those deeper than 0.2 m are left out
        self.assertTrue(painted[int(0.9 / RES), int(5 / RES)])
        self.assertFalse(painted[int(0.5 / RES), int(5 / RES)])
        # the start: the most open cell, the big room's centre (3.9 m from its side walls, 2.9 m from the rest)
        x, y, yaw = world['robot']['start']
        self.assertAlmostEqual(y, 4.0, delta=0.1)
        self.assertTrue(1.1 + 2.8 <= x <= 7.0 - 2.8, x)
        self.assertEqual(yaw, 0)
        raster = WorldRaster(world, robot_radius())
        for point in ((3.0, 3.0), (9.0, 5.0)):
            col, row = raster.cell(point)
            self.assertTrue(raster.reach[row, col], 'no way to %s' % (point,))

    def test_negate_origin_and_a_given_start_carry_over(self):
        img = two_rooms()
        negated = 255 - img
        p, world = self.run_tool(self.write_map(negated, negate=1, origin=[-5.0, 2.0, 0.0]), '--start', '4', '6', '90')
        self.assertEqual(p.returncode, 0, p.stderr)
        p0, plain = self.run_tool(self.write_map(img, name='plain'))
        shifted = sorted((round(b['center'][0] + 5.0, 3), round(b['center'][1] - 2.0, 3)) for b in world['boxes'])
        self.assertEqual(shifted, sorted((b['center'][0], b['center'][1]) for b in plain['boxes']))
        self.assertEqual(world['robot']['start'][:2], [4, 6])
        self.assertAlmostEqual(world['robot']['start'][2], math.pi / 2, places=3)

    def test_a_rotated_origin_rotates_the_boxes(self):
        p, world = self.run_tool(self.write_map(two_rooms(), origin=[0.0, 0.0, math.pi / 2]))
        self.assertEqual(p.returncode, 0, p.stderr)
        for b in world['boxes']:
            self.assertAlmostEqual(b['yaw'], math.pi / 2, places=3)
        xs = [b['center'][0] for b in world['boxes']]
        self.assertLessEqual(max(xs), 0.0)  # the map's +y is the world's -x

    def test_bad_maps_are_refused_with_what_is_wrong_and_nothing_written(self):
        img = two_rooms()
        cases = [
            (self.write_map(None, name='missing', image_name='nowhere.pgm'), 'does not exist'),
            (self.write_map(img, name='negative', resolution=-0.05), 'resolution'),
            (self.write_map(img, name='zero', resolution=0), 'resolution'),
            (self.write_map(img, name='text', resolution='fine'), 'resolution'),
            (self.write_map(img, name='nores', resolution=None), '"resolution" is missing'),
            (self.write_map(img, name='origin', origin=[1, 2]), 'origin'),
            (self.write_map(np.full(img.shape, 254, np.uint8), name='empty'), 'no occupied cell'),
            (self.write_map(np.zeros(img.shape, np.uint8), name='full'), 'no free cell'),
        ]
        with open(os.path.join(self.dir, 'garbage.pgm'), 'w') as f:
            f.write('not an image')
        cases.append((self.write_map(None, name='garbage', image_name='garbage.pgm'), 'cannot be read'))
        narrow = np.zeros(img.shape, np.uint8)
        narrow[100:104, 20:200] = 254  # a free corridor 0.2 m wide: the robot does not fit
        cases.append((self.write_map(narrow, name='narrow'), 'fits in'))
        for path, why in cases:
            p, world = self.run_tool(path)
            self.assertEqual(p.returncode, 2, '%s: %s' % (path, p.stderr))
            self.assertIn(why, p.stderr, path)
            self.assertIn(os.path.basename(path), p.stderr) if why not in ('fits in',) else None
            self.assertIsNone(world, path)

    def test_a_start_in_a_wall_or_too_close_to_one_is_refused(self):
        path = self.write_map(two_rooms())
        for args, why in ((('7.05', '2', '0'), 'occupied'), (('1.2', '4', '0'), 'radius'), (('40', '4', '0'), 'outside')):
            p, world = self.run_tool(path, '--start', *args)
            self.assertEqual(p.returncode, 2, p.stderr)
            self.assertIn(why, p.stderr)
            self.assertIsNone(world)

    def test_a_shipped_world_made_into_a_map_and_back_leaves_the_robot_the_same_floor(self):
        original = os.path.join(WORLDS, 'small_loop.yaml')
        map_path = os.path.join(self.dir, 'small_loop_map.yaml')
        subprocess.run([sys.executable, os.path.join(SCRIPTS, 'map_from_world'), original, map_path], check=True)
        with open(original) as f:
            truth = yaml.safe_load(f)
        s = truth['robot']['start']
        p, world = self.run_tool(map_path, '--start', str(s[0]), str(s[1]), str(math.degrees(s[2])),
                                 '--regions-from', original)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(world['regions'], truth['regions'])
        self.assertEqual(world['doors'], truth['doors'])
        a, b = WorldRaster(truth, robot_radius()), WorldRaster(world, robot_radius())
        self.assertEqual(a.unreachable_rooms(), [])
        self.assertEqual(b.unreachable_rooms(), [])
        # the floor the robot's centre reaches: the same to within a cell along every wall
        # (a wall's cells in the map are whole cells, so its boxes may be up to a cell thicker)
        def reached(r, erode):  # the reached cells, indexed in the world frame, eroded by `erode` cells
            m = cv2.erode(r.reach.astype(np.uint8), np.ones((2 * erode + 1, 2 * erode + 1), np.uint8)) if erode else r.reach
            rows, cols = np.nonzero(m)
            return set(zip((cols + int(round(r.x0 / RES))).tolist(), (rows + int(round(r.y0 / RES))).tolist()))
        for x, y in ((a, b), (b, a)):
            lost = reached(x, 1) - reached(y, 0)
            self.assertEqual(len(lost), 0, '%d cells more than a cell inside the floor of one are not floor of the other' % len(lost))


if __name__ == '__main__':
    rostest.rosrun('hybrid_slam', 'world_from_map', Conversion)
