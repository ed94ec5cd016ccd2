#!/usr/bin/env python3
"""Independent scene generator for judging itplan in closed loop (scene/1 files).

Designed from traffic knowledge and FORMATS.md only (no code or design shared with the
planner or hil_sim's own generator). Every scene is one named archetype with randomised
parameters; each archetype places its actors so that a reasonable driver has a safe plan with
margin (the rule is recorded in the scene's "judge" object and in README.md). Every scene is
then checked by check_scenes.py (independent witness driver + SAT geometry); a scene that
fails is regenerated from the next sub-seed, so the output is a deterministic function of
--seed, --count and --set.

    python3 gen_scenes.py --seed 1 --count 100 --out DIR          # regular mix
    python3 gen_scenes.py --seed 1 --count 20 --set stress --out DIR
"""
import argparse
import json
import math
import os
import random
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from geom import Road  # noqa: E402
import check_scenes  # noqa: E402

DT = 0.1                 # trajectory sample step [s]
DURATION = 15.0          # closed-loop length of every scene [s]
S_EGO0 = 60.0            # ego start along the reference line: room for traffic behind [m]
A_LAT_DESIGN = 2.0       # road design: speed_limit^2 * |kappa| <= this [m/s^2]
EGO_MAX_ACCEL = 3.0      # the planner's documented a_max: the fastest the ego may progress
COMFORT_DECEL = 3.0      # what a reasonable driver brakes with [m/s^2]
REACTION = 1.0           # a reasonable driver's reaction time [s]

EGO_MODELS = [  # (length, width, wheelbase)
    (4.3, 1.8, 2.6), (4.8, 1.9, 2.8), (5.0, 2.0, 3.0)]


# --------------------------------------------------------------------------------------------
# Small helpers
# --------------------------------------------------------------------------------------------
def smoothstep5(u):
    """Quintic 0 -> 1 with zero slope and curvature at both ends; and its derivative."""
    u = min(max(u, 0.0), 1.0)
    return 10 * u ** 3 - 15 * u ** 4 + 6 * u ** 5, 30 * u ** 2 - 60 * u ** 3 + 30 * u ** 4


def stopping_distance(v, decel=COMFORT_DECEL, reaction=REACTION, margin=5.0):
    """Distance a reasonable driver needs to stop from v: reaction, comfortable braking, margin."""
    return v * reaction + v * v / (2.0 * decel) + margin


def follow_gap_needed(v_ego, v_lead, lead_decel=0.0):
    """Initial bumper gap behind a leader that a reasonable driver handles comfortably.
    Constant-speed leader: close the speed difference at 2.5 m/s^2 after 0.8 s reaction.
    Braking leader (lead_decel > 0, to a stop): RSS-style, ego brakes at 4 m/s^2 after 0.5 s."""
    if lead_decel > 0.0:
        return 4.0 + 0.5 * v_ego + v_ego ** 2 / 8.0 - v_lead ** 2 / (2.0 * lead_decel)
    dv = max(0.0, v_ego - v_lead)
    return 4.0 + 0.8 * v_ego + dv * 0.8 + dv * dv / 5.0


def time_gap_floor(v_ego):
    """The least bumper gap a reasonable driver keeps, whatever a rule allows: 1.2 s + 4 m."""
    return 1.2 * v_ego + 4.0


def cut_in_gap_needed(v_ego, v_cut, lead_decel=0.0):
    """Bumper gap a cut-in must leave when its body enters the ego's lane: the follow gap;
    for one that will brake, never under a 1.2 s time gap + 4 m (the README's rule, the
    floor place_leader keeps). The RSS form alone goes negative for a fast cutter that brakes
    gently (27 m/s at 2.7 m/s^2 ahead of a 30 m/s ego: -4 m), which put the cutter of
    seed 7's scene 24 beside the ego."""
    gap = follow_gap_needed(v_ego, v_cut, lead_decel)
    return max(gap, time_gap_floor(v_ego)) if lead_decel > 0.0 else gap


def vehicle_size(rng, lane_width):
    r = rng.random()
    if r < 0.1 and lane_width >= 3.25:
        return round(rng.uniform(9.0, 12.0), 2), 2.5, "truck"
    if r < 0.25:
        return round(rng.uniform(5.2, 6.0), 2), round(rng.uniform(2.0, 2.1), 2), "van"
    return round(rng.uniform(4.0, 4.9), 2), round(rng.uniform(1.7, 1.9), 2), "car"


# --------------------------------------------------------------------------------------------
# Motion of a road user in Frenet coordinates of the reference line
# --------------------------------------------------------------------------------------------
class Motion:
    """Longitudinal phases (t_start, rate, v_target): from t_start the speed moves towards
    v_target at `rate`; lane changes (t_start, duration, l_target) as quintic blends.
    direction = -1 for oncoming traffic (s decreases)."""

    def __init__(self, s0, v0, l0, t0=0.0, direction=1):
        self.s0, self.v0, self.l0, self.t0, self.direction = s0, v0, l0, t0, direction
        self.phases, self.lane_changes = [], []

    def speed_to(self, t, rate, v_target):
        self.phases.append((t, rate, v_target))
        return self

    def lane_change(self, t, duration, l_target):
        self.lane_changes.append((t, duration, l_target))
        return self

    def lateral(self, t):
        l, l_dot = self.l0, 0.0
        for t_start, dur, l_target in sorted(self.lane_changes):
            if t <= t_start:
                break
            f, df = smoothstep5((t - t_start) / dur)
            l_from = l
            l = l_from + (l_target - l_from) * f
            l_dot = (l_target - l_from) * df / dur if t < t_start + dur else 0.0
        return l, l_dot

    def samples(self, t_end, substep=0.01):
        """[(t, s, l, s_dot, l_dot)] every DT from t0 to t_end."""
        out = []
        s, v, t = self.s0, self.v0, self.t0
        phases = sorted(self.phases)
        k_next = 0
        n_sub = int(round(DT / substep))
        while t <= t_end + 1e-9:
            if k_next % n_sub == 0:
                l, l_dot = self.lateral(t)
                out.append((round(t, 3), s, l, self.direction * v, l_dot))
            rate, target = 0.0, v
            for t_start, r, vt in phases:
                if t >= t_start - 1e-9:
                    rate, target = r, vt
            dv = max(-rate * substep, min(rate * substep, target - v))
            s += self.direction * (v + 0.5 * dv) * substep
            v += dv
            t += substep
            k_next += 1
        return out


