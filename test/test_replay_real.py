#!/usr/bin/python3
"""rostest: a real recorded log (CARMEN Freiburg 101, 292 scans over 209 m, a 180 deg scanner, one scan
per ~0.7 m) replayed with config/replay_real.yaml and scored by scripts/evaluate_replay against the log's
SLAM-corrected poses. The rules it checks hold for any log of an office floor:
  - a place is made where the path goes through a door, and stores that door (doors_stored == places);
  - coming back through a known door re-enters that place, and ekf_local_map relocates in it;
  - within places, the EKF's trajectory is closer to the corrected poses than dead reckoning.
Skipped, with a message, where ../shared/data (relative to the project root; HYBRID_SLAM_SHARED_DATA
overrides it) is absent.
"""
import json
import os
import shutil
import socket
import subprocess
import tempfile
import unittest

import rostest

# The project root, through the workspace's symlink to it; the shared data lie beside it.
ROOT = os.path.dirname(os.path.dirname(os.path.realpath(__file__)))
DATA = os.environ.get('HYBRID_SLAM_SHARED_DATA', os.path.join(os.path.dirname(ROOT), 'shared', 'data'))
LOG = os.path.join(DATA, 'carmen', 'freiburg-101-corrected.log.gz')


def free_port():
    with socket.socket() as s:
        s.bind(('localhost', 0))
        return s.getsockname()[1]


class ReplayRealLog(unittest.TestCase):
    def setUp(self):
        self.out = tempfile.mkdtemp(prefix='hybrid_slam_replay_real_')

    def tearDown(self):
        shutil.rmtree(self.out, ignore_errors=True)

    def test_freiburg_101(self):
        if not os.path.exists(LOG):
            # rosunit's XML has no skipped cases: scripts/test_summary.py counts this line instead.
            print('SKIPPED test_freiburg_101: %s is absent: no real log to replay' % LOG, flush=True)
            self.skipTest('%s is absent: no real log to replay' % LOG)
        cmd = ['nice', '-n', '19', '/usr/bin/python3', os.path.join(ROOT, 'scripts', 'evaluate_replay'), LOG,
               '--out', self.out, '--params', os.path.join(ROOT, 'config', 'replay_real.yaml'),
               '--port', str(free_port())]
        run = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
        log = open(os.path.join(self.out, 'freiburg-101.launch.log')).read()[-4000:] if os.path.exists(
            os.path.join(self.out, 'freiburg-101.launch.log')) else ''
        self.assertEqual(run.returncode, 0, run.stdout[-3000:] + log)
        r = json.loads(run.stdout.strip().splitlines()[-1])
        why = json.dumps(r) + '\n' + log
        self.assertGreaterEqual(r['places'], 2, why)
        self.assertGreaterEqual(r['door_crossings'], r['places'], why)
        self.assertEqual(r['doors_stored'], r['places'], 'a place without the door it was entered by\n' + why)
        self.assertGreaterEqual(r['reentries_relocated'], 1, why)
        self.assertLess(r['ekf_error_m']['mean'], r['odometry_error_m']['mean'], why)
        self.assertTrue(os.path.exists(os.path.join(self.out, 'freiburg-101.png')))


if __name__ == '__main__':
    rostest.rosrun('hybrid_slam', 'replay_real', ReplayRealLog)
