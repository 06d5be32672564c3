"""Hexagon shrink/expand Monte Carlo of the chicken-wire model (Sec. 7.4.1, Fig. 7.8).

A configuration on the ``L x M`` torus (lattice of :mod:`forcenet.exact.chicken_wire.model`)
is stored as the set of occupied bond directions at every site.  A move picks
one of the hexagonal cells uniformly and shrinks or expands it by one lattice
unit (probability 1/2 each): its six corners step along their outgoing walls,
inwards or outwards, its sides shorten or lengthen by one, and the six
outgoing walls lengthen or shorten by one.  A move that would produce a
vertex outside the six of Fig. 7.7 is rejected.  The number of hexagons is
conserved and the proposal is symmetric (the reverse move undoes it), so
every configuration of the chain's connected component is equally likely.

Examples
--------
>>> len(ChickenWire.honeycomb(6, 6, side=1).hexagons())  # jammed: no move is possible
12
>>> cw = ChickenWire.honeycomb(12, 12, side=2)
>>> mc = HexagonMonteCarlo(cw, seed=1)
>>> chain = mc.run(100)
>>> chain.shape, 0.1 < mc.accepted / mc.attempted < 0.5
((100, 2), True)
"""

from __future__ import annotations

import numpy as np

from forcenet.core.errors import ArgumentError

Site = tuple[int, int]  # (x, y) on the L x M torus

__all__ = ["ChickenWire", "HexagonMonteCarlo", "component"]

STEP = {0: (1, 0), 60: (0, 1), 120: (-1, 1), 180: (-1, 0), 240: (0, -1), 300: (1, -1)}
ALLOWED = {
    frozenset(),
    frozenset({0, 120, 240}),
    frozenset({60, 180, 300}),
    frozenset({0, 180}),
    frozenset({60, 240}),
    frozenset({120, 300}),
}


