#!/usr/bin/python3
"""rostest: a script's actions at lockstep steps (lockstep.ScriptClock). wait_until returns at the
first step at which its condition holds; the step is acknowledged only once the script waits again,
and its acknowledgement announces what the script published within it (Participant.published), so a
downstream participant has it at that step. Without lockstep the same code polls on sim time."""
import threading
import time
import unittest

import rospy
import rostest
from hybrid_slam_msgs.msg import LockstepAck, LockstepStep

from waiting import wait_for
from lockstep import Participant, ScriptClock


class ScriptAtSteps(unittest.TestCase):
    def test_the_script_acts_within_the_step_its_condition_holds_at(self):
        acks = []
        lock = threading.Lock()

        def on_ack(msg):
            with lock:
                acks.append((msg.stamp.to_nsec(), dict(zip(msg.topics, msg.counts))))

        rospy.Subscriber(rospy.get_name() + '/lockstep_ack', LockstepAck, on_ack, queue_size=None)
        steps = rospy.Publisher('lockstep/step', LockstepStep, queue_size=10)
        participant = Participant()
        self.assertTrue(participant.enabled)
        clock = ScriptClock(participant)
        wait_for(self, lambda: steps.get_num_connections() > 0, 'the participant subscribing to lockstep/step')
        wait_for(self, lambda: participant._ack_pub.get_num_connections() > 0, 'the test subscribing to the acknowledgements')

        def step(nsec, start=False):
            s = LockstepStep(start=start)
            s.stamp = rospy.Time(0, nsec)
            steps.publish(s)

        step(1, start=True)
        wait_for(self, lambda: acks, 'the start step acknowledged')
        acted = []

        def script():
            stamp = clock.wait_until(lambda s: s.to_nsec() >= 30)
            acted.append(stamp.to_nsec())
            time.sleep(0.5)  # a slow action: the step's acknowledgement waits for it
            participant.published('goal')
            participant.published('goal')
            clock.wait_until(lambda s: s.to_nsec() >= 50)
            acted.append('second')
            clock.finish()

        worker = threading.Thread(target=script)
        worker.start()
        time.sleep(0.3)  # the script is waiting
        for nsec in (10, 20, 30):
            step(nsec)
        wait_for(self, lambda: len(acks) >= 4, 'the acknowledgement of step 30')
        with lock:
            self.assertEqual([a[0] for a in acks], [1, 10, 20, 30])
            self.assertEqual(acks[2][1], {}, 'nothing published before the script acted')
            self.assertEqual(acks[3][1], {rospy.resolve_name('goal'): 2}, 'the step announces the script\'s goals')
        self.assertEqual(acted, [30])
        for nsec in (40, 50, 60):
            step(nsec)
        wait_for(self, lambda: len(acks) >= 7, 'the later steps acknowledged')
        worker.join(5.0)
        self.assertFalse(worker.is_alive())
        self.assertEqual(acted, [30, 'second'])
        with lock:
            self.assertEqual([a[0] for a in acks], [1, 10, 20, 30, 40, 50, 60])
            self.assertEqual(acks[-1][1], {rospy.resolve_name('goal'): 2}, 'counts are cumulative')


if __name__ == '__main__':
    rospy.init_node('script_clock_test')
    rostest.rosrun('lockstep', 'script_clock', ScriptAtSteps)
