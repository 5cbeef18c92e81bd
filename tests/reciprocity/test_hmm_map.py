"""Hidden-Markov plume mapping (Farrell, Pang & Li 2003): A(t), α/β/Ψ against a
brute-force small HMM, Viterbi (MLOP) and the detection path (MLDP) against brute force."""

import itertools
import time

import numpy as np
import pytest
from scipy import sparse

from reciprocity.beliefs.hmm import HMMSourceMap, plume_map
from reciprocity.errors import SearchError
from reciprocity.models.hmm import (CellGrid, backtrack, detection_path, forward_path, transition, viterbi,
                                    viterbi_backward)
from reciprocity.observations import Observation

SMALL = CellGrid((0.0, 4.0, 0.0, 3.0), 4, 3)          # 1 m cells, N = 12


def _flows(seed=0, L=6, umax=1.6):
    rng = np.random.default_rng(seed)
    return [rng.uniform(-umax, umax, 2) for _ in range(L)]


@pytest.mark.parametrize("u", [(0.3, 0.2), (-0.7, 0.1), (0.2, -0.9), (0.0, 0.0), (2.5, -1.2)])
def test_rows_of_A_sum_to_one_and_mass_is_conserved(u):
    t = transition(SMALL, u, 1.0)
    a = t.matrix().toarray()
    assert np.allclose(a.sum(axis=1), 1.0) and (a >= 0).all()
    if t.substeps == 1:                            # |u| dt < L: at most nine per row (App. II)
        assert (np.count_nonzero(t.bar().toarray(), axis=1) <= 9).all()
    x = np.r_[np.random.default_rng(1).dirichlet(np.ones(SMALL.N)), 0.0]
    for _ in range(5):
        x = x @ a
    assert x.sum() == pytest.approx(1.0)           # what leaves the cells is in C0
    # with C0's row = π (the source releases into the cells) rows still sum to one
    pi = np.full(SMALL.N, 1 / SMALL.N)
    assert np.allclose(t.matrix(pi).toarray().sum(axis=1), 1.0)


def test_appendix_II_weights():
    g = CellGrid((0, 100, -50, 50), 40, 25)
    t = transition(g, (1.0, 2.0), 1.0)            # ε_x = 1/2.5, ε_y = 2/4
    a = t.bar()
    k = 10 + 12 * 40
    row = a.getrow(k).toarray().ravel()
    assert row[k] == pytest.approx(0.6 * 0.5) and row[k + 1] == pytest.approx(0.4 * 0.5)
    assert row[k + 40] == pytest.approx(0.6 * 0.5) and row[k + 41] == pytest.approx(0.4 * 0.5)


def _dense(ts):
    return [t.bar().toarray() for t in ts]


def test_alpha_beta_psi_against_brute_force():
    ts = [transition(SMALL, u, 1.0) for u in _flows()]
    A = _dense(ts)
    L, N = len(A), SMALL.N

    def phi(lo, hi):                              # Φ(t_hi, t_lo) = Ā(t_lo) ... Ā(t_{hi-1})
        out = np.eye(N)
        for a in A[lo:hi]:
            out = out @ a
        return out

    psi_bf = sum(phi(i, L) for i in range(L + 1)) / (L + 1)          # eq. (16)
    belief = HMMSourceMap(SMALL)
    psi = np.eye(N)
    buf = np.empty_like(psi)
    for n, t in enumerate(ts, start=1):
        t.superpose(psi, n, buf)                  # eq. (13)
        psi, buf = buf, psi
    assert np.allclose(psi, psi_bf, atol=1e-14)
    pi = np.random.default_rng(2).dirichlet(np.ones(N))
    assert np.allclose(plume_map(pi, ts), pi @ psi_bf, atol=1e-14)     # eq. (11) = eq. (12)
    j = 7
    b = np.eye(N)[j]
    total = b.copy()
    for t in reversed(ts):                        # Table II, eq. (14)
        b = t.left(b)
        total += b
    assert np.allclose(b, phi(0, L)[:, j], atol=1e-14)
    assert np.allclose(total / (L + 1), psi_bf[:, j], atol=1e-14)
    for t in ts:                                   # the belief runs the same recursion
        belief.advance(np.array([t.ex * t.sx, t.ey * t.sy]) * t.substeps, False, (0.5, 0.5))
    assert np.allclose(belief.psi, psi_bf, atol=1e-14)


def test_viterbi_reproduces_the_papers_example():
    a0 = sparse.csr_matrix([[0.6, 0.4, 0.0], [0.0, 1.0, 0.0], [0.0, 1.0, 0.0]])
    a1 = sparse.csr_matrix([[0.25, 0.25, 0.5], [0.0, 1.0, 0.0], [0.0, 0.5, 0.5]])
    log_d, psi = viterbi(np.array([1.0, 0.0, 0.0]), [a0, a1, a1])
    d = np.exp(log_d)
    assert np.allclose(d[2], [0.15, 0.40, 0.30]) and np.allclose(d[3], [0.0375, 0.40, 0.15])
    assert backtrack(psi[:2], 1).tolist() == [0, 1, 1]
    assert backtrack(psi, 2).tolist() == [0, 0, 2, 2]


