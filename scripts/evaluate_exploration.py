#!/usr/bin/python3
"""Evaluates an exploration (explore.launch) against the world file's ground truth.

Ground truth is read here only (never by the stack): the rooms and doors of the world file, the
simulator's ground_truth odometry. While the coordinator is METRIC in place k, the regions the robot
is in say which room place k maps; the topological map's door nodes are matched to the world's
doors (display poses in the start frame, within 1.5 m along the door's wall and 2 m across).
Doors closed in the world file or by ~closed_doors (the simulator's parameter) are walls: the
rooms they cut off from the start are reported as unreachable and not counted as missed. At the end (status DONE, or shutdown) it
writes a JSON file: rooms mapped / missed / mapped twice, doors found / missed, spurious door
nodes, travel, times, map file sizes and bytes per square metre of floor; <output>.map.json holds
the topological map's nodes and edges at their display poses (for pictures). Next to it,
<output>.trace.csv holds where the robot truly was (region and pose) at each change of the
coordinator's state and every 5 s of sim time, written as it goes: what went wrong where.
It also compares, once a second of sim time, the stack's own pose of the robot in `map` (tf map ->
base_link, which ekf_local_map publishes) with the true pose in the start frame: map_pose_error_m;
odom_pose_error_m is the same for odometry alone (odom -> base_link), dead reckoning's drift.
"""
import collections
import json
import math
import os
import threading

import rospy
import tf2_ros
import yaml
from hybrid_slam_msgs.msg import ExplorationStatus, TopologicalMap
from lockstep import Participant
from nav_msgs.msg import Odometry
from world_geometry import inside, yaw_of

METRIC, DONE = 1, 3


def area(polygon):
    return 0.5 * abs(sum(polygon[i][0] * polygon[(i + 1) % len(polygon)][1] -
                         polygon[(i + 1) % len(polygon)][0] * polygon[i][1] for i in range(len(polygon))))


# A node finds a door when it lies within DOOR_ALONG of the door's centre along the door's wall and
# within DOOR_ACROSS of it across (a node on the mid-line of a 2.2 m hallway is 1.1 m across; two
# doors facing each other, or beside a junction, are openings of one node, which may lie a door's
# width along from the second one).
DOOR_ALONG, DOOR_ACROSS, DOOR_BEARING = 1.5, 2.0, 0.6  # m, m, rad


def door_opening(x, y, into, nodes, used=()):
    """The (node id, opening index) that finds the door at (x, y) whose room lies at heading `into`
    (map frame): an opening, not in `used`, whose bearing points into the room, on the nearest node
    within the door gate; None if there is none. Each opening counts for one door."""
    best = None
    for n in nodes:
        dx, dy = n.pose.x - x, n.pose.y - y
        across = abs(dx * math.cos(into) + dy * math.sin(into))
        along = abs(-dx * math.sin(into) + dy * math.cos(into))
        if along > DOOR_ALONG or across > DOOR_ACROSS:
            continue
        dist = math.hypot(dx, dy)
        for k, o in enumerate(n.openings):
            off = abs(math.atan2(math.sin(o.bearing - into), math.cos(o.bearing - into)))
            if (n.id, k) not in used and off < DOOR_BEARING and (best is None or dist < best[0]):
                best = (dist, (n.id, k))
    return best[1] if best else None


def into_polygon(polygon, c):
    """Heading from the point c on (or next to) the polygon's boundary into the polygon: the normal
    of the nearest edge, turned to the side where a point 0.3 m away lies inside."""
    best = None
    for i in range(len(polygon)):
        (x1, y1), (x2, y2) = polygon[i], polygon[(i + 1) % len(polygon)]
        dx, dy = x2 - x1, y2 - y1
        L2 = dx * dx + dy * dy
        if L2 <= 0.0:
            continue
        t = max(0.0, min(1.0, ((c[0] - x1) * dx + (c[1] - y1) * dy) / L2))
        d = math.hypot(x1 + t * dx - c[0], y1 + t * dy - c[1])
        if best is None or d < best[0]:
            best = (d, math.atan2(dy, dx))
    if best is None:
        return 0.0
    for heading in (best[1] + 0.5 * math.pi, best[1] - 0.5 * math.pi):
        if inside(polygon, c[0] + 0.3 * math.cos(heading), c[1] + 0.3 * math.sin(heading)):
            return math.atan2(math.sin(heading), math.cos(heading))
    return 0.0


