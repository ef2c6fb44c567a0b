#!/usr/bin/python3
"""rostest of ekf_local_map_node's interface (wall time, static odometry)."""
import math
import os
import unittest

import rospy
import rostest
from geometry_msgs.msg import Point, PoseWithCovarianceStamped
from hybrid_slam_msgs.msg import LaserFeatures, LineFeature
from hybrid_slam_msgs.srv import CreatePlace, LoadMap, SaveMap


def room_features(stamp, frame='laser', nan=False):
    """The four walls of a 6 x 4 m room around the sensor."""
    msg = LaserFeatures()
    msg.header.stamp = stamp
    msg.header.frame_id = frame
    for alpha, r, a, b in ((0.0, 3.0, (3, -2), (3, 2)), (math.pi / 2, 2.0, (3, 2), (-3, 2)),
                           (math.pi, 3.0, (-3, 2), (-3, -2)), (-math.pi / 2, 2.0, (-3, -2), (3, -2))):
        line = LineFeature(alpha=alpha, r=r, covariance=[1e-5, 0.0, 0.0, 1e-5],
                           start=Point(a[0], a[1], 0), end=Point(b[0], b[1], 0), num_points=100)
        msg.lines.append(line)
    if nan:
        msg.lines[0].r = float('nan')
    return msg


class NodeInterface(unittest.TestCase):
    def setUp(self):
        self.poses = {}
        rospy.Subscriber('local_pose', PoseWithCovarianceStamped, self.on_pose)
        self.pub = rospy.Publisher('features', LaserFeatures, queue_size=10)
        for name in ('create_place', 'save_map', 'load_map'):
            rospy.wait_for_service('ekf_local_map/' + name, 30)
        self.create = rospy.ServiceProxy('ekf_local_map/create_place', CreatePlace)
        self.save = rospy.ServiceProxy('ekf_local_map/save_map', SaveMap)
        self.load = rospy.ServiceProxy('ekf_local_map/load_map', LoadMap)
        deadline = rospy.Time.now() + rospy.Duration(20)
        while self.pub.get_num_connections() == 0 and rospy.Time.now() < deadline:
            rospy.sleep(0.05)

    def on_pose(self, msg):
        self.poses[msg.header.stamp.to_nsec()] = msg

    def send(self, msg, timeout=3.0):
        self.pub.publish(msg)
        deadline = rospy.Time.now() + rospy.Duration(timeout)
        while rospy.Time.now() < deadline:
            if msg.header.stamp.to_nsec() in self.poses:
                return self.poses[msg.header.stamp.to_nsec()]
            rospy.sleep(0.02)
        return None

    def test_interface(self):
        self.assertTrue(self.create(use_display_pose=False).success)
        # The tf listener needs the static transforms first: resend until one is answered.
        answered = None
        for _ in range(50):
            answered = self.send(room_features(rospy.Time.now()), 0.5)
            if answered:
                break
        self.assertIsNotNone(answered, 'no local_pose for good features')
        p = answered.pose.pose.position
        self.assertLess(math.hypot(p.x, p.y), 0.01)

        # Unknown frame: refused, no pose for that stamp; the node keeps working.
        self.assertIsNone(self.send(room_features(rospy.Time.now(), frame='nowhere'), 1.5))
        self.assertIsNotNone(self.send(room_features(rospy.Time.now())))

        # A NaN line is rejected, the others fused: the pose stays finite.
        pose = self.send(room_features(rospy.Time.now(), nan=True))
        self.assertIsNotNone(pose)
        self.assertTrue(all(math.isfinite(v) for v in pose.pose.covariance))
        self.assertTrue(math.isfinite(pose.pose.pose.position.x))

        # Save, then a corrupt file is refused and the maps kept; the good file loads.
        path = '/tmp/ekf_node_interface_test.places'
        self.assertTrue(self.save(path=path).success)
        corrupt = path + '.corrupt'
        with open(path, 'rb') as f:
            data = bytearray(f.read())
        data[len(data) // 2] ^= 0xFF
        with open(corrupt, 'wb') as f:
            f.write(data)
        refused = self.load(path=corrupt)
        self.assertFalse(refused.success)
        self.assertIn('kept', refused.message)
        self.assertTrue(self.load(path=path).success)
        os.remove(corrupt)


if __name__ == '__main__':
    rospy.init_node('test_ekf_node_interface')
    rostest.rosrun('ekf_local_map', 'node_interface', NodeInterface)
