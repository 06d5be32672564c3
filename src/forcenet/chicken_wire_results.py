"""What the chicken-wire faces return (Sec. 7.4), rendered as ``forcenet transfer``, ``bethe`` and ``entropy`` render it.

* :class:`TransferSpectrum` — the largest transfer-matrix eigenvalue of every particle sector of a cylinder;
* :class:`BetheGroundState` — the Bethe roots and eigenvalue of one sector's ground state;
* :class:`IsotropicEntropy` — the named quantities on the isotropic line, Eqs. (7.1)-(7.4), at a point or at
  the maxima, with the Bethe-ansatz value of the entropy if asked.

Each has ``to_dict``, ``to_json`` and ``to_text``, byte for byte the command line's output (without its
final newline).  Floats from the eigensolvers are printed rounded to 12 decimals (:func:`_rounded`), so
identical runs print identical bytes; the closed forms print ``mpmath.nstr`` at the digits asked.

Examples
--------
>>> import forcenet
>>> forcenet.transfer_spectrum(4).lambda_max
2.0
>>> import mpmath
>>> mpmath.nstr(forcenet.isotropic_point(Q="1/6", dps=20)["v_per_site"], 20)
'0.061615980539380235922'
"""

from __future__ import annotations

import textwrap
from dataclasses import dataclass
from fractions import Fraction
from typing import TYPE_CHECKING, Any, NamedTuple

import mpmath

from forcenet.core.errors import ArgumentError
from forcenet.rendering import Rendered

if TYPE_CHECKING:  # pragma: no cover - annotations only
    import numpy as np

__all__ = ["Sector", "TransferSpectrum", "BetheGroundState", "IsotropicEntropy"]


def _rounded(x: float) -> float:
    """A float rounded to 12 decimals, the eigensolvers' accuracy: identical runs print identical bytes
    (BLAS kernels may change the last bits from run to run)."""
    return round(float(x), 12) + 0.0  # + 0.0: no negative zero



COLUMNS = 80  # the text output's width, as the help's (issue 53)


def _wrapped(text: str, indent: str = "  ", first: str = "") -> list[str]:
    """``text`` in lines of at most :data:`COLUMNS` characters, continued at ``indent``; numbers never split.

    Examples
    --------
    >>> [len(line) for line in _wrapped("ab " * 40, first="> ")]
    [79, 43]
    """
    return textwrap.wrap(text, COLUMNS, initial_indent=first, subsequent_indent=indent, break_long_words=False,
                         break_on_hyphens=False)


def _digits(value: str, indent: str = "    ") -> list[str]:
    """A long number on lines of at most :data:`COLUMNS` characters, each but the last ending in ``\\`` (as
    ``bc`` prints its long numbers): every digit is kept.

    Examples
    --------
    >>> for line in _digits("0." + "1" * 80, indent="  "):
    ...     print(line)
      0.111111111111111111111111111111111111111111111111111111111111111111111111111\\
      11111
    """
    step = COLUMNS - len(indent) - 1
    chunks = [value[k:k + step] for k in range(0, len(value), step)] or [""]
    return [indent + chunk + "\\" for chunk in chunks[:-1]] + [indent + chunks[-1]]


class Sector(NamedTuple):
    """One particle sector of the transfer matrix: its particle number, largest eigenvalue and ``log(lambda)/L``."""

    particles: int
    eigenvalue: float
    entropy_per_site: float


