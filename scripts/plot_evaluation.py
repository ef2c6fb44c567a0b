#!/usr/bin/python3
"""The report of scripts/evaluate: the hybrid map drawn over the ground-truth world, the belief
entropy over time with U_max, the missions' goal errors (PNGs), a Markdown report with the paper's
Table 1, and the figures as one JSON line on stdout (the last line).

    scripts/plot_evaluation.py --world WORLD_YAML --out DIR --missions MISSIONS_JSON
        [--evaluation EVALUATION_JSON] [--summary SUMMARY_JSON] [--wall-s S]
"""
import argparse
import json
import math
import os

import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
import yaml  # noqa: E402
from world_geometry import compose  # noqa: E402


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError, TypeError):
        return None


def draw_world(ax, world):
    for wall in world.get('walls', []):
        pts = wall['points']
        ax.plot([p[0] for p in pts], [p[1] for p in pts], color='0.55', lw=2.5, zorder=1)
    for b in world.get('boxes', []):
        c, s = math.cos(b.get('yaw', 0.0)), math.sin(b.get('yaw', 0.0))
        hx, hy = b['size'][0] / 2, b['size'][1] / 2
        corners = [(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy), (-hx, -hy)]
        xs = [b['center'][0] + c * x - s * y for x, y in corners]
        ys = [b['center'][1] + s * x + c * y for x, y in corners]
        ax.fill(xs, ys, color='0.85', zorder=0)
    for cy in world.get('cylinders', []):
        ax.add_patch(plt.Circle(cy['center'], cy['radius'], color='0.85', zorder=0))
    for r in world.get('regions', []):
        if r['kind'] == 'room':
            xs = [p[0] for p in r['polygon']]
            ys = [p[1] for p in r['polygon']]
            ax.text(sum(xs) / len(xs), sum(ys) / len(ys), r['name'], fontsize=6, color='0.5', ha='center', zorder=2)


