#!/usr/bin/env python3
"""The QEMU stack-paint test (issue 12, docs/memory.md).

1. The stack bound: tools/stack_analysis.py on the cross build's .su/.ci files.
2. The measured peak: closed-loop scenes planned by the Cortex-M7 firmware
   under QEMU (hil_sim run --target qemu), then its Diagnostics reply, whose
   peak comes from the stack the start-up code painted (never from the
   analysis).
3. Passes when 0 < painted peak < bound <= the linker script's stack.
Python 3 standard library only.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--hil-sim", required=True)
    ap.add_argument("--elf", required=True)
    ap.add_argument("--build", required=True, help="the cross build directory (.su/.ci files)")
    ap.add_argument("--analysis", required=True, help="tools/stack_analysis.py")
    ap.add_argument("--count", type=int, default=3, help="closed-loop scenes to run")
    ap.add_argument("--config", default="default", help="the image's planner configuration (hil_sim run --config)")
    args = ap.parse_args()

    with tempfile.TemporaryDirectory() as tmp:
        bound_json = os.path.join(tmp, "analysis.json")
        diag_json = os.path.join(tmp, "diagnostics.json")
        r = subprocess.run([sys.executable, args.analysis, "--build", args.build, "--elf", args.elf,
                            "--json", bound_json, "--quiet"])
        if r.returncode != 0:
            print("stack_paint_check: the stack analysis failed", file=sys.stderr)
            return 1
        with open(bound_json, encoding="utf-8") as f:
            analysis = json.load(f)
        r = subprocess.run([args.hil_sim, "run", "--suite", "default", "--count", str(args.count), "--seed", "1",
                            "--target", "qemu", "--config", args.config, "--firmware", args.elf,
                            "--diagnostics", diag_json])
        if r.returncode != 0:
            print(f"stack_paint_check: hil_sim run failed ({r.returncode})", file=sys.stderr)
            return 1
        with open(diag_json, encoding="utf-8") as f:
            diag = json.load(f)

    bound = analysis["bound_bytes"]
    peak = diag["stack_peak_bytes"]
    size = diag["stack_bytes"]
    print(f"painted peak {peak} bytes over {diag['scenes']} closed-loop scenes; analysed bound {bound} bytes "
          f"({100.0 * peak / bound:.1f} % of it); stack {size} bytes (linker script {analysis['linker_stack_bytes']})")
    ok = True
    if size != analysis["linker_stack_bytes"]:
        print("error: the firmware's stack size differs from the ELF's .stack section", file=sys.stderr)
        ok = False
    if peak <= 0:
        print("error: no painted peak: the firmware did not paint or measure its stack", file=sys.stderr)
        ok = False
    if peak >= bound:
        print(f"error: the measured peak {peak} is not below the analysed bound {bound}: "
              f"the analysis misses a path", file=sys.stderr)
        ok = False
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
