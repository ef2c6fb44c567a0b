#!/usr/bin/python3
"""rostest: a participant whose node is shutting down acknowledges no step and raises nothing. A step
the simulator published just before the node's shutdown can reach the callback after rospy has
closed the acknowledgement's publisher (scripts/evaluate's missions client ended every run with a
"publish() to a closed topic" traceback)."""
import unittest

import rospy
import rospy.topics
import rostest

from lockstep import Participant


class ParticipantShutdown(unittest.TestCase):
    def test_a_step_after_shutdown_is_dropped_quietly(self):
        participant = Participant()
        self.assertTrue(participant.enabled)
        # A step that is ready (nothing announced, no upstream) arrives as the node shuts down.
        stamp = rospy.Time(0, 5)
        participant._steps.append((stamp, {}, stamp, False))
        rospy.signal_shutdown('the test ends the node')
        # As the interpreter tears the process down after sys.exit, rospy's own check of the shutdown
        # (which would drop the message) no longer answers: emulated here.
        rospy.topics.is_shutdown = lambda: False
        participant._advance()  # raised ROSException("publish() to a closed topic") before
        self.assertFalse(participant._steps)


if __name__ == '__main__':
    rospy.init_node('participant_shutdown_test')
    rostest.rosrun('lockstep', 'participant_shutdown', ParticipantShutdown)
