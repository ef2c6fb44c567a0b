#!/usr/bin/python3
"""rostest / evaluation: the robot drives through a room of the simulator; a place is created when
it is inside, closed when it leaves. The EKF pose (in the place frame) is compared with the ground
truth and with odometry alone. Evaluation code: the only reader of ground truth besides the simulator.

Params: ~world_file, ~room (region name), ~inside_margin (m), ~max_sim_time (s),
~max_final_error (m), ~report (optional path: a Markdown row is appended).
"""
import math
import os
import sys
import time
import unittest

import rospy
import rostest
import yaml
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import Odometry
from std_srvs.srv import Trigger
from hybrid_slam_msgs.srv import CreatePlace
from lockstep import Participant
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'scripts'))
from world_geometry import yaw_of  # noqa: E402



def pose_of(msg_pose):
    return (msg_pose.position.x, msg_pose.position.y, yaw_of(msg_pose.orientation))


def wrap(a):
    return math.atan2(math.sin(a), math.cos(a))


def between(a, b):
    """b in a's frame."""
    c, s = math.cos(a[2]), math.sin(a[2])
    dx, dy = b[0] - a[0], b[1] - a[1]
    return (c * dx + s * dy, -s * dx + c * dy, wrap(b[2] - a[2]))


def inside(polygon, x, y, margin):
    result = False
    j = len(polygon) - 1
    for i in range(len(polygon)):
        (xi, yi), (xj, yj) = polygon[i], polygon[j]
        if (yi > y) != (yj > y) and x < (xj - xi) * (y - yi) / (yj - yi) + xi:
            result = not result
        j = i
    if not result:
        return False
    for i in range(len(polygon)):
        (ax, ay), (bx, by) = polygon[i - 1], polygon[i]
        L2 = (bx - ax) ** 2 + (by - ay) ** 2
        t = max(0.0, min(1.0, ((x - ax) * (bx - ax) + (y - ay) * (by - ay)) / L2))
        if math.hypot(x - ax - t * (bx - ax), y - ay - t * (by - ay)) < margin:
            return False
    return True


def solve3(P, e):
    """e^T P^-1 e for a 3x3 symmetric P (Cramer)."""
    a, b, c = P[0]
    d, e_, f = P[1]
    g, h, i = P[2]
    det = a * (e_ * i - f * h) - b * (d * i - f * g) + c * (d * h - e_ * g)
    inv = [[(e_ * i - f * h) / det, (c * h - b * i) / det, (b * f - c * e_) / det],
           [(f * g - d * i) / det, (a * i - c * g) / det, (c * d - a * f) / det],
           [(d * h - e_ * g) / det, (b * g - a * h) / det, (a * e_ - b * d) / det]]
    return sum(e[r] * inv[r][k] * e[k] for r in range(3) for k in range(3))


