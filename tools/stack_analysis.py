#!/usr/bin/env python3
"""Worst-case stack depth of the Cortex-M7 firmware from GCC's own data.

The cross build compiles every object with `-fstack-usage -fcallgraph-info=su`
(CMake option ITP_STACK_USAGE), which writes next to each object file
  X.su  one line per function: "file:line:col:name<TAB>bytes<TAB>qualifier"
  X.ci  the object's call graph in VCG text: one node per function (its
        frame size and qualifier in the label), one edge per call site, and
        calls through a pointer as edges to "__indirect_call".
This tool reads all of them (but another firmware image's own objects:
CMakeFiles/X.dir next to X.elf), builds the call graph, and computes the deepest
path from Reset_Handler and from every other handler in the ELF's vector
table. It fails (exit 1), naming the culprit, on
  - recursion (a cycle reachable from a root),
  - a frame GCC calls `dynamic` (alloca, variable-length arrays); a frame
    `dynamic,bounded` is accepted with GCC's number, which is then an upper
    bound (GCC documents it so), and is listed in the report,
  - an indirect call that tools/stack_targets.txt does not resolve,
  - a called function without stack data (newlib, libgcc) that
    tools/stack_targets.txt gives no bound for,
  - a linker-script stack (.stack in the ELF) smaller than bound + margin.
Nothing is ignored silently: every resolution from the targets file that was
used is printed. A call to a function that GCC folded into an identical one
(identical code folding, -fipa-icf: the folded function has no stack data of
its own, the ELF names both at one address, e.g. a template instantiated for
two configurations whose sizes it does not use) resolves to that one; these
are counted in the report.

The bound. Handlers preempt the main path. The firmware masks interrupts
(PRIMASK) and polls, so only the fault handlers and NMI can run; to stay
safe without a priority analysis, the bound assumes every distinct handler
could nest on top of the deepest main path at once:
  bound = main + sum over distinct handlers (handler path + exception frame)
with the Cortex-M7's largest exception frame (FP context: 26 words plus one
alignment word = 108 bytes) per nesting level.
The margin: 25 % of the bound, and the sum rounded up to 256 bytes.

Usage: stack_analysis.py --build build/cortex-m7 --elf ELF [--targets FILE]
                         [--json OUT] [--quiet]
Python 3 standard library only; needs arm-none-eabi-nm and -objdump on PATH.
"""
import argparse
import fnmatch
import json
import math
import os
import re
import subprocess
import sys

EXCEPTION_FRAME_BYTES = 108  # 8 basic + 18 FP words, + 1 alignment word
INDIRECT = "__indirect_call"
DEFAULT_MARGIN_PERCENT = 25
ROUND_TO = 256


class AnalysisError(Exception):
    pass


# --------------------------------------------------------------------------
# Input files


NODE_RE = re.compile(r'^node:\s*\{\s*title:\s*"((?:[^"\\]|\\.)*)"\s*label:\s*"((?:[^"\\]|\\.)*)"')
EDGE_RE = re.compile(r'^edge:\s*\{\s*sourcename:\s*"((?:[^"\\]|\\.)*)"\s*targetname:\s*"((?:[^"\\]|\\.)*)"'
                     r'(?:\s*label:\s*"((?:[^"\\]|\\.)*)")?')
FRAME_RE = re.compile(r'(\d+) bytes \(([a-z,]+)\)')


class Function:
    """One function definition in one object (the file is part of the key:
    functions in anonymous namespaces share a mangled name across files)."""

    def __init__(self, obj, symbol, name, frame, qualifier):
        self.obj = obj
        self.symbol = symbol
        self.name = name  # demangled, from the label
        self.frame = frame
        self.qualifier = qualifier
        self.calls = []  # (target symbol, call site)


