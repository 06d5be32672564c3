"""The front door of Part III: clusters of large forces and their finite-size scaling (thesis Chs. 6-7).

* :func:`clusters` — users' force networks (CSV files ``sample,i,j,f``, one
  file per system size, ``M`` = bonds per sample; or arrays / DataFrames with
  those four columns): every threshold's clusters in one pass
  (:mod:`forcenet.numeric.force_chains.newman_ziff`), then the finite-size
  scaling (:mod:`forcenet.numeric.force_chains.finite_size_scaling`), a
  bootstrap over samples.
* :func:`scaling` / :func:`scaling_plan` — a model's networks generated at
  several sizes and scaled: ``percolation`` (independent uniform forces,
  the control with exact exponents 43/48 and 4/3), ``q-independent`` and
  ``q-microcanonical`` (Sec. 7.3), the force network ensemble's ``snooker``,
  ``disordered`` and ``averaged`` (Sec. 7.2, hit-and-run along local
  self-stresses, :mod:`forcenet.numeric.force_chains.network_ensembles`),
  planned first, run in blocks of samples (local processes or a Dask
  cluster's executor, checkpointed).

Both return a :class:`~forcenet.force_chains_results.ForceChainScaling`.

Examples
--------
>>> import forcenet
>>> plan = forcenet.scaling_plan("percolation", sizes=(16, 24, 32, 48), samples=200, replicas=0)
>>> plan.runnable, plan.cost.ticks
(True, 128)
>>> r = plan.run()
>>> abs(r.fit.value["f_c"] - 0.5) < 0.02     # 1 - p_c of bond percolation on the square lattice
True
"""

from __future__ import annotations

import functools
import os
import stat
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from forcenet.core.atomic_files import check_directory
from forcenet.core.errors import ArgumentError, ArgumentTypeError
from forcenet.core.plan import Plan
from forcenet.core.validation import check_int, check_real, check_seed
from forcenet.costed_plans import CostedPlan
from forcenet.force_chains_results import ForceChainScaling
from forcenet.numeric.force_chains.engines import DEFAULTS, MODELS, ScalingRequest
from forcenet.numeric.force_chains.finite_size_scaling import SizeBlocks, analyse
from forcenet.numeric.force_chains.newman_ziff import LATTICES, size_distribution, sweep_samples
from forcenet.registry import REGISTRY

__all__ = ["ScalingPlan", "ForceChainScaling", "scaling", "scaling_plan", "clusters", "read_networks", "example"]

MAX_SIZE = 4096


@dataclass(frozen=True)
class ScalingPlan(CostedPlan):
    """A checked :func:`scaling` request with its cost (make it with :func:`scaling_plan`); :meth:`run` runs it.

    Parameters
    ----------
    request : forcenet.numeric.force_chains.engines.ScalingRequest
        The checked request (model, sizes, samples, seed, thresholds, blocks, ...).
    cost : forcenet.core.plan.Plan
        Its estimated seconds, bytes and progress ticks (one per block), or the refusal.

    Examples
    --------
    >>> import forcenet
    >>> plan = forcenet.scaling_plan("q-independent", sizes=(8, 12, 16), samples=64)
    >>> plan.request.blocks, plan.cost.unit, plan.cost_method
    (32, 'block', 'union-find')
    """

    request: ScalingRequest
    cost: Plan

    def run(self, *, progress: Callable[..., Any] | bool | None = None, executor: Any = None) -> ForceChainScaling:
        """Run as planned.

        Parameters
        ----------
        progress : callable or bool, optional
            A tick per finished block, or ``True`` for a bar.
        executor : Executor or Dask client, optional
            Where the blocks run (default: this process, or ``workers`` local processes).

        Returns
        -------
        ForceChainScaling
            The exponents with their errors, the curves, the figures.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.scaling_plan("q-independent", sizes=(6, 8, 10), samples=16, replicas=0).run().model
        'q-independent'
        """
        engine = REGISTRY.engine(self.request.model, self.request.quantity, self.cost_method)
        with self._ticks(progress, self.request.model) as tick:
            outcome = engine.run(self.request, self.cost.check(), progress=tick, executor=executor)
        r = self.request
        details = {"sizes": list(r.sizes), "samples": list(r.samples), "seed": r.seed, "thresholds": r.thresholds,
                   "blocks": r.blocks, "method": engine.name, "checkpoint_records_reused": outcome.reused}
        if r.model == "percolation":
            details["lattice"] = r.lattice
        details.update(outcome.details)
        return ForceChainScaling(r.model, outcome.data, outcome.fit, outcome.seconds, details)

    @property
    def cost_method(self) -> str:
        """The engine chosen (``auto`` resolved).

        Examples
        --------
        >>> import forcenet
        >>> forcenet.scaling_plan("q-microcanonical", sizes=(8, 12, 16), samples=8).cost_method
        'heat-bath'
        """
        return REGISTRY.choose(self.request)[0].name


