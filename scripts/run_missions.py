#!/usr/bin/python3
"""Random missions between the places of a hybrid map (Tomatis et al. 2001, section 4, Table 1).

Waits until the exploration node is idle (the exploration done, or explore false on a loaded map),
then sends ~missions GoToPlace goals (seeded): each to a random place other than the one the robot
is in, at a random free pose of that place's room (from the world file's ground truth: at least
~goal_clearance from every obstacle, and connected to the place's door through space with at least
~reach_clearance, so that a goal walled in by furniture is not asked for). Prints the
paper's Table 1 for them and writes it as JSON to ~output.

The goal error is measured against the simulator's ground truth: a place's frame in the world is
taken from the first EKF pose of the place (its origin is the robot's pose when it was created)
and the ground-truth pose at the same stamp. Those frames are written to ~truth_file (when
missions run right after an exploration) and read from it (missions on a loaded map); places
without a known frame are not used.

~unknown_place_check and ~wall_goal_check add two missions that must fail cleanly: one to a place
id no node links (refused), one to a goal inside a wall of the room the robot is in (ends at the
closest reachable pose).

In lockstep (the simulator at rate 0) this node is a participant and the exploration node's
upstream (its ~mission_client): each goal is sent within a step (lockstep.ScriptClock), a result is
seen at the step after the one it was set at, and every figure is taken by stamp (the ground truth
at the step, the beliefs and relocations between two steps), so the same seed and map give the
same missions, path and errors whatever the machine's load."""
import bisect
import json
import math
import os
import random
import sys
import time

import actionlib
import rospy
import yaml
from actionlib_msgs.msg import GoalStatus
from lockstep import Participant, ScriptClock
from geometry_msgs.msg import PoseWithCovarianceStamped
from visualization_msgs.msg import MarkerArray
from world_geometry import compose, inside, inverse, segment_distance, yaw_of
from hybrid_slam_msgs.msg import (ExplorationStatus, GoToPlaceAction, GoToPlaceActionResult, GoToPlaceGoal,
                                  RelocationResult, TopologicalBelief, TopologicalMap)
from nav_msgs.msg import Odometry

DONE, TOPOLOGICAL = 3, 0
TERMINAL = (GoalStatus.PREEMPTED, GoalStatus.SUCCEEDED, GoalStatus.ABORTED, GoalStatus.REJECTED, GoalStatus.RECALLED,
            GoalStatus.LOST)


class World:
    def __init__(self, path):
        with open(path) as f:
            w = yaml.safe_load(f)
        self.name = w.get('name', os.path.basename(path))
        self.segments = []
        for wall in w.get('walls', []):
            pts = wall['points']
            self.segments += [(pts[i], pts[i + 1]) for i in range(len(pts) - 1)]
        self.boxes = w.get('boxes', [])
        self.cylinders = w.get('cylinders', [])
        self.rooms = [r for r in w.get('regions', []) if r['kind'] == 'room']

    def room_at(self, x, y):
        for r in self.rooms:
            if inside(r['polygon'], x, y):
                return r
        return None

    def clearance(self, x, y):
        d = min([segment_distance((x, y), a, b) for a, b in self.segments] or [1e9])
        for b in self.boxes:
            c, s = math.cos(-b.get('yaw', 0.0)), math.sin(-b.get('yaw', 0.0))
            lx = c * (x - b['center'][0]) - s * (y - b['center'][1])
            ly = s * (x - b['center'][0]) + c * (y - b['center'][1])
            dx, dy = max(abs(lx) - b['size'][0] / 2, 0.0), max(abs(ly) - b['size'][1] / 2, 0.0)
            d = min(d, math.hypot(dx, dy))
        for cy in self.cylinders:
            d = min(d, math.hypot(x - cy['center'][0], y - cy['center'][1]) - cy['radius'])
        return d


