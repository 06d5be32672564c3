"""Exact counterparts of what the samplers estimate, in the shape ``assert_agrees`` takes.

Examples
--------
>>> [str(w) for w in exact_mean_W(3)[-1]]
['1/4', '1/2', '1/4']
"""

from __future__ import annotations

from fractions import Fraction
from functools import lru_cache
from typing import TYPE_CHECKING

from forcenet.core.errors import ArgumentError
from forcenet.exact import mean_W
from forcenet.exact.packing.mobilized import mean_W_mobilized
from forcenet.exact.protocol import BoundedTable
from forcenet.numeric.packing import Scene

if TYPE_CHECKING:
    from forcenet.numeric.packing import Scene

__all__ = ["exact_mean_W"]


@lru_cache(maxsize=128)
def _packing(N: int, P: int, F: Fraction, j0: int | None, pv: Fraction, mg: Fraction) -> list[list[Fraction]]:
    return mean_W_mobilized(N, P, F=F, j0=j0, pv=pv, mg=mg)


def exact_mean_W(target: int | Scene) -> BoundedTable:
    """Exact ``<W_{i,j}>`` of the ``N``-layer triangle (Eqs. (4.63)-(4.77)) or of a fully mobilized packing scene.

    Parameters
    ----------
    target : int or forcenet.numeric.packing.Scene
        ``N`` for the triangle under the overload
        (:func:`forcenet.exact.mean_W`, rows of lengths ``1..N``), or a scene
        with ``ph=None`` and ``(N-1)(P-1) <= 9``
        (:func:`forcenet.exact.packing.mobilized.mean_W_mobilized`, an
        ``N x P`` table; the scene's float loads are taken exactly).

    Returns
    -------
    forcenet.exact.protocol.BoundedTable
        Rows of Fractions that carry their bounds (``compare`` uses them): every ``W`` of the triangle in
        ``[0, 1]``; every ``W`` of row ``i`` of a packing in ``[0, F + P pv + i P mg]`` (repulsive forces carry
        at most the row's load).

    Raises
    ------
    ArgumentError
        If the scene has ``ph`` set, or ``N`` (or the scene's size) is out of the exact routes' range.

    Examples
    --------
    >>> from forcenet.numeric.packing import Scene
    >>> table = exact_mean_W(Scene(N=2, P=2, F=1.0, j0=1, mg=1.0))
    >>> table, table.bounds
    ([[Fraction(2, 1), Fraction(1, 1)], [Fraction(2, 1), Fraction(3, 1)]], (0, [[Fraction(3, 1), Fraction(3, 1)], [Fraction(5, 1), Fraction(5, 1)]]))
    >>> exact_mean_W(Scene(N=2, P=2, F=1.0, mg=1.0, ph=2.0))
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: scene.ph=2.0: exact means are known when every q is allowed (ph=None)
    """

    if isinstance(target, Scene):
        if target.ph is not None:
            raise ArgumentError(f"scene.ph={target.ph}: exact means are known when every q is allowed (ph=None)")
        F, pv, mg = Fraction(target.F), Fraction(target.pv), Fraction(target.mg)
        loads = [[F + target.P * pv + (i + 1) * target.P * mg] * target.P for i in range(target.N)]
        return BoundedTable(_packing(target.N, target.P, F, target.j0, pv, mg), (0, loads),
                            "every W of a packing's row lies in [0, the row's load F + P pv + i P mg]")

    return mean_W(target)