def scaling_plan(model: str, sizes: Sequence[int] | None = None, samples: int | Sequence[int] | None = None,
                 seed: int = 0, *, lattice: str = "square", thresholds: int = 600, replicas: int = 100,
                 blocks: int = 32, workers: int = 1, checkpoint: str | os.PathLike[str] | None = None,
                 method: str = "auto", average: int = 4) -> ScalingPlan:
    """Check a finite-size-scaling request once and say what it costs.

    Parameters
    ----------
    model : {"percolation", "q-independent", "q-microcanonical", "snooker", "disordered", "averaged"}
        The generator of force networks (Secs. 7.2-7.3; ``snooker``: the force network ensemble on the snooker
        triangle, ``disordered``: on soft-disk packings, ``averaged``: snooker networks each the average of
        ``average`` networks of the ensemble).
    sizes : sequence of int, optional
        Linear sizes ``L`` (at least 3; default: the model's, ``DEFAULTS``): the lattice's side, the snooker
        triangle's layers, ``sqrt`` of a disordered packing's disks.
    samples : int or sequence of int, optional
        Networks per size (one number: the same at every size).
    seed : int
        The seed (the result is a function of the request and the seed alone).
    lattice : {"square", "triangular", "honeycomb"}
        Percolation's periodic lattice.
    thresholds : int
        Number of thresholds (quantiles of pilot networks).
    replicas : int
        Bootstrap resamples.
    blocks : int
        Blocks of samples per size (the tasks, the bootstrap's units).
    workers : int
        Local processes when no executor is given.
    checkpoint : path, optional
        A directory keeping every finished block (a rerun reuses them).
    method : str
        The engine (``auto``: the registry's choice).
    average : int
        ``P`` of the ``averaged`` model (Sec. 7.2.3; 1..64).

    Returns
    -------
    ScalingPlan
        The request and its cost.

    Raises
    ------
    ArgumentError
        A model, lattice or number out of range, fewer than 3 sizes, samples not matching the sizes.
    ArgumentTypeError
        A size or number that is not an integer.

    Examples
    --------
    >>> import forcenet
    >>> forcenet.scaling_plan("q-microcanonical").request.sizes
    (12, 16, 24, 32, 48, 64)
    >>> forcenet.scaling_plan("ising")
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: model='ising' is out of range: model must be one of percolation, q-independent, q-microcanonical, snooker, disordered, averaged
    """
    if model not in MODELS:
        raise ArgumentError(f"model={model!r} is out of range: model must be one of {', '.join(MODELS)}")
    if lattice not in LATTICES:
        raise ArgumentError(f"lattice={lattice!r} is out of range: lattice must be one of {', '.join(LATTICES)}")
    default_sizes, default_samples = DEFAULTS[model]
    if sizes is None:
        sizes_t = default_sizes
    else:
        if isinstance(sizes, str | bytes) or not isinstance(sizes, Sequence):
            raise ArgumentTypeError(f"sizes={sizes!r}: expected a sequence of integers, e.g. (16, 32, 64)")
        sizes_t = tuple(check_int(L, "sizes", 4, MAX_SIZE) for L in sizes)
    if len(sizes_t) < 3 or len(set(sizes_t)) != len(sizes_t):
        raise ArgumentError(f"sizes={list(sizes_t)} is out of range: give at least 3 different sizes")
    if samples is None:
        samples_t = default_samples if sizes is None else tuple([default_samples[-1]] * len(sizes_t))
    elif isinstance(samples, Sequence) and not isinstance(samples, str | bytes):
        samples_t = tuple(check_int(k, "samples", 2) for k in samples)
    else:
        samples_t = tuple([check_int(samples, "samples", 2)] * len(sizes_t))
    if len(samples_t) != len(sizes_t):
        raise ArgumentError(f"samples: {len(samples_t)} numbers for {len(sizes_t)} sizes; give one, or one per size")
    order = np.argsort(sizes_t)
    request = ScalingRequest(
        model, tuple(int(sizes_t[i]) for i in order), tuple(int(samples_t[i]) for i in order),
        seed=check_int(check_seed(seed), "seed", 0), lattice=lattice,
        thresholds=check_int(thresholds, "thresholds", 20, 20000), replicas=check_int(replicas, "replicas", 0, 10000),
        blocks=check_int(blocks, "blocks", 2, 10000), workers=check_int(workers, "workers", 1, 256),
        checkpoint=None if checkpoint is None else check_directory(checkpoint, "checkpoint"), method=str(method),
        average=check_int(average, "average", 1, 64))
    _, cost = REGISTRY.choose(request)
    return ScalingPlan(request, cost)


