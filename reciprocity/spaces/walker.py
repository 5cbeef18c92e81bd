"""Where a walker may go next: its moves, in a fixed order (public, like the lattice's
controls): what strategies choose among and what the Gymnasium face's actions index."""

from __future__ import annotations

import numpy as np

__all__ = ["all_moves", "candidate_moves", "turn_inward", "n_moves"]


def n_moves(nominal: dict) -> int:
    """How many moves :func:`all_moves` lists for a walker of this nominal description."""
    if nominal["motion"] == "turn":
        return int(nominal["n_turns"])
    return 8 if nominal["motion"] == "reach" or nominal.get("moves", 4) == 8 else 4


def all_moves(nominal: dict, position, heading: float):
    """Every move of a walker from `position` with `heading` (rad), in the order moves are
    tried, whether or not it stays in the area.

    Parameters
    ----------
    nominal : dict
        The plume world's nominal description (``step``, ``motion``, ``turns``, ``moves``).
    position : array_like, shape (2,)
    heading : float

    Returns
    -------
    points : ndarray, shape (n_moves, 2)
    headings : ndarray, shape (n_moves,)
        Heading (rad) after each move.
    """
    p = np.asarray(position, dtype=float)
    step, motion = float(nominal["step"]), nominal["motion"]
    if motion == "turn":
        hd = heading + np.asarray(nominal["turns"])
        pts = p + step * np.column_stack([np.cos(hd), np.sin(hd)])
    else:
        # otto's action order: -x, +x, -y, +y (then the diagonals)
        dirs = [(-1, 0), (1, 0), (0, -1), (0, 1)]
        if motion == "reach" or nominal.get("moves", 4) == 8:
            dirs += [(-1, -1), (1, -1), (-1, 1), (1, 1)]
        d = np.array(dirs, dtype=float)
        pts = p + step * d
        hd = np.arctan2(d[:, 1], d[:, 0])
    return pts, hd


def candidate_moves(nominal: dict, position, heading: float):
    """Admissible next places and headings from `position`: :func:`all_moves` without the
    places outside the area, in the same order.

    Returns
    -------
    points : ndarray, shape (m, 2)
    headings : ndarray, shape (m,)
        Heading (rad) after each move.
    """
    pts, hd = all_moves(nominal, position, heading)
    (x0, x1), (y0, y1) = nominal["bounds"]
    inside = (pts[:, 0] >= x0) & (pts[:, 0] <= x1) & (pts[:, 1] >= y0) & (pts[:, 1] <= y1)
    return pts[inside], hd[inside]


def turn_inward(nominal: dict, pos: np.ndarray, heading: float) -> float:
    """New heading (rad) of a walker at the edge of the area facing out: one largest turn
    (the last of ``nominal["turns"]``, rad) toward the middle of the area.

    Parameters
    ----------
    nominal : dict
        The plume world's nominal description (``bounds``, ``turns``).
    pos : ndarray, shape (2,)
        Where the walker stands.
    heading : float
        Its heading, rad.

    Returns
    -------
    float
    """
    (x0, x1), (y0, y1) = nominal["bounds"]
    want = np.arctan2((y0 + y1) / 2 - pos[1], (x0 + x1) / 2 - pos[0])
    diff = (want - heading + np.pi) % (2 * np.pi) - np.pi
    return heading + np.sign(diff) * nominal["turns"][-1]
