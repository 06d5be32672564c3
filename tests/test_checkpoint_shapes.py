"""Every checkpoint store declares the shape of its records (issue 56 item 2, for every store).

A record with a valid checksum but the wrong shape (a faulty program, a hand edit, a record of another
version) used to reach a ``reshape`` and fail the same way on every rerun.  Each store -- count, table, the
second level, the lattice directions, the floor and the layers (pooled and per grain), the finite-size
scaling's blocks -- now names such a record on stderr and recomputes it; the result is the fresh run's.
"""

from __future__ import annotations

import os

import numpy as np
import pytest

import forcenet
from forcenet.core.checkpoints import CheckpointStore
from forcenet.exact.triangle.de_bruijn import floor, layers
from forcenet.exact.triangle.free_fermion import partial_sums, route
from forcenet.exact.triangle.prime_tasks import ROUTES, record_shape
from forcenet.exact.triangle.staircase import dimension

N = 6
# (the store's route key, its layer, the run): each run at N = 6 takes well under a second
RUNS = {
    "count": (None, lambda d: route.count(N, checkpoint=d)),
    "table": (None, lambda d: route.mean_W(N, checkpoint=d)),
    "table2": (None, lambda d: partial_sums.second_survival_tables(N, checkpoint=d)),
    "lattice": (None, lambda d: route.lattice_direction(N, checkpoint=d)),
    "floor": (None, lambda d: floor.floor_pooled_gap_law(N, checkpoint=d)),
    "floor-grains": (None, lambda d: floor.floor_gap_laws(N, checkpoint=d)),
    "layer": (4, lambda d: layers.layer_pooled_gap_law(N, 4, checkpoint=d)),
    "layer-grains": (3, lambda d: layers.layer_gap_laws(N, 3, checkpoint=d)),
}


GAPS = dimension(N) + 2  # a gap law's gaps 0..d + 1
SHAPES = {"floor": (1, GAPS), "floor-grains": (N, GAPS), "layer": (1, GAPS), "layer-grains": (3, GAPS)}


def test_every_route_over_primes_has_a_case_and_a_shape():
    assert set(RUNS) == set(ROUTES)  # a new route over primes needs its shape (and a case here)
    assert {key for key in ROUTES if record_shape(key, N) is None} == set(SHAPES)  # given by the de Bruijn callers


def _plant(folder: str, shape: tuple[int, ...]) -> str:
    """Overwrite the first record of ``folder`` with a valid record (checksum recomputed) of ``shape``."""
    name = sorted(os.listdir(folder))[0]
    key = int(name[1:-4])
    base = os.path.basename(folder)
    route_name, rest = base.split("-N", 1)
    store = CheckpointStore(os.path.dirname(folder), route_name, int(rest.split("-m")[0]))
    with open(os.path.join(folder, name), "wb") as handle:
        handle.write(store.encode(key, np.ones(shape, dtype=np.int64)))
    return os.path.join(folder, name)


def _same(a, b) -> bool:
    return repr(a) == repr(b)


@pytest.mark.parametrize("key", list(RUNS))
def test_a_record_of_the_wrong_shape_is_named_and_recomputed(key, tmp_path, capsys):
    layer, run = RUNS[key]
    fresh = run(None)
    assert _same(run(tmp_path), fresh)  # the records written
    capsys.readouterr()
    folder = os.path.join(tmp_path, f"{ROUTES[key]}{'' if layer is None else layer}-N{N}-m1-v1")
    shape = SHAPES.get(key) or record_shape(key, N)
    assert shape is not None
    wrong = tuple(s + 1 for s in shape) if shape else (2,)  # one more row and column: it cannot fit
    planted = _plant(folder, wrong)
    assert _same(run(tmp_path), fresh)  # recomputed, not a reshape error
    err = capsys.readouterr().err
    named = [line for line in err.splitlines() if planted in line]
    assert len(named) == 1 and f"a record of shape {wrong} where {shape} belongs" in named[0], err
    assert _same(run(tmp_path), fresh) and planted not in capsys.readouterr().err  # written again, whole


def test_a_scaling_block_of_the_wrong_shape_is_named_and_recomputed(tmp_path, capsys):
    options = {"sizes": (8, 12, 16), "samples": 64, "blocks": 2, "replicas": 0, "thresholds": 100}
    fresh = forcenet.scaling("percolation", **options)
    assert forcenet.scaling("percolation", checkpoint=tmp_path, **options).fit.value == fresh.fit.value
    capsys.readouterr()
    (folder,) = [os.path.join(tmp_path, f) for f in os.listdir(tmp_path)]
    planted = _plant(folder, (5,))
    again = forcenet.scaling("percolation", checkpoint=tmp_path, **options)
    err = capsys.readouterr().err
    assert again.fit.value == fresh.fit.value  # the planted block recomputed (the others reused)
    named = [line for line in err.splitlines() if planted in line]
    assert len(named) == 1 and "a record of shape (5,) where" in named[0], err