def scaling(model: str, sizes: Sequence[int] | None = None, samples: int | Sequence[int] | None = None,
            seed: int = 0, *, progress: Callable[..., Any] | bool | None = None, executor: Any = None,
            **options: Any) -> ForceChainScaling:
    """A model's force networks at several sizes, their clusters and the finite-size scaling (Eqs. 6.8, 6.12).

    Parameters
    ----------
    model : str
        As :func:`scaling_plan`.
    sizes : sequence of int, optional
        As :func:`scaling_plan`.
    samples : int or sequence of int, optional
        As :func:`scaling_plan`.
    seed : int
        As :func:`scaling_plan`.
    progress : callable or bool, optional
        A tick per block, or ``True`` for a bar.
    executor : Executor, optional
        Where the blocks run.
    **options
        The other keyword arguments of :func:`scaling_plan` (``lattice``, ``thresholds``, ``replicas``,
        ``blocks``, ``workers``, ``checkpoint``, ``method``).

    Returns
    -------
    ForceChainScaling
        ``f_c``, ``nu``, ``gamma_2`` with errors, the curves, the figures.

    Examples
    --------
    >>> import forcenet
    >>> r = forcenet.scaling("percolation", sizes=(8, 12, 16), samples=64, replicas=0, blocks=8)
    >>> r.fit.value["f_c"] > 0.4
    True
    """
    return scaling_plan(model, sizes, samples, seed, **options).run(progress=progress, executor=executor)


MAX_CSV_BYTES = 2**30  # a force table larger than this is refused before it is read (~40 million bonds)
MAX_ID = 2**53  # sample and grain numbers beyond this are not exact in float64: two grains could merge
_COLUMNS = ("sample", "i", "j", "f")
_PIECE = 2**22  # characters of a CSV parsed at once (~100000 lines)
_KINDS = ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


def _file_problem(path: str) -> str | None:
    """Why ``path`` cannot be a force table (a directory, a FIFO, a device, too large, missing), or None."""
    try:
        info = os.stat(path)
    except OSError as exc:
        return f"cannot read it ({exc.strerror})"
    if not stat.S_ISREG(info.st_mode):
        kind = next((text for test, text in _KINDS if test(info.st_mode)), "not a regular file")
        return f"{kind}, not a CSV file (give a regular file sample,i,j,f)"
    if info.st_size > MAX_CSV_BYTES:
        return (f"{info.st_size} bytes, more than the {MAX_CSV_BYTES} bytes read here "
                "(give fewer samples per file, or arrays)")
    return None


