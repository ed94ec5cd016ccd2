#!/usr/bin/env python3
"""Is any collision-free motion left along the ego's lane?

For a scene/1 file (or one planning instant of it), the set of states (s, v) the ego can reach
while it follows its reference line at a fixed lateral offset, within its acceleration limits,
without its footprint touching any obstacle's true box at any step. The set is propagated
forward in time and *over*-approximated at every step (speed bins, a free set read from sampled
footprints with the gaps between samples given to the ego), so when it runs empty no motion of
that family exists: a collision there is unavoidable for any planner that stays in the lane.

Written from FORMATS.md with the judge's own geometry (geom.py); it shares no code with the
planner or hil_sim.

  python3 escape.py SCENE.json [--offsets -0.5,0,0.5] [--a-min -6] [--a-max 3] [--json OUT]
"""
import argparse
import bisect
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from geom import Box, Polyline, boxes_overlap, ego_box, obstacle_boxes_at  # noqa: E402


class LanePath:
    """The rear axle's path: the reference polyline shifted by a fixed lateral offset; the
    heading of the chord it is on (the box follows the lane)."""

    def __init__(self, points, offset):
        self.line = Polyline(points)
        self.offset = offset

    def pose(self, s):
        p, cum = self.line.p, self.line.cum
        # the segment holding s (the first and last extended)
        i = min(max(bisect.bisect_right(cum, s) - 1, 0), len(p) - 2)
        (ax, ay), (bx, by) = p[i], p[i + 1]
        seg = max(cum[i + 1] - cum[i], 1e-9)
        f = (s - cum[i]) / seg
        th = math.atan2(by - ay, bx - ax)
        x, y = ax + f * (bx - ax), ay + f * (by - ay)
        return x - self.offset * math.sin(th), y + self.offset * math.cos(th), th


def merge(intervals):
    out = []
    for lo, hi in sorted(intervals):
        if out and lo <= out[-1][1]:
            out[-1][1] = max(out[-1][1], hi)
        else:
            out.append([lo, hi])
    return out


def intersect(a, b):
    """Intersection of two sorted, disjoint interval lists."""
    out, i, j = [], 0, 0
    while i < len(a) and j < len(b):
        lo, hi = max(a[i][0], b[j][0]), min(a[i][1], b[j][1])
        if lo <= hi:
            out.append([lo, hi])
        if a[i][1] < b[j][1]:
            i += 1
        else:
            j += 1
    return out


def blocked_intervals(path, ego, boxes, s_lo, s_hi, ds):
    """Per obstacle, the runs of sampled s where the ego's footprint overlaps its box, as
    [first, last] sample: inside the true blocked set wherever that set is an interval (a
    convex box along a lane), so what is left free is a superset of the truly free s."""
    reach = math.hypot(ego["length"], ego["width"]) / 2 + ego["wheelbase"] / 2
    n = int(math.ceil((s_hi - s_lo) / ds)) + 1
    poses = [path.pose(s_lo + k * ds) for k in range(n)]
    out = []
    for oid, _kind, box, _vx, _vy in boxes:
        r = reach + math.hypot(box.length, box.width) / 2
        run = None
        for k, (x, y, th) in enumerate(poses):
            hit = (math.hypot(x - box.cx, y - box.cy) <= r and
                   boxes_overlap(ego_box(x, y, th, ego["length"], ego["width"], ego["wheelbase"]),
                                 box))
            s = s_lo + k * ds
            if hit and run is None:
                run = [s, s, oid]
            elif hit:
                run[1] = s
            elif run is not None:
                out.append(run)
                run = None
        if run is not None:
            out.append(run)
    return out


def free_set(blocked, s_lo, s_hi):
    free, at = [], s_lo
    for lo, hi, _ in sorted(blocked):
        if lo > at:
            free.append([at, lo])
        at = max(at, hi)
    if at < s_hi:
        free.append([at, s_hi])
    return free


def ego_offset(scene):
    """The ego's lateral offset from its reference line (rear axle)."""
    _s, l_ego, _th, _ = Polyline(scene["reference_line"]).project(scene["ego"]["x"], scene["ego"]["y"])
    return l_ego


