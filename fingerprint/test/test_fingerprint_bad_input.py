#!/usr/bin/python3
"""rostest: the fingerprint node on good and bad input - an image of the wrong encoding or size is
reported and the node goes on with laser-only fingerprints, as it does without images."""
import math
import time
import unittest

import rospy
import rostest
from hybrid_slam_msgs.msg import CornerFeature, Fingerprint, FingerprintFeature, LaserFeatures, OpeningFeature
from sensor_msgs.msg import CameraInfo, Image

W, H = 720, 120


class BadInput(unittest.TestCase):
    def setUp(self):
        rospy.init_node('test_fingerprint_bad_input')
        self.got = []
        self.sub = rospy.Subscriber('fingerprint', Fingerprint, self.got.append, queue_size=100)
        self.info = rospy.Publisher('camera/camera_info', CameraInfo, queue_size=10, latch=True)
        self.image = rospy.Publisher('camera/image_raw', Image, queue_size=10)
        self.features = rospy.Publisher('features', LaserFeatures, queue_size=10)
        deadline = time.time() + 20
        while time.time() < deadline and (self.image.get_num_connections() == 0 or self.features.get_num_connections() == 0
                                          or self.info.get_num_connections() == 0 or self.sub.get_num_connections() == 0):
            time.sleep(0.05)
        info = CameraInfo(width=W, height=H)
        fx, fy = W / (2 * math.pi), H / (math.pi / 3)
        info.K = [fx, 0, W / 2.0, 0, fy, H / 2.0, 0, 0, 1]
        info.header.frame_id = 'camera'
        self.info.publish(info)
        time.sleep(0.5)

    def scan(self, stamp):
        m = LaserFeatures()
        m.header.stamp, m.header.frame_id = stamp, 'laser'
        m.corners.append(CornerFeature(x=2.0, y=0.0, theta=math.pi, covariance=[1e-4, 0, 0, 0, 1e-4, 0, 0, 0, 1e-3],
                                       convex=False, confidence=0.9))
        m.openings.append(OpeningFeature(x=0.0, y=2.0, theta=math.pi / 2, width=0.9, kind=OpeningFeature.DOOR,
                                         confidence=0.8))
        self.features.publish(m)

    def frame(self, stamp, encoding='rgb8', rows=H):
        img = Image(width=W, height=rows, encoding=encoding, step=W * (1 if encoding == 'mono8' else 3))
        img.header.stamp, img.header.frame_id = stamp, 'camera'
        row = bytearray()
        for c in range(W):
            row += bytes([200, 60, 50] if c < 300 else [50, 60, 200]) if encoding != 'mono8' else bytes([128])
        img.data = bytes(row) * rows
        self.image.publish(img)

    def next_fingerprint(self, stamp):
        deadline = time.time() + 10
        while time.time() < deadline:
            for m in self.got:
                if m.header.stamp == stamp:
                    return m
            time.sleep(0.02)
        self.fail('no fingerprint for the stamp %s' % stamp.to_sec())

    def test_good_and_bad_images_and_none(self):
        types = lambda m: sorted(f.type for f in m.features)
        # The image first: a scan before any image makes a laser-only fingerprint (no image yet).
        t = rospy.Time.now()
        self.frame(t)
        time.sleep(0.2)
        self.scan(t)
        good = self.next_fingerprint(t)
        self.assertTrue(good.has_image)
        self.assertEqual(good.header.frame_id, 'camera')
        self.assertEqual(types(good).count(FingerprintFeature.VERTICAL_EDGE), 2)
        self.assertEqual(types(good).count(FingerprintFeature.COLOR_PATCH), 2)
        self.assertIn(FingerprintFeature.LASER_CORNER, types(good))
        self.assertIn(FingerprintFeature.LASER_DOOR, types(good))
        corner = [f for f in good.features if f.type == FingerprintFeature.LASER_CORNER][0]
        self.assertAlmostEqual(corner.bearing, 0.0, places=9)  # 2.05 m ahead of the camera

        for kind in ('mono8', 'short'):
            t = t + rospy.Duration(0.2)
            self.scan(t)
            self.frame(t, encoding='mono8' if kind == 'mono8' else 'rgb8', rows=H if kind == 'mono8' else 100)
            bad = self.next_fingerprint(t)
            self.assertFalse(bad.has_image, kind)
            self.assertEqual(types(bad), [FingerprintFeature.LASER_CORNER, FingerprintFeature.LASER_DOOR], kind)

        # No image for more than image_timeout: each scan makes a laser-only fingerprint.
        t = t + rospy.Duration(2.0)
        self.scan(t)
        alone = self.next_fingerprint(t)
        self.assertFalse(alone.has_image)
        self.assertEqual(alone.header.frame_id, 'camera')
        self.assertEqual(len(alone.features), 2)


if __name__ == '__main__':
    rostest.rosrun('fingerprint', 'fingerprint_bad_input', BadInput)