def parse_ci(path):
    """Returns {symbol: Function} defined in this object, and the external
    (called but not defined here) symbols with their labels."""
    defs = {}
    externals = {}
    edges = []
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            line = line.strip()
            m = NODE_RE.match(line)
            if m:
                symbol, label = m.group(1), m.group(2).replace("\\n", "\n")
                parts = label.split("\n")
                frame = FRAME_RE.search(label)
                if frame:
                    defs[symbol] = Function(path, symbol, parts[0], int(frame.group(1)), frame.group(2))
                elif symbol != INDIRECT:
                    externals[symbol] = parts[0]
                continue
            m = EDGE_RE.match(line)
            if m:
                edges.append((m.group(1), m.group(2), m.group(3) or ""))
    for src, dst, site in edges:
        if src not in defs:
            raise AnalysisError(f"{path}: edge from {src}, which has no stack data")
        defs[src].calls.append((dst, site))
    return defs, externals


SU_RE = re.compile(r'^(.*):(\d+):(\d+):(.*)\t(\d+)\t([a-z,]+)\s*$')


def parse_su(path):
    """Returns [(location, name, bytes, qualifier)]."""
    rows = []
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            m = SU_RE.match(line.rstrip("\n"))
            if not m:
                if line.strip():
                    raise AnalysisError(f"{path}: unreadable line: {line.strip()}")
                continue
            rows.append((f"{m.group(1)}:{m.group(2)}:{m.group(3)}", m.group(4), int(m.group(5)), m.group(6)))
    return rows


def parse_targets(path):
    """tools/stack_targets.txt (its header says more):
      lib SYMBOL BYTES             a function without stack data (newlib,
                                   libgcc): its deepest use, callees included
      call CALLER -> CALLEE...     the targets of CALLER's indirect calls;
                                   CALLER is a symbol or a shell pattern on
                                   the demangled name; CALLEE a symbol,
                                   `@init_array` (the ELF's constructor table)
                                   or `-` (no target in this firmware)
      absent SYMBOL                the ELF must not define SYMBOL (backs a `-`)"""
    libs = {}
    calls = {}
    absent = []
    if not path:
        return libs, calls, absent
    with open(path, encoding="utf-8") as f:
        for n, raw in enumerate(f, 1):
            line = raw.split("#", 1)[0].strip()
            if not line:
                continue
            where = f"{path}:{n}"
            if line.startswith("lib "):
                parts = line.split()
                if len(parts) != 3 or not parts[2].isdigit():
                    raise AnalysisError(f"{where}: expected 'lib NAME BYTES'")
                libs[parts[1]] = int(parts[2])
            elif line.startswith("call "):
                body = line[len("call "):]
                if "->" not in body:
                    raise AnalysisError(f"{where}: expected 'call CALLER -> CALLEE [CALLEE...]'")
                caller, callees = body.split("->", 1)
                names = callees.split()
                if not caller.strip() or not names:
                    raise AnalysisError(f"{where}: expected 'call CALLER -> CALLEE [CALLEE...]'")
                calls.setdefault(caller.strip(), []).extend(names)
            elif line.startswith("absent "):
                parts = line.split()
                if len(parts) != 2:
                    raise AnalysisError(f"{where}: expected 'absent SYMBOL'")
                absent.append(parts[1])
            else:
                raise AnalysisError(f"{where}: unknown entry '{line}' (lib, call or absent)")
    return libs, calls, absent


def bare_symbol(title):
    """"/path/file.cpp:_Z3foov" -> "_Z3foov" (mangled names have no ':')."""
    return title.rsplit(":", 1)[-1]


CTOR_ALIAS_RE = re.compile(r'(C1|D1)(E|Ev)')


def alias_of(symbol):
    """The base-object ctor/dtor (C2/D2) for a complete-object one (C1/D1)."""
    bare = bare_symbol(symbol)
    matches = list(CTOR_ALIAS_RE.finditer(bare))
    if not matches:
        return None
    m = matches[-1]
    return bare[:m.start()] + ("C2" if m.group(1) == "C1" else "D2") + bare[m.end(1):]


def run(cmd):
    try:
        return subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        raise AnalysisError(f"{' '.join(cmd)} failed: {e}")


def elf_aliases(elf, nm):
    """{symbol: [other function symbols at the same address]} of the ELF."""
    at = {}
    for line in run([nm, elf]).splitlines():
        parts = line.split()
        if len(parts) == 3 and parts[1] in "TtWw":
            at.setdefault(int(parts[0], 16), []).append(parts[2])
    return {sym: [o for o in syms if o != sym] for syms in at.values() if len(syms) > 1 for sym in syms}


