#!/usr/bin/python3
"""rostest: the evaluation's rules on hand-made input: the door rule on nodes, lockstep stalls in
a log, the benchmark's figures over draws of noise (see the .test)."""
import json
import math
import os
import subprocess
import sys
import tempfile
import types
import unittest

import rostest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'scripts'))
from evaluate_exploration import door_opening  # noqa: E402
from lockstep_log import stalls  # noqa: E402

NORTH, SOUTH = 0.5 * math.pi, -0.5 * math.pi


def node(node_id, x, y, *bearings):
    return types.SimpleNamespace(id=node_id, pose=types.SimpleNamespace(x=x, y=y),
                                 openings=[types.SimpleNamespace(bearing=b) for b in bearings])


class DoorRule(unittest.TestCase):
    def test_a_node_a_door_width_along_from_the_door_finds_it(self):
        # large_floor run 9: doors facing each other 0.8 m apart along a 2.2 m hallway are two
        # openings of one node, 1.05 m along and 1.2 m across from the second door (1.59 m away).
        n = node(41, 1.05, -1.2, SOUTH, NORTH)
        self.assertEqual(door_opening(0.0, 0.0, NORTH, [n]), (41, 1))

    def test_a_node_too_far_along_or_across_does_not(self):
        self.assertIsNone(door_opening(0.0, 0.0, NORTH, [node(1, 1.6, -1.1, NORTH)]))
        self.assertIsNone(door_opening(0.0, 0.0, NORTH, [node(1, 0.0, -2.1, NORTH)]))
        # The door's wall runs north-south here: along is y, across is x.
        self.assertEqual(door_opening(0.0, 0.0, 0.0, [node(1, -1.8, 1.2, 0.0)]), (1, 0))
        self.assertIsNone(door_opening(0.0, 0.0, 0.0, [node(1, -1.2, 1.8, 0.0)]))

    def test_an_opening_away_from_the_room_does_not(self):
        self.assertIsNone(door_opening(0.0, 0.0, NORTH, [node(1, 0.0, -1.1, SOUTH, 0.0)]))

    def test_each_opening_counts_for_one_door_and_the_nearest_node_wins(self):
        near, far = node(1, 0.2, -1.1, NORTH), node(2, 1.0, -1.1, NORTH)
        first = door_opening(0.0, 0.0, NORTH, [far, near])
        self.assertEqual(first, (1, 0))
        self.assertEqual(door_opening(0.0, 0.0, NORTH, [far, near], {first}), (2, 0))
        self.assertIsNone(door_opening(0.0, 0.0, NORTH, [near], {first}))



class LockstepStalls(unittest.TestCase):
    def test_the_simulators_and_a_participants_stalls_are_found_and_nothing_else(self):
        log = [
            '[ERROR] [1796386723.576311086, 0.150000000]: bullet_sim: lockstep: the step at 0.150 s waited 10 s '
            'of wall time for the acknowledgement of /exploration; going on without it',
            '[ERROR] [1796390860.730158423, 5.600000000]: /exploration: lockstep step at 0.150 s waited 10 s of '
            'wall time for /topological_map: 4 of 5; going on without it',
            '[ INFO] [1796401154.068325681, 0.000000014]: bullet_sim: lockstep with laser_features, pomdp_topo '
            '(1.5 s to connect)',
            '[ INFO] [1796401178.481818586, 98.300000000]: bullet_sim: sim time 98.3 s, real-time factor 4.0; '
            'lockstep: 984 steps, 16 % of the wall time waiting for the nodes (4.08 ms a step)',
        ]
        self.assertEqual(stalls(log), [('bullet_sim', 0.15, 'the acknowledgement of /exploration'),
                                       ('/exploration', 0.15, '/topological_map: 4 of 5')])
        self.assertEqual(stalls(log[2:]), [])


class BenchmarkDraws(unittest.TestCase):
    """scripts/benchmark_draws on two hand-made draws of two buildings."""

    SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'scripts', 'benchmark_draws')
    WORLD = ('regions:\n'
             '  - {name: hall, kind: hallway, polygon: [[0, 0], [1, 0], [1, 1]]}\n'
             '  - {name: a, kind: room, polygon: [[0, 0], [1, 0], [1, 1]]}\n'
             '  - {name: b, kind: room, polygon: [[0, 0], [1, 0], [1, 1]]}\n'
             'doors:\n  - {between: [a, hall]}\n  - {between: [b, a]}\n')

    def draw(self, root, label, runs):
        d = os.path.join(root, label)
        os.makedirs(os.path.join(d, 'worlds'))
        buildings = {}
        for name, (mapped, complete, once, start_given_up) in runs.items():
            with open(os.path.join(d, 'worlds', name + '.yaml'), 'w') as f:
                f.write(self.WORLD)
            with open(os.path.join(d, name + '.log'), 'w') as f:
                f.write('exploration: TOPOLOGICAL - missed an opening of node %d: given up\n' % (0 if start_given_up else 3))
            buildings[name] = {
                'explore': {'evaluation': {'rooms_missed': [] if mapped == 2 else ['b']}},
                'score': {'rooms_mapped': mapped, 'rooms': 2, 'rooms_twice': 0, 'doors_found': 1, 'doors': 1,
                          'spurious_door_nodes': 0, 'complete': complete, 'every_room_once': once,
                          'travel_m': 30.0, 'oracle_m': 10.0}}
        with open(os.path.join(d, 'benchmark.json'), 'w') as f:
            json.dump({'buildings': buildings}, f)
        return d

    def test_the_draws_distribution_and_what_the_draw_alone_does(self):
        with tempfile.TemporaryDirectory() as root:
            d0 = self.draw(root, 'draw0', {'building_medium_1': (2, True, True, False),
                                            'building_medium_2': (1, False, False, True)})
            d1 = self.draw(root, 'draw1', {'building_medium_1': (2, True, True, False),
                                            'building_medium_2': (2, True, True, False)})
            out = subprocess.run([sys.executable, self.SCRIPT, d0, d1], capture_output=True, text=True, check=True).stdout
        self.assertIn('| %s | 3 of 4 | 0.75 / 0.50 (building 2: 1 of 2) / 1.00 | 0 | 1 of 2 | 2 of 2 | 0 | 1 | 1 of 2 |' % d0, out)
        self.assertIn("start node's opening given up on 1", out)
        self.assertIn('all 4 runs: rooms 7 of 8; share per run median 1.00, tenth percentile 0.50, worst 0.50 (building 2, %s)' % d0, out)
        self.assertIn('complete 3, every room once 3 (buildings: some draw 1, 2; every draw 1)', out)
        self.assertIn('"complete" differs on 1, every room once on 1, rooms mapped by more than 2 on 0', out)

    def test_a_folder_without_results_is_refused(self):
        with tempfile.TemporaryDirectory() as root:
            r = subprocess.run([sys.executable, self.SCRIPT, root], capture_output=True, text=True)
        self.assertEqual(r.returncode, 2)
        self.assertIn('has no benchmark.json', r.stderr)


