#!/usr/bin/python3
"""rostest of pomdp_topo_node's interface (wall time; the test drives odom -> base_link itself)."""
import math
import os
import unittest

import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import Point, TransformStamped
from hybrid_slam_msgs.msg import BuildingAxes, LaserFeatures, LineFeature, OpeningFeature, TopologicalBelief, TopologicalMap
from hybrid_slam_msgs.msg import TopologicalState
from hybrid_slam_msgs.srv import LoadMap, ResetBelief, SaveMap
from std_srvs.srv import Trigger

DOOR_X = 3.0  # a door on the left of a straight hallway, 1.1 m from its centre line


def hallway_features(stamp, x, nan=False):
    """The two walls of the hallway and the door when within 5 m, in the laser frame at (x, 0, 0)."""
    msg = LaserFeatures()
    msg.header.stamp = stamp
    msg.header.frame_id = 'laser'
    msg.odometry_consistency = -1.0  # not evaluated (the message's default 0 would read as a jump)
    for alpha in (math.pi / 2, -math.pi / 2):
        y = 1.1 if alpha > 0 else -1.1
        msg.lines.append(LineFeature(alpha=alpha, r=1.1, covariance=[1e-5, 0.0, 0.0, 1e-5],
                                     start=Point(-3, y, 0), end=Point(3, y, 0), num_points=100))
    if abs(DOOR_X - x) < 5.0:
        msg.openings.append(OpeningFeature(left=Point(DOOR_X - x - 0.45, 1.1, 0), right=Point(DOOR_X - x + 0.45, 1.1, 0),
                                           x=DOOR_X - x, y=1.1, theta=math.pi / 2, width=0.9,
                                           kind=OpeningFeature.DOOR, confidence=0.8))
    if nan:
        msg.lines[0].alpha = float('nan')
        if msg.openings:
            msg.openings[0].x = float('nan')
    return msg


