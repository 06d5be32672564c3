"""The edge of the lattice directions: the ``N^(-2/3)`` correction of ``<W_(i,1)>`` and its fluctuations.

Given the floor (layer ``N``), the partial sums of the layers above form a
uniform continuous Gelfand-Tsetlin pattern, the eigenvalues of the corners of
``U diag(floor) U*`` (``notes/scaling_limit.md`` Sec. 5); ``W_(i,1) = S_(i,1)``
is the lowest eigenvalue of the corner of size ``i - 1``.  Its density vanishes
like a square root at the end ``e(z)`` of the level curves, a soft edge, where
the lowest eigenvalue fluctuates on the scale ``sigma_N = c(z) N^(-2/3)`` by the
Tracy-Widom GUE law ``chi``:

    <W_(i,1)> = e(z) + |E chi| c(z) N^(-2/3) + O(1/N),
    sd(W_(i,1)) = sd(chi) c(z) N^(-2/3) (1 + o(1)),
    c(z) = (1 - z)^(4/3) / (2^(4/3) (z (2 - z))^(1/6)).

``E chi`` and ``Var chi`` are computed here from Bornemann's quadrature of the
Fredholm determinant ``F_2(s) = det(I - K_Airy)`` on ``L^2(s, infinity)``
(python-flint ball arithmetic, precision a parameter; the quadrature sizes grow
with the digits asked for, checked in ``tests/test_edge.py``).

Examples
--------
>>> mpmath.nstr(edge_amplitude("0.5", dps=15), 15)
'0.292628294213845'
>>> EDGE_EXPONENT
Fraction(2, 3)
"""

from __future__ import annotations

import functools
from fractions import Fraction

import flint
import mpmath

from forcenet.core.errors import ArgumentError
from forcenet.core.precision import GUARD, RealLike, guarded, to_mpf
from forcenet.core.validation import check_dps

__all__ = [
    "EDGE_EXPONENT",
    "tracy_widom_moments",
    "edge_scale",
    "edge_amplitude",
    "edge_sd_amplitude",
    "bulk_edge_coefficient",
]

EDGE_EXPONENT = Fraction(2, 3)  # <W_(i,1)> - e(z) ~ N^(-2/3): the Airy scale of a square-root edge


def _gauss_legendre(n: int) -> tuple[list, list]:
    """Gauss-Legendre nodes and weights on ``[-1, 1]`` at the working precision of flint."""
    pairs = [flint.arb.legendre_p_root(n, k, weight=True) for k in range(n)]
    return [x for x, _ in pairs], [w for _, w in pairs]


def _fredholm_f2(s: flint.arb, nodes: list[flint.arb], weights: list[flint.arb], upper: flint.arb) -> flint.arb:
    """``F_2(s) = det(I - K_Airy)`` on ``(s, upper)`` by Gauss-Legendre (Bornemann 2010), as an arb."""
    half, mid = (upper - s) / 2, (upper + s) / 2
    x = [half * t + mid for t in nodes]
    root_w = [(half * w).sqrt() for w in weights]
    airy = [xi.airy()[:2] for xi in x]  # (Ai, Ai')
    m = len(x)
    rows = []
    for i in range(m):
        ai, di = airy[i]
        row = []
        for j in range(m):
            aj, dj = airy[j]
            kernel = di * di - x[i] * ai * ai if i == j else (ai * dj - di * aj) / (x[i] - x[j])
            row.append((1 if i == j else 0) - root_w[i] * kernel * root_w[j])
        rows.append(row)
    return flint.arb_mat(rows).det()


def _quadrature_sizes(dps: int) -> tuple[int, int]:
    """Nodes of the kernel and of each of the four panels of the ``s`` integral for ``dps`` digits."""
    return 2 * dps + 10, dps + 5


