#!/usr/bin/python3
"""rostest: the topological map of small_loop built by pomdp_topo against the world's ground truth."""
import csv
import json
import os
import time
import unittest

import rospy
import rostest


def wrong_stretches(csv_path, limit=6):
    """The stretches of localized updates that were wrong, from evaluate_topo's trace, for the
    failure message: a rate alone does not say where the belief went wrong."""
    try:
        with open(csv_path) as f:
            rows = list(csv.DictReader(f))
    except (IOError, OSError) as e:
        return 'no trace: %s' % e
    stretches, current = [], None
    for r in rows:
        if r['mode'] == 'localized' and r['right'] == '0':
            if current is None:
                current = [r, r, 0]
                stretches.append(current)
            current[1] = r
            current[2] += 1
        else:
            current = None
    def where(r):
        return 'state %s%s at (%s, %s) heading %s, truth (%s, %s) heading %s' % (
            'node ' if r['at_node'] == '1' else 'edge ', r['state_id'], r['state_x'], r['state_y'],
            r['state_heading'], r['true_x'], r['true_y'], r['true_heading'])
    return '; '.join('%d wrong updates from t=%s (%s) to t=%s (%s)' % (n, a['t'], where(a), b['t'], where(b))
                     for a, b, n in stretches[:limit])


class TopoSmallLoop(unittest.TestCase):
    def test_map_and_localization(self):
        path = rospy.get_param('~result')
        if os.path.exists(path):  # a result of an earlier run must not count
            os.remove(path)
        deadline = time.time() + 360.0
        result = None
        while time.time() < deadline and not rospy.is_shutdown():
            if os.path.exists(path):
                with open(path) as f:
                    try:
                        result = json.load(f)
                    except ValueError:
                        result = None
                if result and result.get('tour_done'):
                    break
            time.sleep(1.0)
        self.assertIsNotNone(result, 'no evaluation written')
        self.assertTrue(result['tour_done'], 'the tour did not end')
        print(json.dumps(result))
        self.assertEqual(result['found'], result['true_nodes'], 'missed: %s' % result['missed'])
        self.assertEqual(result['spurious_nodes'], [])
        self.assertEqual(len(result['loops_closed']), 1)
        self.assertGreater(result['localized_updates'], 40)
        self.assertGreaterEqual(result['correct_rate'], 0.9, '%s; events: %s' % (
            wrong_stretches(path + '.csv'), result['loops_closed'] + result['loops_rejected']))
        self.assertLessEqual(result['unconfident_rate'], 0.1)


if __name__ == '__main__':
    rospy.init_node('test_topo_small_loop')
    rostest.rosrun('hybrid_slam', 'topo_small_loop', TopoSmallLoop)
