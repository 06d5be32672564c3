"""Square-triangle tilings of a torus, on their own: ``Z[zeta_12]`` arithmetic, period lattices, tiles.

``Z[zeta]`` with ``zeta = exp(i pi/6)`` is stored as integer 4-tuples in the
basis ``1, z, z^2, z^3`` (``z^4 = z^2 - 1``); ``UNIT[k] = z^k`` is the unit
edge of direction ``30 k`` degrees (``k`` even: family A, the chicken-wire
lattice directions; ``k`` odd: family B).  A tile is its type (``"T"``
triangle, ``"S"`` square), the position of one corner and the direction of
the edge leaving that corner counterclockwise.  A tiling of the torus
``R^2 / Lambda`` is edge-to-edge with unit edges in the twelve directions.
:func:`check_tiling` validates one (angles, edges, Euler characteristic,
area); :func:`canonical_form` identifies it up to translation.

``F: Z[zeta] -> Z^2`` sends ``z^k`` to the lattice vector of direction ``30 k``
and length 1 (``k`` even) or ``sqrt3`` (``k`` odd): the linear map behind the
correspondence with the chicken-wire model (:mod:`.tiling`).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from fractions import Fraction
from typing import Any

from forcenet.core.errors import ArgumentError, ForcenetError

__all__ = [
    "zmul", "TilingError", "UNIT", "F", "F_IMAGE", "vadd", "vsub", "phys", "area", "Lattice2in4", "Lattice2in2",
    "TILE_STEPS", "tile_edges", "tile_corners", "corner_sectors", "family", "check_tiling", "canonical_form",
    "tiling_tiles", "tiling_from_canonical", "f_preimage", "KERNEL", "Vec4", "Vec2", "Vec", "Tile",
]

Vec4 = tuple[int, ...]  # four integers: an element of Z[zeta_12] in the basis 1, z, z^2, z^3
Vec2 = tuple[int, ...]  # two integers: a vector of the chicken-wire lattice
Vec = tuple[int, ...]
Tile = tuple[str, int, tuple[int, ...]]  # (kind, direction of the first edge, first corner)

# ----------------------------------------------------------------------------------------------
# Z[zeta_12] arithmetic
# ----------------------------------------------------------------------------------------------


def zmul(p: Vec4) -> Vec4:
    """Multiply ``p`` (coordinates in ``1, z, z^2, z^3``) by ``z`` (rotation by 30 degrees)."""
    a0, a1, a2, a3 = p
    return (-a3, a0, a1 + a3, a2)


def _units() -> tuple[Vec4, ...]:
    out, p = [], (1, 0, 0, 0)  # type: list[Vec4], Vec4
    for _ in range(12):
        out.append(p)
        p = zmul(p)
    return tuple(out)


class TilingError(ForcenetError):
    """A check of the chicken-wire <-> square-triangle correspondence failed (the object is not what it claims)."""


UNIT = _units()  # UNIT[k] = z^k
if UNIT[6] != (-1, 0, 0, 0) or zmul(UNIT[11]) != UNIT[0]:  # a self-check of the constant, at import
    raise ArithmeticError("UNIT is not the twelfth roots of unity")

_F_BASIS = ((1, 0), (1, 1), (0, 1), (-1, 2))  # F(1), F(z), F(z^2), F(z^3)


def F(p: Vec4) -> Vec2:
    """The projection ``Z[zeta] -> Z^2`` (lattice coordinates): B directions stretched by ``sqrt 3``."""
    return (sum(c * b[0] for c, b in zip(p, _F_BASIS)), sum(c * b[1] for c, b in zip(p, _F_BASIS)))


F_IMAGE = tuple(F(u) for u in UNIT)  # lattice displacement of a tile edge of direction k


def vadd(p: Vec, q: Vec) -> Vec:
    return tuple(a + b for a, b in zip(p, q))


def vsub(p: Vec, q: Vec) -> Vec:
    return tuple(a - b for a, b in zip(p, q))


def phys(p: Vec4) -> tuple[tuple[Fraction, Fraction], tuple[Fraction, Fraction]]:
    """Physical coordinates of ``p`` as ``((x_rat, x_sqrt3), (y_rat, y_sqrt3))``: ``x = x_rat + x_sqrt3 sqrt 3``."""
    a0, a1, a2, a3 = (Fraction(c) for c in p)
    # z = (sqrt3/2, 1/2), z^2 = (1/2, sqrt3/2), z^3 = (0, 1)
    return ((a0 + a2 / 2, a1 / 2), (a1 / 2 + a3, a2 / 2))


def _qmul(u: tuple[Fraction, Fraction], v: tuple[Fraction, Fraction]) -> tuple[Fraction, Fraction]:
    return (u[0] * v[0] + 3 * u[1] * v[1], u[0] * v[1] + u[1] * v[0])


def area(p: Vec4, q: Vec4) -> tuple[Fraction, Fraction]:
    """Signed physical area ``p x q`` as ``(r, s)`` meaning ``r + s sqrt 3`` (exact)."""
    (px, py), (qx, qy) = phys(p), phys(q)
    a, b = _qmul(px, qy), _qmul(py, qx)
    return (a[0] - b[0], a[1] - b[1])


def _qsign(u: tuple[Fraction, Fraction]) -> int:
    """Sign of ``u[0] + u[1] sqrt 3`` (exact)."""
    r, s = u
    if s == 0:
        return (r > 0) - (r < 0)
    if r == 0 or (r > 0) == (s > 0):
        return 1 if (r > 0 or (r == 0 and s > 0)) else -1
    # opposite signs: compare r^2 with 3 s^2
    big = (r * r > 3 * s * s)
    return (1 if r > 0 else -1) if big else (1 if s > 0 else -1)


# ----------------------------------------------------------------------------------------------
# lattices and reduction
# ----------------------------------------------------------------------------------------------


def _xgcd(a: int, b: int) -> tuple[int, int, int]:
    if b == 0:
        return (abs(a), 1 if a >= 0 else -1, 0)
    g, x, y = _xgcd(b, a % b)
    return (g, y, x - (a // b) * y)


def _hnf2(r1: Sequence[int], r2: Sequence[int]) -> tuple[tuple[Vec, Vec], tuple[int, int]]:
    """Hermite normal form of two integer row vectors (rank 2 required): ``(rows, pivots)``."""
    r1, r2 = list(r1), list(r2)
    n = len(r1)
    c1 = next((c for c in range(n) if r1[c] or r2[c]), None)
    if c1 is None:
        raise ArgumentError("rank 0")
    g, x, y = _xgcd(r1[c1], r2[c1])
    a, b = r1[c1] // g, r2[c1] // g
    n1 = [x * u + y * v for u, v in zip(r1, r2)]
    n2 = [-b * u + a * v for u, v in zip(r1, r2)]  # determinant x a + y b = 1
    c2 = next((c for c in range(c1 + 1, n) if n2[c]), None)
    if c2 is None:
        raise ArgumentError(f"rank < 2: {r1}, {r2}")
    if n2[c2] < 0:
        n2 = [-u for u in n2]
    q = n1[c2] // n2[c2]
    n1 = [u - q * v for u, v in zip(n1, n2)]
    return (tuple(n1), tuple(n2)), (c1, c2)


class _Lattice:
    """A rank-2 sublattice of ``Z^n`` (n = 2 or 4) with a canonical reduction of ``Z^n`` modulo it."""

    def __init__(self, p1: Vec, p2: Vec) -> None:
        (self.b1, self.b2), (self.c1, self.c2) = _hnf2(p1, p2)
        self.gens = (tuple(p1), tuple(p2))

    def reduce(self, p: Vec) -> Any:
        """The canonical representative of ``p`` modulo the lattice."""
        q = p[self.c1] // self.b1[self.c1]
        p = tuple(u - q * v for u, v in zip(p, self.b1))
        q = p[self.c2] // self.b2[self.c2]
        return tuple(u - q * v for u, v in zip(p, self.b2))

    def contains(self, p: Vec) -> bool:
        return not any(self.reduce(p))

    def key(self) -> tuple[Vec, Vec]:
        return (self.b1, self.b2)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, _Lattice) and self.key() == other.key()

    def __hash__(self) -> int:
        return hash(self.key())

    def __repr__(self) -> str:
        return f"{type(self).__name__}{self.key()}"


class Lattice2in4(_Lattice):
    """A period lattice ``Lambda`` of a tiling: rank 2 in ``Z[zeta] = Z^4``."""

    def area(self) -> tuple[Fraction, Fraction]:
        """Physical area ``(r, s)``, ``r + s sqrt3 > 0``."""
        a = area(self.b1, self.b2)
        return a if _qsign(a) > 0 else (-a[0], -a[1])

    def tile_numbers(self) -> tuple[int, int] | None:
        """``(N_squares, N_triangles)`` forced by the area ``N_s + N_t sqrt3 / 4`` (None if impossible)."""
        r, s = self.area()
        if r.denominator != 1 or (4 * s).denominator != 1 or r < 0 or s < 0:
            return None
        return int(r), int(4 * s)

    def image(self) -> Lattice2in2:
        """``F(Lambda)``: the chicken-wire torus of every tiling of this torus."""
        return Lattice2in2(F(self.gens[0]), F(self.gens[1]))


class Lattice2in2(_Lattice):
    """A chicken-wire torus ``Z^2 / Gamma``."""

    def sites(self) -> list[tuple[int, int]]:
        """Canonical representatives of ``Z^2 / Gamma`` (``|det|`` of them)."""
        return [(x, y) for x in range(self.b1[0]) for y in range(self.b2[1])]

    def det(self) -> int:
        return abs(self.b1[0] * self.b2[1])

    @classmethod
    def rect(cls, L: int, M: int) -> Lattice2in2:
        return cls((L, 0), (0, M))


# ----------------------------------------------------------------------------------------------
# tiles
# ----------------------------------------------------------------------------------------------

TILE_STEPS = {"T": (0, 4, 8), "S": (0, 3, 6, 9)}


def tile_edges(kind: str, d: int) -> tuple[int, ...]:
    """Edge directions of a tile, counterclockwise, starting with ``d``."""
    return tuple((d + s) % 12 for s in TILE_STEPS[kind])


def tile_corners(kind: str, d: int, p: Vec4) -> list[Vec4]:
    """Corners (unreduced positions in ``Z[zeta]``) of the tile, the first at ``p``."""
    out = [tuple(p)]
    for e in tile_edges(kind, d)[:-1]:
        out.append(vadd(out[-1], UNIT[e]))
    return out


def corner_sectors(kind: str, d: int) -> list[int]:
    """For each corner, the bitmask of the 30-degree sectors it covers."""
    edges = tile_edges(kind, d)
    out = []
    for i, e in enumerate(edges):
        incoming_back = (edges[i - 1] + 6) % 12
        m, k = 0, e
        while k != incoming_back:
            m |= 1 << k
            k = (k + 1) % 12
        out.append(m)
    return out


def _canonical_start(kind: str, d: int) -> int:
    """Index of the corner used as the tile's reference (its outgoing direction is < 4 or < 3)."""
    edges = tile_edges(kind, d)
    bound = 4 if kind == "T" else 3
    (i,) = [i for i, e in enumerate(edges) if e < bound]
    return i


