#!/usr/bin/python3
"""rostest: the exploration's ~pause service (see the .test)."""
import math
import sys
import os
import time
import unittest

from exploration_result import read_result
import rospy
import rostest
from hybrid_slam_msgs.msg import ExplorationStatus
from nav_msgs.msg import Odometry
from std_srvs.srv import SetBool
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'scripts'))
from world_geometry import yaw_of  # noqa: E402

PAUSE_AFTER = 5.0  # s of sim time: the robot has left the start and drives down the first hallway
MOVING = 0.1  # m/s: the true speed at which the robot counts as driving when the pause is asked
STILL = 10.0  # s of sim time it must stand still once stopped



class ExplorePause(unittest.TestCase):
    def setUp(self):
        self.truth = None
        self.speed = 0.0
        self.status = None
        rospy.Subscriber('ground_truth', Odometry, self.on_truth, queue_size=10)
        rospy.Subscriber('exploration_status', ExplorationStatus, self.on_status, queue_size=10)

    def on_truth(self, msg):
        p = msg.pose.pose
        self.truth = (p.position.x, p.position.y, yaw_of(p.orientation))
        self.speed = abs(msg.twist.twist.linear.x)

    def on_status(self, msg):
        self.status = msg

    def wait_sim(self, until, deadline):
        while rospy.Time.now().to_sec() < until and time.time() < deadline and not rospy.is_shutdown():
            time.sleep(0.05)
        self.assertLess(time.time(), deadline, 'sim time stopped at %.1f s' % rospy.Time.now().to_sec())

    def wait_driving(self, deadline):
        # The pause is tested on a robot that drives: asked while it stands at a door (it stops there to
        # turn in), the pause would stop nothing and the test would test nothing.
        while self.speed < MOVING and time.time() < deadline and not rospy.is_shutdown():
            time.sleep(0.01)
        self.assertGreaterEqual(self.speed, MOVING, 'the robot never drove after %.0f s' % PAUSE_AFTER)

    def test_pause_stops_the_robot_and_resume_goes_on_to_complete(self):
        path = rospy.get_param('~result')
        if os.path.exists(path):
            os.remove(path)
        deadline = time.time() + 360.0
        rospy.wait_for_service('exploration/pause', timeout=60.0)
        pause = rospy.ServiceProxy('exploration/pause', SetBool)
        self.wait_sim(PAUSE_AFTER, deadline)
        self.wait_driving(deadline)
        r = pause(True)
        self.assertTrue(r.success, r.message)
        self.assertFalse(pause(True).success, 'pausing twice')
        self.wait_sim(rospy.Time.now().to_sec() + 2.0, deadline)  # braking
        still = self.truth
        self.wait_sim(rospy.Time.now().to_sec() + STILL, deadline)
        now = self.truth
        self.assertLess(math.hypot(now[0] - still[0], now[1] - still[1]), 0.01, 'the robot moved while paused')
        self.assertLess(abs(math.remainder(now[2] - still[2], 2 * math.pi)), 0.01, 'the robot turned while paused')
        self.assertTrue(self.status.state.startswith('paused'), self.status.state)
        r = pause(False)
        self.assertTrue(r.success, r.message)
        result = None
        while time.time() < deadline and not rospy.is_shutdown() and result is None:
            result = read_result(path)
            time.sleep(1.0)
        self.assertIsNotNone(result, 'no evaluation written: the exploration did not end after the resume')
        self.assertTrue(result['complete'], 'the exploration ended incomplete')
        self.assertEqual(result['rooms_mapped'], result['rooms'])


if __name__ == '__main__':
    rospy.init_node('test_explore_pause')
    rostest.rosrun('hybrid_slam', 'explore_pause', ExplorePause)
