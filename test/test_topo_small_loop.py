#!/usr/bin/python3
"""rostest: the topological map of small_loop built by pomdp_topo against the world's ground truth."""
import json
import os
import time
import unittest

import rospy
import rostest


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
        self.assertGreaterEqual(result['correct_rate'], 0.9)
        self.assertLessEqual(result['unconfident_rate'], 0.1)


if __name__ == '__main__':
    rospy.init_node('test_topo_small_loop')
    rostest.rosrun('hybrid_slam', 'topo_small_loop', TopoSmallLoop)
