#!/usr/bin/env python3
"""Combine evaluate.py summaries (e.g. seeds 1-3) into one per-archetype table.

    python3 combine.py results/seed1.json results/seed2.json results/seed3.json \
        --out results/seeds1-3.json --table results/seeds1-3.md
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import evaluate  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("summaries", nargs="+")
    ap.add_argument("--out", required=True)
    ap.add_argument("--table")
    ap.add_argument("--title", default="combined")
    args = ap.parse_args(argv)
    records, per_run = [], {}
    for path in args.summaries:
        with open(path) as f:
            data = json.load(f)
        records += data["scenes"]
        per_run[data["title"]] = data["overall"]
    by_arch = {}
    for r in records:
        by_arch.setdefault(r["archetype"], []).append(r)
    summary = {k: evaluate.summarise(v) for k, v in by_arch.items()}
    overall = evaluate.summarise(records)
    with open(args.out, "w") as f:
        json.dump({"format": "judge-summary/1", "title": args.title, "runs": per_run,
                   "overall": overall, "per_archetype": summary}, f, indent=1)
    text = evaluate.table(summary, overall, args.title)
    if args.table:
        with open(args.table, "w") as f:
            f.write(text)
    print(text)


if __name__ == "__main__":
    main()
