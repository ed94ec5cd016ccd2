#!/usr/bin/env python3
"""The planner's derived worst case per cycle (issue 12, item 3; `make wcet`).

Two steps, Python standard library only:

  measure  Read closed-loop traces of the Cortex-M7 firmware under QEMU
           (`hil_sim run --target qemu --trace T.jsonl`, -icount shift=0: the
           port's timer counts 40 instructions per tick). Every cycle carries
           its stage ticks and its work in the units of the budgets ("work").
           Per stage, fit the cheapest cost model
               cost <= c0 + a * unit1 + b * unit2        [instructions]
           that lies above EVERY measured cycle (an upper envelope: c0 the
           worst stage cost of a cycle without any unit, then a, b minimise
           seen1 * a + seen2 * b subject to the envelope, seen = the most
           units of a cycle: tight where the data is), and write the
           costs per unit and the measured maxima to a JSON file.

  table    (default) Read the budgets from itp/config.hpp (DefaultSizes, or
           with --sizes a configuration's overrides of them) and
           the JSON, print budget x cost per unit per stage, the derived bound
           (with the stated margin on every measured cost) and the measured
           maxima on the default and the stress suite. With the link's share
           (below), also the bound of a whole firmware cycle.

  link     Run a crypto_bench image under QEMU and keep its measurement of
           the link's share of a cycle at the largest Scene and Plan (frames
           in, MAC check, decode and validation, Plan encoding, MAC, frames
           out: everything the service does besides planning) in
           tools/wcet_link_costs.json, under the image's name.
"""
import argparse
import json
import math
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CONFIG = ROOT / "firmware_core/include/itp/config.hpp"
CONFIGURATIONS = ROOT / "firmware_core/include/itp/configurations.hpp"
COSTS = ROOT / "tools/wcet_costs.json"
LINK_COSTS = ROOT / "tools/wcet_link_costs.json"
INSTRUCTIONS_PER_TICK = 40  # port/mps2: the QEMU timer's 25 MHz at -icount shift=0 (1 GHz virtual)

# stage: (label, cost(work, cycle), [(unit key, budget name), ...])
# Units are per cycle; a budget name "1" means once per cycle.
STAGES = [
    ("prepare", "validation, reference fit, SL scene", lambda w, c: w["prepare"], []),
    ("decision", "convex space + tree (per run, per node)", lambda w, c: w["decision"] - w["coarse"],
     [("decision_runs", "kMaxDecisionRunsPerCycle"), ("tree_nodes", "kMaxTreeNodesPerCycle")]),
    ("coarse", "coarse QPs (per QP, per iteration)", lambda w, c: w["coarse"],
     [("coarse_qps", "kMaxCoarseQpsPerCycle"), ("coarse_iterations", "kMaxCoarseIterationsPerCycle")]),
    ("path", "path QPs (per solve, per iteration)", lambda w, c: w["path"],
     [("path_solves", "kMaxPathSolvesPerCycle"), ("path_iterations", "kMaxPathIterationsPerCycle")]),
    ("speed", "ST graph + speed QP (per solve, per iteration)", lambda w, c: w["speed"],
     [("speed_solves", "kMaxSpeedSolvesPerCycle"), ("speed_iterations", "kMaxSpeedIterationsPerCycle")]),
    ("check", "sampling + collision check (per iteration)", lambda w, c: w["check"],
     [("iterations", "kMaxPlannerIterations")]),
    ("rest", "start state, inputs, fallback stop, records", lambda w, c: w["total"] - (
        w["prepare"] + w["decision"] + w["path"] + w["speed"] + w["check"]), []),
]


# The QP stages share one work budget per cycle (itp/core/work_ledger.hpp):
# kQpWorkPerCycle thousand instructions, each unit charged at the config's
# cost, which must cover the fitted cost x margin for the cap to be a bound.
QP_WORK_BUDGET = "kQpWorkPerCycle"
QP_WORK_COSTS = {  # unit: config constant [k instructions per unit]
    "coarse_qps": "kCoarseQpSetupWork", "coarse_iterations": "kCoarseIterationWork",
    "path_solves": "kPathSolveSetupWork", "path_iterations": "kPathIterationWork",
    "speed_solves": "kSpeedSolveSetupWork", "speed_iterations": "kSpeedIterationWork",
}
QP_STAGES = ("coarse", "path", "speed")


