#!/usr/bin/env python3
"""Self-check of judge scenes: format, no obstacle overlaps, and solvability witnesses.

Independent of the generator's internals: it reads only the scene/1 JSON (plus the recorded
rule numbers in the optional "judge" object) and uses its own geometry (geom.py, SAT).

Witnesses (a scene fails if any fails):
  * careful driver: keeps the lane centre, IDM car-following towards the speed limit, braking
    for anything whose footprint is (or within 2-3 s will be) in its corridor, and for the end
    of its lane. Must finish without contact and without a bumper gap under 1 m, braking at
    most 4.5 m/s^2 (6 m/s^2 in archetypes whose point is a hard-braking leader);
  * constant-speed lane keeper: may run into things, but must never be hit (nothing rear-ends
    or side-swipes an ego that keeps its lane at constant speed);
  * recorded rules: distances at appearance >= the stopping-distance rule etc.

    python3 check_scenes.py DIR_OR_FILES...
"""
import glob
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from geom import (Box, Polyline, boundary_at, boxes_overlap, classify_contact,  # noqa: E402
                  ego_box, obstacle_boxes_at)

STEP = 0.1
HARD_BRAKE_ARCHETYPES = {"hard_brake_leader", "cut_in_brake"}
VRU_KINDS = {"pedestrian", "cyclist"}

# IDM parameters of the careful driver
IDM_ACCEL, IDM_DECEL, IDM_HEADWAY, IDM_MIN_GAP = 2.0, 2.5, 1.2, 2.5
MAX_BRAKE = 6.0


class RoadFrame:
    """The scene's reference line with arc-length sampled poses for the witnesses."""

    def __init__(self, scene):
        self.line = Polyline(scene["reference_line"])
        self.scene = scene

    def pose(self, s, l=0.0):
        p, cum = self.line.p, self.line.cum
        i = 0
        lo, hi = 0, len(cum) - 2
        while lo <= hi:                       # last segment whose start <= s
            mid = (lo + hi) // 2
            if cum[mid] <= s:
                i, lo = mid, mid + 1
            else:
                hi = mid - 1
        (ax, ay), (bx, by) = p[i], p[i + 1]
        seg = cum[i + 1] - cum[i]
        th = math.atan2(by - ay, bx - ax)
        f = (s - cum[i]) / seg
        x, y = ax + f * (bx - ax), ay + f * (by - ay)
        return x - l * math.sin(th), y + l * math.cos(th), th


def frenet_extent(frame, box, vx, vy, hint):
    """(s, l, half_s, half_l, v_s, v_l, segment) of a box in the road frame."""
    s, l, th, seg = frame.line.project(box.cx, box.cy, hint)
    d = box.heading - th
    half_s = abs(box.length / 2 * math.cos(d)) + abs(box.width / 2 * math.sin(d))
    half_l = abs(box.length / 2 * math.sin(d)) + abs(box.width / 2 * math.cos(d))
    c, sn = math.cos(th), math.sin(th)
    return s, l, half_s, half_l, vx * c + vy * sn, -vx * sn + vy * c, seg


def lane_end_wall(scene, s_from, half_width):
    """First s ahead where the drivable area no longer holds the ego at l = 0 (lane ends)."""
    road = scene["road"]
    s = s_from
    end = Polyline(scene["reference_line"]).cum[-1]
    while s < end:
        if (boundary_at(road["right_boundary"], s) > -half_width or
                boundary_at(road["left_boundary"], s) < half_width):
            return s
        s += 1.0
    return None


def idm(v, v_des, gap, v_lead):
    free = 1.0 - (v / max(v_des, 0.1)) ** 4
    if gap is None:
        return free * IDM_ACCEL
    s_star = IDM_MIN_GAP + max(0.0, v * IDM_HEADWAY + v * (v - v_lead) /
                               (2.0 * math.sqrt(IDM_ACCEL * IDM_DECEL)))
    return IDM_ACCEL * (free - (s_star / max(gap, 0.1)) ** 2)