class RoomDrive(unittest.TestCase):
    def test_ekf_beats_odometry_in_a_room(self):
        with open(rospy.get_param('~world_file')) as f:
            world = yaml.safe_load(f)
        room = rospy.get_param('~room')
        polygon = [r['polygon'] for r in world['regions'] if r['name'] == room][0]
        margin = rospy.get_param('~inside_margin', 0.6)
        truth, odom = {}, {}
        state = {'place': None, 'done': False, 't0': None, 'o0': None, 'last': None, 'nees': [], 'samples': 0}

        rospy.wait_for_service('ekf_local_map/create_place', 60)
        create = rospy.ServiceProxy('ekf_local_map/create_place', CreatePlace)
        close = rospy.ServiceProxy('ekf_local_map/close_place', Trigger)

        def key(stamp):
            return round(stamp.to_sec(), 3)

        def on_truth(m):
            truth[key(m.header.stamp)] = pose_of(m.pose.pose)

        def on_odom(m):
            odom[key(m.header.stamp)] = pose_of(m.pose.pose)

        poses = []  # the EKF's poses not yet compared: their ground truth may come after them

        def on_pose(m):
            if state['place'] is not None and not state['done']:
                poses.append(m)

        def compare(m):
            """The EKF's pose against the ground truth and odometry of its stamp, relative to the place."""
            k = key(m.header.stamp)
            true_rel = between(state['t0'], truth[k])
            est = pose_of(m.pose.pose)
            odo_rel = between(state['o0'], odom[k])
            err = (est[0] - true_rel[0], est[1] - true_rel[1], wrap(est[2] - true_rel[2]))
            c = m.pose.covariance
            P = [[c[0], c[1], c[5]], [c[6], c[7], c[11]], [c[30], c[31], c[35]]]
            try:
                state['nees'].append(solve3(P, err))
            except ZeroDivisionError:
                pass
            state['last'] = (err, (odo_rel[0] - true_rel[0], odo_rel[1] - true_rel[1], wrap(odo_rel[2] - true_rel[2])))
            state['samples'] += 1

        # In lockstep (rate 0) this script takes part: it decides at each step of the simulator,
        # after ekf_local_map has finished the step, with that step's ground truth and odometry.
        participant = Participant(upstream=['ekf_local_map'])
        participant.subscribe('ground_truth', Odometry, on_truth, queue_size=200)
        participant.subscribe('odom', Odometry, on_odom, queue_size=200)
        participant.subscribe('local_pose', PoseWithCovarianceStamped, on_pose, queue_size=50)

        def decide():
            """Compares the poses whose ground truth has come; creates the place once the robot is
            inside the room, closes it once it has left."""
            while poses:
                k = key(poses[0].header.stamp)
                if k in truth and k in odom:
                    compare(poses.pop(0))
                elif truth and k < max(truth) - 1.0:
                    poses.pop(0)  # paced: its ground truth was lost
                else:
                    break
            if not truth or state['done']:
                return
            k = max(truth)
            x, y, _ = truth[k]
            now_inside = inside(polygon, x, y, margin)
            if state['place'] is None and now_inside:
                answer = create(use_display_pose=False)
                k0 = key(answer.origin_stamp)
                # That instant's ground truth and odometry may still be on their way (paced runs).
                deadline = time.time() + 2.0
                while (k0 not in truth or k0 not in odom) and time.time() < deadline and not participant.enabled:
                    time.sleep(0.05)
                state['error'] = None if (k0 in truth and k0 in odom) else 'no ground truth or odometry at %.3f' % k0
                if state['error'] is None:
                    state['t0'], state['o0'] = truth[k0], odom[k0]
                    state['place'] = answer.place_id
                    rospy.loginfo('place %d created at the true pose (%.2f, %.2f)', state['place'], x, y)
                else:
                    state['done'] = True
            elif state['place'] is not None and not inside(polygon, x, y, 0.0):
                close()
                state['done'] = True

        participant.on_step(lambda stamp: decide())
        limit = rospy.get_param('~max_sim_time', 600.0)
        rate = rospy.Rate(20)
        while not rospy.is_shutdown() and not state['done'] and rospy.get_time() < limit:
            if not participant.enabled:
                with participant.lock:
                    decide()
            try:
                rate.sleep()
            except rospy.ROSTimeMovedBackwardsException:
                pass
        self.assertIsNone(state.get('error'), state.get('error'))
        self.assertIsNotNone(state['place'], 'the robot never entered %s' % room)
        self.assertTrue(state['done'], 'the robot never left %s' % room)
        self.assertGreater(state['samples'], 50)
        (ex, ey, et), (ox, oy, ot) = state['last']
        ekf_err, odo_err = math.hypot(ex, ey), math.hypot(ox, oy)
        mean_nees = sum(state['nees']) / max(1, len(state['nees']))
        line = ('| %s | %d | %.1f mm / %.2f° | %.1f mm / %.2f° | %.2f |' % (
            room, state['samples'], 1e3 * ekf_err, math.degrees(abs(et)), 1e3 * odo_err, math.degrees(abs(ot)),
            mean_nees))
        rospy.loginfo('room drive: %s', line)
        report = rospy.get_param('~report', '')
        if report:
            with open(report, 'a') as f:
                f.write(line + '\n')
        self.assertLess(ekf_err, rospy.get_param('~max_final_error', 0.05))
        self.assertLess(ekf_err, odo_err, 'the EKF is no better than odometry alone')
        self.assertLess(mean_nees, 3 * 3.0, 'robot pose covariance far too optimistic')


if __name__ == '__main__':
    rospy.init_node('test_ekf_room_drive')
    rostest.rosrun('hybrid_slam', 'ekf_room_drive', RoomDrive)
