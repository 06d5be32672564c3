"""The force network ensemble's polytope: balance ``A f = b``, ``f >= 0`` (and the friction cone), Sec. 2.3.

For a contact network (:mod:`.model`) the unknowns ``z`` are the contact
forces: one normal force per contact, plus a tangential force per contact
with friction.  Mechanical balance of every grain is linear, ``A z = b``
(thesis Eq. (2.9) and Sec. 2.3.1: two force equations per grain in two
dimensions, a torque equation with friction), and the admissible networks
satisfy ``G z >= 0``: ``f_c >= 0`` (repulsive contacts), with friction
``mu f_c - t_c >= 0`` and ``mu f_c + t_c >= 0`` (Coulomb, Sec. 5.1).  The
ensemble is the uniform measure on this polytope (Sec. 2.3.2), written in
coordinates of ``Ker A``: ``z = z0 + K x`` with ``x`` free, ``d = dim Ker A``.

Refusals, each one line and before any work (:func:`check_polytope`, by
linear programming on floats): loads not balanced (no contact with a wall and
a non-zero net force; or no solution of ``A z = b`` at all, with its
residual), infeasible (no compressive network, e.g. tensile loads), unbounded
(a self-stress ``A y = 0``, ``y >= 0``: the forces can grow without bound).

The exact side (:func:`exact_polytope`): rows and contacts scaled so that the
data become rational (the hexagonal lattice's ``sqrt(3)`` in this way: a
contact's force is measured in a unit that absorbs the irrational factor, which
changes the uniform measure by a constant only), then ``Ker A`` exactly by
Gauss-Jordan elimination over the rationals (python-flint).

Examples
--------
>>> from forcenet.exact.contact_network.model import contact_network
>>> net = contact_network(1, [[0, None, "-1/2", "-sqrt(3)/2"], [0, None, "1/2", "-sqrt(3)/2"],
...                           [0, None, 0, -1]], [[0, 0, -1]])
>>> poly = exact_polytope(net)
>>> poly.dimension, poly.scale
(1, (2*sqrt(3)/3, 2*sqrt(3)/3, 1))
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import numpy as np
import sympy
from flint import fmpq, fmpq_mat
from scipy import optimize, sparse

from forcenet.core.errors import ArgumentError

from .model import ContactNetwork

__all__ = ["Balance", "balance", "float_system", "check_polytope", "ExactPolytope", "exact_polytope",
           "TOLERANCE", "IrrationalDataError"]

TOLERANCE = 1e-9  # relative: what the linear programs call zero


@dataclass(frozen=True)
class Balance:
    """``A z = b``, ``G z >= 0`` as sparse triplets in the network's numbers (exact or float).

    Attributes
    ----------
    rows, variables : int
        Equations (2 per grain, 3 with friction) and unknowns (1 per contact, 2 with friction).
    A : tuple of (int, int, number)
        Nonzero entries ``(row, variable, value)``.
    b : tuple of number
        Right-hand side: minus the external loads.
    G : tuple of (int, int, number)
        The inequalities' entries ``(inequality, variable, value)``.
    inequalities : int
        How many rows ``G`` has.
    labels : tuple of str
        What each variable is (``f3`` the normal force of contact 3, ``t3`` its tangential force).
    """

    rows: int
    variables: int
    A: tuple[tuple[int, int, Any], ...]
    b: tuple[Any, ...]
    G: tuple[tuple[int, int, Any], ...]
    inequalities: int
    labels: tuple[str, ...]


def balance(net: ContactNetwork) -> Balance:
    """The balance equations and the admissible cone of ``net`` (Sec. 2.3.1; friction Sec. 5.1).

    A compressive normal force ``f`` on contact ``(i, j, n)`` pushes ``j`` by ``+f n`` and ``i`` by ``-f n``; a
    tangential force ``t`` pushes ``j`` by ``+t s`` and ``i`` by ``-t s`` with ``s = (-ny, nx)``, and turns
    each grain by ``-r t`` (radius ``r``). Row ``3g`` (``2g`` without friction) is grain ``g``'s x balance.

    Examples
    --------
    >>> from forcenet.exact.contact_network.model import contact_network
    >>> bal = balance(contact_network(2, [[0, 1, 1, 0], [1, None, 1, 0]], [[0, 1, 0], [1, 0, 0]]))
    >>> bal.A, bal.b
    (((0, 0, -1), (2, 0, 1), (2, 1, -1)), (-1, 0, 0, 0))
    """
    friction = net.frictional
    per = 3 if friction else 2
    A: list[tuple[int, int, Any]] = []
    G: list[tuple[int, int, Any]] = []
    labels: list[str] = []
    for c, (i, j, nx, ny) in enumerate(net.contacts):
        f = len(labels)
        labels.append(f"f{c}")
        for grain, sign in ((i, -1), (j, 1)):
            if grain is None:
                continue
            for axis, value in ((0, nx), (1, ny)):
                if value != 0:
                    A.append((per * grain + axis, f, sign * value))
        if not friction:
            G.append((len(G), f, 1))
            continue
        t = len(labels)
        labels.append(f"t{c}")
        radii = net.radii or ()
        for grain, sign in ((i, -1), (j, 1)):
            if grain is None:
                continue
            for axis, value in ((0, -ny), (1, nx)):
                if value != 0:
                    A.append((per * grain + axis, t, sign * value))
            A.append((per * grain + 2, t, -radii[grain]))
        k = c * 2  # mu f - t >= 0 and mu f + t >= 0, Coulomb's cone
        G.extend([(k, f, net.friction), (k, t, -1), (k + 1, f, net.friction), (k + 1, t, 1)])
    b = []
    for fx, fy, torque in net.loads:
        b.extend([-fx, -fy] + ([-torque] if friction else []))
    inequalities = 2 * len(net.contacts) if friction else len(net.contacts)
    return Balance(per * net.grains, len(labels), tuple(A), tuple(b), tuple(G), inequalities, tuple(labels))


def float_system(bal: Balance) -> tuple[sparse.csr_matrix, np.ndarray, sparse.csr_matrix]:
    """``(A, b, G)`` as floats (scipy sparse matrices, a numpy vector).

    Examples
    --------
    >>> from forcenet.exact.contact_network.model import contact_network
    >>> A, b, G = float_system(balance(contact_network(1, [[0, None, 0, -1]], [[0, 0, -1]])))
    >>> A.toarray().tolist(), b.tolist()
    ([[0.0], [1.0]], [0.0, 1.0])
    """
    def matrix(entries: tuple[tuple[int, int, Any], ...], rows: int) -> sparse.csr_matrix:
        r = [e[0] for e in entries]
        c = [e[1] for e in entries]
        v = [float(e[2]) for e in entries]
        return sparse.csr_matrix((v, (r, c)), shape=(rows, bal.variables))

    return matrix(bal.A, bal.rows), np.array([float(x) for x in bal.b]), matrix(bal.G, bal.inequalities)


def _net_force_refusal(net: ContactNetwork) -> str | None:
    if any(c[1] is None for c in net.contacts):
        return None
    fx = sum((load[0] for load in net.loads), sympy.Integer(0))
    fy = sum((load[1] for load in net.loads), sympy.Integer(0))
    scale = max([1.0] + [abs(float(x)) for load in net.loads for x in load[:2]])
    if abs(float(fx)) > TOLERANCE * scale or abs(float(fy)) > TOLERANCE * scale or (
            net.exact and (sympy.simplify(fx) != 0 or sympy.simplify(fy) != 0)):
        return (f"the loads are not balanced: their net force is ({fx}, {fy}) and no contact with a wall can take "
                "it; add the walls' contacts or balance the loads")
    return None


def _linprog(cost: np.ndarray, **problem: Any) -> Any:
    """HiGHS's linear program; on its status 4 (numerical difficulties: its simplex on soft-disk packings of
    10^4 contacts, where the interior-point method succeeds) solved again by the interior-point method."""
    result = optimize.linprog(cost, method="highs", **problem)
    if result.status == 4:
        result = optimize.linprog(cost, method="highs-ipm", **problem)
    return result


def check_polytope(net: ContactNetwork, bal: Balance | None = None) -> tuple[np.ndarray, float]:
    """Refuse a network whose ensemble does not exist; else a strictly admissible network and its margin.

    Linear programs (HiGHS) decide, in this order: the loads can be balanced at all; a compressive network
    exists; no self-stress ``A y = 0``, ``G y >= 0``, ``y != 0`` (else the polytope is unbounded). The returned
    network maximizes the smallest slack ``min G z`` (capped at the loads' scale): an interior point where
    the margin is positive (a start for the sampler).

    Returns
    -------
    (numpy.ndarray, float)
        The network ``z`` and its margin ``min G z``.

    Raises
    ------
    ArgumentError
        One line naming the fault: not balanced (how much), infeasible, unbounded (which contacts).

    Examples
    --------
    >>> from forcenet.exact.contact_network.model import contact_network
    >>> check_polytope(contact_network(1, [[0, None, 0, 1]], [[0, 0, -1]]))
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: infeasible: no network of repulsive contact forces balances these loads (a load pulls a grain away from its contacts, i.e. a tensile load?); the sampler and the exact route need one
    """
    refusal = _net_force_refusal(net)
    if refusal:
        raise ArgumentError(refusal)
    bal = balance(net) if bal is None else bal
    A, b, G = float_system(bal)
    scale = max(1.0, float(np.abs(b).max(initial=0.0)))
    m = bal.variables
    # balance at all: least squares residual of A z = b
    solution = sparse.linalg.lsqr(A, b, atol=1e-14, btol=1e-14)[0] if A.nnz else np.zeros(m)
    residual = float(np.abs(A @ solution - b).max(initial=0.0))
    if residual > 1e-7 * scale:
        raise ArgumentError(f"the loads are not balanced: no contact forces at all (of either sign) balance them; "
                            f"the best leaves {residual:.3g} of force unbalanced on some grain")
    # maximin: max s subject to A z = b, G z - s >= 0, s <= scale
    cost = np.zeros(m + 1)
    cost[-1] = -1.0
    A_eq = sparse.hstack([A, sparse.csr_matrix((A.shape[0], 1))]).tocsr()
    A_ub = sparse.hstack([-G, np.ones((G.shape[0], 1))]).tocsr()
    bounds = [(None, None)] * m + [(None, scale)]
    result = _linprog(cost, A_ub=A_ub, b_ub=np.zeros(G.shape[0]), A_eq=A_eq, b_eq=b, bounds=bounds)
    if result.status == 2 or (result.status == 0 and -result.fun < -TOLERANCE * scale):
        if len(net.contacts) > 3 * net.grains // 2 and net.grains > 3:
            raise ArgumentError("infeasible: no network of repulsive contact forces balances these loads: this "
                                "contact network is not a packing in mechanical equilibrium under them (contacts of "
                                "random points, e.g. Delaunay's, are not one); relax the grains under the load first "
                                "(forcenet.numeric.contact_network.soft_disks.relaxed_packing) or take the contacts "
                                "from a simulation")
        raise ArgumentError("infeasible: no network of repulsive contact forces balances these loads (a load "
                            "pulls a grain away from its contacts, i.e. a tensile load?); the sampler and the "
                            "exact route need one")
    if result.status != 0:
        raise ArgumentError(f"the linear program on this network failed: {result.message}")
    z, margin = result.x[:m], float(-result.fun)
    # self-stress: max sum(G y) subject to A y = 0, 0 <= G y <= 1
    stress = _linprog(-np.asarray(G.sum(axis=0)).ravel(), A_ub=sparse.vstack([G, -G]).tocsr(),
                      b_ub=np.concatenate([np.ones(G.shape[0]), np.zeros(G.shape[0])]),
                      A_eq=A, b_eq=np.zeros(A.shape[0]), bounds=[(None, None)] * m)
    if stress.status == 0 and -stress.fun > 1e-7:
        y = stress.x
        loaded = [bal.labels[k] for k in range(m) if abs(y[k]) > 1e-7]
        named = ", ".join(loaded[:8]) + (", ..." if len(loaded) > 8 else "")
        raise ArgumentError(f"unbounded: the contacts {named} can carry a self-stress (forces balancing each "
                            "other with no load), so the forces can grow without bound and there is no uniform "
                            "ensemble; fix the scale with a wall's prescribed load instead of a wall contact, or "
                            "remove a contact")
    return z, margin


@dataclass(frozen=True)
class ExactPolytope:
    """The ensemble's polytope in exact kernel coordinates: ``z = scale * (z0 + K x)``, ``H x + h >= 0``.

    Attributes
    ----------
    scale : tuple of sympy numbers
        Each variable's unit (positive; 1 where the data were rational): ``z_k = scale_k z'_k``.
    z0 : tuple of Fraction
        A particular solution in the scaled variables ``z'`` (free coordinates zero).
    K : tuple of tuple of Fraction
        ``K[k]`` is row ``k`` of the kernel basis: ``z'_k = z0_k + K[k] . x``.
    H, h : tuples of Fraction
        The inequalities in ``x``: ``H[r] . x + h[r] >= 0``.
    free : tuple of int
        The variables that are the coordinates ``x`` (``x_i = z'_{free[i]}``).
    dimension : int
        ``dim Ker A`` (the polytope's dimension unless an inequality holds with equality everywhere).
    labels : tuple of str
        As in :class:`Balance`.
    """

    scale: tuple[Any, ...]
    z0: tuple[Fraction, ...]
    K: tuple[tuple[Fraction, ...], ...]
    H: tuple[tuple[Fraction, ...], ...]
    h: tuple[Fraction, ...]
    free: tuple[int, ...]
    dimension: int
    labels: tuple[str, ...]

    def network(self, x: Any) -> list[Any]:
        """The forces ``z`` (exact) at the coordinates ``x``.

        Examples
        --------
        >>> from forcenet.exact.contact_network.model import contact_network
        >>> poly = exact_polytope(contact_network(1, [[0, None, 0, -1]], [[0, 0, -1]]))
        >>> poly.dimension, poly.network([])
        (0, [1])
        """
        return [self.scale[k] * sympy.Rational(self.z0[k] + sum(a * xi for a, xi in zip(self.K[k], x)))
                for k in range(len(self.z0))]


def _as_fraction(value: Any) -> Fraction | None:
    """``value`` as a Fraction when it is rational (after rationalizing denominators), else None."""
    if not isinstance(value, sympy.Rational):
        value = sympy.nsimplify(sympy.radsimp(value))
    return Fraction(int(value.p), int(value.q)) if isinstance(value, sympy.Rational) else None


def _to_fraction(value: Any) -> Fraction:
    fraction = _as_fraction(value)
    if fraction is None:
        raise _irrational()
    return fraction


def _rational_scaling(bal: Balance) -> tuple[list[Any], list[Any]]:
    """Row and (positive) variable scales ``r``, ``c`` making every ``r_i A_ij c_j``, ``r_i b_i`` and ``G c``
    rational, by a walk over the bipartite graph of the nonzeros; ArgumentError if none exists."""
    rows: list[Any] = [None] * bal.rows
    cols: list[Any] = [None] * bal.variables
    by_row: dict[int, list[tuple[int, Any]]] = {}
    by_col: dict[int, list[tuple[int, Any]]] = {}
    for r, c, v in bal.A:
        by_row.setdefault(r, []).append((c, v))
        by_col.setdefault(c, []).append((r, v))
    for start in range(bal.variables):
        if cols[start] is not None:
            continue
        cols[start] = sympy.Integer(1)
        queue, members = deque([("c", start)]), [("c", start)]
        while queue:
            kind, k = queue.popleft()
            if kind == "c":
                for r, v in by_col.get(k, []):
                    if rows[r] is None:
                        rows[r] = sympy.radsimp(1 / (v * cols[k]))
                        queue.append(("r", r))
                        members.append(("r", r))
            else:
                for c, v in by_row.get(k, []):
                    if cols[c] is None:
                        cols[c] = sympy.Abs(sympy.radsimp(1 / (v * rows[k])))
                        queue.append(("c", c))
                        members.append(("c", c))
        # the component's common factor: chosen so that a loaded row's right-hand side is rational
        loaded = next((r for kind, r in members if kind == "r" and bal.b[r] != 0), None)
        if loaded is not None:
            factor = sympy.radsimp(1 / (rows[loaded] * bal.b[loaded]))
            for kind, k in members:
                if kind == "r":
                    rows[k] = sympy.radsimp(rows[k] * factor)
                else:
                    cols[k] = sympy.radsimp(cols[k] / sympy.Abs(factor))
    rows = [sympy.Integer(1) if r is None else r for r in rows]
    return rows, cols


def _rational(value: Any) -> bool:
    return _as_fraction(value) is not None


def exact_polytope(net: ContactNetwork, bal: Balance | None = None) -> ExactPolytope:
    """The polytope in exact kernel coordinates (rational after scaling rows and variables).

    Raises
    ------
    ArgumentError
        If the data are floats, or no scaling of equations and contacts makes them rational (e.g. ``sqrt(2)`` and
        ``sqrt(3)`` mixed in one equation), naming ``--samples`` as the way that works; or if the loads cannot
        be balanced at all.

    Examples
    --------
    >>> from forcenet.exact.contact_network.model import contact_network
    >>> poly = exact_polytope(contact_network(2, [[0, 1, 1, 0], [0, None, -1, 0], [1, None, 1, 0]],
    ...                                       [[0, 1, 0], [1, -1, 0]]))
    >>> poly.dimension, poly.free, poly.H
    (1, (2,), ((Fraction(1, 1),), (Fraction(1, 1),), (Fraction(1, 1),)))
    """
    if not net.exact:
        raise ArgumentError("the exact route needs exact data (integers, fractions such as '1/2', expressions such "
                            "as 'sqrt(3)/2'); this network has floats: sample it with --samples")
    bal = balance(net) if bal is None else bal
    row_scale, col_scale = _rational_scaling(bal)
    entries = [(r, c, row_scale[r] * v * col_scale[c]) for r, c, v in bal.A]
    rhs = [row_scale[r] * bal.b[r] for r in range(bal.rows)]
    g_entries = [(r, c, v * col_scale[c]) for r, c, v in bal.G]
    g_rows: dict[int, list[tuple[int, Any]]] = {}
    for r, c, v in g_entries:
        g_rows.setdefault(r, []).append((c, v))
    normalized_g: dict[int, list[tuple[int, Fraction]]] = {}
    for r, items in g_rows.items():
        lead = items[0][1]
        ratios = [(c, v / lead) for c, v in items]
        if not all(_rational(q) for _, q in ratios):
            raise _irrational()
        normalized_g[r] = [(c, _to_fraction(q) * (1 if lead > 0 else -1)) for c, q in ratios]
    if not all(_rational(v) for _, _, v in entries) or not all(_rational(v) for v in rhs):
        raise _irrational()
    m = bal.variables
    dense = [[Fraction(0)] * (m + 1) for _ in range(bal.rows)]
    for r, c, v in entries:
        dense[r][c] = _to_fraction(v)
    for r in range(bal.rows):
        dense[r][m] = _to_fraction(rhs[r])
    reduced, rank = fmpq_mat([[fmpq(x.numerator, x.denominator) for x in row] for row in dense]).rref()
    table = [[Fraction(int(x.p), int(x.q)) for x in row] for row in reduced.tolist()]
    pivots = []
    for row in table[:rank]:
        lead = next(k for k, v in enumerate(row) if v != 0)
        if lead == m:
            raise ArgumentError("the loads are not balanced: no contact forces at all (of either sign) balance "
                                "them exactly")
        pivots.append(lead)
    free = tuple(k for k in range(m) if k not in set(pivots))
    z0 = [Fraction(0)] * m
    K = [[Fraction(0)] * len(free) for _ in range(m)]
    for f_index, k in enumerate(free):
        K[k][f_index] = Fraction(1)
    for row, p in zip(table, pivots):
        z0[p] = row[m]
        for f_index, k in enumerate(free):
            K[p][f_index] = -row[k]
    H, h = [], []
    for r in range(bal.inequalities):
        items = normalized_g.get(r, [])
        H.append(tuple(sum((q * K[c][i] for c, q in items), Fraction(0)) for i in range(len(free))))
        h.append(sum((q * z0[c] for c, q in items), Fraction(0)))
    return ExactPolytope(tuple(col_scale), tuple(z0), tuple(tuple(row) for row in K), tuple(H), tuple(h), free,
                         len(free), bal.labels)


class IrrationalDataError(ArgumentError):
    """The refusal of data that no rescaling makes rational: the one a number field may lift
    (:mod:`~.number_field`).

    Examples
    --------
    >>> issubclass(IrrationalDataError, ArgumentError)
    True
    """


def _irrational() -> IrrationalDataError:
    return IrrationalDataError("the exact route needs balance equations that are rational once each equation and "
                               "each contact force is rescaled (as for the hexagonal lattice's sqrt(3)); this network "
                               "mixes irrational numbers that no rescaling removes: sample it with --samples")