def run_witness(scene, careful=True):
    """Drive the ego's lane centre. careful=True: IDM; else constant initial speed.
    Returns a dict of outcomes."""
    frame = RoadFrame(scene)
    ego = scene["ego"]
    length, width, wb = ego["length"], ego["width"], ego["wheelbase"]
    front = 0.5 * (length + wb)
    s, l0, _, _ = frame.line.project(ego["x"], ego["y"])
    v, v_des = ego["v"], scene["road"]["speed_limit"]
    wall = lane_end_wall(scene, s, width / 2 + 0.1) if careful else None
    duration = scene.get("duration", 12.0)
    hints, prev_boxes, me_prev = {}, {}, None
    out = {"contact": None, "min_gap": None, "peak_brake": 0.0}
    t = 0.0
    while t <= duration + 1e-9:
        x, y, th = frame.pose(s)
        me = ego_box(x, y, th, length, width, wb)
        me_v = (v * math.cos(th), v * math.sin(th))
        leader_gap, leader_v = None, 0.0
        if wall is not None:
            leader_gap = wall - (s + front)
        for oid, kind, box, vx, vy in obstacle_boxes_at(scene, t):
            if abs(box.cx - me.cx) > 200 or abs(box.cy - me.cy) > 200:
                continue
            if boxes_overlap(me, box) and out["contact"] is None:
                out["contact"] = dict(classify_contact(me, me_v, box, (vx, vy), me_prev,
                                                       prev_boxes.get(oid)),
                                      t=round(t, 1), obstacle=oid, kind=kind)
            prev_boxes[oid] = box
            if not careful:
                continue
            os_, ol, hs, hl, vs, vl, seg = frenet_extent(frame, box, vx, vy, hints.get(oid))
            hints[oid] = seg
            horizon = 3.0 if kind in VRU_KINDS else 2.0
            lo = ol - hl + min(0.0, vl * horizon)
            hi = ol + hl + max(0.0, vl * horizon)
            corridor = width / 2 + 0.4
            if hi < -corridor or lo > corridor or os_ + hs < s:
                continue
            gap = os_ - hs - (s + front)
            if gap < 0.0 and os_ - hs < s:   # alongside or behind: not a leader
                continue
            if leader_gap is None or gap < leader_gap:
                leader_gap, leader_v = gap, max(0.0, vs)
            if abs(ol) - hl < width / 2 and (out["min_gap"] is None or gap < out["min_gap"]):
                out["min_gap"] = gap
        me_prev = me
        if careful:
            a = max(-MAX_BRAKE, min(IDM_ACCEL, idm(v, v_des, leader_gap, leader_v)))
            if v <= 0.0 and a < 0.0:
                a = 0.0
            out["peak_brake"] = max(out["peak_brake"], -a if v > 0.0 else 0.0)
        else:
            a = 0.0
        v_new = max(0.0, v + a * STEP)
        s += 0.5 * (v + v_new) * STEP
        v = v_new
        t += STEP
    return out


def statics_passable(scene, clearance=0.3):
    """True when every static obstacle ahead leaves a lateral gap of ego width + 2 clearance
    between the road edges and the other statics beside it (a car can pass, possibly using
    another lane); False means the scene's road is blocked by design (stopping is right)."""
    frame = RoadFrame(scene)
    ego = scene["ego"]
    need = ego["width"] + 2 * clearance
    road = scene["road"]
    items = []
    for o in scene.get("static_obstacles", []):
        box = Box(o["x"], o["y"], o["heading"], o["length"], o["width"])
        s, l, hs, hl, _, _, _ = frenet_extent(frame, box, 0.0, 0.0, None)
        items.append((s - hs, s + hs, l - hl, l + hl))
    for s_lo, s_hi, _, _ in items:
        lo_s, hi_s = s_lo - ego["length"], s_hi + ego["length"]
        ss = [lo_s + k * (hi_s - lo_s) / 10 for k in range(11)]
        left = min(boundary_at(road["left_boundary"], s) for s in ss)
        edge = max(boundary_at(road["right_boundary"], s) for s in ss)
        beside = sorted((a, b) for s0, s1, a, b in items if s1 >= lo_s and s0 <= hi_s)
        ok = False
        for a, b in beside:
            if a - edge >= need:
                ok = True
                break
            edge = max(edge, b)
        if not ok and left - edge < need:
            return False
    return True


