"""What :func:`forcenet.sample` returns: Monte Carlo ``<W>`` with standard errors (:class:`Samples`), rendered as
``forcenet sample`` renders it.

The means and their standard errors (for a Markov chain from the integrated
autocorrelation time, Sec. 3.2.4), the effective sample size, the kernel and
the chain's statistics, and the two renderings the command line writes, byte
for byte: the JSON (a function of the arguments, the seed and the workers
alone) and the text summary.

Examples
--------
>>> import forcenet
>>> s = forcenet.sample(4, 400, seed=1)
>>> s.mean.shape, s.effective_samples, s.to_json()[:43]
((4, 4), 400.0, '{"N": 4, "sampler": "exact", "samples": 400')
"""

from __future__ import annotations

import json
import textwrap
from html import escape
from typing import TYPE_CHECKING, Any

import numpy as np

from forcenet.rendering import Rendered

if TYPE_CHECKING:  # pragma: no cover - annotations only
    import numpy as np

    from forcenet.numeric.packing.scene import Scene

__all__ = ["Samples"]


def _plus_minus(mean: float, stderr: float) -> str:
    """``mean±stderr``: four decimals at ordinary scales, significant digits at extreme loads (``F = 1e300``)."""
    scale = max(abs(mean), abs(stderr))
    if scale == 0 or 1e-3 <= scale < 1e6:
        return f"{mean:.4f}±{stderr:.4f}"
    return f"{mean:.5g}±{stderr:.2g}"


