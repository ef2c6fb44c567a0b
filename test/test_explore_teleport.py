#!/usr/bin/python3
"""rostest: the robot is teleported mid-hallway during an exploration of small_loop (kidnapping:
odometry is not told).

After room_east is mapped, while the robot drives east along hall_south between room_east's door
and the hallway's end, it is moved 8.5 m back west along the same hallway (a stretch already in
the map). laser_features' odometry consistency must drop, pomdp_topo's belief must become
unconfident, the coordinator must not enter a room (no METRIC mode, no new place) while
unconfident, the belief must become confident again, and the exploration must still end complete
with every room mapped once and no spurious door node."""
import json
import math
import os
import time
import unittest

import rospy
import rostest
from exploration_result import read_result
from hybrid_slam_msgs.msg import ExplorationStatus, TopologicalState
from hybrid_slam_msgs.srv import Teleport
from geometry_msgs.msg import Pose2D
from nav_msgs.msg import Odometry

METRIC = 1


class ExploreTeleport(unittest.TestCase):
    def setUp(self):
        self.truth = None
        self.status = None
        self.confident = None
        self.teleported_at = None
        self.unconfident_at = None
        self.reconfident_at = None
        self.places_at_teleport = None
        self.entered_unconfident = []  # (sim time, what) room entries while not yet relocalized
        self.teleport = None  # the simulator's teleport service, once it is up
        self.teleport_response = None
        rospy.Subscriber('ground_truth', Odometry, self.on_truth, queue_size=10)
        rospy.Subscriber('exploration_status', ExplorationStatus, self.on_status, queue_size=10)
        rospy.Subscriber('topological_state', TopologicalState, self.on_confident, queue_size=10)

    def on_truth(self, msg):
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        self.truth = (p.x, p.y, math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z)))
        self.maybe_teleport()

    def maybe_teleport(self):
        # On every ground-truth message, not on a wall-clock poll: at 15-25x real time a 50 ms poll
        # is half a metre of travel, and the window below is one metre long.
        s, t = self.status, self.truth
        if (self.teleport is None or self.teleported_at is not None or s is None or t is None or s.places < 1 or
                self.confident is not True or s.mode == METRIC or not 13.0 <= t[0] <= 14.0 or t[1] >= 2.0 or
                abs(t[2]) >= 0.3):
            return
        self.places_at_teleport = s.places
        self.teleported_at = rospy.Time.now().to_sec()  # before the call: its effects may come first
        self.teleport_response = self.teleport(Pose2D(5.0, 1.0, t[2]))
        rospy.loginfo('teleported from (%.2f, %.2f) to (5.0, 1.0) at %.1f s', t[0], t[1], self.teleported_at)

    def on_confident(self, msg):
        self.confident = msg.confident
        now = rospy.Time.now().to_sec()
        if self.teleported_at is None:
            return
        if not msg.confident and self.unconfident_at is None:
            self.unconfident_at = now
        if msg.confident and self.unconfident_at is not None and self.reconfident_at is None:
            self.reconfident_at = now

    def on_status(self, msg):
        self.status = msg
        if self.teleported_at is not None and self.reconfident_at is None:
            if msg.mode == METRIC or msg.places > self.places_at_teleport:
                self.entered_unconfident.append((rospy.Time.now().to_sec(), msg.state))

    def test_teleport_mid_hallway(self):
        path = rospy.get_param('~result')
        if os.path.exists(path):
            os.remove(path)
        rospy.wait_for_service('bullet_sim/teleport', 60.0)
        self.teleport = rospy.ServiceProxy('bullet_sim/teleport', Teleport)
        deadline = time.time() + 360.0
        result = None
        while time.time() < deadline and not rospy.is_shutdown() and result is None:
            result = read_result(path)
            time.sleep(0.05)
        self.assertIsNotNone(self.teleported_at, 'the robot never drove east past room_east\'s door after mapping it')
        self.assertIsNotNone(self.teleport_response, 'the teleport service did not answer')
        self.assertTrue(self.teleport_response.success, self.teleport_response.message)
        self.assertIsNotNone(self.unconfident_at, 'the belief never became unconfident after the teleport')
        self.assertLess(self.unconfident_at - self.teleported_at, 2.0, 'unconfident too late')
        self.assertEqual(self.entered_unconfident, [], 'entered a room before relocalizing')
        self.assertIsNotNone(self.reconfident_at, 'the belief never became confident again')
        rospy.loginfo('unconfident %.1f s after the teleport, confident again after %.1f s',
                      self.unconfident_at - self.teleported_at, self.reconfident_at - self.teleported_at)
        self.assertIsNotNone(result, 'no evaluation written: the exploration did not end')
        print(json.dumps(result))
        print(json.dumps({'unconfident_after_s': round(self.unconfident_at - self.teleported_at, 2),
                          'relocalized_after_s': round(self.reconfident_at - self.teleported_at, 2)}))
        self.assertTrue(result['complete'], 'the exploration ended incomplete')
        self.assertEqual(result['rooms_missed'], [])
        self.assertEqual(result['rooms_mapped_twice'], {})
        self.assertEqual(result['doors_found'], result['hallway_doors'], 'missed: %s' % result['doors_missed'])
        self.assertEqual(result['spurious_door_nodes'], [])


if __name__ == '__main__':
    rospy.init_node('test_explore_teleport')
    rostest.rosrun('hybrid_slam', 'explore_teleport', ExploreTeleport)
