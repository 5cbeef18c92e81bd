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
NEVER = -(1 << 62)  # stamp of a block that never held a finite value


@njit(cache=True, nogil=True, inline="always")
def _dep_changed(dilated, kc, e0, f0, since, p):
    """Whether one of the 2 x 2 blocks from (e0, f0) of layer kc changed at or after stamp ``since``.

    ``dilated`` holds, at ``[kc, e0 + p, f0 + p]``, the latest stamp of those
    blocks (:func:`_dilated`), so the question is one read.
    """
    return dilated[kc, e0 + p, f0 + p] >= since


@njit(cache=True, nogil=True, inline="always")
def _stamp_block(dilated, k, bi, bj, stamp, p):
    """Record stamp ``stamp`` for block (bi, bj) of layer k in the dilated stamps (see :func:`_dilated`)."""
    for e in range(bi - 1 + p, bi + 1 + p):
        for f in range(bj - 1 + p, bj + 1 + p):
            if dilated[k, e, f] < stamp:
                dilated[k, e, f] = stamp


def _dilated(stamps: np.ndarray, p: int) -> np.ndarray:
    """Block stamps (layer, bx, by) as the latest stamp of each 2 x 2 group of blocks.

    Entry ``[k, e0 + p, f0 + p]`` is the largest stamp of the blocks
    ``[e0, e0 + 2) x [f0, f0 + 2)`` of layer k that exist (:data:`NEVER` if
    none does), for ``e0, f0 >= -p``: the question a stencil asks of the
    blocks holding its feet.  A block's new stamp is written to the four
    groups that hold it (:func:`_stamp_block`); stamps only grow, so the
    entries stay the maxima.
    """
    n, nbx, nby = stamps.shape
    out = np.full((n, nbx + 2 * p, nby + 2 * p), NEVER, np.int64)
    for de in (0, 1):
        for df in (0, 1):
            view = out[:, p - de:p - de + nbx, p - df:p - df + nby]
            np.maximum(view, stamps, out=view)
    return out


@njit(cache=True, nogil=True)
def _turning_stencil(phi, k, c, off_i, off_j, w, inv_self, src, cost, adm, pad, i0, i1, j0, j1, tmin):
    """``tmin[i, j]`` lowered to the candidate of turning stencil c where smaller, on ``[i0, i1) x [j0, j1)``.

    A turning stencil reads another layer (``src[k, c]``: the layer, or its
    snapshot, that it reads), which does not change while layer k is swept,
    so it is taken a row at a time in a loop the compiler vectorises.
    """
    m = j1 - j0
    kc = src[k, c]
    w0, w1, w2, w3 = w[k, c, 0], w[k, c, 1], w[k, c, 2], w[k, c, 3]
    cst, inv = cost[k, c], inv_self[k, c]
    bit = np.uint32(1) << np.uint32(c)
    for i in range(i0, i1):
        a = i + pad + off_i[k, c]
        b0 = pad + off_j[k, c] + j0
        # Row slices indexed from 0: the compiler then vectorises the loop over j.
        sc = tmin[i, j0:j1]
        ad = adm[k, i, j0:j1]
        r0 = phi[kc, a, b0:b0 + m + 1]
        r1 = phi[kc, a + 1, b0:b0 + m + 1]
        for j in range(m):
            value = (cst + w0 * r0[j] + w1 * r0[j + 1] + w2 * r1[j] + w3 * r1[j + 1]) * inv
            if (ad[j] & bit) == 0:
                value = INF
            sc[j] = min(sc[j], value)