@dataclass(frozen=True)
class TransferSpectrum(Rendered):
    """The largest transfer-matrix eigenvalue of each particle sector on a cylinder of width ``L`` (Sec. 7.4.1).

    Returned by :func:`forcenet.transfer_spectrum`; :meth:`to_json` and :meth:`to_text` are what
    ``forcenet transfer`` prints.

    Parameters
    ----------
    L : int
        Cylinder width.
    sectors : tuple of Sector
        Each sector computed: particles per row, largest eigenvalue, entropy per site ``log(lambda)/L``.
    particles : int, optional
        The one sector asked for (None: all ``L + 1``).

    Examples
    --------
    >>> import forcenet
    >>> s = forcenet.transfer_spectrum(7, particles=2)
    >>> round(s.sectors[0].eigenvalue, 12)  # 2 cos(pi/7)
    1.801937735805
    """

    L: int
    sectors: tuple[Sector, ...]
    particles: int | None = None

    def _rows(self) -> list[dict[str, Any]]:
        return [{"particles": s.particles, "lambda": _rounded(s.eigenvalue),
                 "entropy_per_site": _rounded(s.entropy_per_site)} for s in self.sectors]

    @property
    def lambda_max(self) -> float:
        """The largest eigenvalue over the sectors computed (rounded to 12 decimals, as printed).

        Examples
        --------
        >>> import forcenet
        >>> forcenet.transfer_spectrum(5).lambda_max
        2.0
        """
        return max(r["lambda"] for r in self._rows())

    @property
    def bulk(self) -> Sector | None:
        """The sector with particles (``n >= 1``) of largest eigenvalue; None when one sector was asked for.

        The empty row's ``lambda = 2`` counts a horizontal line around the cylinder; the bulk's entropy
        per site estimates the model's.

        Examples
        --------
        >>> import forcenet
        >>> b = forcenet.transfer_spectrum(6).bulk
        >>> b.particles, round(b.entropy_per_site, 6)
        (2, 0.091551)
        """
        if self.particles is not None:
            return None
        bulk = [s for s in self.sectors if s.particles > 0]
        return max(bulk, key=lambda s: _rounded(s.eigenvalue)) if bulk else None

    def to_dict(self) -> dict[str, Any]:
        """The JSON fields of ``forcenet transfer --format json`` (floats rounded to 12 decimals).

        Returns
        -------
        dict

        Examples
        --------
        >>> import forcenet
        >>> forcenet.transfer_spectrum(4, particles=0).to_dict()["sectors"]
        [{'particles': 0, 'lambda': 2.0, 'entropy_per_site': 0.17328679514}]
        """
        rows = self._rows()
        top = max(rows, key=lambda r: r["lambda"])
        out: dict[str, Any] = {"L": self.L, "lambda_max": top["lambda"], "entropy_per_site": top["entropy_per_site"],
                               "sectors": rows}
        bulk = [r for r in rows if r["particles"] > 0]
        if bulk and self.particles is None:
            best = max(bulk, key=lambda r: r["lambda"])
            out["bulk"] = {"particles": best["particles"], "entropy_per_site": best["entropy_per_site"]}
        return out

    def to_text(self) -> str:
        """What ``forcenet transfer`` prints: the largest eigenvalue, then one line per sector.

        Returns
        -------
        str

        Examples
        --------
        >>> import forcenet
        >>> print(forcenet.transfer_spectrum(3, particles=0).to_text())
        chicken-wire transfer matrix, cylinder of width L = 3:
          lambda_max = 2, log(lambda)/L = 0.231049060187 per site
          n =  0: lambda = 2   log(lambda)/L = 0.231049060187
        """
        rows = self._rows()
        top = max(rows, key=lambda r: r["lambda"])
        lines = [f"chicken-wire transfer matrix, cylinder of width L = {self.L}:",
                 *_wrapped(f"lambda_max = {top['lambda']:.15g}, log(lambda)/L = {top['entropy_per_site']:.12g} "
                           "per site", "    ", "  ")]
        lines += [f"  n = {r['particles']:2d}: lambda = {r['lambda']:.15g}   log(lambda)/L = {r['entropy_per_site']:.12g}"
                  for r in rows]
        return "\n".join(lines)


