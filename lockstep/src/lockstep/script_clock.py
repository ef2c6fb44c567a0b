"""A script's sequential code run at the simulator's lockstep steps (see participant.py).

A script that acts on the simulation (sends goals, reads the ground truth after them) is written as
a sequence: do this, wait until that holds, do the next thing. In lockstep each of its actions must
happen at a step that does not depend on the machine's load. ScriptClock.wait_until(condition)
returns at the first step, after the call, at which condition(stamp) holds — judged inside the
participant's step hook, so on exactly the messages the step announced — and the code that follows
runs within that step: the hook waits for the script's next wait_until() (or finish()) before it
acknowledges, so the simulator waits too. Without lockstep it polls on sim time instead.
"""
import threading

import rospy


class ScriptClock(object):
    def __init__(self, participant, poll=0.05):
        """participant: the node's lockstep.Participant (the clock takes its step hook); poll (s, sim):
        how often a condition is tried without lockstep."""
        self._participant = participant
        self._poll = poll
        self._cond = threading.Condition()
        self._waiting_for = None  # the script's condition, while it waits
        self._script_runs = False  # the script runs within the step at self._stamp
        self._stamp = None
        self._finished = False
        if participant.enabled:
            participant.on_step(self._on_step)

    @property
    def stamp(self):
        """The step the script runs in (the last one wait_until returned)."""
        return self._stamp

    def wait_until(self, condition):
        """Blocks until a step at which condition(stamp) holds; returns that step's stamp (rospy.Time)."""
        if not self._participant.enabled:
            while not rospy.is_shutdown():
                now = rospy.Time.now()
                if condition(now):
                    self._stamp = now
                    return now
                rospy.sleep(self._poll)
            raise rospy.ROSInterruptException('shut down while waiting')
        with self._cond:
            self._waiting_for = condition
            self._script_runs = False
            self._cond.notify_all()
            while not self._script_runs:
                if rospy.is_shutdown():
                    raise rospy.ROSInterruptException('shut down while waiting')
                self._cond.wait(0.5)
            return self._stamp

    def finish(self):
        """The script has done its last action: steps go on without it."""
        with self._cond:
            self._finished = True
            self._waiting_for = None
            self._script_runs = False
            self._cond.notify_all()

    def _on_step(self, stamp):
        with self._cond:
            if self._finished or self._waiting_for is None or not self._waiting_for(stamp):
                return None
            self._waiting_for = None
            self._stamp = stamp
            self._script_runs = True
            self._cond.notify_all()
            # The step is the script's until it waits again or finishes.
            while self._script_runs and not self._finished and not rospy.is_shutdown():
                self._cond.wait(0.5)
        return None