def escape(scene, offset, a_min=-6.0, a_max=3.0, v_max=None, dt=0.1, dv=0.02, ds=0.02,
           horizon=None, t0=0.0):
    """Propagate the reachable, collision-free (s, v) set from the ego's state at t0 along the
    lane at `offset` from the reference line. Returns a dict: `empty_at` (first time with no
    state left, None if some motion survives the horizon), `blockers` (ids whose boxes bound
    the set in its last non-empty step), `steps`, and the last reachable s and v ranges."""
    ego = scene["ego"]
    path = LanePath(scene["reference_line"], offset)
    s0, _l0, _th, _ = path.line.project(ego["x"], ego["y"])
    v0 = max(0.0, ego["v"])
    if v_max is None:
        v_max = max(v0, scene.get("road", {}).get("speed_limit", 30.0)) + 1.0
    if horizon is None:
        horizon = scene.get("duration", 12.0) - t0
    nv = int(math.ceil(v_max / dv)) + 1
    # states: speed bin j (speeds in [j dv, (j + 1) dv]) -> [v_lo, v_hi, [[s_lo, s_hi], ...]]:
    # the speeds actually reached in the bin, so the top bin does not round up every step
    states = {min(int(v0 / dv), nv - 1): [v0, v0, [[s0, s0]]]}
    steps = int(round(horizon / dt))
    last = {"t": t0, "s": [s0, s0], "v": [v0, v0], "blockers": []}
    for k in range(1, steps + 1):
        t = t0 + k * dt
        nxt = {}
        for _j, (v_lo, v_hi, ivs) in states.items():
            r_lo = max(0.0, v_lo + a_min * dt)  # speeds reachable with a in [a_min, a_max]
            r_hi = min(v_max, v_hi + a_max * dt)
            for jt in range(int(r_lo / dv), min(nv - 1, int(r_hi / dv)) + 1):
                w_lo, w_hi = max(r_lo, jt * dv), min(r_hi, (jt + 1) * dv)
                if w_lo > w_hi:
                    continue
                # constant a over the step: displacement (v + v') dt / 2; a stop inside the
                # step only shortens it, hence the lower bound 0 where v' can be 0
                d_lo = 0.0 if w_lo <= 0.0 else 0.5 * (v_lo + w_lo) * dt
                d_hi = 0.5 * (v_hi + w_hi) * dt
                entry = nxt.setdefault(jt, [w_lo, w_hi, []])
                entry[0], entry[1] = min(entry[0], w_lo), max(entry[1], w_hi)
                entry[2].extend([lo + d_lo, hi + d_hi] for lo, hi in ivs)
        if not nxt:
            break
        s_lo = min(iv[0] for _, _, ivs in nxt.values() for iv in ivs)
        s_hi = max(iv[1] for _, _, ivs in nxt.values() for iv in ivs)
        blocked = blocked_intervals(path, ego, obstacle_boxes_at(scene, t), s_lo - ds, s_hi + ds, ds)
        free = free_set(blocked, s_lo - ds, s_hi + ds)
        states = {}
        for jt, (w_lo, w_hi, ivs) in nxt.items():
            kept = intersect(merge(ivs), free)
            if kept:
                states[jt] = [w_lo, w_hi, kept]
        if not states:
            near = sorted({oid for lo, hi, oid in blocked if hi >= s_lo - 1.0 and lo <= s_hi + 1.0})
            return {"offset": offset, "empty_at": round(t, 3), "blockers": near, "steps": k,
                    "last": last}
        last = {"t": round(t, 3),
                "s": [round(min(iv[0] for _, _, ivs in states.values() for iv in ivs) - s0, 3),
                      round(max(iv[1] for _, _, ivs in states.values() for iv in ivs) - s0, 3)],
                "v": [round(min(e[0] for e in states.values()), 3),
                      round(max(e[1] for e in states.values()), 3)],
                "blockers": sorted({oid for _, _, oid in blocked})}
    return {"offset": offset, "empty_at": None, "blockers": [], "steps": steps, "last": last}


def _point_segment(p, a, b):
    dx, dy = b[0] - a[0], b[1] - a[1]
    n2 = dx * dx + dy * dy
    f = 0.0 if n2 == 0.0 else max(0.0, min(1.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / n2))
    return math.hypot(p[0] - a[0] - f * dx, p[1] - a[1] - f * dy)


def box_distance(a, b):
    """Distance between two oriented boxes, 0 when they overlap (for disjoint convex polygons
    the nearest pair has a corner of one on an edge of the other)."""
    if boxes_overlap(a, b):
        return 0.0
    ca, cb = a.corners(), b.corners()
    return min(_point_segment(p, q[i], q[(i + 1) % 4])
               for p_set, q in ((ca, cb), (cb, ca)) for p in p_set for i in range(4))


