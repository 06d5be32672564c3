"""The compiled sampler kernels against their pure-Python references (the oracles)."""

from collections import Counter
from fractions import Fraction
from functools import lru_cache

import numpy as np
import pytest

# ------------------------------------------------------------- triangle Metropolis


@pytest.mark.parametrize(
    "N, ph, seed, sweeps",
    [(3, None, 0, 400), (6, None, 1, 200), (9, 0.3, 2, 150), (10, 0.01, 3, 100), (11, 1.0, 4, 60), (16, None, 5, 25)],
)
def test_triangle_compiled_chain_is_the_reference_chain(N, ph, seed, sweeps):
    from forcenet.numeric.triangle.metropolis import TriangleMetropolis

    ref = TriangleMetropolis(N, seed=seed, ph=ph, kernel="python")
    fast = TriangleMetropolis(N, seed=seed, ph=ph, kernel="compiled")
    a = ref.run(sweeps, burn_in=5)
    b = fast.run(sweeps, burn_in=5)
    assert np.array_equal(a, b)  # same seed, same chain, move for move
    assert np.array_equal(ref.q, fast.q)
    assert (ref.attempted, ref.accepted, ref.rejected_by_constraint) == (
        fast.attempted, fast.accepted, fast.rejected_by_constraint)
    assert ref.rng.random() == fast.rng.random()  # and the same random numbers consumed
    if ph is not None and ph < 0.5:
        assert fast.rejected_by_constraint > 0


def test_triangle_sweep_then_run_mixes_kernels():
    from forcenet.numeric.triangle.metropolis import TriangleMetropolis

    ref = TriangleMetropolis(7, seed=9, kernel="python")
    fast = TriangleMetropolis(7, seed=9, kernel="compiled")
    ref.sweep(3)
    fast.sweep(3)
    fast.kernel = "python"  # the state carries over between kernels
    ref.sweep(2)
    fast.sweep(2)
    fast.kernel = "compiled"
    assert np.array_equal(ref.run(20), fast.run(20))


def test_kernel_argument_is_checked():
    from forcenet.numeric.triangle.metropolis import TriangleMetropolis

    with pytest.raises(ValueError, match="kernel"):
        TriangleMetropolis(4, kernel="fortran")


# -------------------------------------------------------------- packing Metropolis


def _scenes():
    from forcenet.numeric.packing import Scene

    return [
        (Scene(N=4, P=5, F=10.0, mg=1.0, j0=3), None, 200),
        (Scene(N=5, P=9, F=10.0, pv=1.0, ph=1.0), None, 150),
        (Scene(N=8, P=17, F=10.0, pv=1.0, ph=1.0), 0.2, 40),
        (Scene(N=6, P=9, F=5.0, pv=1.0, mg=0.5, ph=2.0), None, 60),
        (Scene(N=9, P=13, F=100.0, mg=1.0), 0.5, 30),
    ]


@pytest.mark.parametrize("case", range(5))
def test_packing_compiled_chain_is_the_reference_chain(case):
    from forcenet.numeric.packing import PackingMetropolis

    scene, step, sweeps = _scenes()[case]
    ref = PackingMetropolis(scene, seed=11 + case, step=step, kernel="python")
    fast = PackingMetropolis(scene, seed=11 + case, step=step, kernel="compiled")
    Wa, qa = ref.run(sweeps, 5, record_q=True)
    Wb, qb = fast.run(sweeps, 5, record_q=True)
    assert np.array_equal(Wa, Wb) and np.array_equal(qa, qb)
    assert (ref.attempted, ref.accepted, ref.rejected_by_constraint) == (
        fast.attempted, fast.accepted, fast.rejected_by_constraint)


# ----------------------------------------------------- the exact sampler's hook walk


def _strict_partitions(m, largest=None):
    largest = m if largest is None else largest
    if m == 0:
        yield ()
        return
    for first in range(min(m, largest), 0, -1):
        for rest in _strict_partitions(m - first, first - 1):
            yield (first,) + rest


@lru_cache(None)
def _count(lam):
    """Standard shifted tableaux of shape ``lam``, by removing the largest entry (no hook formula)."""
    lam = tuple(x for x in lam if x > 0)
    if not lam:
        return 1
    total = 0
    for r in range(len(lam)):
        shorter = list(lam)
        shorter[r] -= 1
        if r + 1 < len(lam) and shorter[r] <= lam[r + 1]:
            continue  # not a corner: the next row would reach as far
        total += _count(tuple(shorter))
    return total