class ExplorationEvaluator:
    def __init__(self):
        with open(rospy.get_param('~world_file')) as f:
            self.world = yaml.safe_load(f)
        self.output = rospy.get_param('~output', '')
        self.map_file = rospy.get_param('~map_file', '')
        self.regions = self.world.get('regions', [])
        self.kinds = {r['name']: r['kind'] for r in self.regions}
        self.start = self.world['robot']['start']
        self.doors = self.world.get('doors', [])
        # The simulator's ~closed_doors syntax: 'a/b' (either order) or a region name, spaces ignored.
        closing = [c.replace(' ', '') for c in rospy.get_param('~closed_doors', '').split(',') if c.strip()]
        self.open_doors = [d for d in self.doors if not d.get('closed', False) and not any(
            (set(c.split('/')) == set(d['between']) if '/' in c else c in d['between']) for c in closing)]
        self.reachable = self.reachable_regions()
        self.truth = None
        self.travel = 0.0
        self.place_regions = collections.defaultdict(collections.Counter)
        self.metric_places = set()  # every place the robot was METRIC in
        self.status = None
        self.map = None
        self.t0 = None
        self.written = False
        self.trace = None
        self.last_trace = (-1e9, None)  # (stamp, state text)
        self.trace_lock = threading.Lock()  # ground truth and status come in separate threads
        if self.output:
            self.trace = open(self.output + '.trace.csv', 'w', buffering=1)  # line-buffered: nothing lost on a crash
            self.trace.write('t,true_x,true_y,true_yaw,region,mode,place,node,state\n')
        self.pose_errors = {'map': [], 'odom': []}  # (m) map -> base_link, odom -> base_link against the truth, once a second
        self.last_pose_check = -1e9
        self.tf_buffer = tf2_ros.Buffer(cache_time=rospy.Duration(30.0))
        self.tf_listener = tf2_ros.TransformListener(self.tf_buffer)
        # An observer of the lockstep (explore.launch names it): the simulator's first step waits until
        # these are connected, so the trace starts with the run however long this node takes to start;
        # no later step waits for it.
        self.lockstep = Participant(observer=True)
        self.lockstep.subscribe('ground_truth', Odometry, self.on_truth, queue_size=200)
        self.lockstep.subscribe('exploration_status', ExplorationStatus, self.on_status, queue_size=50)
        self.lockstep.subscribe('topological_map', TopologicalMap, self.on_map, queue_size=2)
        rospy.on_shutdown(self.write)

    def reachable_regions(self):
        """Regions the robot can reach from its start through open doors."""
        first = self.region_at(self.start[0], self.start[1])
        seen, todo = {first}, [first]
        while todo:
            here = todo.pop()
            for d in self.open_doors:
                if here in d['between']:
                    for r in d['between']:
                        if r not in seen:
                            seen.add(r)
                            todo.append(r)
        return seen

    def into_room(self, door):
        """World heading from a hallway door's centre into its room: the normal of the room's
        polygon edge the door lies on, on the room's side (walls at any angle)."""
        room = next(r for r in self.regions if r['name'] in door['between'] and self.kinds[r['name']] == 'room')
        return into_polygon(room['polygon'], door['center'])

    def region_at(self, x, y):
        for r in self.regions:
            if inside(r['polygon'], x, y):
                return r['name']
        return None

    def on_truth(self, msg):
        p = msg.pose.pose.position
        if self.truth is not None:
            step = math.hypot(p.x - self.truth[0], p.y - self.truth[1])
            if step < 0.5:
                self.travel += step
        self.truth = (p.x, p.y)
        self.truth_yaw = yaw_of(msg.pose.pose.orientation)
        self.trace_row(msg.header.stamp.to_sec())
        self.check_map_pose(msg.header.stamp, p.x, p.y)
        if self.t0 is None:
            self.t0 = msg.header.stamp.to_sec()
        if self.status is not None and self.status.mode == METRIC and self.status.current_place >= 0:
            self.metric_places.add(self.status.current_place)
            r = self.region_at(p.x, p.y)
            if r is not None and self.kinds[r] == 'room':
                self.place_regions[self.status.current_place][r] += 1

    def check_map_pose(self, stamp, x, y):
        if stamp.to_sec() - self.last_pose_check < 1.0:
            return
        try:
            poses = {f: self.tf_buffer.lookup_transform(f, 'base_link', stamp).transform.translation for f in ('map', 'odom')}
        except (tf2_ros.LookupException, tf2_ros.ConnectivityException, tf2_ros.ExtrapolationException):
            return  # not yet published for this stamp: the next second's check
        self.last_pose_check = stamp.to_sec()
        mx, my = self.to_map(x, y)
        for f, t in poses.items():
            self.pose_errors[f].append(math.hypot(t.x - mx, t.y - my))

    def on_status(self, msg):
        self.status = msg
        self.trace_row(msg.header.stamp.to_sec())
        if msg.mode == DONE and not self.written:
            rospy.sleep(1.0)  # the final map messages
            self.write()

    def on_map(self, msg):
        self.map = msg

    def trace_row(self, stamp):
        if self.trace is None or self.truth is None or self.status is None:
            return
        with self.trace_lock:
            last_stamp, last_state = self.last_trace
            if self.status.state == last_state and stamp - last_stamp < 5.0:
                return
            self.last_trace = (stamp, self.status.state)
            x, y = self.truth
            self.trace.write('%.2f,%.2f,%.2f,%.3f,%s,%d,%d,%d,"%s"\n' % (
                stamp, x, y, self.truth_yaw, self.region_at(x, y) or '', self.status.mode,
                self.status.current_place, self.status.current_node, self.status.state.replace('"', "'")))

    def to_map(self, x, y):
        sx, sy, syaw = self.start
        dx, dy = x - sx, y - sy
        c, s = math.cos(syaw), math.sin(syaw)
        return c * dx + s * dy, -s * dx + c * dy

    def summary(self):
        rooms = sorted(r['name'] for r in self.regions if r['kind'] == 'room' and r['name'] in self.reachable)
        unreachable = sorted(r['name'] for r in self.regions if r['kind'] == 'room' and r['name'] not in self.reachable)
        place_room = {k: c.most_common(1)[0][0] for k, c in self.place_regions.items() if c}
        per_room = collections.Counter(place_room.values())
        # Doors between a room and a hallway: the ones a hallway exploration can find.
        doors = [d for d in self.open_doors if d['between'][0] in self.reachable and
                 sorted(self.kinds.get(b) for b in d['between']) == ['hallway', 'room']]
        nodes = list(self.map.nodes) if self.map else []
        door_nodes = [n for n in nodes if n.type == 0]
        found, missed, used = 0, [], set()
        for d in doors:
            mx, my = self.to_map(*d['center'])
            match = door_opening(mx, my, self.into_room(d) - self.start[2], nodes, used)
            if match is None:
                missed.append(d['between'])
            else:
                used.add(match)
                found += 1
        floor = sum(area(r['polygon']) for r in self.regions)
        sizes = {}
        for name, path in (('topological_map_bytes', self.map_file), ('places_bytes', self.map_file + '.places')):
            sizes[name] = os.path.getsize(path) if path and os.path.exists(path) else None
        total = sum(v for v in sizes.values() if v)
        s = self.status
        out = {
            'world': self.world['name'],
            'complete': bool(s is not None and s.mode == DONE and s.state == 'exploration complete'),
            'rooms': len(rooms), 'rooms_mapped': len(per_room),
            'rooms_missed': [r for r in rooms if r not in per_room],
            'rooms_mapped_twice': {r: n for r, n in per_room.items() if n > 1},
            'rooms_unreachable': unreachable,
            'place_rooms': {str(k): v for k, v in sorted(place_room.items())},
            # Every place the robot was in, linked or not (the status counts the linked ones).
            'places': s.places if s else 0, 'places_in_no_room': sorted(k for k in self.metric_places
                                                                        if k not in place_room),
            'hallway_doors': len(doors), 'doors_found': found, 'doors_missed': missed,
            'spurious_door_nodes': [n.id for n in door_nodes if not any(u[0] == n.id for u in used)],
            'nodes': len(self.map.nodes) if self.map else 0, 'edges': len(self.map.edges) if self.map else 0,
            'openings_explored': s.openings_explored if s else 0,
            'openings_unexplored': s.openings_unexplored if s else 0,
            'travel_m': round(self.travel, 1),
            'sim_time_s': round(s.header.stamp.to_sec() - self.t0, 1) if s and self.t0 else None,
            'real_time_factor': round(s.real_time_factor, 2) if s else None,
            'floor_m2': round(floor, 1), 'map_bytes': total,
            'bytes_per_m2': round(total / floor, 1) if floor > 0 and total else None,
        }
        for f, errors in self.pose_errors.items():
            e = sorted(errors)
            out[f + '_pose_error_m'] = {'checks': len(e), 'median': round(e[len(e) // 2], 3),
                                        'p95': round(e[int(0.95 * (len(e) - 1))], 3), 'max': round(e[-1], 3)} if e else None
        out.update(sizes)
        return out

    def graph(self):
        """The topological map as drawn over the ground truth: nodes at their display poses (the
        map frame is the start's), edges; for pictures (scripts/benchmark_exploration)."""
        m = self.map
        return {
            'start': self.start,
            'nodes': [{'id': n.id, 'type': n.type, 'x': n.pose.x, 'y': n.pose.y} for n in m.nodes] if m else [],
            'edges': [[e.source, e.target] for e in m.edges] if m else [],
        }

    def write(self):
        if self.written:
            return
        self.written = True
        out = self.summary()
        if self.output:
            with open(self.output, 'w') as f:
                json.dump(out, f, indent=1)
            with open(self.output + '.map.json', 'w') as f:
                json.dump(self.graph(), f)
        rospy.loginfo('evaluate_exploration: %s', json.dumps(out))


if __name__ == '__main__':
    rospy.init_node('evaluate_exploration')
    ExplorationEvaluator()
    rospy.spin()