def family(kind: str, d: int) -> str:
    """``"A"`` / ``"B"`` for triangles (parity of the edge directions), ``"S"`` for squares."""
    if kind == "S":
        return "S"
    return "A" if d % 2 == 0 else "B"


# ----------------------------------------------------------------------------------------------
# chicken-wire configurations
# ----------------------------------------------------------------------------------------------



def check_tiling(t: dict[str, Any]) -> dict[str, int]:
    """Check that a combinatorial tiling (as returned by ``config_to_tiling``) is a tiling of the torus.

    Verified: every face's corners close up; at every vertex the face corners cover the twelve
    30-degree sectors exactly once (angle sum 360); every directed edge ``(u, k)`` occurs once and its
    reverse ``(u + k, k + 6)`` occurs too (each edge in exactly two faces); Euler characteristic
    ``V - E + F = 0``; the tile area ``N_s + N_t sqrt3/4`` equals the area of the period lattice
    (so the developing map is a degree-one covering: a genuine edge-to-edge tiling); ``F`` of the
    periods generates ``Gamma``.  Returns a summary dict; raises :class:`TilingError` (a
    :class:`forcenet.ForcenetError`) naming the first check that fails, also under ``python -O``.
    """
    torus = t["torus"]
    masks = {v: 0 for v in t["vertices"]}
    directed: Counter[tuple[tuple[int, ...], int]] = Counter()
    for kind, d, corners in t["faces"]:
        edges = tile_edges(kind, d)
        secs = corner_sectors(kind, d)
        for c, e, m in zip(corners, edges, secs):
            if masks[c] & m:
                raise TilingError(f"overlapping corners at {c}")
            masks[c] |= m
            directed[(c, e)] += 1
        # closure in Z[zeta]
        if tile_corners(kind, d, (0, 0, 0, 0))[-1] != vsub((0, 0, 0, 0), UNIT[edges[-1]]):
            raise TilingError(f"the corners of face ({kind}, {d}) do not close up")
    if any(m != 4095 for m in masks.values()):
        raise TilingError("angle sum != 360 somewhere")
    if max(directed.values()) != 1:
        raise TilingError("a directed edge used twice")
    for (u, e) in directed:
        v = torus.reduce((u[0] + F_IMAGE[e][0], u[1] + F_IMAGE[e][1]))
        if (v, (e + 6) % 12) not in directed:
            raise TilingError("an edge with a single face")
    V, E, Fn = len(t["vertices"]), len(directed) // 2, len(t["faces"])
    if V - E + Fn != 0:
        raise TilingError("Euler characteristic != 0")
    lam = t["lattice"]
    ns = sum(1 for f in t["faces"] if f[0] == "S")
    nt = Fn - ns
    if lam.tile_numbers() != (ns, nt):
        raise TilingError(f"area mismatch: {lam.area()} vs Ns={ns}, Nt={nt}")
    if lam.image() != Lattice2in2(*torus.gens):
        raise TilingError("F(Lambda) != Gamma")
    # positions are consistent with the face edges modulo Lambda
    for kind, d, corners in t["faces"]:
        for c, e in zip(corners, tile_edges(kind, d)):
            nxt = torus.reduce((c[0] + F_IMAGE[e][0], c[1] + F_IMAGE[e][1]))
            if not lam.contains(vsub(vadd(t["pos"][c], UNIT[e]), t["pos"][nxt])):
                raise TilingError(f"the positions of {c} and {nxt} differ by more than edge {e} modulo Lambda")
    nA = sum(1 for f in t["faces"] if f[0] == "T" and f[1] % 2 == 0)
    return {"V": V, "E": E, "F": Fn, "N_s": ns, "N_tA": nA, "N_tB": nt - nA}


