"""Validate once (issue 25): how many argument checks a command's arguments meet on their way to the engines.

The map (notes/architecture.md, "How far an argument travels") states the rule: an argument is checked
at each public boundary it crosses, and trusted inside.  ``benchmarks/walks.py`` counts the checks of a
command run in this process; these tests hold the two walks of issue 25 to their measured lengths, so a
check added inside an engine (a public function calling another public function, a route re-checking
what its engine checks) fails here instead of lengthening the walk unnoticed.
"""

import importlib.util
from pathlib import Path

import pytest

WALKS = Path(__file__).resolve().parent.parent / "benchmarks" / "walks.py"


@pytest.fixture(scope="module")
def walk():
    spec = importlib.util.spec_from_file_location("forcenet_walks", WALKS)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.walk


def test_the_table_walk_checks_each_argument_once_per_public_boundary(walk):
    result = walk(["table", "--N", "12", "--format", "json", "--method", "fast"])
    assert result["exit"] == 0
    checks = result["checks"]
    # N: the parser (check_int), the engine's table_plan and table_run, exact_table, and the first calls of
    # the cached count and normalization; moments: the engine's table_plan and table_run, exact_table
    assert checks.get("check_layers", 0) <= 5, checks
    assert checks.get("check_moments", 0) <= 3, checks
    assert result["check_calls"] <= 11, checks  # 24 before the renovation (commit 3ee584c)


def test_the_entropy_walk_checks_dps_once_per_public_function(walk):
    result = walk(["entropy", "--phi", "0.3", "--dps", "30"])
    assert result["exit"] == 0
    assert result["checks"].get("check_dps", 0) <= 9, result["checks"]  # one per closed form the command prints
    assert result["check_calls"] <= 30, result["checks"]  # 37 before the renovation
