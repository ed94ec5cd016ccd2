#!/usr/bin/env python3
"""RAM of the Cortex-M7 firmware by module, checked against its budget.

Reads the ELF only:
  - section sizes (.data, .bss, .stack) and the symbols of .data/.bss
    (arm-none-eabi-objdump -h, arm-none-eabi-nm -S -C);
  - the service's breakdown: the firmware keeps all of its planner, QP,
    scene, plan and link memory in one static object (one .bss symbol,
    g_service_storage), which symbols cannot split, so the firmware carries a
    table of sizeof() of its parts as the ARM compiler laid them out
    (port/mps2_an500/ram_table.cpp) in the non-loaded section .itp_ram_table.
The budget is RAM_BUDGET in port/mps2_an500/ram_budget.ld (the linker and a
static_assert check the same number); the goal of issue 12, 128 KiB, is
printed beside it. Exit 1 when .data + .bss + stack exceeds the budget, or
when the table disagrees with the ELF (a stale or missing table).

Usage: size_report.py --elf ELF [--budget-file FILE] [--budget BYTES | --no-budget]
Python 3 standard library only; needs arm-none-eabi-nm and -objdump on PATH.
"""
import argparse
import os
import re
import subprocess
import sys

GOAL_BYTES = 128 * 1024
TABLE_SECTION = ".itp_ram_table"
ENTRY_NAME_BYTES = 44
ENTRY_BYTES = ENTRY_NAME_BYTES + 4
SERVICE_SYMBOL = "g_service_storage"

# Display names and order of the table's entries.
LABELS = {
    "service": "firmware service (one static object)",
    "service.planner": "planner",
    "service.planner.qp_arena": "QP storage: problems + solver workspaces (one shared, or one per QP)",
    "service.planner.decision_stage": "decision stage",
    "service.planner.decision_stage.coarse_qp": "coarse QP (result, start)",
    "service.planner.path_qp": "path QP (result, start)",
    "service.planner.st_graph": "ST graph",
    "service.planner.speed_qp": "speed QP (result, start)",
    "service.planner.speed_bounds": "speed bounds",
    "service.planner.path_speed_results": "path + speed results",
    "service.planner.reference_line": "reference line + spline (the spline in shared QP storage)",
    "service.planner.sl_scene": "SL scene",
    "service.planner.previous_plans": "previous ok plan + the cycle's output",
    "service.scene": "scene",
    "service.link": "link (segments, sized by the largest message)",
    "service.link.inbox": "inbox (largest sealed Scene; in shared QP storage: state only)",
    "service.link.outbox": "outbox (largest sealed Plan, resent on Query)",
    "service.link.decoder": "frame decoder (one segment)",
    "service.link.control_tx": "Status outbox + wire frame",
    "service.secure_channel": "secure channel (keys, freshness)",
    "service.qp_check": "QP-check service (test image only)",
}


class ReportError(Exception):
    pass


def run(cmd):
    try:
        return subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        raise ReportError(f"{' '.join(cmd)} failed: {e}")


def sections(elf, objdump):
    out = {}
    for line in run([objdump, "-h", elf]).splitlines():
        parts = line.split()
        if len(parts) >= 7 and parts[0].isdigit():
            out[parts[1]] = int(parts[2], 16)
    return out


def ram_table(elf, objdump):
    data = bytearray()
    for line in run([objdump, "-s", "-j", TABLE_SECTION, elf]).splitlines():
        m = re.match(r'^\s*[0-9a-f]+\s+((?:[0-9a-f]{2,8}\s){1,4})', line)
        if m:
            data += bytes.fromhex("".join(m.group(1).split()))
    if not data or len(data) % ENTRY_BYTES:
        raise ReportError(f"{elf}: section {TABLE_SECTION} missing or malformed ({len(data)} bytes)")
    entries = []
    for i in range(0, len(data), ENTRY_BYTES):
        name = data[i:i + ENTRY_NAME_BYTES].split(b"\0", 1)[0].decode("ascii")
        size = int.from_bytes(data[i + ENTRY_NAME_BYTES:i + ENTRY_BYTES], "little")
        entries.append((name, size))
    return entries


def ram_symbols(elf, nm):
    """[(name, bytes, kind)] of the .data/.bss symbols (kind d or b)."""
    out = []
    for line in run([nm, "--size-sort", "-S", "-C", elf]).splitlines():
        m = re.match(r'^[0-9a-f]+ ([0-9a-f]+) ([bBdD]) (.+)$', line)
        if m:
            out.append((m.group(3), int(m.group(1), 16), m.group(2).lower()))
    return out