@njit(cache=True, nogil=True)
def _straight_pass(lay, tmin, ad, i0, i1, j0, j1, rev_i, rev_j, pad, n_straight, s_bit, s_di, s_dj, s_w, s_cost,
                   s_inv, tol):
    """Gauss-Seidel update of the nodes ``[i0, i1) x [j0, j1)`` of one layer ``lay`` (padded), in their order.

    A node gets the smaller of its value, ``tmin`` (the turning minimum)
    and the candidates of the straight stencils s set in its bitmask ``ad``
    (bit ``s_bit[s]``), whose feet lie in this layer at offsets
    ``(s_di[s], s_dj[s])`` with weights ``s_w[s]``.  The parameters of the
    first two stencils are held in locals for the whole pass.  Returns 2
    if some node decreased by more than ``tol``, else 1 if some node
    decreased, else 0.
    """
    bit0, di0, dj0, cst0, inv0 = s_bit[0], s_di[0], s_dj[0], s_cost[0], s_inv[0]
    w00, w01, w02, w03 = s_w[0, 0], s_w[0, 1], s_w[0, 2], s_w[0, 3]
    bit1, di1, dj1, cst1, inv1 = s_bit[1], s_di[1], s_dj[1], s_cost[1], s_inv[1]
    w10, w11, w12, w13 = s_w[1, 0], s_w[1, 1], s_w[1, 2], s_w[1, 3]
    moved = 0
    for p in range(i1 - i0):
        i = i1 - 1 - p if rev_i else i0 + p
        ip = i + pad
        a0, a1 = ip + di0, ip + di1
        for q in range(j1 - j0):
            j = j1 - 1 - q if rev_j else j0 + q
            bits = ad[i, j]
            if bits == 0:
                continue
            jp = j + pad
            best = tmin[i, j]
            if bits & bit0:
                b = jp + dj0
                best = min(best, (cst0 + w00 * lay[a0, b] + w01 * lay[a0, b + 1] + w02 * lay[a0 + 1, b]
                                  + w03 * lay[a0 + 1, b + 1]) * inv0)
            if bits & bit1:
                b = jp + dj1
                best = min(best, (cst1 + w10 * lay[a1, b] + w11 * lay[a1, b + 1] + w12 * lay[a1 + 1, b]
                                  + w13 * lay[a1 + 1, b + 1]) * inv1)
            for s in range(2, n_straight):
                if bits & s_bit[s]:
                    a, b = ip + s_di[s], jp + s_dj[s]
                    best = min(best, (s_cost[s] + s_w[s, 0] * lay[a, b] + s_w[s, 1] * lay[a, b + 1]
                                      + s_w[s, 2] * lay[a + 1, b] + s_w[s, 3] * lay[a + 1, b + 1]) * s_inv[s])
            old = lay[ip, jp]
            # Candidates that touched BIG stay unreached (BIG) rather than
            # creeping down geometrically through astronomically large values.
            if best < old and best < UNREACHABLE:
                lay[ip, jp] = best
                moved = max(moved, 2 if old - best > tol else 1)
    return moved


