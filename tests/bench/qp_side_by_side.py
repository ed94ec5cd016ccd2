#!/usr/bin/env python3
"""Side-by-side QP benchmark: our solver (qp_solve) next to DAQP, qpOASES and OSQP
(qpanchors, /work/shared/tools/qp-anchors) on the very same qp-text/1 files, in one run.

Sets
  planner_coarse / planner_speed / planner_path
      the planner's QPs: `hil_sim gen --count S --seed 1` (the default suite's first S scenes),
      `planner_cli plan SCENE --dump-qp DIR` (every QP of the scene's first planning cycle);
      one sequence per scene and kind, in the order the planner solved them.
  mm  the Maros-Meszaros problems (QPS, converted once by `qp_solve --write-qp-text`, obj_ref from
      tests/qp/data/maros_meszaros_optima.txt). cold: each problem. warm / hot: a sequence per
      problem, the original followed by F variants with g' = g + c H delta (delta uniform in
      [-1, 1]^n, fixed seed; |c H delta| = p max(1, |g|), inf-norms, p = --perturb): same H, A
      and bounds, optimum moved; since H delta is orthogonal to
      every direction d with H d = 0, a bounded problem stays bounded (a receding-horizon-like
      update). Only the variants are timed warm / hot.

Modes (what each tool times: `qp_solve --help`, `qpanchors --help`)
  cold  each file on its own; warm  from the previous file's working set / solution, H and A
  refactored; hot  previous factorisation re-used where H and A are bit-identical to the
  previous file's (else that file is solved warm by every tool and left out of the hot figures).

Timing: every unit (cold: one file or one scene's files; warm / hot: one sequence) is run by all
solvers in turn, rounds times, the order rotated each round, so machine load hits all alike.
Each call reports a median over --repeat solves; a file's figure is the median over the rounds.
Ours and an anchor are compared on the files that both called optimal, with the requested start.
Ratios are ours / anchor: of the set's medians, and the geometric mean of per-file ratios.

Output: a Markdown table on stdout (and --md FILE), every per-file figure in --json FILE.
Python 3 standard library only.

  tests/bench/qp_side_by_side.py --build build/host-release --scenes 20 \\
      --json build/qp_side_by_side.json --md build/qp_side_by_side.md
"""
import argparse
import collections
import datetime
import glob
import json
import math
import os
import platform
import random
import re
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, '..', '..'))
NAMES = {'ours': 'ours', 'daqp': 'DAQP', 'qpoases': 'qpOASES', 'osqp': 'OSQP'}


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split('\n')[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    p.add_argument('--build', default=os.path.join(ROOT, 'build', 'host-release'),
                   help='build dir with hil_sim/qp_solve, hil_sim/planner_cli, hil_sim/hil_sim')
    p.add_argument('--anchors', default='/work/shared/tools/qp-anchors/qpanchors', help='qpanchors executable')
    p.add_argument('--solvers', default='daqp,qpoases,osqp', help='qpanchors solvers (comma-separated)')
    p.add_argument('--modes', default='cold,warm,hot')
    p.add_argument('--sets', default='planner,mm', help='planner and/or mm')
    p.add_argument('--rounds', type=int, default=3, help='rounds per unit (order rotated)')
    p.add_argument('--repeat', type=int, default=5, help='--repeat of every call')
    p.add_argument('--scenes', type=int, default=20, help='default-suite scenes whose first cycle is dumped')
    p.add_argument('--seed', type=int, default=1, help='suite seed (1: the default suite)')
    p.add_argument('--mm', default='/work/shared/data/maros-meszaros', help='folder of Maros-Meszaros *.QPS')
    p.add_argument('--mm-optima', default=os.path.join(ROOT, 'tests', 'qp', 'data', 'maros_meszaros_optima.txt'))
    p.add_argument('--followers', type=int, default=3, help='mm warm/hot: variants per problem')
    p.add_argument('--perturb', type=float, default=0.05, help='mm variants: |g\' - g| = this * max(1, |g|)')
    p.add_argument('--work', default=None, help='scratch folder (default BUILD/qp_side_by_side)')
    p.add_argument('--json', default=None, help='write every per-file figure here')
    p.add_argument('--md', default=None, help='write the Markdown tables here')
    p.add_argument('--summarise', default=None, metavar='JSON', help='only print the tables of an earlier --json')
    return p.parse_args()


def run(cmd, **kw):
    return subprocess.run(cmd, capture_output=True, text=True, **kw)


# ---- qp-text/1 ----------------------------------------------------------------------------
def read_qp_text(path):
    toks = []
    with open(path) as f:
        for line in f:
            if line.lstrip().startswith('#'):
                continue
            toks.extend(line.split())
    assert toks[0] == 'qp-text/1' and toks[1] == 'n' and toks[3] == 'm', path
    n, m = int(toks[2]), int(toks[4])
    size = {'H': n * n, 'g': n, 'A': m * n, 'lbA': m, 'ubA': m, 'lb': n, 'ub': n, 'x_ref': n, 'obj_ref': 1}
    sec, i = {}, 5
    while i < len(toks):
        key = toks[i]
        sec[key] = toks[i + 1:i + 1 + size[key]]
        i += 1 + size[key]
    return n, m, sec


def write_qp_text(path, n, m, sec):
    with open(path, 'w') as f:
        f.write(f'qp-text/1\nn {n} m {m}\n')
        for key, rows in (('H', n), ('g', 1), ('A', m), ('lbA', 1), ('ubA', 1), ('lb', 1), ('ub', 1),
                          ('x_ref', 1), ('obj_ref', 1)):
            if key not in sec:
                continue
            f.write(key + '\n')
            v = sec[key]
            per = len(v) // rows if rows else 0
            for r in range(rows):
                f.write(' '.join(v[r * per:(r + 1) * per]) + '\n')


def moved_optimum(src, dst, rng, p):
    """g' = g + c H delta, delta uniform in [-1, 1]^n, c such that |c H delta| = p max(1, |g|) (inf-norms);
    everything else (H, A, bounds) as in src; no reference solution."""
    n, m, sec = read_qp_text(src)
    H = [float(v) for v in sec['H']]
    g = [float(v) for v in sec['g']]
    d = [rng.uniform(-p, p) for _ in range(n)]
    hd = [sum(H[i * n + j] * d[j] for j in range(n) if H[i * n + j] != 0.0) for i in range(n)]
    scale = p * max([1.0] + [abs(v) for v in g]) / max([1e-300] + [abs(v) for v in hd])
    g2 = [g[i] + scale * hd[i] for i in range(n)]
    out = {k: v for k, v in sec.items() if k not in ('x_ref', 'obj_ref')}
    out['g'] = [repr(v) for v in g2]
    write_qp_text(dst, n, m, out)


# ---- the sets ------------------------------------------------------------------------------
def prepare_planner(a, work):
    """Units: (name, [files]) per scene and kind, files in the planner's order."""
    scenes = os.path.join(work, 'scenes')
    os.makedirs(scenes, exist_ok=True)
    r = run([os.path.join(a.build, 'hil_sim', 'hil_sim'), 'gen', '--count', str(a.scenes), '--seed', str(a.seed),
             '--out', scenes])
    if r.returncode != 0:
        sys.exit('hil_sim gen failed: ' + r.stderr)
    units = {'planner_coarse': [], 'planner_speed': [], 'planner_path': []}
    for scene in sorted(glob.glob(os.path.join(scenes, '*.json')))[:a.scenes]:
        name = os.path.splitext(os.path.basename(scene))[0]
        dump = os.path.join(work, 'dumps', name)
        for old in glob.glob(os.path.join(dump, '*.qp')):
            os.remove(old)
        r = run([os.path.join(a.build, 'hil_sim', 'planner_cli'), 'plan', scene, '--dump-qp', dump])
        if r.returncode != 0:
            sys.exit(f'planner_cli plan {scene} failed: {r.stderr}')
        files = sorted(glob.glob(os.path.join(dump, '*.qp')))
        for kind in ('coarse', 'speed', 'path'):
            seq = [f for f in files if f.endswith(f'_{kind}.qp')]
            if seq:
                units['planner_' + kind].append((f'{name}/{kind}', seq))
    return units


def prepare_mm(a, work):
    """cold units: one problem each; warm/hot units: the problem and its variants."""
    out = os.path.join(work, 'mm')
    os.makedirs(out, exist_ok=True)
    qps = sorted(glob.glob(os.path.join(a.mm, '*.QPS')))
    r = run([os.path.join(a.build, 'hil_sim', 'qp_solve'), '--references', a.mm_optima, '--write-qp-text', out] + qps)
    if not glob.glob(os.path.join(out, '*.qp')):
        sys.exit('qp_solve --write-qp-text failed: ' + r.stderr)
    rng = random.Random(20240615)
    cold, seq = [], []
    for q in qps:
        name = os.path.splitext(os.path.basename(q))[0]
        base = os.path.join(out, name + '.qp')
        variants = []
        for k in range(1, a.followers + 1):
            v = os.path.join(out, 'moved', f'{name}~{k}.qp')
            os.makedirs(os.path.dirname(v), exist_ok=True)
            moved_optimum(base, v, rng, a.perturb)
            variants.append(v)
        cold.append((name, [base]))
        seq.append((name, [base] + variants))
    return cold, seq


# ---- timing --------------------------------------------------------------------------------
def call(a, tool, mode, files):
    flag = [] if mode == 'cold' else ['--' + mode]
    if tool == 'ours':
        r = run([os.path.join(a.build, 'hil_sim', 'qp_solve'), '--json', '--repeat', str(a.repeat)] + flag + files)
        recs = json.loads(r.stdout)['results']
    else:
        r = run([a.anchors, '--solver', tool, '--json', '--repeat', str(a.repeat)] + flag + files)
        recs = json.loads(r.stdout)
    return {rec['file']: rec for rec in recs}


def time_units(a, tools, mode, units, timed):
    """Per file and tool: list of per-call medians, and the last record. `timed(i)`: is the
    i-th file of a unit part of the comparison."""
    per = {}
    for u, (uname, files) in enumerate(units):
        times = {t: {f: [] for f in files} for t in tools}
        last = {}
        for k in range(a.rounds):
            s = (u + k) % len(tools)
            for t in tools[s:] + tools[:s]:
                recs = call(a, t, mode, files)
                last[t] = recs
                for f in files:
                    if f in recs:
                        times[t][f].append(recs[f].get('median_us', float('nan')))
        for i, f in enumerate(files):
            if not timed(i):
                continue
            row = {'unit': uname}
            for t in tools:
                rec = last[t].get(f, {'status': 'missing'})
                row[t] = {'status': rec.get('status'), 'start': rec.get('start', 'cold' if mode == 'cold' else None),
                          'median_us': statistics.median(times[t][f]) if times[t][f] else None,
                          'objective': rec.get('objective'), 'rel_obj_err': rec.get('rel_obj_err'),
                          'iterations': rec.get('iterations')}
            per[f] = row
        print(f'  {mode:4s} {uname}', file=sys.stderr, flush=True)
    return per


def summarise(tools, mode, per):
    """Per anchor, the files that ours and that anchor both solved optimal with the requested start."""
    files = list(per)
    good = lambda f, t: per[f][t]['status'] == 'optimal' and per[f][t]['start'] == mode
    s = {'files': len(files),
         'optimal': {t: sum(per[f][t]['status'] == 'optimal' for f in files) for t in tools},
         'started_as_mode': {t: sum(per[f][t]['start'] == mode for f in files) for t in tools},
         'statuses': {t: dict(collections.Counter(str(per[f][t]['status']) for f in files)) for t in tools},
         'pairs': {}}
    if mode == 'cold':
        s['rel_obj_err_le_1e-6'] = {t: sum(1 for f in files if per[f][t]['status'] == 'optimal'
                                           and per[f][t]['rel_obj_err'] is not None
                                           and per[f][t]['rel_obj_err'] <= 1e-6) for t in tools}
        s['with_obj_ref'] = sum(1 for f in files if per[f]['ours']['rel_obj_err'] is not None)
    for t in tools[1:]:
        ok = [f for f in files if good(f, 'ours') and good(f, t)]
        if not ok:
            continue
        r = [per[f]['ours']['median_us'] / per[f][t]['median_us'] for f in ok]
        mo = statistics.median(per[f]['ours']['median_us'] for f in ok)
        ma = statistics.median(per[f][t]['median_us'] for f in ok)
        s['pairs'][t] = {'compared': len(ok), 'ours_median_us': mo, 'anchor_median_us': ma,
                         'ratio_of_medians': mo / ma,
                         'geomean_ratio': math.exp(sum(math.log(x) for x in r) / len(r)),
                         'files_ours_slower': sum(x > 1.0 for x in r),
                         'max_rel_obj_diff': max(abs(per[f][t]['objective'] - per[f]['ours']['objective'])
                                                 / max(1.0, abs(per[f]['ours']['objective'])) for f in ok)}
    return s


def versions(anchors):
    readme = os.path.join(os.path.dirname(anchors), 'README.md')
    out = {}
    try:
        for line in open(readme):
            m = re.match(r'\|\s*`(daqp|qpoases|osqp)`.*?\|\s*([^|]+?)\s*\|', line)
            if m:
                out[m.group(1)] = m.group(2)
    except OSError:
        pass
    return out


def load():
    try:
        return open('/proc/loadavg').read().split()[:3]
    except OSError:
        return None


def markdown(summary, tools):
    anchors = [t for t in tools if t != 'ours']
    L = ['| set | mode | ' + ' | '.join(f'vs {NAMES[t]}: files, ours / {NAMES[t]} µs, ratio (geo-mean), files ours slower'
                                        for t in anchors) + ' |',
         '|---|---|' + '---|' * len(anchors)]
    for (name, mode), s in summary.items():
        cells = []
        for t in anchors:
            p = s['pairs'].get(t)
            if not p:
                cells.append('–')
                continue
            ratio = f'{p["ratio_of_medians"]:.3f} ({p["geomean_ratio"]:.3f})'
            if t == 'daqp' and (p['ratio_of_medians'] > 1.0 or p['geomean_ratio'] > 1.0):
                ratio = f'**{ratio}**'
            cells.append(f'{p["compared"]}: {p["ours_median_us"]:.1f} / {p["anchor_median_us"]:.1f}, {ratio}, '
                         f'{p["files_ours_slower"]}')
        L.append(f'| {name} | {mode} | ' + ' | '.join(cells) + ' |')
    L += ['', 'Per anchor: the files that both ours and it solved optimal (with the requested start); medians '
          'of the per-file figures; ratio = ours / anchor of the medians, in brackets the geometric mean of the '
          'per-file ratios (< 1: ours faster; bold: slower than DAQP by either); then the files where ours was '
          'slower.', '',
          '| set | mode | files | ' + ' | '.join(f'{NAMES[t]} optimal' for t in tools) + ' |',
          '|---|---|---|' + '---|' * len(tools)]
    for (name, mode), s in summary.items():
        opt = []
        for t in tools:
            c = f'{s["optimal"][t]}'
            if 'rel_obj_err_le_1e-6' in s and s['with_obj_ref']:
                c += f' ({s["rel_obj_err_le_1e-6"][t]} to 1e-6)'
            if mode != 'cold' and s['started_as_mode'][t] != s['files']:
                c += f', {s["started_as_mode"][t]} {mode}'
            opt.append(c)
        L.append(f'| {name} | {mode} | {s["files"]} | ' + ' | '.join(opt) + ' |')
    return '\n'.join(L) + '\n'


def header(result):
    m = result['machine']
    return (f'{result["date"]}, {m.get("cpu", "?")}, {m["cpus"]} CPUs, load {m["load_before"]} before / '
            f'{m["load_after"]} after; rounds {result["rounds"]} x repeat {result["repeat"]}\n\n')


def resummarise(path, md_out):
    """--summarise JSON: the tables again from a run's per-file figures."""
    result = json.load(open(path))
    tools = ['ours'] + [t for t in ('daqp', 'qpoases', 'osqp', 'osqp3')
                        if any(t in row for per in result['files'].values() for row in per.values())]
    summary = {}
    for key, per in result['files'].items():
        name, mode = key.rsplit('/', 1)
        summary[(name, mode)] = summarise(tools, mode, per)
    text = header(result) + markdown(summary, tools)
    print(text)
    if md_out:
        with open(md_out, 'w') as f:
            f.write(text)


def main():
    a = parse_args()
    if a.summarise:
        return resummarise(a.summarise, a.md)
    a.build = os.path.abspath(a.build)
    work = os.path.abspath(a.work or os.path.join(a.build, 'qp_side_by_side'))
    os.makedirs(work, exist_ok=True)
    tools = ['ours'] + [t for t in a.solvers.split(',') if t]
    modes = [m for m in a.modes.split(',') if m]
    sets = {}
    if 'planner' in a.sets:
        for name, units in prepare_planner(a, work).items():
            sets[name] = {m: (units, (lambda i: True) if m == 'cold' else (lambda i: i > 0)) for m in modes}
    if 'mm' in a.sets:
        cold, seq = prepare_mm(a, work)
        sets['mm'] = {m: ((cold, lambda i: True) if m == 'cold' else (seq, lambda i: i > 0)) for m in modes}
    result = {'date': datetime.datetime.now().isoformat(timespec='seconds'),
              'machine': {'platform': platform.platform(), 'cpus': os.cpu_count(), 'load_before': load()},
              'qp_solve': os.path.join(a.build, 'hil_sim', 'qp_solve'), 'anchors': a.anchors,
              'versions': versions(a.anchors), 'rounds': a.rounds, 'repeat': a.repeat, 'scenes': a.scenes,
              'seed': a.seed, 'followers': a.followers, 'perturb': a.perturb, 'argv': sys.argv,
              'summary': {}, 'files': {}}
    try:
        result['machine']['cpu'] = next(l.split(':', 1)[1].strip() for l in open('/proc/cpuinfo')
                                        if l.startswith('model name'))
    except (OSError, StopIteration):
        pass
    for name, by_mode in sets.items():
        for mode, (units, timed) in by_mode.items():
            print(f'{name} {mode}: {len(units)} units', file=sys.stderr, flush=True)
            per = time_units(a, tools, mode, units, timed)
            result['files'][f'{name}/{mode}'] = per
            result['summary'][(name, mode)] = summarise(tools, mode, per)
    result['machine']['load_after'] = load()
    text = header(result) + markdown(result['summary'], tools)
    print(text)
    if a.md:
        with open(a.md, 'w') as f:
            f.write(text)
    if a.json:
        result['summary'] = [dict(set=k[0], mode=k[1], **v) for k, v in result['summary'].items()]
        with open(a.json, 'w') as f:
            json.dump(result, f, indent=1)


if __name__ == '__main__':
    main()
