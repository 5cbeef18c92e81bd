"""ROS ``map_server`` maps: an occupancy image (PGM or PNG) and its YAML, read as an arena
and written from one.

A map file is recognised by its keys (:data:`ROS_KEYS`)::

    image: lab.pgm               # beside the YAML (or an absolute path)
    resolution: 0.05             # metres per pixel
    origin: [-1.0, -2.5, 0.0]    # the lower-left pixel's corner in the map frame: x, y (m), yaw (rad)
    negate: 0                    # 1: white is occupied
    occupied_thresh: 0.65        # a cell more likely occupied than this is an obstacle
    free_thresh: 0.196           # a cell less likely occupied than this is free
    mode: trinary                # optional: trinary (default), scale or raw

As ``map_server`` reads it, a pixel of grey ``x`` (0-255) is occupied with probability
``p = (255 - x) / 255`` (``x / 255`` with ``negate: 1``; in ``raw`` mode ``x`` is the
occupancy in percent); ``p > occupied_thresh`` is occupied, ``p < free_thresh`` free, and
anything between unknown. The arena is the largest connected free region: its outline is
the boundary, every occupied or unknown part inside it an obstacle (nobody has seen what
an unknown cell holds, so no observer is sent there). Lengths become cm (1 px =
``resolution`` m = ``100 * resolution`` cm) in the map's own frame, so a pose in the
map frame in metres is the same place times 100 in the arena (a ``yaw`` in ``origin``
turns the image about its lower-left corner, as the ROS spec says; many ROS nodes ignore it). The polygons are traced
along the cells and simplified until the arena's limits hold (at most 1000 obstacles and
20000 obstacle vertices, see :mod:`arenas.io`).

The toolkit's own keys may be added to a map file: ``name``, ``source``, ``strength`` and
``start`` (cm and degrees, as in an arena file), and ``unknown: free`` to take the unknown
cells for free space (then only cells above ``occupied_thresh`` are walls).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .errors import ArenaError
from .frames import pixel_to_world
from .geometry import MAX_COORD_CM, MAX_VERTICES, Arena
from .poses import pose_from_degrees

__all__ = ["ROS_KEYS", "is_ros_map", "from_ros_map", "to_ros_map", "MAX_OBSTACLES"]

#: The keys of a ``map_server`` YAML (``mode`` optional).
ROS_KEYS = ("image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh", "mode")
#: The toolkit's own keys a map file may add.
EXTRA_KEYS = ("name", "description", "source", "strength", "start", "unknown")
#: What an unknown cell (between the thresholds) may be taken for.
UNKNOWN_AS = ("obstacle", "free")
#: Most obstacles of an arena read from a map (the limit of arena files).
MAX_OBSTACLES = 1000
#: The modes of ``map_server``.
MODES = ("trinary", "scale", "raw")
#: Grey levels written: free, occupied, unknown (those of ``map_saver``).
FREE, OCCUPIED, UNKNOWN = 254, 0, 205


def is_ros_map(data) -> bool:
    """Whether the mapping `data` of a YAML file is a ``map_server`` map (it names an
    ``image`` and a ``resolution``, keys no arena or scenario file has)."""
    return isinstance(data, dict) and "image" in data and "resolution" in data


def _checked(data: dict, where: str) -> dict:
    """The map keys of `data`, each checked; ArenaError naming the key, its value and what
    is allowed."""
    from .image import _number        # OpenCV, imported where a map is read or written
    unknown = set(data) - set(ROS_KEYS) - set(EXTRA_KEYS)
    if unknown:
        raise ArenaError(f"{where}: unknown key(s) {sorted(unknown)}; a ROS map has "
                         f"{', '.join(ROS_KEYS)} (mode optional) and may add {', '.join(EXTRA_KEYS)}")
    missing = [k for k in ROS_KEYS[:-1] if k not in data]
    if missing:
        raise ArenaError(f"{where}: ROS map misses key(s) {', '.join(missing)}")
    out = {}
    if not isinstance(data["image"], str) or not data["image"].strip():
        raise ArenaError(f"{where}: 'image' must be the file name of the map's PGM or PNG; got {data['image']!r}")
    out["resolution"] = _number(data["resolution"], f"{where}: 'resolution' (m per pixel)", 0.0, 1e3,
                                open_lo=True)
    origin = data["origin"]
    if not isinstance(origin, list) or len(origin) not in (2, 3):
        raise ArenaError(f"{where}: 'origin' must be [x, y, yaw] (m, m, rad); got {origin!r}")
    x, y = (_number(v, f"{where}: 'origin' x and y (m)", -MAX_COORD_CM / 100, MAX_COORD_CM / 100)
            for v in origin[:2])
    yaw = _number(origin[2], f"{where}: 'origin' yaw (rad)", -2 * math.pi, 2 * math.pi) if len(origin) == 3 else 0.0
    out["origin_cm"], out["yaw"] = (100.0 * x, 100.0 * y), yaw
    negate = data["negate"]
    if negate not in (0, 1) or isinstance(negate, float):
        raise ArenaError(f"{where}: 'negate' must be 0 or 1; got {negate!r}")
    out["negate"] = bool(negate)
    occ = _number(data["occupied_thresh"], f"{where}: 'occupied_thresh'", 0.0, 1.0)
    free = _number(data["free_thresh"], f"{where}: 'free_thresh'", 0.0, 1.0)
    if not free < occ:
        raise ArenaError(f"{where}: 'free_thresh' ({free:g}) must be below 'occupied_thresh' ({occ:g}), "
                         "both in [0, 1]")
    out["occupied_thresh"], out["free_thresh"] = occ, free
    mode = data.get("mode", "trinary")
    if mode not in MODES:
        raise ArenaError(f"{where}: 'mode' must be one of {', '.join(MODES)}; got {mode!r}")
    out["mode"] = mode
    unknown = data.get("unknown", "obstacle")
    if unknown not in UNKNOWN_AS:
        raise ArenaError(f"{where}: 'unknown' must be one of {', '.join(UNKNOWN_AS)}; got {unknown!r}")
    out["unknown"] = unknown
    return out


def free_cells(grey: np.ndarray, *, negate: bool = False, occupied_thresh: float = 0.65,
               free_thresh: float = 0.196, mode: str = "trinary", unknown: str = "obstacle") -> np.ndarray:
    """The free cells of a ``map_server`` image, as ``map_server`` classifies them.

    Parameters
    ----------
    grey : ndarray of uint8, shape (rows, cols)
        The image's grey levels (row 0 at the top).
    negate : bool
        White is occupied.
    occupied_thresh, free_thresh : float
        Occupancy probabilities above which a cell is occupied and below which it is free.
    mode : {"trinary", "scale", "raw"}
        ``raw``: the grey level is the occupancy in percent.
    unknown : {"obstacle", "free"}
        What a cell between the thresholds is: an obstacle (nobody has seen it), or free
        (only cells more likely occupied than `occupied_thresh` are walls).

    Returns
    -------
    ndarray of bool, shape (rows, cols)
        True where the cell is free.
    """
    x = grey.astype(float)
    p = x / 100.0 if mode == "raw" else x / 255.0 if negate else (255.0 - x) / 255.0
    return p < free_thresh if unknown == "obstacle" else p <= occupied_thresh


def _outline(free: np.ndarray, cm_per_px: float, origin_cm: tuple, where: str):
    """The largest connected free region of the mask `free`, as a shapely polygon in cm,
    traced along the cells' edges, with no pinch (two walls meeting at a point)."""
    import cv2
    from shapely.geometry import Polygon
    n, labels, stats, _ = cv2.connectedComponentsWithStats(free.astype(np.uint8), connectivity=4)
    if n < 2:
        raise ArenaError(f"{where}: the map has no free cell (check occupied_thresh, free_thresh and negate)")
    biggest = 1 + int(np.argmax(stats[1:, cv2.CC_STAT_AREA]))
    mask = (labels == biggest).astype(np.uint8)
    contours, hierarchy = cv2.findContours(mask, cv2.RETR_CCOMP, cv2.CHAIN_APPROX_SIMPLE)
    rows = mask.shape[0]

    def ring(c):
        return pixel_to_world(c[:, 0, :], cm_per_px, rows, origin_cm)

    outer = [i for i, h in enumerate(hierarchy[0]) if h[3] < 0]
    shell = max(outer, key=lambda i: cv2.contourArea(contours[i]))
    holes = [ring(contours[i]) for i, h in enumerate(hierarchy[0]) if h[3] == shell and len(contours[i]) >= 3]
    shell_ring = ring(contours[shell])
    if len(shell_ring) < 3:
        raise ArenaError(f"{where}: the largest free region of the map is a line of cells, too thin to "
                         "hold an arena")
    poly = Polygon(shell_ring, holes).buffer(0)
    # the contours run through the centres of the rim cells: open by a quarter cell (two
    # walls that meet at a corner become one) and grow by half a cell onto the cells' edges
    e = 0.25 * cm_per_px
    poly = poly.buffer(-e, join_style=2).buffer(e + 0.5 * cm_per_px, join_style=2)
    if poly.geom_type != "Polygon":
        poly = max(poly.geoms, key=lambda g: g.area)
    return poly