def elf_functions(elf, nm):
    """{address: symbol} of the ELF's functions."""
    by_addr = {}
    for line in run([nm, elf]).splitlines():
        parts = line.split()
        if len(parts) == 3 and parts[1] in "TtWw":
            by_addr.setdefault(int(parts[0], 16), parts[2])
    return by_addr


def section_words(elf, objdump, section):
    words = []
    for line in run([objdump, "-s", "-j", section, elf]).splitlines():
        m = re.match(r'^\s*([0-9a-f]+)\s+((?:[0-9a-f]{8}\s){1,4})', line)
        if m:
            for w in m.group(2).split():
                words.append(int.from_bytes(bytes.fromhex(w), "little"))
    return words


def init_array(elf, objdump, by_addr):
    """Symbols of the static constructors the reset handler calls."""
    if ".init_array" not in run([objdump, "-h", elf]):
        return []
    out = []
    for w in section_words(elf, objdump, ".init_array"):
        if (w & ~1) not in by_addr:
            raise AnalysisError(f".init_array entry 0x{w:08x} is no function symbol")
        out.append(by_addr[w & ~1])
    return out


def vector_table(elf, nm, objdump):
    """[(index, symbol)] of the non-null handlers in .isr_vector."""
    by_addr = elf_functions(elf, nm)
    words = section_words(elf, objdump, ".isr_vector")
    if len(words) < 2:
        raise AnalysisError(f"{elf}: no vector table (.isr_vector)")
    handlers = []
    for i, w in enumerate(words[1:], 1):
        if w == 0:
            continue
        sym = by_addr.get(w & ~1)
        if sym is None:
            raise AnalysisError(f"vector {i} points at 0x{w:08x}, which is no function symbol")
        handlers.append((i, sym))
    return handlers


def section_size(elf, name, objdump):
    for line in run([objdump, "-h", elf]).splitlines():
        parts = line.split()
        if len(parts) >= 3 and parts[1] == name:
            return int(parts[2], 16)
    raise AnalysisError(f"{elf}: no section {name}")


# --------------------------------------------------------------------------
# The graph