def drive(scene, offset, accel, start, dt=0.02, horizon=None):
    """Exact replay of one motion along the lane: standing (or rolling at the ego's speed)
    until `start`, then `accel` up to the speed limit. Returns (first contact or None,
    {obstacle id: (smallest distance, t)})."""
    ego = scene["ego"]
    path = LanePath(scene["reference_line"], offset)
    s, _l, _th, _ = path.line.project(ego["x"], ego["y"])
    v, t = max(0.0, ego["v"]), 0.0
    limit = scene.get("road", {}).get("speed_limit", 30.0)
    horizon = scene.get("duration", 12.0) if horizon is None else horizon
    nearest = {}
    while t < horizon - 1e-9:
        a = accel if t >= start and v < limit else 0.0
        v_next = min(limit, max(0.0, v + a * dt))
        s += 0.5 * (v + v_next) * dt
        v, t = v_next, t + dt
        x, y, th = path.pose(s)
        me = ego_box(x, y, th, ego["length"], ego["width"], ego["wheelbase"])
        for oid, _kind, box, _vx, _vy in obstacle_boxes_at(scene, t):
            d = box_distance(me, box)
            if d == 0.0:
                return (round(t, 2), oid), nearest
            if d < nearest.get(oid, (math.inf,))[0]:
                nearest[oid] = (round(d, 2), round(t, 2))
    return None, nearest


def best_witness(scene, offset, accels=(0.5, 1.0, 1.5, 2.0, 2.5, 3.0),
                 starts=(0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0)):
    """The collision-free `drive` with the largest smallest distance to any obstacle, as
    (accel, start, smallest distance, {id: (distance, t)}), or None."""
    best = None
    for a in accels:
        for t0 in starts:
            contact, nearest = drive(scene, offset, a, t0)
            if contact is not None:
                continue
            d = min((v[0] for v in nearest.values()), default=math.inf)
            if best is None or d > best[2]:
                best = (a, t0, d, nearest)
    return best


def avoidability(scene):
    """For a scene that ended in a collision: was any motion along the lane collision-free
    from the start? {"avoidable": bool, "empty_at": t or None, "blockers": ids,
    "witness": {accel, start, min_distance} or None}; `avoidable` is True only with a
    witness (an exact replay), False only when the over-approximated set runs empty."""
    l_ego = ego_offset(scene)
    r = escape(scene, l_ego)
    out = {"avoidable": None, "empty_at": r["empty_at"], "blockers": r["blockers"], "witness": None}
    if r["empty_at"] is not None:
        out["avoidable"] = False
        return out
    w = best_witness(scene, l_ego)
    if w is not None:
        out["avoidable"] = True
        out["witness"] = {"accel": w[0], "start": w[1], "min_distance": w[2]}
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene", help="scene/1 JSON (e.g. from `hil_sim import FILE.xml`)")
    ap.add_argument("--offsets", default="-0.5,-0.25,0,0.25,0.5",
                    help="lateral offsets from the ego's own, in metres (comma-separated)")
    ap.add_argument("--a-min", type=float, default=-6.0, help="braking limit [m/s^2]")
    ap.add_argument("--a-max", type=float, default=3.0, help="acceleration limit [m/s^2]")
    ap.add_argument("--t0", type=float, default=0.0, help="start time (the ego's state is the scene's)")
    ap.add_argument("--witness", action="store_true",
                    help="also replay constant-acceleration starts exactly (every 0.02 s) and give "
                         "the collision-free one with the most room")
    ap.add_argument("--json", help="write the results here")
    args = ap.parse_args(argv)
    with open(args.scene) as f:
        scene = json.load(f)
    l_ego = ego_offset(scene)
    results = []
    for d in (float(x) for x in args.offsets.split(",")):
        r = escape(scene, l_ego + d, a_min=args.a_min, a_max=args.a_max, t0=args.t0)
        r["offset_from_ego"] = d
        results.append(r)
        verdict = ("no motion left at t = %.1f s (blocked by %s)" % (r["empty_at"], r["blockers"])
                   if r["empty_at"] is not None else "some motion survives the horizon")
        print("offset %+.2f m: %s; last reachable: t %.1f s, s %s m, v %s m/s" %
              (d, verdict, r["last"]["t"], r["last"]["s"], r["last"]["v"]))
        if args.witness and r["empty_at"] is None:
            w = best_witness(scene, l_ego + d)
            if w is None:
                print("  no constant-acceleration start (0.5-3 m/s^2 from 0-3 s) is collision-free")
            else:
                closest = sorted(w[3].items(), key=lambda kv: kv[1][0])[:3]
                print("  witness: %.1f m/s^2 from t = %.1f s, at least %.2f m from every obstacle; "
                      "closest %s" % (w[0], w[1], w[2],
                                      ", ".join("%s %.2f m at %.1f s" % (i, dd, tt)
                                                for i, (dd, tt) in closest)))
                r["witness"] = {"accel": w[0], "start": w[1], "min_distance": w[2]}
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"scene": scene.get("name", args.scene), "a_min": args.a_min,
                       "a_max": args.a_max, "results": results}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
