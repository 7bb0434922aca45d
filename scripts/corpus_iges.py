#!/usr/bin/env python3
"""Runs `prw bake` and `prw info` on every IGES file of a directory and prints a table.

usage: scripts/corpus_iges.py DIR [--prw PATH] [--timeout S] [--tsv OUT.tsv] [--compare BASE.tsv]
                              [--render OUTDIR]

For each *.igs / *.iges file (sorted by name): the exporter (native system ID, Global parameter 5,
else the preprocessor version, parameter 6), the surfaces the reader kept, and two results:
  bake: `prw bake FILE --no-cache` (fresh cache directory), ok / refused: <message> / crash (signal)
        / timeout; "ok*" when the hierarchy has failed patches; its wall and CPU seconds (on a shared
        machine a wall-clock timeout with few CPU seconds is the load, not the file; timed-out runs
        are listed at the end with the CPU seconds they had used);
  info: `prw info` of a one-entry manifest naming the file: ok / refused / crash / timeout.
A file LOADS when `prw info` accepts it; it is RENDER-READY when `prw bake` builds its hierarchy
with no failed patch.  --render OUTDIR also opens each file directly, `prw render FILE --size
160x120` (its own bake, same timeout), and judges the PNG with scripts/png_stats.py (an image, or
black / empty / flat / clipped).  --tsv writes the rows; --compare BASE.tsv (a --tsv of another build) lists
files that load in BASE but not here.  Exit status 1 when any run crashed or timed out, or (with
--render) a render that exited 0 is not an image.
Only the Python standard library; the corpus itself is never part of the repository: the public
corpus the issue's figures use is listed in scripts/iges_corpus_sources.tsv (file name, GitHub
repository, path, commit, bytes, sha256 prefix) to fetch it again.
"""
import argparse
import json
import os
import re
import resource
import signal
import subprocess
import sys
import tempfile
import time


def global_fields(path):
    """Global-section parameters (strings for Hollerith fields), or [] when unreadable."""
    try:
        with open(path, 'rb') as f:
            data = f.read()
    except OSError:
        return []
    text = data.decode('latin-1')
    lines = text.splitlines()
    if len(lines) <= 2 and len(text) > 160:  # bare 80-column records
        flat = text.replace('\r', '').replace('\n', '')
        lines = [flat[i:i + 80] for i in range(0, len(flat), 80)]
    g = ''.join(l[:72] for l in lines if len(l) >= 73 and l[72] == 'G')
    if not g:
        return []
    pd, rd, i = ',', ';', 0
    for k in range(2):  # delimiters: empty (default) or 1Hc
        if g[i:i + 2] == '1H':
            c = g[i + 2]
            if k == 0:
                pd = c
            else:
                rd = c
            i += 3
        if i < len(g) and g[i] in (pd, rd):
            i += 1
    out = ['', '']
    while i < len(g):
        while i < len(g) and g[i] == ' ':
            i += 1
        m = re.match(r'(\d+)H', g[i:])
        if m:
            n = int(m.group(1))
            s = i + len(m.group(0))
            out.append(g[s:s + n].strip())
            i = s + n
            while i < len(g) and g[i] not in (pd, rd):
                i += 1
        else:
            j = i
            while j < len(g) and g[j] not in (pd, rd):
                j += 1
            out.append(g[i:j].strip())
            i = j
        if i >= len(g) or g[i] == rd:
            break
        i += 1
    return out


def exporter(path):
    f = global_fields(path)
    for k in (4, 5, 2):  # native system ID, preprocessor version, sender's product ID
        if len(f) > k and f[k]:
            return f[k]
    return '?'


def child_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run(cmd, timeout, env, cpu=None):
    """(result, stdout, stderr, wall seconds); cpu (a list) gets the child's CPU seconds appended."""
    t0, c0 = time.monotonic(), child_cpu()
    try:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=timeout, env=env)
    except subprocess.TimeoutExpired:
        if cpu is not None:
            cpu.append(child_cpu() - c0)
        return 'timeout', '', '', time.monotonic() - t0
    dt = time.monotonic() - t0
    if cpu is not None:
        cpu.append(child_cpu() - c0)
    out = p.stdout.decode('utf-8', 'replace')
    err = p.stderr.decode('utf-8', 'replace')
    if p.returncode < 0 or p.returncode >= 128:
        sig = -p.returncode if p.returncode < 0 else p.returncode - 128
        try:
            name = signal.Signals(sig).name
        except ValueError:
            name = str(sig)
        return 'crash (%s)' % name, out, err, dt
    if p.returncode != 0:
        msg = [l for l in err.splitlines() if 'error:' in l]
        m = msg[-1].split('error:', 1)[1].strip() if msg else err.strip().splitlines()[-1:] or ['?']
        return 'refused: %s' % (m if isinstance(m, str) else m[0]), out, err, dt
    return 'ok', out, err, dt


