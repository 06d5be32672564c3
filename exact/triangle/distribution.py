"""Exact force distributions of the fully mobilized triangle: densities, CDFs, pooled P(f).

Every force that is a difference of two comparable partial sums is a spacing
``U_(t) - U_(s)`` of ``d = N(N-1)/2`` sorted uniforms, Beta(``g``,
``d + 1 - g``) given the tableau with ``g`` the rank gap (:mod:`.gaps`).  So
its density on ``[0, 1]`` is the Bernstein polynomial of degree ``d - 1``

    p(w) = sum_g P(gap = g) w^(g-1) (1-w)^(d-g) / B(g, d+1-g)
         = d sum_{k=0}^{d-1} P(gap = k+1) C(d-1, k) w^k (1-w)^(d-1-k),

and, since ``I_w(g, d+1-g) = P(Binomial(d, w) >= g)``, its distribution function
the Bernstein polynomial of degree ``d`` whose coefficients are the
distribution function of the gap,

    P(W <= w) = sum_{k=0}^{d} P(gap <= k) C(d, k) w^k (1-w)^(d-k).

The forces covered: the vertical loads ``W_{i,j}`` (:func:`density`,
:func:`cdf`), the inter-layer contacts ``F1, F2, F5, F6`` in units of
``2/sqrt3`` (:func:`contact_density`), pooled ``P(f)`` with ``f`` the force
over the mean force of its layer (:func:`layer_force_density`,
:func:`triangle_force_density`, :func:`contact_layer_force_density`), and
``q_{i,j}`` (:func:`q_density`).  Everything is a sympy ``Poly`` over ``QQ``
(exact rationals) or a list of :class:`Piece`; floating-point evaluation is in
:mod:`forcenet.numeric.triangle.force_distribution`.  Derivation and physics:
``notes/force_distribution.md``.

Examples
--------
>>> density(4, (4, 2))
Poly(-15*w**5 + 30*w**4 - 30*w**2 + 15*w, w, domain='QQ')
>>> cdf(3, (3, 2))
Poly(-2*w**3 + 3*w**2, w, domain='QQ')

References
----------
S. Ostojic, PhD thesis (2006), Eqs. (3.2)-(3.4), (3.8), (4.5)-(4.9); the
thesis's ``P(f)``: Figs. 2.4, 3.8, 7.3.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from fractions import Fraction
from math import comb

import sympy

from forcenet.core.errors import ArgumentError
from forcenet.core.plan import Plan
from forcenet.core.validation import available_memory, check_grain, check_int, check_layers

from .gap_counts import GapCounts, moment_from_gaps, pool_gaps
from .gaps import chain_pass, contact_gap_counts, contact_gap_law, gap_laws_cost
from .joint_gaps import q_gap_counts
from .moments import mean_W_grain
from .pieces import Piece, as_pieces, bernstein_to_monomial, bin_probabilities, piecewise_cdf, sum_pieces
from .spacings import rising

__all__ = [
    "W_SYMBOL",
    "F_SYMBOL",
    "density_from_gaps",
    "cdf_from_gaps",
    "moment_from_gaps",
    "density",
    "cdf",
    "contact_density",
    "contact_cdf",
    "pool_gaps",
    "grain_pieces",
    "layer_pieces",
    "layer_pieces_from_gaps",
    "Piece",
    "layer_force_density",
    "triangle_force_density",
    "contact_layer_force_density",
    "bin_probabilities",
    "piecewise_cdf",
    "as_pieces",
    "grain_scaled_pool_density",
    "beta_mixture_density",
    "q_density",
    "poly_strings",
    "distribution_plan",
    "Q_SYMBOL",
]

W_SYMBOL = sympy.Symbol("w")
F_SYMBOL = sympy.Symbol("f")
Q_SYMBOL = sympy.Symbol("q")


def _poly(coeffs: Sequence[Fraction | int], var: sympy.Symbol) -> sympy.Poly:
    """``sum coeffs[m] var^m`` (Fractions or ints) as a Poly over QQ."""
    return sympy.Poly.from_list([sympy.Rational(x.numerator, x.denominator) for x in reversed(coeffs)], var, domain="QQ")


# ------------------------------------------------------------------ one spacing


def _check_density_gaps(gaps: GapCounts) -> None:
    if gaps.counts[0] or gaps.counts[gaps.d + 1]:
        raise ArgumentError("the gap law has mass at g = 0 or g = d + 1 (a force identically 0 or 1, "
                         "e.g. W_{1,1} = 1): it has no density")


def density_from_gaps(gaps: GapCounts, var: sympy.Symbol = W_SYMBOL) -> sympy.Poly:
    """Exact density ``sum_g P(g) Beta(g, d+1-g)``, a polynomial of degree ``<= d - 1`` on ``[0, 1]``.

    The Bernstein coefficients are ``d P(gap = k + 1)``, ``k = 0..d-1``.

    Examples
    --------
    >>> density_from_gaps(GapCounts((0, 1, 0, 0), 1, 2))  # U_(1) of two uniforms
    Poly(-2*w + 2, w, domain='QQ')
    """
    _check_density_gaps(gaps)
    d, c = gaps.d, gaps.counts
    # integer coefficients of w^m, times total / d: Bernstein weights c[k+1] C(d-1, k), k = 0..d-1
    coeffs = bernstein_to_monomial([c[k + 1] * comb(d - 1, k) for k in range(d)])
    return _poly([Fraction(d * x, gaps.total) for x in coeffs], var)


def cdf_from_gaps(gaps: GapCounts, var: sympy.Symbol = W_SYMBOL) -> sympy.Poly:
    """Exact ``P(X <= w)`` on ``[0, 1]``: the Bernstein coefficients are ``P(gap <= k)``.

    ``I_w(g, d+1-g) = P(Binomial(d, w) >= g)``; summing over ``g`` gives
    ``sum_k P(gap <= k) C(d, k) w^k (1-w)^(d-k)``.

    Examples
    --------
    >>> cdf_from_gaps(GapCounts((0, 1, 0, 0), 1, 2))
    Poly(-w**2 + 2*w, w, domain='QQ')
    """
    _check_density_gaps(gaps)
    d, c = gaps.d, gaps.counts
    coeffs, G = [], 0
    for k in range(d + 1):  # Bernstein weights P(gap <= k) C(d, k), times total
        G += c[k]
        coeffs.append(G * comb(d, k))
    return _poly([Fraction(x, gaps.total) for x in bernstein_to_monomial(coeffs)], var)


def _load_gaps(N: int, grain: tuple[int, int], progress: Callable[[int], object] | None = None) -> GapCounts:
    N = check_layers(N)
    i, j = check_grain(N, grain)
    if i == 1:
        raise ArgumentError(f"grain={grain!r}: W_{{1,1}} = 1 is the overload, it has no density; "
                         f"i must be an integer in 2..{N}")
    plan = distribution_plan(N, "grain", available_memory())
    if not plan.runnable:  # the pass over the 2^(N-1) order ideals cannot run here: refused before the work
        raise ArgumentError(f"density(N={N}): {plan.refusal}; a lattice-direction load (i, 1) or (i, i) to N = 128, "
                            "and every floor load, by Pfaffians: forcenet dist --N N --grain i,j "
                            "(N = 64: ~1-2 min)")
    return chain_pass("layer", N, i, progress)[j - 1]


def density(N: int, grain: tuple[int, int], var: sympy.Symbol = W_SYMBOL, progress: Callable[[int], object] | None = None) -> sympy.Poly:
    """Exact density of ``W_{i,j}`` on ``[0, 1]`` (layers ``i >= 2``), degree ``<= d - 1``.

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.
    grain : (int, int)
        ``(i, j)``, ``2 <= i <= N``, ``1 <= j <= i``.
    var : sympy.Symbol, optional
        The variable of the polynomial (``w``).
    progress : callable, optional
        Called once per level of the ideal lattice if the pass over the ideals runs.

    Returns
    -------
    sympy.Poly
        The density, exact rational coefficients.

    Raises
    ------
    ArgumentError
        If ``N`` or the grain is out of range (``i = 1``: the overload has no density).

    Examples
    --------
    >>> density(3, (3, 2))
    Poly(-6*w**2 + 6*w, w, domain='QQ')
    """
    return density_from_gaps(_load_gaps(N, grain, progress), var)


def cdf(N: int, grain: tuple[int, int], var: sympy.Symbol = W_SYMBOL, progress: Callable[[int], object] | None = None) -> sympy.Poly:
    """Exact ``P(W_{i,j} <= w)`` on ``[0, 1]`` (layers ``i >= 2``).

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.
    grain : (int, int)
        ``(i, j)``, ``2 <= i <= N``, ``1 <= j <= i``.
    var : sympy.Symbol, optional
        The variable of the polynomial (``w``).
    progress : callable, optional
        Called once per level of the ideal lattice if the pass over the ideals runs.

    Returns
    -------
    sympy.Poly
        The distribution function on ``[0, 1]``.

    Raises
    ------
    ArgumentError
        If ``N`` or the grain is out of range (``i = 1``: the overload has no density).

    Examples
    --------
    >>> cdf(3, (3, 2))
    Poly(-2*w**3 + 3*w**2, w, domain='QQ')
    """
    return cdf_from_gaps(_load_gaps(N, grain, progress), var)


def contact_density(N: int, grain: tuple[int, int], kind: str, var: sympy.Symbol = W_SYMBOL,
                    progress: Callable[[int], object] | None = None) -> sympy.Poly:
    """Exact density of ``x = (sqrt3/2) F`` for the contact ``kind`` in F1, F2, F5, F6 of ``grain``.

    ``F5 = (2/sqrt3) q W``, ``F6 = (2/sqrt3)(1-q) W`` (3.8) are spacings of
    neighbouring cells (:func:`forcenet.exact.triangle.gaps.contact_spacing`);
    the density of ``F`` itself is ``(sqrt3/2) p(sqrt3 F / 2)``.

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.
    grain : (int, int)
        ``(i, j)``, ``1 <= i <= N``, ``1 <= j <= i``.
    kind : {"F1", "F2", "F5", "F6"}
        The contact force.
    var : sympy.Symbol, optional
        The variable of the polynomial (``w``, standing for ``x``).
    progress : callable, optional
        Called once per level of the ideal lattice if the pass over the ideals runs.

    Returns
    -------
    sympy.Poly
        The density of ``x`` on ``[0, 1]``.

    Raises
    ------
    ArgumentError
        If ``N`` or the grain is out of range, or the contact is not random there
        (:func:`forcenet.exact.triangle.gaps.contact_spacing`).

    Examples
    --------
    >>> contact_density(3, (2, 1), "F5")  # S_{3,1} = U_(1) of three uniforms
    Poly(3*w**2 - 6*w + 3, w, domain='QQ')
    """
    return density_from_gaps(contact_gap_law(N, grain, kind, progress), var)


def contact_cdf(N: int, grain: tuple[int, int], kind: str, var: sympy.Symbol = W_SYMBOL,
                progress: Callable[[int], object] | None = None) -> sympy.Poly:
    """Exact ``P((sqrt3/2) F <= x)`` for the contact ``kind`` of ``grain``.

    Examples
    --------
    >>> contact_cdf(3, (2, 1), "F6")
    Poly(w**3 - 3*w**2 + 3*w, w, domain='QQ')
    """
    return cdf_from_gaps(contact_gap_law(N, grain, kind, progress), var)


# ------------------------------------------------------------------ pooled P(f)


def _scaled(p: sympy.Poly, scale: Fraction, var: sympy.Symbol) -> sympy.Poly:
    """The density of ``f = X / scale``: ``scale * p(scale * f)`` (coefficients ``c_m scale^(m+1)``)."""
    coeffs = [Fraction(int(c.p), int(c.q)) for c in reversed(p.all_coeffs())]
    return _poly([c * scale ** (m + 1) for m, c in enumerate(coeffs)], var)


def layer_force_density(N: int, i: int, var: sympy.Symbol = F_SYMBOL, progress: Callable[[int], object] | None = None) -> sympy.Poly:
    """Exact ``P_i(f)`` of ``f = i W_{i,j}`` pooled over the grains of layer ``i``.

    Every layer carries the unit overload, so the mean of its ``i`` loads is
    ``1/i`` in *every* configuration and ``f`` is the force over the mean force
    of its layer, as in the thesis's ``P(f)``, ``f = F / <F>``.  Supported on
    ``[0, i]``, ``int P = int f P = 1``.

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.
    i : int
        The layer, ``2 <= i <= N``.
    var : sympy.Symbol, optional
        The variable of the polynomial (``f``).
    progress : callable, optional
        Called once per level of the ideal lattice if the pass over the ideals runs.

    Returns
    -------
    sympy.Poly
        The density of ``f`` on ``[0, i]``.

    Raises
    ------
    ArgumentError
        If ``N`` or ``i`` is out of range.

    Examples
    --------
    >>> layer_force_density(3, 3)
    Poly(-2/9*f + 2/3, f, domain='QQ')
    """
    N = check_layers(N)
    return _layer_force_density(N, check_int(i, "i", 2, N), var, progress)


def _layer_force_density(N: int, i: int, var: sympy.Symbol, progress: Callable[[int], object] | None
                         ) -> sympy.Poly:
    """:func:`layer_force_density` for ``N`` and ``i`` already checked."""
    p = density_from_gaps(pool_gaps(chain_pass("layer", N, i, progress)), var)
    return _scaled(p, Fraction(1, i), var)


def triangle_force_density(N: int, var: sympy.Symbol = F_SYMBOL, layers: Iterable[int] | None = None,
                           progress: Callable[[int], object] | None = None) -> list[Piece]:
    """Exact ensemble ``P(f)`` pooled over every grain of layers ``2..N``, ``f = i W_{i,j}``.

    Each grain has weight ``1 / (number of grains)``; each load is divided by
    its layer's mean ``1/i`` (layer 1 is the overload ``W = 1`` and is left
    out).  Piecewise polynomial with breaks at the integers (layer ``i`` lives
    on ``[0, i]``); ``layers`` restricts the pool.  ``N - 1`` passes over the ideals.

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.
    var : sympy.Symbol, optional
        The variable of the polynomials (``f``).
    layers : iterable of int, optional
        The layers pooled, each in ``2..N`` (default all).
    progress : callable, optional
        Called once per level of the ideal lattice for every pass that runs.

    Returns
    -------
    list of Piece
        The density on ``[0, N]``, one polynomial between consecutive integers that are layer ends.

    Raises
    ------
    ArgumentError
        If ``N`` or a layer is out of range, or ``layers`` is empty.

    Examples
    --------
    >>> [(p.lo, p.hi, p.poly.as_expr()) for p in triangle_force_density(3)]
    [(0, 2, -3*f**2/10 + 7*f/15 + 2/5), (2, 3, 2/5 - 2*f/15)]
    """
    N = check_layers(N)
    layers = list(range(2, N + 1)) if layers is None else sorted({check_int(i, "layer", 2, N) for i in layers})
    if not layers:
        raise ArgumentError("layers: need at least one layer in 2..N")
    grains = sum(layers)
    terms = [(sympy.Integer(i), _layer_force_density(N, i, var, progress) * sympy.Rational(i, grains)) for i in layers]
    return sum_pieces(terms, var)


def contact_layer_force_density(N: int, i: int, var: sympy.Symbol = F_SYMBOL,
                                progress: Callable[[int], object] | None = None) -> sympy.Poly:
    """Exact ``P(f)`` of the ``2i`` contacts between layers ``i`` and ``i + 1`` (F5, F6 of layer ``i``).

    They carry ``(2/sqrt3) sum_j W_{i,j} = 2/sqrt3`` in every configuration,
    mean ``1/(sqrt3 i)``, so ``f = F/<F> = 2 i x`` with ``x = (sqrt3/2) F`` the
    spacing; supported on ``[0, 2i]``.  Uses the ``N - 1`` row passes
    (:func:`forcenet.exact.triangle.gaps.contact_gap_counts`).

    Examples
    --------
    >>> contact_layer_force_density(3, 2)  # four Beta(1, 3) spacings, f = 4 x
    Poly(3/64*f**2 - 3/8*f + 3/4, f, domain='QQ')
    """
    N = check_layers(N)
    i = check_int(i, "i", 1, N - 1)
    laws = contact_gap_counts(N, progress=progress)
    pool = pool_gaps([laws[(i, j, kind)] for j in range(1, i + 1) for kind in ("F5", "F6")])
    return _scaled(density_from_gaps(pool, var), Fraction(1, 2 * i), var)


def grain_scaled_pool_density(N: int, grains: Iterable[tuple[int, int]], var: sympy.Symbol = F_SYMBOL) -> list[Piece]:
    """Exact density of ``f = W_{i,j} / <W_{i,j}>`` for a uniformly chosen grain of ``grains``.

    The alternative normalization: each grain by its own ensemble mean.
    Piecewise polynomial with breaks at ``1/<W_{i,j}>``.

    Examples
    --------
    >>> [(p.lo, p.hi) for p in grain_scaled_pool_density(3, [(3, 1), (3, 2)])]
    [(0, 2), (2, 4)]
    """
    N = check_layers(N)
    grains = [check_grain(N, g) for g in grains]
    if not grains:
        raise ArgumentError("grains: need at least one grain")
    terms = []
    for i, j in grains:
        mu = mean_W_grain(N, i, j)
        poly = _scaled(density_from_gaps(_load_gaps(N, (i, j)), var), mu, var) * sympy.Rational(1, len(grains))
        terms.append((sympy.Rational(mu.denominator, mu.numerator), poly))
    return sum_pieces(terms, var)


# ------------------------------------------------------------------ q = F5 / (F5 + F6)


def beta_mixture_density(counts: Sequence[Sequence[int]], total: int, var: sympy.Symbol = Q_SYMBOL) -> sympy.Poly:
    """``sum_{a,b} counts[a][b] / total * Beta(a, b)`` as an exact polynomial.

    Examples
    --------
    >>> beta_mixture_density([[0, 0, 0], [0, 0, 1], [0, 1, 0]], 2)  # (Beta(1,2) + Beta(2,1)) / 2
    Poly(1, q, domain='QQ')
    """
    top = max((a + b for a, row in enumerate(counts) for b, c in enumerate(row) if c), default=2)
    coeffs = [Fraction(0)] * (top - 1)
    for a, row in enumerate(counts):
        for b, c in enumerate(row):
            if not c:
                continue
            if a < 1 or b < 1:
                raise ArgumentError("beta_mixture_density: both gaps must be >= 1")
            norm = Fraction(c * rising(1, a + b - 1), total * rising(1, a - 1) * rising(1, b - 1))  # 1/B(a, b)
            for t in range(b):  # q^(a-1) (1-q)^(b-1)
                coeffs[a - 1 + t] += norm * comb(b - 1, t) * (-1) ** t
    return _poly(coeffs, var)


def q_density(N: int, grain: tuple[int, int], var: sympy.Symbol = Q_SYMBOL) -> sympy.Poly:
    """Exact density of ``q_{i,j}`` (3.8) on ``[0, 1]``: ``sum P(g5, g6) Beta(g5, g6)``.

    Examples
    --------
    >>> q_density(4, (3, 2))  # above the floor q is exactly uniform
    Poly(1, q, domain='QQ')
    >>> q_density(5, (3, 2))
    Poly(-2*q**2 + 2*q + 2/3, q, domain='QQ')
    """
    counts, total = q_gap_counts(N, grain)
    return beta_mixture_density(counts, total, var)


def grain_pieces(gaps: GapCounts, var: sympy.Symbol = W_SYMBOL) -> tuple[list[Piece], list[Piece]]:
    """The density and the CDF of a gap law (a grain's ``W_ij`` or a contact's spacing) as pieces on ``[0, 1]``.

    Parameters
    ----------
    gaps : GapCounts
        The gap law (:func:`forcenet.exact.triangle.gaps.grain_gap_counts`, ``contact_gap_law``).
    var : sympy.Symbol, optional
        The variable of the polynomials (``w``).

    Returns
    -------
    density, cdf : list of Piece
        One piece each, on ``[0, 1]`` (:func:`density_from_gaps`, :func:`cdf_from_gaps`).

    Raises
    ------
    ArgumentError
        If the law has no density (an atom at a gap).

    Examples
    --------
    >>> from forcenet.exact.triangle.gaps import grain_gap_counts
    >>> p, F = grain_pieces(grain_gap_counts(3, (3, 2)))
    >>> p[0].lo, p[0].hi, p[0].poly.as_expr(), F[0].poly.as_expr()
    (0, 1, -6*w**2 + 6*w, -2*w**3 + 3*w**2)
    """
    return as_pieces(density_from_gaps(gaps, var), (0, 1)), as_pieces(cdf_from_gaps(gaps, var), (0, 1))


def layer_pieces(N: int, i: int, var: sympy.Symbol = F_SYMBOL,
                 progress: Callable[[int], object] | None = None) -> tuple[list[Piece], list[Piece]]:
    """The density and the CDF of layer ``i``'s ``P_i(f)`` (:func:`layer_force_density`) as pieces on ``[0, i]``.

    Parameters
    ----------
    N, i : int
        Number of layers ``N >= 2`` and the layer, ``2 <= i <= N``.
    var : sympy.Symbol, optional
        The variable of the polynomials (``f``).
    progress : callable, optional
        Called once per level of the ideal lattice if the pass over the ideals runs.

    Returns
    -------
    density, cdf : list of Piece
        One piece each, on ``[0, i]``; the CDF is :func:`piecewise_cdf` of the density.

    Raises
    ------
    ArgumentError
        If ``N`` or ``i`` is out of range.

    Examples
    --------
    >>> p, F = layer_pieces(3, 3)
    >>> p[0].hi, F[0].poly.as_expr()
    (3, -f**2/9 + 2*f/3)
    """
    return layer_pieces_from_gaps(pool_gaps(chain_pass("layer", check_layers(N), check_int(i, "i", 2, N), progress)), i, var)


def layer_pieces_from_gaps(gaps: GapCounts, i: int, var: sympy.Symbol = F_SYMBOL) -> tuple[list[Piece], list[Piece]]:
    """Layer ``i``'s ``P_i(f)``, ``f = i W``, and its CDF from the layer's pooled gap law, whatever route gave it.

    Examples
    --------
    >>> from forcenet.exact.triangle.gaps import layer_gap_counts
    >>> p, F = layer_pieces_from_gaps(pool_gaps(layer_gap_counts(3, 3)), 3)
    >>> p[0].poly.as_expr()
    2/3 - 2*f/9
    """
    pieces = as_pieces(_scaled(density_from_gaps(gaps, var), Fraction(1, check_int(i, "i", 2)), var), (0, i))
    return pieces, piecewise_cdf(pieces)


# ------------------------------------------------------------------ output and cost


def poly_strings(poly: sympy.Poly) -> list[str]:
    """Coefficients of ``poly`` from the constant term up, as ``"p/q"`` strings.

    Examples
    --------
    >>> poly_strings(density(3, (3, 2)))
    ['0', '6', '-6']
    """
    return [str(c) for c in reversed(poly.all_coeffs())]


def distribution_plan(N: int, kind: str = "grain", memory_bytes: int | None = None) -> Plan:
    """The cost of one density (``kind="grain"``, ``"contact"``, ``"layer"``) or of the
    ensemble ``P(f)`` (``"ensemble"``: ``N - 1`` layer passes) or every grain
    (``"all"``: the same passes) or every contact (``"contacts"``: ``N - 1`` row passes).

    Examples
    --------
    >>> distribution_plan(12, "all").seconds < 5
    True
    >>> distribution_plan(20, "ensemble").seconds > 60
    True
    """
    N = check_layers(N)
    passes = {"grain": 1, "contact": 1, "layer": 1, "ensemble": N - 1, "all": N - 1, "contacts": N - 1}
    if kind not in passes:
        raise ArgumentError(f"kind={kind!r}: must be one of {', '.join(passes)}")
    what = {"grain": f"exact density N={N}", "contact": f"exact contact density N={N}",
            "layer": f"exact layer P(f) N={N}", "ensemble": f"exact ensemble P(f) N={N}",
            "all": f"exact densities of every grain N={N}", "contacts": f"exact contact densities N={N}"}[kind]
    return gap_laws_cost(N, passes[kind], memory_bytes, what=f"{what} ({passes[kind]} pass{'es' if passes[kind] > 1 else ''})")
