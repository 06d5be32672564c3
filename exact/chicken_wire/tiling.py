"""Chicken-wire configurations <-> square-triangle tilings: the map, its inverse, and their checks.

Conventions
-----------
*Chicken-wire lattice.*  Sites ``(x, y)`` of the triangular lattice in lattice
coordinates; bond directions ``0 -> (1, 0)``, ``60 -> (0, 1)``,
``120 -> (-1, 1)`` and opposites (as in :mod:`.model`).  A torus is
``Z^2 / Gamma`` for a rank-2 sublattice ``Gamma``; the ``L x M`` torus of the
project is ``Gamma = <(L, 0), (0, M)>``.  A configuration is a dict
``site -> frozenset of occupied bond directions``.

*Tiling side.*  ``Z[zeta]`` with ``zeta = exp(i pi/6)`` is stored as integer
4-tuples in the basis ``1, z, z^2, z^3`` (``z^4 = z^2 - 1``).  ``UNIT[k]`` is
``z^k`` (direction ``30 k`` degrees).  Directions ``k`` even are *family A*
(the chicken-wire lattice directions), ``k`` odd *family B*.  A tile is given
by its type (``"T"`` triangle, ``"S"`` square), the position of one corner and
the direction ``d`` of the edge leaving that corner counterclockwise; the edge
directions are ``d, d+4, d+8`` (triangle) or ``d, d+3, d+6, d+9`` (square).
The corner at which the edge of direction ``e_i`` starts covers the sectors
``e_i, ..., e_{i-1} + 5`` (30-degree sectors numbered like the directions).
A tiling of the torus ``R^2 / Lambda`` (``Lambda`` a rank-2 sublattice of
``Z[zeta]``) is *edge-to-edge* with unit edges in the twelve directions.

*The map* (``config_to_tiling``).  Let ``F: Z[zeta] -> Z^2`` be the Z-linear
map ``z^k -> `` the lattice vector of direction ``30 k`` and length 1 (``k``
even) or ``sqrt 3`` (``k`` odd), i.e. ``F(1, z, z^2, z^3) = (1,0), (1,1),
(0,1), (-1,2)``.  Tiling vertices are the empty sites; the faces are

- an A triangle for each unit lattice triangle with three empty corners;
- a square for each pass-through site ``s`` (H, R, L): for H the corners are
  ``s + (0,-1), s + (1,-1), s + (0,1), s + (-1,1)`` (edges ``0, 3, 6, 9``),
  rotated by 60/120 degrees for R/L;
- a B triangle for each Y (corners ``s + (0,1), s + (-1,0), s + (1,-1)``,
  edges ``7, 11, 3``) and each inverted Y (corners ``s + (1,0), s + (-1,1),
  s + (0,-1)``, edges ``5, 9, 1``);

every tile edge of direction ``k`` joins sites differing by ``F(z^k)``.
The inverse (``tiling_to_config``) sends a vertex ``p`` to the site ``F(p)``
(empty), a square to the site ``F(centre)`` (a wall along its A edges) and a B
triangle to ``F(centre)`` (a Y with bonds perpendicular to its sides).  On the
tiling side ``F`` is the piecewise-affine map that stretches every B direction
by ``sqrt 3``: unit triangles of family A are kept, squares become
``1 x sqrt3`` rectangles and B triangles triangles of side ``sqrt 3``; their
lattice points are exactly their corners plus the centres of rectangles and
big triangles.

The independent enumerator (``enumerate_tilings``) does not use any of this:
it fills angular gaps at vertices of ``Z[zeta] / Lambda``.
"""


from __future__ import annotations

from collections import Counter, deque
from collections.abc import Collection, Iterator
from fractions import Fraction
from math import gcd
from typing import Any

from forcenet.core.errors import ArgumentError

from .model import BOND_STEPS, VERTICES, torus_configurations
from .square_triangle import (
    F_IMAGE,
    KERNEL,
    UNIT,
    F,
    Lattice2in2,
    Lattice2in4,
    Tile,
    TilingError,
    canonical_form,
    check_tiling,
    tile_corners,
    tile_edges,
    tiling_from_canonical,
    tiling_tiles,
    vadd,
    vsub,
    zmul,
)