class Samples(Rendered):
    """Monte Carlo ``<W_ij>`` with standard errors: what :func:`forcenet.sample` returns.

    The triangle's arrays are ``N x N`` (``W[i-1, j-1] = W_ij``, zero above the diagonal), the packing's ``N x P``.
    The renderings are byte for byte those of ``forcenet sample`` (the triangle's rows: its lower triangle).

    Parameters
    ----------
    N : int
        Number of layers.
    sampler : {"exact", "metropolis"}
        The sampler that drew them.
    samples : int
        Samples (exact) or recorded sweeps (metropolis), over all workers.
    seed : int
        The seed; the values depend on it and on ``workers`` only.
    workers : int
        Processes that drew them.
    mean, stderr : numpy.ndarray
        The mean of every ``W`` and its standard error.
    extra : dict
        The engine's further fields, in the order the JSON writes them: ``kernel``, ``effective_samples``, and for
        a chain ``burn_in``, ``move``, the packing's scene, ``acceptance``, ``tau_max``, ``std_W``, ``G``,
        ``stderr_G``.
    scene : forcenet.Scene, optional
        The N x P packing; None for the triangle.

    Examples
    --------
    >>> import forcenet
    >>> s = forcenet.sample(3, 200, seed=2)
    >>> s
    Samples(N=3, sampler='exact', samples=200, seed=2, workers=1)
    >>> s.to_text().splitlines()[0]
    'exact sampler, N = 3 (triangle), 200 samples, 200 effective'
    """

    def __init__(self, N: int, sampler: str, samples: int, seed: int, workers: int, mean: np.ndarray,
                 stderr: np.ndarray, extra: dict[str, Any], scene: Scene | None = None):
        self.N, self.sampler, self.samples, self.seed, self.workers = N, sampler, samples, seed, workers
        self.mean, self.stderr, self.extra, self.scene = mean, stderr, dict(extra), scene

    def __repr__(self) -> str:
        return (f"Samples(N={self.N}, sampler={self.sampler!r}, samples={self.samples}, seed={self.seed}, "
                f"workers={self.workers})")

    @property
    def effective_samples(self) -> float:
        """The effective sample size: the samples for the exact sampler; for chains ``min`` over the grains of
        ``sum_k n_k / tau_k``.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.sample(3, 2000, sampler="metropolis", seed=1).effective_samples < 2000
        True
        """
        return float(self.extra["effective_samples"])

    @property
    def kernel(self) -> str:
        """The kernel that drew them (``"compiled"`` or ``"python"``).

        Examples
        --------
        >>> import forcenet
        >>> forcenet.sample(3, 100, seed=1).kernel in ("compiled", "python")
        True
        """
        return str(self.extra["kernel"])

    @property
    def tau(self) -> float | None:
        """The largest integrated autocorrelation time of a chain, in sweeps (``tau_max``); None for exact samples.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.sample(3, 2000, sampler="metropolis", seed=1).tau >= 1
        True
        >>> forcenet.sample(3, 100, seed=1).tau is None
        True
        """
        tau = self.extra.get("tau_max")
        return None if tau is None else float(tau)

    @property
    def G(self) -> np.ndarray | None:
        """The response ``G(i, j) = (<W>_{p+F} - <W>_p) / F`` (``response=True``, the packing); else None.

        Examples
        --------
        >>> import forcenet
        >>> scene = forcenet.Scene(N=3, P=4, F=20.0, mg=1.0)
        >>> s = forcenet.sample(3, 2000, sampler="metropolis", scene=scene, response=True, seed=2)
        >>> round(float(s.G[-1].sum()), 9)  # the whole overload reaches the floor
        1.0
        """
        return self.extra.get("G")

    @property
    def stderr_G(self) -> np.ndarray | None:
        """The standard error of :attr:`G`; None without a response.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.sample(3, 100, seed=1).stderr_G is None
        True
        """
        return self.extra.get("stderr_G")

    def _rows(self, a: np.ndarray) -> list[list[float]]:
        if self.scene is None:  # the triangle: the rows of the lower triangle
            return [[float(a[i, j]) for j in range(i + 1)] for i in range(self.N)]
        return [[float(v) for v in row] for row in a]

    def to_dict(self, timing: float | None = None) -> dict[str, Any]:
        """What ``forcenet sample --format json`` writes (the triangle's arrays as the rows of its lower triangle).

        Parameters
        ----------
        timing : float, optional
            The run's wall-clock seconds: adds ``seconds`` and ``effective_samples_per_second``
            (``forcenet sample --timing``; the output then differs from run to run).

        Returns
        -------
        dict

        Examples
        --------
        >>> import forcenet
        >>> d = forcenet.sample(2, 100, seed=1).to_dict()
        >>> list(d), d["mean_W"][0]
        (['N', 'sampler', 'samples', 'seed', 'workers', 'kernel', 'effective_samples', 'mean_W', 'stderr_W'], [1.0])
        """

        out: dict[str, Any] = {"N": self.N, "sampler": self.sampler, "samples": self.samples, "seed": self.seed,
                               "workers": self.workers}
        out.update({k: (self._rows(v) if isinstance(v, np.ndarray) else v) for k, v in self.extra.items()})
        if timing is not None:  # opt-in: wall-clock figures make the output differ from run to run
            out.update({"seconds": timing, "effective_samples_per_second": self.effective_samples / timing})
        out.update({"mean_W": self._rows(self.mean), "stderr_W": self._rows(self.stderr)})
        return out

    def to_json(self, timing: float | None = None) -> str:
        """``forcenet sample --format json`` (without its newline): identical bytes for the same arguments, seed and
        workers.

        Parameters
        ----------
        timing : float, optional
            The run's wall-clock seconds (``--timing``): adds ``seconds`` and ``effective_samples_per_second``.

        Returns
        -------
        str

        Examples
        --------
        >>> import forcenet
        >>> forcenet.sample(2, 100, seed=1).to_json()  # doctest: +ELLIPSIS
        '{"N": 2, "sampler": "exact", "samples": 100, "seed": 1, "workers": 1, "kernel": ..., "mean_W": [[1.0], [0.5...'
        """
        return json.dumps(self.to_dict(timing), allow_nan=False)

    def to_text(self) -> str:
        """``forcenet sample``'s text: the run in one line, the bottom row's ``<W_N,j>`` (and ``G(N, j)``) with errors.

        Returns
        -------
        str

        Examples
        --------
        >>> import forcenet
        >>> print(forcenet.sample(3, 1000, seed=1).to_text())  # the exact bottom row: 1/4, 1/2, 1/4
        exact sampler, N = 3 (triangle), 1000 samples, 1000 effective
          bottom row <W_N,j>: 0.2488±0.0062 0.5058±0.0071 0.2454±0.0060
        """
        where = "triangle" if self.scene is None else f"{self.scene.name} packing, P = {self.scene.P}"
        lines = [f"{self.sampler} sampler, N = {self.N} ({where}), {self.samples} samples, "
                 f"{self.effective_samples:.0f} effective"]
        rows = [("  bottom row <W_N,j>: ", self.mean[-1], self.stderr[-1])]
        if self.G is not None and self.stderr_G is not None:
            rows.append(("  bottom row G(N,j): ", self.G[-1], self.stderr_G[-1]))
        for head, means, errors in rows:  # at most 80 columns: the values wrap under the first (issue 53)
            lines += textwrap.wrap(" ".join(_plus_minus(m, e) for m, e in zip(means, errors)), 80,
                                   initial_indent=head, subsequent_indent=" " * len(head))
        return "\n".join(lines)

    def _repr_html_(self) -> str:
        return f"<pre>{escape(self.to_text())}</pre>"
