"""The chicken-wire <-> square-triangle correspondence (notes/chicken_wire.md, Sec. 7), both sides counted independently."""

import copy
import importlib.util
from collections import Counter
from pathlib import Path

import pytest

from forcenet.core.errors import ArgumentError
from forcenet.exact.chicken_wire.tiler import enumerate_tilings, scan_lifts
from forcenet.exact.chicken_wire.tiling import (
    F_IMAGE,
    KERNEL,
    NAME_OF,
    STEP,
    UNIT,
    F,
    Lattice2in2,
    Lattice2in4,
    MapError,
    TilingError,
    canonical_form,
    check_cells,
    check_tiling,
    chicken_wire_configs,
    config_canonical,
    config_to_tiling,
    config_vertex_counts,
    predicted_failures,
    tiling_tiles,
    tiling_to_config,
    zmul,
)

SURVEY = Path(__file__).resolve().parent.parent / "benchmarks" / "tiling_survey.py"  # a test helper, not installed
_spec = importlib.util.spec_from_file_location("forcenet_tiling_survey", SURVEY)
_survey_module = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_survey_module)
call_with_timeout, survey = _survey_module.call_with_timeout, _survey_module.survey

SMALL_TORI = [(2, 2), (2, 3), (3, 2), (3, 3), (3, 4), (4, 3), (4, 4), (2, 6), (5, 5)]


def test_zeta12_arithmetic_and_projection():
    assert all(zmul(UNIT[k]) == UNIT[(k + 1) % 12] for k in range(12))
    assert all(tuple(-c for c in UNIT[k]) == UNIT[k + 6] for k in range(6))
    for k in range(12):  # F(z^k): length 1 (k even) or sqrt3 (k odd) in direction 30k
        x, y = F_IMAGE[k]
        assert x * x + x * y + y * y == (1 if k % 2 == 0 else 3)
    assert [F_IMAGE[k] for k in (0, 2, 4)] == [(1, 0), (0, 1), (-1, 1)]
    assert all(F(k) == (0, 0) for k in KERNEL)


def test_config_enumeration_matches_project_count():
    from forcenet.exact.chicken_wire import count_torus

    for L, M in SMALL_TORI:
        assert sum(1 for _ in chicken_wire_configs(L, M)) == count_torus(L, M)


def _adjacent_lines(config, torus):
    """Independent description of the failures: parallel lines, two of them on neighbouring rows."""
    names = config_vertex_counts(config)
    if names["Y"] or names["inverted Y"]:
        return False
    if names["empty"] == 0:
        return True
    for s, v in config.items():
        if not v:
            continue
        for d, (dx, dy) in STEP.items():
            if d in v:
                continue
            if config[torus.reduce((s[0] + dx, s[1] + dy))]:
                return True  # an occupied neighbour off the line: a second line next to it
    return False


@pytest.mark.parametrize("L,M", SMALL_TORI)
def test_map_is_a_tiling_exactly_off_adjacent_lines(L, M):
    torus = Lattice2in2.rect(L, M)
    for config in chicken_wire_configs(L, M):
        names = config_vertex_counts(config)
        try:
            t = config_to_tiling(config, torus)
        except MapError:
            assert _adjacent_lines(config, torus)
            continue
        assert not _adjacent_lines(config, torus)
        summary = check_tiling(t)
        check_cells(config, torus)
        # tiling vertices = empty sites, squares = pass-through sites, B triangles = Y + inverted Y
        assert summary["V"] == names["empty"]
        assert summary["N_s"] == names["H"] + names["R"] + names["L"]
        assert summary["N_tB"] == names["Y"] + names["inverted Y"]
        assert names["Y"] == names["inverted Y"]
        bonds = sum(len(v) for v in config.values()) // 2
        assert names["empty"] == L * M - bonds + names["Y"]  # e = 1 - 3Q + y
        # inverse o forward = identity (up to translation)
        form, _ = canonical_form(tiling_tiles(t), t["lattice"])
        back, gamma = tiling_to_config(form, t["lattice"])
        assert gamma == torus and config_canonical(back, torus) == config_canonical(config, torus)


@pytest.mark.parametrize("L,M", SMALL_TORI + [(3, 5), (6, 6)])
def test_failure_count_formula(L, M):
    torus = Lattice2in2.rect(L, M)
    fails = 0
    for config in chicken_wire_configs(L, M):
        try:
            config_to_tiling(config, torus)
        except MapError:
            fails += 1
    assert fails == predicted_failures(L, M)


@pytest.mark.parametrize("L,M", [(2, 2), (2, 3), (3, 3), (3, 4), (4, 4), (2, 6), (5, 5)])
def test_independent_tiler_agrees_lattice_by_lattice(L, M):
    r = survey(L, M, enumerate_limit_vertices=30)
    assert r["rows"]
    for row in r["rows"]:
        assert row["tiling_classes"] == row["image_classes"] == row["config_classes"] == row["matched"]
        assert row["configs_predicted"] == row["configs"]
        assert row["round_trip"] == row["tiling_classes"]