class Graph:
    def __init__(self, targets_libs, targets_calls):
        self.defs = {}  # title -> [Function]
        self.prefixed = {}  # bare symbol of a "SOURCE:SYMBOL" title -> [Function]
        self.externals = {}  # symbol -> label
        self.libs = targets_libs
        self.calls = targets_calls
        self.used_libs = {}
        self.used_calls = {}
        self.bounded = {}
        self.memo = {}
        self.state = {}
        self.init_array = []  # symbols of the ELF's .init_array entries
        self.aliases = {}  # symbol -> symbols at the same ELF address (identical code folding)
        self.used_aliases = {}  # folded symbol -> the one with stack data it resolved to
        self.errors = []  # unresolved calls: all are reported, then the analysis fails

    def add(self, defs, externals):
        for title, fn in defs.items():
            self.defs.setdefault(title, []).append(fn)
            bare = bare_symbol(title)
            if bare != title:
                self.prefixed.setdefault(bare, []).append(fn)
        self.externals.update(externals)

    def resolve(self, caller, symbol):
        """The Function(s) a call from `caller` to `symbol` can reach (as
        resolve_direct), else, when GCC folded `symbol` into an identical
        function (the ELF has both at one address), that function's."""
        found = self.resolve_direct(caller, symbol)
        if found:
            return found
        bare = bare_symbol(symbol)
        prefix = symbol[:len(symbol) - len(bare)]
        for other in self.aliases.get(bare, []):
            found = self.resolve_direct(caller, prefix + other)
            if found:
                self.used_aliases[symbol] = other
                return found
        return []

    def resolve_direct(self, caller, symbol):
        """The Function(s) a call from `caller` to `symbol` can reach.
        GCC titles a function "SOURCE:SYMBOL" when it is local to its object
        or an explicit template instantiation; other objects call the bare
        SYMBOL. So: the exact title in the caller's object, else in any
        object (identical COMDAT copies: the deepest counts), else a
        "SOURCE:SYMBOL" definition of the bare symbol, else the same for the
        base-object constructor/destructor (C2/D2) when the complete-object
        one (C1/D1) is GCC's alias of it."""
        for candidate in (symbol, alias_of(symbol)):
            if candidate is None:
                continue
            own = [fn for fn in self.defs.get(candidate, []) if fn.obj == caller.obj]
            if own:
                return own
            if candidate in self.defs:
                return self.defs[candidate]
            if candidate in self.prefixed:
                return self.prefixed[candidate]
        return []

    def indirect_targets(self, fn):
        bare = bare_symbol(fn.symbol)
        for key, targets in self.calls.items():
            if key in (fn.symbol, bare) or fnmatch.fnmatchcase(fn.name, key):
                self.used_calls[key] = targets
                out = []
                for t in targets:
                    if t == "@init_array":
                        out.extend(self.init_array)
                    elif t != "-":
                        out.append(t)
                return out
        self.errors.append(
            f"unresolved indirect call in {fn.name} [{fn.symbol}] ({os.path.basename(fn.obj)}): "
            f"add 'call {fn.symbol} -> CALLEE...' to the targets file")
        return []

    def worst(self, fn, stack):
        """(bytes, path) of the deepest chain starting in fn; path is a list
        of (name, symbol, frame, note)."""
        key = (fn.obj, fn.symbol)
        if key in self.memo:
            return self.memo[key]
        if self.state.get(key) == "open":
            cycle = [f"{f.name}" for f in stack[stack.index(fn):]] + [fn.name]
            raise AnalysisError("recursion: " + " -> ".join(cycle))
        if fn.qualifier == "dynamic":
            raise AnalysisError(f"dynamic stack frame (alloca or a variable-length array) in {fn.name} "
                                f"[{fn.symbol}] ({os.path.basename(fn.obj)}): no bound")
        if fn.qualifier not in ("static", "dynamic,bounded"):
            raise AnalysisError(f"unknown stack qualifier '{fn.qualifier}' for {fn.name}")
        if fn.qualifier == "dynamic,bounded":
            self.bounded[fn.symbol] = (fn.name, fn.frame)
        self.state[key] = "open"
        stack.append(fn)
        best = (0, [])
        for target, _site in fn.calls:
            if target == INDIRECT:
                names = self.indirect_targets(fn)
                note = "indirect (targets file)"
            else:
                names = [target]
                note = ""
            for name in names:
                cand = self.callee_worst(fn, name, note, stack)
                if cand[0] > best[0]:
                    best = cand
        stack.pop()
        self.state[key] = "done"
        result = (fn.frame + best[0], [(fn.name, fn.symbol, fn.frame, fn.qualifier if fn.qualifier != "static" else "")]
                  + best[1])
        self.memo[key] = result
        return result

    def callee_worst(self, caller, symbol, note, stack):
        fns = self.resolve(caller, symbol)
        if fns:
            best = (0, [])
            for f in fns:
                cand = self.worst(f, stack)
                if cand[0] >= best[0]:
                    best = cand
            if note:
                head = best[1][0]
                best = (best[0], [(head[0], head[1], head[2], ", ".join(x for x in (head[3], note) if x))]
                        + best[1][1:])
            return best
        if symbol in self.libs:
            self.used_libs[symbol] = self.libs[symbol]
            label = self.externals.get(symbol, symbol)
            return (self.libs[symbol], [(label, symbol, self.libs[symbol],
                                         ", ".join(x for x in (note, "library bound (targets file)") if x))])
        self.errors.append(
            f"no stack data for {self.externals.get(symbol, symbol)} [{symbol}], called from {caller.name}: "
            f"a library function needs 'lib {symbol} BYTES' in the targets file")
        return (0, [])


# --------------------------------------------------------------------------


def other_image(root, d, elf):
    """True for CMakeFiles/X.dir of another firmware image: X.elf next to
    CMakeFiles, X not the analysed ELF's stem (each image compiles its own
    start-up, port and image objects; both define firmware_run)."""
    if os.path.basename(root) != "CMakeFiles" or not d.endswith(".dir"):
        return False
    target = d[:-len(".dir")]
    stem = os.path.splitext(os.path.basename(elf))[0]
    return target != stem and os.path.exists(os.path.join(os.path.dirname(root), target + ".elf"))