def check_format(scene):
    problems = []
    for key in ("format", "reference_line", "road", "ego"):
        if key not in scene:
            problems.append("missing " + key)
    if scene.get("format") != "scene/1":
        problems.append("format is not scene/1")
    road = scene["road"]
    for side in ("left_boundary", "right_boundary"):
        b = road[side]
        if isinstance(b, list):
            ss = [p[0] for p in b]
            if any(b1 <= b0 for b0, b1 in zip(ss, ss[1:])):
                problems.append(side + " not ascending")
            if len(b) > 32:
                problems.append(side + " has more than 32 knots")
    if not 2.0 <= road["lane_width"] <= 6.0:
        problems.append("lane width out of range")
    if not 0.0 <= scene["ego"]["v"] <= road["speed_limit"] + 1e-6:
        problems.append("ego speed outside [0, limit]")
    ids = [o["id"] for o in scene.get("static_obstacles", []) + scene.get("dynamic_obstacles", [])]
    if len(ids) != len(set(ids)):
        problems.append("duplicate obstacle ids")
    for o in scene.get("dynamic_obstacles", []):
        ts = [p["t"] for p in o["trajectory"]]
        if any(b <= a for a, b in zip(ts, ts[1:])):
            problems.append("obstacle %d: t not ascending" % o["id"])
    line = Polyline(scene["reference_line"])
    for (ax, ay), (bx, by), (cx, cy) in zip(line.p, line.p[1:], line.p[2:]):
        turn = abs(math.atan2((bx - ax) * (cy - by) - (by - ay) * (cx - bx),
                              (bx - ax) * (cx - bx) + (by - ay) * (cy - by)))
        if turn > math.radians(30):
            problems.append("reference line turns sharply")
            break
    return problems


def check_obstacles_apart(scene):
    """No two obstacles may touch at any time (the world itself must be collision-free)."""
    duration = scene.get("duration", 12.0)
    t = 0.0
    while t <= duration + 1e-9:
        boxes = obstacle_boxes_at(scene, t)
        for i in range(len(boxes)):
            for j in range(i + 1, len(boxes)):
                a, b = boxes[i][2], boxes[j][2]
                if abs(a.cx - b.cx) > 25 or abs(a.cy - b.cy) > 25:
                    continue
                if boxes_overlap(a.inflated(0.2, 0.1), b.inflated(0.2, 0.1)):
                    return ["obstacles %d and %d touch at t=%.1f" % (boxes[i][0], boxes[j][0], t)]
        t += 0.2
    return []


def check_recorded_rules(scene):
    params = scene.get("judge", {}).get("params", {})
    problems = []
    if "rule_min_distance" in params:
        d = params.get("distance_at_appear", params.get("distance"))
        if d is not None and d + 1e-6 < params["rule_min_distance"]:
            problems.append("distance %.1f below rule %.1f" % (d, params["rule_min_distance"]))
    if "gap_from" in params and params["gap_to"] - params["gap_from"] < 12.0 - 1e-6:
        problems.append("oncoming gap shorter than 12 s")
    return problems


def check_scene(scene):
    """List of problems; empty when the scene is valid and solvable by the witnesses."""
    problems = check_format(scene) + check_recorded_rules(scene) + check_obstacles_apart(scene)
    if problems:
        return problems
    archetype = scene.get("judge", {}).get("archetype", "")
    careful = run_witness(scene, careful=True)
    if careful["contact"]:
        problems.append("careful driver touches %s" % careful["contact"])
    if careful["min_gap"] is not None and careful["min_gap"] < 1.0:
        problems.append("careful driver gap %.2f m" % careful["min_gap"])
    brake_cap = 6.0 if archetype in HARD_BRAKE_ARCHETYPES else 4.5
    if careful["peak_brake"] > brake_cap + 1e-6:
        problems.append("careful driver brakes %.1f m/s^2" % careful["peak_brake"])
    steady = run_witness(scene, careful=False)
    if steady["contact"] and steady["contact"]["who"] == "hit":
        problems.append("constant-speed lane keeper is hit: %s" % steady["contact"])
    scene.setdefault("judge", {})["witness"] = {
        "careful_peak_brake": round(careful["peak_brake"], 2),
        "careful_min_gap": None if careful["min_gap"] is None else round(careful["min_gap"], 2),
        "statics_passable": statics_passable(scene)}
    return problems


def main(argv):
    files = []
    for arg in argv or ["."]:
        files += sorted(glob.glob(os.path.join(arg, "*.json"))) if os.path.isdir(arg) else [arg]
    bad = 0
    for path in files:
        with open(path) as f:
            scene = json.load(f)
        problems = check_scene(scene)
        if problems:
            bad += 1
            print("%s: %s" % (os.path.basename(path), "; ".join(problems)))
    print("%d scenes checked, %d with problems" % (len(files), bad))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
