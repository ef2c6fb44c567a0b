"""Plane geometry the evaluation scripts share (ground truth only): the point-in-polygon test of
world regions, 2D pose composition (x, y, theta) and the yaw of a quaternion."""
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
