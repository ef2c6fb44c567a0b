#!/usr/bin/python3
"""Evaluation of pomdp_topo against the simulator's ground truth (evaluation only: the mapper and
the localizer never read ground truth).

Per belief update it checks whether the most likely state is the true one: the state's display
position (interpolated between its edge's nodes) within ~tolerance m of the robot's true position
in the map frame and its heading within 45 deg of the true heading. It counts unconfident updates,
the updates near the two look-alike doors of institute, steps and metres until the first confident
and right update (global localization), and -- with ~kidnaps > 0 -- teleports the robot along its
current tour segment (odometry is not told) and counts the updates until it is confident and right
again. At the end it matches the map's nodes against the world's doors and junctions. Writes a
JSON summary to ~output (also on shutdown), and prints it.
"""
import bisect
import collections
import json
import math

import rospy
import yaml
from world_geometry import yaw_of
from geometry_msgs.msg import Pose2D
from hybrid_slam_msgs.msg import TopoEvent, TopologicalBelief, TopologicalMap, TopologicalState
from hybrid_slam_msgs.srv import Teleport
from nav_msgs.msg import Odometry
from std_msgs.msg import Bool

MODE_NAMES = {TopologicalState.FRONTIER: 'frontier', TopologicalState.LOCALIZED: 'localized',
              TopologicalState.LOOP_CHECK: 'loop_check'}
LOOK_ALIKE_DOORS = {'office_1', 'office_3'}


def wrap(a):
    return math.atan2(math.sin(a), math.cos(a))


