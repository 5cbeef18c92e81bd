"""Compiled kernels of the path search: the exact φ near a point target and the hybrid A*.

:func:`hjplanner.optimal_path` re-plans every few centimetres on the car, and its
best-first search expands about a hundred poses per plan; in numpy each
expansion cost a dozen small-array calls.  Here one call runs the whole
search.  Every step mirrors its numpy counterpart operation for operation:
:func:`point_distance` that of :func:`hjplanner.dubins.point_distance` (to
within an ulp: numpy's ``arctan2`` and ``arccos`` are its own vectorised
versions), the arcs those of :func:`hjplanner._motion.arcs_from` and φ the
same :func:`hjplanner._sweep.interpolate`.
"""

from __future__ import annotations

import heapq

import numpy as np
from numba import njit

from ._motion import _arc_end, arcs_from
from ._sweep import interpolate

TWO_PI = 2.0 * np.pi


@njit(cache=True, nogil=True, inline="always")
def _cs_left(a, b, rho):
    """:func:`hjplanner.dubins._cs_left` of one point."""
    cx, cy = a, b - rho
    dc2 = cx * cx + cy * cy
    tangent = np.sqrt(max(dc2 - rho * rho, 0.0))
    psi = np.arctan2(cy, cx) - np.arctan2(tangent, rho)
    turn = np.mod(psi + 0.5 * np.pi, TWO_PI)
    if turn > TWO_PI - 1e-9:
        turn = 0.0
    if dc2 >= rho * rho * (1.0 - 1e-12):
        return rho * turn + tangent
    return np.inf


@njit(cache=True, nogil=True, inline="always")
def _cc_right_left(a, b, rho):
    """:func:`hjplanner.dubins._cc_right_left` of one point."""
    dx, dy = a, b + rho
    d = np.hypot(dx, dy)
    if not (d >= rho and d <= 3.0 * rho):
        return np.inf
    cos_alpha = min(max((3.0 * rho * rho + d * d) / (4.0 * rho * max(d, 1e-300)), -1.0), 1.0)
    alpha = np.arccos(cos_alpha)
    delta = np.arctan2(dy, dx)
    best = np.inf
    for sign in (-1.0, 1.0):
        direction = delta + sign * alpha
        t1 = np.mod(0.5 * np.pi - direction, TWO_PI)
        c2x = 2.0 * rho * np.cos(direction)
        c2y = 2.0 * rho * np.sin(direction)
        end_angle = np.arctan2(dy - c2y, dx - c2x)
        t2 = np.mod(end_angle - (direction + np.pi), TWO_PI)
        best = min(best, rho * (t1 + t2))
    return best


@njit(cache=True, nogil=True)
def point_distance(x, y, theta, rho, tx, ty):
    """:func:`hjplanner.dubins.point_distance` of one pose to the point (tx, ty)."""
    dx, dy = tx - x, ty - y
    c, s = np.cos(theta), np.sin(theta)
    a, b = c * dx + s * dy, -s * dx + c * dy
    if np.hypot(a, b) == 0.0:
        return 0.0
    return min(min(_cs_left(a, b, rho), _cs_left(a, -b, rho)),
               min(_cc_right_left(a, b, rho), _cc_right_left(a, -b, rho)))


@njit(cache=True, nogil=True)
def local_exact(x, y, theta, tx, ty, rho, r0, reverse):
    """:func:`hjplanner.dubins.local_exact` of one pose.

    Poses whose target lies too little ahead for any path of length ``<= r0`` are
    answered without solving: at arc length ``t`` a path has turned by at most
    ``t/ρ``, so after a length ``L <= πρ/2`` it has advanced at least ``ρ sin(L/ρ)``
    along its first heading, and ``L >= d`` (the distance to the target). A target
    less than ``ρ sin(d/ρ)`` ahead (behind, for reverse driving) is out of the layer,
    the same answer as solving it would give.
    """
    dx, dy = tx - x, ty - y
    d = np.hypot(dx, dy)
    if not d <= r0 * (1.0 + 1e-9) + 1e-12:
        return np.inf
    forward, backward = True, reverse
    if r0 <= 0.5 * np.pi * rho:
        ahead = np.cos(theta) * dx + np.sin(theta) * dy
        least = rho * np.sin(d / rho) - 1e-9 * (rho + d) - 1e-12
        forward = ahead >= least
        backward = reverse and -ahead >= least
    value = point_distance(x, y, theta, rho, tx, ty) if forward else np.inf
    if backward:
        value = min(value, point_distance(x, y, theta + np.pi, rho, tx, ty))
    return value if value <= r0 else np.inf


@njit(cache=True, nogil=True)
def local_exact_many(x, y, theta, tx, ty, rho, r0, reverse):
    """:func:`local_exact` of poses ``(x[n], y[n], theta[n])`` (1-D arrays), compiled.

    :func:`hjplanner.dubins.local_exact` of the same poses to within an ulp, in one
    pass without the temporary arrays of the numpy version.
    """
    out = np.empty(x.shape[0])
    for n in range(x.shape[0]):
        out[n] = local_exact(x[n], y[n], theta[n], tx, ty, rho, r0, reverse)
    return out


@njit(cache=True, nogil=True)
def exact_layer(bc, ii, jj, xs, ys, thetas, tx, ty, rho, r0, reverse):
    """Write the exact values into ``bc[k, ii[n], jj[n]]`` for every heading ``thetas[k]``
    and node ``(xs[n], ys[n])``: :func:`local_exact` (+inf beyond ``r0``)."""
    for k in range(thetas.shape[0]):
        for n in range(ii.shape[0]):
            bc[k, ii[n], jj[n]] = local_exact(xs[n], ys[n], thetas[k], tx, ty, rho, r0, reverse)


