"""An independent enumerator of square-triangle tilings of a torus ``R^2 / Lambda``.

It fills the angular gaps at the vertices of ``Z[zeta_12] / Lambda`` one tile
at a time (backtracking, canonical forms up to translation) and knows nothing
of the chicken-wire model: it uses only :mod:`.square_triangle` (the
arithmetic of ``Z[zeta_12]`` and the tile geometry), so that the tests can
count both sides of the correspondence independently.  Exponential; tori
with up to ~40 vertices.

:func:`survey` and :func:`scan_lifts` then compare both sides of the
correspondence (:mod:`.tiling`) torus by torus.

May import: :mod:`.square_triangle` (the enumerator); :mod:`.tiling` (the survey only).
"""

from __future__ import annotations

from itertools import product

from .square_triangle import KERNEL, Lattice2in4, _f_preimage, canonical_form, corner_sectors, tile_corners, vadd

__all__ = ["enumerate_tilings", "lifts", "survey", "scan_lifts"]


def enumerate_tilings(lam, limit=None):
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
    masks = {}
    order = []  # vertices in creation order
    tiles = []
    counts = {"T": 0, "S": 0}
    result = {"raw": 0}
    classes = {}
    FULL = 4095
    limits = {"T": NT, "S": NS}

    def first_gap(m):
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

    def place(kind, d, p):
        """Try to place a tile; return the undo record or None."""
        if counts[kind] >= limits[kind]:
            return None
        corners = [lam.reduce(c) for c in tile_corners(kind, d, p)]
        secs = corner_sectors(kind, d)
        added = {}
        new = []
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

    def undo(rec, kind):
        added, new = rec
        tiles.pop()
        counts[kind] -= 1
        for c, m in added.items():
            masks[c] &= ~m
        for c in reversed(new):
            del masks[c]
            order.pop()

    def rec():
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


def lifts(gamma, bound):
    """Period lattices ``Lambda`` with ``F(Lambda) = Gamma``: ``P_i = A(g_i) + m . KERNEL``, ``|m_j| <= bound``."""
    g1, g2 = gamma.gens
    out = set()
    for m in product(range(-bound, bound + 1), repeat=4):
        P1 = vadd(vadd(_f_preimage(g1), tuple(m[0] * c for c in KERNEL[0])), tuple(m[1] * c for c in KERNEL[1]))
        P2 = vadd(vadd(_f_preimage(g2), tuple(m[2] * c for c in KERNEL[0])), tuple(m[3] * c for c in KERNEL[1]))
        try:
            out.add(Lattice2in4(P1, P2))
        except ValueError:
            pass
    return out


# ---------------------------------------------------------- both sides compared