class MissionRunner:
    def __init__(self):
        self.world = World(rospy.get_param('~world_file'))
        self.missions = int(rospy.get_param('~missions', 15))
        self.rng = random.Random(int(rospy.get_param('~seed', 1)))
        self.output = rospy.get_param('~output', '')
        self.truth_file = rospy.get_param('~truth_file', '')
        self.mission_timeout = float(rospy.get_param('~mission_timeout', 900.0))  # s, sim
        self.clearance = float(rospy.get_param('~goal_clearance', 0.55))  # m, free space around a goal
        # m, free space along some way from the door to a goal: the robot's radius (0.25) and the
        # controller's safety margin (0.10), plus 5 cm
        self.reach_clearance = float(rospy.get_param('~reach_clearance', 0.40))
        self.reachable = {}  # place id -> set of reachable 0.1 m cells (world)
        self.doors = {}  # place id -> its door in the world (x, y, theta into the room)
        self.truth = []  # (stamp, (x, y, theta))
        self.frames = {}  # place id -> place frame in the world (x, y, theta)
        if self.truth_file and os.path.exists(self.truth_file):
            with open(self.truth_file) as f:
                self.frames = {int(k): tuple(v) for k, v in json.load(f).items()}
        self.pending_frames = set()  # place ids whose first EKF pose waits for its ground truth
        self.pending_truth = []  # (stamp, use): what waits for the ground truth of its stamp
        self.map = None
        self.status = None
        self.modes = []  # (stamp s, exploration mode) of each status: the mode at a belief's stamp
        self.beliefs = []  # (stamp s, confident) of every belief
        self.entropy = []  # (sim s, entropy, entropy_max, confident): the whole run, every 5th belief
        self.place_lines = {}  # place id -> [[x1, y1, x2, y2], ...] in the place frame
        self.relocations = []  # (stamp s, verdict) of every relocation
        # The map, the places' frames and the entropy series for the report's plots.
        self.dump = rospy.get_param('~map_dump', self.output + '.map.json' if self.output else '')
        # Lockstep: every input counted (a step has all its messages), goals sent within steps.
        self.lockstep = Participant()
        self.clock = ScriptClock(self.lockstep)
        self.client = actionlib.SimpleActionClient('go_to_place', GoToPlaceAction)
        sub = self.lockstep.subscribe
        sub('ground_truth', Odometry, self.on_truth, queue_size=200)
        sub('local_pose', PoseWithCovarianceStamped, self.on_local, queue_size=50)
        sub('topological_map', TopologicalMap, self.on_map, queue_size=2)
        sub('topological_belief', TopologicalBelief, self.on_belief, queue_size=50)
        sub('exploration_status', ExplorationStatus, self.on_status, queue_size=50)
        sub('relocation', RelocationResult, self.on_relocation, queue_size=50)
        # Counted after the action client's own subscription (rospy calls a topic's callbacks in
        # order): once a step's result is counted, the client has it.
        sub('go_to_place/result', GoToPlaceActionResult, lambda msg: None, queue_size=10)
        rospy.Subscriber('places_markers', MarkerArray, self.on_places, queue_size=2)  # for the plots only

    def on_truth(self, msg):
        p = msg.pose.pose
        self.truth.append((msg.header.stamp.to_sec(), (p.position.x, p.position.y, yaw_of(p.orientation))))
        if len(self.truth) > 4000:
            del self.truth[:1000]
        waiting, self.pending_truth = self.pending_truth, []
        for stamp, use in waiting:
            self.with_truth(stamp, use)

    def with_truth(self, stamp, use):
        """use(ground truth at `stamp`, or None if there is none) once the ground truth of that stamp
        has come: a message stamped at a step may arrive before the step's ground truth."""
        if not self.truth or self.truth[-1][0] < stamp:
            self.pending_truth.append((stamp, use))
        else:
            use(self.truth_at(stamp))

    def truth_at(self, stamp):
        if not self.truth:
            return None
        stamps = [t for t, _ in self.truth]
        i = bisect.bisect_left(stamps, stamp)
        best = min((j for j in (i - 1, i) if 0 <= j < len(self.truth)), key=lambda j: abs(stamps[j] - stamp))
        return self.truth[best][1] if abs(stamps[best] - stamp) < 0.05 else None

    def on_local(self, msg):
        f = msg.header.frame_id
        if not f.startswith('place_'):
            return
        pid = int(f[len('place_'):])
        p = msg.pose.pose
        pose = (p.position.x, p.position.y, yaw_of(p.orientation))
        if pid not in self.frames and pid not in self.pending_frames and math.hypot(pose[0], pose[1]) < 0.3:
            # The place's first EKF pose: the robot is at (or within centimetres of) its origin.
            self.pending_frames.add(pid)

            def frame(t):  # the place's frame in the world (none without a ground truth at the stamp)
                self.pending_frames.discard(pid)
                if t is not None:
                    self.frames[pid] = compose(t, inverse(pose))
            self.with_truth(msg.header.stamp.to_sec(), frame)

    def on_relocation(self, msg):
        v = {'place': msg.place_id, 'success': msg.success, 'verdict': msg.verdict, 'matched': msg.matched,
             'joint_nis': round(msg.joint_nis, 2), 'bound': round(msg.joint_nis_bound, 2)}
        self.relocations.append((msg.header.stamp.to_sec(), v))

        def where(t):  # where the robot really was (ground truth, world), to tell a wrong door from a bad match
            if t is not None:
                v['truth'] = [round(c, 2) for c in t]
        self.with_truth(msg.header.stamp.to_sec(), where)

    def relocations_between(self, t0, t1):
        """The relocation verdicts stamped in [t0, t1) (s): those of one mission, at most 40."""
        return [v for t, v in self.relocations if t0 <= t < t1][:40]

    def on_map(self, msg):
        self.map = msg

    def on_belief(self, msg):
        stamp = msg.header.stamp.to_sec()
        self.beliefs.append((stamp, bool(msg.confident)))
        if len(self.beliefs) % 5 == 0:
            self.entropy.append((round(stamp, 2), round(msg.entropy, 4), msg.entropy_max, bool(msg.confident)))

    def state_estimates(self, t0, t1):
        """(beliefs, unconfident ones) stamped in [t0, t1) (s) while the exploration node was in its
        topological mode (its last status stamped before the belief)."""
        stamps = [t for t, _ in self.modes]
        n = unconfident = 0
        for t, confident in self.beliefs:
            if not t0 <= t < t1:
                continue
            i = bisect.bisect_left(stamps, t) - 1
            if i >= 0 and self.modes[i][1] == TOPOLOGICAL:
                n += 1
                unconfident += 0 if confident else 1
        return n, unconfident

    def on_places(self, msg):
        lines = {}
        for m in msg.markers:
            if not m.header.frame_id.startswith('place_') or len(m.points) < 2:
                continue
            pid = int(m.header.frame_id[len('place_'):])
            pts = m.points
            lines.setdefault(pid, []).extend(
                [[pts[i].x, pts[i].y, pts[i + 1].x, pts[i + 1].y] for i in range(0, len(pts) - 1, 2)])
        if lines:
            self.place_lines = lines

    def write_dump(self, mission_start):
        """The hybrid map as the run left it, for scripts/plot_evaluation.py."""
        if not self.dump:
            return
        nodes = [{'id': n.id, 'type': n.type, 'x': n.pose.x, 'y': n.pose.y,
                  'place_ids': [o.place_id for o in n.openings if o.place_id >= 0]}
                 for n in (self.map.nodes if self.map else [])]
        edges = [[e.source, e.target] for e in (self.map.edges if self.map else [])]
        with open(self.dump, 'w') as f:
            json.dump({'nodes': nodes, 'edges': edges, 'place_lines': {str(k): v for k, v in self.place_lines.items()},
                       'place_frames': {str(k): v for k, v in self.frames.items()},
                       'entropy': self.entropy, 'missions_start_s': mission_start}, f)

    def on_status(self, msg):
        self.status = msg
        self.modes.append((msg.header.stamp.to_sec(), msg.mode))

    def idle(self):
        s = self.status
        return s is not None and (s.mode == DONE or s.state.startswith('waiting for a mission') or
                                  s.state.startswith('mission done') or s.state.startswith('mission failed'))

    def places(self):
        out = {}
        for o in (o for n in (self.map.nodes if self.map else []) for o in n.openings):
            if o.place_id >= 0 and o.place_id in self.frames:
                door = compose(self.frames[o.place_id], (o.door_in_place.x, o.door_in_place.y, o.door_in_place.theta))
                # The room: the world's room 1 m through the door.
                room = self.world.room_at(door[0] + math.cos(door[2]), door[1] + math.sin(door[2]))
                if room is not None:
                    out[o.place_id] = room
                    self.doors[o.place_id] = door
        return out

    def reachable_cells(self, place_id, room, cell=0.1):
        """The 0.1 m cells of the room reachable from its door with reach_clearance (ground truth)."""
        if place_id in self.reachable:
            return self.reachable[place_id]
        door = self.doors[place_id]
        key = lambda x, y: (int(math.floor(x / cell)), int(math.floor(y / cell)))
        free = lambda c: (inside(room['polygon'], (c[0] + 0.5) * cell, (c[1] + 0.5) * cell) and
                          self.world.clearance((c[0] + 0.5) * cell, (c[1] + 0.5) * cell) > self.reach_clearance)
        # From 0.5 m inside the door (the door's own centre is no wider than its jambs allow).
        start = key(door[0] + 0.5 * math.cos(door[2]), door[1] + 0.5 * math.sin(door[2]))
        seen, todo = {start}, [start] if free(start) else []
        reached = set(todo)
        while todo:
            c = todo.pop()
            for n in ((c[0] + 1, c[1]), (c[0] - 1, c[1]), (c[0], c[1] + 1), (c[0], c[1] - 1)):
                if n not in seen:
                    seen.add(n)
                    if free(n):
                        reached.add(n)
                        todo.append(n)
        self.reachable[place_id] = reached
        return reached

    def random_goal(self, place_id, room):
        xs = [p[0] for p in room['polygon']]
        ys = [p[1] for p in room['polygon']]
        for _ in range(5000):
            x, y = self.rng.uniform(min(xs), max(xs)), self.rng.uniform(min(ys), max(ys))
            if (inside(room['polygon'], x, y) and self.world.clearance(x, y) > self.clearance and
                    (int(math.floor(x / 0.1)), int(math.floor(y / 0.1))) in self.reachable_cells(place_id, room)):
                world = (x, y, self.rng.uniform(-math.pi, math.pi))
                return world, compose(inverse(self.frames[place_id]), world)
        return None, None

    def wall_goal(self, place_id, room):
        """A point on the room's wall farthest from the robot (inside the wall)."""
        here = self.truth_at(self.clock.stamp.to_sec()) or self.truth[-1][1]
        poly = room['polygon']
        mids = [((poly[i][0] + poly[(i + 1) % len(poly)][0]) / 2, (poly[i][1] + poly[(i + 1) % len(poly)][1]) / 2)
                for i in range(len(poly))]
        x, y = max(mids, key=lambda m: math.hypot(m[0] - here[0], m[1] - here[1]))
        world = (x, y, 0.0)
        return world, compose(inverse(self.frames[place_id]), world)

    def send(self, place_id, goal_place):
        """Sends a goal at the current step and waits for its result: (result, sim s)."""
        g = GoToPlaceGoal()
        g.place_id = place_id
        g.goal.x, g.goal.y, g.goal.theta = goal_place
        t0 = self.clock.stamp
        self.client.send_goal(g)
        self.lockstep.published('go_to_place/goal')
        done = lambda stamp: self.client.get_state() in TERMINAL
        end = self.clock.wait_until(lambda stamp: done(stamp) or (stamp - t0).to_sec() > self.mission_timeout)
        if not done(end):
            self.client.cancel_goal()
            self.lockstep.published('go_to_place/cancel')
            end = self.clock.wait_until(lambda stamp: done(stamp) or (stamp - t0).to_sec() > self.mission_timeout + 10.0)
        return self.client.get_result(), (end - t0).to_sec()

    def error(self, place_id, goal_place):
        """Ground-truth pose in the place frame against the goal, at the current step: (position m,
        heading rad)."""
        truth = self.truth_at(self.clock.stamp.to_sec())
        if truth is None:
            return None, None
        true_in_place = compose(inverse(self.frames[place_id]), truth)
        e = math.hypot(true_in_place[0] - goal_place[0], true_in_place[1] - goal_place[1])
        h = abs(math.atan2(math.sin(true_in_place[2] - goal_place[2]), math.cos(true_in_place[2] - goal_place[2])))
        return e, h

    def run(self):
        wall0 = time.time()
        rospy.loginfo('missions: waiting for the exploration node to be idle and its go_to_place server')
        if not self.client.wait_for_server(rospy.Duration(60.0)):
            rospy.logfatal('missions: no go_to_place action server (exploration node with serve_missions)')
            return 1
        idle = self.clock.wait_until(lambda stamp: self.idle())
        self.clock.wait_until(lambda stamp: stamp >= idle + rospy.Duration(2.0))  # the last map message
        places = self.places()
        if self.truth_file:
            with open(self.truth_file, 'w') as f:
                json.dump({str(k): v for k, v in self.frames.items()}, f)
        rospy.loginfo('missions: %d places with a known frame: %s', len(places), sorted(places))
        rows = []
        if len(places) < 2:
            rospy.logerr('missions: fewer than two places with a known frame (%s)', sorted(places))
        sim0 = self.clock.stamp.to_sec()
        current = self.status.current_place if self.status else -1
        for k in range(self.missions if len(places) >= 2 else 0):
            target = self.rng.choice([p for p in sorted(places) if p != current])
            world, goal = self.random_goal(target, places[target])
            if goal is None:
                rospy.logerr('missions: no free goal found in place %d', target)
                continue
            rospy.loginfo('missions: %d/%d to place %d (%s) at world (%.2f, %.2f)', k + 1, self.missions, target,
                          places[target]['name'], world[0], world[1])
            t0 = self.clock.stamp
            res, sim = self.send(target, goal)
            settled = self.clock.stamp + rospy.Duration(0.5)  # the robot at rest, its last ground truth
            self.clock.wait_until(lambda stamp: stamp >= settled)
            e, h = self.error(target, goal)
            row = {'place': target, 'room': places[target]['name'], 'goal_world': [round(v, 3) for v in world],
                   'success': bool(res and res.success), 'message': res.message if res else 'no result',
                   'path_m': res.path_length if res else 0.0, 'sim_s': sim,
                   'goal_error_m': e, 'heading_error_rad': h,
                   'relocations': self.relocations_between(t0.to_sec(), self.clock.stamp.to_sec())}
            if res:
                p = res.final_pose.pose
                est = (p.position.x, p.position.y)
                row['estimate_error_m'] = math.hypot(est[0] - goal[0], est[1] - goal[1]) if res.success else None
            rows.append(row)
            rospy.loginfo('missions: %s', json.dumps(row))
            current = target if row['success'] else -1
        sim1 = self.clock.stamp.to_sec()
        checks = {}
        if rospy.get_param('~unknown_place_check', False):
            res, _ = self.send(max(list(places) + [0]) + 100, (0.0, 0.0, 0.0))
            checks['unknown_place'] = {'success': bool(res and res.success), 'message': res.message if res else ''}
        if rospy.get_param('~wall_goal_check', False) and current in places:
            world, goal = self.wall_goal(current, places[current])
            res, sim = self.send(current, goal)
            e, _ = self.error(current, goal)
            checks['wall_goal'] = {'success': bool(res and res.success), 'message': res.message if res else '',
                                   'distance_to_wall_point_m': e, 'sim_s': sim}
        self.clock.finish()
        beliefs, unconfident = self.state_estimates(sim0, sim1)
        ok = [r for r in rows if r['success']]
        errs = [r['goal_error_m'] for r in ok if r['goal_error_m'] is not None]
        report = {
            'world': self.world.name, 'missions': len(rows), 'successes': len(ok),
            'success_rate': len(ok) / len(rows) if rows else 0.0,
            'state_estimates': beliefs, 'unconfident_states': unconfident,
            'unconfident_rate': unconfident / beliefs if beliefs else 0.0,
            'travel_m': sum(r['path_m'] for r in rows),
            'mean_goal_error_m': sum(errs) / len(errs) if errs else None,
            'max_goal_error_m': max(errs) if errs else None,
            'sim_s': sim1 - sim0, 'wall_s': time.time() - wall0,
            'rows': rows, 'checks': checks,
        }
        self.write_dump(sim0)
        print('\nTable 1 (Tomatis et al. 2001) for %s: %d missions' % (report['world'], len(rows)))
        print('  success rate          %5.1f %% (%d of %d)' % (100 * report['success_rate'], len(ok), len(rows)))
        print('  state estimates       %d' % report['state_estimates'])
        print('  unconfident states    %5.1f %%' % (100 * report['unconfident_rate']))
        print('  total travel          %.0f m' % report['travel_m'])
        if errs:
            print('  goal error            mean %.3f m, max %.3f m' % (report['mean_goal_error_m'], report['max_goal_error_m']))
        print('  time                  %.0f s sim, %.0f s wall' % (report['sim_s'], report['wall_s']))
        for name, c in checks.items():
            print('  check %-15s %s' % (name, json.dumps(c)))
        sys.stdout.flush()
        if self.output:
            with open(self.output, 'w') as f:
                json.dump(report, f)
        return 0


if __name__ == '__main__':
    rospy.init_node('run_missions')
    code = MissionRunner().run()
    rospy.signal_shutdown('missions done')
    sys.exit(code)
