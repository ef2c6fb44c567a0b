#!/usr/bin/python3
"""Draws an `evaluate_local_map --plot FILE` dump: the place's lines, the EKF trajectory, the
reference trajectory and odometry alone, in the place frame.

    scripts/plot_local_map.py DUMP OUT.png [--title TEXT]
"""
import argparse

import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('dump')
    parser.add_argument('out')
    parser.add_argument('--title', default='')
    args = parser.parse_args()
    ekf, ref, odo, lines = [], [], [], []
    with open(args.dump) as f:
        for row in f:
            w = row.split()
            if w and w[0] == 'pose':
                v = list(map(float, w[1:]))
                ekf.append(v[0:2])
                ref.append(v[2:4])
                odo.append(v[4:6])
            elif w and w[0] == 'line':
                lines.append(list(map(float, w[1:])))
    fig, ax = plt.subplots(figsize=(8, 8))
    for sx, sy, ex, ey in lines:
        ax.plot([sx, ex], [sy, ey], c='tab:blue', lw=2)
    for points, label, style in ((ref, 'reference (SLAM-corrected log)', 'k-'), (ekf, 'EKF', 'g-'),
                                 (odo, 'odometry alone', 'r--')):
        if points:
            xs, ys = zip(*points)
            ax.plot(xs, ys, style, lw=1.5, label=label)
    ax.set_aspect('equal')
    ax.grid(alpha=0.3)
    ax.legend(loc='best')
    ax.set_title(args.title or 'one place: %d lines' % len(lines))
    fig.tight_layout()
    fig.savefig(args.out, dpi=80)


if __name__ == '__main__':
    main()