def ego_progress(s0, v0, limit, t, accel=EGO_MAX_ACCEL):
    """(s, v) of the fastest reasonable ego: full acceleration to the limit from the start."""
    t_acc = max(0.0, (limit - v0) / accel)
    if t <= t_acc:
        return s0 + v0 * t + 0.5 * accel * t * t, v0 + accel * t
    return s0 + v0 * t_acc + 0.5 * accel * t_acc ** 2 + limit * (t - t_acc), limit


# --------------------------------------------------------------------------------------------
# Scene builder: road, ego, obstacles
# --------------------------------------------------------------------------------------------
class Scene:
    def __init__(self, rng, name, archetype, lanes=None, ego_lane=None, two_way=False,
                 limit=None, v0=None, shape=None):
        self.rng, self.name, self.archetype = rng, name, archetype
        self.tags = ["archetype:" + archetype]
        self.params = {}
        self.statics, self.dynamics = [], []
        self.next_static_id, self.next_dynamic_id = 1, 101
        self.occupied_lanes = set()      # lanes with static obstacles or primary actors
        self.target_lane_offset = 0.0
        self._choose_lanes(lanes, ego_lane, two_way)
        self.limit = limit if limit is not None else round(rng.uniform(5.0, 33.0), 2)
        self.v0 = v0 if v0 is not None else round(rng.uniform(0.0, self.limit), 2)
        self.ego_len, self.ego_wid, self.ego_wb = rng.choice(EGO_MODELS)
        self.front = 0.5 * (self.ego_len + self.ego_wb)    # rear axle -> front bumper
        self.rear = 0.5 * (self.ego_len - self.ego_wb)     # rear axle -> rear bumper
        self.left_boundary = self.l_left_edge
        self.right_boundary = self.l_right_edge
        self._build_road(shape)

    # ---- road -------------------------------------------------------------------------------
    def _choose_lanes(self, lanes, ego_lane, two_way):
        rng = self.rng
        self.two_way = two_way
        self.n_lanes = lanes if lanes is not None else rng.choice([1, 2, 2, 3, 3, 4])
        self.w = round(rng.uniform(2.75, 3.75), 2)
        self.ego_lane = ego_lane if ego_lane is not None else rng.randrange(self.n_lanes)
        # lane j (0 = rightmost) has its centre at l = (j - ego_lane) * w
        self.l_right_edge = -(self.ego_lane + 0.5) * self.w
        self.l_left_edge = (self.n_lanes - self.ego_lane - 0.5) * self.w
        self.tags += ["lanes:%d" % self.n_lanes, "ego_lane:%d" % self.ego_lane,
                      "lane_width:%.2f" % self.w]
        if two_way:
            self.tags.append("two_way")

    def lane_l(self, j):
        return (j - self.ego_lane) * self.w

    def lanes_other_than_ego(self):
        return [j for j in range(self.n_lanes) if j != self.ego_lane and
                not (self.two_way and j == 1)]

    def _build_road(self, shape):
        rng = self.rng
        length = S_EGO0 + self.limit * DURATION + 360.0
        l_extent = max(abs(self.l_left_edge), abs(self.l_right_edge)) + 3.0
        r_min = max(30.0, self.limit ** 2 / A_LAT_DESIGN, 2.5 * l_extent)
        radius = r_min * rng.uniform(1.0, 3.0)
        k = rng.choice([-1.0, 1.0]) / radius
        shape = shape or rng.choice(["straight", "curve", "s_curve", "clothoid"])
        # heading changes of each bend stay below 150 deg so the road never loops onto itself
        max_arc = radius * math.radians(rng.uniform(40.0, 150.0))
        trans = rng.uniform(30.0, 120.0)
        if shape == "straight":
            pieces = [(length, 0.0, 0.0)]
        elif shape == "curve":       # the ego starts inside a bend
            pieces = [(max(max_arc, S_EGO0 + 40.0), k, k), (trans, k, 0.0), (length, 0.0, 0.0)]
        elif shape == "clothoid":    # straight, then a clothoid into a bend ahead of the ego
            a = S_EGO0 + rng.uniform(10.0, 120.0)
            pieces = [(a, 0.0, 0.0), (trans, 0.0, k), (max_arc * 0.6, k, k), (trans, k, 0.0),
                      (length, 0.0, 0.0)]
        else:                        # S: left-right (or right-left) with clothoids in between
            a = S_EGO0 + rng.uniform(-40.0, 80.0)
            arc = max_arc * 0.4
            pieces = [(max(a, 1.0), 0.0, 0.0), (trans, 0.0, k), (arc, k, k), (2 * trans, k, -k),
                      (arc, -k, -k), (trans, -k, 0.0), (length, 0.0, 0.0)]
        kappa = piecewise_kappa(pieces)
        heading0 = rng.uniform(-math.pi, math.pi)
        x0, y0 = rng.uniform(-500, 500), rng.uniform(-500, 500)
        self.road = Road(x0, y0, heading0, length, kappa)
        self.tags.append("road:" + shape)
        self.params.update(road_shape=shape, radius=round(radius, 1) if shape != "straight"
                           else None, speed_limit=self.limit, v0=self.v0)

    def set_boundary_event(self, kind, side, s_start, taper, delta):
        """Tables of [s, l]: the edge on `side` moves by delta (positive = outwards) over
        `taper` metres from s_start. lane_end / narrowing move inwards, widening outwards."""
        base = self.left_boundary if side == "left" else self.right_boundary
        sign = 1.0 if side == "left" else -1.0
        if kind == "widening":
            start_l, end_l = base - sign * delta, base
        else:
            start_l, end_l = base, base - sign * delta
        table = [[0.0, round(start_l, 3)], [round(s_start, 2), round(start_l, 3)],
                 [round(s_start + taper, 2), round(end_l, 3)]]
        if side == "left":
            self.left_boundary = table
        else:
            self.right_boundary = table
        self.tags.append("boundary:" + kind)
        self.params.setdefault("boundary_events", []).append(
            {"kind": kind, "side": side, "s_start": round(s_start, 1), "taper": round(taper, 1),
             "delta": round(delta, 2)})

    # ---- actors -----------------------------------------------------------------------------
    def add_static(self, kind, s, l, length, width, heading_offset=0.0):
        x, y, th, _ = self.road.pose(s)
        x, y = self.road.to_xy(s, l)
        self.statics.append({"id": self.next_static_id, "kind": kind, "x": round(x, 4),
                             "y": round(y, 4), "heading": round(th + heading_offset, 5),
                             "length": length, "width": width})
        self.next_static_id += 1

    def add_dynamic(self, kind, motion, length, width):
        traj = []
        for t, s, l, s_dot, l_dot in motion.samples(DURATION):
            x, y, h, v = self.road.frenet_pose(s, l, s_dot, l_dot)
            traj.append({"t": t, "x": round(x, 4), "y": round(y, 4), "heading": round(h, 5),
                         "v": round(v, 4)})
        self.dynamics.append({"id": self.next_dynamic_id, "kind": kind, "length": length,
                              "width": width, "trajectory": traj})
        self.next_dynamic_id += 1

    def add_crossing(self, kind, s_cross, from_right, angle, speed, t_appear, length, width,
                     side_offset):
        """A pedestrian / cyclist walking a straight line across the road through (s_cross, 0)
        at `angle` to the road's direction; it appears side_offset beyond the road edge."""
        x0, y0, th, _ = self.road.pose(s_cross)
        edge = boundary_value(self.right_boundary if from_right else self.left_boundary, s_cross)
        far_edge = boundary_value(self.left_boundary if from_right else self.right_boundary,
                                  s_cross)
        direction = th + (angle if from_right else -angle)
        dirx, diry = math.cos(direction), math.sin(direction)
        lat_per_m = abs(math.sin(angle))                # lateral metres per metre walked
        d_start = (abs(edge) + side_offset) / lat_per_m  # walk from start to l = 0
        d_total = (abs(edge) + abs(far_edge) + 2 * side_offset) / lat_per_m
        px, py = x0 - d_start * dirx, y0 - d_start * diry
        traj = []
        n = int(math.ceil(d_total / speed / DT)) + 1
        for i in range(n + 1):
            t = t_appear + i * DT
            if t > DURATION:
                break
            d = speed * i * DT
            traj.append({"t": round(t, 3), "x": round(px + d * dirx, 4),
                         "y": round(py + d * diry, 4), "heading": round(direction, 5),
                         "v": speed})
        # after crossing it stops on the far sidewalk (a last sample with v = 0 would make it
        # walk on forever at v otherwise)
        last = traj[-1]
        traj.append({"t": round(last["t"] + DT, 3), "x": last["x"], "y": last["y"],
                     "heading": last["heading"], "v": 0.0})
        self.dynamics.append({"id": self.next_dynamic_id, "kind": kind, "length": length,
                              "width": width, "trajectory": traj})
        self.next_dynamic_id += 1
        return t_appear + d_start / speed

    def add_lane_traffic(self, lane, count, speed, s_from, s_to, kind="adjacent_car",
                         min_headway=1.5):
        """Vehicles keeping `lane` at constant speed, spaced at least min_headway seconds."""
        rng = self.rng
        placed = 0
        s = s_from + rng.uniform(0.0, 15.0)
        while placed < count and s < s_to:
            length, width, _ = vehicle_size(rng, self.w)
            self.add_dynamic(kind, Motion(s + length / 2, speed, self.lane_l(lane)), length,
                             width)
            placed += 1
            s += length + 6.0 + speed * rng.uniform(min_headway, 3.5)
        return placed

    def ego_front_at(self, t, fastest=True):
        if fastest:
            s, v = ego_progress(S_EGO0, self.v0, self.limit, t)
        else:
            s, v = S_EGO0 + self.v0 * t, self.v0
        return s + self.front, v

    # ---- output -----------------------------------------------------------------------------
    def to_json(self):
        x, y, th, k = self.road.pose(S_EGO0)
        return {
            "format": "scene/1",
            "name": self.name,
            "tags": self.tags,
            "reference_line": self.road.polyline(2.0),
            "road": {"lane_width": self.w, "left_boundary": self.left_boundary,
                     "right_boundary": self.right_boundary,
                     "target_lane_offset": self.target_lane_offset,
                     "speed_limit": self.limit},
            "ego": {"x": round(x, 4), "y": round(y, 4), "heading": round(th, 6), "v": self.v0,
                    "a": 0.0, "kappa": round(k, 6), "length": self.ego_len,
                    "width": self.ego_wid, "wheelbase": self.ego_wb},
            "static_obstacles": self.statics,
            "dynamic_obstacles": self.dynamics,
            "duration": DURATION,
            "judge": {"archetype": self.archetype, "s_ego0": S_EGO0, "params": self.params},
        }


