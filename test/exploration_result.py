"""The evaluation JSON that scripts/evaluate_exploration.py writes at the end of an exploration, as
the exploration rostests read it."""
import json
import os
import time


def read_result(path):
    """The evaluation at `path`, or None while it is not (completely) written."""
    if not os.path.exists(path):
        return None
    time.sleep(0.5)  # written once, at the end: let the writer finish
    with open(path) as f:
        try:
            return json.load(f)
        except ValueError:
            return None


class GroundTruthGuard:
    """Watches a running launch for ground truth on the stack's side: who publishes map -> odom on
    /tf (from each message's connection header) and who subscribes to ground_truth (the master's
    system state). Only the evaluation's scripts and the test itself may read ground truth."""
    EVALUATION = ('/evaluate_exploration', '/run_missions')

    def __init__(self):
        import rospy
        from tf2_msgs.msg import TFMessage
        self.map_to_odom = set()
        self._sub = rospy.Subscriber('/tf', TFMessage, self._on_tf, queue_size=200)

    def _on_tf(self, msg):
        for t in msg.transforms:
            if t.header.frame_id.lstrip('/') == 'map' and t.child_frame_id.lstrip('/') == 'odom':
                self.map_to_odom.add(msg._connection_header['callerid'])

    def ground_truth_readers(self):
        """The nodes subscribed to ground_truth, other than the evaluation's and this test's."""
        import rosgraph
        import rospy
        _, subscribers, _ = rosgraph.Master(rospy.get_name()).getSystemState()
        allowed = set(self.EVALUATION) | {rospy.get_name()}
        return sorted(n for topic, nodes in subscribers if topic == '/ground_truth' for n in nodes if n not in allowed)