@njit(cache=True, nogil=True)
def _update_layer(phi, tmin, k, off_i, off_j, w, inv_self, kk, src, cost, adm, rev_i, rev_j, pad, qi, qj, self_seen,
                  tol, clock, fixed, changed, touched, computed, layer_changed, turn, stale):
    """One Gauss-Seidel pass over layer ``k`` of the padded array, block by block.

    Candidate of stencil c, if its arc is clear of the walls (bit c of
    ``adm``): ``(cost + Σ_ab w_ab φ_foot,ab) * inv_self`` where a weight on
    the node itself (straight steps shorter than the cell diagonal) is moved
    to the left-hand side.  The foot cells of stencil c from a block lie in
    the 2 x 2 blocks from ``(bi + qi[k, c], bj + qj[k, c])`` of layer
    ``src[k, c]``.  A block is computed only if one of them changed after
    the block last read it (``changed > computed``).  Each computed block
    takes the stamp ``t = 2 * clock`` (the clock counts computed blocks),
    or ``t = fixed`` if ``fixed`` > 0 (one stamp for a whole sweep), and
    gets ``changed[k, bi, bj] = layer_changed[k] = t`` where some node
    decreased by more than ``tol``, ``touched[k, bi, bj] = t`` where some
    node decreased at all, and ``computed[k, bi, bj] = t`` -- or ``t - 1``
    when a change of the block itself may have come after a node read it
    (``self_seen`` false: a straight foot not upstream; always with
    ``fixed``), so that it is computed again.  Returns the blocks computed
    and the clock.

    ``tmin[k]`` (unpadded) holds, node by node, the smallest of ``bc`` and
    the turning stencils' candidates read so far.  Values only decrease, so
    no candidate is ever below one read earlier, and ``tmin`` is the
    current turning minimum once the stencils whose feet decreased since
    the last read have been read again: a computed block reads only those
    (``touched`` after ``computed``; :func:`_turning_stencil`, a row of
    blocks at a time).  The result is the same as reading every turning
    stencil at every computation, to the bit.

    The blocks are visited row by row in the order of the nodes (``rev_i``,
    ``rev_j``), and the nodes of a block in that order too: a node whose
    straight feet all lie upstream in both coordinates reads them after
    their update, as in a pass over the whole layer.  Whether a block depends
    on a change of this layer is decided when the pass reaches it, so a
    change travels along straight motion across any number of blocks in one
    pass.  The straight stencils are taken node by node
    (:func:`_straight_pass`).
    """
    nt, nxp, nyp = phi.shape
    nx, ny = nxp - 2 * pad, nyp - 2 * pad
    nc = off_i.shape[1]
    nbx, nby = computed.shape[1], computed.shape[2]
    p = (changed.shape[1] - nbx) // 2  # the margin of the dilated stamps
    n_straight = 0
    straight = np.empty(nc, np.int64)
    for c in range(nc):
        if kk[k, c] == k:
            straight[n_straight] = c
            n_straight += 1
    s_bit = np.zeros(max(n_straight, 2), np.uint32)  # at least two entries: bit 0 means no such stencil
    s_di = np.zeros(max(n_straight, 2), np.int64)
    s_dj = np.zeros(max(n_straight, 2), np.int64)
    s_w = np.zeros((max(n_straight, 2), 4))
    s_cost = np.zeros(max(n_straight, 2))
    s_inv = np.zeros(max(n_straight, 2))
    for s in range(n_straight):
        c = straight[s]
        s_bit[s] = np.uint32(1) << np.uint32(c)
        s_di[s], s_dj[s], s_cost[s], s_inv[s] = off_i[k, c], off_j[k, c], cost[k, c], inv_self[k, c]
        s_w[s] = w[k, c]
    lay, ad, tm = phi[k], adm[k], tmin[k]
    n_blocks = 0
    for pb in range(nbx):
        bi = nbx - 1 - pb if rev_i else pb
        i0, i1 = bi * BLOCK, min(bi * BLOCK + BLOCK, nx)
        for bj in range(nby):
            since = computed[k, bi, bj] + 1
            flag = False
            for c in range(nc):
                if kk[k, c] != k:
                    stale[bj, c] = _dep_changed(touched, src[k, c], bi + qi[k, c], bj + qj[k, c], since, p)
                    flag = flag or (stale[bj, c] and _dep_changed(changed, src[k, c], bi + qi[k, c],
                                                                  bj + qj[k, c], since, p))
                else:
                    stale[bj, c] = False
            turn[bj] = flag
        for c in range(nc):
            bj = 0
            while bj < nby:
                if not (turn[bj] and stale[bj, c]):
                    bj += 1
                    continue
                run = bj
                while run < nby and turn[run] and stale[run, c]:
                    run += 1
                _turning_stencil(phi, k, c, off_i, off_j, w, inv_self, src, cost, adm, pad, i0, i1, bj * BLOCK,
                                 min(run * BLOCK, ny), tm)
                bj = run
        for qb in range(nby):
            bj = nby - 1 - qb if rev_j else qb
            j0, j1 = bj * BLOCK, min(bj * BLOCK + BLOCK, ny)
            if not turn[bj]:
                since = computed[k, bi, bj] + 1
                flag = False
                for s in range(n_straight):
                    c = straight[s]
                    if _dep_changed(changed, k, bi + qi[k, c], bj + qj[k, c], since, p):
                        flag = True
                        break
                if not flag:
                    continue
                for c in range(nc):
                    if stale[bj, c]:
                        _turning_stencil(phi, k, c, off_i, off_j, w, inv_self, src, cost, adm, pad, i0, i1, j0, j1,
                                         tm)
            n_blocks += 1
            clock += 1
            stamp = fixed if fixed > 0 else 2 * clock
            computed[k, bi, bj] = stamp if self_seen and fixed <= 0 else stamp - 1
            moved = _straight_pass(lay, tm, ad, i0, i1, j0, j1, rev_i, rev_j, pad, n_straight, s_bit, s_di, s_dj, s_w,
                                   s_cost, s_inv, tol)
            if moved > 0:
                _stamp_block(touched, k, bi, bj, stamp, p)
            if moved > 1:
                _stamp_block(changed, k, bi, bj, stamp, p)
                layer_changed[k] = stamp
    return n_blocks, clock