def other_core(d, elf):
    """True for the planner library an image does not link: the _f32 images
    link firmware_core_f32 (float), every other image firmware_core (double).
    Both define the same functions with different frames."""
    stem = os.path.splitext(os.path.basename(elf))[0]
    linked = "firmware_core_f32.dir" if stem.endswith("_f32") else "firmware_core.dir"
    return d in ("firmware_core.dir", "firmware_core_f32.dir") and d != linked


def collect(build, elf):
    ci_files, su_files = [], []
    for root, dirs, files in os.walk(build):
        # Header self-containment checks compile each header alone; they are
        # not linked into any image. Other images' own objects are not in this
        # one, nor is the other scalar's planner library.
        dirs[:] = [d for d in dirs if "header_check" not in d and not other_image(root, d, elf)
                   and not other_core(d, elf)]
        for name in files:
            if name.endswith(".ci"):
                ci_files.append(os.path.join(root, name))
            elif name.endswith(".su"):
                su_files.append(os.path.join(root, name))
    return sorted(ci_files), sorted(su_files)


def round_up(value, step):
    return int(math.ceil(value / step)) * step


def analyse(args):
    ci_files, su_files = collect(args.build, args.elf)
    if not ci_files:
        raise AnalysisError(f"no .ci files under {args.build}: configure the cross build with "
                            f"ITP_STACK_USAGE=ON (the cortex-m7 preset does) and build it")
    libs, calls, absent = parse_targets(args.targets)
    graph = Graph(libs, calls)
    symbols = elf_functions(args.elf, args.nm)
    for sym in absent:
        if sym in symbols.values():
            raise AnalysisError(f"{sym} is in the ELF, but the targets file says it is absent "
                                f"(an indirect call it backs may have a target now)")
    graph.init_array = init_array(args.elf, args.objdump, symbols)
    graph.aliases = elf_aliases(args.elf, args.nm)
    su_rows = 0
    for ci in ci_files:
        defs, externals = parse_ci(ci)
        su = ci[:-3] + ".su"
        if not os.path.exists(su):
            raise AnalysisError(f"{ci} has no matching {su}")
        rows = parse_su(su)
        su_rows += len(rows)
        # Cross-check: the two files of one object report the same frames.
        su_frames = sorted((b, q) for _, _, b, q in rows)
        ci_frames = sorted((fn.frame, fn.qualifier) for fn in defs.values())
        if su_frames != ci_frames:
            raise AnalysisError(f"{su} and {ci} disagree on the frames")
        graph.add(defs, externals)
    if len(su_files) != len(ci_files):
        raise AnalysisError(f"{len(su_files)} .su files but {len(ci_files)} .ci files under {args.build}")

    handlers = vector_table(args.elf, args.nm, args.objdump)
    if not handlers or handlers[0][0] != 1:
        raise AnalysisError("the vector table has no reset handler")
    roots = []
    seen = set()
    for index, sym in handlers:
        if sym in seen:
            continue
        seen.add(sym)
        fns = graph.defs.get(sym)
        if not fns:
            raise AnalysisError(f"vector {index} ({sym}) has no stack data")
        best = max((graph.worst(f, []) for f in fns), key=lambda r: r[0])
        roots.append((index, sym, best))

    if graph.errors:
        raise AnalysisError("\n  ".join(["the call graph has gaps:"] + sorted(set(graph.errors))))
    main = roots[0]
    handler_roots = roots[1:]
    bound = main[2][0] + sum(r[2][0] + EXCEPTION_FRAME_BYTES for r in handler_roots)
    required = round_up(bound * (100 + args.margin_percent) / 100.0, ROUND_TO)
    stack = section_size(args.elf, ".stack", args.objdump)
    return {
        "objects": len(ci_files),
        "functions": su_rows,
        "main": {"root": main[1], "bytes": main[2][0], "path": main[2][1]},
        "handlers": [{"vector": i, "root": s, "bytes": r[0], "path": r[1]} for i, s, r in handler_roots],
        "exception_frame_bytes": EXCEPTION_FRAME_BYTES,
        "bound_bytes": bound,
        "margin_percent": args.margin_percent,
        "required_stack_bytes": required,
        "linker_stack_bytes": stack,
        "library_bounds_used": graph.used_libs,
        "indirect_resolutions_used": graph.used_calls,
        "dynamic_bounded": {k: v[1] for k, v in graph.bounded.items()},
        "folded_calls_resolved": len(graph.used_aliases),
    }


