#!/usr/bin/env python3
"""Run judge scenes through `hil_sim run` in closed loop and summarise per archetype.

    python3 evaluate.py --scenes DIR [--hil-sim PATH] --out RESULTS.json [--table T.md]
                        [--batch 25] [--jobs 1] [--work DIR] [--plots DIR]

For every batch it runs
    hil_sim run --scene <files> --target inproc --report R.json --trace T.jsonl
and reads the report's per-scene figures and the per-cycle trace. With its own geometry
(geom.py, SAT) it finds the first collision step, the obstacle touched and who ran into whom
(classify_contact), and whether a scene that ends stopped had a free road ahead (stuck).
"""
import argparse
import glob
import json
import math
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from escape import avoidability  # noqa: E402
from geom import (Polyline, boundary_at, boxes_overlap, classify_contact,  # noqa: E402
                  ego_box, obstacle_boxes_at)

REPO = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
DEFAULT_HIL_SIM = os.path.join(REPO, "build", "host-release", "hil_sim", "hil_sim")
HARSH_BRAKE = -4.0
STOPPED_V = 0.3          # m/s
STUCK_WINDOW = 3.0       # s stopped at the end of the run


# --------------------------------------------------------------------------------------------
# Running hil_sim
# --------------------------------------------------------------------------------------------
def run_batch(hil_sim, files, work, index, plots):
    report = os.path.join(work, "report_%03d.json" % index)
    trace = os.path.join(work, "trace_%03d.jsonl" % index)
    cmd = [hil_sim, "run", "--scene"] + files + ["--target", "inproc", "--report", report,
                                                  "--trace", trace]
    if plots:
        cmd += ["--plots", plots]
    log = os.path.join(work, "log_%03d.txt" % index)
    with open(log, "w") as f:
        rc = subprocess.call(cmd, stdout=f, stderr=subprocess.STDOUT)
    if rc not in (0, 3):
        raise RuntimeError("hil_sim exited %d on batch %d (see %s)" % (rc, index, log))
    return report, trace


def read_trace(path):
    per_scene = {}
    with open(path) as f:
        for line in f:
            rec = json.loads(line)
            per_scene.setdefault(rec["scene"], []).append(rec)
    return per_scene


# --------------------------------------------------------------------------------------------
# Collision classification and "stuck" with the judge's geometry
# --------------------------------------------------------------------------------------------
def first_collision(scene, cycles):
    """At the first cycle flagged as a collision: the obstacle whose box overlaps the ego's,
    and who ran into whom. The trace's x, y is the rear axle (checked: SAT agrees)."""
    ego = scene["ego"]
    prev = None
    for rec in cycles:
        if not rec.get("collision"):
            prev = rec
            continue
        me = ego_box(rec["x"], rec["y"], rec["heading"], ego["length"], ego["width"],
                     ego["wheelbase"])
        me_v = (rec["v"] * math.cos(rec["heading"]), rec["v"] * math.sin(rec["heading"]))
        hits = [(oid, kind, box, vx, vy) for oid, kind, box, vx, vy
                in obstacle_boxes_at(scene, rec["t"]) if boxes_overlap(me, box)]
        if not hits:
            return {"t": rec["t"], "who": "unconfirmed", "note": "judge SAT finds no overlap"}
        # the one the ego's centre is closest to is the contact that matters
        oid, kind, box, vx, vy = min(hits, key=lambda h: math.hypot(h[2].cx - me.cx,
                                                                    h[2].cy - me.cy))
        me_prev = box_prev = None
        if prev is not None:      # the step before: across which side they came together
            me_prev = ego_box(prev["x"], prev["y"], prev["heading"], ego["length"],
                              ego["width"], ego["wheelbase"])
            box_prev = next((b for i, _, b, _, _ in obstacle_boxes_at(scene, prev["t"])
                             if i == oid), None)
        out = classify_contact(me, me_v, box, (vx, vy), me_prev, box_prev)
        out.update(t=rec["t"], obstacle=oid, kind=kind, ego_v=round(rec["v"], 2),
                   obstacle_v=round(math.hypot(vx, vy), 2), status=rec["status"],
                   reason=rec.get("reason", ""), decisions=rec.get("decisions", ""))
        return out
    return None


