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

from exploration_result import GroundTruthGuard, read_result
from lockstep import Participant
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
        state = {'killed': False, 'failed': []}

        def kill(now):
            if kill_at > 0 and not state['killed'] and now.to_sec() >= kill_at:
                _, state['failed'] = rosnode.kill_nodes(['/exploration'])
                state['killed'] = True
                rospy.loginfo('killed the coordinator at %.2f s', now.to_sec())

        # In lockstep this script takes part (explore_restart.test names it): the kill comes at the
        # simulator's first step from kill_at on, the same step every run.
        guard = GroundTruthGuard()
        participant = Participant() if kill_at > 0 else None
        lockstep = participant is not None and participant.enabled
        if lockstep:
            participant.on_step(kill)
        while time.time() < deadline and not rospy.is_shutdown() and result is None:
            if not lockstep:
                kill(rospy.Time.now())
            result = read_result(path)
            time.sleep(1.0)
        # no ground truth on the stack's side: map -> odom is ekf_local_map's estimate alone
        self.assertEqual(guard.ground_truth_readers(), [], 'stack nodes read ground_truth')
        self.assertEqual(guard.map_to_odom, {'/ekf_local_map'}, 'map -> odom published by %s' % sorted(guard.map_to_odom))
        self.assertEqual(state['failed'], [], 'could not kill the coordinator')
        killed = state['killed']
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