def _shifted_hook(lam, r, c):
    """The cells of the shifted hook of (r, c) other than (r, c) itself: the arm, the leg, and row c+1."""
    cells = [(r, cc) for cc in range(c + 1, r + lam[r])]
    cells += [(rr, c) for rr in range(r + 1, len(lam)) if rr <= c < rr + lam[rr]]
    if c + 1 < len(lam):
        cells += [(c + 1, cc) for cc in range(c + 1, c + 1 + lam[c + 1])]
    return cells


def test_shifted_hook_walk_lands_on_each_corner_with_the_removal_probability():
    # exact rational absorption probabilities of the walk the kernel runs, against g(lambda - e_r) / g(lambda)
    checked = 0
    for m in range(1, 15):
        for lam in _strict_partitions(m):
            cells = [(r, c) for r, part in enumerate(lam) for c in range(r, r + part)]

            @lru_cache(None)
            def absorb(cell, lam=lam):
                hook = _shifted_hook(lam, *cell)
                if not hook:
                    return {cell: Fraction(1)}
                out = Counter()
                for h in hook:
                    for corner, p in absorb(h).items():
                        out[corner] += p / len(hook)
                return out

            landing = Counter()
            for cell in cells:
                for corner, p in absorb(cell).items():
                    landing[corner] += p / len(cells)
            for (r, _), p in landing.items():
                shorter = list(lam)
                shorter[r] -= 1
                assert p == Fraction(_count(tuple(shorter)), _count(lam))
                checked += 1
    assert checked == 212  # every corner of every strict partition of size <= 14


def test_hook_walk_tableaux_are_standard():
    from forcenet.numeric.triangle.hook_walk import hook_walk_tableaux

    n = 30
    T = hook_walk_tableaux(np.random.default_rng(1), n, 3)
    d = n * (n + 1) // 2
    for t in T:
        cells = t[1:, 1:]
        upper = np.triu(np.ones((n, n), dtype=bool))
        assert sorted(cells[upper].tolist()) == list(range(1, d + 1))
        rows_increase = np.diff(cells, axis=1)[upper[:, 1:] & upper[:, :-1]]
        cols_increase = np.diff(cells, axis=0)[upper[1:] & upper[:-1]]
        assert (rows_increase > 0).all() and (cols_increase > 0).all()


@pytest.mark.parametrize("kernel", ["compiled", "python"])
def test_both_exact_kernels_agree_with_the_exact_table(kernel):
    from forcenet.exact import mean_W
    from forcenet.numeric.agreement import compare_means
    from forcenet.numeric.triangle.exact_sampler import ExactSampler

    N = 9
    mean, stderr = ExactSampler(N, seed=5, kernel=kernel).mean_W(6000)
    mask = np.tril(np.ones((N, N), dtype=bool))
    mask[0, 0] = False
    exact = np.array([[float(x) for x in row] + [0.0] * (N - len(row)) for row in mean_W(N)])
    result = compare_means(mean[mask], stderr[mask], exact[mask])
    assert result.max_z < 5 and result.passed


def test_compiled_exact_stream_does_not_depend_on_batching():
    from forcenet.numeric.triangle.exact_sampler import ExactSampler

    a = ExactSampler(7, seed=3).sample_W(10)
    s = ExactSampler(7, seed=3)
    b = np.concatenate([s.sample_W(4), s.sample_W(6)])
    assert np.array_equal(a, b)
    m1 = ExactSampler(7, seed=4).moments(50, (1, 2))
    W = ExactSampler(7, seed=4).sample_W(50)
    assert np.allclose(m1[1][0], W.mean(axis=0), rtol=0, atol=1e-14)
    assert np.allclose(m1[2][0], (W**2).mean(axis=0), rtol=0, atol=1e-14)


def test_thinned_records_are_every_thin_th_state():
    from forcenet.numeric.packing import PackingMetropolis, Scene
    from forcenet.numeric.triangle.metropolis import TriangleMetropolis

    for kernel in ("python", "compiled"):
        full = TriangleMetropolis(6, seed=1, kernel=kernel).run(12)
        thin = TriangleMetropolis(6, seed=1, kernel=kernel).run(4, thin=3)
        assert np.array_equal(full[2::3], thin)
        scene = Scene(N=5, P=9, F=10.0, pv=1.0, ph=1.0)
        full = PackingMetropolis(scene, seed=2, kernel=kernel).run(12)
        thin = PackingMetropolis(scene, seed=2, kernel=kernel).run(4, thin=3)
        assert np.array_equal(full[2::3], thin)