def road_ahead_free(scene, rec, look_ahead=40.0):
    """Is there a lateral gap of ego width + 0.6 m within the road edges over the next
    `look_ahead` metres, given the obstacles there at the end of the run? Moving obstacles
    count only close ahead (15 m) — a leader that drives off frees the road — except oncoming
    ones, which block their lane over 80 m. Queued behind a road user (the nearest obstacle
    in the ego's corridor is a dynamic one, even if it stands) is not stuck: it may move on."""
    ego = scene["ego"]
    line = Polyline(scene["reference_line"])
    s0, l_ego, _, _ = line.project(rec["x"], rec["y"])
    front = 0.5 * (ego["length"] + ego["wheelbase"])
    road = scene["road"]
    ss = [s0 + k for k in range(0, int(look_ahead + front) + 1)]
    left = min(boundary_at(road["left_boundary"], s) for s in ss) - 0.2
    right = max(boundary_at(road["right_boundary"], s) for s in ss) + 0.2
    if s0 + front + 20.0 > line.cum[-1]:
        return False                       # the map ends: stopping is right
    blocked = []
    nearest_in_lane = None      # (distance, is_dynamic) of the closest obstacle in the corridor
    for oid, kind, box, vx, vy in obstacle_boxes_at(scene, rec["t"]):
        s, l, th, _ = line.project(box.cx, box.cy)
        d = box.heading - th
        hs = abs(box.length / 2 * math.cos(d)) + abs(box.width / 2 * math.sin(d))
        hl = abs(box.length / 2 * math.sin(d)) + abs(box.width / 2 * math.cos(d))
        v_s = vx * math.cos(th) + vy * math.sin(th)
        speed = math.hypot(vx, vy)
        reach = look_ahead + front
        if speed > 0.5:
            reach = 80.0 if v_s < -0.5 else front + 15.0
        if s + hs < s0 - 2.0 or s - hs > s0 + reach:
            continue
        blocked.append((l - hl, l + hl))
        if abs(l_ego - l) < hl + ego["width"] / 2 and s > s0:
            is_dynamic = any(o["id"] == oid for o in scene.get("dynamic_obstacles", []))
            if nearest_in_lane is None or s < nearest_in_lane[0]:
                nearest_in_lane = (s, is_dynamic)
    if nearest_in_lane and nearest_in_lane[1]:
        return False        # queued behind a road user (it may drive on): waiting is fine
    need = ego["width"] + 0.6
    edge = right
    for lo, hi in sorted(blocked):
        if lo - edge >= need:
            return True
        edge = max(edge, hi)
    return left - edge >= need


def stuck(scene, cycles):
    last = cycles[-1]
    if last["v"] > STOPPED_V:
        return False
    t_end = last["t"]
    window = [c for c in cycles if c["t"] >= t_end - STUCK_WINDOW]
    if any(c["v"] > STOPPED_V for c in window):
        return False
    moved = math.hypot(window[-1]["x"] - window[0]["x"], window[-1]["y"] - window[0]["y"])
    return moved < 1.0 and road_ahead_free(scene, last)


# --------------------------------------------------------------------------------------------
# Per scene and per archetype
# --------------------------------------------------------------------------------------------
def nearest_ahead_in_lane(scene, rec):
    """(kind, id, bumper gap) of the nearest obstacle ahead overlapping the ego's corridor at
    the end of the run: what a stopped ego is waiting behind."""
    ego = scene["ego"]
    line = Polyline(scene["reference_line"])
    s0, l0, _, _ = line.project(rec["x"], rec["y"])
    front = 0.5 * (ego["length"] + ego["wheelbase"])
    best = None
    for oid, kind, box, _, _ in obstacle_boxes_at(scene, rec["t"]):
        s, l, th, _ = line.project(box.cx, box.cy)
        d = box.heading - th
        hs = abs(box.length / 2 * math.cos(d)) + abs(box.width / 2 * math.sin(d))
        hl = abs(box.length / 2 * math.sin(d)) + abs(box.width / 2 * math.cos(d))
        gap = s - hs - (s0 + front)
        if abs(l - l0) < hl + ego["width"] / 2 and gap > -1.0 and (best is None or gap < best[2]):
            best = (kind, oid, round(gap, 2))
    return best