def _translated(poly, by: tuple):
    from shapely import affinity
    return affinity.translate(poly, *by) if any(by) else poly


def _within_limits(poly, cm_per_px: float, simplify_cm: float, where: str):
    """`poly` simplified, and its smallest obstacles dropped, until its obstacles are at
    most :data:`MAX_OBSTACLES` with :data:`MAX_VERTICES` vertices together."""
    from shapely.geometry import Polygon
    tol, least = simplify_cm, 0.0
    for _ in range(40):
        p = poly.simplify(tol, preserve_topology=True) if tol > 0 else poly
        holes = [h for h in p.interiors if Polygon(h).area > least]
        p = Polygon(p.exterior, holes)
        if len(holes) <= MAX_OBSTACLES and sum(len(h.coords) - 1 for h in holes) <= MAX_VERTICES:
            return p
        tol, least = max(2 * tol, cm_per_px), max(2 * least, cm_per_px ** 2)
    raise ArenaError(f"{where}: the map's obstacles stay above the arena limits ({MAX_OBSTACLES} obstacles, "
                     f"{MAX_VERTICES} vertices) however simplified")


def from_ros_map(data: dict, folder=".", *, where: str = "ROS map", name: str = "map",
                 simplify_cm: float | None = None) -> Arena:
    """Build an arena from the mapping of a ROS ``map_server`` YAML (see module doc).

    Parameters
    ----------
    data : dict
        The YAML's mapping (``image``, ``resolution``, ``origin``, ``negate``,
        ``occupied_thresh``, ``free_thresh``, optional ``mode``; optional ``name``,
        ``source``, ``strength``, ``start``).
    folder : str or os.PathLike
        Where a relative ``image`` lies (the YAML's folder).
    where : str
        How messages name the map.
    name : str
        The arena's name when `data` gives none.
    simplify_cm : float, optional
        Douglas-Peucker tolerance of the polygons, cm (default: half a cell). It grows
        until the arena's limits hold.

    Returns
    -------
    Arena
        In cm, in the map's frame (the image's lower-left corner at ``origin``).

    Raises
    ------
    ArenaError
        A key missing, unknown or out of range, the image missing, unreadable or larger
        than :data:`arenas.image.MAX_PIXELS`, no free cell, or invalid geometry.

    Examples
    --------
    >>> import numpy as np, tempfile, pathlib, arenas
    >>> grid = np.full((60, 80), 254, np.uint8); grid[20:40, 30:50] = 0
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> import cv2; _ = cv2.imwrite(str(folder / "m.pgm"), grid)
    >>> a = arenas.from_ros_map({"image": "m.pgm", "resolution": 0.05, "origin": [0, 0, 0],
    ...                          "negate": 0, "occupied_thresh": 0.65, "free_thresh": 0.196}, folder)
    >>> a.boundary.max(axis=0), len(a.obstacles)
    (array([400., 300.]), 1)
    """
    from .image import MAX_PIXELS, _number, _read_image
    keys = _checked(data, where)
    image = Path(data["image"])
    image = image if image.is_absolute() else Path(folder) / image
    grey = _read_image(image)
    if grey.size > MAX_PIXELS:
        raise ArenaError(f"{where}: image of {grey.shape[1]} x {grey.shape[0]} px has more than {MAX_PIXELS} "
                         "pixels; crop or coarsen the map")
    cm_per_px = 100.0 * keys["resolution"]
    if max(grey.shape) * cm_per_px + max(map(abs, keys["origin_cm"])) > MAX_COORD_CM:
        raise ArenaError(f"{where}: image of {grey.shape[1]} x {grey.shape[0]} px at {keys['resolution']:g} m "
                         f"per pixel reaches beyond {MAX_COORD_CM / 100:g} m")
    free = free_cells(grey, negate=keys["negate"], occupied_thresh=keys["occupied_thresh"],
                      free_thresh=keys["free_thresh"], mode=keys["mode"], unknown=keys["unknown"])
    poly = _outline(free, cm_per_px, (0.0, 0.0), where)
    if keys["yaw"]:                      # the image turned by yaw about its lower-left corner
        from shapely import affinity
        poly = affinity.rotate(poly, keys["yaw"], origin=(0.0, 0.0), use_radians=True)
    poly = _translated(poly, keys["origin_cm"])
    tol = 0.5 * cm_per_px if simplify_cm is None else _number(simplify_cm, "simplify_cm", 0.0, MAX_COORD_CM)
    poly = _within_limits(poly, cm_per_px, tol, where)
    try:
        holes = [np.asarray(h.coords)[:-1] for h in poly.interiors]
        return Arena.from_polygons(np.asarray(poly.exterior.coords)[:-1], holes, name=str(data.get("name", name)),
                                   **_scenario_keys(data, where))
    except ArenaError as exc:
        raise ArenaError(f"{where}: {exc}") from None


