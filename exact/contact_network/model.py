"""A contact network: grains, contacts with their unit normals, external loads, friction (thesis Sec. 2.3).

The force network ensemble lives on *any* contact geometry (Ostojic 2006,
Sec. 2.3): the grains and their contacts are fixed, each contact ``c``
carries a repulsive normal force ``f_c >= 0`` (and, with friction ``mu > 0``,
a tangential force ``|t_c| <= mu f_c``), and every grain is in mechanical
balance under the contact forces and its external load.  This module holds
that geometry as one immutable value, checked once when it is built:

* a contact is ``(i, j, nx, ny)``: grains ``i`` and ``j`` (``j = None``: a
  wall or the floor, a fixed body outside the network) and the unit normal
  ``n`` pointing from ``i`` to ``j``; a compressive force ``f`` pushes ``j``
  by ``+f n`` and ``i`` by ``-f n``;
* a load is ``(g, fx, fy)`` (``(g, fx, fy, torque)`` with friction), the
  external force on grain ``g`` (gravity, an overload, a wall's prescribed
  pressure);
* numbers are exact where given exactly -- integers, ``Fraction``, strings
  such as ``"1/2"``, ``"0.25"`` or ``"sqrt(3)/2"`` (sympy numbers) -- and
  floats where given as floats (then the network is ``exact=False``: the
  exact route refuses it, the sampler takes it).

Readers: :func:`contact_network` (Python values), :func:`read_json` (the
file format of ``forcenet network``), :func:`from_networkx` (a graph with
positions) and :func:`read_csv` (the contact lists MD codes write).

Examples
--------
>>> net = contact_network(2, [[0, 1, 1, 0], [0, None, -1, 0], [1, None, 1, 0]], [[0, 1, 0], [1, -1, 0]])
>>> net.grains, len(net.contacts), net.exact
(2, 3, True)
>>> contact_network(2, [[0, 2, 1, 0]], [])
Traceback (most recent call last):
...
forcenet.core.errors.ArgumentError: contacts[0]: grain 2 does not exist: grains are numbered 0..1 (use null for a wall)
"""

from __future__ import annotations

import csv
import io
import json
import math
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Any

import sympy

from forcenet.core.errors import ArgumentError, ArgumentTypeError
from forcenet.core.validation import check_int, check_not_bool, is_integer

__all__ = ["ContactNetwork", "contact_network", "read_json", "parse_json", "from_networkx", "read_csv",
           "exact_number", "is_exact"]

Number = Any  # a sympy number (exact) or a float

_EXPRESSION = re.compile(r"^[0-9+\-*/().eE ]*$")  # what remains of an exact expression once sqrt is removed


def exact_number(value: Any, name: str) -> Number:
    """A number as given: exact (a sympy number) from an int, Fraction, sympy number or string; a float stays a float.

    Parameters
    ----------
    value : int, Fraction, str, float or sympy number
        ``"1/2"``, ``"0.25"`` (read as 1/4), ``"sqrt(3)/2"``, ``3``, ``Fraction(1, 3)``, ``0.5``.
    name : str
        The value's place, named in the error.

    Returns
    -------
    sympy.Expr or float
        A real, finite sympy number, or the float.

    Examples
    --------
    >>> exact_number("sqrt(3)/2", "nx"), exact_number("0.25", "fx"), exact_number(0.5, "fy")
    (sqrt(3)/2, 1/4, 0.5)
    >>> exact_number("nan", "fx")
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: fx='nan' is not a finite number: give an integer, a fraction '1/3', a decimal or an expression such as 'sqrt(3)/2'
    """
    fix = "give an integer, a fraction '1/3', a decimal or an expression such as 'sqrt(3)/2'"
    if value is None:
        raise ArgumentTypeError(f"{name}={value!r} is not a number: {fix}")
    check_not_bool(value, name)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ArgumentError(f"{name}={value!r} is not a finite number: {fix}")
        return value
    if is_integer(value):
        return sympy.Integer(int(value))
    if isinstance(value, Fraction):
        return sympy.Rational(value.numerator, value.denominator)
    if isinstance(value, sympy.Expr):
        expr = value
    elif isinstance(value, str):
        text = value.strip()
        try:
            return sympy.Rational(Fraction(text))
        except (ValueError, ZeroDivisionError):
            pass
        if not text or not _EXPRESSION.match(text.replace("sqrt", "")):
            raise ArgumentError(f"{name}={value!r} is not a finite number: {fix}")
        try:
            expr = sympy.sympify(text, rational=True)
        except (sympy.SympifyError, SyntaxError, TypeError, ZeroDivisionError):
            raise ArgumentError(f"{name}={value!r} is not a finite number: {fix}") from None
    else:
        raise ArgumentTypeError(f"{name}={value!r} is not a number: {fix}")
    if not (expr.is_number and expr.is_real and expr.is_finite):
        raise ArgumentError(f"{name}={value!r} is not a finite number: {fix}")
    return sympy.nsimplify(expr) if expr.has(sympy.Float) else expr