def _read_text(path: str) -> str:
    """The text of a regular file of at most :data:`MAX_CSV_BYTES` (never opened if it is a FIFO or a device;
    a UTF-8 byte-order mark dropped)."""
    problem = _file_problem(path)
    if problem is None:
        try:  # non-blocking and checked on the handle: a FIFO put in its place meanwhile is never waited on
            fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
            with os.fdopen(fd, "rb") as handle:
                if not stat.S_ISREG(os.fstat(handle.fileno()).st_mode):
                    problem = "not a regular file, not a CSV file (give a regular file sample,i,j,f)"
                    data = b""
                else:
                    data = handle.read(MAX_CSV_BYTES + 1)
        except OSError as exc:
            problem = f"cannot read it ({exc.strerror})"
    if problem is None and len(data) > MAX_CSV_BYTES:
        problem = f"more than the {MAX_CSV_BYTES} bytes read here (give fewer samples per file)"
    if problem is not None:
        raise ArgumentError(f"{path}: {problem}")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ArgumentError(f"{path}: not UTF-8 text at byte {exc.start} (a CSV of numbers sample,i,j,f)") from None


def _parse_csv(text: str, path: str) -> np.ndarray:
    """Rows ``sample,i,j,f`` of a CSV text (a header naming the four columns, in any order, optional; blank lines
    and CRLF line ends allowed) as float64 ``(n, 4)``; any other line is named.  Read in pieces of about
    :data:`_PIECE` characters: the parse holds a piece's lines and numbers as Python objects, not the file's."""
    first, at = "", 0
    while at < len(text) and not first.strip():  # the first line that is not blank (no copy of the text)
        end = text.find("\n", at)
        end = len(text) if end < 0 else end + 1
        first, at = text[at:end], end
    order, skip, number = list(range(4)), 0, 0
    if first.strip() and not _is_number(first.split(",")[0]):  # a header: its first field names a column
        header = [name.strip().lower() for name in first.split(",")]
        if sorted(header) != sorted(_COLUMNS):
            raise ArgumentError(f"{path}: the header {first.strip()!r} must name the columns sample,i,j,f")
        order, skip = [header.index(name) for name in _COLUMNS], 1
    pieces, start = [], 0
    while start < len(text):
        stop = text.find("\n", start + _PIECE)
        stop = len(text) if stop < 0 else stop + 1
        lines = [line for line in text[start:stop].splitlines() if line.strip()][skip:]
        start, skip = stop, 0
        for k, line in enumerate(lines, start=number + 1):
            if line.count(",") != 3:
                raise ArgumentError(f"{path}: data line {k} ({line.strip()[:60]!r}) has {line.count(',') + 1} "
                                    "columns: expected 4, sample,i,j,f")
        tokens = ",".join(lines).split(",") if lines else []  # spaces around a number are read; "1 2" is not one
        try:
            pieces.append(np.array(tokens, dtype=np.float64).reshape(-1, 4))
        except ValueError:
            bad = next(k for k, token in enumerate(tokens) if not _is_number(token))
            raise ArgumentError(f"{path}: data line {number + bad // 4 + 1}: {tokens[bad][:40]!r} is not a number "
                                "(a CSV of numbers sample,i,j,f)") from None
        number += len(lines)
    if not number:
        raise ArgumentError(f"{path}: no bonds (give one line sample,i,j,f per bond)")
    return np.concatenate(pieces)[:, order]


def _is_number(token: str) -> bool:
    try:
        float(token)
    except ValueError:
        return False
    return True


def _table(source: Any) -> np.ndarray:
    """Columns ``sample, i, j, f`` of a CSV path, an array or a DataFrame, as float64 ``(n, 4)``."""
    if isinstance(source, str | os.PathLike):
        path = os.fspath(source)
        return _parse_csv(_read_text(path), path)
    if isinstance(source, bytes):
        raise ArgumentTypeError(f"sources: {source[:40]!r} is bytes; give a path as str, an array or a DataFrame")
    try:
        if hasattr(source, "columns") and hasattr(source, "to_numpy"):  # a DataFrame: by column names
            return np.asarray(source[list(_COLUMNS)].to_numpy(), dtype=np.float64)
        array = np.asarray(source, dtype=np.float64)
    except KeyError as exc:
        raise ArgumentError("a DataFrame needs the columns sample, i, j, f") from exc
    except (ValueError, TypeError) as exc:
        raise ArgumentTypeError(f"sources: a {type(source).__name__} that is not a table of numbers sample, i, j, f "
                                f"({str(exc)[:80]})") from None
    if array.ndim != 2 or array.shape[1] != 4:
        raise ArgumentError(f"an array of force networks must have shape (bonds, 4): sample, i, j, f; got {array.shape}")
    return array


