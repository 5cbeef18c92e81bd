"""Arenas from YAML and from an image, drawn side by side.

    python examples/arenas_figure.py [--out out/examples]

Writes ``arenas.png``: the built-in arenas (each a YAML file of the package, loaded with
:func:`arenas.load`), an arena written as YAML text (through :func:`arenas.from_dict`), and one drawn as a picture (black = obstacle, through
:func:`arenas.from_image`), each with its source (star) and start (arrow).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import cv2
import numpy as np
from matplotlib.figure import Figure

import arenas
from arenas.files import parse_yaml
from reciprocity.viz.figures import draw_arena

#: An arena file as text: a 120 x 90 cm room, a wall from the floor, a pillar, a wedge.
ROOM_YAML = """\
boundary: [[0, 0], [120, 0], [120, 90], [0, 90]]
obstacles:
  - [[40, 0], [45, 0], [45, 55], [40, 55]]
  - [[75, 40], [90, 40], [90, 55], [75, 55]]
  - [[95, 80], [110, 80], [102, 65]]
source: [60, 75]
strength: 600
start: [10, 10, 45]
"""


def floor_plan(path: Path) -> Path:
    """A 100 x 100 cm floor plan at 0.5 cm per pixel: a round pillar and an L-shaped wall."""
    img = np.full((200, 200), 255, np.uint8)
    cv2.circle(img, (60, 60), 18, 0, -1)
    cv2.polylines(img, [np.array([[110, 40], [110, 150], [170, 150]])], False, 0, thickness=8)
    cv2.imwrite(str(path), img)
    return path


def main(argv=None) -> list[str]:
    """Write ``arenas.png`` (and the floor plan it reads); return the panel titles."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/examples", help="output folder (created)")
    a = ap.parse_args(argv)
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    panels = [(f"{name} (built-in YAML)", arenas.load(name)) for name in arenas.builtin_names()]
    panels.append(("room.yaml (YAML text)", arenas.from_dict(parse_yaml(ROOM_YAML, "room.yaml"), where="room.yaml")))
    panels.append(("floor_plan.png (image)",
                   arenas.from_image(floor_plan(out / "floor_plan.png"), cm_per_px=0.5,
                                     source=(80.0, 40.0), start=(10.0, 10.0, 0.0))))
    cols = 4
    rows = -(-len(panels) // cols)
    fig = Figure(figsize=(3 * cols, 3 * rows), layout="constrained")
    for k, (title, arena) in enumerate(panels):
        ax = fig.add_subplot(rows, cols, k + 1)
        draw_arena(ax, arena)
        if arena.source is not None:
            ax.plot(*arena.source, "*", color="red", ms=10)
        if arena.start is not None:
            x, y, th = arena.start
            ax.annotate("", (x + 8 * np.cos(th), y + 8 * np.sin(th)), (x, y),
                        arrowprops=dict(arrowstyle="->", color="tab:blue", lw=1.5))
        ax.set_title(title, fontsize=9)
        ax.set_aspect("equal")
        ax.set_xticks([])
        ax.set_yticks([])
    fig.savefig(out / "arenas.png", dpi=100)
    print(f"{len(panels)} arenas -> {out / 'arenas.png'}")
    return [t for t, _ in panels]


if __name__ == "__main__":
    main()