@functools.lru_cache(maxsize=8)
def _tw_moments(dps: int) -> tuple[str, str]:
    """Mean and variance of Tracy-Widom GUE as decimal strings of ``dps + GUARD`` digits (cached per ``dps``)."""
    kernel_nodes, panel_nodes = _quadrature_sizes(dps)
    with flint.ctx.workdps(dps + GUARD):
        arb = flint.arb
        tail = arb(10).log() * (dps + GUARD)
        upper = (arb(3) / 4 * tail) ** (arb(2) / 3)  # 1 - F_2(s) and Ai(s)^2 ~ exp(-4 s^(3/2) / 3)
        lower = -((12 * tail) ** (arb(1) / 3))  # F_2(s) ~ exp(-|s|^3 / 12)
        nodes, weights = _gauss_legendre(kernel_nodes)
        panel_x, panel_w = _gauss_legendre(panel_nodes)
        first, second = arb(0), arb(0)
        for lo, hi in ((lower, lower / 2), (lower / 2, arb(0)), (arb(0), upper / 2), (upper / 2, upper)):
            for t, w in zip(panel_x, panel_w):
                s, weight = (hi - lo) / 2 * t + (lo + hi) / 2, (hi - lo) / 2 * w
                f = _fredholm_f2(s, nodes, weights, upper + 1 if s > upper - 1 else upper)
                # E chi = int_0^inf (1 - F) - int_-inf^0 F;  E chi^2 = int 2 s (1 - F) (s > 0) + int 2 |s| F (s < 0)
                if s < 0:
                    first -= weight * f
                    second -= 2 * s * weight * f
                else:
                    first += weight * (1 - f)
                    second += 2 * s * weight * (1 - f)
        variance = second - first * first
        digits = dps + GUARD
        return first.mid().str(digits, radius=False), variance.mid().str(digits, radius=False)


def tracy_widom_moments(dps: int = 20) -> tuple[mpmath.mpf, mpmath.mpf]:
    """Mean ``E chi`` and variance ``Var chi`` of the Tracy-Widom GUE law ``F_2`` (Tracy and Widom 1994).

    ``F_2(s) = det(I - K_Airy)`` on ``L^2(s, infinity)`` is evaluated by
    Gauss-Legendre quadrature of the Fredholm determinant (Bornemann 2010) in
    python-flint ball arithmetic, and ``E chi = int_0^inf (1 - F_2) - int_-inf^0 F_2``,
    ``E chi^2 = int 2 |s| P(chi on the far side of s) ds`` by Gauss-Legendre on four
    panels.  The quadrature sizes grow linearly with ``dps``; results are cached per ``dps``.

    Parameters
    ----------
    dps : int
        Decimal digits of the results, ``5..60`` (60 digits: minutes).

    Returns
    -------
    (mpmath.mpf, mpmath.mpf)
        ``E chi`` (about -1.7711) and ``Var chi`` (about 0.8132), rounded to ``dps`` digits.

    Raises
    ------
    ArgumentError
        If ``dps`` is outside ``5..60``.

    Examples
    --------
    >>> mean, var = tracy_widom_moments(15)
    >>> mpmath.nstr(mean, 15), mpmath.nstr(var, 15)
    ('-1.7710868074116', '0.813194792832958')
    """
    return _rounded_moments(check_dps(dps, maximum=60))


def _rounded_moments(dps: int) -> tuple[mpmath.mpf, mpmath.mpf]:
    """:func:`tracy_widom_moments` for a ``dps`` checked by the caller (the edge amplitudes ask 2 digits more
    than their own ``dps``, up to 62)."""
    mean, variance = _tw_moments(dps)
    with mpmath.workdps(dps):
        return +mpmath.mpf(mean), +mpmath.mpf(variance)


def _open_depth(z: RealLike) -> mpmath.mpf:
    depth = to_mpf(z, "z")
    if not 0 < depth < 1:
        raise ArgumentError(f"z={mpmath.nstr(depth, 15)} is out of range: the edge law needs 0 < z < 1 "
                            "(z = 1 is the floor's hard edge, W_(N,1) ~ Beta(1, d))")
    return depth


def _scale(depth: mpmath.mpf) -> mpmath.mpf:
    """``c(z) = (1 - z)^(4/3) / (2^(4/3) (z (2 - z))^(1/6))`` at the working precision."""
    third = mpmath.mpf(1) / 3
    return (1 - depth) ** (4 * third) / (2 ** (4 * third) * (depth * (2 - depth)) ** (third / 2))


def edge_scale(z: RealLike, dps: int = 20) -> mpmath.mpf:
    """``c(z)``: the edge scale of layer ``i = zN`` is ``sigma_N = c(z) N^(-2/3)`` (the lattice directions, Sec. 4.8).

    ``c = A^(-2/3)``, where layer ``zN`` holds ``(N A / pi) sqrt(s - e) ds`` partial
    sums just above its lowest one, ``A = 4 (z (2 - z))^(1/4) / (1 - z)^2``
    (:func:`forcenet.exact.limit_shape.closed_forms.edge_density_coefficient`).

    Parameters
    ----------
    z : int, float, str, Fraction or mpmath.mpf
        Depth ``z = i/N``, ``0 < z < 1``.
    dps : int
        Decimal digits of the result, ``5..10000``.

    Returns
    -------
    mpmath.mpf

    Raises
    ------
    ArgumentError
        If ``z`` is outside ``(0, 1)``, or ``dps`` outside ``5..10000``.

    Examples
    --------
    >>> mpmath.nstr(edge_scale("0.5", dps=20), 20)  # 2^(2/3) 3^(5/6) / 24
    '0.16522526902084117853'
    """
    dps = check_dps(dps)
    return guarded(lambda: _scale(_open_depth(z)), dps)