def print_path(title, total, path):
    print(f"{title}: {total} bytes")
    print(f"  {'frame':>6} {'depth':>6}  function")
    depth = 0
    for name, sym, frame, note in path:
        depth += frame
        shown = name if len(name) <= 110 else name[:107] + "..."
        print(f"  {frame:6d} {depth:6d}  {shown}{'  [' + note + ']' if note else ''}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", required=True, help="cross build directory with .su/.ci files")
    ap.add_argument("--elf", required=True, help="the firmware ELF (vector table, .stack size)")
    ap.add_argument("--targets", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "stack_targets.txt"),
                    help="indirect-call resolutions and library bounds")
    ap.add_argument("--margin-percent", type=int, default=DEFAULT_MARGIN_PERCENT)
    ap.add_argument("--nm", default="arm-none-eabi-nm")
    ap.add_argument("--objdump", default="arm-none-eabi-objdump")
    ap.add_argument("--json", help="write the result as JSON here")
    ap.add_argument("--quiet", action="store_true", help="only the summary line")
    args = ap.parse_args()
    try:
        r = analyse(args)
    except AnalysisError as e:
        print(f"stack_analysis: error: {e}", file=sys.stderr)
        return 1
    if not args.quiet:
        print(f"stack_analysis: {r['functions']} functions in {r['objects']} objects")
        print_path(f"worst path from {r['main']['root']}", r["main"]["bytes"], r["main"]["path"])
        for h in r["handlers"]:
            print_path(f"worst path from vector {h['vector']} {h['root']}", h["bytes"], h["path"])
        if r["library_bounds_used"]:
            print("library bounds used (tools/stack_targets.txt):")
            for k, v in sorted(r["library_bounds_used"].items()):
                print(f"  {v:6d}  {k}")
        if r["indirect_resolutions_used"]:
            print("indirect calls resolved (tools/stack_targets.txt):")
            for k, v in sorted(r["indirect_resolutions_used"].items()):
                print(f"  {k} -> {' '.join(v)}")
        if r["folded_calls_resolved"]:
            print(f"calls to identical-code-folded functions resolved to the function kept at their address: "
                  f"{r['folded_calls_resolved']}")
        if r["dynamic_bounded"]:
            print("dynamic,bounded frames (GCC's number taken as the bound):")
            for k, v in sorted(r["dynamic_bounded"].items()):
                print(f"  {v:6d}  {k}")
    handlers = " + ".join(f"{h['root']} {h['bytes']}+{r['exception_frame_bytes']}" for h in r["handlers"])
    print(f"stack bound: {r['bound_bytes']} bytes (main {r['main']['bytes']}"
          f"{' + ' + handlers if handlers else ''}); with {r['margin_percent']} % margin, rounded up to "
          f"{ROUND_TO} B: {r['required_stack_bytes']} bytes; linker script stack: {r['linker_stack_bytes']} bytes")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as f:
            json.dump(r, f, indent=1)
    if r["linker_stack_bytes"] < r["required_stack_bytes"]:
        print(f"stack_analysis: error: the linker script's stack ({r['linker_stack_bytes']} bytes) is smaller "
              f"than bound + margin ({r['required_stack_bytes']} bytes): raise STACK_SIZE in "
              f"port/mps2_an500/mps2_an500.ld", file=sys.stderr)
        return 1
    if r["linker_stack_bytes"] > r["required_stack_bytes"]:
        print(f"stack_analysis: note: the linker script's stack is {r['linker_stack_bytes'] - r['required_stack_bytes']}"
              f" bytes larger than bound + margin; STACK_SIZE = {r['required_stack_bytes']} would do")
    return 0


if __name__ == "__main__":
    sys.exit(main())
