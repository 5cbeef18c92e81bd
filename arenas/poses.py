"""Poses as files and command lines write them, and as the code uses them.

A heading is written in **degrees** wherever a person writes it (arena files, scenario files,
campaign specs, ``--start x,y,deg``) and is in **radians** everywhere in the Python API.
Every reader converts with :func:`pose_from_degrees` and every writer with
:func:`pose_to_degrees`: this is the one place where degrees become radians.
"""

from __future__ import annotations

import numpy as np

__all__ = ["pose_from_degrees", "pose_to_degrees"]


def pose_from_degrees(pose) -> np.ndarray:
    """``[x, y]`` or ``[x, y, heading_deg]`` (or an (n, 2|3) array of them) as floats with the
    heading in radians; positions (cm) and poses without a heading pass unchanged.

    Parameters
    ----------
    pose : array_like, shape (2,), (3,), (n, 2) or (n, 3)
        Position in cm, heading in degrees.

    Returns
    -------
    ndarray
        A new float array of the same shape, heading in radians.

    Examples
    --------
    >>> pose_from_degrees([10, 20, 90]).round(4).tolist()
    [10.0, 20.0, 1.5708]
    """
    out = np.array(pose, dtype=float)
    if out.shape[-1] == 3:
        out[..., 2] = np.radians(out[..., 2])
    return out


def pose_to_degrees(pose) -> list:
    """The inverse of :func:`pose_from_degrees`, as plain floats (for writing files).

    Examples
    --------
    >>> pose_to_degrees([10.0, 20.0, np.pi])
    [10.0, 20.0, 180.0]
    """
    out = np.array(pose, dtype=float)
    if out.shape[-1] == 3:
        out[..., 2] = np.degrees(out[..., 2])
    return out.tolist()