class ChickenWire:
    """A chicken-wire configuration on the ``L x M`` torus.

    ``occ[(x, y)]`` is the frozenset of occupied bond directions at the site.
    """

    def __init__(self, L: int, M: int, occ: dict) -> None:
        self.L, self.M = L, M
        self.occ = {(x, y): frozenset(occ.get((x, y), ())) for x in range(L) for y in range(M)}
        bad = self.invalid_sites()
        if bad:
            raise ArgumentError(f"not a chicken-wire configuration: sites {sorted(bad)[:4]} have forbidden vertices")

    def shift(self, s: Site, d: int, k: int = 1) -> Site:
        dx, dy = STEP[d]
        return ((s[0] + k * dx) % self.L, (s[1] + k * dy) % self.M)

    def invalid_sites(self) -> list[Site]:
        bad = []
        for s, v in self.occ.items():
            if v not in ALLOWED or any((d + 180) % 360 not in self.occ[self.shift(s, d)] for d in v):
                bad.append(s)
        return bad

    def key(self) -> tuple[tuple[Site, tuple[int, ...]], ...]:
        return tuple(sorted((s, tuple(sorted(v))) for s, v in self.occ.items() if v))

    @classmethod
    def honeycomb(cls, L: int, M: int, side: int = 1) -> ChickenWire:
        """The regular foam of hexagons of the given side (needs ``3 side | L, M``)."""
        period = 3 * side
        if L % period or M % period:
            raise ArgumentError(f"L={L}, M={M}: a honeycomb of side {side} needs L and M divisible by {period}")
        occ: dict[tuple[int, int], set[int]] = {}

        def add(s: Site, d: int) -> None:
            occ.setdefault(s, set()).add(d)
            dx, dy = STEP[d]
            t = ((s[0] + dx) % L, (s[1] + dy) % M)
            occ.setdefault(t, set()).add((d + 180) % 360)

        # corners: Y at (x, y) with x - y = side (mod 3 side), inverted Y at x - y = 2 side
        for x in range(L):
            for y in range(M):
                if (x - y) % period == side % period and (x // side * side == x) and (y // side * side == y):
                    for d in (0, 120, 240):  # walls of length side from each Y
                        s = (x, y)
                        for _ in range(side):
                            add(s, d)
                            dx, dy = STEP[d]
                            s = ((s[0] + dx) % L, (s[1] + dy) % M)
        return cls(L, M, occ)

    def cells(self) -> list[frozenset[Site]]:
        """Interiors of the cells: connected components of empty sites."""
        seen, out = set(), []
        for s, v in self.occ.items():
            if v or s in seen:
                continue
            comp, stack = set(), [s]
            seen.add(s)
            while stack:
                u = stack.pop()
                comp.add(u)
                for d in STEP:
                    w = self.shift(u, d)
                    if not self.occ[w] and w not in seen:
                        seen.add(w)
                        stack.append(w)
            out.append(frozenset(comp))
        return out

    def _corners(self, interior: frozenset[Site]) -> list[tuple[Site, int]] | None:
        """The six corners of a hexagonal cell in order, with the side direction leaving each; None if not a hexagon."""
        boundary = {self.shift(s, d) for s in interior for d in STEP} - set(interior)
        corners = [c for c in boundary if len(self.occ[c]) == 3]
        if len(corners) != 6:
            return None
        start = corners[0]
        sides = [d for d in self.occ[start] if self.shift(start, d) in boundary]
        if len(sides) != 2:
            return None
        order, d, c = [], sides[0], start
        for _ in range(6):
            order.append((c, d))
            s, length = self.shift(c, d), 1
            while len(self.occ[s]) == 2:
                s, length = self.shift(s, d), length + 1
                if length > self.L * self.M:
                    return None
            nxt = [e for e in self.occ[s] if e != (d + 180) % 360 and self.shift(s, e) in boundary]
            if len(nxt) != 1:
                return None
            c, d = s, nxt[0]
        if c != start:
            return None
        return order

    def hexagons(self) -> list[list[tuple[Site, int]]]:
        """The hexagonal cells (computed once: a configuration is immutable)."""
        if getattr(self, "_hexagons", None) is None:
            self._hexagons = [h for h in (self._corners(i) for i in self.cells()) if h is not None]
        return self._hexagons

    def moved(self, hexagon: list[tuple[Site, int]], grow: bool) -> ChickenWire | None:
        """The configuration with one hexagon expanded (``grow``) or shrunk; None if not allowed."""
        occ = {s: set(v) for s, v in self.occ.items()}

        def toggle(s: Site, d: int, on: bool) -> None:
            t = self.shift(s, d)
            (occ[s].add if on else occ[s].discard)(d)
            (occ[t].add if on else occ[t].discard)((d + 180) % 360)

        new_corners = []
        for c, d in hexagon:  # remove the old sides
            s = c
            while True:
                toggle(s, d, False)
                s = self.shift(s, d)
                if len(self.occ[s]) == 3:
                    break
        for k, (c, d) in enumerate(hexagon):
            prev = hexagon[k - 1][1]  # side arriving at c runs along prev
            out = ({0, 60, 120, 180, 240, 300} - {d, (prev + 180) % 360}) & self.occ[c]
            (o,) = out
            if grow:  # corner retracts along its outgoing wall
                if len(self.occ[self.shift(c, o)]) != 2:
                    return None
                toggle(c, o, False)
                new_corners.append(self.shift(c, o))
            else:  # corner advances inwards, the outgoing wall lengthens
                inward = (o + 180) % 360
                toggle(c, inward, True)
                new_corners.append(self.shift(c, inward))
        for k, (_, d) in enumerate(hexagon):  # the new sides
            s, target, steps = new_corners[k], new_corners[(k + 1) % 6], 0
            while s != target:
                toggle(s, d, True)
                s = self.shift(s, d)
                steps += 1
                if steps > self.L + self.M:
                    return None
            if steps == 0:
                return None
        frozen = {s: frozenset(v) for s, v in occ.items()}
        for v in frozen.values():
            if v not in ALLOWED:
                return None
        new = ChickenWire.__new__(ChickenWire)
        new.L, new.M, new.occ = self.L, self.M, frozen
        if new.invalid_sites() or len(new.hexagons()) != len(self.hexagons()):
            return None
        return new

    def observables(self) -> np.ndarray:
        """``(sum of squared cell interiors, number of minimal hexagons)``."""
        cells = self.cells()
        minimal = sum(1 for c in cells if len(c) == 1)
        return np.array([sum(len(c) ** 2 for c in cells), minimal], dtype=float)


class HexagonMonteCarlo:
    """Metropolis chain of shrink/expand moves (all configurations weigh the same)."""

    def __init__(self, config: ChickenWire, seed: int | np.random.Generator | None = None) -> None:
        self.state = config
        self.rng = np.random.default_rng(seed)
        self.accepted = self.attempted = 0

    def step(self) -> None:
        hexes = self.state.hexagons()
        if not hexes:
            raise ArgumentError("the configuration has no hexagonal cell to move")
        h = hexes[self.rng.integers(len(hexes))]
        new = self.state.moved(h, grow=bool(self.rng.integers(2)))
        self.attempted += 1
        if new is not None:
            self.state = new
            self.accepted += 1

    def run(self, sweeps: int, burn_in: int = 0) -> np.ndarray:
        """Record :meth:`ChickenWire.observables` after each sweep (one move per hexagon)."""
        n = len(self.state.hexagons())
        for _ in range(burn_in * n):
            self.step()
        out = np.empty((sweeps, 2))
        for t in range(sweeps):
            for _ in range(n):
                self.step()
            out[t] = self.state.observables()
        return out


def component(config: ChickenWire, limit: int = 200_000) -> list[ChickenWire]:
    """All configurations reachable by shrink/expand moves (breadth-first), as a list."""
    seen = {config.key(): config}
    frontier = [config]
    while frontier:
        nxt = []
        for c in frontier:
            for h in c.hexagons():
                for grow in (False, True):
                    new = c.moved(h, grow)
                    if new is not None and new.key() not in seen:
                        seen[new.key()] = new
                        nxt.append(new)
                        if len(seen) > limit:
                            raise ArgumentError(f"component larger than limit={limit}")
        frontier = nxt
    return list(seen.values())
