#!/usr/bin/python3
"""rostest of launch/replay.launch (a bag replayed through the stack builds a hybrid map and ends).

One script, three cases (~case):
  sim        the simulator's small_loop tour recorded at test time (sim.launch record:=) and replayed:
             the launch ends by itself with status 0 and leaves a map with nodes and at least one place
  bad_topic  a bag whose scans are on front_scan, replayed with the default scan topic: the launch
             ends with a non-zero status and an error that lists the bag's topics with their types
  no_odom    a bag of scans without odometry or tf: the launch says so, runs laser_features only,
             ends with status 0 and writes no topological map
The replay runs as a nested roslaunch on the test's own master.
"""
import json
import math
import os
import shutil
import subprocess
import tempfile
import time
import unittest

import rosbag
import rospy
import rostest
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan

ROSLAUNCH = ['nice', '-n', '19', 'roslaunch', '--wait']


def room_scan(stamp, x, frame='laser', beams=360):
    """A 360-degree scan of a 6 x 4 m room centred at the origin, from (x, 0) heading +x."""
    s = LaserScan()
    s.header.stamp = stamp
    s.header.frame_id = frame
    s.angle_min, s.angle_increment = -math.pi, 2 * math.pi / beams
    s.angle_max = s.angle_min + (beams - 1) * s.angle_increment
    s.range_min, s.range_max = 0.1, 15.0
    for k in range(beams):
        a = s.angle_min + k * s.angle_increment
        c, d = math.cos(a), math.sin(a)
        hits = []
        if c > 1e-9:
            hits.append((3.0 - x) / c)
        if c < -1e-9:
            hits.append((-3.0 - x) / c)
        if d > 1e-9:
            hits.append(2.0 / d)
        if d < -1e-9:
            hits.append(-2.0 / d)
        s.ranges.append(min(hits))
    return s


def write_bag(path, scan_topic, with_odom, scans=40, period=0.1):
    with rosbag.Bag(path, 'w') as bag:
        for k in range(scans):
            t = rospy.Time(1.0 + k * period)
            x = -1.0 + 0.05 * k
            bag.write(scan_topic, room_scan(t, x), t)
            if with_odom:
                o = Odometry()
                o.header.stamp, o.header.frame_id, o.child_frame_id = t, 'odom', 'base_link'
                o.pose.pose.position.x = x
                o.pose.pose.orientation.w = 1.0
                bag.write('/odom', o, t)


def replay(bag, map_file, summary, timeout, extra=()):
    """Runs replay.launch; returns (exit status, output, wall seconds)."""
    cmd = ROSLAUNCH + ['hybrid_slam', 'replay.launch', 'bag:=' + bag, 'map_file:=' + map_file,
                       'summary:=' + summary, 'rate:=10'] + list(extra)
    start = time.time()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=timeout,
                       universal_newlines=True)
    return p.returncode, p.stdout, time.time() - start


class Replay(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix='replay_test_')
        self.map_file = os.path.join(self.dir, 'replay.topo')
        self.summary = os.path.join(self.dir, 'summary.json')

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def test_replay(self):
        case = rospy.get_param('~case')
        getattr(self, 'case_' + case)()

    def case_sim(self):
        bag = os.path.join(self.dir, 'small_loop.bag')
        start = time.time()
        record = subprocess.run(ROSLAUNCH + ['hybrid_slam', 'sim.launch', 'world:=small_loop', 'rate:=10',
                                             'features:=false', 'record:=' + bag],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=150,
                                universal_newlines=True)
        self.assertEqual(record.returncode, 0, record.stdout[-3000:])
        for _ in range(50):  # rosbag record renames BAG.active when it has closed it
            if os.path.exists(bag):
                break
            time.sleep(0.2)
        self.assertTrue(os.path.exists(bag), 'no bag recorded: ' + record.stdout[-3000:])
        rospy.loginfo('replay test: small_loop tour recorded in %.0f s', time.time() - start)
        status, out, wall = replay(bag, self.map_file, self.summary, timeout=150)
        self.assertEqual(status, 0, out[-4000:])
        self.assertTrue(os.path.exists(self.map_file), 'no topological map written\n' + out[-4000:])
        self.assertTrue(os.path.exists(self.map_file + '.places'), 'no places written\n' + out[-4000:])
        with open(self.summary) as f:
            summary = json.load(f)
        rospy.loginfo('replay test: %s (replay %.0f s wall)', summary, wall)
        self.assertTrue(summary['mapping'])
        self.assertGreaterEqual(summary['places'], 1, out[-4000:])
        self.assertGreaterEqual(summary['nodes'], 2, out[-4000:])
        self.assertEqual(summary['end'], 'the bag has ended')

    def case_bad_topic(self):
        bag = os.path.join(self.dir, 'front.bag')
        write_bag(bag, '/front_scan', with_odom=True)
        status, out, _ = replay(bag, self.map_file, self.summary, timeout=60)
        self.assertNotEqual(status, 0, out)
        self.assertIn('the scan topic /scan is not in this bag', out)
        self.assertIn('/front_scan', out)
        self.assertIn('sensor_msgs/LaserScan', out)
        self.assertIn('nav_msgs/Odometry', out)
        self.assertIn('pass scan_topic:=front_scan', out)
        self.assertFalse(os.path.exists(self.map_file))

    def case_no_odom(self):
        bag = os.path.join(self.dir, 'scans_only.bag')
        write_bag(bag, '/scan', with_odom=False)
        status, out, _ = replay(bag, self.map_file, self.summary, timeout=90)
        self.assertEqual(status, 0, out)
        self.assertIn('have no matching odometry', out)
        self.assertIn('pomdp_topo_node not started', out)
        self.assertIn('ekf_local_map_node not started', out)
        self.assertFalse(os.path.exists(self.map_file), 'a topological map was written without odometry')
        self.assertFalse(os.path.exists(self.map_file + '.places'))
        with open(self.summary) as f:
            summary = json.load(f)
        self.assertFalse(summary['mapping'])
        self.assertGreater(summary['features'], 0, 'laser_features did not run: ' + out[-3000:])


if __name__ == '__main__':
    rospy.init_node('test_replay', anonymous=True)
    rostest.rosrun('hybrid_slam', 'replay', Replay)
