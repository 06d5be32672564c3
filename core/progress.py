"""Progress where a person watches: one policy for the front door and the command line (issue 53).

* **When.** ``progress=None`` (the front door's default) shows a bar where a
  person watches -- standard error a terminal, or a Jupyter kernel -- for a
  run planned at over :data:`SHOWN_SECONDS`; nothing in a pipe, a log file or
  a batch job. ``True`` always, ``False`` never, a callable receives the ticks.
* **With the plan.** The bar comes after the plan's line (what runs, the
  estimate: :meth:`forcenet.core.plan.Plan.describe`), as the command line
  announces it.
* **Never past 100 %.** When the work outgrows the plan's ticks (an estimate
  counted in seconds, a slower machine), the bar re-estimates its total
  instead of counting on (:class:`Bar`), and tells the time left in words a
  person reads: ``~12 s left``, never ``est. s``.

Examples
--------
>>> bar = Bar(10, "table N=8", "prime", draw=False)
>>> for _ in range(14):
...     bar.update()
>>> bar.n, bar.total >= bar.n, bar.percent <= 100
(14, True, True)
>>> bar.close()
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any

__all__ = ["SHOWN_SECONDS", "Bar", "left_text", "owned", "ticks", "watched"]

SHOWN_SECONDS = 2.0  # a run planned at most this long shows no bar unasked (the command line's announcement rule)
_HEADROOM = 0.99  # a bar whose count reaches its total re-estimates the total so that it stands at 99 %
COLUMNS = 80  # a bar's line at most


_OWNED: ContextVar[bool] = ContextVar("forcenet_progress_owned", default=False)


@contextmanager
def owned() -> Iterator[None]:
    """Inside, ``progress=None`` shows nothing: the caller (the command line's ``run_planned``) owns the progress.

    Examples
    --------
    >>> from forcenet.core.plan import Plan
    >>> with owned(), ticks(Plan("x", 30.0, ticks=3), None, "x") as tick:
    ...     tick is None
    True
    """
    token = _OWNED.set(True)
    try:
        yield
    finally:
        _OWNED.reset(token)


def watched(stream: Any = None) -> bool:
    """Whether a person watches ``stream`` (default standard error): a terminal, or a Jupyter kernel's output.

    Examples
    --------
    >>> import io
    >>> watched(io.StringIO())
    False
    """
    stream = sys.stderr if stream is None else stream
    if "ipykernel" in sys.modules and type(stream).__module__.startswith("ipykernel"):
        return True  # a notebook's cell output
    try:
        return bool(stream is not None and stream.isatty())
    except (AttributeError, ValueError):  # closed or not a file
        return False


def left_text(seconds: float) -> str:
    """The time left for a person: ``"~12 s left"``, ``"~3 min left"``, ``"~1.5 h left"``.

    Examples
    --------
    >>> left_text(12.4), left_text(185), left_text(5400)
    ('~12 s left', '~3 min left', '~1.5 h left')
    """
    if seconds < 90:
        return f"~{seconds:.0f} s left"
    if seconds < 5400:
        return f"~{seconds / 60:.0f} min left"
    return f"~{seconds / 3600:.1f} h left"


class Bar:
    """A progress bar that never passes 100 %: when the count reaches its total, the total is re-estimated.

    On a terminal or in a notebook, a tqdm bar (``tqdm.auto``) of at most
    :data:`COLUMNS` columns showing the percentage and the time left;
    ``draw=False`` draws nothing (the count and the re-estimates still hold).

    Parameters
    ----------
    total : float
        The plan's ticks.
    desc : str
        A short label (``"table N=40"``).
    unit : str
        The ticks' unit (``"s"``: estimated seconds, then the count is not shown).
    file : stream, optional
        Where to draw (default standard error).
    draw : bool
        Draw the bar.
    """

    def __init__(self, total: float, desc: str, unit: str, file: Any = None, draw: bool = True) -> None:
        self.total, self.desc, self.unit = float(max(total, 1e-9)), desc, unit
        self.n: float = 0
        self.t0 = time.perf_counter()
        self._bar: Any = None
        if draw:
            from tqdm.auto import tqdm

            file = sys.stderr if file is None else file
            count = "" if unit == "s" else " {n_fmt}/{total_fmt} " + unit + ","
            self._bar = tqdm(total=self.total, desc=desc, unit=unit, file=file, leave=False, ncols=COLUMNS,
                             bar_format="{l_bar}{bar}|" + count + " {postfix}")

    @property
    def percent(self) -> float:
        """The share done, in percent (at most 100)."""
        return min(100.0, 100.0 * self.n / self.total)

    def update(self, k: float = 1) -> None:
        """``k`` more ticks done; past the total, the total grows (the bar stands at 99 % until the end)."""
        self.n += k
        if self.n > _HEADROOM * self.total:
            self.retotal(self.n / _HEADROOM)
        elapsed = time.perf_counter() - self.t0
        if self._bar is not None:
            self._bar.update(k)
            if self.n > 0:
                self._bar.set_postfix_str(left_text(elapsed * (self.total - self.n) / self.n), refresh=False)

    def retotal(self, total: float) -> None:
        """A new estimate of the total (never below the count)."""
        self.total = max(float(total), self.n)
        if self._bar is not None:
            self._bar.total = self.total  # tqdm's public attribute; drawn at the next refresh
            self._bar.refresh()

    def write(self, line: str) -> None:
        """A line above the bar (the bar is redrawn below it)."""
        if self._bar is not None:
            self._bar.write(line, file=self._bar.fp)

    def close(self) -> None:
        """Remove the bar."""
        if self._bar is not None:
            self._bar.close()


@contextmanager
def ticks(plan: Any, progress: Callable[..., Any] | bool | None, desc: str,
          file: Any = None) -> Iterator[Callable[..., Any] | None]:
    """The front door's ``progress`` argument as the run's tick (the policy in the module's docstring).

    Parameters
    ----------
    plan : forcenet.core.plan.Plan
        The run's plan (its ticks, unit, seconds and line).
    progress : callable, bool or None
        A callable (receives the ticks), ``True`` (a bar), ``False`` (nothing), ``None`` (a bar where a person
        watches, for a run planned at over :data:`SHOWN_SECONDS`).
    desc : str
        The bar's label.
    file : stream, optional
        Where the plan's line and the bar go (default standard error).

    Yields
    ------
    callable or None
        ``tick(k=1)``, or None when nothing is shown.

    Examples
    --------
    >>> from forcenet.core.plan import Plan
    >>> import io
    >>> out = io.StringIO()
    >>> with ticks(Plan("exact table N=40", 30.0, ticks=12, unit="prime"), True, "table N=40", out) as tick:
    ...     tick(12)
    >>> print(out.getvalue().splitlines()[0])
    forcenet: exact table N=40: estimated ~30 s
    >>> with ticks(Plan("x", 30.0, ticks=3), None, "x", io.StringIO()) as tick:  # nobody watches a StringIO
    ...     tick is None
    True
    """
    if callable(progress) and progress is not True:
        yield progress
        return
    stream = sys.stderr if file is None else file
    show = progress is True or (progress is None and not _OWNED.get() and plan.seconds > SHOWN_SECONDS
                                and watched(stream))
    if not show or not plan.runnable or not plan.ticks:
        yield None
        return
    print(f"forcenet: {plan.what}: estimated {plan.describe()}", file=stream, flush=True)
    bar = Bar(plan.ticks, desc, plan.unit, file=stream)
    try:
        yield bar.update
    finally:
        bar.close()