def is_exact(value: Number) -> bool:
    """True for a sympy number, False for a float.

    Examples
    --------
    >>> is_exact(exact_number("1/3", "x")), is_exact(0.5)
    (True, False)
    """
    return not isinstance(value, float)


def _is_unit(nx: Number, ny: Number) -> bool:
    if is_exact(nx) and is_exact(ny):
        return bool(sympy.simplify(nx * nx + ny * ny - 1) == 0)
    return abs(float(nx) ** 2 + float(ny) ** 2 - 1.0) <= 1e-9


@dataclass(frozen=True)
class ContactNetwork:
    """A contact network in the force network ensemble's sense (Sec. 2.3), checked once.

    Parameters
    ----------
    grains : int
        The number of grains, numbered ``0 .. grains - 1``.
    contacts : tuple of (int, int or None, number, number)
        ``(i, j, nx, ny)``: the unit normal from ``i`` to ``j``; ``j = None`` is a wall.
    loads : tuple of tuple of number
        Per grain the external ``(fx, fy, torque)`` (zeros where no load was given).
    friction : number
        ``mu``: 0 is frictionless (one normal force per contact), ``mu > 0`` adds a tangential force per contact
        with ``|t| <= mu f`` and torque balance (needs ``radii``).
    radii : tuple of number or None
        Grain radii (the torque's lever arms), needed with friction.
    positions : tuple of (number, number) or None
        Grain centres, for figures and for networks built from positions.
    exact : bool
        Every number given exactly (the exact route's condition).

    Examples
    --------
    >>> net = contact_network(1, [[0, None, 0, -1]], [[0, 0, -1]])
    >>> net.loads, net.frictional
    (((0, -1, 0),), False)
    """

    grains: int
    contacts: tuple[tuple[int, int | None, Number, Number], ...]
    loads: tuple[tuple[Number, Number, Number], ...]
    friction: Number = sympy.Integer(0)
    radii: tuple[Number, ...] | None = None
    positions: tuple[tuple[Number, Number], ...] | None = None
    exact: bool = True

    @property
    def frictional(self) -> bool:
        """True when ``mu > 0``.

        Examples
        --------
        >>> contact_network(1, [[0, None, 0, -1]], [[0, 0, -1]]).frictional
        False
        """
        return bool(self.friction > 0)

    def describe(self) -> str:
        """One line: grains, contacts, walls, friction.

        Returns
        -------
        str
            The line.

        Examples
        --------
        >>> contact_network(1, [[0, None, 0, -1]], [[0, 0, -1]]).describe()
        '1 grains, 1 contacts (1 with walls), frictionless, exact data'
        """
        walls = sum(1 for c in self.contacts if c[1] is None)
        mu = "frictionless" if not self.frictional else f"friction mu={self.friction}"
        return (f"{self.grains} grains, {len(self.contacts)} contacts ({walls} with walls), {mu}, "
                f"{'exact' if self.exact else 'floating-point'} data")


