"""numba's ``njit`` for forcenet's kernels, with their machine code cached outside the installed package.

numba's ``cache=True`` writes its cache files into ``__pycache__`` beside the
module: for an installed package, into site-packages.  pip does not know
those files, so ``pip uninstall forcenet`` (or the uninstall that ``pip
install -e .`` does first) leaves a ``forcenet/`` folder of cache files
behind, without an ``__init__.py``; Python then finds that folder first, as a
namespace package, and a later editable install fails on import with
``No module named 'forcenet.exact...'`` (seen on a development machine:
``pip install .``, a run, then ``pip install -e .``).

So forcenet's kernels keep their cache under ``$XDG_CACHE_HOME/forcenet/numba``
(else ``~/.cache/forcenet/numba``), one folder per source folder as numba's
own user-wide cache does, and never in the package: by numba's public
setting, ``NUMBA_CACHE_DIR`` (:func:`_use_cache_directory`).  A
``NUMBA_CACHE_DIR`` the user set still wins (numba's rule); when neither
place is writable, numba's own choice applies.  The cache is checked against the source's content hash, so
a changed kernel is compiled again, and the code is the same wherever it is cached.

Examples
--------
>>> import os
>>> cache_directory().endswith(os.path.join("forcenet", "numba"))
True
>>> from forcenet.exact.triangle.residues import inv_mod
>>> inv_mod.stats.cache_path.startswith(os.environ["NUMBA_CACHE_DIR"])
True
"""

from __future__ import annotations

import atexit
import os
import shutil
import sys
import tempfile
from collections.abc import Callable
from typing import Any

from .errors import ArgumentError

try:
    import resource
except ImportError:  # Windows: no limit on open files to read
    resource = None  # type: ignore[assignment]

__all__ = ["cache_directory", "cache_home", "check_environment", "compile_features", "host_features", "njit",
           "prefer_wide_vectors"]

MIN_OPEN_FILES = 64  # a table over primes with its pool of workers needs ~24 (pipes, semaphores); headroom for more

# LLVM tunes most AVX-512 Intel cores to prefer 256-bit vectors (``prefer-256-bit``); the route's hot loops
# run over blocks of eight float64, one 512-bit vector: 1.4x per table prime at N = 100 (notes/benchmarks.md)
WIDE_VECTOR_FEATURE = "-prefer-256-bit"


def cache_home() -> str:
    """The user's cache folder by the XDG rules: ``$XDG_CACHE_HOME`` when it is an absolute path, else
    ``~/.cache`` (a relative or empty ``$XDG_CACHE_HOME`` is ignored, as the XDG Base Directory specification says,
    so nothing lands in the current folder).

    Examples
    --------
    >>> import os
    >>> os.path.isabs(cache_home())
    True
    """
    base = os.environ.get("XDG_CACHE_HOME", "")
    return base if os.path.isabs(base) else os.path.join(os.path.expanduser("~"), ".cache")


def check_environment(environ: dict[str, str] | None = None) -> None:
    """Refuse, in one line, the settings under which numba cannot work, before anything imports it.

    numba aborts the process inside LLVM for a ``NUMBA_CPU_FEATURES`` item without its ``+``/``-``, raises at
    import for ``NUMBA_NUM_THREADS`` below 1, and with ``NUMBA_DISABLE_JIT`` leaves forcenet's kernels
    uncompiled. A limit on open files below :data:`MIN_OPEN_FILES` is raised to the hard limit where allowed,
    else refused (the pools of worker processes need pipes).

    Raises
    ------
    ArgumentError
        Naming the setting, its value and what would work.

    Examples
    --------
    >>> check_environment({"NUMBA_NUM_THREADS": "2"})
    >>> check_environment({"NUMBA_CPU_FEATURES": "avx2"})
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: NUMBA_CPU_FEATURES='avx2' is not a list of +feature/-feature items (e.g. '+avx2,-avx512f'): correct it or unset it
    """
    env = os.environ if environ is None else environ
    features = env.get("NUMBA_CPU_FEATURES")
    if features is not None and any(item and item[0] not in "+-" for item in features.split(",")):
        raise ArgumentError(f"NUMBA_CPU_FEATURES={features[:80]!r} is not a list of +feature/-feature items "
                            "(e.g. '+avx2,-avx512f'): correct it or unset it")
    threads = env.get("NUMBA_NUM_THREADS")
    if threads is not None and threads.strip() and not (threads.strip().isdigit() and int(threads) >= 1):
        raise ArgumentError(f"NUMBA_NUM_THREADS={threads[:80]!r} must be a whole number of at least 1 "
                            "(unset: one thread per core)")
    disable = env.get("NUMBA_DISABLE_JIT", "").strip()
    if disable.lstrip("+-").isdigit() and int(disable) != 0:
        raise ArgumentError(f"NUMBA_DISABLE_JIT={disable!r} turns off the compiled kernels forcenet's routes are "
                            "written for: unset it (or set it to 0)")
    if environ is None:
        _enough_open_files()