class TopoEvaluator:
    def __init__(self):
        with open(rospy.get_param('~world_file')) as f:
            self.world = yaml.safe_load(f)
        self.output = rospy.get_param('~output', '')
        self.tolerance = rospy.get_param('~tolerance', 1.0)
        self.kidnaps = rospy.get_param('~kidnaps', 0)
        self.kidnap_interval = rospy.get_param('~kidnap_interval', 40.0)
        self.kidnap_jump = rospy.get_param('~kidnap_jump', 6.0)
        self.max_sim_time = rospy.get_param('~max_sim_time', 0.0)
        tour_file = rospy.get_param('~tour_file', '')
        self.waypoints = []
        if tour_file:
            with open(tour_file) as f:
                self.waypoints = [tuple(p) for p in yaml.safe_load(f)['waypoints']]
        sx, sy, syaw = self.world['robot']['start']
        self.start = (sx, sy, syaw)
        self.regions = self.world.get('regions', [])
        kinds = {r['name']: r['kind'] for r in self.regions}
        # Ground-truth graph nodes: openings that touch a hallway.
        self.true_nodes = []
        for d in self.world.get('doors', []):
            a, b = d['between']
            if kinds.get(a) == 'hallway' or kinds.get(b) == 'hallway':
                mx, my = self.to_map(d['center'][0], d['center'][1])
                self.true_nodes.append({'between': [a, b], 'x': mx, 'y': my,
                                        'junction': kinds.get(a) == 'hallway' and kinds.get(b) == 'hallway',
                                        'look_alike': bool(LOOK_ALIKE_DOORS & {a, b})})
        self.truth = None
        self.truth_path = 0.0
        # Beliefs wait until the ground truth at their stamp has arrived (callbacks run in separate
        # threads and ground truth comes at 50 Hz times the sim rate).
        self.truth_history = collections.deque(maxlen=5000)  # (stamp, x, y, yaw, path) in the map frame
        self.pending = collections.deque()
        self.map = None
        self.mode = ''
        self.events = []
        self.steps = {'total': 0, 'localized': 0, 'correct': 0, 'unconfident': 0,
                      'look_alike': 0, 'look_alike_correct': 0, 'look_alike_unconfident': 0,
                      'tracked': 0, 'tracked_correct': 0, 'tracked_unconfident': 0}
        self.first_right = None
        self.kidnap_log = []
        self.pending_kidnap = None
        self.segment = 0
        self.last_kidnap = None
        self.done = False
        self.trace = []  # per belief update: sim time, mode, state, true position, right, entropy
        rospy.Subscriber('ground_truth', Odometry, self.on_truth, queue_size=2000, buff_size=2 ** 24)
        rospy.Subscriber('topological_map', TopologicalMap, self.on_map, queue_size=2)
        rospy.Subscriber('topological_belief', TopologicalBelief, self.on_belief, queue_size=50)
        rospy.Subscriber('topological_state', TopologicalState, self.on_mode, queue_size=10)
        rospy.Subscriber('topo_events', TopoEvent, self.on_event, queue_size=100)
        rospy.Subscriber('tour_done', Bool, self.on_done, queue_size=1)
        rospy.on_shutdown(self.write)

    def to_map(self, x, y):
        sx, sy, syaw = self.start
        dx, dy = x - sx, y - sy
        c, s = math.cos(syaw), math.sin(syaw)
        return c * dx + s * dy, -s * dx + c * dy

    def on_truth(self, msg):
        p = msg.pose.pose.position
        yaw = yaw_of(msg.pose.pose.orientation)
        mx, my = self.to_map(p.x, p.y)
        if self.truth is not None:
            step = math.hypot(mx - self.truth[0], my - self.truth[1])
            if step < 0.5:  # a teleport is not travel
                self.truth_path += step
        self.truth = (mx, my, wrap(yaw - self.start[2]), p.x, p.y, yaw)
        stamp = msg.header.stamp.to_sec()
        self.truth_history.append((stamp, mx, my, self.truth[2], self.truth_path))
        while self.pending and self.pending[0][0].header.stamp.to_sec() <= stamp:
            belief, mode = self.pending.popleft()
            self.evaluate(belief, mode)
        self.maybe_kidnap(stamp)
        if self.max_sim_time > 0 and stamp > self.max_sim_time and not self.done:
            rospy.logerr('evaluate_topo: the tour did not end within %.0f s of sim time; giving up', self.max_sim_time)
            self.write()
            rospy.signal_shutdown('max_sim_time')

    def on_map(self, msg):
        self.map = msg

    def on_mode(self, msg):
        self.mode = MODE_NAMES.get(msg.mode, 'unknown')

    def on_event(self, msg):
        self.events.append((msg.kind, msg.text))

    def on_done(self, msg):
        if msg.data:
            self.done = True
            self.write()

    def node_pos(self, nid):
        for n in self.map.nodes:
            if n.id == nid:
                return n.pose.x, n.pose.y
        return None

    def state_position(self, msg, i):
        if msg.at_node[i]:
            return self.node_pos(msg.state_edge[i])
        for e in self.map.edges:
            if e.id == msg.state_edge[i]:
                a, b = self.node_pos(e.source), self.node_pos(e.target)
                if a is None or b is None:
                    return None
                t = min(1.0, max(0.0, msg.state_offset[i] / e.length)) if e.length > 1e-9 else 0.0
                return a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])
        return None

    def on_belief(self, msg):
        self.pending.append((msg, self.mode))

    def truth_at(self, stamp):
        stamps = [h[0] for h in self.truth_history]
        i = bisect.bisect_left(stamps, stamp)
        if i >= len(stamps):
            i = len(stamps) - 1
        if i > 0 and abs(stamps[i - 1] - stamp) < abs(stamps[i] - stamp):
            i -= 1
        return self.truth_history[i]

    def evaluate(self, msg, mode):
        if self.map is None or not self.truth_history or msg.most_likely < 0:
            return
        _, tx, ty, tyaw, path = self.truth_at(msg.header.stamp.to_sec())
        self.steps['total'] += 1
        if mode != 'localized':
            self.trace.append((msg.header.stamp.to_sec(), mode, -1, 0, 0.0, '', '', '', tx, ty, tyaw, 0, msg.entropy,
                               int(msg.confident)))
            return
        s = self.steps
        s['localized'] += 1
        i = msg.most_likely
        pos = self.state_position(msg, i)
        right = pos is not None and math.hypot(pos[0] - tx, pos[1] - ty) <= self.tolerance and \
            abs(wrap(msg.state_heading[i] - tyaw)) < math.pi / 4
        s['correct'] += int(right)
        self.trace.append((msg.header.stamp.to_sec(), mode, msg.state_edge[i], int(msg.at_node[i]),
                           msg.state_offset[i], pos[0] if pos else '', pos[1] if pos else '', msg.state_heading[i],
                           tx, ty, tyaw, int(right), msg.entropy, int(msg.confident)))
        s['unconfident'] += int(not msg.confident)
        near_twin = any(n['look_alike'] and math.hypot(n['x'] - tx, n['y'] - ty) < 1.5 for n in self.true_nodes)
        if near_twin:
            s['look_alike'] += 1
            s['look_alike_correct'] += int(right)
            s['look_alike_unconfident'] += int(not msg.confident)
        if self.first_right is not None:  # tracking, after global localization
            s['tracked'] += 1
            s['tracked_correct'] += int(right)
            s['tracked_unconfident'] += int(not msg.confident)
        if self.first_right is None and right and msg.confident:
            self.first_right = {'steps': s['localized'], 'metres': round(path, 2)}
        if self.pending_kidnap is not None and msg.header.stamp.to_sec() > self.pending_kidnap['stamp']:
            k = self.pending_kidnap
            k['steps'] += 1
            if right and msg.confident:
                k['recovered_steps'] = k['steps']
                k['recovered_metres'] = round(path - k['path0'], 2)
                self.kidnap_log.append(k)
                self.pending_kidnap = None

    def maybe_kidnap(self, now):
        """Teleport the robot along its current tour segment (it keeps driving to the same waypoint)."""
        if len(self.kidnap_log) + (self.pending_kidnap is not None) >= self.kidnaps or not self.waypoints:
            return
        if self.mode != 'localized' or self.pending_kidnap is not None:
            return
        if self.last_kidnap is not None and now - self.last_kidnap < self.kidnap_interval:
            return
        if self.last_kidnap is None:
            self.last_kidnap = now
            return
        # The segment the robot is on: the nearest tour segment to its true position.
        wx, wy = self.truth[3], self.truth[4]
        pts = [tuple(self.world['robot']['start'][:2])] + self.waypoints
        best = None
        for k in range(len(pts) - 1):
            (ax, ay), (bx, by) = pts[k], pts[k + 1]
            L = math.hypot(bx - ax, by - ay)
            if L < 1e-6:
                continue
            t = max(0.0, min(1.0, ((wx - ax) * (bx - ax) + (wy - ay) * (by - ay)) / (L * L)))
            d = math.hypot(ax + t * (bx - ax) - wx, ay + t * (by - ay) - wy)
            if best is None or d < best[0]:
                best = (d, k, t, L)
        if best is None or best[0] > 0.3:
            return
        _, k, t, L = best
        (ax, ay), (bx, by) = pts[k], pts[k + 1]
        # Only while driving along the segment, away from its ends (not while turning at a corner).
        if abs(wrap(self.truth[5] - math.atan2(by - ay, bx - ax))) > 0.2 or t * L < 1.0 or (1 - t) * L < 1.0:
            return
        remaining = (1 - t) * L
        if remaining < self.kidnap_jump + 1.0 and t * L < self.kidnap_jump + 1.0:
            return  # segment too short to jump along
        # Jump back along the segment when possible (the robot drives the stretch again), else ahead.
        jump = -self.kidnap_jump if t * L >= self.kidnap_jump + 1.0 else self.kidnap_jump
        nt = t + jump / L
        pose = Pose2D(ax + nt * (bx - ax), ay + nt * (by - ay), self.truth[5])
        try:
            rospy.wait_for_service('bullet_sim/teleport', 2.0)
            r = rospy.ServiceProxy('bullet_sim/teleport', Teleport)(pose)
        except (rospy.ServiceException, rospy.ROSException) as e:
            rospy.logwarn('evaluate_topo: teleport failed: %s', e)
            return
        if not r.success:
            rospy.logwarn('evaluate_topo: teleport refused: %s', r.message)
            return
        self.last_kidnap = now
        self.pending_kidnap = {'at': [round(pose.x, 2), round(pose.y, 2)], 'jump_m': jump, 'steps': 0,
                               'path0': self.truth_path, 'stamp': now}
        rospy.loginfo('evaluate_topo: kidnapped the robot by %.1f m to (%.2f, %.2f)', jump, pose.x, pose.y)

    def node_match(self):
        if self.map is None:
            return {}
        nodes = [n for n in self.map.nodes if n.type in (0, 1)]  # doors and junctions
        # A node stands for as many world openings as it has openings (two doors face to face at
        # one spot are one node with two openings).
        capacity = {n.id: max(1, len(n.openings)) for n in nodes}
        used = collections.Counter()
        found = 0
        missed = []
        for t in sorted(self.true_nodes, key=lambda t: min([math.hypot(n.pose.x - t['x'], n.pose.y - t['y'])
                                                             for n in nodes] or [1e9])):
            best = None
            for n in nodes:
                d = math.hypot(n.pose.x - t['x'], n.pose.y - t['y'])
                if used[n.id] < capacity[n.id] and d <= 1.5 and (best is None or d < best[0]):
                    best = (d, n.id)
            if best is None:
                missed.append(t['between'])
            else:
                used[best[1]] += 1
                found += 1
        spurious = [n.id for n in nodes if used[n.id] == 0]
        return {'true_nodes': len(self.true_nodes), 'found': found, 'missed': missed,
                'spurious_nodes': spurious, 'map_nodes': len(self.map.nodes), 'map_edges': len(self.map.edges),
                'node_types': {str(k): sum(1 for n in self.map.nodes if n.type == k) for k in range(5)}}

    def summary(self):
        s = self.steps
        loc = max(1, s['localized'])
        out = {'world': self.world['name'], 'belief_updates': s['total'], 'localized_updates': s['localized'],
               'correct_rate': round(s['correct'] / loc, 4), 'unconfident_rate': round(s['unconfident'] / loc, 4),
               'tracking_correct_rate': round(s['tracked_correct'] / max(1, s['tracked']), 4),
               'tracking_unconfident_rate': round(s['tracked_unconfident'] / max(1, s['tracked']), 4),
               'look_alike_updates': s['look_alike'],
               'look_alike_correct_rate': round(s['look_alike_correct'] / max(1, s['look_alike']), 4),
               'look_alike_unconfident_rate': round(s['look_alike_unconfident'] / max(1, s['look_alike']), 4),
               'first_confident_and_right': self.first_right, 'travel_m': round(self.truth_path, 1),
               'kidnaps': [{k: v for k, v in x.items() if k not in ('path0', 'stamp')} for x in self.kidnap_log],
               'kidnap_unrecovered': self.pending_kidnap is not None,
               'loops_closed': [t for k, t in self.events if k == TopoEvent.LOOP_CLOSED],
               'loops_rejected': [t for k, t in self.events if k == TopoEvent.LOOP_REJECTED],
               'tour_done': self.done}
        out.update(self.node_match())
        return out

    def write(self):
        out = self.summary()
        if self.output:
            with open(self.output, 'w') as f:
                json.dump(out, f, indent=1)
            with open(self.output + '.csv', 'w') as f:
                f.write('t,mode,state_id,at_node,offset,state_x,state_y,state_heading,true_x,true_y,true_heading,'
                        'right,entropy,confident\n')
                for row in self.trace:
                    f.write(','.join(str(round(v, 3)) if isinstance(v, float) else str(v) for v in row) + '\n')
        rospy.loginfo('evaluate_topo: %s', json.dumps(out))


if __name__ == '__main__':
    rospy.init_node('evaluate_topo')
    TopoEvaluator()
    rospy.spin()