def qp_work_of(work, budgets):
    """The QP work a cycle charged, in instructions (what the ledger booked)."""
    return 1000.0 * sum(work[u] * budgets[c] for u, c in QP_WORK_COSTS.items())


def qp_cover_of(work, budgets, ipt):
    """A cycle's QP stages' measured instructions over what the ledger charged for them."""
    charged = qp_work_of(work, budgets)
    return ipt * sum(work[k] for k in QP_STAGES) / charged if charged > 0 else 0.0


def read_budgets(path, sizes="DefaultSizes"):
    """The int constants of DefaultSizes (itp/config.hpp), with those a
    configuration derived from it overrides (`struct LowRamSizes : DefaultSizes`
    in itp/configurations.hpp) when `sizes` names one."""
    def constants(text, name):
        start = text.index(f"struct {name}")
        body = text[start:text.index("};", start)]
        return {m.group(1): int(m.group(2))
                for m in re.finditer(r"static constexpr int (k\w+) = ([0-9]+);", body)}
    budgets = constants(Path(path).read_text(), "DefaultSizes")
    if sizes != "DefaultSizes":
        budgets.update(constants(CONFIGURATIONS.read_text(), sizes))
    return budgets


def read_cycles(paths):
    cycles = []
    for p in paths:
        with open(p) as f:
            for line in f:
                c = json.loads(line)
                if "work" in c:
                    cycles.append(c)
    return cycles


def units_of(w, c, key):
    return c.get(key, 0) if key == "iterations" else w[key]


def fit(points, budgets):
    """points: [(cost, (u1, u2, ...))]. Returns (c0, [per unit]) with
    c0 + sum(a_j u_j) >= cost for every point, minimising sum(a_j B_j)."""
    zero = [cost for cost, u in points if all(x == 0 for x in u)]
    c0 = max(zero, default=0.0)
    pts = [(cost - c0, u) for cost, u in points if any(x > 0 for x in u) and cost > c0]
    if not budgets:
        return max([cost for cost, _ in points], default=0.0), []
    if len(budgets) == 1:
        return c0, [max([r / u[0] for r, u in pts], default=0.0)]
    # Two units: a(b) = max_i (r_i - b k_i) / n_i is convex and piecewise
    # linear, so B1 a(b) + B2 b is convex in b: ternary search. Points with
    # n_i = 0 bound b from below.
    best = {}
    for r, (n, k) in pts:  # keep the worst cost per (n, k)
        best[(n, k)] = max(best.get((n, k), 0.0), r)
    pts = [(r, n, k) for (n, k), r in best.items()]
    b_lo = max([r / k for r, n, k in pts if n == 0], default=0.0)
    b_hi = max([r / k for r, n, k in pts if k > 0] + [b_lo])

    def a_of(b):
        return max([max(0.0, (r - b * k) / n) for r, n, k in pts if n > 0], default=0.0)

    B1, B2 = budgets
    lo, hi = b_lo, b_hi
    for _ in range(100):
        m1, m2 = lo + (hi - lo) / 3, hi - (hi - lo) / 3
        if B1 * a_of(m1) + B2 * m1 <= B1 * a_of(m2) + B2 * m2:
            hi = m2
        else:
            lo = m1
    b = hi  # the upper end keeps every n = 0 point covered
    return c0, [a_of(b), b]


