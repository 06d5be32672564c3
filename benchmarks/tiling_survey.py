"""The chicken-wire <-> square-triangle correspondence checked torus by torus against the independent tiler.

:func:`survey` maps every configuration of an ``L x M`` torus to its tiling
(``forcenet.exact.chicken_wire.tiling``), groups them by period lattice, and compares each group
with what the independent enumerator (``forcenet.exact.chicken_wire.tiler``, which knows nothing of
the chicken-wire model) finds on that lattice: translation classes, labelled
counts, and the round trip of every tiling (notes/chicken_wire.md, Sec. 7).
A benchmark and test helper, not part of the installed package: tests/test_tiling.py imports it by path.

Run:  python benchmarks/tiling_survey.py 18 60 2x2 2x3 3x3 3x4 4x4 3x5 2x6 5x5 6x6 7x7
      (max tiling vertices to enumerate, seconds per lattice, tori)
Prints, per torus: configurations, in the image, failures (= formula), period lattices,
classes up to translation on both sides, matched.
"""

from __future__ import annotations

import signal
import sys
import threading
from collections import Counter
from collections.abc import Callable
from fractions import Fraction
from typing import TypeVar

from forcenet.core.errors import ArgumentError
from forcenet.core.validation import check_int, check_real
from forcenet.exact.chicken_wire.square_triangle import (
    Lattice2in2,
    Lattice2in4,
    TilingError,
    canonical_form,
    check_tiling,
    tiling_from_canonical,
    tiling_tiles,
)
from forcenet.exact.chicken_wire.tiler import enumerate_tilings
from forcenet.exact.chicken_wire.tiling import (
    MapError,
    check_cells,
    chicken_wire_configs,
    config_canonical,
    config_to_tiling,
    failure_kind,
    tiling_to_config,
)

__all__ = ["survey", "call_with_timeout"]

T = TypeVar("T")


def _check_timeout(seconds: float | None) -> float | None:
    """``seconds`` as a float ``> 0`` (None: no limit); refused where no interval timer can interrupt the caller."""
    if seconds is None:
        return None
    seconds = check_real(seconds, "max_seconds", 0, low_open=True)
    if not hasattr(signal, "setitimer") or threading.current_thread() is not threading.main_thread():
        raise ArgumentError(f"max_seconds={seconds}: a time limit needs a Unix interval timer in the main thread; "
                            "give max_seconds=None")
    return seconds


def call_with_timeout(seconds: float | None, fn: Callable[..., T], *args: object) -> T:
    """``fn(*args)``, abandoned with ``TimeoutError`` after ``seconds`` (a real-time interval timer).

    Fractions of a second count (``signal.setitimer``, not the whole seconds
    of ``signal.alarm``); the previous handler and timer are restored.

    Parameters
    ----------
    seconds : float or None
        The limit, ``> 0``; None: no limit.
    fn : callable
        The work, called with ``args``.

    Returns
    -------
    object
        What ``fn`` returns.

    Raises
    ------
    ArgumentError
        If ``seconds`` is not a finite number ``> 0``, or no interval timer exists here.
    TimeoutError
        If ``fn`` did not return within ``seconds``.

    Examples
    --------
    >>> call_with_timeout(0.5, sum, [1, 2, 3])
    6
    >>> import time
    >>> call_with_timeout(0.05, time.sleep, 5)
    Traceback (most recent call last):
    ...
    TimeoutError: abandoned after 0.05 s
    """
    seconds = _check_timeout(seconds)
    if seconds is None:
        return fn(*args)

    def handler(*_: object) -> None:
        raise TimeoutError(f"abandoned after {seconds:g} s")

    old = signal.signal(signal.SIGALRM, handler)
    try:
        signal.setitimer(signal.ITIMER_REAL, seconds)
        try:
            return fn(*args)
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
    finally:  # also when the (one-shot) timer fired just as fn returned
        signal.signal(signal.SIGALRM, old)


def survey(L: int, M: int, enumerate_limit_vertices: int = 18, max_seconds: float | None = None) -> dict:
    """Map every configuration of the ``L x M`` torus, group by period lattice, and compare with the tiler.

    Every configuration is mapped (``config_to_tiling``), checked (``check_tiling``, ``check_cells``),
    and mapped back (``tiling_to_config``).  For each period lattice with at most
    ``enumerate_limit_vertices`` vertices the independent tiler is run (abandoned after
    ``max_seconds``, :func:`call_with_timeout`, if given: the row then has ``"tiler": "timeout"``);
    its translation classes are compared with the images, its labelled count with the number of
    configurations, and every tiling is mapped back to a configuration and forward again.

    Parameters
    ----------
    L, M : int
        The torus, ``L, M >= 1``.
    enumerate_limit_vertices : int
        Run the tiler on period lattices with at most this many tiling vertices (``>= 0``).
    max_seconds : float, optional
        Abandon the tiler on one lattice after this many seconds (``> 0``; fractions of a second
        count); None: no limit.

    Returns
    -------
    dict
        The counts (``configs``, ``failures`` by kind, ``valid``) and the per-lattice ``rows``.

    Raises
    ------
    ArgumentError
        If an argument is out of range, or ``max_seconds`` is given where no interval timer exists.
    TilingError
        If the two sides of the correspondence disagree.

    Examples
    --------
    >>> r = survey(2, 2)
    >>> r["configs"], r["valid"], [row["matched"] for row in r["rows"]]
    (10, 7, [1, 1, 1, 1])
    """
    L, M = check_int(L, "L", 1), check_int(M, "M", 1)
    enumerate_limit_vertices = check_int(enumerate_limit_vertices, "enumerate_limit_vertices", 0)
    max_seconds = _check_timeout(max_seconds)
    gamma = Lattice2in2.rect(L, M)
    n_conf = 0
    failures: Counter[str] = Counter()
    by_lattice: dict[Lattice2in4, dict[object, int]] = {}  # Lambda -> {canonical form -> number of configurations}
    conf_classes: dict[Lattice2in4, set[object]] = {}  # Lambda -> set of config canonical forms
    for config in chicken_wire_configs(L, M):
        n_conf += 1
        try:
            t = config_to_tiling(config, gamma)
        except MapError:
            failures[failure_kind(config)] += 1
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
    rows: list[dict[str, object]] = []
    for lam, forms in sorted(by_lattice.items(), key=lambda kv: kv[0].tile_numbers()):
        ns, nt = lam.tile_numbers()
        V = nt // 2 + ns
        row = {"lattice": lam.key(), "N_s": ns, "N_t": nt, "V": V, "configs": sum(forms.values()),
               "config_classes": len(conf_classes[lam]), "image_classes": len(forms)}
        if V <= enumerate_limit_vertices:
            try:
                raw, classes = call_with_timeout(max_seconds, enumerate_tilings, lam)
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


if __name__ == "__main__":
    vmax, seconds = int(sys.argv[1]), float(sys.argv[2])
    for spec in sys.argv[3:]:
        L, M = (int(x) for x in spec.split("x"))
        print(spec, survey(L, M, vmax, seconds), flush=True)