class BenchmarkMisses(unittest.TestCase):
    """scripts/benchmark_misses on a hand-made floor: a hallway along y = 0 the robot drove from x = 0
    to x = 10, a room whose door it passed (x 5), one whose door lies beyond its path (x 20), a room
    behind the first and one behind the second."""

    SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'scripts', 'benchmark_misses')
    WORLD = ('regions:\n'
             '  - {name: hall_3, kind: hallway, polygon: [[0, 0], [1, 0], [1, 1]]}\n' +
             ''.join('  - {name: %s, kind: room, polygon: [[0, 0], [1, 0], [1, 1]]}\n' % r for r in 'abcd') +
             'doors:\n'
             '  - {between: [a, hall_3], center: [5, 1.5], width: 0.9}\n'
             '  - {between: [b, hall_3], center: [20, 1.0], width: 0.9}\n'
             '  - {between: [c, a], center: [5, 6], width: 0.9}\n'
             '  - {between: [d, b], center: [20, 6], width: 0.9}\n')

    def run_script(self, root, *draws):
        """The script on one folder per draw, each with the rooms mapped in it."""
        folders = [self.folder(os.path.join(root, 'draw%d' % k), mapped) for k, mapped in enumerate(draws)]
        return subprocess.run([sys.executable, self.SCRIPT] + folders + ['--list'], capture_output=True, text=True,
                              check=True).stdout

    def folder(self, d, mapped):
        os.makedirs(os.path.join(d, 'worlds'))
        with open(os.path.join(d, 'worlds', 'building_medium_1.yaml'), 'w') as f:
            f.write(self.WORLD)
        evaluation = os.path.join(d, 'building_medium_1.evaluation.json')
        with open(evaluation, 'w') as f:
            json.dump({'rooms_missed': [r for r in 'abcd' if r not in mapped],
                       'place_rooms': {str(k): r for k, r in enumerate(mapped)}}, f)
        with open(evaluation + '.trace.csv', 'w') as f:
            f.write('t,true_x,true_y,true_yaw,region,mode,place,node,state\n'
                    '0.0,0.0,0.0,0.0,hall_3,0,-1,0,"following a new hallway"\n'
                    '20.0,10.0,0.0,0.0,hall_3,0,-1,0,"following a new hallway"\n')
        with open(os.path.join(d, 'benchmark.json'), 'w') as f:
            json.dump({'buildings': {'building_medium_1': {'score': {}}}}, f)
        return d

    def test_each_missed_room_has_its_cause(self):
        with tempfile.TemporaryDirectory() as root:
            out = self.run_script(root, [])
        self.assertIn('A door counts as passed within 2.0 m', out)
        self.assertIn('a: door passed: hall (hall_3, 1.5 m)', out)
        self.assertIn('b: never near (10.0 m from its door)', out)
        self.assertIn('c: behind a room, host missed (a)', out)
        self.assertIn('all: 4 missed | behind a room, host missed 2, door passed: hall 1, never near 1', out)

    def test_a_room_behind_a_mapped_room_is_its_inner_door_not_taken(self):
        with tempfile.TemporaryDirectory() as root:
            out = self.run_script(root, ['a', 'b'])
        self.assertIn('c: behind a room, host mapped (a)', out)
        self.assertIn('all: 2 missed | behind a room, host mapped 2', out)

    def test_a_run_without_its_trace_is_refused(self):
        with tempfile.TemporaryDirectory() as root:
            d = self.folder(os.path.join(root, 'draw0'), [])
            os.remove(os.path.join(d, 'building_medium_1.evaluation.json.trace.csv'))
            r = subprocess.run([sys.executable, self.SCRIPT, d], capture_output=True, text=True)
        self.assertEqual(r.returncode, 1)
        self.assertIn('building_medium_1: no trace', r.stderr)

    def test_the_rooms_missed_in_every_draw(self):
        with tempfile.TemporaryDirectory() as root:
            out = self.run_script(root, ['a', 'b'], ['a', 'b', 'd'])
        self.assertIn('all: 3 missed | behind a room, host mapped 3', out)
        self.assertIn('missed in every folder with its building: 1 rooms | behind a room, host mapped 1', out)


def suite():
    load = unittest.defaultTestLoader.loadTestsFromTestCase
    return unittest.TestSuite([load(DoorRule), load(LockstepStalls), load(BenchmarkDraws), load(BenchmarkMisses)])


if __name__ == '__main__':
    rostest.rosrun('hybrid_slam', 'evaluation_rules', '__main__.suite')
