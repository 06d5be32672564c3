"""The force network ensemble under a shear stress (thesis Ch. 8, Sec. 8.2): Eq. (8.1) and the yield stress.

Eq. (8.1), reconstructed (``notes/shear.md``): the macroscopic stress of a
packing of volume ``V`` is ``sigma_ab = (1/V) sum_ij f_ij,a (r_i - r_j)_b``;
for central forces ``f_ij = f_c n_c`` along the contact's unit normal and
``r_j - r_i = l_c n_c`` (monodisperse disks of diameter ``l_c = 1``) it is
``sigma = (1/V) sum_c f_c n_c n_c^T``.  The ensemble under shear (Sec. 8.2,
after Snoeijer et al., PRL 96, 098001 (2006)) keeps ``sigma_xx = sigma_yy``
and imposes ``tau = sigma_xy / sigma_xx``; here, on a packing without walls
or loads (the periodic hexagonal packing), the three rows

    sum_c f_c n_x^2 = P,   sum_c f_c n_y^2 = P,   sum_c f_c n_x n_y = tau P,
    P = pressure * contacts / 2 (so that the mean force is ``pressure``)

join the grains' balance ``A f = 0`` (:func:`sheared_balance`).  The yield
stress (Sec. 8.2: "networks of repulsive forces ... only for tau smaller
than a maximum shear stress") is the largest ``tau`` for which this polytope
is not empty: a linear program.

Exactly (:func:`yield_stress`): each equation is divided by its first
coefficient, which makes the hexagonal lattice's rows rational (the
``sqrt(3)`` of the ``y`` rows and of the ``xy`` row leave with the factor),
and the program ``max w``, ``w = s tau P`` (``s`` the ``xy`` row's factor),
is solved by a two-phase simplex over ``Fraction`` (Bland's rule, so it
ends).  The answer is a proof, checked in exact arithmetic before it is
returned: a network ``f >= 0`` balancing every grain at ``tau_max`` (the
polytope is not empty there), and a solution ``y`` of the *dual* program
(solved by the same simplex, separately) with ``E_f^T y >= 0``,
``E_w . y = 1`` and ``e . y = w_max``: then every admissible network has
``w = e . y - (E_f^T y) . f <= w_max``, so the polytope is empty for every
``tau > tau_max`` (Farkas).  :func:`float_yield_stress` is the second
route (HiGHS on the floats).  For the hexagonal lattice the bound is known in
closed form, ``tau_max = 1/sqrt(3)`` (``notes/shear.md``: only three bond
directions, ``sigma = sum_k F_k n_k n_k^T`` with ``F_k >= 0``).

Examples
--------
>>> from forcenet.exact.contact_network.geometries import hexagonal_torus
>>> yield_stress(hexagonal_torus(3).network).tau_max
sqrt(3)/3
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import numpy as np
import sympy
from scipy import optimize

from forcenet.core.errors import ArgumentError, ConvergenceError

from .model import ContactNetwork, exact_number, is_exact
from .polytope import Balance, balance, float_system

__all__ = ["stress_rows", "sheared_balance", "YieldStress", "yield_stress", "float_yield_stress", "simplex_max",
           "uniform_network"]


def _check_periodic(net: ContactNetwork) -> None:
    walls = sum(1 for c in net.contacts if c[1] is None)
    loaded = any(x != 0 for load in net.loads for x in load)
    if walls or loaded or net.frictional:
        raise ArgumentError(f"the sheared ensemble needs a periodic frictionless packing without walls or loads "
                            f"(this one: {net.describe()}); build it with hexagonal_torus(L)")


def stress_rows(net: ContactNetwork) -> list[list[Any]]:
    """The three rows ``sum_c f_c n n^T`` of Eq. (8.1) (``xx``, ``yy``, ``xy``), one coefficient per contact.

    Contacts of length 1 (monodisperse disks of diameter 1), so ``(r_j - r_i) = n``.

    Parameters
    ----------
    net : ContactNetwork
        Periodic, frictionless, without walls or loads (:func:`~.geometries.hexagonal_torus`).

    Returns
    -------
    list of list
        ``[[n_x^2 ...], [n_y^2 ...], [n_x n_y ...]]``.

    Examples
    --------
    >>> from forcenet.exact.contact_network.geometries import hexagonal_torus
    >>> [row[:3] for row in stress_rows(hexagonal_torus(3).network)]
    [[1, 1/4, 1/4], [0, 3/4, 3/4], [0, sqrt(3)/4, -sqrt(3)/4]]
    """
    _check_periodic(net)
    return [[nx * nx for _, _, nx, _ in net.contacts], [ny * ny for _, _, _, ny in net.contacts],
            [nx * ny for _, _, nx, ny in net.contacts]]


def sheared_balance(net: ContactNetwork, tau: Any, pressure: Any = 1) -> Balance:
    """The balance of every grain plus the imposed stress ``sigma_xx = sigma_yy = P``, ``sigma_xy = tau P``.

    ``P = pressure * contacts / 2``: the trace fixes the sum of the forces, so the mean force is ``pressure``
    in every network (Eq. (8.1) with ``V`` absorbed in ``P``).

    Parameters
    ----------
    net : ContactNetwork
        A periodic packing (:func:`~.geometries.hexagonal_torus`).
    tau : number
        The dimensionless shear stress ``sigma_xy / sigma_xx`` (exact as in :func:`~.model.exact_number`, or a float).
    pressure : number
        The mean force (default 1).

    Returns
    -------
    Balance
        The grains' rows, then the ``xx``, ``yy``, ``xy`` rows.

    Examples
    --------
    >>> from forcenet.exact.contact_network.geometries import hexagonal_torus
    >>> bal = sheared_balance(hexagonal_torus(3).network, "1/5")
    >>> bal.rows, bal.b[-3:]
    (21, (27/2, 27/2, 27/10))
    """
    t, p = exact_number(tau, "tau"), exact_number(pressure, "pressure")
    if p <= 0:
        raise ArgumentError(f"pressure={pressure!r} is out of range: the mean force must be > 0")
    rows = stress_rows(net)
    base = balance(net)
    P = p * sympy.Rational(len(net.contacts), 2) if is_exact(p) else p * len(net.contacts) / 2
    extra = tuple((base.rows + r, c, v) for r, row in enumerate(rows) for c, v in enumerate(row) if v != 0)
    return Balance(base.rows + 3, base.variables, base.A + extra, base.b + (P, P, t * P), base.G,
                   base.inequalities, base.labels)


def uniform_network(tau: Any, pressure: Any = 1) -> tuple[Any, Any, Any]:
    """The forces of the torus' three bond directions when each direction carries one force (the thesis's start).

    ``sigma = (L^2) sum_k F_k n_k n_k^T`` gives ``(F_side, F_up, F_upleft) = p (1, 1 + sqrt(3) tau,
    1 - sqrt(3) tau)``: admissible while ``|tau| <= 1/sqrt(3)``.

    Parameters
    ----------
    tau, pressure : number
        As in :func:`sheared_balance`.

    Returns
    -------
    tuple
        The three forces.

    Examples
    --------
    >>> uniform_network("sqrt(3)/6")
    (1, 3/2, 1/2)
    """
    t, p = exact_number(tau, "tau"), exact_number(pressure, "pressure")
    root3 = sympy.sqrt(3) if is_exact(t) else 3 ** 0.5
    return (p, sympy.expand(p * (1 + root3 * t)) if is_exact(t) else p * (1 + root3 * t),
            sympy.expand(p * (1 - root3 * t)) if is_exact(t) else p * (1 - root3 * t))


def _fraction(value: Any) -> Fraction | None:
    value = sympy.nsimplify(sympy.radsimp(value)) if not isinstance(value, sympy.Rational) else value
    return Fraction(int(value.p), int(value.q)) if isinstance(value, sympy.Rational) else None


def simplex_max(c: list[Fraction], E: list[list[Fraction]], e: list[Fraction]) -> tuple[Fraction, list[Fraction]]:
    """``max c.z`` subject to ``E z = e``, ``z >= 0``, exactly: a two-phase tableau simplex, Bland's rule.

    Parameters
    ----------
    c : list of Fraction
        The objective.
    E, e : list of list of Fraction, list of Fraction
        The equations.

    Returns
    -------
    (Fraction, list of Fraction)
        The optimum and an optimal vertex.

    Raises
    ------
    ArgumentError
        The program is infeasible (no ``z``) or unbounded.

    Examples
    --------
    >>> F = Fraction
    >>> simplex_max([F(1), F(1), F(0)], [[F(1), F(2), F(1)]], [F(4)])
    (Fraction(4, 1), [Fraction(4, 1), Fraction(0, 1), Fraction(0, 1)])
    """
    m, n = len(E), len(c)
    # phase 1: rows with e >= 0, artificial columns n .. n+m-1, objective row last
    T = [[(-v if e[r] < 0 else v) for v in E[r]] + [Fraction(int(k == r)) for k in range(m)] + [abs(e[r])]
         for r in range(m)]
    basis = [n + r for r in range(m)]

    def pivot(r: int, k: int) -> None:
        lead = T[r][k]
        T[r] = [v / lead for v in T[r]]
        for q in range(len(T)):
            if q != r and T[q][k] != 0:
                factor = T[q][k]
                T[q] = [a - factor * b for a, b in zip(T[q], T[r])]
        basis[r] = k

    def optimize_row(allowed: int) -> None:
        while True:  # reduced costs in the last row: enter the first negative (Bland), leave the first minimal ratio
            k = next((j for j in range(allowed) if T[-1][j] < 0), None)
            if k is None:
                return
            best: tuple[Fraction, int] | None = None
            for r in range(len(T) - 1):
                if T[r][k] > 0:
                    ratio = (T[r][-1] / T[r][k], basis[r])
                    if best is None or ratio < best:
                        best = ratio
            if best is None:
                raise ArgumentError("the linear program is unbounded")
            pivot(basis.index(best[1]), k)

    T.append([-sum((T[r][j] for r in range(m)), Fraction(0)) if j < n or j == n + m else Fraction(0)
              for j in range(n + m + 1)])
    optimize_row(n + m)
    if T[-1][-1] != 0:
        raise ArgumentError("the linear program is infeasible")
    for r in range(m):  # artificials left in the basis at zero: pivot them out, or their row is redundant
        if basis[r] >= n:
            k = next((j for j in range(n) if T[r][j] != 0), None)
            if k is not None:
                pivot(r, k)
    keep = [r for r in range(m) if basis[r] < n]
    T = [T[r][:n] + [T[r][-1]] for r in keep]
    basis = [basis[r] for r in keep]
    objective = [-v for v in c] + [Fraction(0)]
    for r, k in enumerate(basis):
        if objective[k] != 0:
            factor = objective[k]
            objective = [a - factor * b for a, b in zip(objective, T[r])]
    T.append(objective)
    optimize_row(n)
    z = [Fraction(0)] * n
    for r, k in enumerate(basis):
        z[k] = T[r][-1]
    return T[-1][-1], z


@dataclass(frozen=True)
class YieldStress:
    """The yield stress of a periodic packing with its exact proof (module docstring).

    Attributes
    ----------
    tau_max : sympy number
        The largest shear stress ``sigma_xy / sigma_xx`` the polytope admits.
    witness : tuple of sympy numbers
        An admissible network at ``tau_max`` (mean force 1).
    certificate : tuple of Fraction
        The dual solution ``y`` (per scaled equation) bounding ``tau`` for every admissible network.
    row_scale : tuple of sympy numbers
        The factor each equation was multiplied by to make it rational.
    """

    tau_max: Any
    witness: tuple[Any, ...]
    certificate: tuple[Fraction, ...]
    row_scale: tuple[Any, ...]


def _rational_program(net: ContactNetwork) -> tuple[list[list[Fraction]], list[Fraction], list[Any]]:
    """The sheared balance at unknown ``tau`` as rational equations ``E (f, w) = e``, ``w = s tau P``."""
    bal = sheared_balance(net, 0)
    C = bal.variables
    dense: list[list[Any]] = [[sympy.Integer(0)] * C for _ in range(bal.rows)]
    for r, k, v in bal.A:
        dense[r][k] = v
    E, e, scales = [], [], []
    for r, row in enumerate(dense):
        lead = next((v for v in row if v != 0), None)
        if lead is None:
            continue
        scale = sympy.radsimp(1 / lead)
        values = [_fraction(v * scale) for v in row]
        rhs = _fraction(bal.b[r] * scale)
        if rhs is None or any(v is None for v in values):
            raise ArgumentError("the exact yield stress needs equations that become rational once each is rescaled "
                                "(as the hexagonal lattice's); this packing's do not: use float_yield_stress")
        scales.append(scale)
        E.append([v if v is not None else Fraction(0) for v in values] + [Fraction(-int(r == bal.rows - 1))])
        e.append(rhs)
    return E, e, scales


def yield_stress(net: ContactNetwork) -> YieldStress:
    """The largest shear stress ``tau = sigma_xy / sigma_xx`` for which repulsive balanced networks exist (Sec. 8.2).

    Exact (module docstring): the primal simplex's vertex and the dual simplex's ``y`` are checked in
    ``Fraction`` arithmetic (balance, ``f >= 0``, dual feasibility, equal optima) before they are returned.

    Parameters
    ----------
    net : ContactNetwork
        A periodic frictionless packing (:func:`~.geometries.hexagonal_torus`).

    Returns
    -------
    YieldStress

    Raises
    ------
    ArgumentError
        Walls, loads or friction; equations that no rescaling makes rational.

    Examples
    --------
    >>> from forcenet.exact.contact_network.geometries import hexagonal_torus
    >>> ys = yield_stress(hexagonal_torus(3).network)
    >>> ys.tau_max, min(ys.witness)
    (sqrt(3)/3, 0)
    """
    E, e, scales = _rational_program(net)
    rows, C = len(E), len(E[0]) - 1
    # primal: w = w+ - w-, maximize w
    E2 = [row + [-row[-1]] for row in E]
    w_max, z = simplex_max([Fraction(0)] * C + [Fraction(1), Fraction(-1)], E2, e)
    f, w = z[:C], z[C] - z[C + 1]
    # dual: minimize e.y subject to E_f^T y - s = 0 (s >= 0), E_w . y = 1, y = y+ - y- free
    D = [[E[r][k] for r in range(rows)] + [-E[r][k] for r in range(rows)] + [Fraction(-int(j == k)) for j in range(C)]
         for k in range(C)]
    D.append([E[r][C] for r in range(rows)] + [-E[r][C] for r in range(rows)] + [Fraction(0)] * C)
    neg, yz = simplex_max([-v for v in e] + list(e) + [Fraction(0)] * C, D, [Fraction(0)] * C + [Fraction(1)])
    y = [yz[r] - yz[rows + r] for r in range(rows)]
    # the proof, in exact arithmetic
    primal_ok = all(v >= 0 for v in f) and all(
        sum((E[r][k] * f[k] for k in range(C)), Fraction(0)) + E[r][C] * w == e[r] for r in range(rows))
    dual_ok = all(sum((E[r][k] * y[r] for r in range(rows)), Fraction(0)) >= 0 for k in range(C)) and \
        sum((E[r][C] * y[r] for r in range(rows)), Fraction(0)) == 1
    if not (primal_ok and dual_ok and w == w_max == -neg == sum((a * b for a, b in zip(e, y)), Fraction(0))):
        raise ConvergenceError("the exact yield stress's proof failed (primal and dual disagree): please report")
    P = sympy.Rational(C, 2)
    tau = sympy.radsimp(sympy.Rational(w.numerator, w.denominator) / (scales[-1] * P))
    return YieldStress(tau, tuple(sympy.Rational(v.numerator, v.denominator) for v in f), tuple(y), tuple(scales))


def float_yield_stress(net: ContactNetwork) -> float:
    """The yield stress by HiGHS on floats (the second route to :func:`yield_stress`).

    ``max tau`` over ``(f, tau)`` with ``A f = 0``, the stress rows of :func:`sheared_balance` with ``tau P`` moved
    to the left, ``f >= 0``.

    Parameters
    ----------
    net : ContactNetwork
        As in :func:`yield_stress`.

    Returns
    -------
    float

    Examples
    --------
    >>> from forcenet.exact.contact_network.geometries import hexagonal_torus
    >>> round(float_yield_stress(hexagonal_torus(4).network), 9)
    0.577350269
    """
    bal = sheared_balance(net, 0)
    A, b, _ = float_system(bal)
    column = np.zeros((A.shape[0], 1))
    column[-1, 0] = -float(bal.b[-2])  # the xy row: sum f n_x n_y - tau P = 0
    cost = np.zeros(A.shape[1] + 1)
    cost[-1] = -1.0
    result = optimize.linprog(cost, A_eq=np.hstack([A.toarray(), column]), b_eq=b,
                              bounds=[(0, None)] * A.shape[1] + [(None, None)], method="highs")
    if result.status != 0:
        raise ArgumentError(f"the floating linear program failed: {result.message}")
    return float(result.x[-1])
