"""Layer-by-layer nested-matrix integration (thesis Secs. 4.3-4.5), exactly.

The thesis integrates the uniform measure over the W's layer by layer from
the bottom, and finds that after each layer the remaining integrand is a
matrix product ``L t(W_{m,1}) t(W_{m,2}) ... t(W_{m,m}) R`` over the grains of
the current layer ``m`` (Eqs. 4.4, 4.27), whose matrix indices are nested
tuples (Fig. 4.1b).  This module implements that recursion directly.

One integration step (layer ``m`` -> ``m-1``): write ``X_k = W_{m,k}``,
``Y_k = W_{m-1,k}``, ``u_k = b_{m,k} - X_k``.  By (4.9)-(4.11),
``b_k - a_k = Y_k``, ``a_k = u_{k-1}`` (``a_1 = 0``) and ``X_m = u_{m-1}``.
Sweeping ``k = m-1, ..., 1`` and integrating ``X_k`` with the central
integral (4.14),

    int_{a}^{b} x^s (b - x)^e dx = sum_f gamma^{f}_{s,e} (b - a)^{e + 1 + s - f} a^f,
    gamma^{f}_{s,e} = s! e! / ((e + s - f + 1)! f!),

turns each matrix entry ``x^s`` of site ``k`` into entries ``Y_k^{e+1+s-f}``
of a new matrix whose column index is the pair (old column, ``e``) and whose
row index is (old row, ``f``): the nesting of indices of Eqs. (4.28)-(4.30).
The last site gives the new right vector (4.31)/(4.45), ``a_1 = 0`` the new
left vector (4.44).  At the top ``W_{1,1} = 1`` and ``J_1 = L t(1) R`` is the
normalization (4.46).

Moments and correlations multiply the matrix of a grain by ``x^s`` before its
layer is integrated: the thesis's defects of type I and II (4.57)-(4.61),
(4.80)-(4.85) are what this does to the recursion.

Everything is exact.  Two engines run the same recursion: the literal one
(``arithmetic="fraction"``: nested-tuple indices, :class:`fractions.Fraction`
values) and the default one (``arithmetic="modular"``: bonds renumbered as
integers, every entry a monomial stored as flat numpy arrays, coefficients
modulo word-size primes, the integer ``(d + s)! I`` rebuilt by the Chinese
remainder theorem).  The bond dimension grows like the number of index tuples
(4.32): 1, 2, 7, 37, 268, 2496, 28612, ... (N = 9: 6-43 s and under 2 GB
per integration).

Examples
--------
>>> normalization_nested(4)
Fraction(1, 360)
>>> moment_nested(5, {(5, 1): 1})
Fraction(1, 11)
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Sequence
from fractions import Fraction
from functools import lru_cache
from math import factorial
from typing import Any

import numpy as np

from forcenet.core.errors import ArgumentError, ArgumentTypeError
from forcenet.core.validation import check_grain, check_int, check_layers

from ..modular import crt, primes_for_bound
from ..protocol import Progress
from ..triangle.staircase import dimension
from .coefficients import gamma, gamma_residues

__all__ = ["check_powers", "multiply_site", "integrate_layer", "prune_layer", "integrate_layers", "normalization_nested", "moment_nested", "moment_table_nested", "mean_W_nested"]


def multiply_site(site: dict, power: int) -> dict:
    """Multiply every entry of a site matrix by ``x**power``."""
    return {key: {p + power: c for p, c in poly.items()} for key, poly in site.items()}


def integrate_layer(left: dict, sites: list, right: dict) -> tuple[dict, list, dict]:
    """Integrate one layer: ``(L, [T_1..T_m], R)`` -> ``(L', [T'_1..T'_{m-1}], R')``."""
    m = len(sites)
    # new right vector: X_m = u_{m-1}, so site m's powers become exponents of u
    new_right: defaultdict[tuple, Fraction] = defaultdict(Fraction)
    for (row, col), poly in sites[m - 1].items():
        if col in right:
            for power, c in poly.items():
                new_right[(row, power)] += c * right[col]
    # exponents e of u_k that reach site k from the right: the rows' powers of site k+1
    reach: list[defaultdict[Any, set]] = [defaultdict(set) for _ in range(m)]
    for (row, power) in new_right:
        reach[m - 1][row].add(power)
    new_sites: list[dict] = [{} for _ in range(m - 1)]
    for k in range(m - 2, -1, -1):  # site k+1 (1-based) integrated; sweep right to left
        exps = reach[k + 1]
        table: defaultdict[tuple, defaultdict[int, Fraction]] = defaultdict(lambda: defaultdict(Fraction))
        for (row, col), poly in sites[k].items():
            for e in exps.get(col, ()):
                for s, c in poly.items():
                    for f in range(s + 1):  # a_k^f with a_k = u_{k-1}; Y_k^{e+1+s-f}
                        table[((row, f), (col, e))][e + 1 + s - f] += c * gamma(f, s, e)
        new_sites[k] = {key: dict(poly) for key, poly in table.items()}
        for (row, f), _col in new_sites[k]:
            reach[k][row].add(f)
    new_left = {(row, 0): c for row, c in left.items()}  # a_1 = 0: only f = 0 survives
    return new_left, new_sites, dict(new_right)


def prune_layer(left: dict, sites: list, right: dict) -> tuple[dict, list, dict]:
    """Drop matrix entries no path from ``L`` to ``R`` uses (exact: they never contribute)."""
    m = len(sites)
    alive = set(left)
    forward = []
    for site in sites:  # column bonds reachable from the left vector
        forward.append(alive)
        alive = {col for (row, col) in site if row in alive}
    alive = set(right)
    kept: list[dict] = [{} for _ in range(m)]
    for k in range(m - 1, -1, -1):  # keep entries on a path left -> right
        kept[k] = {key: poly for key, poly in sites[k].items() if key[0] in forward[k] and key[1] in alive}
        alive = {row for (row, col) in kept[k]}
    left = {row: c for row, c in left.items() if row in alive}
    return left, kept, right


def check_powers(N: int, powers: dict | None) -> dict:
    """Validated ``{grain: power}`` without zero powers."""
    if powers is None:
        return {}
    if not isinstance(powers, dict):
        raise ArgumentTypeError(f"powers={powers!r}: need a dict {{(i, j): power}}")
    out: dict[tuple[int, int], int] = {}
    for g, e in powers.items():
        i, j = check_grain(N, g, "powers key")
        e = check_int(e, f"powers[{(i, j)}]", 0)
        if e:
            out[(i, j)] = out.get((i, j), 0) + int(e)
    return out


def integrate_layers(N: int, powers: dict | None = None, arithmetic: str = "modular") -> Fraction:
    """``int prod dW  prod_{(i,j)} W_{i,j}^{powers[(i,j)]}`` over the ensemble (unnormalized).

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.
    powers : dict, optional
        ``{(i, j): s}``: the power of each grain's force in the integrand.
    arithmetic : {"modular", "fraction"}
        ``"modular"`` (default): integer-indexed bonds and residues modulo
        word-size primes, reconstructed exactly (N = 9 in 6-48 s and under
        2 GB per integration).  ``"fraction"``: the recursion written literally with
        nested-tuple indices and :class:`~fractions.Fraction` values (the
        baseline; N = 9 takes ~6 min and 19 GB).

    Returns
    -------
    Fraction
        The integral (4.1) with the given powers; ``powers=None`` gives the
        normalization (4.46).

    Raises
    ------
    ArgumentError
        If ``N`` is not an integer ``>= 2``, a key of ``powers`` is not a grain,
        a power is negative, or ``arithmetic`` is neither value.

    Examples
    --------
    >>> integrate_layers(3)
    Fraction(1, 6)
    >>> integrate_layers(4, {(4, 2): 1}, arithmetic="fraction")
    Fraction(1, 1008)
    """
    N = check_layers(N)
    powers = check_powers(N, powers)
    if arithmetic == "modular":
        return _integrate_modular(N, powers)
    if arithmetic != "fraction":
        raise ArgumentError(f"arithmetic={arithmetic!r}: must be 'modular' or 'fraction'")
    one = {0: Fraction(1)}
    left, right = {(): Fraction(1)}, {(): Fraction(1)}
    sites = [{((), ()): dict(one)} for _ in range(N)]  # the bottom layer's integrand is 1
    for m in range(N, 1, -1):
        sites = [multiply_site(site, powers.get((m, k), 0)) for k, site in enumerate(sites, start=1)]
        left, sites, right = prune_layer(*integrate_layer(left, sites, right))
    # layer 1: W_{1,1} = 1 (a power of W_{1,1} changes nothing)
    total = Fraction(0)
    for (row, col), poly in sites[0].items():
        if row in left and col in right:
            total += left[row] * sum(poly.values()) * right[col]
    return total


def normalization_nested(N: int, arithmetic: str = "modular") -> Fraction:
    """The normalization (4.46)/(4.51) by nested-matrix integration.

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.
    arithmetic : {"modular", "fraction"}
        See :func:`integrate_layers`.

    Returns
    -------
    Fraction
        Equal to :func:`forcenet.exact.normalization`.

    Examples
    --------
    >>> normalization_nested(5)
    Fraction(1, 302400)
    """
    return integrate_layers(N, arithmetic=arithmetic)


def moment_nested(N: int, powers: dict, arithmetic: str = "modular") -> Fraction:
    """``< prod W_{i,j}^{e_{ij}} >`` by nested-matrix integration (Secs. 4.4-4.5).

    A single grain with power ``s`` is ``<W^s>`` with the s-th order defects
    (4.80)-(4.85); two grains give a correlation (Sec. 4.5.2).

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.
    powers : dict
        ``{(i, j): e}``: the power of each grain's force.
    arithmetic : {"modular", "fraction"}
        See :func:`integrate_layers`.

    Returns
    -------
    Fraction

    Examples
    --------
    >>> moment_nested(4, {(4, 2): 2})
    Fraction(9, 56)
    >>> moment_nested(4, {(4, 1): 1, (4, 4): 1})
    Fraction(1, 56)
    """
    return integrate_layers(N, powers, arithmetic) / integrate_layers(N, arithmetic=arithmetic)


def moment_table_nested(
    N: int, s: int = 1, arithmetic: str = "modular", progress: Progress | None = None, volume: Fraction | None = None
) -> list[list[Fraction]]:
    """The whole table ``<W_{i,j}^s>`` by nested-matrix integration (4.63), (4.80)-(4.85).

    One integration for the normalization and one per grain, with ``x^s``
    inserted at the grain (the s-th order defects).  Modular arithmetic at
    N = 9: ~12 min for ``s = 1`` (under 2 GB per integration); the bottom-row
    grains grow fastest with ``s`` (grain (9, 3): 36 s and 1.9 GB for
    ``s = 1``, 287 s and 12.4 GB for ``s = 3``).

    Parameters
    ----------
    N : int
        Number of layers.
    s : int
        The power, ``s >= 1``.
    arithmetic : {"modular", "fraction"}
        See :func:`integrate_layers`.
    progress : callable, optional
        Called with no argument after each grain.
    volume : Fraction, optional
        The normalization, if already integrated (tables for several ``s``).

    Returns
    -------
    list of lists of Fraction
        Row ``i - 1`` holds ``<W_{i,1}^s>, ..., <W_{i,i}^s>``.

    Raises
    ------
    ArgumentError
        If ``N`` or ``s`` is out of range, or ``arithmetic`` is neither value.

    Examples
    --------
    >>> [str(x) for x in moment_table_nested(4, 2)[-1]]
    ['1/28', '9/56', '9/56', '1/28']
    """
    N = check_layers(N)
    s = check_int(s, "s", 1)
    if volume is None:
        volume = integrate_layers(N, arithmetic=arithmetic)
    table = []
    for i in range(1, N + 1):
        row = []
        for j in range(1, i + 1):
            row.append(integrate_layers(N, {(i, j): s}, arithmetic) / volume)
            if progress is not None:
                progress()
        table.append(row)
    return table


def mean_W_nested(N: int, arithmetic: str = "modular", progress: Progress | None = None) -> list[list[Fraction]]:
    """The whole table ``<W_{i,j}>`` (4.63)-(4.77) by nested-matrix integration.

    :func:`moment_table_nested` with ``s = 1``: N = 8 takes ~5 s and N = 9
    ~12 min (46 integrations, under 2 GB each).

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.
    arithmetic : {"modular", "fraction"}
        See :func:`integrate_layers`.
    progress : callable, optional
        Called with no argument after each grain.

    Returns
    -------
    list of lists of Fraction
        ``table[i-1][j-1] = <W_{i,j}>``.

    Examples
    --------
    >>> mean_W_nested(3)
    [[Fraction(1, 1)], [Fraction(1, 2), Fraction(1, 2)], [Fraction(1, 4), Fraction(1, 2), Fraction(1, 4)]]
    """
    return moment_table_nested(N, 1, arithmetic, progress)


# ---------------------------------------------------------------------------
# The same recursion with integer-indexed bonds and multi-modular values.
#
# Every matrix entry is a monomial ``c Y^power`` (4.28), so a site is four flat
# arrays: row bond, column bond, power and the coefficient ``c`` modulo a few
# primes below 2**31.  Bonds are numbered 0..D-1 after every layer; the nested
# index pairs of (4.29)-(4.30) are built as (old bond, exponent) keys and
# renumbered.  The result is exact: ``(d + s)! I`` is an integer in
# ``[0, (d + s)!]`` (notes/chapter4.md, "Integrality"), recovered by the
# Chinese remainder theorem from enough primes.
# ---------------------------------------------------------------------------

class _Site:
    """One site matrix: entry ``t`` is ``val[t] Y^pw[t]`` at (``row[t]``, ``col[t]``)."""

    __slots__ = ("row", "col", "pw", "val")

    def __init__(self, row: np.ndarray, col: np.ndarray, pw: np.ndarray, val: np.ndarray) -> None:
        self.row, self.col, self.pw, self.val = row, col, pw, val


class _GammaTable:
    """``gamma^f_{s,e}`` of (4.15) modulo each prime, tabulated for ``s, e, f < size``."""

    def __init__(self, primes: Sequence[int]) -> None:
        self.primes = np.array(primes, dtype=np.int64)
        self.size = 0
        self._grow(16)

    def _grow(self, size: int) -> None:
        table = gamma_residues(size, self.primes.tolist())
        self.table, self.size = table.reshape(size**3, len(self.primes)), size

    def __call__(self, s: np.ndarray, e: np.ndarray, f: np.ndarray) -> np.ndarray:
        """``s! e! / ((e + s - f + 1)! f!)`` mod each prime, shape ``(len(s), n_primes)``."""
        top = max(int(s.max(initial=0)), int(e.max(initial=0))) + 1
        if top > self.size:
            self._grow(max(top, 2 * self.size))
        n = self.size
        return self.table[(s * n + e) * n + f]


@lru_cache(maxsize=4)
def _gamma_table(primes: tuple) -> _GammaTable:
    """One table per set of primes, shared by the integrations of a table."""
    return _GammaTable(primes)


def _expand(counts: Any) -> tuple[np.ndarray, np.ndarray]:
    """For groups of sizes ``counts``: (group of each item, rank of the item in its group)."""
    counts = np.asarray(counts, dtype=np.int64)
    owner = np.repeat(np.arange(len(counts), dtype=np.int64), counts)
    starts = np.cumsum(counts) - counts
    rank = np.arange(len(owner), dtype=np.int64) - starts[owner]
    return owner, rank


def _group_sum(keys: np.ndarray, vals: np.ndarray, primes: np.ndarray) -> tuple[Any, Any]:
    """Sum ``vals`` (mod primes) over equal ``keys``: (sorted unique keys, sums)."""
    order = np.argsort(keys, kind="stable")
    keys, vals = keys[order], vals[order]
    if len(keys) == 0:
        return keys, vals
    first = np.flatnonzero(np.r_[True, keys[1:] != keys[:-1]])
    return keys[first], np.add.reduceat(vals, first, axis=0) % primes  # each term < 2**31


def _integrate_site(site: _Site, bond_old: np.ndarray, bond_exp: np.ndarray, gamma: _GammaTable, lo: int = 0,
                    hi: int | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Integrate ``X_k`` in the entries ``lo:hi`` of one site against the exponents on its column bond (4.14).

    The column bond of the new site is given as the sorted pairs (old column
    bond ``bond_old``, exponent ``bond_exp`` of ``u_k``); an entry ``x^s`` at
    (row, col) meets every exponent ``e`` carried on ``col`` and gives, for
    ``f = 0..s``, ``gamma^f_{s,e} Y^{e+1+s-f}`` at row (row, ``f``) and column
    (col, ``e``).  Returns (row, f, new column, power, coefficient).
    """
    primes = gamma.primes
    row, col, pw, val = site.row[lo:hi], site.col[lo:hi], site.pw[lo:hi], site.val[lo:hi]
    start = np.searchsorted(bond_old, col, "left")
    count = np.searchsorted(bond_old, col, "right") - start
    owner, rank = _expand(count)  # each entry meets every exponent e carried on its column
    new_col = start[owner] + rank
    e = bond_exp[new_col]
    s = pw[owner]
    owner2, f = _expand(s + 1)  # a_k^f, f = 0..s
    src = owner[owner2]
    new_col, e, s = new_col[owner2], e[owner2], s[owner2]
    return row[src], f, new_col, e + 1 + s - f, val[src] * gamma(s, e, f) % primes