__all__ = [
    "chicken_wire_configs", "config_vertex_counts", "config_canonical", "MapError", "config_to_tiling",
    "tiling_to_config", "check_cells", "predicted_failures", "lucas", "failure_kind",
    # re-exported from .square_triangle for convenience
    "UNIT", "F", "F_IMAGE", "KERNEL", "Lattice2in2", "Lattice2in4", "TilingError", "check_tiling", "canonical_form",
    "tiling_from_canonical", "tiling_tiles", "zmul",
]

Site = tuple[int, int]
Config = dict[Site, frozenset[int]]  # site -> occupied bond directions

STEP = BOND_STEPS
VERTEX_SETS = VERTICES
NAME_OF = {v: k for k, v in VERTEX_SETS.items()}


_SQUARE = {
    "H": ((0, -1), 0),
    "R": ((1, -1), 2),
    "L": ((1, 0), 4),
}
_BTRI = {"Y": ((0, 1), 7), "inverted Y": ((1, 0), 5)}


def chicken_wire_configs(L: int, M: int) -> Iterator[Config]:
    """Every configuration of the ``L x M`` torus (:func:`.model.torus_configurations`)."""
    return torus_configurations(L, M)


def config_vertex_counts(config: Config) -> Counter[str]:
    """``Counter`` of vertex names."""
    return Counter(NAME_OF[v] for v in config.values())


def config_canonical(config: Config, torus: Lattice2in2) -> tuple[Any, ...] | None:
    """Canonical form of a configuration up to translations of the torus (min over shifts)."""
    items = [(s, tuple(sorted(v))) for s, v in config.items() if v]
    best = None
    for t in torus.sites():
        key = tuple(sorted((torus.reduce((s[0] - t[0], s[1] - t[1])), v) for s, v in items))
        if best is None or key < best:
            best = key
    return best


class MapError(ArgumentError):
    """The configuration has no image tiling (with the reason)."""


def _site_faces(torus: Lattice2in2, config: Config) -> list[tuple[str, int, Site]]:
    """All faces of the image: list of ``(kind, d, first corner site)``; raise MapError on a non-empty corner."""
    faces = []
    empty = {s for s, v in config.items() if not v}

    def add(kind: str, d: int, s0: Site, why: str) -> None:
        s = s0
        for e in tile_edges(kind, d):
            if s not in empty:
                raise MapError(f"{why}: corner {s} is not an empty site")
            s = torus.reduce((s[0] + F_IMAGE[e][0], s[1] + F_IMAGE[e][1]))
        faces.append((kind, d, s0))

    for s, v in config.items():
        name = NAME_OF[v]
        if name == "empty":
            # A triangles with s as lower-left corner: up (0, 4, 8) at s; down (10, 2, 6) at s
            for d in (0, 10):
                cs, ok = s, True
                for e in tile_edges("T", d):
                    if cs not in empty:
                        ok = False
                        break
                    cs = torus.reduce((cs[0] + F_IMAGE[e][0], cs[1] + F_IMAGE[e][1]))
                if ok:
                    faces.append(("T", d, s))
        elif name in _SQUARE:
            off, d = _SQUARE[name]
            add("S", d, torus.reduce((s[0] + off[0], s[1] + off[1])), f"square of {name} at {s}")
        else:
            off, d = _BTRI[name]
            add("T", d, torus.reduce((s[0] + off[0], s[1] + off[1])), f"B triangle of {name} at {s}")
    return faces