def stencil_masks(distance, free, clearance, ci, cj, corner_dist, margin, reach, threads=1, base=None):
    """Bitmask (ntheta, nx, ny) of the stencils whose arc is clear of the walls (see
    :func:`_stencil_mask_rows`), computed by ``threads`` threads (at most :data:`GROUPS`),
    each taking every ``threads``-th row of nodes: rows near the walls cost the most, and
    interleaved rows share them evenly.  Each node's bits depend on that node alone, so
    the result is the same bits for any number of threads.

    ``base``, optional, is ``(distance, free, adm)`` of the same grid and stencils (another
    map of the same arena): a node's bits depend only on ``distance`` and ``free`` within
    the reach of its arcs' samples (:func:`mask_reach`), so only the nodes within that
    reach of a node where either differs are computed, and the others keep ``adm``'s bits:
    the same bits as computing them all.
    """
    nt = ci.shape[0]
    nx, ny = distance.shape
    if base is None:
        adm = np.zeros((nt, nx, ny), np.uint32)
        todo = np.ones((nx, ny), np.bool_)
    else:
        old_distance, old_free, old_adm = base
        adm = np.array(old_adm, dtype=np.uint32, copy=True)
        todo = mask_reach((old_distance != distance) | (old_free != free), ci, cj)
        if not todo.any():
            return adm
    args = (distance, free, float(clearance), ci, cj, corner_dist, margin, reach, todo, adm)
    threads = max(1, min(int(threads), GROUPS, nx))
    if threads == 1:
        _stencil_mask_rows(*args, 0, 1)
        return adm
    with ThreadPoolExecutor(threads) as pool:       # the kernel releases the GIL
        list(pool.map(lambda first: _stencil_mask_rows(*args, first, threads), range(threads)))
    return adm


def mask_reach(changed, ci, cj):
    """The nodes (nx, ny) whose clear-arc bits read a node of `changed` (nx, ny): the node
    itself, and the corners ``(i + ci + a, j + cj + b)``, ``a, b`` in {0, 1}, of its arcs'
    sample cells (:func:`_stencil_mask_rows`)."""
    lo_i, hi_i = min(0, int(ci.min())), max(0, int(ci.max()) + 1)
    lo_j, hi_j = min(0, int(cj.min())), max(0, int(cj.max()) + 1)
    nx, ny = changed.shape
    # counts of changed nodes in each window [i + lo_i, i + hi_i] x [j + lo_j, j + hi_j]
    padded = np.zeros((nx + hi_i - lo_i + 1, ny + hi_j - lo_j + 1), np.int64)
    padded[1 - lo_i:1 - lo_i + nx, 1 - lo_j:1 - lo_j + ny] = changed
    total = padded.cumsum(axis=0).cumsum(axis=1)
    wi, wj = hi_i - lo_i + 1, hi_j - lo_j + 1
    window = total[wi:wi + nx, wj:wj + ny] - total[:nx, wj:wj + ny] - total[wi:wi + nx, :ny] + total[:nx, :ny]
    return window > 0