# ------------------------------------------------------------------ the slice move


def test_slice_move_matches_the_exact_gravity_scene():
    from forcenet.exact.packing.mobilized import mean_W_mobilized
    from forcenet.numeric.autocorr import mean_and_stderr
    from forcenet.numeric.packing import PackingMetropolis, Scene

    scene = Scene(N=3, P=4, F=10, j0=2, mg=1)
    exact = np.array(mean_W_mobilized(3, 4, F=10, j0=2, mg=1), dtype=float)
    sampler = PackingMetropolis(scene, seed=2006, move="slice")
    mean, err, _ = mean_and_stderr(sampler.run(sweeps=8000, burn_in=200))
    free = err > 0
    assert np.abs((mean - exact)[free] / err[free]).max() < 5
    assert sampler.acceptance_rate == 1.0 and sampler.evaluations >= sampler.attempted


def test_slice_move_matches_rejection_on_the_isotropic_scene():
    import math

    from forcenet.numeric.autocorr import mean_and_stderr
    from forcenet.numeric.packing import PackingMetropolis, Scene
    from forcenet.numeric.packing.networks import uniform_networks
    from forcenet.numeric.packing.scene import forces_from_q, lateral_forces

    scene = Scene(N=3, P=3, F=1, pv=1, ph=1)
    W, _ = uniform_networks(scene, 20000, np.random.default_rng(7))
    ref, ref_err = W.mean(axis=0), W.std(axis=0, ddof=1) / math.sqrt(len(W))
    sampler = PackingMetropolis(scene, seed=11, move="slice")
    mean, err, _ = mean_and_stderr(sampler.run(sweeps=20000, burn_in=300))
    sigma = np.hypot(err, ref_err)
    free = sigma > 0
    assert np.abs((mean - ref)[free] / sigma[free]).max() < 5
    assert lateral_forces(sampler.q, sampler.W, scene).min() >= -1e-9  # every force stays repulsive
    assert np.allclose(forces_from_q(sampler.q, scene), sampler.W, rtol=0, atol=1e-12)


def test_slice_move_arguments():
    from forcenet.numeric.packing import PackingMetropolis, Scene

    scene = Scene(N=3, P=3, F=1, pv=1, ph=1)
    with pytest.raises(ValueError, match="move"):
        PackingMetropolis(scene, move="gibbs")
    with pytest.raises(ValueError, match="slice"):
        PackingMetropolis(scene, move="slice", kernel="python")


def test_triangle_slice_move_matches_the_exact_table():
    from forcenet.exact import mean_W
    from forcenet.numeric.autocorr import mean_and_stderr
    from forcenet.numeric.triangle.metropolis import TriangleMetropolis

    N = 7
    exact = np.array([[float(x) for x in row] + [0.0] * (N - len(row)) for row in mean_W(N)])
    sampler = TriangleMetropolis(N, seed=8, move="slice")
    mean, err, tau = mean_and_stderr(sampler.run(20000, burn_in=500))
    free = err > 0
    assert np.abs((mean - exact)[free] / err[free]).max() < 5
    assert np.allclose(mean[~free], exact[~free])
    assert sampler.accepted == sampler.attempted  # every move changes q (with probability 1)


def test_triangle_slice_move_with_side_pressure_agrees_with_metropolis():
    from forcenet.numeric.autocorr import mean_and_stderr
    from forcenet.numeric.triangle.metropolis import TriangleMetropolis, forces_from_q, lateral_forces

    out = {}
    for move in ("metropolis", "slice"):
        sampler = TriangleMetropolis(6, seed=3, ph=0.3, move=move)  # starts from the zero-density state
        out[move] = mean_and_stderr(sampler.run(30000, burn_in=1000))[:2]
        assert (lateral_forces(sampler.q, sampler.W, 0.3) >= -1e-12).all()
        assert np.allclose(forces_from_q(sampler.q), sampler.W, rtol=0, atol=1e-12)
    (m1, e1), (m2, e2) = out.values()
    sigma = np.hypot(e1, e2)
    free = sigma > 0
    assert np.abs((m1 - m2)[free] / sigma[free]).max() < 5