def _scenario_keys(data: dict, where: str) -> dict:
    """The toolkit's ``source``, ``strength`` and ``start`` (cm, degrees) of a map file, as
    :meth:`Arena.from_polygons` takes them (start heading in radians)."""
    out = {}
    for key, shapes, form in (("source", [(2,)], "[x, y]"), ("start", [(2,), (3,)], "[x, y] or [x, y, heading_deg]")):
        if data.get(key) is None:
            continue
        value = data[key]
        try:
            v = np.asarray(value, dtype=float) if isinstance(value, list) else None
        except (TypeError, ValueError):
            v = None
        if v is None or v.shape not in shapes or not np.all(np.isfinite(v)):
            raise ArenaError(f"{where}: {key!r} must be {form} in cm (and degrees); got {value!r}")
        out[key] = pose_from_degrees(v) if key == "start" else v
    if "strength" in data:
        out["strength"] = data["strength"]
    return out


def to_ros_map(arena: Arena, path, resolution: float = 0.01) -> Path:
    """Write `arena` as a ROS ``map_server`` map: the YAML at `path` and a PGM beside it.

    Free cells are written 254, obstacle cells 0 and cells outside the boundary 205
    (unknown), as ``map_saver`` writes them; ``negate: 0``, ``occupied_thresh: 0.65``,
    ``free_thresh: 0.196``. The map's frame is the arena's (``origin`` is the lower-left
    corner of its bounding box, in m); a cell is free when its centre is.

    Parameters
    ----------
    arena : Arena
        The arena (cm).
    path : str or os.PathLike
        The YAML file to write (``.yaml``); the image is the same name with ``.pgm``.
    resolution : float
        Metres per pixel, in (0, 1000]; the image has at most
        :data:`arenas.image.MAX_PIXELS` pixels.

    Returns
    -------
    Path
        The YAML written.
    """
    import cv2
    import shapely
    import yaml
    from shapely.geometry import Polygon

    from .image import MAX_PIXELS, _number
    cm_per_px = 100.0 * _number(resolution, "resolution (m per pixel)", 0.0, 1e3, open_lo=True)
    lo, hi = arena.boundary.min(axis=0), arena.boundary.max(axis=0)
    cols, rows = (int(math.ceil(v / cm_per_px - 1e-9)) for v in hi - lo)
    if cols * rows > MAX_PIXELS or min(cols, rows) < 4:
        raise ArenaError(f"a map of arena {arena.name!r} at {resolution:g} m per pixel has {cols} x {rows} "
                         f"pixels; choose a resolution that gives 4 to {MAX_PIXELS} pixels")
    rows_i, cols_i = np.mgrid[0:rows, 0:cols]
    centres = pixel_to_world(np.column_stack([cols_i.ravel(), rows_i.ravel()]), cm_per_px, rows, tuple(lo))
    inside = shapely.contains_xy(Polygon(arena.boundary), centres[:, 0], centres[:, 1])
    grey = np.where(arena.contains(centres), FREE, np.where(inside, OCCUPIED, UNKNOWN)).astype(np.uint8)
    grey = grey.reshape(rows, cols)
    path = Path(path)
    image = path.with_suffix(".pgm")
    if not cv2.imwrite(str(image), grey):
        raise ArenaError(f"cannot write {str(image)!r}")
    meta = {"image": image.name, "resolution": float(resolution),
            "origin": [float(lo[0]) / 100.0, float(lo[1]) / 100.0, 0.0], "negate": 0,
            "occupied_thresh": 0.65, "free_thresh": 0.196, "mode": "trinary"}
    path.write_text(yaml.safe_dump(meta, sort_keys=False))
    return path