def _enough_open_files() -> None:
    """Raise the soft limit on open files to at least :data:`MIN_OPEN_FILES` (up to the hard limit), or refuse."""
    if resource is None:  # not on this platform: nothing to check
        return
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    if soft == resource.RLIM_INFINITY or soft >= MIN_OPEN_FILES:
        return
    wanted = MIN_OPEN_FILES if hard == resource.RLIM_INFINITY else min(hard, MIN_OPEN_FILES)
    if wanted > soft:
        resource.setrlimit(resource.RLIMIT_NOFILE, (wanted, hard))
    if wanted < MIN_OPEN_FILES:
        raise ArgumentError(f"the limit on open files is {hard} (ulimit -n), below the {MIN_OPEN_FILES} forcenet's "
                            f"worker processes need: raise it (e.g. ulimit -n 1024)")


def cache_directory() -> str:
    """The folder of forcenet's compiled-kernel cache: ``$XDG_CACHE_HOME/forcenet/numba``, else ``~/.cache/forcenet/numba``.

    Read when a kernel is defined (at import of its module).

    Returns
    -------
    str
        The folder (created when the first kernel is cached).

    Examples
    --------
    >>> os.path.basename(cache_directory())
    'numba'
    """
    return os.path.join(cache_home(), "forcenet", "numba")


_PRIVATE_CACHE: list[str] = []


def _usable_cache_directory() -> str:
    """:func:`cache_directory`, unless it would live in a home folder that does not exist (no
    ``$XDG_CACHE_HOME``): then a private folder of this process (``mkdtemp``: mode 0700, a fresh name),
    removed at exit. A missing home is never created, and nothing is cached where another user could plant
    machine code."""
    if os.path.isabs(os.environ.get("XDG_CACHE_HOME", "")) or os.path.isdir(os.path.expanduser("~")):
        return cache_directory()
    if not _PRIVATE_CACHE:
        _PRIVATE_CACHE.append(tempfile.mkdtemp(prefix="forcenet-numba-"))
        atexit.register(shutil.rmtree, _PRIVATE_CACHE[0], True)
    return _PRIVATE_CACHE[0]


_SET_HERE: list[str] = []  # the NUMBA_CACHE_DIR values this module set (any other is the user's choice)


def _use_cache_directory() -> None:
    """Point numba's cache at :func:`cache_directory` by its public setting, ``NUMBA_CACHE_DIR``.

    Set in the environment (numba reads it when imported and again whenever
    a ``NUMBA_*`` variable changes; worker processes inherit it) and in
    ``numba.config.CACHE_DIR`` (numba imported already).  A value the user
    set wins, as numba's rule says.  numba's user-provided locator falls back
    to its own choice when the folder cannot be created.
    """
    current = os.environ.get("NUMBA_CACHE_DIR")
    if current and current not in _SET_HERE:
        return
    directory = _usable_cache_directory()
    os.environ["NUMBA_CACHE_DIR"] = directory
    _SET_HERE.append(directory)
    if "numba" in sys.modules:
        import numba

        numba.config.CACHE_DIR = directory  # type: ignore[attr-defined]  # numba sets its settings at run time


