"""An independent enumerator of square-triangle tilings of a torus ``R^2 / Lambda``.

It fills the angular gaps at the vertices of ``Z[zeta_12] / Lambda`` one tile
at a time (backtracking, canonical forms up to translation) and knows nothing
of the chicken-wire model: it uses only :mod:`.square_triangle` (the
arithmetic of ``Z[zeta_12]`` and the tile geometry), so that the tests can
count both sides of the correspondence independently.  Exponential; tori
with up to ~40 vertices.  :func:`scan_lifts` runs it on every period lattice
over a torus of the chicken-wire lattice; the comparison with the
correspondence, torus by torus, is ``benchmarks/tiling_survey.py`` (not installed).
"""

from __future__ import annotations

from itertools import product
from typing import Any

from .square_triangle import (
    KERNEL,
    Lattice2in2,
    Lattice2in4,
    Tile,
    canonical_form,
    corner_sectors,
    f_preimage,
    tile_corners,
    vadd,
)

__all__ = ["enumerate_tilings", "lifts", "scan_lifts"]


def enumerate_tilings(lam: Lattice2in4, limit: int | None = None) -> tuple[int, dict[tuple[Tile, ...], int]]:
    """All edge-to-edge square-triangle tilings of ``R^2 / Lambda`` with a vertex at 0.

    Backtracking on vertices of ``Z[zeta] / Lambda``: every vertex keeps a 12-bit mask of covered
    30-degree sectors; the vertex whose first uncovered run of sectors is shortest is filled at the
    start of that run with a triangle or a square (a run of one sector is a dead end).  The numbers
    of squares and triangles are bounded by the area of ``Lambda`` (``N_s + N_t sqrt3/4``), so a
    completed surface (all masks full) has exactly the area of the torus: the developing map is a
    degree-one covering, i.e. a genuine tiling.

    Returns ``(raw, classes)``: ``raw`` the number of tilings with a vertex at 0 (each translation
    class counted ``V / |stabilizer|`` times), ``classes`` a dict ``canonical form -> stabilizer``.
    Uses nothing of the chicken-wire construction.
    """
    tn = lam.tile_numbers()
    if tn is None:
        return 0, {}
    NS, NT = tn
    NV = NT // 2 + NS
    if NT % 2 or NV == 0:
        return 0, {}
    masks: dict[tuple[int, ...], int] = {}
    order = []  # vertices in creation order
    tiles = []
    counts = {"T": 0, "S": 0}
    result = {"raw": 0}
    classes = {}
    FULL = 4095
    limits = {"T": NT, "S": NS}

    def first_gap(m: int) -> tuple[int, int] | None:
        """(start, length) of the first free run that follows an occupied sector; None if full."""
        if m == FULL:
            return None
        for j in range(12):
            if not (m >> j) & 1 and (m >> ((j - 1) % 12)) & 1:
                length = 0
                while length < 12 and not (m >> ((j + length) % 12)) & 1:
                    length += 1
                return j, length
        return 0, 12  # empty mask

    def place(kind: str, d: int, p: tuple[int, ...]) -> Any:
        """Try to place a tile; return the undo record or None."""
        if counts[kind] >= limits[kind]:
            return None
        corners = [lam.reduce(c) for c in tile_corners(kind, d, p)]
        secs = corner_sectors(kind, d)
        added: dict[tuple[int, ...], int] = {}
        new: list[tuple[int, ...]] = []
        for c, m in zip(corners, secs):
            cur = masks.get(c, 0) | added.get(c, 0)
            if c not in masks and c not in added and len(masks) + len(new) + 1 > NV:
                return None
            if cur & m:
                return None
            if c not in masks and c not in added:
                new.append(c)
            added[c] = added.get(c, 0) | m
        for c in new:
            masks[c] = 0
            order.append(c)
        for c, m in added.items():
            masks[c] |= m
        counts[kind] += 1
        tiles.append((kind, d, corners[0]))
        return added, new

    def undo(rec: Any, kind: str) -> None:
        added, new = rec
        tiles.pop()
        counts[kind] -= 1
        for c, m in added.items():
            masks[c] &= ~m
        for c in reversed(new):
            del masks[c]
            order.pop()

    def rec() -> None:
        if limit is not None and result["raw"] >= limit:
            return
        best = None
        for v in order:
            g = first_gap(masks[v])
            if g is None:
                continue
            if g[1] < 2:
                return  # a 30-degree hole cannot be filled
            if best is None or g[1] < best[1][1]:
                best = (v, g)
                if g[1] <= 3:
                    break
        if best is None:
            if counts["T"] == NT and counts["S"] == NS and len(masks) == NV:
                result["raw"] += 1
                form, mult = canonical_form(tiles, lam)
                classes[form] = mult
            return
        v, (j, length) = best
        options = []
        if length == 12:  # the initial empty vertex: every tile covering sector 0
            options = [("T", 0), ("T", 11), ("S", 0), ("S", 11), ("S", 10)]
        else:
            options = [("T", j), ("S", j)]
        for kind, d in options:
            r = place(kind, d, v)
            if r is not None:
                rec()
                undo(r, kind)

    zero = lam.reduce((0, 0, 0, 0))
    masks[zero] = 0
    order.append(zero)
    rec()
    return result["raw"], classes


def lifts(gamma: Lattice2in2, bound: int) -> set[Lattice2in4]:
    """Period lattices ``Lambda`` with ``F(Lambda) = Gamma``: ``P_i = A(g_i) + m . KERNEL``, ``|m_j| <= bound``."""
    g1, g2 = gamma.gens
    out = set()
    for m in product(range(-bound, bound + 1), repeat=4):
        P1 = vadd(vadd(f_preimage(g1), tuple(m[0] * c for c in KERNEL[0])), tuple(m[1] * c for c in KERNEL[1]))
        P2 = vadd(vadd(f_preimage(g2), tuple(m[2] * c for c in KERNEL[0])), tuple(m[3] * c for c in KERNEL[1]))
        try:
            out.add(Lattice2in4(P1, P2))
        except ValueError:
            pass
    return out


def scan_lifts(L: int, M: int, bound: int, vmax: int) -> tuple[dict[Lattice2in4, int], int]:
    """Run the tiler on every lift ``Lambda`` of the ``L x M`` torus from ``lifts(.., bound)`` with ``V <= vmax``.

    Returns ``{Lambda: number of tiling classes}`` for the lattices that carry at least one tiling,
    and the number of lattices tried.  Independent of the chicken-wire enumeration.
    """
    gamma = Lattice2in2.rect(L, M)
    found, tried = {}, 0
    for lam in lifts(gamma, bound):
        tn = lam.tile_numbers()
        if tn is None or tn[1] % 2:
            continue
        V = tn[1] // 2 + tn[0]
        if V == 0 or V > vmax:
            continue
        tried += 1
        raw, classes = enumerate_tilings(lam)
        if classes:
            found[lam] = len(classes)
    return found, tried
