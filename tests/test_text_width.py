"""Every command's default text output fits 80 columns and loses nothing (issue 53, item 8).

``count`` is the exception: it prints one integer and nothing else, for a script to read
(``$(forcenet count --N 20)``); at N = 20 it has 120 digits, and it is left on one line.

Each command runs in-process on a small input; its stdout must have no line over 80 characters. Where the
text had to be wrapped (``entropy``'s long values, ``bethe``'s roots), the wrapped text still carries every
digit of ``--format json``.
"""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

import forcenet.numeric.force_chains.newman_ziff as newman_ziff
from forcenet.cli import main

COLUMNS = 80

COMMANDS = [
    ["count", "--N", "12"],
    ["maps", "--N", "7"],
    ["limit", "--x", "0.2", "--z", "0.6"],
    ["sample", "--N", "6", "--samples", "400", "--seed", "1", "--sampler", "metropolis"],
    ["transfer", "--L", "6"],
    ["transfer", "--L", "7", "--particles", "2"],
    ["bethe", "--L", "6", "--n", "2", "--m", "1"],
    ["bethe", "--L", "8", "--n", "3", "--m", "1"],
    ["entropy", "--phi", "0.3"],
    ["entropy", "--Q", "1/3"],
    ["entropy", "--max"],
    ["entropy", "--phi", "0.3", "--dps", "200"],
    ["dist", "--N", "7", "--layer", "7"],
    ["dist", "--N", "7", "--contact", "F1", "--grain", "5,2"],
    ["scaling", "--model", "percolation", "--sizes", "6,8,10", "--samples", "10", "--replicas", "2"],
]

SMALL_NETWORK = {"grains": 1, "contacts": [[0, None, "-3/5", "-4/5"], [0, None, "3/5", "-4/5"], [0, None, 0, -1]],
                 "loads": [[0, 0, -1]]}


def text_of(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    code = main([*argv, "--quiet"] if argv[0] not in ("count", "maps", "limit", "dist", "clusters") else argv)
    out = capsys.readouterr().out
    assert code == 0, argv
    return out


def assert_fits(text: str) -> None:
    wide = [line for line in text.splitlines() if len(line) > COLUMNS]
    assert text.strip() and not wide, "\n".join(wide)


@pytest.mark.parametrize("argv", COMMANDS, ids=" ".join)
def test_text_output_fits_80_columns(argv, capsys):
    assert_fits(text_of(argv, capsys))


def test_clusters_and_network_fit_80_columns(tmp_path, capsys):
    rng = np.random.default_rng(0)
    files = []
    for L in (6, 8, 10):
        lat = newman_ziff.periodic_lattice("square", L)
        rows = np.concatenate([np.column_stack([np.full(lat.bonds, k), lat.head, lat.tail, rng.random(lat.bonds)])
                               for k in range(10)])
        files.append(str(tmp_path / f"L{L}.csv"))
        np.savetxt(files[-1], rows, fmt="%g", delimiter=",", header="sample,i,j,f", comments="")
    assert_fits(text_of(["clusters", *files, "--replicas", "2"], capsys))
    path = tmp_path / "net.json"
    path.write_text(json.dumps(SMALL_NETWORK))
    pytest.importorskip("PyNormaliz")
    assert_fits(text_of(["network", str(path), "--exact", "--moments", "2"], capsys))


def test_wrapped_entropy_keeps_every_digit(capsys):
    """dps = 120: each value spans two lines ending in a backslash; joined, they are the JSON's strings."""
    argv = ["entropy", "--phi", "0.3", "--dps", "120"]
    exact = json.loads(text_of([*argv, "--format", "json"], capsys))
    lines = text_of(argv, capsys).splitlines()
    assert_fits("\n".join(lines))
    values: dict[str, str] = {}
    key = None
    for line in lines:
        if line.endswith(" ="):
            key = line[:-2]
            values[key] = ""
        elif key is not None and re.match(r"    [-0-9]", line):  # a value's line (a description's start "(")
            values[key] += line.strip().removesuffix("\\")
    assert values and values == {k: exact[k] for k in values}
    assert any(line.endswith("\\") for line in lines)


def test_wrapped_bethe_roots_are_the_json_roots(capsys):
    """Three roots w on two lines: the same numbers, to 10 decimals, as ``--format json``."""
    argv = ["bethe", "--L", "8", "--n", "3", "--m", "1"]
    exact = json.loads(text_of([*argv, "--format", "json"], capsys))
    text = text_of(argv, capsys)
    after = text.split("  w: ", 1)[1].split()
    assert [complex(z.replace("i", "j")) for z in after] == pytest.approx(
        [complex(re, im) for re, im in exact["w"]], abs=1e-10)
    assert len(after) == 3 and len(text.splitlines()) == 3 + 1 + 2  # header, Lambda, residual; u; w on 2 lines