def read_networks(source: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """One system size's networks as the flat arrays of the cluster pass: ``starts``, ``sites``, ``head``,
    ``tail``, ``force`` (each sample's grain labels renumbered from 0).

    Parameters
    ----------
    source : path, array or DataFrame
        Rows ``sample, i, j, f``: a bond between grains ``i`` and ``j`` of sample ``sample`` carrying ``f``.

    Returns
    -------
    tuple of ndarray

    Examples
    --------
    >>> import numpy as np
    >>> starts, sites, head, tail, force = read_networks(np.array([[0, 7, 9, 1.0], [1, 3, 4, 2.0], [1, 4, 5, 0.5]]))
    >>> starts.tolist(), sites.tolist(), head.tolist(), tail.tolist()
    ([0, 1, 3], [2, 3], [0, 0, 1], [1, 1, 2])
    """
    table = _table(source)
    name = os.fspath(source) if isinstance(source, str | os.PathLike) else "force networks"
    if table.shape[0] == 0:
        raise ArgumentError(f"{name}: no bonds (give one row sample, i, j, f per bond)")
    finite = np.isfinite(table)
    if not finite.all():
        row, column = np.argwhere(~finite)[0]
        raise ArgumentError(f"{name}: bond {row + 1} has {_COLUMNS[column]}={table[row, column]}: every value must be a "
                            "finite number")
    ids = table[:, :3]
    if np.any(ids != np.round(ids)) or np.any(np.abs(ids) >= MAX_ID):
        row = int(np.argwhere((ids != np.round(ids)) | (np.abs(ids) >= MAX_ID))[0][0])
        raise ArgumentError(f"{name}: bond {row + 1} has sample, i, j = {ids[row].tolist()}: they must be integers "
                            f"of magnitude below 2**53")
    loops = np.flatnonzero(table[:, 1] == table[:, 2])
    if loops.size:
        raise ArgumentError(f"{name}: bond {loops[0] + 1} joins grain {table[loops[0], 1]:.0f} to itself "
                            f"(sample {table[loops[0], 0]:.0f}): a contact joins two grains")
    table = table[np.argsort(table[:, 0], kind="stable")]
    labels, starts = np.unique(table[:, 0], return_index=True)
    starts = np.append(starts, table.shape[0])
    head = np.empty(table.shape[0], np.int64)
    tail = np.empty(table.shape[0], np.int64)
    sites = np.empty(labels.size, np.int64)
    for r in range(labels.size):
        lo, hi = starts[r], starts[r + 1]
        _, inverse = np.unique(table[lo:hi, 1:3], return_inverse=True)
        inverse = inverse.reshape(-1, 2)
        head[lo:hi], tail[lo:hi] = inverse[:, 0], inverse[:, 1]
        sites[r] = int(inverse.max()) + 1
    return starts.astype(np.int64), sites, head, tail, table[:, 3].copy()


def clusters(sources: Sequence[Any], *, thresholds: int = 600, replicas: int = 100, seed: int = 0,
             labels: Sequence[float] | None = None) -> ForceChainScaling:
    """The clusters of large forces of users' force networks and their finite-size scaling (Sec. 6.5, Eq. 6.12).

    Parameters
    ----------
    sources : sequence
        One entry per system size (at least 3): a CSV path (header ``sample,i,j,f``), an array with those four
        columns, or a DataFrame with those columns.  ``M`` is the mean number of bonds per sample.
    thresholds : int
        Thresholds: quantiles 1 %..99 % of all the forces given.
    replicas : int
        Bootstrap resamples (over samples).
    seed : int
        The bootstrap's seed.
    labels : sequence of float, optional
        A label per size (e.g. the linear size ``L``; default none).

    Returns
    -------
    ForceChainScaling
        The scaling size is ``S = M``; ``wrapping`` is not known (no geometry).  ``details["n_s_at_f_c"]``:
        per size, the clusters per bond of ``s`` bonds at the ``f_c`` found, in bins ``[2^k, 2^(k+1))``.

    Raises
    ------
    ArgumentError
        Fewer than 3 sizes or 2 samples of a size, a file that cannot be read or is not ``sample,i,j,f``.
    ConvergenceError
        If no collapse is found (the forces' range leaves no window covered by every size).

    Examples
    --------
    >>> import numpy as np, forcenet
    >>> from forcenet.numeric.force_chains.newman_ziff import periodic_lattice
    >>> rng = np.random.default_rng(0)
    >>> def networks(L, K):                                   # independent uniform forces: percolation
    ...     lat = periodic_lattice("square", L)
    ...     return np.concatenate([np.column_stack([np.full(lat.bonds, k), lat.head, lat.tail, rng.random(lat.bonds)])
    ...                            for k in range(K)])
    >>> r = forcenet.clusters([networks(12, 300), networks(16, 200), networks(24, 120), networks(32, 80)], replicas=0)
    >>> abs(r.fit.value["f_c"] - 0.5) < 0.05, r.summary()["sizes"][0]["M"]
    (True, 288)
    """
    if isinstance(sources, str | bytes) or not isinstance(sources, Sequence):
        raise ArgumentTypeError("sources: expected a list of CSV paths, arrays or DataFrames, one per system size")
    if len(sources) < 3:
        raise ArgumentError(f"sources: finite-size scaling needs at least 3 system sizes, got {len(sources)}")
    thresholds = check_int(thresholds, "thresholds", 20, 20000)
    replicas = check_int(replicas, "replicas", 0, 10000)
    seed = check_int(seed, "seed", 0)
    for source in sources:  # every file checked before any is read: a FIFO, a device or a folder named at once
        problem = _file_problem(os.fspath(source)) if isinstance(source, str | os.PathLike) else None
        if problem is not None:
            raise ArgumentError(f"{os.fspath(source)}: {problem}")
    if labels is not None:
        if isinstance(labels, str | bytes) or not isinstance(labels, Sequence) or len(labels) != len(sources):
            raise ArgumentError(f"labels: give one number per source ({len(sources)}), e.g. the linear sizes L")
        labels = [check_real(label, "labels") for label in labels]
    started = time.perf_counter()
    rng = np.random.default_rng(seed)
    pooled = []
    for source in sources:  # pass 1: the thresholds, from up to 2^17 forces of every size (one size in memory)
        force = read_networks(source)[4]
        pooled.append(force if force.size <= 2**17 else rng.choice(force, 2**17, replace=False))
    levels = np.unique(np.quantile(np.concatenate(pooled), np.linspace(0.01, 0.99, thresholds)))
    del pooled
    data = []
    for index, source in enumerate(sources):  # pass 2: one size at a time
        starts, sites, head, tail, force = read_networks(source)
        stats = sweep_samples(starts, sites, head, tail, force, levels)
        K = sites.size
        if K < 2:
            raise ArgumentError(f"sources[{index}]: the bootstrap needs at least 2 samples, got {K}")
        M = float(force.size) / K
        label = float(labels[index]) if labels is not None else 0.0
        data.append(SizeBlocks(M, int(round(M)), levels, stats.total.astype(np.float64),
                               stats.largest.astype(np.float64), stats.wraps.astype(np.float64), np.ones(K),
                               label=label))
        del starts, sites, head, tail, force, stats
    fit = analyse(data, replicas=replicas, seed=seed)
    n_s = []
    for source in sources:  # pass 3: the cluster numbers n_s at the f_c found (Eq. 6.1)
        lower, density = size_distribution(*read_networks(source), fit.value["f_c"])
        n_s.append({"s": lower.tolist(), "n_s": [float(f"{x:.6g}") for x in density]})
    details = {"sources": [os.fspath(s) if isinstance(s, str | os.PathLike) else f"<{type(s).__name__}>"
                           for s in sources], "thresholds": int(levels.size),
               "n_s_at_f_c": n_s}
    return ForceChainScaling("data", sorted(data, key=lambda d: d.S), fit, time.perf_counter() - started, details)


@functools.cache
def example() -> ForceChainScaling:
    """A small result to try the renderings on: bond percolation on periodic square lattices ``L = 8..24``
    (64 samples each, no bootstrap), made once per session.

    Examples
    --------
    >>> example().model
    'percolation'
    """
    return scaling("percolation", sizes=(8, 12, 16, 24), samples=64, replicas=0, blocks=8)
