#!/usr/bin/python3
"""rostest: fingerprints of the simulated robot's surroundings, from its camera and laser."""
import math
import time
import unittest

import rospy
import rostest
from hybrid_slam_msgs.msg import Fingerprint, FingerprintFeature


class FingerprintSim(unittest.TestCase):
    def test_fingerprints_hold_edges_patches_and_laser_features_by_bearing(self):
        rospy.init_node('test_fingerprint_sim')
        got = []
        sub = rospy.Subscriber('fingerprint', Fingerprint, got.append, queue_size=100)
        t0 = time.time()
        while len([m for m in got if m.has_image]) < 10 and time.time() - t0 < 120 and not rospy.is_shutdown():
            time.sleep(0.05)
        sub.unregister()
        with_image = [m for m in got if m.has_image]
        self.assertGreaterEqual(len(with_image), 10, 'fingerprints with an image: %d of %d' % (len(with_image), len(got)))
        for m in with_image:
            self.assertEqual(m.header.frame_id, 'camera')
            bearings = [f.bearing for f in m.features]
            self.assertEqual(bearings, sorted(bearings))
            self.assertTrue(all(-math.pi - 1e-9 <= b <= math.pi + 1e-9 for b in bearings))
        # small_loop's hallway from its start: door frames, wall ends and corners in view. Each kind
        # is in most fingerprints (laser_features skips the first scan, before tf).
        for t, name in ((FingerprintFeature.VERTICAL_EDGE, 'vertical edges'), (FingerprintFeature.COLOR_PATCH, 'colour patches'),
                        (FingerprintFeature.LASER_CORNER, 'laser corners')):
            counts = [sum(1 for f in m.features if f.type == t) for m in with_image]
            self.assertGreaterEqual(sum(1 for c in counts if c > 0), 0.8 * len(with_image), '%s per fingerprint: %s' % (name, counts))
        patches = [f for m in with_image for f in m.features if f.type == FingerprintFeature.COLOR_PATCH]
        self.assertTrue(all(f.hue_bin < 12 and f.angular_width >= 0.05 for f in patches))


if __name__ == '__main__':
    rostest.rosrun('fingerprint', 'fingerprint_sim', FingerprintSim)