@njit(cache=True, nogil=True, inline="always")
def _arrived(x, y, theta, tx, ty, rho, stop_tol, r0, reverse):
    """Within ``stop_tol`` of the target, or in the exact layer of radius ``r0``."""
    if np.hypot(x - tx, y - ty) <= stop_tol:
        return True
    return r0 > 0 and np.isfinite(local_exact(x, y, theta, tx, ty, rho, r0, reverse))


@njit(cache=True, nogil=True)
def _values(phi, free, x0, y0, h, ends, clear, lengths, tx, ty, rho, r0, reverse, lenient):
    """``s + φ(end)`` of clear arcs (+inf for the others), φ as ``ValueFunction.at_certified``."""
    phi_end = interpolate(phi, free, clear, x0, y0, h, np.ascontiguousarray(ends[:, 0]),
                          np.ascontiguousarray(ends[:, 1]), np.ascontiguousarray(ends[:, 2]), False, lenient)
    out = np.empty(ends.shape[0])
    for c in range(ends.shape[0]):
        value = phi_end[c]
        if r0 > 0 and np.hypot(ends[c, 0] - tx, ends[c, 1] - ty) <= r0:
            value = min(value, local_exact(ends[c, 0], ends[c, 1], ends[c, 2], tx, ty, rho, r0, reverse))
        out[c] = lengths[c] + value if clear[c] else np.inf
    return out


@njit(cache=True, nogil=True)
def hybrid_astar(phi, free, distance, x0, y0, h, dtheta, ntheta, start, value_start, us, vs, lengths, rho,
                 clearance, tx, ty, stop_tol, r0, reverse, ds, max_length, max_steps):
    """The best-first search of :func:`hjplanner.paths._search`, compiled.

    Returns
    -------
    moves : numpy.ndarray
        Indices into (us, vs, lengths) of the controls from the start.
    arrived : bool
        Whether the chain ends on an arriving pose (else on the expanded pose of smallest φ).
    """
    m = us.shape[0]
    cap = 1024
    px, py, pt = np.empty(cap), np.empty(cap), np.empty(cap)
    parent = np.empty(cap, np.int64)
    move = np.empty(cap, np.int64)
    done = np.empty(cap, np.bool_)
    px[0], py[0], pt[0], parent[0], move[0] = start[0], start[1], start[2], -1, -1
    done[0] = _arrived(start[0], start[1], start[2], tx, ty, rho, stop_tol, r0, reverse)
    size = 1
    heap = [(value_start, 0, 0.0, 0)]
    closed = set()
    counter = 0
    best_value, best_node = np.inf, 0
    smax = lengths.max()
    n_along = max(2, int(np.ceil(smax / ds)) + 1)
    along_step = 1.0 / (n_along - 1)  # np.linspace(0, 1, n_along)
    reach = max(stop_tol, r0)
    pose = np.empty(3)
    while len(heap) > 0 and len(closed) < max_steps:
        item = heapq.heappop(heap)
        g, n = item[2], item[3]
        if done[n]:
            return _chain(parent, move, n), True
        key = (int(np.floor(px[n] / h)), int(np.floor(py[n] / h)),
               int(np.floor(np.mod(pt[n], TWO_PI) / dtheta + 0.5)) % ntheta)
        if key in closed:
            continue
        closed.add(key)
        pose[0], pose[1], pose[2] = px[n], py[n], pt[n]
        ends, clear = arcs_from(pose, us, vs, lengths, rho, distance, x0, y0, h, clearance)
        values = _values(phi, free, x0, y0, h, ends, clear, lengths, tx, ty, rho, r0, reverse, len(closed) == 1)
        c_min = np.argmin(values)
        if np.isfinite(values[c_min]):
            v = values[c_min] - lengths[c_min]
            if v < best_value or (v == best_value and n < best_node):
                best_value, best_node = v, n
        for c in range(m):
            if not np.isfinite(values[c]) or g + lengths[c] > max_length:
                continue
            passing = _arrived(ends[c, 0], ends[c, 1], ends[c, 2], tx, ty, rho, stop_tol, r0, reverse)
            if not passing and np.hypot(px[n] - tx, py[n] - ty) <= lengths[c] + reach:
                for j in range(n_along):  # does the arc arrive somewhere along its length?
                    frac = 1.0 if j == n_along - 1 else j * along_step
                    x, y, t = _arc_end(px[n], py[n], pt[n], float(us[c]), float(vs[c]), lengths[c] * frac, rho)
                    if _arrived(x, y, t, tx, ty, rho, stop_tol, r0, reverse):
                        passing = True
                        break
            counter += 1
            if size == cap:
                cap *= 2
                px, py, pt = _grow(px, cap), _grow(py, cap), _grow(pt, cap)
                parent, move, done = _grow(parent, cap), _grow(move, cap), _grow(done, cap)
            px[size], py[size], pt[size] = ends[c, 0], ends[c, 1], ends[c, 2]
            parent[size], move[size], done[size] = n, c, passing
            heapq.heappush(heap, (g + values[c], counter, g + lengths[c], size))
            size += 1
    return _chain(parent, move, best_node), False


@njit(cache=True, nogil=True)
def _grow(a, cap):
    out = np.empty(cap, a.dtype)
    out[:a.shape[0]] = a
    return out


@njit(cache=True, nogil=True)
def _chain(parent, move, n):
    """Control indices from the root of the search tree to node ``n``."""
    k, j = 0, n
    while parent[j] >= 0:
        k += 1
        j = parent[j]
    out = np.empty(k, np.int64)
    j = n
    while parent[j] >= 0:
        k -= 1
        out[k] = move[j]
        j = parent[j]
    return out