def plot_map(path, world, dump, missions):
    fig, ax = plt.subplots(figsize=(10, 8))
    draw_world(ax, world)
    frames = {int(k): v for k, v in dump.get('place_frames', {}).items()}
    for pid, lines in dump.get('place_lines', {}).items():
        f = frames.get(int(pid))
        if f is None:
            continue
        for x1, y1, x2, y2 in lines:
            a, b = compose(f, (x1, y1)), compose(f, (x2, y2))
            ax.plot([a[0], b[0]], [a[1], b[1]], color='tab:blue', lw=1.2, zorder=3)
    # The graph at its display poses (map frame = the world's start pose; odometric, for display).
    start = world['robot']['start']
    frame = (start[0], start[1], start[2] if len(start) > 2 else 0.0)
    pos = {n['id']: compose(frame, (n['x'], n['y'])) for n in dump.get('nodes', [])}
    for s, t in dump.get('edges', []):
        if s in pos and t in pos:
            ax.plot([pos[s][0], pos[t][0]], [pos[s][1], pos[t][1]], color='tab:orange', lw=1, zorder=4)
    colours = {0: 'tab:green', 1: 'tab:red', 2: 'black', 3: 'tab:purple', 4: 'tab:orange'}
    for n in dump.get('nodes', []):
        p = pos[n['id']]
        ax.plot(p[0], p[1], 'o', color=colours.get(n['type'], 'k'), ms=5, zorder=5)
    for r in (missions or {}).get('rows', []):
        g = r['goal_world']
        ax.plot(g[0], g[1], 'x' if not r['success'] else '*', color='tab:red' if not r['success'] else 'tab:green',
                ms=8, zorder=6)
    ax.set_aspect('equal')
    ax.set_title('hybrid map over the ground truth (grey): room lines (blue; EKF, placed by each place\'s ground-truth frame)\n'
                 'graph (orange; nodes: green door, red junction, black end, orange start; odometric display poses)\n'
                 'mission goals (green * reached, red x not)', fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_entropy(path, dump):
    e = dump.get('entropy', [])
    fig, ax = plt.subplots(figsize=(10, 3.5))
    if e:
        t0 = e[0][0]
        ax.plot([r[0] - t0 for r in e], [r[1] for r in e], lw=0.7, label='entropy U (nats)')
        ax.plot([r[0] - t0 for r in e], [r[2] for r in e], 'r--', lw=1, label='U_max')
        if dump.get('missions_start_s'):
            ax.axvline(dump['missions_start_s'] - t0, color='k', lw=1, label='missions start')
    ax.set_xlabel('sim time (s)')
    ax.set_ylabel('nats')
    ax.legend(fontsize=8)
    ax.set_title('topological belief entropy (eq. 3) over the run')
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_errors(path, missions):
    rows = (missions or {}).get('rows', [])
    fig, ax = plt.subplots(figsize=(8, 3.5))
    xs = list(range(1, len(rows) + 1))
    ax.bar(xs, [100 * (r['goal_error_m'] or 0.0) if r['success'] else 0.0 for r in rows],
           color=['tab:green' if r['success'] else 'tab:red' for r in rows])
    for x, r in zip(xs, rows):
        if not r['success']:
            ax.text(x, 0.1, 'failed', rotation=90, fontsize=7, ha='center', va='bottom')
    ax.set_xlabel('mission')
    ax.set_ylabel('goal error (cm, ground truth)')
    ax.set_title('goal error of each mission')
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--world', required=True)
    ap.add_argument('--out', required=True)
    ap.add_argument('--missions', required=True)
    ap.add_argument('--evaluation')
    ap.add_argument('--summary')
    ap.add_argument('--wall-s', type=float, default=None)
    args = ap.parse_args()
    with open(args.world) as f:
        world = yaml.safe_load(f)
    missions = load(args.missions)
    dump = load(args.missions + '.map.json') or {}
    evaluation = load(args.evaluation) or {}
    summary = load(args.summary) or {}
    os.makedirs(args.out, exist_ok=True)
    plot_map(os.path.join(args.out, 'map.png'), world, dump, missions)
    plot_entropy(os.path.join(args.out, 'entropy.png'), dump)
    plot_errors(os.path.join(args.out, 'goal_errors.png'), missions)
    m = missions or {}
    figures = {
        'world': world.get('name', os.path.basename(args.world)),
        'exploration_complete': summary.get('complete'),
        'rooms_total': evaluation.get('rooms'), 'rooms_mapped': evaluation.get('rooms_mapped'),
        'rooms_mapped_twice': len(evaluation.get('rooms_mapped_twice', {}) or {}),
        'exploration_travel_m': summary.get('travel_m'), 'exploration_sim_s': summary.get('sim_time_s'),
        'map_bytes': evaluation.get('map_bytes'),
        'missions': m.get('missions', 0), 'success_rate': m.get('success_rate'),
        'mean_goal_error_m': m.get('mean_goal_error_m'), 'max_goal_error_m': m.get('max_goal_error_m'),
        'unconfident_rate': m.get('unconfident_rate'), 'state_estimates': m.get('state_estimates'),
        'travel_m': m.get('travel_m'), 'missions_sim_s': m.get('sim_s'),
        'sim_s': (summary.get('sim_time_s') or 0.0) + (m.get('sim_s') or 0.0),
        'wall_s': args.wall_s,
    }

    def f(v, fmt):
        return fmt % v if isinstance(v, (int, float)) else 'n/a'

    lines = [
        '# Evaluation: %s' % figures['world'], '',
        '## Exploration', '',
        '| complete | rooms mapped | rooms mapped twice | travel | sim time | map size |', '|---|---|---|---|---|---|',
        '| %s | %s of %s | %s | %s m | %s s | %s bytes |' % (
            figures['exploration_complete'], figures['rooms_mapped'], figures['rooms_total'],
            figures['rooms_mapped_twice'], f(figures['exploration_travel_m'], '%.0f'),
            f(figures['exploration_sim_s'], '%.0f'), figures['map_bytes']), '',
        '## Missions (Table 1 of Tomatis et al. 2001)', '',
        '| missions | success rate | state estimates | unconfident states | total travel | mean goal error | max goal error | sim time | wall time |',
        '|---|---|---|---|---|---|---|---|---|',
        '| %s | %s %% | %s | %s %% | %s m | %s cm | %s cm | %s s | %s s |' % (
            figures['missions'], f(100 * (figures['success_rate'] or 0), '%.1f'), figures['state_estimates'],
            f(100 * (figures['unconfident_rate'] or 0), '%.1f'), f(figures['travel_m'], '%.0f'),
            f((figures['mean_goal_error_m'] or 0) * 100 if figures['mean_goal_error_m'] is not None else None, '%.2f'),
            f((figures['max_goal_error_m'] or 0) * 100 if figures['max_goal_error_m'] is not None else None, '%.2f'),
            f(figures['missions_sim_s'], '%.0f'), f(figures['wall_s'], '%.0f')), '',
        '(wall time: the whole evaluation, exploration included)', '',
        'The paper: 15 missions, 87 % success, mean goal error under 1 cm, 7 % unconfident states, 0.4 km.', '',
        '| # | room | success | goal error (cm) | heading error (rad) | path (m) | sim (s) | message |',
        '|---|---|---|---|---|---|---|---|',
    ]
    for i, r in enumerate(m.get('rows', []), 1):
        lines.append('| %d | %s | %s | %s | %s | %.1f | %.0f | %s |' % (
            i, r['room'], r['success'], f(100 * r['goal_error_m'] if r['goal_error_m'] is not None else None, '%.2f'),
            f(r['heading_error_rad'], '%.3f'), r['path_m'], r['sim_s'], r['message'].replace('|', '/')))
    lines += ['', '![hybrid map](map.png)', '', '![entropy](entropy.png)', '', '![goal errors](goal_errors.png)', '']
    with open(os.path.join(args.out, 'report.md'), 'w') as fo:
        fo.write('\n'.join(lines))
    print(json.dumps(figures))


if __name__ == '__main__':
    main()