@njit(cache=True, nogil=True)
def _stencil_mask_rows(distance, free, clearance, ci, cj, corner_dist, margin, reach, todo, adm, first, step):
    """Write into ``adm`` (ntheta, nx, ny) the bitmask of the stencils whose arc is clear of the
    walls, for the nodes of ``todo`` (nx, ny) in the rows ``first, first + step, ...``.

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
    1-Lipschitz); samples in such disks are skipped.  An arc whose end sample
    is off the grid or surely within ``margin[c]`` of a wall (its distance
    bounded above by ``D(corner) + |sample - corner|``) is rejected before
    the walk: no certified disk can hold that sample.
    """
    nt, nc, nm = ci.shape
    nx, ny = distance.shape
    every = np.uint32((1 << nc) - 1)
    far = clearance + reach.max()
    mid = (nm - 1) // 2
    half = (nm - 1 - mid) / (nm - 1)  # arc length from the middle sample to the farther end / reach
    for i in range(first, nx, step):
        for j in range(ny):
            if not todo[i, j]:
                continue
            if not free[i, j]:
                for k in range(nt):
                    adm[k, i, j] = 0
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
                        # The end sample first: an arc whose end leaves the grid, or lies surely
                        # within margin[c] of a wall (an upper bound of the distance there, the
                        # distance being 1-Lipschitz), is blocked; no certified disk can hold it.
                        a = i + ci[k, c, nm - 1]
                        b = j + cj[k, c, nm - 1]
                        if a < 0 or b < 0 or a > nx - 2 or b > ny - 2:
                            continue
                        upper = np.inf
                        for corner in range(4):
                            value = distance[a + corner // 2, b + corner % 2] + corner_dist[k, c, nm - 1, corner]
                            if value < upper:
                                upper = value
                        if upper < margin[c]:
                            continue
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


@njit(cache=True, nogil=True)
def _sweep_layers(phi, tmin, off_i, off_j, w, inv_self, kk, src, cost, adm, pad, qi, qj, self_seen, tol, clock, fixed,
                  changed, touched, computed, layer_changed, layer_pass, skip, order, rev_i, rev_j, turn, stale):
    """Sweep the layers in ``order`` (:func:`_update_layer`); returns the blocks computed and the clock.

    ``layer_changed[k]`` is the stamp of the last change in layer k and
    ``layer_pass[k]`` the clock's stamp when its last pass began.  With
    ``skip``, a layer none of whose source layers (itself included) changed
    since then is passed over without looking at its blocks: each of them
    has read every change it depends on.
    """
    n_blocks = 0
    for p in range(order.shape[0]):
        k = order[p]
        if skip:
            idle = True
            for c in range(kk.shape[1]):
                if layer_changed[src[k, c]] > layer_pass[k]:
                    idle = False
            layer_pass[k] = 2 * clock
            if idle:
                continue
        n, clock = _update_layer(phi, tmin, k, off_i, off_j, w, inv_self, kk, src, cost, adm, rev_i[k], rev_j[k],
                                 pad, qi, qj, self_seen[k], tol, clock, fixed, changed, touched, computed,
                                 layer_changed, turn, stale)
        n_blocks += n
    return n_blocks, clock


def _upstream(off_i, off_j, w, kk, rev_i, rev_j):
    """Per layer: whether the feet of all its straight stencils lie upstream in the order of the nodes.

    A foot corner ``(di, dj)`` with a positive weight is upstream when each
    offset is 0 or points against the order of the nodes in its coordinate,
    so that the pass (block by block, node by node) has updated it before
    the node reads it.
    """
    nt = kk.shape[0]
    di = off_i[..., None] + np.array([0, 0, 1, 1])  # (nt, nc, 4): corners (0,0), (0,1), (1,0), (1,1)
    dj = off_j[..., None] + np.array([0, 1, 0, 1])
    up_i = (di == 0) | ((di > 0) == np.asarray(rev_i, bool)[:, None, None])
    up_j = (dj == 0) | ((dj > 0) == np.asarray(rev_j, bool)[:, None, None])
    ok = np.all((w <= 0) | (up_i & up_j), axis=-1)
    return np.all(ok | (kk != np.arange(nt)[:, None]), axis=1)


def solve_sweeps(phi, bc, off_i, off_j, w, inv_self, kk, cost, adm, rev_i, rev_j, pad, tol, max_sweeps, nthreads,
                 two_way=False, progress=None, consume_bc=False):
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
    whose feet lie behind the node, are resolved in one pass as well.

    Work is tracked in (x, y) blocks of :data:`BLOCK` nodes of each layer,
    with stamps: every block computation gets a larger stamp than the
    previous one (with 2 threads, every sweep gets one), a block records the
    stamp of its last computation and of its last change by more than
    ``tol``, and it is computed again only if a block holding the feet of
    one of its stencils changed after it read them.  Blocks that never held
    a finite value have no stamp, so the sweeps skip the region the front
    has not reached, and converged regions cost nothing in later sweeps.
    The turning minimum of each node is kept between computations and only
    the turning stencils whose feet decreased since are read again (see
    :func:`_update_layer`).  With ``consume_bc`` (a float64 C-contiguous ``bc`` the caller
    will not read again) ``bc`` itself holds the turning minima, saving a copy.  Returns the
    number of sweeps done.
    """
    nt = phi.shape[0]
    nx, ny = phi.shape[1] - 2 * pad, phi.shape[2] - 2 * pad
    nbx = (nx + BLOCK - 1) // BLOCK
    nby = (ny + BLOCK - 1) // BLOCK
    qi, qj = off_i // BLOCK, off_j // BLOCK
    groups = max(1, min(int(nthreads), GROUPS, nt))
    turn = int(np.abs((kk - np.arange(nt)[:, None] + nt // 2) % nt - nt // 2).max())
    nsnap = 0 if groups == 1 else min(nt, 2 * groups * turn)
    # layers nt.. of `work` and `changed` hold the snapshots of the sweep
    if nsnap:
        work = np.empty((nt + nsnap, *phi.shape[1:]))
        work[:nt] = phi
    else:
        work = phi
    changed = np.full((nt + nsnap, nbx, nby), NEVER, np.int64)  # stamp of the last change
    _stamp_initial(phi, pad, changed)  # the initial data
    layer_changed = changed[:nt].max(axis=(1, 2))
    # from here on, both hold the stamps of each group of 2 x 2 blocks a stencil's feet lie in
    changed = _dilated(changed, 1 + int(max(np.abs(qi).max(), np.abs(qj).max())))
    touched = changed.copy()  # stamp of the last decrease of any size
    computed = np.full((nt, nbx, nby), -1, np.int64)  # stamp of the last computation
    layer_pass = np.full(nt, -1, np.int64)
    clock = 0
    flags = np.zeros((groups, nby), np.bool_)
    stale = np.zeros((groups, nby, kk.shape[1]), np.bool_)
    # the turning minimum read so far, node by node (see _update_layer); it starts as bc
    tmin = bc if consume_bc else np.array(bc, dtype=float)
    args = (work, tmin, off_i, off_j, w, inv_self, kk)
    rest = (cost, adm, pad, qi, qj)

    def layers(group, sweep):
        start, stop = (group * nt) // groups, ((group + 1) * nt) // groups
        shift = (sweep * nt) // (2 * groups)  # move the group boundaries between sweeps
        order = np.arange(start, stop) if sweep % 2 == 0 else np.arange(stop - 1, start - 1, -1)
        return (order + shift) % nt

    def sources(sweep):
        """``kk`` with every stencil reaching into another group redirected to a snapshot layer."""
        if groups == 1:
            return kk
        owner = np.empty(nt, np.int64)
        for group in range(groups):
            owner[layers(group, sweep)] = group
        cross = owner[kk] != owner[:, None]
        deps = np.unique(kk[cross])
        slot = np.arange(nt)
        slot[deps] = nt + np.arange(len(deps))
        work[nt:nt + len(deps)] = work[deps]
        changed[nt:nt + len(deps)] = changed[deps]
        touched[nt:nt + len(deps)] = touched[deps]
        return np.where(cross, slot[kk], kk)

    upstream = {flip: _upstream(off_i, off_j, w, kk, rev_i ^ flip, rev_j ^ flip) for flip in {False, bool(two_way)}}
    pool = ThreadPoolExecutor(groups) if groups > 1 else None
    try:
        sweeps = 0
        while sweeps < max_sweeps:
            source = sources(sweeps)
            flip = two_way and (sweeps // 2) % 2 == 1
            ri, rj = rev_i ^ flip, rev_j ^ flip
            if groups == 1:  # a stamp per block computation
                fixed = 0
            else:  # a stamp per sweep: a change in the sweep of a block's computation counts as unseen
                fixed = 2 * (sweeps + 1)

            def run(group, sweep=sweeps, fixed=fixed, clock=clock):
                return _sweep_layers(*args, source, *rest, upstream[flip], float(tol), clock, fixed, changed,
                                     touched, computed, layer_changed, layer_pass, groups == 1, layers(group, sweep),
                                     ri, rj, flags[group], stale[group])

            results = list(map(run, range(groups)) if pool is None else pool.map(run, range(groups)))
            n_blocks = sum(n for n, _ in results)
            clock = max(c for _, c in results)
            if n_blocks == 0:
                break
            sweeps += 1
            if progress is not None:
                progress(sweeps, n_blocks, nt * nbx * nby)
    finally:
        if pool is not None:
            pool.shutdown()
    if work is not phi:
        phi[:] = work[:nt]
    return sweeps


@njit(cache=True, nogil=True)
def _stamp_initial(phi, pad, changed):
    """Stamp 0 in ``changed`` (layer, block) for every block holding a node of ``phi`` below UNREACHABLE."""
    nt = phi.shape[0]
    nx, ny = phi.shape[1] - 2 * pad, phi.shape[2] - 2 * pad
    for k in range(nt):
        for i in range(nx):
            for j in range(ny):
                if phi[k, i + pad, j + pad] < UNREACHABLE:
                    changed[k, i // BLOCK, j // BLOCK] = 0


@njit(cache=True, nogil=True)
def initial_values(bc, free, pad, out):
    """Write into ``out`` the padded array the sweeps update: ``bc`` where finite at a free node, BIG elsewhere.

    ``bc`` (ntheta, nx, ny); ``out`` (ntheta, nx + 2 pad, ny + 2 pad), written once
    (the border and blocked nodes hold BIG, see :func:`solve_sweeps`).
    """
    nt, nx, ny = bc.shape
    for k in range(nt):
        out[k, :pad, :] = BIG
        out[k, nx + pad:, :] = BIG
        for i in range(nx):
            row = out[k, i + pad]
            row[:pad] = BIG
            row[ny + pad:] = BIG
            for j in range(ny):
                value = bc[k, i, j]
                row[j + pad] = value if np.isfinite(value) and free[i, j] else BIG


@njit(cache=True, nogil=True)
def final_values(phi, pad, out):
    """Write into ``out`` (ntheta, nx, ny) the unpadded φ of the sweeps' array, +inf where it is at
    least UNREACHABLE."""
    nt = phi.shape[0]
    nx, ny = phi.shape[1] - 2 * pad, phi.shape[2] - 2 * pad
    for k in range(nt):
        for i in range(nx):
            for j in range(ny):
                value = phi[k, i + pad, j + pad]
                out[k, i, j] = INF if value >= UNREACHABLE else value


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