def piecewise_kappa(pieces):
    """kappa(s) from (length, kappa_start, kappa_end) pieces, linear within each."""
    starts, s = [], 0.0
    for length, k0, k1 in pieces:
        starts.append((s, length, k0, k1))
        s += length

    def kappa(s_query):
        for s0, length, k0, k1 in starts:
            if s_query <= s0 + length:
                return k0 + (k1 - k0) * (s_query - s0) / length
        return pieces[-1][2]
    return kappa


def boundary_value(boundary, s):
    from geom import boundary_at
    return boundary_at(boundary, s)


# --------------------------------------------------------------------------------------------
# Archetypes. Each returns a Scene; its solvability rule is in README.md.
# --------------------------------------------------------------------------------------------
def maybe_boundary_event(sc, allow_lane_end=True):
    """A third of the scenes get a boundary table: roadworks narrowing, a lane that ends or a
    lane that appears, on a side whose outer lane carries no actor."""
    rng = sc.rng
    if rng.random() > 0.35:
        return
    side = rng.choice(["left", "right"])
    outer = sc.n_lanes - 1 if side == "left" else 0
    s_start = S_EGO0 + rng.uniform(50.0, 220.0)
    if (outer != sc.ego_lane and outer not in sc.occupied_lanes and allow_lane_end
            and not sc.two_way):
        kind = rng.choice(["lane_end", "widening", "narrowing"])
        if kind in ("lane_end", "widening"):
            sc.set_boundary_event(kind, side, s_start, rng.uniform(40.0, 120.0), sc.w)
            sc.occupied_lanes.add(outer)      # background traffic stays out of it
            return
    # narrowing of the edge: the ego's lane keeps ego width + 0.8 m free
    room = sc.w - sc.ego_wid - 0.8 if outer == sc.ego_lane else sc.w - 2.6
    delta = min(rng.uniform(0.3, 1.0), room)
    if delta >= 0.2:
        sc.set_boundary_event("narrowing", side, s_start, rng.uniform(15.0, 40.0), delta)


def background_traffic(sc, max_vehicles=3):
    """Vehicles in free adjacent lanes that keep their lane (never enter the ego's)."""
    rng = sc.rng
    lanes = [j for j in sc.lanes_other_than_ego() if j not in sc.occupied_lanes]
    for lane in lanes:
        if rng.random() < 0.5:
            continue
        speed = round(sc.limit * rng.uniform(0.6, 1.0), 2)
        sc.add_lane_traffic(lane, rng.randint(1, max_vehicles), speed, S_EGO0 - 50.0,
                            S_EGO0 + 180.0)
        sc.occupied_lanes.add(lane)


