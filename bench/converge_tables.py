#!/usr/bin/env python3
"""The many-light bias tables and the bdlightcuts defaults sweep (bench/RESULTS.md, "Many-light
images that converge").

Renders each many-light integrator and `path` with the defaults under --time-limit on the five
shared interiors, compares each image with a converged reference of the same size, and prints
markdown tables: relMSE, channel means, worst 16x16 block, ratio to path's relMSE.

  python3 bench/converge_tables.py --refs REFDIR [--bin build/manylight] [--limits 10,20,60]
      [--before OLD_BINARY] [--sweep]

REFDIR holds SCENE-WxH.exr, e.g. made by
  build/manylight render ../shared/scenes/SCENE/scene-v4.pbrt --integrator path \\
      --resolution WxH --spp 2048 --seed 4242 -o REFDIR/SCENE-WxH.exr
Renders are kept in --out (default bench-out/converge) and reused when present.
"""
import argparse, json, os, subprocess

SCENES = {'classroom': '320x180', 'veach-ajar': '256x256', 'kitchen': '320x180',
          'coffee': '320x180', 'staircase': '180x320'}
MANY = ['bdlightcuts', 'mdlightcuts', 'lightcuts', 'stochasticlightcuts']
SWEEP = [('bdlightcuts', 'bdlightcuts.c_clamp=0.003'), ('bdlightcuts', 'bdlightcuts.c_clamp=0.03'),
         ('bdlightcuts', 'vpl.count=30000'), ('stochasticlightcuts', 'stochasticlightcuts.cut=64')]


def render(a, binary, scene, integ, limit, tag, sets=()):
    out = os.path.join(a.out, tag)
    if not os.path.exists(out + '.json'):
        cmd = [binary, 'render', f'{a.shared}/scenes/{scene}/scene-v4.pbrt', '--integrator', integ,
               '--resolution', SCENES[scene], '--time-limit', str(limit), '--seed', '1',
               '--threads', '2', '-q', '-o', out + '.exr', '--stats', out + '.json']
        for s in sets:
            cmd += ['--set', s]
        subprocess.run(cmd, check=True)
    d = json.loads(subprocess.run([a.bin, 'diff', '--json', '--block', '16', out + '.exr',
                                   f'{a.refs}/{scene}-{SCENES[scene]}.exr'], check=True,
                                  capture_output=True, text=True).stdout)
    st = json.load(open(out + '.json'))
    w, h = map(int, SCENES[scene].split('x'))
    d['spp'] = st['rays']['camera'] / (w * h)
    return d


def cells(d):
    m = [100 * x for x in d['mean_rel_diff']]
    return (f"{d['relmse']:.3f} | {m[0]:+.1f} / {m[1]:+.1f} / {m[2]:+.1f} | "
            f"{100 * d.get('worst_block_rel_diff', 0):.0f}%")


def main():
    p = argparse.ArgumentParser()
    p.add_argument('--refs', required=True)
    p.add_argument('--bin', default='build/manylight')
    p.add_argument('--before', help='an older manylight binary, rendered at 20 s')
    p.add_argument('--limits', default='10,20,60')
    p.add_argument('--sweep', action='store_true', help='the bdlightcuts sweep at 60 s')
    p.add_argument('--shared', default='../shared')
    p.add_argument('--out', default='bench-out/converge')
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    path = {}
    for t in [int(x) for x in a.limits.split(',')]:
        print(f'\n**{t} s**\n')
        print('| scene | integrator | spp | relMSE | means r/g/b % | worst 16x16 | relMSE / path\'s |')
        print('|---|---|---|---|---|---|---|')
        for sc in SCENES:
            path[sc, t] = render(a, a.bin, sc, 'path', t, f'{sc}-path-{t}')
            for integ in ['path'] + MANY:
                d = path[sc, t] if integ == 'path' else render(a, a.bin, sc, integ, t,
                                                                f'{sc}-{integ}-{t}')
                print(f"| {sc} | {integ} | {d['spp']:.1f} | {cells(d)} | "
                      f"{d['relmse'] / path[sc, t]['relmse']:.2f} |")
    if a.before:
        print('\n| scene | integrator | before: relMSE | means r/g/b % | worst 16x16 |')
        print('|---|---|---|---|---|')
        for sc in SCENES:
            for integ in MANY:
                d = render(a, a.before, sc, integ, 20, f'{sc}-{integ}-before-20')
                print(f'| {sc} | {integ} | {cells(d)} |')
    if a.sweep:
        print('\n| setting | ' + ' | '.join(SCENES) + ' | worst ratio | eligible |')
        print('|---' * (len(SCENES) + 3) + '|')
        for integ, s in SWEEP:
            row, worst, ok = [], 0, True
            for sc in SCENES:
                ref = path.get((sc, 60)) or render(a, a.bin, sc, 'path', 60, f'{sc}-path-60')
                d = render(a, a.bin, sc, integ, 60, f'{sc}-{integ}-{s}-60', [s])
                m = max(abs(x) for x in d['mean_rel_diff'])
                r = d['relmse'] / ref['relmse']
                worst, ok = max(worst, r), ok and m < 0.01
                row.append(f'{r:.2f} ({100 * m:.1f}%)')
            print(f"| {integ} {s} | " + ' | '.join(row) +
                  f" | {worst:.2f} | {'yes' if ok else 'no'} |")


if __name__ == '__main__':
    main()