def scene_record(scene, rep, cycles):
    a_lon = [c.get("a_lon", 0.0) for c in cycles]
    reasons = {}
    for c in cycles:
        if c["status"] == "fallback":
            reasons[c.get("reason") or "?"] = reasons.get(c.get("reason") or "?", 0) + 1
    rec = {
        "name": scene["name"],
        "archetype": scene.get("judge", {}).get("archetype", "?"),
        "tags": scene.get("tags", []),
        "cycles": len(cycles),
        "collision": bool(rep["collisions"]),
        "collision_detail": first_collision(scene, cycles) if rep["collisions"] else None,
        # was any motion along the lane collision-free from the start? (escape.py)
        "avoidable_in_lane": avoidability(scene) if rep["collisions"] else None,
        "road_departure": bool(rep["road_departures"]),
        "max_road_excess_m": round(rep.get("max_road_excess_m", 0.0), 3),
        "fallbacks": sum(reasons.values()),
        "fallback_reasons": reasons,
        "invalid_inputs": rep.get("invalid_inputs", 0),
        "crashed": bool(rep.get("crashed")),
        "max_abs_lat_acc": round(rep["max_abs_lat_acc"], 3),
        "max_abs_lon_acc": round(rep["max_abs_lon_acc"], 3),
        "min_a_lon": round(min(a_lon), 3) if a_lon else 0.0,
        "harsh_brake_cycles": sum(1 for a in a_lon if a < HARSH_BRAKE),
        # the lane-keeping careful driver of check_scenes.py got by with <= 3 m/s^2 here
        "witness_peak_brake": scene.get("judge", {}).get("witness", {}).get(
            "careful_peak_brake"),
        "min_clearance_m": rep.get("min_clearance_m"),
        "progress_m": round(rep.get("progress_m", 0.0), 1),
        "final_v": round(cycles[-1]["v"], 2) if cycles else None,
        "stuck": bool(cycles) and stuck(scene, cycles),
        "first_fallback": next(({"t": round(c["t"], 1), "reason": c.get("reason", ""),
                                 "v": round(c["v"], 2)} for c in cycles
                                if c["status"] == "fallback"), None),
        "ends_behind": nearest_ahead_in_lane(scene, cycles[-1]) if cycles and
        cycles[-1]["v"] <= STOPPED_V else None,
        # the road is blocked by design (a stop is the right answer): its fallbacks are fine
        "blocked_by_design": not scene.get("judge", {}).get("witness", {}).get(
            "statics_passable", True),
    }
    if rec["min_clearance_m"] is not None:
        rec["min_clearance_m"] = round(rec["min_clearance_m"], 3)
    return rec


def summarise(records):
    """Aggregate a list of scene records."""
    cycles = sum(r["cycles"] for r in records)
    fallbacks = sum(r["fallbacks"] for r in records)
    reasons = {}
    for r in records:
        for k, v in r["fallback_reasons"].items():
            reasons[k] = reasons.get(k, 0) + v
    coll = [r for r in records if r["collision"]]
    open_ = [r for r in records if not r["blocked_by_design"]]
    return {
        "scenes": len(records),
        "cycles": cycles,
        "collisions": len(coll),
        "collisions_ran_into": sum(1 for r in coll if (r["collision_detail"] or {}).get("who")
                                   == "ran_into"),
        "collisions_hit": sum(1 for r in coll if (r["collision_detail"] or {}).get("who")
                              == "hit"),
        "road_departures": sum(r["road_departure"] for r in records),
        "fallback_cycles": fallbacks,
        "fallback_share": round(fallbacks / cycles, 4) if cycles else 0.0,
        "fallback_reasons": dict(sorted(reasons.items(), key=lambda kv: -kv[1])),
        "scenes_blocked_by_design": sum(r["blocked_by_design"] for r in records),
        "fallback_share_passable": round(
            sum(r["fallbacks"] for r in open_) / max(1, sum(r["cycles"] for r in open_)), 4),
        "invalid_inputs": sum(r["invalid_inputs"] for r in records),
        "crashes": sum(r["crashed"] for r in records),
        "max_abs_lat_acc": max((r["max_abs_lat_acc"] for r in records), default=0.0),
        "scenes_lat_acc_over_3": sum(r["max_abs_lat_acc"] > 3.0 for r in records),
        "scenes_lat_acc_over_4": sum(r["max_abs_lat_acc"] > 4.0 for r in records),
        "max_abs_lon_acc": max((r["max_abs_lon_acc"] for r in records), default=0.0),
        "scenes_harsh_braking": sum(r["harsh_brake_cycles"] > 0 for r in records),
        "harsh_brake_cycles": sum(r["harsh_brake_cycles"] for r in records),
        "scenes_harsh_braking_unneeded": sum(
            r["harsh_brake_cycles"] > 0 and (r["witness_peak_brake"] or 0.0) <= 3.0
            for r in records),
        "scenes_min_clearance_below_0_3": sum(
            r["min_clearance_m"] is not None and 0.0 < r["min_clearance_m"] < 0.3
            for r in records),
        "stuck": sum(r["stuck"] for r in records),
    }


def badness(r):
    """Ordering for the 'worst scenes' list."""
    return (r["collision"] * 100 + r["road_departure"] * 50 + r["stuck"] * 30 +
            (r["max_abs_lat_acc"] > 4.0) * 10 + r["fallbacks"] / 10.0)