def njit(function: Callable[..., Any] | None = None, **options: Any) -> Any:
    """``numba.njit`` whose ``cache=True`` (the default here) caches under :func:`cache_directory`.

    Parameters
    ----------
    function : callable, optional
        The Python function (``@njit``); without it, a decorator (``@njit(**options)``).
    **options
        numba's options (``inline``, ``fastmath``, ``nogil``, ``boundscheck``...);
        ``cache=False`` compiles in every process, as numba does.

    Returns
    -------
    numba dispatcher, or a decorator making one

    Examples
    --------
    >>> @njit(cache=False)
    ... def square(x):
    ...     return x * x
    >>> square(7)
    49
    """
    cache = options.pop("cache", True)

    def decorate(func: Callable[..., Any]) -> Any:
        if cache:
            _use_cache_directory()  # before numba decides where this kernel's cache lives (at decoration)
        import numba

        return numba.njit(cache=cache, **options)(func)

    return decorate if function is None else decorate(function)


def prefer_wide_vectors(environ: Any = None) -> str | None:
    """Let numba compile 512-bit vector loops on an AVX-512 machine, for the processes of a command-line run.

    Sets ``NUMBA_CPU_FEATURES`` in ``environ`` (default ``os.environ``) to
    this machine's features plus ``-prefer-256-bit``, so that LLVM vectorizes
    the kernels' loops over blocks of eight float64 with one 512-bit vector
    instead of two 256-bit ones (LLVM's tuning for most Intel cores with
    AVX-512).  numba reads the variable when it is imported and worker
    processes inherit it, so the command line calls this first thing
    (``forcenet.__main__.run``), before numba is imported; a library user
    may do the same in their own process.  The residues do not change: the
    kernels' arithmetic is exact in any vector width.  Nothing is done when
    the user chose (``NUMBA_CPU_FEATURES`` or ``NUMBA_CPU_NAME`` set), when
    numba is already imported, or without AVX-512.

    Parameters
    ----------
    environ : mapping, optional
        The environment to set (``os.environ`` by default).

    Returns
    -------
    str or None
        The feature string set, or None when nothing was set.

    Examples
    --------
    >>> prefer_wide_vectors({"NUMBA_CPU_FEATURES": "+avx2"}) is None  # the user's choice wins
    True
    """
    environ = os.environ if environ is None else environ
    if "NUMBA_CPU_FEATURES" in environ or "NUMBA_CPU_NAME" in environ or "numba" in sys.modules:
        return None
    wide = _wide_features(host_features())
    if wide is None:
        return None
    environ["NUMBA_CPU_FEATURES"] = wide
    return wide


def host_features() -> str:
    """This machine's CPU features as numba names them by default (LLVM's, flattened: ``"+64bit,+adx,..."``).

    Examples
    --------
    >>> host_features().startswith(("+", "-")) or host_features() == ""
    True
    """
    if not _HOST:
        try:
            from llvmlite import binding

            _HOST.append(binding.get_host_cpu_features().flatten())
        except (ImportError, RuntimeError):  # pragma: no cover - llvmlite comes with numba; no features known
            _HOST.append("")
    return _HOST[0]


_HOST: list[str] = []


def _wide_features(features: str) -> str | None:
    """``features`` preferring 512-bit vectors, on an AVX-512 machine; else None."""
    return f"{features},{WIDE_VECTOR_FEATURE}" if "+avx512f" in features.split(",") else None


def compile_features(workers: bool = False) -> str:
    """The CPU features numba compiles forcenet's kernels for, in this process or in forcenet's worker processes.

    A ``NUMBA_CPU_FEATURES`` in the environment (the user's, or the command
    line's :func:`prefer_wide_vectors`) is what numba uses; else this
    machine's features.  Worker processes of a local pool
    (``workers=True``) take :func:`prefer_wide_vectors` in their
    initializer: 512-bit vectors on an AVX-512 machine, unless the
    environment chose (``NUMBA_CPU_NAME`` too).  numba keys its cached
    machine code by these features, so a plan asks for the ones the run
    will use.

    Examples
    --------
    >>> compile_features() in (os.environ.get("NUMBA_CPU_FEATURES"), host_features())
    True
    """
    chosen = os.environ.get("NUMBA_CPU_FEATURES")
    if chosen:
        return chosen
    if workers and "NUMBA_CPU_NAME" not in os.environ:
        return _wide_features(host_features()) or host_features()
    return host_features()