_ABSORB_CHUNK = 1 << 22  # integrated entries per chunk (~0.5 GB of temporaries with 5 primes)


def _absorb_last_site(site: _Site, right: tuple[np.ndarray, np.ndarray, np.ndarray], gamma: _GammaTable,
                      power: int) -> tuple[Any, Any]:
    """Integrate the last site of a layer straight into the next right vector.

    The last force of a layer is ``X_m = u_{m-1}`` (4.20)-(4.21), so the last
    site only ever enters through ``R'[(row, power)] = sum_col t[row, col] R[col]``
    (4.31)/(4.45).  Done in chunks of about ``_ABSORB_CHUNK`` integrated entries, the
    largest site (10^8 entries for a bottom-row grain at N = 9) is never
    stored.  ``power`` is the moment inserted at that last grain.
    Returns the new row bond as sorted (old row, ``f``) pairs and the right
    vector as sorted (bond, exponent, coefficient) arrays.
    """
    primes = gamma.primes
    bond_old, bond_exp, right_val = right
    width = int(site.pw.max(initial=0)) + 1  # f <= s < width
    top = int(bond_exp.max(initial=0)) + width + power + 1  # exponents e + 1 + s - f + power < top
    start = np.searchsorted(bond_old, site.col, "left")
    count = np.searchsorted(bond_old, site.col, "right") - start
    sizes = np.cumsum(count * (site.pw + 1))
    keys, sums = [np.zeros(0, dtype=np.int64)], [np.zeros((0, len(primes)), dtype=np.int64)]
    lo = 0
    while lo < len(site.row):
        hi = int(np.searchsorted(sizes, (sizes[lo - 1] if lo else 0) + _ABSORB_CHUNK, "right"))
        hi = max(hi, lo + 1)
        row, f, col, pw, val = _integrate_site(site, bond_old, bond_exp, gamma, lo, hi)
        k, v = _group_sum((row * width + f) * top + pw + power, val * right_val[col] % primes, primes)
        keys.append(k)
        sums.append(v)
        lo = hi
    keys, sums = _group_sum(np.concatenate(keys), np.concatenate(sums), primes)
    rows, exps = keys // top, keys % top
    row_keys, bond = np.unique(rows, return_inverse=True)
    return (row_keys // width, row_keys % width), (bond.astype(np.int64), exps, sums)


def _integrate_layer_mod(left: tuple[np.ndarray, np.ndarray], sites: list[_Site], right: Any, gamma: _GammaTable,
                         last_power: int) -> tuple[Any, list[_Site], Any]:
    """Integrate one layer, modular version of :func:`integrate_layer` (same recursion).

    ``sites`` are the sites ``1..m-1`` of layer ``m``; the last site is already
    part of ``right``, given as sorted (bond, exponent of ``u_{m-1}``,
    coefficient) arrays.  ``last_power`` is the moment at grain
    ``(m-1, m-1)``.  Returns the same kind of state for layer ``m - 1``.
    """
    m = len(sites) + 1
    (bond_old, bond_exp), new_right = _absorb_last_site(sites[m - 2], right, gamma, last_power)
    new_sites: list[Any] = [None] * (m - 2)
    for k in range(m - 3, -1, -1):  # integrate X_k, sweeping right to left (4.14)
        row, f, col, pw, val = _integrate_site(sites[k], bond_old, bond_exp, gamma)
        width = int(f.max(initial=0)) + 1
        keys, new_row = np.unique(row * width + f, return_inverse=True)
        new_sites[k] = _Site(new_row.astype(np.int64), col, pw, val)
        bond_old, bond_exp = keys // width, keys % width
    # a_1 = 0 keeps only f = 0 in the new left vector (4.44)
    left_ids, left_val = left
    pos = np.minimum(np.searchsorted(left_ids, bond_old), len(left_ids) - 1)
    keep = (bond_exp == 0) & (left_ids[pos] == bond_old)
    new_left = (np.flatnonzero(keep), left_val[pos[keep]])
    return _prune_mod(new_left, new_sites, new_right)


def _prune_mod(left: tuple[np.ndarray, np.ndarray], sites: list[Any], right: Any) -> tuple[Any, list[_Site], Any]:
    """Keep the entries on a path from ``L`` to ``R`` and renumber the bonds 0..D-1.

    Built right to left, every column already leads to ``R``; one forward sweep
    removes what ``L`` cannot reach.  Renumbering is monotone, so sorted
    arrays stay sorted.
    """
    left_ids, left_val = left
    renumber = np.full(int(left_ids.max(initial=-1)) + 1, -1, dtype=np.int64)
    renumber[left_ids] = np.arange(len(left_ids))
    new_left = (renumber[left_ids], left_val)
    kept = []
    for site in sites:
        table = np.full(max(len(renumber), int(site.row.max(initial=-1)) + 1), -1, dtype=np.int64)
        table[: len(renumber)] = renumber
        keep = table[site.row] >= 0
        row, col, pw, val = table[site.row[keep]], site.col[keep], site.pw[keep], site.val[keep]
        alive = np.unique(col)
        renumber = np.full(int(alive.max(initial=-1)) + 1, -1, dtype=np.int64)
        renumber[alive] = np.arange(len(alive))
        kept.append(_Site(row, renumber[col], pw, val))
    bond, exps, vals = right
    table = np.full(max(len(renumber), int(bond.max(initial=-1)) + 1), -1, dtype=np.int64)
    table[: len(renumber)] = renumber
    keep = table[bond] >= 0
    return new_left, kept, (table[bond[keep]], exps[keep], vals[keep])


def _integral_residues(N: int, powers: dict, primes: Sequence[int]) -> np.ndarray:
    """``int prod W^powers`` modulo each prime (the layer recursion in modular arithmetic)."""
    gamma = _gamma_table(tuple(primes))
    P = len(primes)
    one = np.ones((1, P), dtype=np.int64)
    zero = np.zeros(1, dtype=np.int64)
    # layer N: the integrand is 1; the last grain (N, N) is already in the right vector
    left = (zero.copy(), one.copy())
    right = (zero.copy(), np.array([powers.get((N, N), 0)], dtype=np.int64), one.copy())
    sites = [_Site(zero.copy(), zero.copy(), zero.copy(), one.copy()) for _ in range(N - 1)]
    for m in range(N, 1, -1):
        for k, site in enumerate(sites, start=1):
            if powers.get((m, k)):
                site.pw = site.pw + powers[(m, k)]
        left, sites, right = _integrate_layer_mod(left, sites, right, gamma, powers.get((m - 1, m - 1), 0))
    # layer 1: W_{1,1} = 1, so every exponent counts alike; L' keeps f = 0 (done above)
    left_ids, left_val = left
    bond, _, vals = right
    lv = np.zeros((int(max(left_ids.max(initial=0), bond.max(initial=0))) + 1, P), dtype=np.int64)
    lv[left_ids] = left_val
    p = gamma.primes
    return (lv[bond] * vals % p).sum(axis=0) % p


def _integrate_modular(N: int, powers: dict) -> Fraction:
    """The layer recursion in modular arithmetic, reconstructed exactly.

    ``(d + s)! I`` is an integer between 0 and ``(d + s)!`` (``d = N(N-1)/2``,
    ``s`` the total power; notes/chapter4.md, "Integrality"), so its residues
    modulo primes whose product exceeds ``(d + s)!`` determine it (:func:`~forcenet.exact.modular.primes_for_bound`).
    """
    powers = {g: e for g, e in powers.items() if g != (1, 1)}  # W_{1,1} = 1
    d = dimension(N)
    scale = factorial(d + sum(powers.values()))
    primes = primes_for_bound(scale)
    residues = _integral_residues(N, powers, primes)
    scaled = crt([int(r) * scale % p for r, p in zip(residues.tolist(), primes)], primes)
    return Fraction(scaled, scale)
