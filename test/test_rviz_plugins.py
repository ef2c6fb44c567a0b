#!/usr/bin/python3
"""rostest: the rviz plugins of hybrid_slam_rviz load in rviz under Xvfb with config/hybrid_slam.rviz
(the panel subscribes to the exploration's status and belief, the tool is an action client of
go_to_place), and a pose clicked and dragged with the "Go to place" tool arrives at a GoToPlace
server (this test's) in the frame of the nearest place. No simulator: the test publishes the place
frames and serves the action. With ~screenshot set, a picture of the window is written there."""
import math
import os
import subprocess
import time
import unittest

import actionlib
import rosgraph
import rospkg
import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import TransformStamped
from hybrid_slam_msgs.msg import ExplorationStatus, GoToPlaceAction, GoToPlaceResult, TopologicalBelief

SIZE = (1400, 900)  # the screen; hybrid_slam.rviz's window fills it


def frame(parent, child, x, y, yaw):
    t = TransformStamped()
    t.header.stamp = rospy.Time.now()
    t.header.frame_id, t.child_frame_id = parent, child
    t.transform.translation.x, t.transform.translation.y = x, y
    t.transform.rotation.z, t.transform.rotation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    return t


class RvizPlugins(unittest.TestCase):
    def setUp(self):
        self.goals = []
        self.procs = []

    def tearDown(self):
        for p in reversed(self.procs):
            p.terminate()
            try:
                p.wait(10)
            except subprocess.TimeoutExpired:
                p.kill()

    def on_goal(self, goal):
        self.goals.append(goal)
        self.server.set_succeeded(GoToPlaceResult(success=True, message='test server'))

    def start_display(self):
        r, w = os.pipe()
        self.procs.append(subprocess.Popen(['Xvfb', '-displayfd', str(w), '-screen', '0', '%dx%dx24' % SIZE, '-nolisten', 'tcp'],
                                           pass_fds=[w], stderr=subprocess.DEVNULL))
        os.close(w)
        number = b''
        while not number.endswith(b'\n'):
            c = os.read(r, 1)
            self.assertTrue(c, 'Xvfb did not start')
            number += c
        os.close(r)
        return ':' + number.decode().strip()

    def rviz_node(self):
        """rviz's node name once it subscribes to exploration_status (the panel loaded), or None."""
        _, subscribers, _ = rosgraph.Master(rospy.get_name()).getSystemState()
        for topic, nodes in subscribers:
            if topic == '/exploration_status':
                return next((n for n in nodes if 'rviz' in n), None)
        return None

    def test_the_panel_and_tool_load_and_a_click_sends_a_mission_to_the_nearest_place(self):
        static = tf2_ros.StaticTransformBroadcaster()
        # map = world here; place 0 near the view's centre (15, 12.5), place 1 far from it
        static.sendTransform([frame('world', 'map', 0, 0, 0), frame('map', 'place_0', 14.0, 12.0, math.pi / 2),
                              frame('map', 'place_1', 3.0, 3.0, 0.0)])
        self.server = actionlib.SimpleActionServer('go_to_place', GoToPlaceAction, self.on_goal, auto_start=False)
        self.server.start()
        status = rospy.Publisher('exploration_status', ExplorationStatus, queue_size=1, latch=True)
        belief = rospy.Publisher('topological_belief', TopologicalBelief, queue_size=1, latch=True)
        status.publish(ExplorationStatus(mode=ExplorationStatus.METRIC, current_place=0, current_node=-1, places=2,
                                         nodes=5, travel_distance=42.0, state='exploring the room'))
        belief.publish(TopologicalBelief(entropy=0.5, entropy_max=2.0, confident=True, most_likely=-1))

        display = self.start_display()
        env = dict(os.environ, DISPLAY=display)
        config = os.path.join(rospkg.RosPack().get_path('hybrid_slam'), 'config', 'hybrid_slam.rviz')
        log = open(os.path.join(os.environ.get('ROS_LOG_DIR', '/tmp'), 'test_rviz_plugins_rviz.log'), 'w')
        self.procs.append(subprocess.Popen(['rosrun', 'rviz', 'rviz', '-d', config], env=env, stdout=log, stderr=subprocess.STDOUT))
        deadline = time.time() + 90.0
        node = None
        while time.time() < deadline and node is None:
            node = self.rviz_node()
            time.sleep(0.5)
        self.assertIsNotNone(node, 'rviz never subscribed to exploration_status: the panel did not load')
        _, subscribers, _ = rosgraph.Master(rospy.get_name()).getSystemState()
        self.assertIn(node, dict(subscribers).get('/topological_belief', []))
        while time.time() < deadline and self.server.action_server.status_pub.get_num_connections() == 0:
            time.sleep(0.5)  # the tool's action client
        self.assertGreater(self.server.action_server.status_pub.get_num_connections(), 0,
                           'no action client on go_to_place: the tool did not load')
        time.sleep(3.0)  # the first frames rendered

        # click in the middle of the 3D view (the view centre), press 'p' (the tool), drag 60 px right
        x, y = 880, 460
        xdo = ['xdotool', 'mousemove', str(x), str(y), 'click', '1', 'key', 'p', 'sleep', '0.5', 'mousedown', '1',
               'mousemove', str(x + 20), str(y), 'mousemove', str(x + 60), str(y), 'mouseup', '1']
        subprocess.run(xdo, env=env, check=True)
        while time.time() < deadline and not self.goals:
            time.sleep(0.2)
        shot = rospy.get_param('~screenshot', '')
        if shot:
            subprocess.run('xwd -root -display %s | convert xwd:- %s' % (display, shot), shell=True, check=False)
        log.close()
        self.assertEqual(len(self.goals), 1, 'the click sent no mission (rviz log: %s)' % log.name)
        g = self.goals[0]
        self.assertEqual(g.place_id, 0)
        # the view's centre (about (15, 12.5) in map) in place 0's frame (at (14, 12), yawed +90 deg):
        # about (0.5, -1.0); the drag to the right is map +x, place 0's -y: theta about -90 deg
        self.assertAlmostEqual(g.goal.x, 0.5, delta=1.0)
        self.assertAlmostEqual(g.goal.y, -1.0, delta=1.0)
        self.assertAlmostEqual(g.goal.theta, -math.pi / 2, delta=0.2)


if __name__ == '__main__':
    rospy.init_node('test_rviz_plugins')
    rostest.rosrun('hybrid_slam', 'rviz_plugins', RvizPlugins)