def survey(L, M, enumerate_limit_vertices=18, max_seconds=None):
    """Map every configuration of the ``L x M`` torus, group by period lattice, and compare with the tiler.

    Every configuration is mapped (``config_to_tiling``), checked (``check_tiling``, ``check_cells``),
    and mapped back (``tiling_to_config``).  For each period lattice with at most
    ``enumerate_limit_vertices`` vertices the independent tiler is run (abandoned after
    ``max_seconds``, Unix alarm, if given: the row then has ``"tiler": "timeout"``); its translation
    classes are compared with the images, its labelled count with the number of configurations,
    and every tiling is mapped back to a configuration and forward again.
    Returns a dict with the counts and per-lattice rows.
    """
    from collections import Counter
    from fractions import Fraction

    from .square_triangle import Lattice2in2, TilingError, check_tiling, tiling_from_canonical, tiling_tiles
    from .tiling import MapError, _failure_kind, check_cells, chicken_wire_configs, config_canonical, config_to_tiling, tiling_to_config

    gamma = Lattice2in2.rect(L, M)
    n_conf = 0
    failures = Counter()
    by_lattice = {}  # Lambda -> {canonical form -> number of configurations}
    conf_classes = {}  # Lambda -> set of config canonical forms
    for config in chicken_wire_configs(L, M):
        n_conf += 1
        try:
            t = config_to_tiling(config, gamma)
        except MapError:
            failures[_failure_kind(config)] += 1
            continue
        check_tiling(t)
        check_cells(config, gamma)
        lam = t["lattice"]
        form, _ = canonical_form(tiling_tiles(t), lam)
        cfg_back, _ = tiling_to_config(tiling_from_canonical(form), lam)  # inverse o forward = id
        if config_canonical(cfg_back, gamma) != config_canonical(config, gamma):
            raise TilingError("a configuration's tiling does not map back to it")
        d = by_lattice.setdefault(lam, {})
        d[form] = d.get(form, 0) + 1
        conf_classes.setdefault(lam, set()).add(config_canonical(config, gamma))
    rows = []
    for lam, forms in sorted(by_lattice.items(), key=lambda kv: kv[0].tile_numbers()):
        ns, nt = lam.tile_numbers()
        V = nt // 2 + ns
        row = {"lattice": lam.key(), "N_s": ns, "N_t": nt, "V": V, "configs": sum(forms.values()),
               "config_classes": len(conf_classes[lam]), "image_classes": len(forms)}
        if V <= enumerate_limit_vertices:
            try:
                raw, classes = _with_alarm(max_seconds, enumerate_tilings, lam)
            except TimeoutError:
                row["tiler"] = "timeout"
                rows.append(row)
                continue
            row["tilings_raw"] = raw
            row["tiling_classes"] = len(classes)
            row["matched"] = len(set(classes) & set(forms))
            # each class is found V/|stab| times with a vertex at 0, and stands for N/|stab| labelled
            # configurations of the N-site torus (|stab| = translation group of the tiling mod Lambda)
            if raw != sum(Fraction(V, s) for s in classes.values()):
                raise TilingError(f"{raw} raw tilings of {lam.key()} are not V/|stab| per class")
            row["configs_predicted"] = sum(Fraction(gamma.det(), s) for s in classes.values())
            # constructive check: every enumerated tiling maps back to a configuration of the
            # L x M torus whose image is the same tiling, and that configuration was enumerated
            back = 0
            for form in classes:
                cfg, g = tiling_to_config(tiling_from_canonical(form), lam)
                if g != gamma:
                    raise TilingError(f"a tiling of {lam.key()} lives on another torus than {L} x {M}")
                t = config_to_tiling(cfg, gamma)
                check_tiling(t)
                if t["lattice"] != lam:
                    raise TilingError(f"a tiling of {lam.key()} maps back to the period lattice {t['lattice'].key()}")
                if canonical_form(tiling_tiles(t), lam)[0] != form:
                    raise TilingError(f"a tiling of {lam.key()} does not map back to itself")
                if config_canonical(cfg, gamma) not in conf_classes[lam]:
                    raise TilingError(f"a tiling of {lam.key()} maps back to a configuration that was not enumerated")
                back += 1
            row["round_trip"] = back
        rows.append(row)
    return {"L": L, "M": M, "configs": n_conf, "failures": dict(failures),
            "valid": n_conf - sum(failures.values()), "rows": rows}


def _with_alarm(seconds, fn, *args):
    if not seconds:
        return fn(*args)
    import signal

    def handler(*_):
        raise TimeoutError

    old = signal.signal(signal.SIGALRM, handler)
    signal.alarm(int(seconds))
    try:
        return fn(*args)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


def scan_lifts(L, M, bound, vmax):
    """Run the tiler on every lift ``Lambda`` of the ``L x M`` torus from ``lifts(.., bound)`` with ``V <= vmax``.

    Returns ``{Lambda: number of tiling classes}`` for the lattices that carry at least one tiling,
    and the number of lattices tried.  Independent of the chicken-wire enumeration.
    """
    from .square_triangle import Lattice2in2

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