def edge_amplitude(z: RealLike, dps: int = 20) -> mpmath.mpf:
    """``|E chi| c(z)``: ``<W_(i,1)> = <W_(i,i)> = e(z) + edge_amplitude(z) N^(-2/3) + o(N^(-2/3))`` (Sec. 4.8, Fig. 3.5).

    ``e(z) = (1 - sqrt(z (2 - z)))/2`` is :func:`~forcenet.numeric.limit_shape.surface.lattice_response`;
    ``chi`` is Tracy-Widom GUE (:func:`tracy_widom_moments`), ``c`` is :func:`edge_scale`.  Derived given steps
    that are argued, not proved (notes/scaling_limit.md Sec. 5.4: the edge theorem for a random floor, the
    convergence of the moments, the remainder, argued ``O(1/N)``); the exact columns to N = 160 confirm it.

    Parameters
    ----------
    z : int, float, str, Fraction or mpmath.mpf
        Depth ``z = i/N``, ``0 < z < 1``.
    dps : int
        Decimal digits of the result, ``5..60``.

    Returns
    -------
    mpmath.mpf

    Raises
    ------
    ArgumentError
        If ``z`` is outside ``(0, 1)``, or ``dps`` outside ``5..60``.

    Examples
    --------
    >>> mpmath.nstr(edge_amplitude("0.25", dps=12), 12)
    '0.549690876488'
    """
    dps = check_dps(dps, maximum=60)
    mean, _ = _rounded_moments(dps + 2)
    return guarded(lambda: -mean * _scale(_open_depth(z)), dps)


def edge_sd_amplitude(z: RealLike, dps: int = 20) -> mpmath.mpf:
    """``sd(chi) c(z)``: ``sd(W_(i,1)) = edge_sd_amplitude(z) N^(-2/3) (1 + o(1))`` (Sec. 4.8).

    The relative correction is argued to be ``O(N^(-1/3))`` (notes/scaling_limit.md Sec. 5.4), not proved.

    Parameters
    ----------
    z : int, float, str, Fraction or mpmath.mpf
        Depth ``z = i/N``, ``0 < z < 1``.
    dps : int
        Decimal digits of the result, ``5..60``.

    Returns
    -------
    mpmath.mpf

    Raises
    ------
    ArgumentError
        If ``z`` is outside ``(0, 1)``, or ``dps`` outside ``5..60``.

    Examples
    --------
    >>> mpmath.nstr(edge_sd_amplitude("0.5", dps=12), 11)
    '0.14899570936'
    """
    dps = check_dps(dps, maximum=60)
    _, variance = _rounded_moments(dps + 2)
    return guarded(lambda: mpmath.sqrt(variance) * _scale(_open_depth(z)), dps)


def bulk_edge_coefficient(z: RealLike, dps: int = 20) -> mpmath.mpf:
    """``C(z)`` of ``G(x, z) ~ C(z) (z - |x|)^(-1/3)``, the bulk response near the lattice directions (Sec. 4.8).

    ``C = 2 pi q (6 pi r q)^(-1/3)``, ``q = (1 - z)^2 / 4``, ``r = sqrt(z (2 - z))``
    (derived in ``notes/scaling_limit.md`` Sec. 1).

    Parameters
    ----------
    z : int, float, str, Fraction or mpmath.mpf
        Depth ``z = i/N``, ``0 < z < 1``.
    dps : int
        Decimal digits of the result, ``5..10000``.

    Returns
    -------
    mpmath.mpf

    Raises
    ------
    ArgumentError
        If ``z`` is outside ``(0, 1)``, or ``dps`` outside ``5..10000``.

    Examples
    --------
    >>> mpmath.nstr(bulk_edge_coefficient("0.5", dps=15), 15)  # (sqrt(3) pi^2 / 288)^(1/3)
    '0.390082045840335'
    """
    dps = check_dps(dps)

    def compute() -> mpmath.mpf:
        depth = _open_depth(z)
        q, r = (1 - depth) ** 2 / 4, mpmath.sqrt(depth * (2 - depth))
        return 2 * mpmath.pi * q / mpmath.cbrt(6 * mpmath.pi * r * q)

    return guarded(compute, dps)
