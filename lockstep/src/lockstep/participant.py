"""A rospy node's side of the simulator's lockstep: the same protocol as lockstep::Participant
(lockstep/include/lockstep/participant.h), for scripts that act on the simulation (tests).

With the parameter lockstep/enabled false or absent nothing here waits. With it true, the node
counts what it receives on the topics it subscribes to through subscribe(), and at each step of the
simulator, once it has received as many messages as the step announced and as its upstream
participants announced when they acknowledged the step, it calls its step hook (from one thread at
a time) and acknowledges on <node>/lockstep_ack. rospy runs each subscription's callback on a thread
of its own: a lock orders them, and counting, not arrival order, decides when a step runs.
"""
import collections
import threading

import rospy
from hybrid_slam_msgs.msg import LockstepAck, LockstepStep


def _counts(msg):
    return dict(zip(msg.topics, msg.counts))


class Participant(object):
    def __init__(self, upstream=(), observer=False):
        """observer: acknowledge the simulator's start steps only, once connected, never a later step
        (a node the launch names in lockstep/observers: the first step waits for it, none after)."""
        self.enabled = bool(rospy.get_param('lockstep/enabled', False))
        self._observer = observer
        self.lock = threading.RLock()  # held by every callback of a counted subscription and the hook
        self._received = collections.Counter()
        self._watched = collections.Counter()  # subscriptions per topic: each receives every message
        self._steps = collections.deque()
        self._last_step = -1
        self._upstream = [rospy.resolve_name(n) for n in upstream]
        self._acks = {}
        self._hook = None
        self._wake = rospy.Time()
        self._joined = False
        self._subscribers = []
        self._published = collections.OrderedDict()  # resolved topic -> messages published so far
        self._published_lock = threading.Lock()
        if not self.enabled:
            return
        self._ack_pub = rospy.Publisher(rospy.get_name() + '/lockstep_ack', LockstepAck, queue_size=100)
        self._shutting_down = False  # set by the first shutdown hook: no acknowledgement after it
        rospy.on_shutdown(self._on_shutdown)
        rospy.Subscriber('lockstep/step', LockstepStep, self._on_step, queue_size=100, tcp_nodelay=True)
        for node in self._upstream:
            rospy.Subscriber(node + '/lockstep_ack', LockstepAck, self._on_ack, queue_size=100, tcp_nodelay=True)
        rospy.loginfo('%s: lockstep with the simulator', rospy.get_name())

    def subscribe(self, topic, msg_type, callback, queue_size=100):
        """A counted subscription; the callback runs on arrival, under the participant's lock. In
        lockstep its queue never drops (a dropped message would hold its step until the timeout);
        otherwise it holds `queue_size` messages."""
        resolved = rospy.resolve_name(topic)
        self._watched[resolved] += 1

        def counted(msg):
            with self.lock:
                callback(msg)
                self._received[resolved] += 1
                self._advance()

        sub = rospy.Subscriber(topic, msg_type, counted, queue_size=None if self.enabled else queue_size,
                               tcp_nodelay=True)
        self._subscribers.append(sub)
        return sub

    def published(self, topic, n=1):
        """Counts `n` messages this node has published on `topic` (through a publisher it does not
        own, such as an action client's goal): its next acknowledgement announces them, and a
        downstream participant that counts the topic waits for them before that step."""
        resolved = rospy.resolve_name(topic)
        with self._published_lock:  # not self.lock: a script may publish within a step whose hook holds that
            self._published[resolved] = self._published.get(resolved, 0) + n

    def on_step(self, hook):
        """hook(stamp) runs at every step; it returns the next sim time it needs a step at, or None."""
        self._hook = hook

    def _on_step(self, msg):
        with self.lock:
            announced = _counts(msg)
            stamp = msg.stamp.to_nsec()
            if stamp <= self._last_step:
                return
            if msg.start or not self._joined:
                if any(s.resolved_name in announced and s.get_num_connections() == 0 for s in self._subscribers):
                    return  # not connected yet: the simulator asks again
                self._joined = True
                for topic, n in announced.items():  # what came before counts as received
                    if topic in self._watched:
                        self._received[topic] = max(self._received[topic], n * self._watched[topic])
            self._last_step = stamp
            if self._observer:
                if msg.start:  # connected: the run may start; no later step waits for an observer
                    self._publish_ack(LockstepAck(node=rospy.get_name(), stamp=msg.stamp))
                return
            self._steps.append((stamp, announced, msg.stamp, msg.start))
            self._advance()

    def _on_ack(self, msg):
        with self.lock:
            old = self._acks.get(msg.node)
            if old is None or msg.stamp.to_nsec() >= old[0]:
                self._acks[msg.node] = (msg.stamp.to_nsec(), _counts(msg))
            self._advance()

    def _on_shutdown(self):
        self._shutting_down = True

    def _publish_ack(self, ack):
        """Publishes an acknowledgement; False once the node is shutting down. A step's callback can
        run after rospy closed the publisher, even while the interpreter tears the process down
        (when rospy's own is_shutdown() no longer answers): no step follows a shutdown."""
        try:
            self._ack_pub.publish(ack)
            return True
        except rospy.ROSException:
            if self._shutting_down:
                return False
            raise

    def _covers(self, announced):
        return all(self._received[t] >= n * self._watched[t] for t, n in announced.items() if t in self._watched)

    def _ready(self, stamp, announced):
        if not self._covers(announced):
            return False
        for node in self._upstream:
            ack = self._acks.get(node)
            if ack is None or ack[0] < stamp or not self._covers(ack[1]):
                return False
        return True

    def _advance(self):
        with self.lock:
            while self._steps and self._ready(self._steps[0][0], self._steps[0][1]):
                _, _, stamp, start = self._steps.popleft()
                if self._hook is not None and not start:  # a start step carries no data yet
                    wake = self._hook(stamp)
                    self._wake = wake if wake is not None else rospy.Time()
                with self._published_lock:
                    topics, counts = list(self._published), list(self._published.values())
                ack = LockstepAck(node=rospy.get_name(), stamp=stamp, topics=topics, counts=counts)
                ack.wake = self._wake if self._wake > stamp else rospy.Time()
                if not self._publish_ack(ack):
                    return