def table(summary_by_arch, overall, title):
    cols = ["scenes", "collisions", "collisions_ran_into", "collisions_hit", "road_departures",
            "fallback_share", "fallback_share_passable", "max_abs_lat_acc", "scenes_lat_acc_over_3",
            "scenes_lat_acc_over_4", "max_abs_lon_acc", "scenes_harsh_braking",
            "scenes_harsh_braking_unneeded", "scenes_min_clearance_below_0_3", "stuck"]
    heads = ["scenes", "coll", "ran_into", "hit", "depart", "fallback%", "fb% passable","max|a_lat|",
             ">3", ">4", "max|a_lon|", "harsh", "harsh unneeded", "clear<0.3", "stuck"]
    lines = ["### " + title, "",
             "| archetype | " + " | ".join(heads) + " | top fallback reasons |",
             "|---" * (len(heads) + 2) + "|"]

    def row(name, s):
        vals = []
        for c in cols:
            v = s[c]
            if c.startswith("fallback_share"):
                vals.append("%.1f" % (100 * v))
            elif isinstance(v, float):
                vals.append("%.2f" % v)
            else:
                vals.append(str(v))
        top = ", ".join("%s %d" % kv for kv in list(s["fallback_reasons"].items())[:3])
        return "| %s | %s | %s |" % (name, " | ".join(vals), top)
    for name in sorted(summary_by_arch):
        lines.append(row(name, summary_by_arch[name]))
    lines.append(row("**all**", overall))
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenes", required=True, nargs="+", help="scene dirs or files")
    ap.add_argument("--hil-sim", default=DEFAULT_HIL_SIM)
    ap.add_argument("--out", required=True, help="summary JSON")
    ap.add_argument("--table", help="also write the readable table here (markdown)")
    ap.add_argument("--title", default="judge scenes")
    ap.add_argument("--batch", type=int, default=25)
    ap.add_argument("--jobs", type=int, default=1, choices=[1, 2])
    ap.add_argument("--work", default=None, help="where reports/traces go (default: beside --out)")
    ap.add_argument("--plots", help="pass --plots DIR to hil_sim")
    args = ap.parse_args(argv)

    files = []
    for p in args.scenes:
        files += sorted(glob.glob(os.path.join(p, "*.json"))) if os.path.isdir(p) else [p]
    work = args.work or os.path.splitext(args.out)[0] + "_work"
    os.makedirs(work, exist_ok=True)
    batches = [files[i:i + args.batch] for i in range(0, len(files), args.batch)]
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        outputs = list(pool.map(lambda ib: run_batch(args.hil_sim, ib[1], work, ib[0],
                                                     args.plots), enumerate(batches)))
    scenes = {}
    for path in files:
        with open(path) as f:
            sc = json.load(f)
        sc["_file"] = os.path.relpath(path, REPO) if path.startswith(REPO) else path
        scenes[sc["name"]] = sc
    records = []
    for report_path, trace_path in outputs:
        with open(report_path) as f:
            report = json.load(f)
        traces = read_trace(trace_path)
        for rep in report["per_scene"]:
            sc = scenes[rep["name"]]
            rec = scene_record(sc, rep, traces.get(rep["name"], []))
            rec["file"] = sc["_file"]
            records.append(rec)
    by_arch = {}
    for r in records:
        by_arch.setdefault(r["archetype"], []).append(r)
    summary_by_arch = {k: summarise(v) for k, v in by_arch.items()}
    overall = summarise(records)
    worst = sorted(records, key=badness, reverse=True)[:10]
    result = {"format": "judge-summary/1", "title": args.title,
              "hil_sim": os.path.relpath(args.hil_sim, REPO)
              if args.hil_sim.startswith(REPO) else args.hil_sim,
              "overall": overall, "per_archetype": summary_by_arch,
              "worst": [{k: r[k] for k in ("name", "file", "archetype", "collision",
                                           "collision_detail", "avoidable_in_lane", "road_departure", "stuck",
                                           "fallbacks", "fallback_reasons", "first_fallback",
                                           "ends_behind", "max_abs_lat_acc",
                                           "min_a_lon", "progress_m", "final_v")}
                        for r in worst if badness(r) > 0],
              "scenes": records}
    with open(args.out, "w") as f:
        json.dump(result, f, indent=1)
    text = table(summary_by_arch, overall, args.title)
    if args.table:
        with open(args.table, "w") as f:
            f.write(text)
    print(text)
    for r in result["worst"]:
        avoid = r["avoidable_in_lane"] or {}
        print("worst: %-45s coll=%s%s depart=%s stuck=%s fallbacks=%d %s" % (
            r["name"], (r["collision_detail"] or {}).get("who", "-") if r["collision"] else "-",
            {True: " (avoidable in lane)", False: " (unavoidable in lane)"}.get(
                avoid.get("avoidable"), ""),
            r["road_departure"], r["stuck"], r["fallbacks"], r["fallback_reasons"]))


if __name__ == "__main__":
    main()