def measure(args):
    budgets = read_budgets(args.config, args.sizes)
    suites = {"default": args.default, "stress": args.stress}
    data = {name: read_cycles(paths) for name, paths in suites.items() if paths}
    allc = [c for cs in data.values() for c in cs]
    if not allc:
        sys.exit("wcet_table: no cycles with 'work' in the traces")
    ipt = args.instructions_per_tick
    out = {"instructions_per_tick": ipt, "margin": args.margin, "stages": {}, "measured": {},
           "traces": {k: [str(p) for p in v] for k, v in suites.items() if v}, "note": args.note,
           "budgets_at_measurement": budgets}
    for key, label, cost, units in STAGES:
        pts = [(ipt * cost(c["work"], c), tuple(units_of(c["work"], c, u) for u, _ in units)) for c in allc]
        # The envelope is made tight at the largest work seen (not at the
        # budgets, which would let the fit drop the cost of the unit with the
        # larger budget and keep only what the data never tested).
        seen = [max(1, max(u[j] for _, u in pts)) for j in range(len(units))]
        c0, per = fit(pts, seen)
        worst = max(cost for cost, _ in pts)
        maxu = [max(u[j] for _, u in pts) for j in range(len(units))]
        out["stages"][key] = {"label": label, "per_cycle": c0,
                              "units": [{"unit": u, "budget": b, "cost": a, "max_seen": m}
                                        for (u, b), a, m in zip(units, per, maxu)],
                              "max_seen": worst}
    for name, cs in data.items():
        ins = [c.get("instructions", ipt * c["work"]["total"]) for c in cs]
        worst = max(range(len(cs)), key=lambda i: ins[i])
        wc = cs[worst]
        out["measured"][name] = {
            "cycles": len(cs), "max": max(ins), "median": sorted(ins)[len(ins) // 2],
            "p99": sorted(ins)[min(len(ins) - 1, int(0.99 * len(ins)))],
            "worst_cycle": {"scene": wc["scene"], "t": wc["t"], "status": wc["status"], "reason": wc["reason"],
                            "work": wc["work"]},
            "qp_work_max": max(qp_work_of(c["work"], budgets) for c in cs),
            "qp_cover_worst": max(qp_cover_of(c["work"], budgets, ipt) for c in cs),
            "fallbacks": sum(1 for c in cs if c["status"] == "fallback"),
            "budget_fallbacks": sum(1 for c in cs if c["reason"] == "budget"),
        }
    Path(args.out).write_text(json.dumps(out, indent=1) + "\n")
    print(f"wcet_table: {len(allc)} cycles -> {args.out}")


def fmt_m(x):
    return f"{x / 1e6:8.2f} M"


def table(args):
    budgets = read_budgets(args.config, args.sizes)
    costs = json.loads(Path(args.costs).read_text())
    margin = costs["margin"]
    print(f"Derived worst case per planning cycle (Cortex-M7 instructions, QEMU -icount; "
          f"measured costs x {margin:g} margin)")
    config = Path(args.config).resolve()
    shown = config.relative_to(ROOT) if config.is_relative_to(ROOT) else config
    print(f"budgets: {shown} ({args.sizes}); costs: {args.costs}")
    print()
    print(f"{'stage':<10} {'unit':<18} {'budget':>7} {'cost/unit':>11} {'product':>11}   {'max seen (units)':>16}")
    total = 0.0
    qp_stages = 0.0   # the QP stages' products (per-stage budgets)
    qp_fixed = 0.0    # their per-cycle terms, which the ledger does not charge
    stale = []
    for key, label, _, units in STAGES:
        st = costs["stages"][key]
        stage_sum = margin * st["per_cycle"]
        rows = []
        if st["per_cycle"] > 0 or not units:
            rows.append(("per cycle", 1, margin * st["per_cycle"], margin * st["per_cycle"], ""))
        for u in st["units"]:
            b = budgets[u["budget"]]
            prod = b * margin * u["cost"]
            stage_sum += prod
            rows.append((u["unit"], b, margin * u["cost"], prod, u["max_seen"]))
            charged = QP_WORK_COSTS.get(u["unit"])
            if charged and 1000.0 * budgets[charged] < margin * u["cost"]:
                stale.append(f"{charged} = {budgets[charged]} k < fitted {margin * u['cost'] / 1000:.1f} k")
        for i, (unit, b, c, p, seen) in enumerate(rows):
            print(f"{key if i == 0 else '':<10} {unit:<18} {b:>7} {c:>11.0f} {fmt_m(p):>11}   {seen!s:>16}")
        print(f"{'':<10} {'= ' + label:<50} {fmt_m(stage_sum):>11}   (max seen {fmt_m(st['max_seen']).strip()})")
        if key in QP_STAGES:
            qp_stages += stage_sum - margin * st["per_cycle"]
            qp_fixed += margin * st["per_cycle"]
        else:
            total += stage_sum
    cap = 1000.0 * budgets[QP_WORK_BUDGET]
    # Where the per-unit costs charged lie below the fit (the float image:
    # a solve after another stage's claim restarts), the cap bounds the QP
    # stages through the measured ratio of their instructions to what the
    # ledger charged in the same cycle, with the margin on that ratio:
    # instructions <= charged x worst ratio x margin <= cap x worst ratio x margin.
    covers = [m["qp_cover_worst"] for m in costs.get("measured", {}).values() if "qp_cover_worst" in m]
    cover = max(covers) * margin if covers else None
    qp_cap = cap * max(1.0, cover) if stale and cover is not None else cap
    print()
    print(f"{'QP stages (coarse + path + speed), their budgets':<50} {fmt_m(qp_stages):>11}")
    print(f"{'  capped by their shared work, ' + QP_WORK_BUDGET:<50} {fmt_m(cap):>11}"
          f"   (costs charged: " + ", ".join(f"{u} {budgets[c]} k" for u, c in QP_WORK_COSTS.items()) + ")")
    if qp_cap != cap:
        print(f"{'  x worst measured / charged x margin':<50} {fmt_m(qp_cap):>11}"
              f"   ({max(covers):.3f} x {margin:g}: the per-unit costs charged lie below the fit)")
    total += qp_fixed + min(qp_stages, qp_cap)
    print()
    print(f"{'derived bound per cycle':<50} {fmt_m(total):>11}   (acceptance <= 40 M, goal 20 M)")
    link = read_link_share(args)
    if link is not None:
        share = margin * link["link_share_instructions"]
        print(f"{'  + link share at the largest messages':<50} {fmt_m(share):>11}"
              f"   (measured {fmt_m(link['link_share_instructions']).strip()} x {margin:g}, {args.link_image}: "
              f"Scene {link['link_scene_body_bytes']} B in {link['link_frames_in_per_cycle']} frames, "
              f"Plan {link['link_plan_body_bytes']} B in {link['link_frames_out_per_cycle']})")
        print(f"{'derived bound per firmware cycle':<50} {fmt_m(total + share):>11}"
              f"   (the planner's + the link's: request in .. reply out)")
    for name, m in costs.get("measured", {}).items():
        wc = m["worst_cycle"]
        print(f"measured max, {name:<8} suite ({m['cycles']} cycles): {fmt_m(m['max']).strip()}"
              f"  (median {fmt_m(m['median']).strip()}, p99 {fmt_m(m['p99']).strip()};"
              f" worst: {wc['scene']} t = {wc['t']:.1f} s {wc['status']} {wc['reason']};"
              f" budget fallbacks {m['budget_fallbacks']} of {m['fallbacks']})")
        if "qp_work_max" in m:
            print(f"{'':<15}QP work charged: max {fmt_m(m['qp_work_max']).strip()} of {fmt_m(cap).strip()}"
                  + (f"; measured / charged per cycle: max {m['qp_cover_worst']:.3f}" if "qp_cover_worst" in m else ""))
    if costs.get("note"):
        print(f"note: {costs['note']}")
    if stale and cover is None:
        print("wcet_table: the QP work costs in itp/config.hpp are below the fitted costs "
              "(the cap is no bound; raise them): " + "; ".join(stale))
        return 1
    if stale:
        print("wcet_table: per unit the costs charged lie below the fit (" + "; ".join(stale) +
              f"); the QP stages' term is the cap x the worst measured instructions / charged x {margin:g}")
    return 0 if total <= 40e6 else 1


def read_link_share(args):
    """The image's link share (the `link` step's JSON), None when not measured."""
    path = Path(getattr(args, "link_costs", LINK_COSTS))
    if not path.exists():
        return None
    return json.loads(path.read_text()).get("images", {}).get(getattr(args, "link_image", "production"))


def link(args):
    """Run the crypto_bench ELF under QEMU until it prints "done"; keep its link_* figures."""
    cmd = ["qemu-system-arm", "-M", "mps2-an500", "-nographic", "-monitor", "none", "-icount", "shift=0",
           "-serial", "null", "-serial", "stdio", "-kernel", args.elf]
    figures = {}
    with subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True) as q:
        try:
            for line in q.stdout:
                print(line.rstrip(), flush=True)
                if line.strip() == "done":
                    break
                name, _, value = line.strip().partition(" ")
                if name.startswith("link_") and value.isdigit():
                    figures[name] = int(value)
        finally:
            q.kill()
    if (figures.get("link_cycles_valid", 0) == 0 or figures.get("link_cycles_valid") != figures.get("link_cycles")
            or "link_share_instructions" not in figures):
        print("wcet_table link: not every measured cycle authenticated and validated", file=sys.stderr)
        return 1
    path = Path(args.out)
    data = json.loads(path.read_text()) if path.exists() else {"images": {}}
    if args.check:
        # The bound adds the recorded share x margin: a build whose share grew
        # past that no longer meets it (instruction counts under -icount are exact).
        recorded = data["images"].get(args.image, {}).get("link_share_instructions")
        if recorded is None:
            print(f"wcet_table link: no recorded share for {args.image} in {path}", file=sys.stderr)
            return 1
        limit = args.margin * recorded
        measured = figures["link_share_instructions"]
        print(f"{args.image}: link share {measured} instructions, recorded {recorded} x {args.margin:g} = {limit:.0f}")
        return 0 if measured <= limit else 1
    data["images"][args.image] = dict(figures, elf=Path(args.elf).name)
    data["note"] = ("instructions under qemu-system-arm -M mps2-an500 -icount shift=0 (one per virtual ns); "
                    "port/common/image_crypto_bench.cpp, bench_link_share")
    path.write_text(json.dumps(data, indent=1, sort_keys=True) + "\n")
    print(f"wrote {path} ({args.image}: link share {fmt_m(figures['link_share_instructions']).strip()})")
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--config", default=str(CONFIG))
    ap.add_argument("--sizes", default="DefaultSizes",
                    help="the configuration's sizes (e.g. LowRamSizes, the float image's)")
    sub = ap.add_subparsers(dest="cmd")
    m = sub.add_parser("measure", help="fit costs per unit from QEMU traces")
    m.add_argument("--default", nargs="*", default=[], help="traces of the default suite")
    m.add_argument("--stress", nargs="*", default=[], help="traces of the stress suite")
    m.add_argument("--out", default=str(COSTS))
    m.add_argument("--margin", type=float, default=1.2, help="factor on every measured cost")
    m.add_argument("--instructions-per-tick", type=float, default=INSTRUCTIONS_PER_TICK)
    m.add_argument("--note", default="")
    t = sub.add_parser("table", help="print the table (default)")
    t.add_argument("--costs", default=str(COSTS))
    t.add_argument("--link-costs", default=str(LINK_COSTS), help="the link step's JSON")
    t.add_argument("--link-image", default="production", help="whose link share to add (production, road, f32)")
    k = sub.add_parser("link", help="measure the link's share of a cycle under QEMU (a crypto_bench ELF)")
    k.add_argument("--elf", required=True)
    k.add_argument("--image", required=True, help="the name it is kept under (production, road, f32)")
    k.add_argument("--out", default=str(LINK_COSTS))
    k.add_argument("--check", action="store_true",
                   help="do not record: fail when the share exceeds the recorded one x --margin")
    k.add_argument("--margin", type=float, default=1.2, help="with --check: the margin the bound puts on it")
    args = ap.parse_args()
    if args.cmd == "measure":
        measure(args)
        return 0
    if args.cmd == "link":
        return link(args)
    if args.cmd is None:
        args.costs = str(COSTS)
    return table(args)


if __name__ == "__main__":
    sys.exit(main())
