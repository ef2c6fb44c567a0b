#!/usr/bin/python3
"""rostest: the laser stops publishing mid-exploration; the robot stops and resumes (see the .test)."""
import math
import time
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan


class LaserGap(unittest.TestCase):
    def setUp(self):
        self.gap_start = rospy.get_param('~gap_start')
        self.gap_length = rospy.get_param('~gap_length')
        self.last_relayed = None  # stamp (s) of the last scan passed on
        self.cmds = []            # (sim time, v, w)
        self.speeds = []          # (sim time, true speed)
        self.pub = rospy.Publisher('scan', LaserScan, queue_size=10)
        rospy.Subscriber('scan_raw', LaserScan, self.on_scan, queue_size=10)
        rospy.Subscriber('cmd_vel', Twist, self.on_cmd, queue_size=100)
        rospy.Subscriber('ground_truth', Odometry, self.on_truth, queue_size=100)

    def in_gap(self, t):
        return self.gap_start <= t < self.gap_start + self.gap_length

    def on_scan(self, msg):
        t = msg.header.stamp.to_sec()
        if self.in_gap(t):
            return
        self.last_relayed = t
        self.pub.publish(msg)

    def on_cmd(self, msg):
        self.cmds.append((rospy.Time.now().to_sec(), msg.linear.x, msg.angular.z))

    def on_truth(self, msg):
        v = msg.twist.twist.linear
        self.speeds.append((msg.header.stamp.to_sec(), math.hypot(v.x, v.y)))

    def test_stops_and_resumes(self):
        deadline = time.time() + 150.0
        end = self.gap_start + self.gap_length + 10.0
        while time.time() < deadline and not rospy.is_shutdown() and rospy.Time.now().to_sec() < end:
            time.sleep(0.2)
        self.assertGreaterEqual(rospy.Time.now().to_sec(), end, 'sim time did not reach the end of the test')
        moving = [v for t, v, _ in self.cmds if self.gap_start - 2.0 <= t < self.gap_start]
        self.assertTrue(moving and max(moving) > 0.2, 'the robot was not driving before the gap')
        # The last scan before the gap: within one scan period of its start.
        last = self.gap_start - 0.1
        stopped = [t for t, v, w in self.cmds if t > last and abs(v) < 1e-6 and abs(w) < 1e-6 and t < self.gap_start + self.gap_length]
        self.assertTrue(stopped, 'the commands never reached zero during the gap')
        delay = stopped[0] - last
        print('commands zero %.2f s after the last scan' % delay)
        # Watchdog after 0.5 s without a scan, then the stop within 0.5 s (the controller's limits).
        self.assertLessEqual(delay, 1.0 + 0.15)
        still = [s for t, s in self.speeds if stopped[0] + 0.2 <= t < self.gap_start + self.gap_length]
        self.assertTrue(still and max(still) < 0.02, 'the robot kept moving: %s' % (max(still) if still else None))
        # Scans return: it drives on within 2 s.
        back = self.gap_start + self.gap_length
        resumed = [t for t, v, w in self.cmds if back <= t <= back + 2.0 and (abs(v) > 0.05 or abs(w) > 0.1)]
        self.assertTrue(resumed, 'the robot did not drive on after the scans returned')


if __name__ == '__main__':
    rospy.init_node('test_explore_laser_gap')
    rostest.rosrun('hybrid_slam', 'explore_laser_gap', LaserGap)