@dataclass(frozen=True)
class BetheGroundState(Rendered):
    """The ground state of one sector of the nested Bethe ansatz (Sec. 7.4.2): roots and eigenvalue.

    Returned by :func:`forcenet.bethe_ground_state`; :meth:`to_json` and :meth:`to_text` are what
    ``forcenet bethe`` prints.

    Parameters
    ----------
    solution : forcenet.numeric.chicken_wire.bethe.BetheSolution
        The engine's solution: width ``L``, ``n`` particles, ``m`` left-movers, roots ``w`` and ``u``, residual.

    Examples
    --------
    >>> import forcenet
    >>> g = forcenet.bethe_ground_state(8, 3, 1)
    >>> round(g.eigenvalue, 12), (g.L, g.n, g.m)
    (1.563320996252, (8, 3, 1))
    """

    solution: Any

    @property
    def L(self) -> int:
        """Cylinder width.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.bethe_ground_state(6).L
        6
        """
        return int(self.solution.L)

    @property
    def n(self) -> int:
        """Particles per row.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.bethe_ground_state(6).n
        2
        """
        return int(self.solution.n)

    @property
    def m(self) -> int:
        """Left-movers among the particles.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.bethe_ground_state(6).m
        1
        """
        return int(self.solution.m)

    @property
    def eigenvalue(self) -> float:
        """The transfer-matrix eigenvalue ``Lambda = prod u`` of the ground state.

        Examples
        --------
        >>> import forcenet
        >>> round(forcenet.bethe_ground_state(6).eigenvalue, 12)  # sqrt 3
        1.732050807569
        """
        return float(self.solution.eigenvalue)

    @property
    def entropy_per_site(self) -> float:
        """``log(Lambda)/L``.

        Examples
        --------
        >>> import forcenet
        >>> round(forcenet.bethe_ground_state(6).entropy_per_site, 6)
        0.091551
        """
        return float(self.solution.entropy_per_site)

    @property
    def residual(self) -> float:
        """The largest relative residual of the Bethe equations at the roots.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.bethe_ground_state(6).residual < 1e-10
        True
        """
        return float(self.solution.residual)

    @property
    def w(self) -> np.ndarray:
        """The ``n`` roots ``w`` (complex).

        Examples
        --------
        >>> import forcenet
        >>> len(forcenet.bethe_ground_state(6).w)
        2
        """
        return self.solution.w

    @property
    def u(self) -> np.ndarray:
        """The ``m`` roots ``u`` (complex); ``Lambda = prod u``.

        Examples
        --------
        >>> import forcenet
        >>> len(forcenet.bethe_ground_state(6).u)
        1
        """
        return self.solution.u

    def to_dict(self) -> dict[str, Any]:
        """The JSON fields of ``forcenet bethe --format json`` (floats rounded to 12 decimals).

        Returns
        -------
        dict

        Examples
        --------
        >>> import forcenet
        >>> d = forcenet.bethe_ground_state(6).to_dict()
        >>> d["eigenvalue"], d["u"]
        (1.732050807569, [[1.732050807569, 0.0]])
        """
        return {
            "L": self.L, "n": self.n, "m": self.m, "eigenvalue": _rounded(self.eigenvalue),
            "entropy_per_site": _rounded(self.entropy_per_site), "residual": float(f"{self.residual:.1e}"),
            "w": [[round(float(z.real), 12), round(float(z.imag), 12)] for z in self.w],
            "u": [[round(float(z.real), 12), round(float(z.imag), 12)] for z in self.u],
        }

    def to_text(self) -> str:
        """What ``forcenet bethe`` prints: the eigenvalue, then the roots ``u`` and ``w``.

        Returns
        -------
        str

        Examples
        --------
        >>> import forcenet
        >>> print(forcenet.bethe_ground_state(6).to_text())
        Bethe ansatz, L = 6, n = 2 particles, m = 1 left-movers:
          Lambda = 1.73205080756888, log(Lambda)/L = 0.0915510240556758 per site
          max residual of the Bethe equations 4.5e-16
          u: +1.7320508076+0.0000000000i
          w: +0.8660254038-0.5000000000i  +0.8660254038+0.5000000000i
        """
        lines = [*_wrapped(f"Bethe ansatz, L = {self.L}, n = {self.n} particles, m = {self.m} left-movers:"),
                 *_wrapped(f"Lambda = {self.eigenvalue:.15g}, log(Lambda)/L = {self.entropy_per_site:.15g} per site",
                           "    ", "  "),
                 f"  max residual of the Bethe equations {self.residual:.1e}"]
        for name, roots in (("u", self.u), ("w", self.w)):  # two roots a line (5 + 2 x 28 columns)
            lines += _wrapped("  ".join(f"{z.real:+.10f}{z.imag:+.10f}i" for z in roots), "     ", f"  {name}: ")
        return "\n".join(lines)


class BetheValue(NamedTuple):
    """The Bethe-ansatz value of the entropy per site at a density: value, error, the rational densities solved."""

    v: float
    error: float
    densities: tuple[Fraction, ...]
    L_max: int


