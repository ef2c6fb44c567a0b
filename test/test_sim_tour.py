#!/usr/bin/python3
"""rostest: the scripted tour of a world ends, without a bump, having entered every room."""
import unittest

import rospy
import rostest
import yaml
from nav_msgs.msg import Odometry
from std_msgs.msg import Bool


def inside(polygon, x, y):
    result = False
    j = len(polygon) - 1
    for i in range(len(polygon)):
        (xi, yi), (xj, yj) = polygon[i], polygon[j]
        if (yi > y) != (yj > y) and x < (xj - xi) * (y - yi) / (yj - yi) + xi:
            result = not result
        j = i
    return result


class SimTour(unittest.TestCase):
    def test_tour_visits_every_room_without_bumping(self):
        with open(rospy.get_param('~world_file')) as f:
            world = yaml.safe_load(f)
        regions = world['regions']
        visited = set()
        state = {'done': False, 'bumps': 0, 'truth': 0}

        def on_truth(msg):
            state['truth'] += 1
            p = msg.pose.pose.position
            for r in regions:
                if inside(r['polygon'], p.x, p.y):
                    visited.add(r['name'])

        def on_bumper(msg):
            state['bumps'] += int(msg.data)

        def on_done(msg):
            state['done'] = state['done'] or msg.data

        rospy.Subscriber('ground_truth', Odometry, on_truth)
        rospy.Subscriber('bumper', Bool, on_bumper)
        rospy.Subscriber('tour_done', Bool, on_done)
        limit = rospy.get_param('~max_sim_time', 1200.0)
        wall = rospy.Rate(20)
        while not rospy.is_shutdown() and not state['done']:
            if rospy.get_time() > limit:
                break
            try:
                wall.sleep()
            except rospy.ROSTimeMovedBackwardsException:
                pass
        self.assertTrue(state['done'], 'tour not finished after %.0f s of sim time' % rospy.get_time())
        self.assertGreater(state['truth'], 100)
        self.assertEqual(state['bumps'], 0, 'the robot bumped into something on the tour')
        rooms = {r['name'] for r in regions if r['kind'] == 'room'}
        self.assertEqual(rooms - visited, set(), 'rooms never entered')


if __name__ == '__main__':
    rospy.init_node('test_sim_tour')
    rostest.rosrun('hybrid_slam', 'sim_tour', SimTour)
