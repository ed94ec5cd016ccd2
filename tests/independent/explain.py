#!/usr/bin/env python3
"""Re-run one judge scene and print what happened: the scene's archetype and rule values,
then a compressed timeline of the planner's status, reason and decisions (a line whenever
they change), and the judge's reading of the end (collision detail, stuck, what it waits
behind). Optionally writes hil_sim's SVG plot (and a PNG if rsvg-convert exists).

    python3 explain.py SCENE.json [--hil-sim PATH] [--plots DIR]
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import evaluate  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--hil-sim", default=evaluate.DEFAULT_HIL_SIM)
    ap.add_argument("--plots")
    args = ap.parse_args(argv)
    with open(args.scene) as f:
        scene = json.load(f)
    work = tempfile.mkdtemp(prefix="judge-explain-")
    report, trace = evaluate.run_batch(args.hil_sim, [args.scene], work, 0, args.plots)
    cycles = evaluate.read_trace(trace)[scene["name"]]
    with open(report) as f:
        rep = json.load(f)["per_scene"][0]
    judge = scene.get("judge", {})
    print("%s: %s" % (scene["name"], " ".join(scene.get("tags", []))))
    print("params:", json.dumps(judge.get("params", {})))
    print("ego v0 %.2f, limit %.2f, obstacles: %s" % (
        scene["ego"]["v"], scene["road"]["speed_limit"],
        ", ".join("%d %s" % (o["id"], o.get("kind", "?")) for o in
                  scene.get("static_obstacles", []) + scene.get("dynamic_obstacles", []))))
    last = None
    for c in cycles:
        key = (c["status"], c.get("reason", ""), c.get("decisions", ""))
        if key != last or c.get("collision"):
            print("  t=%5.1f %-8s %-16s v=%5.2f a=%5.2f clear=%5s %s %s%s" % (
                c["t"], c["status"], c.get("reason", ""), c["v"], c.get("a_lon", 0.0),
                "%.2f" % c["clearance"] if c.get("clearance") is not None else "-",
                c.get("decisions", ""), c.get("collision_with", ""),
                " COLLISION" if c.get("collision") else ""))
            last = key
    record = evaluate.scene_record(scene, rep, cycles)
    print("judge:", json.dumps({k: record[k] for k in (
        "collision_detail", "road_departure", "stuck", "ends_behind", "first_fallback",
        "fallback_reasons", "max_abs_lat_acc", "min_a_lon", "progress_m")}))
    if args.plots and shutil.which("rsvg-convert"):
        svg = os.path.join(args.plots, scene["name"] + ".svg")
        subprocess.call(["rsvg-convert", "-w", "1000", svg, "-o", svg[:-4] + ".png"])
        print("plot:", svg[:-4] + ".png")
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