class NodeInterface(unittest.TestCase):
    def setUp(self):
        self.beliefs = []
        self.map = None
        rospy.Subscriber('topological_belief', TopologicalBelief, self.beliefs.append)
        rospy.Subscriber('topological_map', TopologicalMap, self.on_map)
        self.axes = []
        rospy.Subscriber('building_axes', BuildingAxes, self.axes.append)
        self.states = []
        rospy.Subscriber('topological_state', TopologicalState, self.states.append)
        self.pub = rospy.Publisher('features', LaserFeatures, queue_size=100)
        self.tf = tf2_ros.TransformBroadcaster()
        for name in ('save_map', 'load_map', 'reset_belief', 'clear_map'):
            rospy.wait_for_service('pomdp_topo/' + name, 30)
        self.save = rospy.ServiceProxy('pomdp_topo/save_map', SaveMap)
        self.load = rospy.ServiceProxy('pomdp_topo/load_map', LoadMap)
        self.reset = rospy.ServiceProxy('pomdp_topo/reset_belief', ResetBelief)
        deadline = rospy.Time.now() + rospy.Duration(20)
        while self.pub.get_num_connections() == 0 and rospy.Time.now() < deadline:
            rospy.sleep(0.05)
        rospy.sleep(1.0)  # the static laser transform reaches the node's tf buffer

    def on_map(self, msg):
        self.map = msg

    def odom(self, stamp, x):
        t = TransformStamped()
        t.header.stamp = stamp
        t.header.frame_id = 'odom'
        t.child_frame_id = 'base_link'
        t.transform.translation.x = x
        t.transform.rotation.w = 1.0
        self.tf.sendTransform(t)

    def step(self, x, nan=False, stamp=None):
        stamp = stamp or rospy.Time.now()
        self.odom(stamp, x)
        rospy.sleep(0.01)
        self.pub.publish(hallway_features(stamp, x, nan))
        rospy.sleep(0.02)
        return stamp

    def assert_belief_sane(self):
        self.assertTrue(self.beliefs, 'no belief published')
        b = self.beliefs[-1]
        self.assertTrue(all(math.isfinite(p) for p in b.probability))
        if b.probability:
            self.assertAlmostEqual(sum(b.probability), 1.0, places=6)

    def door_nodes(self):
        return [n for n in self.map.nodes if n.type == n.DOOR] if self.map else []

    def test_interface(self):
        # Drive 6 m along the hallway, past the door at 3 m: a door node is built.
        x = 0.0
        while x < 6.0:
            self.step(x)
            x += 0.05
        rospy.sleep(0.5)
        self.assertEqual(len(self.door_nodes()), 1, 'one door node expected, map: %s' % self.map)
        self.assert_belief_sane()
        # The building's axis, from the hallway's two walls of the first scan (normals at +-90 deg).
        self.assertTrue(self.axes, 'no building_axes published')
        self.assertEqual(self.axes[-1].source, BuildingAxes.ESTIMATED)
        self.assertAlmostEqual(self.axes[-1].axis_angle, 0.0, places=3)
        self.assertEqual(self.axes[-1].heading_bins, 4)
        self.assertGreater(self.axes[-1].agreement, 0.99)
        # One state per features message, stamped with it: mapping a new stretch (FRONTIER), where
        # the place is known; the heading along the hallway's axis; the position where the last
        # step put the robot (the map frame is the odometry's at the first scan).
        self.assertTrue(self.states, 'no topological_state published')
        s = self.states[-1]
        self.assertEqual(s.mode, TopologicalState.FRONTIER)
        self.assertTrue(s.confident)
        self.assertLess(abs(s.heading), 0.05)
        self.assertLess(abs(s.x - (x - 0.05)), 0.05)
        self.assertLess(abs(s.y), 0.05)
        self.assertEqual(len(set(m.header.stamp for m in self.states)), len(self.states))

        # NaN features: dropped, the node keeps working, no NaN in the belief.
        for _ in range(10):
            self.step(x, nan=True)
            x += 0.05
        self.assert_belief_sane()

        # Features older than the last ones: dropped (no belief for that stamp).
        last = self.step(x)
        count = len(self.beliefs)
        self.pub.publish(hallway_features(last - rospy.Duration(1.0), x))
        rospy.sleep(0.3)
        self.assertFalse(any(b.header.stamp == last - rospy.Duration(1.0) for b in self.beliefs[count:]))

        # An odometry jump of 5 m between two scans: refused, the node carries on from there.
        x += 5.0
        self.step(x)
        for _ in range(20):
            x += 0.05
            self.step(x)
        self.assert_belief_sane()
        self.assertEqual(len(self.door_nodes()), 1)

        # Reset to a node that does not exist: refused, belief unchanged; uniform: accepted.
        r = self.reset(uniform=False, node=9999, heading=0.0)
        self.assertFalse(r.success)
        self.assertIn('9999', r.message)
        self.assertTrue(self.reset(uniform=True, node=0, heading=0.0).success)
        self.step(x)
        self.assert_belief_sane()

        # Save; a corrupt file is refused and the map kept; the good file loads.
        path = '/tmp/pomdp_topo_node_interface_test.topo'
        self.assertTrue(self.save(path=path).success)
        with open(path, 'rb') as f:
            data = bytearray(f.read())
        data[len(data) // 2] ^= 0xFF
        corrupt = path + '.corrupt'
        with open(corrupt, 'wb') as f:
            f.write(data)
        nodes_before = len(self.map.nodes)
        r = self.load(path=corrupt)
        self.assertFalse(r.success)
        self.assertIn('checksum', r.message)
        rospy.sleep(0.2)
        self.assertEqual(len(self.map.nodes), nodes_before)
        self.assertTrue(self.load(path=path).success)
        # A loaded map starts a global localization: on the known graph (LOCALIZED), the belief
        # uniform and not confident; one state for the features of that stamp.
        x += 0.05
        stamp = self.step(x)
        rospy.sleep(0.2)
        s = [m for m in self.states if m.header.stamp == stamp]
        self.assertEqual(len(s), 1, 'one topological_state for the features at %s' % stamp)
        self.assertEqual(s[0].mode, TopologicalState.LOCALIZED)
        self.assertFalse(s[0].confident)
        self.assertFalse(self.load(path='/nonexistent/dir/map.topo').success)
        os.remove(corrupt)

        # An empty map: clearing works, scans keep coming, nothing crashes.
        self.assertTrue(rospy.ServiceProxy('pomdp_topo/clear_map', Trigger)().success)
        for _ in range(10):
            x += 0.05
            self.step(x)
        self.assert_belief_sane()


if __name__ == '__main__':
    rospy.init_node('test_pomdp_topo_node_interface')
    rostest.rosrun('pomdp_topo', 'node_interface', NodeInterface)