def config_to_tiling(config: Config, torus: Lattice2in2) -> dict[str, Any]:
    """Image of a configuration on ``Z^2 / Gamma``: a combinatorial tiling with lifted positions.

    Returns a dict with
    ``vertices`` (empty sites), ``faces`` (list of ``(kind, d, corner sites)``),
    ``pos`` (site -> position in ``Z[zeta]`` of a lift, base vertex at 0),
    ``periods`` (``P(g1), P(g2)`` in ``Z[zeta]`` for the generators ``g1, g2`` of ``Gamma``),
    ``lattice`` (``Lattice2in4`` of the periods).  Raises ``MapError`` if no image exists
    (a face corner is not empty, or there is no empty site).
    """
    if isinstance(torus, tuple):
        torus = Lattice2in2.rect(*torus)
    vertices = sorted(s for s, v in config.items() if not v)
    if not vertices:
        raise MapError("no empty site: the image has no vertex")
    raw = _site_faces(torus, config)
    faces = []
    out_edges: dict[Site, list[tuple[int, Site]]] = {}  # site -> list of (direction, target site)
    for kind, d, s0 in raw:
        corners, s = [], s0
        for e in tile_edges(kind, d):
            corners.append(s)
            out_edges.setdefault(s, []).append((e, torus.reduce((s[0] + F_IMAGE[e][0], s[1] + F_IMAGE[e][1]))))
            s = torus.reduce((s[0] + F_IMAGE[e][0], s[1] + F_IMAGE[e][1]))
        faces.append((kind, d, tuple(corners)))
    # lift: breadth-first over the face edges, tracking unwrapped lattice coordinates
    g1, g2 = torus.gens
    det = g1[0] * g2[1] - g1[1] * g2[0]
    base = vertices[0]
    pos: dict[Site, tuple[int, ...]] = {base: (0, 0, 0, 0)}
    lat = {base: base}
    records = []
    queue = deque([base])
    while queue:
        u = queue.popleft()
        for e, v in out_edges.get(u, ()):
            lv = (lat[u][0] + F_IMAGE[e][0], lat[u][1] + F_IMAGE[e][1])
            pv = vadd(pos[u], UNIT[e])
            if v not in pos:
                pos[v], lat[v] = pv, lv
                queue.append(v)
            else:
                dl = (lv[0] - lat[v][0], lv[1] - lat[v][1])  # an element of Gamma
                # coordinates in the generators (Cramer)
                w1 = Fraction(dl[0] * g2[1] - dl[1] * g2[0], det)
                w2 = Fraction(g1[0] * dl[1] - g1[1] * dl[0], det)
                if w1.denominator != 1 or w2.denominator != 1:
                    raise TilingError("lattice displacement of a cycle is not a period")
                records.append((int(w1), int(w2), vsub(pv, pos[v])))
    if set(pos) != set(vertices):
        raise MapError(f"the face graph is not connected / misses vertices: {sorted(set(vertices) - set(pos))[:4]}")
    periods = _solve_periods(records)
    return {
        "torus": torus,
        "vertices": vertices,
        "faces": faces,
        "pos": pos,
        "periods": periods,
        "lattice": Lattice2in4(*periods),
    }


def _solve_periods(records: list[tuple[int, int, tuple[int, ...]]]) -> tuple[Any, Any]:
    """Solve ``D = w1 P1 + w2 P2`` for integer ``P1, P2`` from all cycle records and verify every record."""
    pairs = [(r, s) for r in records for s in records if r[0] * s[1] - r[1] * s[0] != 0]
    # find two records whose windings are a basis of Z^2 if possible, else any independent pair
    best = None
    for r, s in pairs:
        dt = r[0] * s[1] - r[1] * s[0]
        if abs(dt) == 1:
            best = (r, s, dt)
            break
        if best is None:
            best = (r, s, dt)
    if best is None:
        raise MapError("cycles do not span the torus homology")
    r, s, dt = best
    P1: tuple[Any, ...] = tuple(Fraction(s[1] * a - r[1] * b, dt) for a, b in zip(r[2], s[2]))
    P2: tuple[Any, ...] = tuple(Fraction(r[0] * b - s[0] * a, dt) for a, b in zip(r[2], s[2]))
    if any(c.denominator != 1 for c in P1 + P2):
        raise TilingError("non-integral period")
    P1, P2 = tuple(int(c) for c in P1), tuple(int(c) for c in P2)
    for w1, w2, D in records:
        if tuple(w1 * a + w2 * b for a, b in zip(P1, P2)) != D:
            raise TilingError("periods are not a homomorphism")
    return P1, P2


