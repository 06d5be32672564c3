"""Validate once, plan once (issues 25, 44): the checks and plans a command's arguments meet on their way.

The map (notes/architecture.md, "The seam" and "The rules, each with its test") states the rule: the command line's parser
checks the text it reads, the registry (``forcenet.exact.routes.check_request``) checks the request once,
and everything behind it (the engine objects' ``plan``/``run``) trusts it.  ``benchmarks/walks.py``
counts the checks of a command run in this process; these tests hold the walks to one check of ``N``, the
request's (the parser reads the text and leaves the range to it), so a check added inside an engine fails here
instead of lengthening the walk.
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


@pytest.mark.parametrize("method", [[], ["--method", "fast"]], ids=["auto", "fast"])
def test_the_table_walk_checks_the_request_once(walk, method):
    result = walk(["table", "--N", "12", "--format", "json", *method])
    assert result["exit"] == 0
    checks = result["checks"]
    # N: the parser reads the text as an integer and leaves its range to the registry's one request check
    assert checks.get("check_layers", 0) + checks.get("check_int", 0) == 0, checks
    assert checks.get("check_request", 0) == 1, checks  # N, moments, method, memory once (delegations not counted)
    assert checks.get("check_moments", 0) == 0, checks  # moments: checked in the request only
    assert checks.get("check_progress", 0) == 1, checks  # the run's progress= once, where the plan runs
    assert result["check_calls"] == 4, checks  # and the two destination checks of standard output; 21 (auto) before


@pytest.mark.parametrize("argv, line", [
    (["table", "--N", "1"], "forcenet table: error: argument --N: N=1 is out of range: N must be an integer >= 2"),
    (["table", "--N", "-3", "--format", "json"],
     "forcenet table: error: argument --N: N=-3 is out of range: N must be an integer >= 2"),
    (["table", "--N", "x", "--format", "json"],
     "forcenet table: error: argument --N: N='x' is not an integer: N must be an integer >= 2"),
    # the chicken-wire commands' integers: read by the parser, ranged by the faces (the engines' limits)
    (["transfer", "--L", "15"],
     "forcenet transfer: error: argument --L: L=15 is out of range: L must be an integer in 2..14"),
    (["transfer", "--L", "5", "--particles", "-1"],
     "forcenet transfer: error: argument --particles: particles=-1 is out of range: particles must be an integer >= 0"),
    (["bethe", "--L", "5001"],
     "forcenet bethe: error: argument --L: L=5001 is out of range: L must be an integer in 3..5000"),
    (["bethe", "--L", "9", "--n", "1"],
     "forcenet bethe: error: argument --n: n=1 is out of range: n must be an integer >= 2"),
    (["bethe", "--L", "9", "--n", "4", "--m", "0"],
     "forcenet bethe: error: argument --m: m=0 is out of range: m must be an integer >= 1"),
    (["entropy", "--phi", "0.3", "--dps", "10001"],
     "forcenet entropy: error: argument --dps: dps=10001 is out of range: dps must be an integer in 5..10000"),
    (["entropy", "--max", "--dps", "4"],
     "forcenet entropy: error: argument --dps: dps=4 is out of range: dps must be an integer in 5..10000"),
    (["entropy", "--Q", "1/6", "--bethe", "--L-max", "1201"],
     "forcenet entropy: error: argument --L-max: L_max=1201 is out of range: L_max must be an integer in 60..1200"),
    (["limit", "--x", "0.2", "--z", "0.6", "--dps", "10001"],
     "forcenet limit: error: argument --dps: dps=10001 is out of range: dps must be an integer in 5..10000"),
    (["limit", "--x", "0.3", "--z", "0.3", "--dps", "61"],  # a lattice direction: the edge law's digits
     "forcenet limit: error: argument --dps: dps=61 is out of range: dps must be an integer in 5..60"),
    (["entropy", "--Q", "1/6", "--bethe", "--L-max", "x"],
     "forcenet entropy: error: argument --L-max: L_max='x' is not an integer: L_max must be an integer in 60..1200"),
])
def test_a_range_left_to_the_front_door_reads_as_the_parsers_refusal(argv, line, capsys, tmp_path, monkeypatch):
    """The parser reads --N (--L, --dps...), the front door checks its range once; the refusal still names the
    option, exit 2."""
    from forcenet.cli import main

    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert (out, err) == ("", line + "\n")
    assert not list(tmp_path.iterdir())  # nothing written


@pytest.fixture
def plan_calls(monkeypatch):
    """Calls of each table engine's plan (the engine object's, which the registry asks), counted by method."""
    from forcenet.exact import routes

    calls: dict[str, int] = {}
    for engine in routes.TABLE_ENGINES:
        real = engine.table_plan

        def counted(*args, _real=real, _method=engine.name, **kwargs):
            calls[_method] = calls.get(_method, 0) + 1
            return _real(*args, **kwargs)

        monkeypatch.setattr(engine, "table_plan", counted)
    return calls


def test_the_chosen_engine_is_planned_once_per_run(plan_calls, capsys):
    import forcenet
    from forcenet.cli import main

    table = forcenet.table(12)
    assert plan_calls[table.method] == 1, plan_calls  # auto compared the plans; the chosen one runs as planned
    assert all(n == 1 for n in plan_calls.values()), plan_calls  # every candidate planned at most once
    plan_calls.clear()
    assert main(["table", "--N", "12", "--format", "json"]) == 0
    assert capsys.readouterr().out.startswith("{")
    assert plan_calls[table.method] == 1 and all(n == 1 for n in plan_calls.values()), plan_calls
    plan_calls.clear()
    assert main(["table", "--N", "12", "--format", "json", "--method", "fast"]) == 0
    assert plan_calls == {"fast": 1}


def test_the_entropy_walk_checks_dps_once_per_public_function(walk):
    result = walk(["entropy", "--phi", "0.3", "--dps", "30"])
    assert result["exit"] == 0
    assert result["checks"].get("check_dps", 0) <= 9, result["checks"]  # one per closed form the command prints
    assert result["checks"].get("check_progress", 0) <= 1, result["checks"]  # progress= once, where it runs
    assert result["check_calls"] <= 30, result["checks"]  # 37 before the renovation, 30 before --dps was deferred,
    # 29 then, and one check of progress= since issue 56
