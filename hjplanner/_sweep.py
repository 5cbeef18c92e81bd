"""Semi-Lagrangian Gauss-Seidel sweeps, compiled with numba.

Discretisation of eq. (11) of Landa et al. (the dynamic programming
principle behind eq. (13)): from node (x_i, y_j, θ_k) the car follows an exact
arc (or segment) of length ``s_c`` with control ``c``, landing at heading
``θ_k + u_c s_c/ρ`` -- chosen to be a grid heading -- and at a position that is
generally off the grid.  Then

    φ_ijk = min( bc_ijk, min_c [ s_c + Σ_ab w_ab φ(i + di + a, j + dj + b, k') ] )

with bilinear weights ``w_ab >= 0`` summing to one, over the controls c whose
whole arc is certified clear of the walls (:func:`stencil_masks`).  The update is a monotone,
consistent scheme, and its fixed point is found by Gauss-Seidel sweeps.
Within a heading layer the nodes are visited against the direction of
straight motion, so the straight-line dependencies are resolved in a single
pass; the layers are visited alternately by increasing and decreasing θ, which
resolves left and right turns respectively.

Blocked and unreachable states are +inf in the result.  During the sweeps
they hold the finite stand-in ``BIG``: a stencil touching one with a positive
weight yields a candidate above ``UNREACHABLE`` (effectively +inf), while no
``0 * inf`` or ``inf - inf`` can arise, and nodes not yet reached do not block
the growth of the finite region.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np
from numba import njit

from ._motion import _arc_end, _arc_is_clear, _sample_count

INF = np.inf
# Stand-in for +inf inside the sweeps.  Blocked and not-yet-reached nodes hold
# BIG; a bilinear weight is either 0 or above ~1e-18 (fractions are snapped),
# so any candidate that touches a BIG node exceeds UNREACHABLE and is +inf in
# the result, while finite candidates never mix with inf arithmetic.
BIG = 1e100
UNREACHABLE = 1e50


BLOCK = 8  # side of the (x, y) blocks whose changes are tracked, in nodes
GROUPS = 2  # groups of layers swept independently within a sweep (see solve_sweeps)


@njit(cache=True, nogil=True)
def _update_layer(phi, bc, k, off_i, off_j, w, inv_self, kk, cost, adm, rev_i, rev_j, pad, active, tol, sweep,
                  changed, scratch):
    """One Gauss-Seidel pass over layer ``k`` of the padded array, only in ``active`` blocks.

    Candidate of stencil c, if its arc is clear of the walls (bit c of
    ``adm``): ``(cost + Σ_ab w_ab φ_foot,ab) * inv_self`` where a weight on
    the node itself (straight steps shorter than the cell diagonal) is moved
    to the left-hand side.  Sets ``changed[k, bi, bj] = sweep`` where some
    node decreased by more than ``tol``.

    The turning stencils read other layers only, which do not change during
    this pass: their minimum (with ``bc``) is taken first, a whole row of
    active blocks at a time in loops the compiler vectorises, into
    ``scratch`` (nx, ny).  The straight stencils, whose feet lie in this
    layer, follow node by node in the Gauss-Seidel order.  The minimum being
    exact, the result is the same as taking every candidate node by node.
    """
    nt, nxp, nyp = phi.shape
    nx, ny = nxp - 2 * pad, nyp - 2 * pad
    nc = off_i.shape[1]
    nby = active.shape[1]
    for i in range(nx):
        bi = i // BLOCK
        ip = i + pad
        bj = 0
        while bj < nby:
            if not active[bi, bj]:
                bj += 1
                continue
            run = bj
            while run < nby and active[bi, run]:
                run += 1
            j0, j1 = bj * BLOCK, min(run * BLOCK, ny)
            bj = run
            for j in range(j0, j1):
                scratch[i, j] = bc[k, i, j]
            for c in range(nc):
                kc = kk[k, c]
                if kc == k:
                    continue
                a = ip + off_i[k, c]
                b0 = pad + off_j[k, c]
                w0, w1, w2, w3 = w[k, c, 0], w[k, c, 1], w[k, c, 2], w[k, c, 3]
                cst, inv = cost[k, c], inv_self[k, c]
                bit = np.uint32(1) << np.uint32(c)
                for j in range(j0, j1):
                    b = b0 + j
                    value = (cst + w0 * phi[kc, a, b] + w1 * phi[kc, a, b + 1] + w2 * phi[kc, a + 1, b]
                             + w3 * phi[kc, a + 1, b + 1]) * inv
                    if (adm[k, i, j] & bit) != 0 and value < scratch[i, j]:
                        scratch[i, j] = value
    for p in range(nx):
        i = nx - 1 - p if rev_i else p
        bi = i // BLOCK
        for q in range(ny):
            j = ny - 1 - q if rev_j else q
            bj = j // BLOCK
            bits = adm[k, i, j]
            if bits == 0 or not active[bi, bj]:
                continue
            ip, jp = i + pad, j + pad
            best = scratch[i, j]
            for c in range(nc):
                if kk[k, c] == k and (bits >> c) & 1:
                    best = min(best, _candidate(phi, k, c, ip, jp, off_i, off_j, w, inv_self, kk, cost))
            old = phi[k, ip, jp]
            # Candidates that touched BIG stay unreached (BIG) rather than
            # creeping down geometrically through astronomically large values.
            if best < old and best < UNREACHABLE:
                phi[k, ip, jp] = best
                if old - best > tol:
                    changed[k, bi, bj] = sweep


@njit(cache=True, nogil=True, inline="always")
def _candidate(phi, k, c, ip, jp, off_i, off_j, w, inv_self, kk, cost):
    """Value of stencil c at padded node (ip, jp) of layer k: cost plus the bilinear φ at its foot."""
    kc = kk[k, c]
    a = ip + off_i[k, c]
    b = jp + off_j[k, c]
    return (cost[k, c] + w[k, c, 0] * phi[kc, a, b] + w[k, c, 1] * phi[kc, a, b + 1]
            + w[k, c, 2] * phi[kc, a + 1, b] + w[k, c, 3] * phi[kc, a + 1, b + 1]) * inv_self[k, c]


@njit(cache=True, nogil=True)
def stencil_masks(distance, free, clearance, ci, cj, corner_dist, margin, reach):
    """Bitmask (ntheta, nx, ny) of the stencils whose arc is clear of the walls.

    Bit c of ``adm[k, i, j]`` is set when the arc of control c from the free
    node (i, j) at heading k stays at the clearance: either the node is
    farther than ``clearance + reach[c]`` from every wall (the arc is
    shorter than ``reach[c]``), or its middle sample has a certified wall
    distance of at least ``margin[c]`` plus the arc length from it to the
    farther end (the whole arc lies in that disk), or every sample m of
    the arc, in cell ``(i + ci, j + cj)`` at ``corner_dist`` from its
    corners, has a certified wall distance of at least ``margin[c]`` or
    lies within the disk of radius ``bound - margin[c]`` around an earlier
    sample of certified distance ``bound`` (a point of that disk is at
    least ``margin[c]`` from every wall, the wall distance being
    1-Lipschitz); samples in such disks are skipped.
    """
    nt, nc, nm = ci.shape
    nx, ny = distance.shape
    adm = np.zeros((nt, nx, ny), np.uint32)
    every = np.uint32((1 << nc) - 1)
    far = clearance + reach.max()
    mid = (nm - 1) // 2
    half = (nm - 1 - mid) / (nm - 1)  # arc length from the middle sample to the farther end / reach
    for i in range(nx):
        for j in range(ny):
            if not free[i, j]:
                continue
            d0 = distance[i, j]
            if d0 >= far:  # every arc is shorter than the distance to the walls
                for k in range(nt):
                    adm[k, i, j] = every
                continue
            for k in range(nt):
                bits = np.uint32(0)
                for c in range(nc):
                    ok = d0 >= clearance + reach[c]
                    if not ok:
                        a = i + ci[k, c, mid]
                        b = j + cj[k, c, mid]
                        if a >= 0 and b >= 0 and a <= nx - 2 and b <= ny - 2:
                            bound = -np.inf
                            for corner in range(4):
                                value = distance[a + corner // 2, b + corner % 2] - corner_dist[k, c, mid, corner]
                                if value > bound:
                                    bound = value
                            ok = bound >= margin[c] + reach[c] * half
                    if not ok:
                        ok = True
                        step = reach[c] / (nm - 1)  # arc length between samples
                        covered = -1.0  # samples up to this index lie in the certified disk of a checked one
                        m = 0
                        while m < nm:
                            a = i + ci[k, c, m]
                            b = j + cj[k, c, m]
                            if a < 0 or b < 0 or a > nx - 2 or b > ny - 2:
                                ok = False
                                break
                            bound = -np.inf
                            for corner in range(4):
                                value = distance[a + corner // 2, b + corner % 2] - corner_dist[k, c, m, corner]
                                if value > bound:
                                    bound = value
                            if bound < margin[c]:
                                if m <= covered:
                                    m += 1
                                    continue
                                ok = False
                                break
                            if bound - margin[c] >= reach[c] * (nm - 1 - m) / (nm - 1):
                                break  # the rest of the arc lies in the certified disk around this sample
                            covered = max(covered, m + (bound - margin[c]) / step)
                            m += max(1, int((bound - margin[c]) / step))
                    if ok:
                        bits |= np.uint32(1) << np.uint32(c)
                adm[k, i, j] = bits
    return adm


@njit(cache=True, nogil=True)
def _layer_is_active(k, kk, reach, changed, computed, active):
    """Mark blocks of layer k that depend on a block changed since they were computed."""
    nt, nbx, nby = changed.shape
    nc = kk.shape[1]
    n_active = 0
    for bi in range(nbx):
        for bj in range(nby):
            since = computed[k, bi, bj]
            flag = False
            for c in range(nc + 1):
                kc = k if c == nc else kk[k, c]
                for ei in range(max(bi - reach, 0), min(bi + reach + 1, nbx)):
                    for ej in range(max(bj - reach, 0), min(bj + reach + 1, nby)):
                        if changed[kc, ei, ej] >= since:
                            flag = True
                            break
                    if flag:
                        break
                if flag:
                    break
            active[bi, bj] = flag
            if flag:
                n_active += 1
    return n_active


@njit(cache=True, nogil=True)
def _sweep_layers(phi, bc, off_i, off_j, w, inv_self, kk, cost, adm, pad, reach, tol, sweep, changed, computed,
                  active, order, rev_i, rev_j, scratch):
    """Sweep the layers in ``order``; returns how many layers had active blocks."""
    n_run = 0
    for k in order:
        if _layer_is_active(k, kk, reach, changed, computed, active) == 0:
            continue
        n_run += 1
        _update_layer(phi, bc, k, off_i, off_j, w, inv_self, kk, cost, adm, rev_i[k], rev_j[k], pad, active, tol,
                      sweep, changed, scratch)
        for bi in range(active.shape[0]):
            for bj in range(active.shape[1]):
                if active[bi, bj]:
                    computed[k, bi, bj] = sweep
    return n_run


def solve_sweeps(phi, bc, off_i, off_j, w, inv_self, kk, cost, adm, rev_i, rev_j, pad, tol, max_sweeps, nthreads,
                 two_way=False, progress=None):
    """Iterate Gauss-Seidel sweeps until no value decreases by more than ``tol``.

    ``phi`` (ntheta, nx + 2 pad, ny + 2 pad) is updated in place; its border
    and blocked nodes hold BIG, so that a foot in a cell with a blocked
    corner gives no candidate; ``adm`` is the bitmask of :func:`stencil_masks`.
    Values only decrease from the initial data, so the iteration is monotone,
    and it converges under any order of the updates.

    Sweeps visit the layers by increasing θ on even sweeps and decreasing θ
    on odd ones (resolving left and right turns).  With ``nthreads`` = 2
    (at most :data:`GROUPS`) each sweep splits the layers into two groups of
    consecutive headings, whose boundaries move by a quarter turn every
    sweep; a stencil reaching into the other group reads that layer as it
    was at the start of the sweep (a snapshot), so the groups share no value
    that changes during a sweep and two threads (the kernels release the
    GIL) sweep them concurrently with a result that does not depend on
    their timing: the same inputs and thread count give the same bits.  ``progress``, if
    given, is called after every sweep with the sweeps done, the blocks recomputed in it
    and the number of blocks.  With reverse driving (``two_way``) the order within the layers
    also flips every other pair of sweeps, so that reverse straight steps,
    whose feet lie behind the node, are resolved in one pass as well.  A
    block of a layer is recomputed only if a block it depends on changed
    since the block was last computed, so converged regions cost nothing in
    later sweeps.  Returns the number of sweeps done.
    """
    nt = phi.shape[0]
    nx, ny = phi.shape[1] - 2 * pad, phi.shape[2] - 2 * pad
    nbx = (nx + BLOCK - 1) // BLOCK
    nby = (ny + BLOCK - 1) // BLOCK
    reach = (pad + BLOCK - 1) // BLOCK
    groups = max(1, min(int(nthreads), GROUPS, nt))
    turn = int(np.abs((kk - np.arange(nt)[:, None] + nt // 2) % nt - nt // 2).max())
    nsnap = 0 if groups == 1 else min(nt, 2 * groups * turn)
    # layers nt.. of `work` and `changed` hold the snapshots of the sweep
    work = np.empty((nt + nsnap, *phi.shape[1:]))
    work[:nt] = phi
    changed = np.full((nt + nsnap, nbx, nby), -1, np.int64)  # sweep of the last change; -1: initial data
    computed = np.full((nt, nbx, nby), -2, np.int64)  # sweep of the last computation
    active = np.zeros((groups, nbx, nby), np.bool_)
    scratch = np.empty((groups, nx, ny))
    args = (work, bc, off_i, off_j, w, inv_self)
    rest = (cost, adm, pad, reach, float(tol))

    def layers(group, sweep):
        start, stop = (group * nt) // groups, ((group + 1) * nt) // groups
        shift = (sweep * nt) // (2 * groups)  # move the group boundaries between sweeps
        order = np.arange(start, stop) if sweep % 2 == 0 else np.arange(stop - 1, start - 1, -1)
        return (order + shift) % nt

    def sources(sweep):
        """``kk`` with every stencil reaching into another group redirected to a snapshot layer."""
        owner = np.empty(nt, np.int64)
        for group in range(groups):
            owner[layers(group, sweep)] = group
        cross = owner[kk] != owner[:, None]
        deps = np.unique(kk[cross])
        slot = np.arange(nt)
        slot[deps] = nt + np.arange(len(deps))
        work[nt:nt + len(deps)] = work[deps]
        changed[nt:nt + len(deps)] = changed[deps]
        return np.where(cross, slot[kk], kk)

    pool = ThreadPoolExecutor(groups) if groups > 1 else None
    try:
        sweeps = 0
        while sweeps < max_sweeps:
            source = sources(sweeps)
            flip = two_way and (sweeps // 2) % 2 == 1
            ri, rj = rev_i ^ flip, rev_j ^ flip

            def run(group, sweep=sweeps):
                return _sweep_layers(*args, source, *rest, sweep, changed, computed, active[group],
                                     layers(group, sweep), ri, rj, scratch[group])

            n_run = sum(map(run, range(groups)) if pool is None else pool.map(run, range(groups)))
            if n_run == 0:
                break
            sweeps += 1
            if progress is not None:
                progress(sweeps, n_run, nt * nbx * nby)
    finally:
        if pool is not None:
            pool.shutdown()
    phi[:] = work[:nt]
    return sweeps


@njit(cache=True, nogil=True)
def _cubic_weights(t, w):
    """Catmull-Rom weights for offsets -1, 0, 1, 2 at fraction ``t``."""
    t2 = t * t
    t3 = t2 * t
    w[0] = -0.5 * t3 + t2 - 0.5 * t
    w[1] = 1.5 * t3 - 2.5 * t2 + 1.0
    w[2] = -1.5 * t3 + 2.0 * t2 + 0.5 * t
    w[3] = 0.5 * t3 - 0.5 * t2


@njit(cache=True, nogil=True)
def interpolate(phi, free, certified, x0, y0, h, xs, ys, ths, cubic, lenient):
    """φ at arbitrary poses: tricubic (Catmull-Rom, periodic in θ) or trilinear.

    The trilinear value is +inf if a corner of the pose's cell is blocked
    (not ``free``), as at the feet of the scheme's stencils, or +inf;
    with ``lenient``, unreached free corners are left out and the weights
    of the others renormalised.  Where the cubic stencil touches a +inf
    node the trilinear value is used.  Poses outside the grid or not
    ``certified`` (outside free space or its clearance) give +inf.
    """
    nt = phi.shape[0]
    n = xs.shape[0]
    out = np.empty(n)
    dth = 2.0 * np.pi / nt
    wxc = np.empty(4)
    wyc = np.empty(4)
    wtc = np.empty(4)
    for m in range(n):
        if not certified[m]:
            out[m] = INF
            continue
        out[m] = _interpolate_one(phi, free, (xs[m] - x0) / h, (ys[m] - y0) / h, (ths[m] / dth) % nt, cubic,
                                  lenient, wxc, wyc, wtc)
    return out


@njit(cache=True, nogil=True)
def _interpolate_one(phi, free, gx, gy, gt, cubic, lenient, wxc, wyc, wtc):
    """:func:`interpolate` at grid coordinates (gx, gy, gt), gt in [0, ntheta); ``w*c`` are scratch (4,).

    At a grid heading (gt an integer) only that layer is read.
    """
    nt, nx, ny = phi.shape
    if not (gx >= -1e-9 and gx <= nx - 1 + 1e-9 and gy >= -1e-9 and gy <= ny - 1 + 1e-9):
        return INF
    i = min(max(int(np.floor(gx)), 0), nx - 2)
    j = min(max(int(np.floor(gy)), 0), ny - 2)
    k = int(np.floor(gt)) % nt
    fx = gx - i
    fy = gy - j
    ft = gt - np.floor(gt)
    # trilinear; with lenient, over the reached corners only
    lin = 0.0
    total = 0.0
    for c in range(2):
        wt = ft if c == 1 else 1.0 - ft
        if wt <= 0.0:
            continue
        kc = (k + c) % nt
        for a in range(2):
            wa = fx if a == 1 else 1.0 - fx
            for b in range(2):
                wb = fy if b == 1 else 1.0 - fy
                weight = wt * wa * wb
                if weight <= 0.0:
                    continue
                v = phi[kc, i + a, j + b]
                if not free[i + a, j + b] or (v == INF and not lenient):
                    lin = INF
                if v == INF:
                    continue
                if lin < INF:
                    lin += weight * v
                    total += weight
    if lin == INF or total <= 0.0:
        return INF
    lin /= total
    if not cubic or i < 1 or j < 1 or i > nx - 3 or j > ny - 3:
        return lin
    _cubic_weights(fx, wxc)
    _cubic_weights(fy, wyc)
    _cubic_weights(ft, wtc)
    c0, c1 = (1, 2) if ft == 0.0 else (0, 4)  # Catmull-Rom weights at 0: (0, 1, 0, 0)
    acc = 0.0
    for c in range(c0, c1):
        kc = (k + c - 1) % nt
        for a in range(4):
            for b in range(4):
                v = phi[kc, i + a - 1, j + b - 1]
                if v == INF:
                    return lin
                acc += wtc[c] * wxc[a] * wyc[b] * v
    return max(acc, 0.0)


@njit(cache=True, nogil=True)
def arc_readings(phi, free, distance, clearance, x0, y0, h, rho, reverse, xs, ys, ths, base, steps, cubic,
                 lenient):
    """``base`` lowered, pose by pose, by readings along exact arcs to the nearby grid headings.

    From a pose (x, y, θ) between the grid headings θ_k and θ_k+1 the car
    can turn left to θ_k+1, ..., θ_k+steps or right to θ_k, ..., θ_k+1-steps
    (forwards; with ``reverse`` also backwards) along an exact arc of length
    ``s = ρ |Δθ|``, which ends at a grid heading: ``s + φ(end)`` is then an
    upper bound of φ (the dynamic programming principle) read without
    interpolation in θ, which smears φ across its jumps (where the target
    passes from one side of a turning circle to the other) over a whole
    angular step.  Only arcs certified clear of the walls at ``clearance``
    (the samples of :func:`hjplanner._motion.arcs_are_clear`) and ending at
    a finite reading count.  Poses where ``base`` is +inf, or at a grid
    heading, keep it.

    Parameters
    ----------
    phi, free, distance : numpy.ndarray
        Node values (ntheta, nx, ny), free mask and signed wall distance (nx, ny).
    clearance, x0, y0, h, rho : float
        Wall clearance, grid origin, spacing and turning radius (length unit).
    reverse : bool
        Also backward arcs.
    xs, ys, ths, base : numpy.ndarray
        (n,) poses (length unit, radians) and their interpolated φ.
    steps : int
        Grid headings reached on each side.
    cubic, lenient : bool
        As in :func:`interpolate`.

    Returns
    -------
    numpy.ndarray
        (n,) the smaller of ``base`` and the arc readings.
    """
    nt = phi.shape[0]
    dth = 2.0 * np.pi / nt
    out = base.copy()
    wxc = np.empty(4)
    wyc = np.empty(4)
    wtc = np.empty(4)
    for m in range(xs.shape[0]):
        if out[m] == INF:
            continue
        gt = (ths[m] / dth) % nt
        k = int(np.floor(gt))
        f = gt - k
        if f == 0.0:
            continue  # at a grid heading nothing is interpolated in θ
        best = out[m]
        for jj in range(1, steps + 1):
            for side in range(2):
                if side == 0:  # left turn forwards (right turn backwards) to heading k + jj
                    d, u, kc = (jj - f) * dth, 1.0, (k + jj) % nt
                else:  # right turn forwards (left turn backwards) to heading k + 1 - jj
                    d, u, kc = (f + jj - 1) * dth, -1.0, (k + 1 - jj) % nt
                if d <= 0.0:
                    continue
                s = rho * d
                if s >= best:
                    continue
                npts = _sample_count(s, h)
                need = clearance + 0.5 * (s / (npts - 1))
                for v in (1.0, -1.0):
                    if v < 0 and not reverse:
                        continue
                    ex, ey, _ = _arc_end(xs[m], ys[m], ths[m], u * v, v, s, rho)
                    if not _arc_is_clear(distance, x0, y0, h, need, xs[m], ys[m], ths[m], u * v, v, s, npts, rho):
                        continue
                    value = s + _interpolate_one(phi, free, (ex - x0) / h, (ey - y0) / h, float(kc), cubic, lenient,
                                                 wxc, wyc, wtc)
                    if value < best:
                        best = value
        out[m] = best
    return out
