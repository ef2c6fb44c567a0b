"""Plane geometry the evaluation scripts share (ground truth only): the point-in-polygon test of
world regions, a point's distance to a segment, 2D pose composition (x, y, theta), the yaw of a
quaternion, and which rooms of a world file lie behind other rooms."""
import math


def inside(polygon, x, y):
    """Whether (x, y) lies inside the polygon [[x, y], ...] (even-odd rule)."""
    c = False
    n = len(polygon)
    for i in range(n):
        (x1, y1), (x2, y2) = polygon[i], polygon[(i + 1) % n]
        if (y1 > y) != (y2 > y) and x < (x2 - x1) * (y - y1) / (y2 - y1) + x1:
            c = not c
    return c


def segment_distance(p, a, b):
    """Distance from point p to the segment a-b (points (x, y))."""
    ax, ay = b[0] - a[0], b[1] - a[1]
    L = ax * ax + ay * ay
    t = 0.0 if L == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * ax + (p[1] - a[1]) * ay) / L))
    return math.hypot(p[0] - a[0] - t * ax, p[1] - a[1] - t * ay)


def compose(a, b):
    """Pose a (+) pose b; b may be a point (x, y): then the point in a's parent frame."""
    c, s = math.cos(a[2]), math.sin(a[2])
    x, y = a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1]
    if len(b) < 3:
        return (x, y)
    return (x, y, math.atan2(math.sin(a[2] + b[2]), math.cos(a[2] + b[2])))


def inverse(a):
    c, s = math.cos(a[2]), math.sin(a[2])
    return (-c * a[0] - s * a[1], s * a[0] - c * a[1], -a[2])


def yaw_of(q):
    """The yaw (rad) of a geometry_msgs/Quaternion."""
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def rooms_behind_rooms(world):
    """The rooms of a loaded world file none of whose doors opens onto a region of another kind (a
    hallway): reachable only through another room."""
    rooms = {r['name'] for r in world['regions'] if r.get('kind') == 'room'}
    on_hallway = {a for door in world.get('doors', []) for a, b in (door['between'], door['between'][::-1])
                  if a in rooms and b not in rooms}
    return rooms - on_hallway