def test_viterbi_forward_and_backward_against_brute_force():
    g = CellGrid((0, 2, 0, 2), 2, 2)
    ts = [transition(g, u, 1.0) for u in _flows(seed=4, L=3, umax=0.9)]
    A = _dense(ts)
    pi = np.array([0.4, 0.3, 0.2, 0.1])
    paths = list(itertools.product(range(4), repeat=len(A) + 1))
    prob = {q: pi[q[0]] * np.prod([A[k][q[k], q[k + 1]] for k in range(len(A))]) for q in paths}
    log_d, psi = viterbi(pi, [t.bar() for t in ts])
    for j in range(4):
        best = max((p for q, p in prob.items() if q[-1] == j), default=0.0)
        assert np.exp(log_d[-1, j]) == pytest.approx(best)
        if best > 0:
            assert prob[tuple(backtrack(psi, j))] == pytest.approx(best)
    j = 3
    log_mu, nxt = viterbi_backward(j, [t.bar() for t in ts])
    for i in range(4):
        best = max(np.prod([A[k][q[k], q[k + 1]] for k in range(len(A))]) for q in paths
                   if q[0] == i and q[-1] == j)
        assert np.exp(log_mu[0, i]) == pytest.approx(best)
        if best > 0:
            q = forward_path(nxt, i, 0)
            assert q[-1] == j
            assert np.prod([A[k][q[k], q[k + 1]] for k in range(len(A))]) == pytest.approx(best)


def test_detection_path_against_brute_force():
    g = CellGrid((0, 3, 0, 2), 3, 2)
    alpha = np.random.default_rng(5).uniform(0.05, 1.0, g.N)
    nb = g.neighbours()
    j, s = 0, 3
    log_mu, prev = detection_path(alpha, nb, j, s)
    for m in range(g.N):
        best = 0.0
        for q in itertools.product(range(g.N), repeat=s):
            path = (j,) + q
            if path[-1] == m and all(path[k + 1] in nb[path[k]] for k in range(s)):
                best = max(best, np.prod(alpha[list(path)]))
        assert np.exp(log_mu[s, m]) == pytest.approx(best)


def test_slim_update_moves_mass_upflow_of_a_detection():
    g = CellGrid((0, 100, -50, 50), 40, 25)
    b = HMMSourceMap(g, readings=1)
    for _ in range(40):
        b.update(Observation((60.0, 1.0), 0.0, kind="detection", data={"wind": [1.0, 0.0]}))
    assert b.weights().sum() == pytest.approx(1.0) and (b.weights() >= 0).all()
    b.update(Observation((60.0, 1.0), 1.0, kind="detection", data={"wind": [1.0, 0.0]}))
    est = b.estimate()
    assert est[0] < 60.0 and abs(est[1]) < 5.0     # upflow of the detection, on its line
    assert b.entropy() < np.log(g.N)
    k = int(g.index((60.0, 1.0))[0])
    odour, start = b.mlop(k)
    assert odour[-1] == k and (np.diff(g.ij(odour)[0]) >= 0).all()     # carried downflow to C_k
    cross = b.intersection(k)
    assert cross["estimate"][0] <= 61.25 and k in cross["cells"]
    with pytest.raises(SearchError, match="wind"):
        b.update(Observation((60.0, 1.0), 0.0, kind="detection"))


@pytest.mark.benchmark
def test_one_map_update_is_fast():
    """α/β/Ψ over 1000 cells per mapping period: ≤ 5 ms (median of 50)."""
    g = CellGrid((0, 100, -50, 50), 40, 25)
    b = HMMSourceMap(g, readings=1)
    rng = np.random.default_rng(0)
    times = []
    for k in range(60):
        t0 = time.perf_counter()
        b.advance(rng.normal([1.0, 0.0], 0.3), bool(k % 7 == 0), rng.uniform([0, -50], [100, 50]))
        b.alpha()
        times.append(time.perf_counter() - t0)
    assert np.median(times[10:]) < 5e-3


def test_paper_cell_numbers():
    g = CellGrid((0, 100, -50, 50), 40, 25)
    x0, y0 = g.centres()[g.from_paper(488)]
    assert abs(x0 - 20) <= 1.25 and abs(y0) <= 2           # the source's cell, C_488
    assert g.centres()[g.from_paper(64)][1] > 40             # C_64 lies at the top edge
    assert all(g.to_paper(g.from_paper(k)) == k for k in (1, 64, 388, 471, 488, 619, 1000))


def test_most_likely_odour_path_under_the_uniform_flow_of_eq_18():
    """Fig. 7's set-up: 1 m/s along x for t < 30 s, then along y; the MLOP from C_488 at
    t = 0 to C_388 at t = 44 s moves only downflow: +x first, then +y."""
    g = CellGrid((0, 100, -50, 50), 40, 25)
    mats = [transition(g, (1.0, 0.0) if t < 30 else (0.0, 1.0), 1.0).bar() for t in range(44)]
    log_d, psi = viterbi(np.eye(g.N)[g.from_paper(488)], mats)
    q = backtrack(psi, g.from_paper(388))
    assert np.isfinite(log_d[-1, g.from_paper(388)])
    i, j = g.ij(q)
    assert q[0] == g.from_paper(488) and q[-1] == g.from_paper(388)
    assert (np.diff(i[:31]) >= 0).all() and (np.diff(j[:31]) == 0).all()
    assert (np.diff(i[30:]) == 0).all() and (np.diff(j[30:]) >= 0).all()


def test_farrell_figures_are_written(tmp_path):
    from reciprocity.wiring.filament import filament_params
    from reciprocity.scenarios import load_scenario
    from reciprocity.viz.hmm import farrell_figures
    from reciprocity.worlds.filament_figures import farrell_record
    (path,) = farrell_figures(farrell_record(filament_params(load_scenario("farrell").params)), tmp_path)
    assert path.exists() and path.stat().st_size > 20_000
