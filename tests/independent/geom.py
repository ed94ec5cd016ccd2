"""Independent geometry for the judge: roads from curvature profiles, Frenet <-> Cartesian,
oriented boxes (separating axis theorem) and scene/1 obstacle poses.

Written from the scene/1 definition in FORMATS.md only; it shares no code with the planner
or with hil_sim, so that a bug there cannot hide itself here.
"""
import bisect
import math


# --------------------------------------------------------------------------------------------
# Oriented boxes
# --------------------------------------------------------------------------------------------
class Box:
    """Rectangle given by its centre, heading (rad) and size (length along the heading)."""

    __slots__ = ("cx", "cy", "heading", "length", "width")

    def __init__(self, cx, cy, heading, length, width):
        self.cx, self.cy, self.heading = cx, cy, heading
        self.length, self.width = length, width

    def axes(self):
        c, s = math.cos(self.heading), math.sin(self.heading)
        return (c, s), (-s, c)

    def corners(self):
        (ux, uy), (vx, vy) = self.axes()
        hl, hw = self.length / 2.0, self.width / 2.0
        return [(self.cx + a * hl * ux + b * hw * vx, self.cy + a * hl * uy + b * hw * vy)
                for a, b in ((1, 1), (-1, 1), (-1, -1), (1, -1))]

    def inflated(self, d_long, d_lat):
        return Box(self.cx, self.cy, self.heading, self.length + 2 * d_long,
                   self.width + 2 * d_lat)


def _projection_interval(corners, axis):
    values = [p[0] * axis[0] + p[1] * axis[1] for p in corners]
    return min(values), max(values)


def boxes_overlap(a, b):
    """Separating axis theorem: two convex rectangles are disjoint iff one of the four edge
    normals separates their projections. Touching counts as overlap (as in FORMATS.md)."""
    ca, cb = a.corners(), b.corners()
    for axis in a.axes() + b.axes():
        lo_a, hi_a = _projection_interval(ca, axis)
        lo_b, hi_b = _projection_interval(cb, axis)
        if hi_a < lo_b or hi_b < lo_a:
            return False
    return True


def ego_box(x, y, heading, length, width, wheelbase):
    """Footprint from the rear-axle pose; the rear overhang is (length - wheelbase) / 2, so the
    box centre lies wheelbase / 2 ahead of the rear axle."""
    return Box(x + 0.5 * wheelbase * math.cos(heading), y + 0.5 * wheelbase * math.sin(heading),
               heading, length, width)


def wrap_angle(a):
    return (a + math.pi) % (2.0 * math.pi) - math.pi


# --------------------------------------------------------------------------------------------
# Road: a reference line integrated from a curvature profile kappa(s)
# --------------------------------------------------------------------------------------------
class Road:
    """Reference line sampled every `ds` metres from a start pose and a curvature function.
    Positions are integrated exactly along arcs of constant curvature per step."""

    def __init__(self, x0, y0, heading0, length, kappa_of_s, ds=0.5):
        self.ds = ds
        n = int(math.ceil(length / ds)) + 1
        self.s = [i * ds for i in range(n)]
        self.kappa = [kappa_of_s(s) for s in self.s]
        self.x, self.y, self.theta = [x0], [y0], [heading0]
        for i in range(1, n):
            k = 0.5 * (self.kappa[i - 1] + self.kappa[i])
            th0 = self.theta[-1]
            th1 = th0 + k * ds
            if abs(k) < 1e-9:
                dx, dy = ds * math.cos(th0), ds * math.sin(th0)
            else:
                dx = (math.sin(th1) - math.sin(th0)) / k
                dy = (math.cos(th0) - math.cos(th1)) / k
            self.x.append(self.x[-1] + dx)
            self.y.append(self.y[-1] + dy)
            self.theta.append(th1)

    @property
    def length(self):
        return self.s[-1]

    def _interp(self, arr, s):
        if s <= 0.0:
            return arr[0], 0
        i = min(int(s / self.ds), len(arr) - 2)
        f = (s - self.s[i]) / self.ds
        return arr[i] + f * (arr[i + 1] - arr[i]), i

    def pose(self, s):
        """(x, y, theta, kappa) on the reference line; extrapolated straight beyond its ends."""
        if s < 0.0 or s > self.length:
            end = 0 if s < 0.0 else -1
            base = self.s[end]
            th = self.theta[end]
            return (self.x[end] + (s - base) * math.cos(th), self.y[end] + (s - base) * math.sin(th),
                    th, 0.0)
        x, _ = self._interp(self.x, s)
        y, _ = self._interp(self.y, s)
        th, _ = self._interp(self.theta, s)
        k, _ = self._interp(self.kappa, s)
        return x, y, th, k

    def to_xy(self, s, l):
        x, y, th, _ = self.pose(s)
        return x - l * math.sin(th), y + l * math.cos(th)

    def frenet_pose(self, s, l, s_dot, l_dot):
        """Cartesian pose and speed of a point moving in (s, l): velocity = s_dot (1 - kappa l) T
        + l_dot N, so heading = theta + atan2(l_dot, s_dot (1 - kappa l))."""
        x, y = self.to_xy(s, l)
        _, _, th, k = self.pose(s)
        vt, vn = s_dot * (1.0 - k * l), l_dot
        speed = math.hypot(vt, vn)
        if speed < 1e-6:
            heading = th if s_dot >= 0.0 else th + math.pi
        else:
            heading = th + math.atan2(vn, vt)
        return x, y, wrap_angle(heading), speed

    def polyline(self, spacing):
        step = max(1, int(round(spacing / self.ds)))
        idx = list(range(0, len(self.s), step))
        if idx[-1] != len(self.s) - 1:
            idx.append(len(self.s) - 1)
        return [[round(self.x[i], 4), round(self.y[i], 4)] for i in idx]


