#!/usr/bin/python3
"""Draws scans with their features from an `evaluate_features --plot FILE` dump into one PNG.

    scripts/plot_features.py DUMP OUT.png [--title TEXT]

Points grey, lines blue, corners as arrows (green concave, red convex), openings orange (doors)
or yellow (junctions) or grey dashed (unknown), the place type in each panel's title.
"""
import argparse
import math

import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402

PLACE = {0: 'unknown', 1: 'room', 2: 'hallway'}
OPENING_STYLE = {0: ('0.5', '--'), 1: ('darkorange', '-'), 2: ('gold', '-')}


def read(path):
    scans = []
    with open(path) as f:
        for line in f:
            w = line.split()
            if not w:
                continue
            if w[0] == 'scan':
                scans.append({'index': int(w[1]), 'points': [], 'lines': [], 'corners': [], 'openings': [],
                              'place': (0, 0.0)})
            elif w[0] == 'points':
                v = list(map(float, w[1:]))
                scans[-1]['points'] = list(zip(v[0::2], v[1::2]))
            elif w[0] == 'line':
                scans[-1]['lines'].append(tuple(map(float, w[1:5])))
            elif w[0] == 'corner':
                scans[-1]['corners'].append((float(w[1]), float(w[2]), float(w[3]), w[4] == '1'))
            elif w[0] == 'opening':
                scans[-1]['openings'].append((*map(float, w[1:5]), int(w[5])))
            elif w[0] == 'place':
                scans[-1]['place'] = (int(w[1]), float(w[2]))
    return scans


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('dump')
    parser.add_argument('out')
    parser.add_argument('--title', default='')
    args = parser.parse_args()
    scans = read(args.dump)
    if not scans:
        raise SystemExit('%s: no scans' % args.dump)
    cols = min(3, len(scans))
    rows = (len(scans) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(5.5 * cols, 5.5 * rows), squeeze=False)
    for ax in axes.flat:
        ax.set_visible(False)
    for ax, s in zip(axes.flat, scans):
        ax.set_visible(True)
        if s['points']:
            xs, ys = zip(*s['points'])
            ax.scatter(xs, ys, s=2, c='0.55', zorder=1)
        for sx, sy, ex, ey in s['lines']:
            ax.plot([sx, ex], [sy, ey], c='tab:blue', lw=2.2, zorder=2)
        for x, y, th, convex in s['corners']:
            ax.arrow(x, y, 0.35 * math.cos(th), 0.35 * math.sin(th), width=0.03, color='red' if convex else 'green',
                     zorder=3)
        for lx, ly, rx, ry, kind in s['openings']:
            color, style = OPENING_STYLE.get(kind, OPENING_STYLE[0])
            ax.plot([lx, rx], [ly, ry], c=color, ls=style, lw=3, zorder=3)
        ax.plot([0], [0], marker=(3, 0, -90), ms=12, c='k', zorder=4)
        kind, conf = s['place']
        ax.set_title('scan %d: %d lines, %d corners, %d openings, %s %.0f%%' % (
            s['index'], len(s['lines']), len(s['corners']), len(s['openings']), PLACE.get(kind, '?'), 100 * conf),
            fontsize=9)
        ax.set_aspect('equal')
        ax.grid(alpha=0.3)
    if args.title:
        fig.suptitle(args.title)
    fig.tight_layout()
    fig.savefig(args.out, dpi=80)


if __name__ == '__main__':
    main()
