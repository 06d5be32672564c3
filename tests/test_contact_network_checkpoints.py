"""The contact-network sampler's checkpoints (issue 55): interrupted runs resume with the uninterrupted run's bits."""

from __future__ import annotations

import json
import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import forcenet
from forcenet.cli import main
from forcenet.exact.contact_network.geometries import rectangular_packing, triangle
from forcenet.numeric.contact_network import chain_records
from forcenet.numeric.contact_network.hit_and_run import HitAndRun, run_chains


class Interrupted(Exception):
    """Stands for Ctrl-C (a KeyboardInterrupt would stop pytest itself)."""


def _interrupt_after(states: int):
    done = [0]

    def tick(k: int = 1) -> None:
        done[0] += k
        if done[0] >= states:
            raise Interrupted

    return tick


@pytest.mark.parametrize("geometry", [triangle(4), rectangular_packing(2, 2)], ids=["frictionless", "frictional"])
def test_an_interrupted_chain_resumes_with_the_same_bits(geometry, tmp_path):
    """Blocks of 100 states: interrupted in the third block, resumed from the two recorded ones; every state
    equals the uninterrupted run's (frictionless: slacks are forces; frictional: slacks tracked apart)."""
    walk = HitAndRun(geometry.network)
    whole = walk.run(600, seed=3, burn_in=50, block=100).samples
    with pytest.raises(Interrupted):
        walk.run(600, seed=3, burn_in=50, block=100, checkpoint=str(tmp_path), progress=_interrupt_after(250))
    ticks: list[int] = []
    resumed = HitAndRun(geometry.network).run(600, seed=3, burn_in=50, block=100, checkpoint=str(tmp_path),
                                              progress=ticks.append)
    assert ticks[0] == 200  # the two finished blocks, reused
    assert np.array_equal(resumed.samples, whole)
    again: list[int] = []
    HitAndRun(geometry.network).run(600, seed=3, burn_in=50, block=100, checkpoint=str(tmp_path),
                                    progress=again.append)
    assert again == [600]  # all six blocks recorded: nothing sampled


def test_a_damaged_block_is_recomputed_and_another_request_is_not_reused(tmp_path):
    walk = HitAndRun(triangle(3).network)
    whole = walk.run(300, seed=1, burn_in=20, block=100, checkpoint=str(tmp_path)).samples
    (folder,) = os.listdir(tmp_path)
    record = tmp_path / folder / "p1.rec"
    data = bytearray(record.read_bytes())
    data[100] ^= 1
    record.write_bytes(bytes(data))
    reports: list[str] = []
    store = chain_records.chain_store(str(tmp_path), triangle(3).network, ("chain", 1, 300, 20, 1, 100, True),
                                      chain_records.block_shape(100, 15))
    store.report = reports.append
    assert store.load(1) is None and "checksum" in reports[0]
    assert np.array_equal(walk.run(300, seed=1, burn_in=20, block=100, checkpoint=str(tmp_path)).samples, whole)
    other = walk.run(300, seed=2, burn_in=20, block=100, checkpoint=str(tmp_path)).samples  # another seed
    assert not np.array_equal(other, whole) and len(os.listdir(tmp_path)) == 2


def test_independent_chains_are_recorded_one_by_one(tmp_path):
    """chains=2: each finished chain is a record; a lost one is rerun alone, the pooled samples identical."""
    net = triangle(3).network
    with ThreadPoolExecutor(2) as pool:
        first = run_chains(net, 400, 7, 30, 1, 2, executor=pool, checkpoint=str(tmp_path))
        (folder,) = os.listdir(tmp_path)
        os.remove(tmp_path / folder / "p1.rec")
        second = run_chains(net, 400, 7, 30, 1, 2, executor=pool, checkpoint=str(tmp_path))
        plain = run_chains(net, 400, 7, 30, 1, 2, executor=pool)
    assert np.array_equal(first.samples, second.samples) and np.array_equal(first.samples, plain.samples)
    assert first.lengths == (200, 200) and np.array_equal(first.fixed, plain.fixed)


def test_the_command_line_resumes_after_an_interruption(tmp_path, capsys, monkeypatch):
    """``forcenet network FILE --samples K --checkpoint DIR``: interrupted, run again, the same JSON as a run
    without checkpoints (blocks made small so that the run has several)."""
    monkeypatch.setattr(chain_records, "PROJECT_MOVES", 3 * 100)  # d = 3: blocks of 100 states
    path = tmp_path / "net.json"
    geo = triangle(3).network
    path.write_text(json.dumps({"grains": geo.grains, "loads": [[g, str(x), str(y)] for g, (x, y, _) in
                                                                enumerate(geo.loads)],
                                "contacts": [[i, j, str(nx), str(ny)] for i, j, nx, ny in geo.contacts]}))
    args = ["network", str(path), "--samples", "500", "--seed", "4", "--format", "json", "--quiet"]
    assert main(args) == 0
    plain = json.loads(capsys.readouterr().out)
    with pytest.raises(Interrupted):
        forcenet.network(path, samples=500, seed=4, checkpoint=tmp_path / "ck", progress=_interrupt_after(150))
    assert main([*args, "--checkpoint", str(tmp_path / "ck")]) == 0
    assert json.loads(capsys.readouterr().out) == plain
    assert main([*args, "--checkpoint", str(tmp_path / "net.json")]) == 2  # a file, not a directory
    assert "checkpoint" in capsys.readouterr().err