def main():
    ap = argparse.ArgumentParser(description='prw bake / info over a directory of IGES files')
    ap.add_argument('dir')
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument('--prw', default=os.path.join(here, '..', 'build', 'app', 'prw'))
    ap.add_argument('--timeout', type=float, default=120)
    ap.add_argument('--tsv')
    ap.add_argument('--compare')
    ap.add_argument('--render')
    a = ap.parse_args()
    if a.render:
        sys.path.insert(0, here)
        import png_stats
        os.makedirs(a.render, exist_ok=True)
    renders = {'image': 0, 'not an image': 0, 'refused': 0, 'crash': 0, 'timeout': 0}
    files = sorted(f for f in os.listdir(a.dir) if f.lower().endswith(('.igs', '.iges')))
    if not files:
        sys.exit('corpus_iges: no .igs / .iges files in %s' % a.dir)
    rows = []
    bad = 0
    with tempfile.TemporaryDirectory(prefix='prw_corpus_') as tmp:
        env = dict(os.environ, PRW_CACHE_DIR=os.path.join(tmp, 'cache'))
        print('%-40s %-34s %5s  %-9s %7s %7s  %s' % ('file', 'exporter', 'surf', 'info', 'bake s', 'cpu s', 'bake result'))
        for name in files:
            path = os.path.abspath(os.path.join(a.dir, name))
            man = os.path.join(tmp, 'm.json')
            with open(man, 'w') as f:
                json.dump({'prw_manifest': 1, 'nurbs': [{'file': path}]}, f)
            icpu = []
            info, iout, ierr, _ = run([a.prw, 'info', man], a.timeout, env, icpu)
            cpu = []
            bake, bout, berr, dt = run([a.prw, 'bake', path, '--no-cache'], a.timeout, env, cpu)
            m = re.search(r'read .*: (\d+) surfaces', berr)
            surf = m.group(1) if m else '-'
            m = re.search(r'(\d+) failed\)', bout)
            if bake == 'ok' and m and int(m.group(1)) > 0:
                bake = 'ok* (%s failed patches)' % m.group(1)
            if info.startswith(('crash', 'timeout')) or bake.startswith(('crash', 'timeout')):
                bad += 1
            exp = exporter(path)
            rows.append((name, exp, surf, info.split(':')[0], '%.1f' % dt, bake, '%.1f' % cpu[0], '%.1f' % icpu[0]))
            print('%-40s %-34.34s %5s  %-9s %7.1f %7.1f  %s' % (name[:40], exp, surf, info.split(':')[0], dt, cpu[0],
                                                             bake[:160]), flush=True)
            if a.render:
                out = os.path.join(a.render, name + '.exr')
                png = os.path.join(a.render, name + '.png')
                rcpu = []
                rres, _, _, rdt = run([a.prw, 'render', path, '--size', '160x120', '--out', out, '--png', png],
                                      a.timeout, env, rcpu)
                if rres == 'ok':
                    try:
                        st = png_stats.stats(png)
                        verdict = st['verdict']
                    except (OSError, ValueError) as err:
                        verdict, st = 'unreadable (%s)' % err, None
                    key = 'image' if verdict == 'image' else 'not an image'
                    renders[key] += 1
                    if key != 'image':
                        bad += 1
                    print('    render %.1f s (cpu %.1f s): %s  (%s)' % (rdt, rcpu[0], png_stats.describe(st) if st else
                                                                    verdict, png), flush=True)
                else:
                    key = 'refused' if rres.startswith('refused') else rres.split(' ')[0]
                    renders[key] += 1
                    if key in ('crash', 'timeout'):
                        bad += 1
                    print('    render %.1f s (cpu %.1f s): %s' % (rdt, rcpu[0], rres[:200]), flush=True)
    loads = sum(r[3] == 'ok' for r in rows)
    ready = sum(r[5] == 'ok' for r in rows)
    crash = sum(r[3].startswith('crash') or r[5].startswith('crash') for r in rows)
    hang = sum(r[3] == 'timeout' or r[5] == 'timeout' for r in rows)
    exps = sorted(set(r[1] for r in rows))
    slow = ['%s (%s)' % (r[0], ', '.join(['info %s s CPU' % r[7]] * (r[3] == 'timeout') + ['bake %s s CPU' % r[6]] *
                                          (r[5] == 'timeout')))
            for r in rows if r[3] == 'timeout' or r[5] == 'timeout']
    print('\n%d files, %d load (prw info), %d render-ready (bake ok, no failed patch), %d refused by info, '
          '%d crashes, %d timeouts; %d exporters' % (len(rows), loads, ready, len(rows) - loads - crash - hang,
                                                    crash, hang, len(exps)))
    if slow:
        print('timed out (wall clock, %g s; the CPU seconds the run had used tell a slow file from a loaded '
              'machine): %s' % (a.timeout, ', '.join(slow)))
    if a.render:
        print('renders (prw render FILE): %s' % ', '.join('%s %d' % kv for kv in renders.items()))
    if a.tsv:
        with open(a.tsv, 'w') as f:
            f.write('file\texporter\tsurfaces\tinfo\tbake_s\tbake\tbake_cpu_s\tinfo_cpu_s\n')
            for r in rows:
                f.write('\t'.join(r) + '\n')
    if a.compare:
        base = {}
        with open(a.compare) as f:
            next(f)
            for l in f:
                c = l.rstrip('\n').split('\t')
                if len(c) >= 6:
                    base[c[0]] = c
        lost = [r[0] for r in rows if r[0] in base and base[r[0]][3] == 'ok' and r[3] != 'ok']
        lost_bake = [r[0] for r in rows if r[0] in base and base[r[0]][5].startswith('ok') and not r[5].startswith('ok')]
        gained = [r[0] for r in rows if r[0] in base and base[r[0]][3] != 'ok' and r[3] == 'ok']
        print('compared with %s: %d load there and not here %s; %d bake there and not here %s; %d newly load' %
              (a.compare, len(lost), lost, len(lost_bake), lost_bake, len(gained)))
        if lost or lost_bake:
            bad += 1
    sys.exit(1 if bad else 0)


if __name__ == '__main__':
    main()