def arch_free_road(sc):
    maybe_boundary_event(sc)
    background_traffic(sc)


def arch_lane_change(sc):
    """A requested lane change into a neighbour lane, with traffic in it leaving a gap."""
    rng = sc.rng
    options = [j for j in (sc.ego_lane - 1, sc.ego_lane + 1) if 0 <= j < sc.n_lanes]
    target = rng.choice(options)
    sc.target_lane_offset = sc.lane_l(target)
    sc.tags.append("lane_change_request")
    sc.occupied_lanes.add(target)
    # a vehicle ahead in the target lane at a comfortable gap
    if rng.random() < 0.6:
        v = round(sc.limit * rng.uniform(0.6, 1.0), 2)
        length, width, _ = vehicle_size(rng, sc.w)
        gap = follow_gap_needed(sc.limit, v) * rng.uniform(1.3, 2.5)
        s = S_EGO0 + sc.front + gap + length / 2
        sc.add_dynamic("target_lane_leader", Motion(s, v, sc.lane_l(target)), length, width)
    # a slower vehicle behind in the target lane, far enough to merge in front of it
    if rng.random() < 0.5 and sc.v0 > 5.0:
        v = round(sc.v0 * rng.uniform(0.5, 0.9), 2)
        length, width, _ = vehicle_size(rng, sc.w)
        s = S_EGO0 - sc.rear - rng.uniform(25.0, 50.0) - length / 2
        sc.add_dynamic("target_lane_follower", Motion(s, v, sc.lane_l(target)), length, width)
    sc.params["target_lane"] = target
    maybe_boundary_event(sc)
    background_traffic(sc, 2)


def arch_ego_lane_ends(sc):
    """The ego's lane ends (a taper ahead): the target lane is the neighbour."""
    rng = sc.rng
    side = "right" if sc.ego_lane == 0 else "left"
    target = 1 if side == "right" else sc.n_lanes - 2
    sc.target_lane_offset = sc.lane_l(target)
    s_start = S_EGO0 + max(stopping_distance(sc.limit), 60.0) + rng.uniform(0.0, 120.0)
    sc.set_boundary_event("lane_end", side, s_start, rng.uniform(50.0, 120.0), sc.w)
    sc.tags.append("ego_lane_ends")
    sc.occupied_lanes.add(target)
    if rng.random() < 0.5:
        v = round(sc.limit * rng.uniform(0.7, 1.0), 2)
        length, width, _ = vehicle_size(rng, sc.w)
        gap = follow_gap_needed(sc.limit, v) * rng.uniform(1.3, 2.0)
        sc.add_dynamic("target_lane_leader",
                       Motion(S_EGO0 + sc.front + gap + length / 2, v, sc.lane_l(target)),
                       length, width)
    sc.params["target_lane"] = target
    background_traffic(sc, 2)


def arch_breakdown(sc):
    """A stopped vehicle in the ego's lane, at least a comfortable stopping distance ahead."""
    rng = sc.rng
    length, width, _ = vehicle_size(rng, sc.w)
    d_min = stopping_distance(sc.v0) + 10.0
    d = rng.uniform(d_min, max(d_min + 20.0, 140.0))
    l = rng.uniform(-0.4, 0.4) * (sc.w - width)
    sc.add_static("stopped_vehicle", S_EGO0 + sc.front + d + length / 2, l, length, width,
                  rng.uniform(-0.08, 0.08))
    sc.occupied_lanes.add(sc.ego_lane)
    sc.params.update(distance=round(d, 1), rule_min_distance=round(d_min, 1))
    maybe_boundary_event(sc)
    background_traffic(sc, 2)


def arch_parked_cars(sc):
    """Parked cars at the road edge, intruding into the ego's lane (or the edge lane)."""
    rng = sc.rng
    side = rng.choice(["right", "left"]) if not sc.two_way else "right"
    edge_lane = 0 if side == "right" else sc.n_lanes - 1
    sign = -1.0 if side == "right" else 1.0
    edge = sc.l_right_edge if side == "right" else sc.l_left_edge
    kerb_parking = rng.random() < 0.5     # else a parking strip inside the drivable area
    if not kerb_parking:
        strip = 2.2
        if side == "right":
            sc.right_boundary -= strip
        else:
            sc.left_boundary += strip
        sc.tags.append("parking_strip")
    # intrusion into the edge lane; in a one-lane road the ego must still pass in it
    if sc.n_lanes == 1:
        max_intrusion = max(0.1, sc.w - sc.ego_wid - 0.9)
    else:
        max_intrusion = 1.3
    intrusion = rng.uniform(0.1, max_intrusion)
    count = rng.randint(1, 4)
    s = S_EGO0 + sc.front + stopping_distance(sc.v0) + rng.uniform(5.0, 60.0)
    for _ in range(count):
        length, width = round(rng.uniform(4.0, 5.0), 2), round(rng.uniform(1.7, 1.9), 2)
        # the car's inner side reaches `intrusion` into the lane
        l_inner = edge - sign * intrusion
        l = l_inner + sign * width / 2
        sc.add_static("parked_car", s + length / 2, l, length, width, rng.uniform(-0.05, 0.05))
        s += length + rng.uniform(2.0, 15.0)
    sc.occupied_lanes.add(edge_lane)
    sc.params.update(side=side, intrusion=round(intrusion, 2), count=count)
    maybe_boundary_event(sc, allow_lane_end=False)
    background_traffic(sc, 2)


def arch_debris(sc):
    """Small objects on the road, in the ego's lane or the next one."""
    rng = sc.rng
    count = rng.randint(1, 3)
    s = S_EGO0 + sc.front + stopping_distance(sc.v0) + rng.uniform(5.0, 60.0)
    lanes = [sc.ego_lane] + sc.lanes_other_than_ego()[:1]
    for _ in range(count):
        lane = rng.choice(lanes)
        size = rng.uniform(0.2, 1.0)
        l = sc.lane_l(lane) + rng.uniform(-0.3, 0.3) * sc.w
        sc.add_static("debris", s, l, round(size, 2), round(size * rng.uniform(0.5, 1.5), 2),
                      rng.uniform(-1.5, 1.5))
        sc.occupied_lanes.add(lane)
        s += rng.uniform(5.0, 40.0)
    sc.params.update(count=count)
    maybe_boundary_event(sc, allow_lane_end=False)
    background_traffic(sc, 2)


