"""Motion-capture ground truth -> state_groundtruth_estimate0/data.csv (EuRoC columns).

Accepted types (detected per message): geometry_msgs/PoseStamped, PoseWithCovarianceStamped,
TransformStamped, nav_msgs/Odometry. Position and orientation (w, x, y, z) are written as given
(the mocap frame is taken as W, the tracked body as I). Velocity in W:
  * Odometry: twist.twist.linear is in the child (body) frame by ROS convention, rotated to W
    with the message's own orientation;
  * otherwise central finite differences of position, v_i = (p_{i+1} - p_{i-1}) / (t_{i+1} - t_{i-1}),
    one-sided at the first and last sample, zero for a single sample.
Gyro and accelerometer biases are unknown to a mocap system and written as 0.
"""
from __future__ import annotations

from .errors import UnknownTypeError
from .extract import GT_HEADER, Handler


def quat_rotate(q, v):
    """Rotate vector v by the Hamilton unit quaternion q = (w, x, y, z)."""
    w, x, y, z = q
    # t = 2 * (q_vec x v); v' = v + w t + q_vec x t
    tx = 2.0 * (y * v[2] - z * v[1])
    ty = 2.0 * (z * v[0] - x * v[2])
    tz = 2.0 * (x * v[1] - y * v[0])
    return (v[0] + w * tx + (y * tz - z * ty),
            v[1] + w * ty + (z * tx - x * tz),
            v[2] + w * tz + (x * ty - y * tx))


def pose_of(msg, where: str):
    """(position (x,y,z), quaternion (w,x,y,z), body-frame linear velocity or None)."""
    if hasattr(msg, "transform"):
        p, q = msg.transform.translation, msg.transform.rotation
        return (p.x, p.y, p.z), (q.w, q.x, q.y, q.z), None
    pose = getattr(msg, "pose", None)
    if pose is not None and hasattr(pose, "pose"):  # Odometry / PoseWithCovarianceStamped
        pose_inner = pose.pose
        twist = getattr(msg, "twist", None)
        v = None
        if twist is not None and hasattr(twist, "twist"):
            lin = twist.twist.linear
            v = (lin.x, lin.y, lin.z)
        p, q = pose_inner.position, pose_inner.orientation
        return (p.x, p.y, p.z), (q.w, q.x, q.y, q.z), v
    if pose is not None and hasattr(pose, "position"):
        p, q = pose.position, pose.orientation
        return (p.x, p.y, p.z), (q.w, q.x, q.y, q.z), None
    raise UnknownTypeError(f"{where}: not a pose message (expected PoseStamped, "
                           "PoseWithCovarianceStamped, TransformStamped or Odometry)")


def central_difference(prev, nxt):
    """Velocity from two (t_ns, p) samples: (p_b - p_a) / (t_b - t_a) [m/s]."""
    (ta, pa), (tb, pb) = prev, nxt
    dt = (tb - ta) * 1e-9
    return tuple((pb[i] - pa[i]) / dt for i in range(3))


class GroundTruthHandler(Handler):
    header = GT_HEADER

    def __init__(self, rs, mav0, bag_path):
        super().__init__(rs, mav0, bag_path)
        self.window = []  # up to 3 samples (t, p, q) awaiting finite-difference velocity
        self.last_t = None
        self.velocity_source = None

    def _emit(self, t, p, q, v):
        self.csv.write(t, (*p, *q, *v, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0))

    def feed(self, index, topic, msgtype, msg, bag_ns):
        where = self.where(topic, msgtype)
        p, q, v_body = pose_of(msg, where)
        t = self.stamp(msg, bag_ns, self.rs.source.stamp, where)
        if self.last_t is not None and t <= self.last_t:
            self.csv.dropped += 1
            return
        self.last_t = t
        if v_body is not None:
            self.velocity_source = "odometry_twist_rotated_to_world"
            self._emit(t, p, q, quat_rotate(q, v_body))
            return
        self.velocity_source = "central_finite_difference"
        self.window.append((t, p, q))
        if len(self.window) == 2:  # first sample: forward difference
            t0, p0, q0 = self.window[0]
            self._emit(t0, p0, q0, central_difference((t0, p0), (t, p)))
        elif len(self.window) == 3:
            (ta, pa, _), (tb, pb, qb), _ = self.window
            self._emit(tb, pb, qb, central_difference((ta, pa), (t, p)))
            self.window.pop(0)

    def finish(self):
        if len(self.window) == 1:
            t, p, q = self.window[0]
            self._emit(t, p, q, (0.0, 0.0, 0.0))
        elif len(self.window) == 2:  # last sample: backward difference
            (ta, pa, _), (tb, pb, qb) = self.window
            self._emit(tb, pb, qb, central_difference((ta, pa), (tb, pb)))
        self.window = []
        super().finish()
