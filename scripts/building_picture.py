"""Pictures of generated buildings and of explorations over their ground truth (matplotlib, PNG)."""
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
import yaml  # noqa: E402
from plot_evaluation import draw_world  # noqa: E402


def draw_doors(ax, world):
    kinds = {r['name']: r['kind'] for r in world.get('regions', [])}
    for d in world.get('doors', []):
        hall = sorted(kinds.get(b) for b in d['between']) == ['hallway', 'hallway']
        ax.plot(d['center'][0], d['center'][1], '.' if hall else 's', ms=2 if hall else 3,
                color='0.7' if hall else 'tab:brown', zorder=3)


def draw_building_picture(world_file, out):
    with open(world_file) as f:
        world = yaml.safe_load(f)
    fig, ax = plt.subplots(figsize=(10, 8))
    draw_world(ax, world)
    draw_doors(ax, world)
    s = world['robot']['start']
    ax.annotate('', xy=(s[0] + 1.2 * __import__('math').cos(s[2]), s[1] + 1.2 * __import__('math').sin(s[2])),
                xytext=(s[0], s[1]), arrowprops=dict(arrowstyle='->', color='tab:red'))
    ax.set_aspect('equal')
    ax.set_title('%s: walls, furniture (grey), doors (brown), start (red)' % world['name'], fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    plt.close(fig)