# --------------------------------------------------------------------------------------------
# Projection onto a polyline (the judge's own; chords, not arcs: errors of c^2/8R are fine for
# classification and for "is the road ahead free")
# --------------------------------------------------------------------------------------------
class Polyline:
    def __init__(self, points):
        self.p = points
        self.cum = [0.0]
        for a, b in zip(points, points[1:]):
            self.cum.append(self.cum[-1] + math.hypot(b[0] - a[0], b[1] - a[1]))

    def project(self, x, y, hint=None):
        """(s, l, segment heading) of the nearest point; first/last segments extended."""
        best = None
        rng = range(len(self.p) - 1)
        if hint is not None:
            rng = range(max(0, hint - 40), min(len(self.p) - 1, hint + 40))
        for i in rng:
            ax, ay = self.p[i]
            bx, by = self.p[i + 1]
            dx, dy = bx - ax, by - ay
            seg = math.hypot(dx, dy)
            if seg < 1e-9:
                continue
            t = ((x - ax) * dx + (y - ay) * dy) / (seg * seg)
            if i > 0:
                t = max(t, 0.0)
            if i < len(self.p) - 2:
                t = min(t, 1.0)
            px, py = ax + t * dx, ay + t * dy
            d2 = (x - px) ** 2 + (y - py) ** 2
            if best is None or d2 < best[0]:
                cross = (dx * (y - ay) - dy * (x - ax)) / seg
                best = (d2, self.cum[i] + t * seg, cross, math.atan2(dy, dx), i)
        _, s, l, th, i = best
        return s, l, th, i


def boundary_at(boundary, s):
    """scene/1 boundary: a number, or [s, l] pairs piecewise linear, constant beyond its ends."""
    if isinstance(boundary, (int, float)):
        return float(boundary)
    ss = [p[0] for p in boundary]
    if s <= ss[0]:
        return boundary[0][1]
    if s >= ss[-1]:
        return boundary[-1][1]
    i = bisect.bisect_right(ss, s) - 1
    (s0, l0), (s1, l1) = boundary[i], boundary[i + 1]
    return l0 + (s - s0) / (s1 - s0) * (l1 - l0)


# --------------------------------------------------------------------------------------------
# scene/1 obstacles over time
# --------------------------------------------------------------------------------------------
def dynamic_pose(obstacle, t):
    """(x, y, heading, v) of a dynamic obstacle at time t, None before its first sample:
    linear between samples (heading along the shorter arc), constant velocity after the last."""
    traj = obstacle["trajectory"]
    if t < traj[0]["t"] - 1e-9:
        return None
    last = traj[-1]
    if t >= last["t"]:
        dt = t - last["t"]
        return (last["x"] + last["v"] * dt * math.cos(last["heading"]),
                last["y"] + last["v"] * dt * math.sin(last["heading"]), last["heading"], last["v"])
    times = obstacle.get("_times")
    if times is None:
        times = obstacle["_times"] = [p["t"] for p in traj]
    i = max(0, bisect.bisect_right(times, t) - 1)
    a, b = traj[i], traj[i + 1]
    f = (t - a["t"]) / (b["t"] - a["t"])
    dh = wrap_angle(b["heading"] - a["heading"])
    return (a["x"] + f * (b["x"] - a["x"]), a["y"] + f * (b["y"] - a["y"]),
            wrap_angle(a["heading"] + f * dh), a["v"] + f * (b["v"] - a["v"]))


