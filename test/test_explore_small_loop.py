#!/usr/bin/python3
"""rostest: a complete exploration of small_loop (explore.launch) against the world's ground truth.

With ~kill_at > 0 the coordinator is killed once at that sim time (in the first hallway) and
restarted by roslaunch (respawn): it must pick up from the topological map and still complete.
With ~unreachable (comma-separated room names) the simulator has closed doors: the exploration must
still end complete, with every other room mapped and exactly those rooms reported unreachable."""
import json
import os
import time
import unittest

from exploration_result import read_result
import rosnode
import rospy
import rostest


class ExploreSmallLoop(unittest.TestCase):
    def test_complete_exploration(self):
        path = rospy.get_param('~result')
        if os.path.exists(path):  # a result of an earlier run must not count
            os.remove(path)
        deadline = time.time() + 360.0
        result = None
        kill_at = rospy.get_param('~kill_at', 0.0)
        killed = False
        while time.time() < deadline and not rospy.is_shutdown() and result is None:
            if kill_at > 0 and not killed and rospy.Time.now().to_sec() >= kill_at:
                _, failed = rosnode.kill_nodes(['/exploration'])
                self.assertEqual(failed, [], 'could not kill the coordinator')
                killed = True
                rospy.loginfo('killed the coordinator at %.1f s', rospy.Time.now().to_sec())
            result = read_result(path)
            time.sleep(1.0)
        self.assertIsNotNone(result, 'no evaluation written: the exploration did not end')
        if kill_at > 0:
            self.assertTrue(killed, 'the coordinator was never killed')
        print(json.dumps(result))
        self.assertTrue(result['complete'], 'the exploration ended incomplete')
        self.assertEqual(result['rooms_missed'], [])
        unreachable = sorted(r for r in rospy.get_param('~unreachable', '').split(',') if r)
        self.assertEqual(result['rooms_unreachable'], unreachable)
        self.assertEqual(result['rooms_mapped'], result['rooms'])
        self.assertEqual(result['rooms_mapped_twice'], {})
        self.assertEqual(result['places_in_no_room'], [])
        self.assertEqual(result['doors_found'], result['hallway_doors'], 'missed: %s' % result['doors_missed'])
        self.assertEqual(result['spurious_door_nodes'], [])
        self.assertGreater(result['topological_map_bytes'] or 0, 0, 'the topological map was not saved')
        self.assertGreater(result['places_bytes'] or 0, 0, 'the places were not saved')


if __name__ == '__main__':
    rospy.init_node('test_explore_small_loop')
    rostest.rosrun('hybrid_slam', 'explore_small_loop', ExploreSmallLoop)
