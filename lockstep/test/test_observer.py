#!/usr/bin/python3
"""rostest: an observer of the lockstep (lockstep.Participant(observer=True)) holds the simulator's
start until it is connected, and then no step: it acknowledges a start step only once its counted
subscription has a publisher, and never a later step."""
import threading
import time
import unittest

import rospy
import rostest
from hybrid_slam_msgs.msg import LockstepAck, LockstepStep
from std_msgs.msg import String

from waiting import wait_for
from lockstep import Participant


class Observer(unittest.TestCase):
    def test_acknowledges_start_steps_once_connected_and_no_later_step(self):
        acks = []
        lock = threading.Lock()

        def on_ack(msg):
            with lock:
                acks.append((msg.stamp.to_nsec(), msg.node))

        rospy.Subscriber(rospy.get_name() + '/lockstep_ack', LockstepAck, on_ack, queue_size=None)
        steps = rospy.Publisher('lockstep/step', LockstepStep, queue_size=10)
        observer = Participant(observer=True)
        self.assertTrue(observer.enabled)
        observer.subscribe('observed', String, lambda msg: None)
        wait_for(self, lambda: steps.get_num_connections() > 0, 'the observer subscribing to lockstep/step')

        def step(nsec, start):
            s = LockstepStep(start=start, topics=[rospy.resolve_name('observed')], counts=[0])
            s.stamp = rospy.Time(0, nsec)
            steps.publish(s)

        # Not connected (no publisher of its counted topic): the start waits.
        step(1, True)
        time.sleep(1.0)
        with lock:
            self.assertEqual(acks, [])
        publisher = rospy.Publisher('observed', String, queue_size=1)
        wait_for(self, lambda: publisher.get_num_connections() > 0, 'the observer connecting to "observed"')
        step(2, True)
        wait_for(self, lambda: acks, 'an acknowledgement of the start step')
        # A step of the run: never acknowledged.
        step(3, False)
        time.sleep(1.0)
        with lock:
            self.assertEqual([a[0] for a in acks], [2])
            self.assertEqual(acks[0][1], rospy.get_name())


if __name__ == '__main__':
    rospy.init_node('observer_test')
    rostest.rosrun('lockstep', 'observer', Observer)