def canonical_form(tiles: list[Tile], lam: Lattice2in4) -> tuple[Any, int]:
    """Canonical form of a tiling of ``R^2 / Lambda`` up to translation.

    ``tiles``: iterable of ``(kind, d, position of the corner where edge d starts)``.
    Each tile is rewritten from its reference corner (outgoing direction < 4 for triangles,
    < 3 for squares); the form is the lexicographically smallest sorted tuple over all
    translations taking a vertex to 0.  Returns ``(form, number of vertices achieving it)``
    (the latter is the order of the tiling's translation group modulo ``Lambda``).
    """
    norm: list[Tile] = []
    verts: set[tuple[int, ...]] = set()
    for kind, d, p in tiles:
        corners = tile_corners(kind, d, p)
        i = _canonical_start(kind, d)
        norm.append((kind, tile_edges(kind, d)[i], corners[i]))
        verts.update(lam.reduce(c) for c in corners)
    best, mult = None, 0
    for v in verts:
        key = tuple(sorted((k, e, lam.reduce(vsub(p, v))) for k, e, p in norm))
        if best is None or key < best:
            best, mult = key, 1
        elif key == best:
            mult += 1
    return best, mult


def tiling_tiles(t: dict[str, Any]) -> list[Tile]:
    """The tiles of a mapped tiling as ``(kind, d, lifted position of the first corner)``."""
    return [(kind, d, t["pos"][corners[0]]) for kind, d, corners in t["faces"]]


def tiling_from_canonical(form: tuple[Tile, ...]) -> list[Tile]:
    """Tiles from a canonical form."""
    return [(k, e, p) for k, e, p in form]


def f_preimage(g: Vec2) -> Vec4:
    """An element of ``Z[zeta]`` with ``F = g`` (A directions only).

    Examples
    --------
    >>> F(f_preimage((2, -3)))
    (2, -3)
    """
    x, y = g
    return (x, 0, y, 0)


KERNEL = ((-1, 1, -1, 0), (1, 0, -2, 1))  # a basis of ker F
if any(F(k) != (0, 0) for k in KERNEL):  # a self-check of the constant, at import
    raise ArithmeticError("KERNEL is not in the kernel of F")
