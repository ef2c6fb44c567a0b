#!/usr/bin/python3
"""rostest: tools/evaluate_fingerprints' protocol on a bag made here. The robot drives 10 m along a
corridor of landmarks and back; each fingerprint holds the bearings of the landmarks within 6 m as
its features. The way back (another pass, turned round) is matched against the way out's references."""
import json
import math
import os
import random
import subprocess
import tempfile
import unittest

import rosbag
import rospy
import rostest
from hybrid_slam_msgs.msg import Fingerprint, FingerprintFeature
from nav_msgs.msg import Odometry

KINDS = (FingerprintFeature.VERTICAL_EDGE, FingerprintFeature.LASER_CORNER, FingerprintFeature.LASER_DOOR)


def tool():
    out = subprocess.run(['catkin_find', '--first-only', 'hybrid_slam', 'evaluate_fingerprints'],
                         stdout=subprocess.PIPE, universal_newlines=True)
    return out.stdout.strip() or 'evaluate_fingerprints'


class FingerprintEvaluation(unittest.TestCase):
    def write_bag(self, path, shuffle_back=False):
        rng = random.Random(3)
        landmarks = [(rng.uniform(-2, 12), rng.choice((-1.5, 1.5)) + rng.uniform(-0.3, 0.3), rng.choice(KINDS))
                     for _ in range(40)]
        with rosbag.Bag(path, 'w') as bag:
            def at(t, x, heading):
                stamp = rospy.Time.from_sec(t)
                o = Odometry()
                o.header.stamp = stamp
                o.pose.pose.position.x, o.pose.pose.position.y = x, 0.0
                bag.write('/ground_truth', o, stamp)
                fp = Fingerprint(has_image=True)
                fp.header.stamp = stamp
                seen = landmarks if not (shuffle_back and heading) else [(rng.uniform(-2, 12), l[1], l[2]) for l in landmarks]
                for lx, ly, kind in seen:
                    if math.hypot(lx - x, ly) > 6.0:
                        continue
                    b = math.atan2(ly, lx - x) - heading
                    fp.features.append(FingerprintFeature(type=kind, bearing=math.atan2(math.sin(b), math.cos(b)),
                                                          bearing_sigma=0.02, hue_bin=255))
                fp.features.sort(key=lambda f: f.bearing)
                bag.write('/fingerprint', fp, stamp)
            for k in range(101):  # out: 0.1 m a step, 5 fingerprints a second
                at(1.0 + k * 0.2, k * 0.1, 0.0)
            for k in range(101):  # back, turned round, 100 s later
                at(100.0 + k * 0.2, 10.0 - k * 0.1, math.pi)

    def run_tool(self, bag):
        out = subprocess.run([tool(), '--bag', bag], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                             universal_newlines=True, timeout=60)
        self.assertEqual(out.returncode, 0, out.stdout)
        return json.loads(out.stdout.strip().splitlines()[-1])

    def test_the_way_back_finds_the_way_outs_references(self):
        with tempfile.TemporaryDirectory() as d:
            bag = os.path.join(d, 'corridor.bag')
            self.write_bag(bag)
            r = self.run_tool(bag)
            self.assertEqual(r['fingerprints'], 202)
            self.assertEqual(r['references'], 7)  # every 1.5 m of the way out: x = 0, 1.6, 3.2, ... 9.6
            self.assertGreater(r['tests'], 40)
            # A test lies up to 0.75 m from its nearest reference, and the next one (1.6 m on) sees most
            # of the same landmarks: the answer is that reference or its neighbour.
            self.assertGreaterEqual(r['near'], 0.95 * r['tests'])
            self.assertGreaterEqual(r['right_pct'], 80.0)

    def test_places_that_changed_are_not_found(self):
        with tempfile.TemporaryDirectory() as d:
            bag = os.path.join(d, 'changed.bag')
            self.write_bag(bag, shuffle_back=True)
            r = self.run_tool(bag)
            self.assertLess(r['right_pct'], 50.0)


if __name__ == '__main__':
    rostest.rosrun('hybrid_slam', 'fingerprint_evaluation', FingerprintEvaluation)