def budget_from(path):
    with open(path, encoding="utf-8") as f:
        m = re.search(r'^RAM_BUDGET = (\d+);', f.read(), re.M)
    if not m:
        raise ReportError(f"{path}: no line 'RAM_BUDGET = <bytes>;'")
    return int(m.group(1))


def kib(n):
    return f"{n / 1024:9.1f}"


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--elf", required=True)
    ap.add_argument("--budget-file", default=os.path.join(here, "..", "port", "mps2_an500", "ram_budget.ld"))
    ap.add_argument("--budget", type=int, help="override the budget file [bytes]")
    ap.add_argument("--no-budget", action="store_true",
                    help="report only (the road image and the QP-check test image have no budget)")
    ap.add_argument("--nm", default="arm-none-eabi-nm")
    ap.add_argument("--objdump", default="arm-none-eabi-objdump")
    args = ap.parse_args()
    try:
        secs = sections(args.elf, args.objdump)
        for s in (".data", ".bss", ".stack"):
            if s not in secs:
                raise ReportError(f"{args.elf}: no section {s}")
        table = ram_table(args.elf, args.objdump)
        symbols = ram_symbols(args.elf, args.nm)
        budget = args.budget if args.budget is not None else budget_from(args.budget_file)
    except ReportError as e:
        print(f"size_report: error: {e}", file=sys.stderr)
        return 1

    sizes = dict(table)
    service_syms = [s for s in symbols if s[0].endswith(SERVICE_SYMBOL)]
    if len(service_syms) != 1:
        print(f"size_report: error: expected one {SERVICE_SYMBOL} symbol, found {len(service_syms)}", file=sys.stderr)
        return 1
    if service_syms[0][1] != sizes.get("service"):
        print(f"size_report: error: {SERVICE_SYMBOL} is {service_syms[0][1]} bytes but {TABLE_SECTION} says "
              f"{sizes.get('service')}: the table is stale", file=sys.stderr)
        return 1

    rows = []  # (depth, label, bytes)

    def children(parent):
        prefix = parent + "."
        return [n for n, _ in table if n.startswith(prefix) and "." not in n[len(prefix):]]

    def emit(name, depth):
        rows.append((depth, LABELS.get(name, name), sizes[name]))
        kids = children(name)
        for k in kids:
            emit(k, depth + 1)
        if kids:
            rest = sizes[name] - sum(sizes[k] for k in kids)
            if rest < 0:
                print(f"size_report: error: the parts of {name} exceed it", file=sys.stderr)
                sys.exit(1)
            if rest:
                rows.append((depth + 1, "other (members, padding)", rest))

    emit("service", 0)
    others = [s for s in symbols if not s[0].endswith(SERVICE_SYMBOL)]
    others_total = sum(s[1] for s in others)
    rows.append((0, f"other statics ({len(others)} symbols: newlib, port)", others_total))
    stack = secs[".stack"]
    rows.append((0, "stack (linker script; bound + margin, `make stack`)", stack))
    total = secs[".data"] + secs[".bss"] + stack
    gaps = total - sizes["service"] - others_total - stack
    if gaps:
        rows.append((0, "alignment between symbols", gaps))

    width = max(len("  " * d + l) for d, l, _ in rows) + 2
    print(f"RAM by module ({os.path.basename(args.elf)}; sizes as the ARM compiler laid them out)")
    print(f"{'module':<{width}} {'bytes':>9} {'KiB':>9}")
    for depth, label, n in rows:
        print(f"{'  ' * depth + label:<{width}} {n:9d} {kib(n)}")
    print("-" * (width + 20))
    print(f"{'total .data + .bss + stack':<{width}} {total:9d} {kib(total)}")
    print(f"{'  .data / .bss / .stack':<{width}} {secs['.data']} / {secs['.bss']} / {stack}")
    if args.no_budget:
        print("size_report: ok (no budget for this image: its figure is reported)")
        return 0
    source = "--budget" if args.budget is not None else "port/mps2_an500/ram_budget.ld"
    print(f"{'budget (' + source + ')':<{width}} {budget:9d} {kib(budget)}")
    print(f"{'goal (issue 12)':<{width}} {GOAL_BYTES:9d} {kib(GOAL_BYTES)}"
          f"   ({total - GOAL_BYTES:+d} bytes from it)")
    if total > budget:
        print(f"size_report: error: RAM {total} bytes exceeds the budget of {budget} bytes", file=sys.stderr)
        return 1
    print(f"size_report: ok, {budget - total} bytes under the budget")
    return 0


if __name__ == "__main__":
    sys.exit(main())