def contact_network(grains: Any, contacts: Iterable[Sequence[Any]], loads: Iterable[Sequence[Any]] = (), *,
                    friction: Any = 0, radii: Iterable[Any] | None = None,
                    positions: Iterable[Sequence[Any]] | None = None) -> ContactNetwork:
    """Build and check a :class:`ContactNetwork` (Sec. 2.3) from Python values.

    Parameters
    ----------
    grains : int
        Number of grains (``>= 1``), numbered from 0.
    contacts : iterable of (i, j, nx, ny)
        ``j`` is a grain or ``None`` (a wall); ``(nx, ny)`` the unit normal from ``i`` to ``j``.
    loads : iterable of (g, fx, fy) or (g, fx, fy, torque)
        External loads; a grain named twice has its loads added.
    friction : number, optional
        ``mu >= 0`` (default 0).
    radii, positions : optional
        Per grain; radii are needed when ``friction > 0``.

    Returns
    -------
    ContactNetwork

    Raises
    ------
    ArgumentError
        A contact to a missing grain, a grain in contact with itself, a normal that is not of unit length,
        a number that is NaN or infinite, a torque or friction without radii.

    Examples
    --------
    >>> contact_network(1, [[0, None, "3/5", "4/5"]], [[0, "-3/5", "-4/5"]]).contacts
    ((0, None, 3/5, 4/5),)
    >>> contact_network(1, [[0, None, 1, 1]], [])
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: contacts[0]: the normal (1, 1) has length 1.41421, not 1: give a unit vector (divide by its length)
    """
    grains = check_int(grains, "grains", 1)
    exact = True
    mu = exact_number(friction, "friction")
    if mu < 0:
        raise ArgumentError(f"friction={friction!r} is out of range: friction (mu) must be >= 0")
    exact &= is_exact(mu)
    out = []
    for k, contact in enumerate(contacts):
        where = f"contacts[{k}]"
        if isinstance(contact, (str, bytes)) or len(contact) != 4:
            raise ArgumentError(f"{where}={contact!r}: a contact is [i, j, nx, ny] (j null for a wall)")
        i = _grain(contact[0], grains, where)
        j = None if contact[1] is None or contact[1] == "wall" else _grain(contact[1], grains, where)
        if i == j:
            raise ArgumentError(f"{where}: grain {i} cannot touch itself")
        nx, ny = exact_number(contact[2], f"{where} nx"), exact_number(contact[3], f"{where} ny")
        if not _is_unit(nx, ny):
            length = math.hypot(float(nx), float(ny))
            raise ArgumentError(f"{where}: the normal ({nx}, {ny}) has length {length:g}, not 1: "
                                "give a unit vector (divide by its length)")
        exact &= is_exact(nx) and is_exact(ny)
        out.append((i, j, nx, ny))
    total: list[list[Number]] = [[sympy.Integer(0)] * 3 for _ in range(grains)]
    for k, load in enumerate(loads):
        where = f"loads[{k}]"
        if isinstance(load, (str, bytes)) or len(load) not in (3, 4):
            raise ArgumentError(f"{where}={load!r}: a load is [g, fx, fy] or [g, fx, fy, torque]")
        g = _grain(load[0], grains, where)
        for axis, value in enumerate(load[1:]):
            number = exact_number(value, f"{where} {('fx', 'fy', 'torque')[axis]}")
            exact &= is_exact(number)
            total[g][axis] = total[g][axis] + number
    radii_t = None if radii is None else tuple(exact_number(r, f"radii[{g}]") for g, r in enumerate(radii))
    if radii_t is not None:
        if len(radii_t) != grains:
            raise ArgumentError(f"radii has {len(radii_t)} entries: give one radius per grain ({grains})")
        if any(r <= 0 for r in radii_t):
            raise ArgumentError("radii: every radius must be > 0")
        exact &= all(is_exact(r) for r in radii_t)
    if mu > 0 and radii_t is None:
        raise ArgumentError(f"friction={friction}: torque balance needs the grains' radii; give \"radii\"")
    if mu == 0 and any(t != 0 for _, _, t in total):
        raise ArgumentError("a torque load on a frictionless network cannot be balanced (normal forces exert "
                            "no torque on round grains): drop the torque or give friction > 0")
    pos_t = None
    if positions is not None:
        pos_t = tuple((exact_number(p[0], f"positions[{g}] x"), exact_number(p[1], f"positions[{g}] y"))
                      for g, p in enumerate(positions))
        if len(pos_t) != grains:
            raise ArgumentError(f"positions has {len(pos_t)} entries: give one per grain ({grains})")
    return ContactNetwork(grains, tuple(out), tuple((fx, fy, t) for fx, fy, t in total), mu, radii_t, pos_t,
                          bool(exact))