def place_leader(sc, v_lead, lead_decel=0.0, factor=(1.2, 2.5)):
    """Bumper gap from the ego to a leader starting ahead in the ego's lane."""
    v_ego = max(sc.v0, v_lead)
    gap = follow_gap_needed(v_ego, v_lead, lead_decel) * sc.rng.uniform(*factor)
    return max(gap, 8.0, time_gap_floor(v_ego))


def arch_slow_leader(sc):
    rng = sc.rng
    v = round(sc.limit * rng.uniform(0.2, 0.7), 2)
    length, width, _ = vehicle_size(rng, sc.w)
    gap = place_leader(sc, v)
    sc.add_dynamic("slow_leader", Motion(S_EGO0 + sc.front + gap + length / 2, v, 0.0),
                   length, width)
    sc.occupied_lanes.add(sc.ego_lane)
    sc.params.update(v_lead=v, gap=round(gap, 1))
    maybe_boundary_event(sc)
    background_traffic(sc, 2)


def arch_stop_and_go(sc):
    """A leader that brakes to a stop (1-3 m/s^2), waits, restarts; once or twice."""
    rng = sc.rng
    v = round(sc.limit * rng.uniform(0.4, 0.9), 2)
    decel = rng.uniform(1.0, 3.0)
    length, width, _ = vehicle_size(rng, sc.w)
    gap = place_leader(sc, v, decel)
    m = Motion(S_EGO0 + sc.front + gap + length / 2, v, 0.0)
    t = rng.uniform(1.5, 4.0)
    for _ in range(rng.randint(1, 2)):
        m.speed_to(t, decel, 0.0)
        t += v / decel + rng.uniform(1.0, 4.0)
        m.speed_to(t, rng.uniform(1.0, 2.0), v)
        t += rng.uniform(3.0, 5.0)
    sc.add_dynamic("stop_and_go_leader", m, length, width)
    sc.occupied_lanes.add(sc.ego_lane)
    sc.params.update(v_lead=v, decel=round(decel, 2), gap=round(gap, 1))
    maybe_boundary_event(sc)
    background_traffic(sc, 2)


def arch_hard_brake_leader(sc):
    """A leader at about the ego's speed brakes hard (4-6 m/s^2), to a stop or to a crawl."""
    rng = sc.rng
    v = round(max(sc.v0, 6.0) * rng.uniform(0.9, 1.05), 2)
    v = min(v, sc.limit)
    decel = rng.uniform(4.0, 6.0)
    length, width, _ = vehicle_size(rng, sc.w)
    # a reasonable driver keeps >= 1.8 s; the ego may also speed up to the limit before
    gap = max(place_leader(sc, v, decel, (1.1, 1.6)), 1.8 * max(sc.v0, v))
    t_brake = rng.uniform(2.0, 6.0)
    v_end = rng.choice([0.0, 0.0, round(v * 0.3, 2)])
    m = Motion(S_EGO0 + sc.front + gap + length / 2, v, 0.0).speed_to(t_brake, decel, v_end)
    sc.add_dynamic("hard_brake_leader", m, length, width)
    sc.occupied_lanes.add(sc.ego_lane)
    sc.params.update(v_lead=v, decel=round(decel, 2), gap=round(gap, 1), t_brake=round(t_brake, 1))
    background_traffic(sc, 2)


def cut_in_vehicle(sc, from_side, v_c, lc_start, lc_dur, then_brake=None, kind="cut_in"):
    """Places a vehicle in the neighbour lane on `from_side` so that, when its body first
    enters the ego's lane, its gap to the fastest and the constant-speed ego is at least the
    comfortable (or RSS-style, if it will brake) gap times a random factor > 1."""
    rng = sc.rng
    lane = sc.ego_lane + (1 if from_side == "left" else -1)
    l0 = sc.lane_l(lane)
    length, width, _ = vehicle_size(rng, sc.w)
    # time its near side crosses into the ego's lane (|l| - width/2 < w/2)
    t_in = lc_start
    m_probe = Motion(0.0, v_c, l0).lane_change(lc_start, lc_dur, 0.0)
    while t_in < lc_start + lc_dur:
        l, _ = m_probe.lateral(t_in)
        if abs(l) - width / 2 < sc.w / 2:
            break
        t_in += 0.05
    lead_decel = then_brake[1] if then_brake else 0.0
    needed = 0.0
    for fastest in (True, False):
        front, v_e = sc.ego_front_at(t_in, fastest)
        gap = cut_in_gap_needed(v_e, v_c, lead_decel)
        needed = max(needed, front + gap * rng.uniform(1.2, 1.8) - S_EGO0)
    s_at_in = S_EGO0 + needed + length / 2
    m = Motion(s_at_in - v_c * t_in, v_c, l0).lane_change(lc_start, lc_dur, 0.0)
    if then_brake:
        t_b, decel, v_end = then_brake
        m.speed_to(t_b, decel, v_end)
    sc.add_dynamic(kind, m, length, width)
    sc.occupied_lanes.update({lane, sc.ego_lane})
    return {"side": from_side, "v": v_c, "t_in": round(t_in, 2), "gap_at_in": round(needed, 1)}


def cut_in_sides(sc):
    sides = []
    if sc.ego_lane + 1 < sc.n_lanes and not sc.two_way:
        sides.append("left")
    if sc.ego_lane > 0:
        sides.append("right")
    return sides


def arch_cut_in(sc, brake=False):
    rng = sc.rng
    side = rng.choice(cut_in_sides(sc))
    v_c = round(min(sc.limit, max(3.0, max(sc.v0, 0.5 * sc.limit) * rng.uniform(0.6, 1.15))), 2)
    lc_start, lc_dur = rng.uniform(0.5, 4.0), rng.uniform(2.5, 4.5)
    then_brake = None
    if brake:
        decel = rng.uniform(2.0, 5.0)
        then_brake = (lc_start + lc_dur + rng.uniform(0.0, 1.5), decel, 0.0)
    info = cut_in_vehicle(sc, side, v_c, lc_start, lc_dur, then_brake,
                          "cut_in_brake" if brake else "cut_in")
    if then_brake:
        info["decel"] = round(then_brake[1], 2)
    sc.params.update(info)
    sc.tags.append("cut_in_" + side)
    background_traffic(sc, 2)