def tiling_to_config(tiles: list[Tile], lam: Lattice2in4) -> tuple[Config, Lattice2in2]:
    """The chicken-wire configuration of a tiling of ``R^2 / Lambda`` on the torus ``Z^2 / F(Lambda)``.

    Vertex ``p`` -> empty site ``F(p)``; square -> pass-through site ``F(centre)`` with bonds along its
    A edges; B triangle -> ``F(centre)``, a Y (edges 7, 11, 3) or inverted Y (5, 9, 1).
    Raises :class:`~forcenet.exact.chicken_wire.square_triangle.TilingError` if a site is hit twice or missed, or bonds do not match.
    """
    gamma = lam.image()
    config = {}

    def put(s: Any, v: frozenset[int]) -> None:
        s = gamma.reduce(s)
        if s in config:
            raise TilingError(f"site {s} hit twice")
        config[s] = v

    seen_vertices = set()
    for kind, d, p in tiles:
        corners = tile_corners(kind, d, p)
        for c in corners:
            r = lam.reduce(c)
            if r not in seen_vertices:
                seen_vertices.add(r)
                put(F(c), frozenset())
        if kind == "S":
            edges = tile_edges(kind, d)
            a = next(e for e in edges if e % 2 == 0)  # an A edge direction
            twice = vadd(vadd(corners[0], corners[0]), vadd(UNIT[edges[0]], UNIT[edges[1]]))
            fx, fy = F(twice)
            if fx % 2 or fy % 2:
                raise TilingError(f"the centre of square ({kind}, {d}) at {p} is not a site")
            put((fx // 2, fy // 2), frozenset({(a * 30) % 180, (a * 30) % 180 + 180}))
        elif d % 2 == 1:  # B triangle
            edges = tile_edges(kind, d)
            thrice = vadd(vadd(corners[0], corners[0]), vadd(corners[0], vadd(vadd(UNIT[edges[0]], UNIT[edges[0]]), UNIT[edges[1]])))
            fx, fy = F(thrice)
            if fx % 3 or fy % 3:
                raise TilingError(f"the centre of B triangle ({kind}, {d}) at {p} is not a site")
            y_kind = VERTEX_SETS["Y"] if d in (3, 7, 11) else VERTEX_SETS["inverted Y"]
            put((fx // 3, fy // 3), y_kind)
    sites = gamma.sites()
    if set(config) != set(sites):
        raise TilingError(f"{len(sites) - len(config)} sites not covered")
    for s, v in config.items():  # bond consistency
        for dd in STEP:
            o = gamma.reduce((s[0] + STEP[dd][0], s[1] + STEP[dd][1]))
            if (dd in v) != ((dd + 180) % 360 in config[o]):
                raise TilingError(f"bond mismatch at {s}")
    return config, gamma


def failure_kind(config: Config) -> str:
    """Why a configuration has no tiling: ``"no empty site"``, ``"foam"`` (Y vertices) or ``"lines with spacing 1"``."""
    names = config_vertex_counts(config)
    if names["empty"] == 0:
        return "no empty site"
    if names["Y"] or names["inverted Y"]:
        return "foam"
    return "lines with spacing 1"


def _bounds(points: Collection[Site]) -> tuple[int, int, int, int, int, int]:
    xs = [p[0] for p in points]
    ys = [p[1] for p in points]
    ss = [p[0] + p[1] for p in points]
    return min(xs), max(xs), min(ys), max(ys), min(ss), max(ss)


def _hexagon_points(b: tuple[int, int, int, int, int, int]) -> set[Site]:
    x0, x1, y0, y1, s0, s1 = b
    return {(x, y) for x in range(x0, x1 + 1) for y in range(y0, y1 + 1) if s0 <= x + y <= s1}


def _hexagon_sides(b: tuple[int, int, int, int, int, int]) -> tuple[int, ...]:
    """Side lengths (lattice steps) of the hexagon ``x0<=x<=x1, y0<=y<=y1, s0<=x+y<=s1``, ccw from y = y0."""
    x0, x1, y0, y1, s0, s1 = b
    return (
        min(x1, s1 - y0) - max(x0, s0 - y0),  # y = y0, direction 0
        min(y1, s1 - x1) - max(y0, s0 - x1),  # x = x1, direction 60
        min(x1, s1 - y0) - max(x0, s1 - y1),  # x + y = s1, direction 120
        min(x1, s1 - y1) - max(x0, s0 - y1),  # y = y1, direction 180
        min(y1, s1 - x0) - max(y0, s0 - x0),  # x = x0, direction 240
        min(x1, s0 - y0) - max(x0, s0 - y1),  # x + y = s0, direction 300
    )


def check_cells(config: Config, torus: Lattice2in2) -> list[tuple[Any, Any]]:
    """Check the cell <-> domain statement for a configuration (foam, lines, or empty).

    For a foam: every connected set of empty sites (unwrapped) is exactly the set of lattice points of
    its hexagonal hull ``x0..x1, y0..y1, s0..s1`` (``s = x + y``); the hull widened by one in all six
    directions has the Y / inverted Y vertices at its six corners, pass-through sites along its sides
    (bonds along the side) and side lengths ``a_k = b_k + 1`` where ``b_k >= 0`` are the domain's.
    Returns the list of ``(domain sides, cell sides)``; for non-foams returns ``[]``.
    """
    names = config_vertex_counts(config)
    if not (names["Y"] or names["inverted Y"]):
        return []
    empty = {s for s, v in config.items() if not v}
    seen, out = set(), []
    for start in sorted(empty):
        if start in seen:
            continue
        comp, unwrapped, queue = {start: start}, {start}, deque([start])
        seen.add(start)
        while queue:
            u = queue.popleft()
            for dx, dy in STEP.values():
                w = (comp[u][0] + dx, comp[u][1] + dy)
                r = torus.reduce(w)
                if r in empty:
                    if r not in comp:
                        comp[r] = w
                        unwrapped.add(w)
                        seen.add(r)
                        queue.append(r)
                    else:
                        if comp[r] != w:
                            raise TilingError("a cell wraps around the torus")
        b = _bounds(unwrapped)
        if unwrapped != _hexagon_points(b):
            raise TilingError("domain is not a full lattice hexagon")
        inner = _hexagon_sides(b)
        B = (b[0] - 1, b[1] + 1, b[2] - 1, b[3] + 1, b[4] - 1, b[5] + 1)
        outer = _hexagon_sides(B)
        if any(k < 0 for k in inner) or any(a != k + 1 for a, k in zip(outer, inner)):
            raise TilingError(f"cell sides {outer} are not the domain sides {inner} plus one")
        ring = _hexagon_points(B) - unwrapped
        for p in ring:
            v = config[torus.reduce(p)]
            on = [B[0] == p[0], B[1] == p[0], B[2] == p[1], B[3] == p[1], B[4] == p[0] + p[1], B[5] == p[0] + p[1]]
            if sum(on) == 2:
                if NAME_OF[v] not in ("Y", "inverted Y"):
                    raise TilingError("a cell corner is not a Y")
            else:
                if sum(on) != 1:
                    raise TilingError(f"ring point {p} is on {sum(on)} sides of the cell")
                k = on.index(True)
                if v != VERTEX_SETS[("R", "R", "H", "H", "L", "L")[k]]:
                    raise TilingError("a cell side is not a straight wall")
        out.append((inner, outer))
    return out


def lucas(k: int) -> int:
    """Lucas numbers ``L(1) = 1, L(2) = 3``: nonempty-or-empty independent sets of a k-cycle."""
    a, b = 2, 1  # L(0), L(1)
    for _ in range(k - 1):
        a, b = b, a + b
    return b if k >= 1 else a


def predicted_failures(L: int, M: int) -> int:
    """Number of configurations of the ``L x M`` torus outside the map: parallel lines, two of them adjacent.

    Per direction there are ``k`` parallel closed lines (``k = M, L, gcd(L, M)`` for directions
    0, 60, 120) arranged on a cycle; the configurations using that direction are the nonempty
    subsets of lines, and those without two cyclically adjacent lines number ``lucas(k) - 1``
    (for ``k = 1`` the single line is its own neighbour).  Total ``sum_d 2^k - lucas(k)``.
    """
    return sum(2 ** k - lucas(k) for k in (M, L, gcd(L, M)))