def test_no_tilings_on_other_lifts():
    """Lifts of the 3x3 torus that no configuration produces carry no tiling (within the scan)."""
    found, tried = scan_lifts(3, 3, bound=2, vmax=12)
    occurring = {row["lattice"] for row in survey(3, 3, 0)["rows"]}
    assert tried > 50 and {lam.key() for lam in found} == occurring


def test_rotating_by_30_degrees_changes_the_chicken_wire_torus():
    """The empty 3x3 torus (9 A-triangle vertices) turned by 30 degrees is the side-1 honeycomb on 27 sites."""
    torus = Lattice2in2.rect(3, 3)
    empty = {s: frozenset() for s in torus.sites()}
    t = config_to_tiling(empty, torus)
    lam = t["lattice"]
    rot = Lattice2in4(zmul(lam.gens[0]), zmul(lam.gens[1]))
    tiles = [(k, (d + 1) % 12, zmul(p)) for k, d, p in tiling_tiles(t)]
    config, gamma = tiling_to_config(tiles, rot)
    assert gamma.det() == 27
    assert config_vertex_counts(config) == Counter({"empty": 9, "Y": 9, "inverted Y": 9})
    t2 = config_to_tiling(config, gamma)
    check_tiling(t2)
    assert t2["lattice"] == rot


def test_checks_have_teeth():
    """A corrupted image (a face dropped, or a square's corner moved) is rejected by a family error."""
    torus = Lattice2in2.rect(5, 5)
    foam = next(c for c in chicken_wire_configs(5, 5) if config_vertex_counts(c)["Y"] and config_vertex_counts(c)["H"])
    t = config_to_tiling(foam, torus)
    check_tiling(t)
    bad = copy.deepcopy(t)
    bad["faces"].pop()
    with pytest.raises(TilingError):
        check_tiling(bad)
    bad = copy.deepcopy(t)
    k = next(i for i, f in enumerate(bad["faces"]) if f[0] == "S")
    kind, d, corners = bad["faces"][k]
    bad["faces"][k] = (kind, (d + 2) % 12, corners)  # wrong orientation of one square
    with pytest.raises(TilingError):
        check_tiling(bad)


def test_tiler_small_lattice_by_hand():
    """The triangular lattice of side 2 (4 vertices) is the only tiling of 2 Z[omega]; squares alone tile (1, z^3) x 2."""
    raw, classes = enumerate_tilings(Lattice2in4((2, 0, 0, 0), (0, 0, 2, 0)))
    assert raw == 1 and len(classes) == 1
    raw, classes = enumerate_tilings(Lattice2in4((2, 0, 0, 0), (0, 0, 0, 2)))  # 2 x 2 square torus
    assert len(classes) == 1 and all(k == "S" for k, _, _ in next(iter(classes)))
    assert NAME_OF[frozenset()] == "empty"


# ------------------------------------------------------------------ the survey's time limit


def test_timeout_below_one_second_interrupts():
    """A limit of a fraction of a second is honoured (signal.alarm would round 0.2 down to 'no alarm')."""
    import time

    t0 = time.perf_counter()
    with pytest.raises(TimeoutError):
        call_with_timeout(0.2, time.sleep, 5)
    assert time.perf_counter() - t0 < 2


def test_timeout_restores_the_previous_handler_and_returns_the_value():
    import signal

    before = signal.getsignal(signal.SIGALRM)
    assert call_with_timeout(0.5, max, 3, 7) == 7
    assert call_with_timeout(None, max, 3, 7) == 7
    assert signal.getsignal(signal.SIGALRM) is before
    assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)


@pytest.mark.parametrize("seconds", [0, -1, float("nan"), float("inf")])
def test_timeout_out_of_range_is_refused_naming_the_argument(seconds):
    with pytest.raises(ArgumentError, match="max_seconds="):
        survey(2, 2, max_seconds=seconds)


def test_survey_timeout_marks_the_row():
    """A tiny limit abandons the tiler on a lattice (the row says so); without one the same row is matched."""
    rows = survey(3, 3, enumerate_limit_vertices=30, max_seconds=1e-6)["rows"]
    assert any(row.get("tiler") == "timeout" for row in rows)


def test_tiler_imports_only_square_triangle():
    """The enumerator is independent of the correspondence it checks (notes/architecture.md)."""
    import ast
    from pathlib import Path

    import forcenet.exact.chicken_wire.tiler as tiler

    tree = ast.parse(Path(tiler.__file__).read_text())
    relative = {node.module for node in ast.walk(tree) if isinstance(node, ast.ImportFrom) and node.level}
    absolute = {alias.name for node in ast.walk(tree) if isinstance(node, ast.Import) for alias in node.names}
    absolute |= {node.module for node in ast.walk(tree) if isinstance(node, ast.ImportFrom) and not node.level}
    assert relative == {"square_triangle"}
    assert not any(name.startswith("forcenet") for name in absolute)