def arch_merge(sc):
    """The neighbour lane ends ahead; its vehicle merges into the ego's lane before the end."""
    rng = sc.rng
    side = rng.choice(cut_in_sides(sc))
    outer = sc.n_lanes - 1 if side == "left" else 0
    lane = sc.ego_lane + (1 if side == "left" else -1)
    if lane != outer:           # only an edge lane can end
        side = "right" if sc.ego_lane == 1 else "left"
        lane = sc.ego_lane + (1 if side == "left" else -1)
    v_c = round(min(sc.limit, max(4.0, max(sc.v0, 0.5 * sc.limit) * rng.uniform(0.7, 1.05))), 2)
    lc_start, lc_dur = rng.uniform(1.0, 5.0), rng.uniform(3.0, 5.0)
    info = cut_in_vehicle(sc, side, v_c, lc_start, lc_dur, kind="merging")
    # its lane ends after it has left: taper starts where it completes the merge
    merging = sc.dynamics[-1]
    end_s = S_EGO0 + info["gap_at_in"] + v_c * (lc_start + lc_dur - info["t_in"]) + 20.0
    sc.set_boundary_event("lane_end", side, end_s, rng.uniform(40.0, 90.0), sc.w)
    sc.params.update(info)
    sc.params["merging_id"] = merging["id"]
    sc.tags.append("merge_" + side)
    background_traffic(sc, 2)


def arch_overtaker(sc):
    """Faster vehicles coming up from behind in a neighbour lane and passing the ego."""
    rng = sc.rng
    lanes = sc.lanes_other_than_ego()
    lane = rng.choice([j for j in lanes if abs(j - sc.ego_lane) == 1] or lanes)
    count = rng.randint(1, 3)
    s = S_EGO0 - sc.rear - rng.uniform(15.0, 60.0)
    v = round(max(sc.v0, 2.0) + rng.uniform(3.0, 8.0), 2)
    for _ in range(count):
        # each one no faster than the one ahead of it: they never close up on each other
        v = round(max(max(sc.v0, 2.0) + 3.0, v - rng.uniform(0.0, 2.0)), 2)
        length, width, _ = vehicle_size(rng, sc.w)
        sc.add_dynamic("overtaker", Motion(s - length / 2, v, sc.lane_l(lane)), length, width)
        s -= length + rng.uniform(15.0, 40.0)
    sc.occupied_lanes.add(lane)
    sc.params.update(lane=lane, count=count)
    maybe_boundary_event(sc)
    background_traffic(sc, 2)


def oncoming_platoon(sc, s_ref, t_clear, t_next, count):
    """Oncoming cars in lane 1 that have all passed s_ref by t_clear; the next one reaches
    s_ref no earlier than t_next (the gap a driver uses to pass)."""
    rng = sc.rng
    v = round(sc.limit * rng.uniform(0.7, 1.0), 2)
    l = sc.lane_l(1)
    # the last platoon car's rear (its highest s) is 5 m past s_ref at t_clear; the ones
    # before it are further along (lower s)
    s_rear = s_ref - 5.0 + v * t_clear
    for _ in range(count):
        length, width, _ = vehicle_size(rng, sc.w)
        sc.add_dynamic("oncoming", Motion(s_rear - length / 2, v, l, direction=-1), length, width)
        s_rear -= length + 8.0 + v * rng.uniform(1.5, 2.5)
    if t_next is not None:
        length, width, _ = vehicle_size(rng, sc.w)
        sc.add_dynamic("oncoming", Motion(s_ref + v * t_next + length / 2, v, l, direction=-1),
                       length, width)
    return v


def arch_oncoming(sc, with_obstacle):
    """Two-way road: the left lane carries oncoming traffic. With an obstacle (a parked or
    broken-down car) in the ego's lane, passing it needs a gap in the oncoming stream."""
    rng = sc.rng
    if with_obstacle:
        length, width, _ = vehicle_size(rng, sc.w)
        d = stopping_distance(sc.v0) + rng.uniform(10.0, 60.0)
        s_obs = S_EGO0 + sc.front + d + length / 2
        l = -0.5 * sc.w + width / 2 + rng.uniform(-0.3, 0.3)   # at the right of the lane
        sc.add_static("parked_car", s_obs, l, length, width)
        t_clear = rng.uniform(0.0, 8.0)
        t_next = t_clear + rng.uniform(12.0, 18.0)
        v_onc = oncoming_platoon(sc, s_obs, t_clear, t_next, rng.randint(0, 3))
        sc.params.update(obstacle_distance=round(d, 1), gap_from=round(t_clear, 1),
                         gap_to=round(t_next, 1), v_oncoming=v_onc)
        sc.tags.append("pass_via_oncoming_lane")
    else:
        s_ref = S_EGO0 + rng.uniform(50.0, 200.0)
        oncoming_platoon(sc, s_ref, rng.uniform(2.0, 10.0), None, rng.randint(2, 5))
        if rng.random() < 0.5:
            arch_slow_leader_light(sc)


def arch_slow_leader_light(sc):
    rng = sc.rng
    v = round(sc.limit * rng.uniform(0.4, 0.8), 2)
    length, width, _ = vehicle_size(rng, sc.w)
    gap = place_leader(sc, v)
    sc.add_dynamic("slow_leader", Motion(S_EGO0 + sc.front + gap + length / 2, v, 0.0),
                   length, width)


def arch_crossing(sc, kind):
    """A pedestrian or cyclist crossing at 60-120 deg, appearing at t > 0 on the sidewalk,
    timed to meet an ego at constant speed, and never closer than the fastest ego's
    comfortable stopping distance when it appears."""
    rng = sc.rng
    if kind == "pedestrian":
        speed = round(rng.uniform(0.8, 2.0), 2)
        length, width = 0.5, 0.6
    else:
        speed = round(rng.uniform(3.0, 6.0), 2)
        length, width = 1.8, 0.7
    angle = math.radians(rng.uniform(60.0, 120.0))
    from_right = rng.random() < 0.5
    t_appear = round(rng.uniform(0.5, 4.0), 1)
    side_offset = rng.uniform(1.0, 3.0)
    edge = abs(sc.l_right_edge if from_right else sc.l_left_edge)
    t_to_centre = (edge + side_offset) / abs(math.sin(angle)) / speed
    # where the constant-speed ego's front is when the crosser is at the lane centre
    front_cv, _ = sc.ego_front_at(t_appear + t_to_centre, fastest=False)
    front_fast, v_fast = sc.ego_front_at(t_appear, fastest=True)
    # walking at an angle it reaches the ego's lane up to |edge| cot(angle) before s_cross
    slant = (edge + side_offset) * abs(1.0 / math.tan(angle))
    s_rule = front_fast + stopping_distance(v_fast) + length + slant
    s_cross = max(front_cv + rng.uniform(-2.0, 4.0), s_rule, S_EGO0 + sc.front + 15.0)
    sc.add_crossing(kind, s_cross, from_right, angle, speed, t_appear, length, width,
                    side_offset)
    sc.params.update(speed=speed, angle_deg=round(math.degrees(angle), 1),
                     from_right=from_right, t_appear=t_appear,
                     distance_at_appear=round(s_cross - front_fast, 1),
                     rule_min_distance=round(stopping_distance(v_fast) + length + slant, 1))
    sc.tags.append("crossing_from_" + ("right" if from_right else "left"))