def _grain(value: Any, grains: int, where: str) -> int:
    if not is_integer(value):
        raise ArgumentTypeError(f"{where}: grain {value!r} is not an integer: grains are numbered 0..{grains - 1}")
    g = int(value)
    if not 0 <= g < grains:
        raise ArgumentError(f"{where}: grain {g} does not exist: grains are numbered 0..{grains - 1} "
                            "(use null for a wall)")
    return g


def parse_json(text: str, source: str = "the input") -> ContactNetwork:
    """A network from the JSON text of ``forcenet network`` (keys below; numbers may be strings such as ``"1/2"``).

    ``{"grains": n, "contacts": [[i, j, "nx", "ny"], ...], "loads": [[g, "fx", "fy"], ...]}`` with optional
    ``"friction"``, ``"radii"``, ``"positions"``. JSON numbers with a fraction part or an exponent are floats;
    integers and strings are exact.

    Examples
    --------
    >>> parse_json('{"grains": 1, "contacts": [[0, null, "0", "-1"]], "loads": [[0, 0, "-1/2"]]}').loads
    ((0, -1/2, 0),)
    >>> parse_json("[1, 2")
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: the input is not JSON: Expecting ',' delimiter: line 1 column 6 (char 5)
    """
    try:
        data = json.loads(text, parse_constant=_refuse_constant)
    except json.JSONDecodeError as exc:
        raise ArgumentError(f"{source} is not JSON: {exc}") from None
    if not isinstance(data, dict) or "grains" not in data or "contacts" not in data:
        raise ArgumentError(f"{source}: a contact network is a JSON object with \"grains\", \"contacts\" and "
                            "\"loads\"")
    unknown = set(data) - {"grains", "contacts", "loads", "friction", "radii", "positions", "name"}
    if unknown:
        raise ArgumentError(f"{source}: unknown keys {sorted(unknown)}: the keys are grains, contacts, loads, "
                            "friction, radii, positions")
    return contact_network(data["grains"], data["contacts"], data.get("loads", ()), friction=data.get("friction", 0),
                           radii=data.get("radii"), positions=data.get("positions"))


def _refuse_constant(name: str) -> Any:
    raise ArgumentError(f"{name} is not a finite number: a contact network holds finite numbers only")


def read_json(path: str | Path) -> ContactNetwork:
    """A network from a JSON file (the format of :func:`parse_json`).

    Examples
    --------
    >>> import tempfile, os
    >>> with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
    ...     _ = f.write('{"grains": 1, "contacts": [[0, null, 0, -1]], "loads": [[0, 0, -1]]}')
    >>> read_json(f.name).grains
    1
    >>> os.unlink(f.name)
    """
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ArgumentError(f"cannot read {path}: {exc}") from None
    return parse_json(text, str(path))