def obstacle_boxes_at(scene, t):
    """[(id, kind, Box, vx, vy)] of every obstacle present at time t."""
    out = []
    for o in scene.get("static_obstacles", []):
        out.append((o["id"], o.get("kind", "static"),
                    Box(o["x"], o["y"], o["heading"], o["length"], o["width"]), 0.0, 0.0))
    for o in scene.get("dynamic_obstacles", []):
        p = dynamic_pose(o, t)
        if p is None:
            continue
        x, y, h, v = p
        out.append((o["id"], o.get("kind", "dynamic"), Box(x, y, h, o["length"], o["width"]),
                    v * math.cos(h), v * math.sin(h)))
    return out


def contact_normal(a, b, a_prev=None, b_prev=None):
    """Unit contact direction from a's centre towards b's. With the boxes one step before the
    contact (a_prev, b_prev, disjoint), it is the SAT axis that separated them most then: the
    side across which they came together (a deep step into a car's rear is then still a
    rear contact). Otherwise the axis of least penetration now."""
    best = None
    if a_prev is not None and b_prev is not None and not boxes_overlap(a_prev, b_prev):
        ca, cb = a_prev.corners(), b_prev.corners()
        for axis in a_prev.axes() + b_prev.axes():
            lo_a, hi_a = _projection_interval(ca, axis)
            lo_b, hi_b = _projection_interval(cb, axis)
            gap = max(lo_b - hi_a, lo_a - hi_b)
            if best is None or gap > best[0]:
                best = (gap, axis)
        ref = (b_prev.cx - a_prev.cx, b_prev.cy - a_prev.cy)
    else:
        ca, cb = a.corners(), b.corners()
        for axis in a.axes() + b.axes():
            lo_a, hi_a = _projection_interval(ca, axis)
            lo_b, hi_b = _projection_interval(cb, axis)
            depth = min(hi_a - lo_b, hi_b - lo_a)
            if best is None or -depth > best[0]:
                best = (-depth, axis)
        ref = (b.cx - a.cx, b.cy - a.cy)
    ux, uy = best[1]
    if ref[0] * ux + ref[1] * uy < 0:
        ux, uy = -ux, -uy
    return ux, uy


def classify_contact(ego, ego_v, obstacle, obs_v, ego_prev=None, obstacle_prev=None):
    """Who ran into whom at a contact. u = the contact direction from the ego towards the
    obstacle (contact_normal); the ego's share of the closing speed is ego_v . u, the
    obstacle's is -obs_v . u. The one with the larger share ran into the other ('ran_into':
    the ego; 'hit': the obstacle: a rear-end or a cut into the ego's side); a tie (both
    shares within 0.05 m/s) goes to the faster one. The location (front / rear / left /
    right) is where the obstacle's centre lies in the ego's frame, scaled by the ego's half
    length and half width."""
    ux, uy = contact_normal(ego, obstacle, ego_prev, obstacle_prev)
    rx, ry = obstacle.cx - ego.cx, obstacle.cy - ego.cy
    ego_share = ego_v[0] * ux + ego_v[1] * uy
    obs_share = -(obs_v[0] * ux + obs_v[1] * uy)
    if abs(ego_share - obs_share) < 0.05:
        ego_first = math.hypot(*ego_v) >= math.hypot(*obs_v)
    else:
        ego_first = ego_share > obs_share
    c, s = math.cos(ego.heading), math.sin(ego.heading)
    fwd, left = rx * c + ry * s, -rx * s + ry * c
    if abs(fwd) / (ego.length / 2) >= abs(left) / (ego.width / 2):
        location = "front" if fwd > 0 else "rear"
    else:
        location = "left" if left > 0 else "right"
    return {"who": "ran_into" if ego_first else "hit", "location": location,
            "ego_share": round(ego_share, 2), "obstacle_share": round(obs_share, 2)}