def arch_dense_traffic(sc):
    """8-15 vehicles in lane flows: leaders in the ego's lane at safe gaps, neighbours ahead
    and behind keeping their lanes (more than the planner's 5 dynamic slots)."""
    rng = sc.rng
    target = rng.randint(8, 15)
    flows = {j: round(sc.limit * rng.uniform(0.5, 1.0), 2) for j in range(sc.n_lanes)}
    v = flows[sc.ego_lane]
    s = S_EGO0 + sc.front + place_leader(sc, v)
    for _ in range(rng.randint(1, 3)):           # a chain of leaders in the ego's lane
        length, width, _ = vehicle_size(rng, sc.w)
        sc.add_dynamic("dense_leader", Motion(s + length / 2, v, 0.0), length, width)
        s += length + 8.0 + v * rng.uniform(1.5, 3.0)
    slots = []                                   # free places in the other lanes' flows
    for lane in sc.lanes_other_than_ego():
        s = S_EGO0 - 70.0 + rng.uniform(0.0, 10.0)
        while s < S_EGO0 + 260.0:
            length, width, _ = vehicle_size(rng, sc.w)
            slots.append((lane, s + length / 2, length, width))
            s += length + 6.0 + flows[lane] * rng.uniform(1.2, 2.5)
    rng.shuffle(slots)
    for lane, s, length, width in slots[:max(0, target - len(sc.dynamics))]:
        sc.add_dynamic("dense_neighbour", Motion(s, flows[lane], sc.lane_l(lane)), length, width)
    sc.params.update(vehicles=len(sc.dynamics))


def arch_late_entry(sc):
    """Vehicles that enter the scene at t > 0: one joining the ego's lane ahead from a
    driveway (slow, beyond the fastest ego's stopping distance) and/or ones entering sensor
    range in a neighbour lane."""
    rng = sc.rng
    t_app = round(rng.uniform(1.0, 6.0), 1)
    front_fast, v_fast = sc.ego_front_at(t_app, fastest=True)
    v = round(sc.limit * rng.uniform(0.2, 0.6), 2)
    length, width, _ = vehicle_size(rng, sc.w)
    d = follow_gap_needed(v_fast, v) + stopping_distance(v_fast) * rng.uniform(0.2, 1.0)
    m = Motion(front_fast + d + length / 2, v, 0.0, t0=t_app)
    sc.add_dynamic("late_entry", m, length, width)
    sc.occupied_lanes.add(sc.ego_lane)
    others = [j for j in sc.lanes_other_than_ego() if j not in sc.occupied_lanes]
    if others and rng.random() < 0.7:
        lane = rng.choice(others)
        t2 = round(rng.uniform(1.0, 8.0), 1)
        v2 = round(sc.limit * rng.uniform(0.6, 1.1), 2)
        length, width, _ = vehicle_size(rng, sc.w)
        s2 = S_EGO0 + rng.choice([-1, 1]) * rng.uniform(60.0, 120.0) + v2 * t2
        sc.add_dynamic("late_entry", Motion(s2, v2, sc.lane_l(lane), t0=t2), length, width)
        sc.occupied_lanes.add(lane)
    sc.params.update(t_appear=t_app, distance_at_appear=round(d, 1))


# --------------------------------------------------------------------------------------------
# The mix: (name, weight, builder) — builder(rng, name) -> Scene
# --------------------------------------------------------------------------------------------
def simple(archetype, body, **scene_kw):
    def build(rng, name):
        sc = Scene(rng, name, archetype, **scene_kw)
        body(sc)
        return sc
    return build


def multi_lane(archetype, body, min_lanes=2):
    def build(rng, name):
        sc = Scene(rng, name, archetype, lanes=rng.randint(min_lanes, 4))
        body(sc)
        return sc
    return build


def edge_lane(archetype, body):
    def build(rng, name):
        n = rng.randint(2, 4)
        sc = Scene(rng, name, archetype, lanes=n, ego_lane=rng.choice([0, n - 1]))
        body(sc)
        return sc
    return build


def with_speed(archetype, body, v_min, lanes_min=1):
    """Archetypes about motion need a moving ego."""
    def build(rng, name):
        limit = round(rng.uniform(max(v_min + 2, 5.0), 33.0), 2)
        sc = Scene(rng, name, archetype, lanes=rng.randint(lanes_min, 4), limit=limit,
                   v0=round(rng.uniform(v_min, limit), 2))
        body(sc)
        return sc
    return build


def two_way(archetype, body):
    def build(rng, name):
        limit = round(rng.uniform(8.0, 25.0), 2)
        sc = Scene(rng, name, archetype, lanes=2, ego_lane=0, two_way=True, limit=limit)
        body(sc)
        return sc
    return build


def cut_in_build(archetype, brake):
    def build(rng, name):
        limit = round(rng.uniform(8.0, 33.0), 2)
        sc = Scene(rng, name, archetype, lanes=rng.randint(2, 4), limit=limit,
                   v0=round(rng.uniform(0.3 * limit, limit), 2))
        arch_cut_in(sc, brake)
        return sc
    return build


def merge_build(rng, name):
    n = rng.randint(2, 4)
    ego_lane = rng.choice([1, n - 2]) if n >= 3 else rng.choice([0, 1])
    limit = round(rng.uniform(8.0, 30.0), 2)
    sc = Scene(rng, name, "merge", lanes=n, ego_lane=ego_lane, limit=limit,
               v0=round(rng.uniform(0.3 * limit, limit), 2))
    arch_merge(sc)
    return sc


def crossing_build(kind):
    def build(rng, name):
        limit = round(rng.uniform(5.0, 17.0), 2)   # urban roads
        sc = Scene(rng, name, kind + "_crossing", lanes=rng.choice([1, 2, 2, 3]), limit=limit)
        arch_crossing(sc, kind)
        return sc
    return build


