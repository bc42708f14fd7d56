#!/usr/bin/env python3
"""The 20-s sweep of `bdlightcuts` settings (bench/RESULTS.md, "Many-light images that converge",
"The 20-s sweep at eye_length 1").

Renders `path` and `--integrator manylight` with each setting of SWEEP under --time-limit on the
five shared interiors (2 threads, the given seeds), compares each image with a converged
reference of the same size, and prints one markdown row per setting: per scene, the relMSE
ratio to `path` of the same seed (seeds separated by /) and, in brackets, the largest error of a
channel's mean.

  python3 bench/bdlightcuts_sweep.py --refs REFDIR [--bin build/manylight] [--seeds 1,2]
      [--limit 20] [--only default,max_cut=100]

REFDIR holds SCENE.exr, our `path` at 2048 spp (the classroom 2786), seed 4242, at the sizes of
SCENES. Renders are kept in --out and reused when present.
"""
import argparse
import json
import os
import subprocess

SCENES = {'classroom': '320x180', 'veach-ajar': '256x256', 'kitchen': '320x180',
          'coffee': '320x180', 'staircase': '180x320'}
# label: the --set arguments ('path' is the integrator itself).
SWEEP = {
    'default': [],
    'refine=estimates': ['bdlightcuts.refine=estimates'],
    'max_cut=600': ['bdlightcuts.max_cut=600'],
    'max_cut=150': ['bdlightcuts.max_cut=150'],
    'max_cut=100': ['bdlightcuts.max_cut=100'],
    'max_cut=60': ['bdlightcuts.max_cut=60'],
    'samples=8': ['bdlightcuts.samples=8'],
    'samples=32': ['bdlightcuts.samples=32'],
    'samples=32 max_cut=150': ['bdlightcuts.samples=32', 'bdlightcuts.max_cut=150'],
    'rest_paths=2': ['bdlightcuts.rest_paths=2'],
    'rest_paths=1': ['bdlightcuts.rest_paths=1'],
    'c_clamp=0.003': ['bdlightcuts.c_clamp=0.003'],
    'c_clamp=0.03': ['bdlightcuts.c_clamp=0.03'],
    'vpl.count=300000': ['vpl.count=300000'],
    'vpl.focus=0.5': ['vpl.focus=0.5'],
    'vpl.focus=0.9': ['vpl.focus=0.9'],
}


def measure(a, scene, label, seed):
    tag = os.path.join(a.out, f'{scene}-{label.replace(" ", "_")}-{a.limit}-{seed}')
    if not os.path.exists(tag + '.json'):
        integ = 'path' if label == 'path' else 'manylight'
        cmd = [a.bin, 'render', f'{a.shared}/scenes/{scene}/scene-v4.pbrt', '--integrator', integ,
               '--resolution', SCENES[scene], '--time-limit', str(a.limit), '--seed', str(seed),
               '--threads', '2', '-q', '-o', tag + '.exr', '--stats', tag + '.json']
        for s in SWEEP.get(label, []):
            cmd += ['--set', s]
        subprocess.run(cmd, check=True)
    d = json.loads(subprocess.run([a.bin, 'diff', '--json', tag + '.exr',
                                   os.path.join(a.refs, scene + '.exr')], check=True,
                                  capture_output=True, text=True).stdout)
    return d['relmse'], max(abs(100 * m) for m in d['mean_rel_diff'])


def main():
    p = argparse.ArgumentParser()
    p.add_argument('--refs', required=True)
    p.add_argument('--bin', default='build/manylight')
    p.add_argument('--seeds', default='1,2')
    p.add_argument('--limit', type=int, default=20)
    p.add_argument('--only', help='comma-separated labels of SWEEP')
    p.add_argument('--shared', default='../shared')
    p.add_argument('--out', default='bench-out/bdlightcuts-sweep')
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    seeds = [int(s) for s in a.seeds.split(',')]
    labels = a.only.split(',') if a.only else list(SWEEP)
    path = {(sc, s): measure(a, sc, 'path', s)[0] for sc in SCENES for s in seeds}
    print('| setting | ' + ' | '.join(SCENES) + ' | worst ratio |')
    print('|---' * (len(SCENES) + 2) + '|')
    for label in labels:
        cells, worst = [], 0.0
        for sc in SCENES:
            got = [measure(a, sc, label, s) for s in seeds]
            ratios = [r / path[(sc, s)] for (r, _), s in zip(got, seeds)]
            worst = max([worst] + ratios)
            cells.append(' / '.join(f'{r:.2f}' for r in ratios) + ' (' +
                         ' / '.join(f'{m:.1f}%' for _, m in got) + ')')
        print(f'| {label} | ' + ' | '.join(cells) + f' | {worst:.2f} |')


if __name__ == '__main__':
    main()
