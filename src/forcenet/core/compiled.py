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
own user-wide cache does, and never in the package.  ``NUMBA_CACHE_DIR``, when
set, still wins (numba's rule); when neither place is writable, numba's own
choice applies.  The cache is checked against the source's content hash, so
a changed kernel is compiled again, and the code is the same wherever it is cached.

Imports only: the standard library and, when a kernel is defined, ``numba``.

Examples
--------
>>> import os
>>> cache_directory().endswith(os.path.join("forcenet", "numba"))
True
>>> from forcenet.exact.triangle.pfaffian.residues import inv_mod
>>> inv_mod._cache._cache_path.startswith(cache_directory()) or bool(os.environ.get("NUMBA_CACHE_DIR"))
True
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import Any

__all__ = ["cache_directory", "njit"]


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
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "forcenet", "numba")


_FUNCTION_CACHE: Any = None


def _function_cache_class() -> Any:
    """numba's ``FunctionCache`` with forcenet's locator after the user-provided one (built once)."""
    global _FUNCTION_CACHE
    if _FUNCTION_CACHE is None:
        from numba.core import caching

        def named(*names: str) -> Any:  # numba 0.60 spells them with a leading underscore
            return next(getattr(caching, n) for n in names if hasattr(caching, n))

        user_wide = named("UserWideCacheLocator", "_UserWideCacheLocator")
        user_provided = named("UserProvidedCacheLocator", "_UserProvidedCacheLocator")
        impl = caching.FunctionCache._impl_class

        class KernelCacheLocator(user_wide):  # type: ignore[misc, valid-type]
            """numba's user-wide locator, rooted at :func:`cache_directory`."""

            def __init__(self, py_func: Any, py_file: str) -> None:
                super().__init__(py_func, py_file)
                self._cache_path = os.path.join(cache_directory(), self.get_suitable_cache_subpath(py_file))

        class KernelCacheImpl(impl):  # type: ignore[misc, valid-type]
            _locator_classes = [user_provided, KernelCacheLocator,
                                *(c for c in impl._locator_classes if c is not user_provided)]

        class KernelFunctionCache(caching.FunctionCache):  # type: ignore[misc]
            _impl_class = KernelCacheImpl

        _FUNCTION_CACHE = KernelFunctionCache
    return _FUNCTION_CACHE


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
        import numba

        dispatcher = numba.njit(cache=False, **options)(func)
        if cache:  # Dispatcher.enable_caching, with forcenet's place for the files
            dispatcher._cache = _function_cache_class()(dispatcher.py_func)
        return dispatcher

    return decorate if function is None else decorate(function)