ARCHETYPES = [
    ("free_road", 1.0, simple("free_road", arch_free_road)),
    ("lane_change", 1.0, multi_lane("lane_change", arch_lane_change)),
    ("ego_lane_ends", 0.8, edge_lane("ego_lane_ends", arch_ego_lane_ends)),
    ("breakdown", 1.0, simple("breakdown", arch_breakdown)),
    ("parked_cars", 1.0, simple("parked_cars", arch_parked_cars)),
    ("debris", 0.8, simple("debris", arch_debris)),
    ("slow_leader", 1.0, with_speed("slow_leader", arch_slow_leader, 3.0)),
    ("stop_and_go", 1.0, with_speed("stop_and_go", arch_stop_and_go, 3.0)),
    ("hard_brake_leader", 1.0, with_speed("hard_brake_leader", arch_hard_brake_leader, 6.0)),
    ("cut_in", 1.0, cut_in_build("cut_in", False)),
    ("cut_in_brake", 1.0, cut_in_build("cut_in_brake", True)),
    ("merge", 0.8, merge_build),
    ("overtaker", 1.0, with_speed("overtaker", arch_overtaker, 0.0, lanes_min=2)),
    ("oncoming", 0.6, two_way("oncoming", lambda sc: arch_oncoming(sc, False))),
    ("oncoming_pass", 1.0, two_way("oncoming_pass", lambda sc: arch_oncoming(sc, True))),
    ("pedestrian_crossing", 1.0, crossing_build("pedestrian")),
    ("cyclist_crossing", 0.8, crossing_build("cyclist")),
    ("dense_traffic", 1.0, with_speed("dense_traffic", arch_dense_traffic, 3.0, lanes_min=3)),
    ("late_entry", 0.8, with_speed("late_entry", arch_late_entry, 0.0)),
]


# --------------------------------------------------------------------------------------------
# Stress set: >= 10 static + >= 5 moving on a wide road
# --------------------------------------------------------------------------------------------
def stress_build(rng, name):
    """4 lanes with shoulders; the ego in lane 1. Parked cars on both shoulders, debris and a
    breakdown in lane 0 far ahead, leaders in the ego's lane, traffic in lanes 2-3,
    sometimes a pedestrian crossing ahead."""
    limit = round(rng.uniform(10.0, 25.0), 2)
    sc = Scene(rng, name, "stress", lanes=4, ego_lane=1, limit=limit,
               v0=round(rng.uniform(0.3 * limit, limit), 2))
    shoulder = 2.5
    sc.right_boundary -= shoulder
    sc.left_boundary += shoulder
    s = S_EGO0 + sc.front + stopping_distance(sc.v0)
    for side in ("right", "left"):
        pos = s + rng.uniform(0.0, 20.0)
        for _ in range(rng.randint(4, 5)):
            length, width = round(rng.uniform(4.0, 5.0), 2), round(rng.uniform(1.7, 1.9), 2)
            if side == "right":
                l = sc.l_right_edge - shoulder + width / 2 + rng.uniform(0.0, 0.4)
            else:
                l = sc.l_left_edge + shoulder - width / 2 - rng.uniform(0.0, 0.4)
            sc.add_static("parked_car", pos + length / 2, l, length, width)
            pos += length + rng.uniform(3.0, 25.0)
    lane0 = sc.lane_l(0)
    pos = s + rng.uniform(20.0, 60.0)
    sc.add_static("stopped_vehicle", pos, lane0, 4.6, 1.8)
    for _ in range(rng.randint(1, 2)):
        pos += rng.uniform(8.0, 30.0)
        sc.add_static("debris", pos, lane0 + rng.uniform(-0.8, 0.8), 0.6, 0.5,
                      rng.uniform(-1, 1))
    sc.occupied_lanes.update({0, 1})
    v_lead = round(limit * rng.uniform(0.5, 0.9), 2)
    length, width, _ = vehicle_size(rng, sc.w)
    gap = place_leader(sc, v_lead)
    sc.add_dynamic("slow_leader", Motion(S_EGO0 + sc.front + gap + length / 2, v_lead, 0.0),
                   length, width)
    for lane in (2, 3):
        sc.add_lane_traffic(lane, rng.randint(2, 4), round(limit * rng.uniform(0.6, 1.0), 2),
                            S_EGO0 - 50.0, S_EGO0 + 200.0, "adjacent_car")
    sc.params.update(statics=len(sc.statics), dynamics=len(sc.dynamics))
    return sc


# --------------------------------------------------------------------------------------------
# Driver
# --------------------------------------------------------------------------------------------
def pick_archetypes(rng, count):
    """Deterministic, balanced: every archetype in proportion to its weight, order shuffled."""
    total = sum(w for _, w, _ in ARCHETYPES)
    plan = []
    for name, w, build in ARCHETYPES:
        plan += [(name, build)] * max(1, int(round(count * w / total)))
    rng.shuffle(plan)
    while len(plan) < count:
        plan.append(rng.choice([(n, b) for n, _, b in ARCHETYPES]))
    return plan[:count]


def generate_one(seed, index, name, build, max_tries=30):
    """Build, check; on a failed check retry from the next sub-seed. Returns (scene, tries)."""
    for attempt in range(max_tries):
        rng = random.Random("%d/%d/%d" % (seed, index, attempt))
        sc = build(rng, name)
        scene = sc.to_json()
        problems = check_scenes.check_scene(scene)
        if not problems:
            scene["judge"]["attempts"] = attempt + 1
            return scene, attempt + 1
        last = problems
    raise RuntimeError("%s: no valid scene after %d tries: %s" % (name, max_tries, last))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--count", type=int, default=100)
    ap.add_argument("--set", choices=["mix", "stress"], default="mix")
    ap.add_argument("--out", required=True)
    ap.add_argument("--only", help="comma-separated archetypes (mix set only)")
    args = ap.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    rng = random.Random(args.seed * 7919 + (1 if args.set == "stress" else 0))
    if args.set == "stress":
        plan = [("stress", stress_build)] * args.count
    else:
        archetypes = ARCHETYPES
        if args.only:
            keep = set(args.only.split(","))
            archetypes = [a for a in ARCHETYPES if a[0] in keep]
        globals()["ARCHETYPES"] = archetypes
        plan = pick_archetypes(rng, args.count)
    retries = {}
    for i, (arch, build) in enumerate(plan):
        name = "judge-s%d-%s-%03d-%s" % (args.seed, args.set, i, arch)
        scene, tries = generate_one(args.seed * 100003 + (7 if args.set == "stress" else 0),
                                       i, name, build)
        retries[arch] = retries.get(arch, 0) + tries - 1
        with open(os.path.join(args.out, name + ".json"), "w") as f:
            json.dump(scene, f, separators=(",", ":"))
    print("wrote %d scenes to %s (regenerated after a failed check: %s)"
          % (len(plan), args.out, json.dumps({k: v for k, v in retries.items() if v})))


if __name__ == "__main__":
    main()