def from_networkx(graph: Any, loads: Iterable[Sequence[Any]] = (), *, walls: Iterable[Sequence[Any]] = (),
                  friction: Any = 0, pos: str = "pos", radius: str = "radius") -> ContactNetwork:
    """A network from a networkx graph whose nodes carry positions: edges are contacts, normals from the centres.

    Parameters
    ----------
    graph : networkx.Graph
        Nodes with a ``pos`` attribute ``(x, y)`` (exact numbers give exact normals), optionally ``radius``.
    loads : iterable of (node, fx, fy)
        External loads by node.
    walls : iterable of (node, nx, ny)
        Contacts with walls: the unit normal from the node to the wall.
    friction : number, optional
        ``mu``.

    Returns
    -------
    ContactNetwork
        Grains numbered in the graph's node order.

    Examples
    --------
    >>> import networkx as nx
    >>> g = nx.Graph(); g.add_node("a", pos=(0, 0)); g.add_node("b", pos=(3, 4)); g.add_edge("a", "b")
    >>> from_networkx(g, walls=[("a", 0, -1), ("b", 0, 1)]).contacts[0]
    (0, 1, 3/5, 4/5)
    """
    nodes = list(graph.nodes)
    index = {node: k for k, node in enumerate(nodes)}
    try:
        centres = [(exact_number(graph.nodes[n][pos][0], f"{n} x"), exact_number(graph.nodes[n][pos][1], f"{n} y"))
                   for n in nodes]
    except KeyError:
        raise ArgumentError(f"from_networkx: every node needs a {pos!r} attribute (x, y)") from None
    contacts: list[list[Any]] = []
    for a, b in graph.edges:
        dx, dy = centres[index[b]][0] - centres[index[a]][0], centres[index[b]][1] - centres[index[a]][1]
        exact = is_exact(dx) and is_exact(dy)
        length = sympy.sqrt(dx * dx + dy * dy) if exact else math.hypot(dx, dy)
        if length == 0:
            raise ArgumentError(f"from_networkx: nodes {a!r} and {b!r} sit at the same position")
        nx_, ny_ = (sympy.radsimp(dx / length), sympy.radsimp(dy / length)) if exact else (dx / length, dy / length)
        contacts.append([index[a], index[b], nx_, ny_])
    for node, wx, wy in walls:
        contacts.append([index[node], None, wx, wy])
    radii = None
    if all(radius in graph.nodes[n] for n in nodes) and nodes:
        radii = [graph.nodes[n][radius] for n in nodes]
    return contact_network(len(nodes), contacts, [[index[g], *rest] for g, *rest in loads], friction=friction,
                           radii=radii, positions=centres)


def read_csv(source: str | Path, grains: int, loads: Iterable[Sequence[Any]] = (), *, friction: Any = 0,
             radii: Iterable[Any] | None = None) -> ContactNetwork:
    """A network from a contact list as MD/DEM codes write it: a CSV with columns ``i, j, nx, ny``.

    A header row naming the columns is used when present (other columns are ignored); ``j`` empty, ``-1`` or
    ``wall`` is a wall. Numbers are read as written: ``0.6`` is exact 3/5 here (a decimal in a text file is
    its decimal value).

    Examples
    --------
    >>> read_csv(io.StringIO("i,j,nx,ny\\n0,1,1,0\\n0,-1,-1,0\\n1,wall,1,0\\n"), 2).contacts[1]
    (0, None, -1, 0)
    """
    handle = io.StringIO(Path(source).read_text(encoding="utf-8")) if isinstance(source, (str, Path)) else source
    rows = [row for row in csv.reader(handle) if row and not row[0].startswith("#")]
    columns = {"i": 0, "j": 1, "nx": 2, "ny": 3}
    if rows and not _numeric(rows[0][0]):
        header = [name.strip().lower() for name in rows[0]]
        missing = [name for name in columns if name not in header]
        if missing:
            raise ArgumentError(f"the CSV header {rows[0]} lacks the columns {missing} (i, j, nx, ny)")
        columns = {name: header.index(name) for name in columns}
        rows = rows[1:]
    contacts = []
    for number, row in enumerate(rows, start=1):
        try:
            j = row[columns["j"]].strip()
            contacts.append([int(row[columns["i"]]), None if j in ("", "-1", "wall") else int(j),
                             row[columns["nx"]].strip(), row[columns["ny"]].strip()])
        except (ValueError, IndexError):
            raise ArgumentError(f"the CSV's contact row {number} ({','.join(row)}) is not i, j, nx, ny with "
                                "integer grains") from None
    return contact_network(grains, contacts, loads, friction=friction, radii=radii)


def _numeric(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True