@dataclass(frozen=True)
class IsotropicEntropy(Rendered):
    """The named quantities of the chicken-wire model on the isotropic line, Eqs. (7.1)-(7.4), to ``dps`` digits.

    Returned by :func:`forcenet.isotropic_point` (the quantities at one point) and
    :func:`forcenet.isotropic_maximum` (the maxima); :meth:`to_json` and :meth:`to_text` are what
    ``forcenet entropy`` prints.  ``result[key]`` is a row's value (``mpmath.mpf``, rounded to ``dps``
    digits).

    Parameters
    ----------
    dps : int
        Decimal digits of every value.
    rows : tuple of (str, str, mpmath.mpf)
        ``(key, description, value)``, in the command line's order.
    bethe : BetheValue, optional
        The independent Bethe-ansatz value of ``v`` (``bethe=True``): ``v``, its error, the densities solved,
        the largest width.

    Examples
    --------
    >>> import forcenet
    >>> e = forcenet.isotropic_point(phi=0, dps=15)
    >>> import mpmath
    >>> e.keys()[:3], mpmath.nstr(e["Q"], 15)  # 1/2 - 1/(2 sqrt3)
    (['phi', 'Q', 'v_per_site'], '0.211324865405187')
    """

    dps: int
    rows: tuple[tuple[str, str, mpmath.mpf], ...]
    bethe: BetheValue | None = None

    def __getitem__(self, key: str) -> mpmath.mpf:
        for name, _, value in self.rows:
            if name == key:
                return value
        raise ArgumentError(f"key={key!r} is not a row here: the rows are {', '.join(self.keys())}")

    def keys(self) -> list[str]:
        """The rows' keys, in order.

        Returns
        -------
        list of str

        Examples
        --------
        >>> import forcenet
        >>> forcenet.isotropic_maximum(dps=10).keys()[:2]
        ['v_max_per_site', 'Q_max']
        """
        return [key for key, _, _ in self.rows]

    def describe(self, key: str) -> str:
        """What the row ``key`` is (the command line's description, with the equation).

        Parameters
        ----------
        key : str
            A row's key (:meth:`keys`).

        Returns
        -------
        str

        Examples
        --------
        >>> import forcenet
        >>> forcenet.isotropic_point(Q="1/6", dps=10).describe("v_per_site")
        'entropy per chicken-wire site, Eq. (7.1)'
        """
        for name, what, _ in self.rows:
            if name == key:
                return what
        raise ArgumentError(f"key={key!r} is not a row here: the rows are {', '.join(self.keys())}")

    def to_dict(self) -> dict[str, Any]:
        """The JSON fields of ``forcenet entropy --format json``: ``mpmath.nstr`` at ``dps`` digits, notes, Bethe.

        Returns
        -------
        dict

        Examples
        --------
        >>> import forcenet
        >>> forcenet.isotropic_point(Q=0, dps=8).to_dict()["v_per_site"]
        '0.0'
        """
        out: dict[str, Any] = {"dps": self.dps}
        out.update({key: mpmath.nstr(value, self.dps) for key, _, value in self.rows})
        out.update({f"{key}_note": what.split("; ", 1)[1] for key, what, _ in self.rows if "; NOT VALID here" in what})
        if self.bethe is not None:
            out.update({"v_bethe": self.bethe.v, "v_bethe_error": self.bethe.error,
                        "bethe_densities": [str(f) for f in self.bethe.densities]})
        return out

    def to_text(self) -> str:
        """What ``forcenet entropy`` prints: per quantity ``key = value``, then ``(description)`` below it.

        At most 80 columns: when a ``key = value`` line would be wider, every value goes on its own lines
        below its key, a long one continued with ``\\`` at the line's end (every digit printed; ``--format
        json`` has them on one line).

        Returns
        -------
        str

        Examples
        --------
        >>> import forcenet
        >>> print("\\n".join(forcenet.isotropic_point(Q="1/6", dps=10).to_text().splitlines()[4:6]))
        v_per_site          = 0.06161598054
            (entropy per chicken-wire site, Eq. (7.1))
        >>> print("\\n".join(forcenet.isotropic_point(Q="1/6", dps=100).to_text().splitlines()[8:12]))
        v_per_site =
            0.0616159805393802359215413794766532118272731312289089670592134875347696395\\
            3982563133723928137063737215
            (entropy per chicken-wire site, Eq. (7.1))
        """
        rows = [(key, mpmath.nstr(value, self.dps), what) for key, what, value in self.rows]
        if self.bethe is not None:
            b = self.bethe
            rows.append(("v_bethe", f"{b.v:.12f} +- {b.error:.1e}", "entropy per site from the Bethe ansatz, "
                         f"densities {', '.join(str(f) for f in b.densities)}, L <= {b.L_max}"))
        width = max(len(key) for key, _, _ in rows)
        inline = all(width + 3 + len(value) <= COLUMNS for _, value, _ in rows)
        lines = []
        for key, value, what in rows:
            lines += [f"{key:<{width}} = {value}"] if inline else [f"{key} =", *_digits(value)]
            lines += _wrapped(f"({what})", "     ", "    ")
        return "\n".join(lines)
