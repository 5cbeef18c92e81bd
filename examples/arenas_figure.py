"""Arenas from YAML and from an image, drawn side by side.

    python examples/arenas_figure.py [--out out/examples]

Writes ``arenas.png``: the built-in arenas (each a YAML file of the package, loaded with
:func:`arenas.load`), an arena written as YAML text (the README's example, through
:func:`arenas.from_dict`), and one drawn as a picture (black = obstacle, through
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

#: The README's arena file.
MY_ARENA = """\
boundary: [[0, 0], [140, 0], [140, 140], [0, 140]]
obstacles:
  - [[40, 50], [46, 50], [46, 96], [94, 96], [94, 76], [100, 76], [100, 102], [40, 102]]
source: [70.21, 70.21]
strength: 850
start: [128, 12, 135]
"""


def floor_plan(path: Path) -> Path:
    """A 100 x 80 cm floor plan at 0.5 cm per pixel: a cross, a wall on the left, a wedge."""
    img = np.full((160, 200), 255, np.uint8)
    cv2.rectangle(img, (90, 30), (109, 129), 0, -1)
    cv2.rectangle(img, (60, 70), (139, 89), 0, -1)
    cv2.rectangle(img, (0, 40), (39, 47), 0, -1)
    cv2.fillPoly(img, [np.array([[160, 150], [190, 150], [175, 110]])], 0)
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
    panels.append(("my_arena.yaml (README)", arenas.from_dict(parse_yaml(MY_ARENA, "my_arena"), where="my_arena")))
    panels.append(("floor_plan.png (image)",
                   arenas.from_image(floor_plan(out / "floor_plan.png"), cm_per_px=0.5,
                                     source=(25.0, 60.0), start=(60.0, 8.0, 0.0))))
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
