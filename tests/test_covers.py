"""A cell is uniform between its covers: <W^2> of layer N - 1 (and row 3) for the price of the mean (issue 43).

notes/fluctuations.md Sec. 3.1.  Checked against independent routes:

* the general identity E[(U - L)^2] = 3 E[L^2] + 3 E[U^2] - 6 E[x^2] on every cell, L the max of its lower
  covers and U the min of its upper ones, from every linear extension's ranks (networkx), N = 4, 5, 6;
* the covers against the Hasse diagram of the reference poset (networkx's transitive reduction);
* the rows' <W> and <W^2> against the order-ideal DP (N <= 10, hypothesis over N and j) and against one
  layer's de Bruijn Pfaffians beyond it (N = 14, 16, slow);
* the row routes (forcenet.exact.routes.choose_row / row_run) and ``forcenet table --row``.
"""

import json
from fractions import Fraction

import networkx as nx
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from forcenet.core.errors import ArgumentError
from forcenet.exact.reference.linear_extensions import partial_sum_poset
from forcenet.exact.routes import choose_row, row_plan, row_run, table_run
from forcenet.exact.triangle.de_bruijn.layers import layer_gap_laws
from forcenet.exact.triangle.distribution import moment_from_gaps
from forcenet.exact.triangle.free_fermion import covers as cv
from forcenet.exact.triangle.moments import mean_W_grain, moment


def _rank_moments(N):
    """``E[S_a S_b]`` for every pair of free partial sums and the constants 0 (rank 0) and 1 (rank d + 1), from
    every linear extension: given the ranks ``r <= r'``, ``E[S S'] = r (r' + 1)/((d + 1)(d + 2))`` (order
    statistics of ``d`` uniforms)."""
    d = N * (N - 1) // 2
    extensions = list(nx.all_topological_sorts(partial_sum_poset(N)))

    def expect(f):
        return Fraction(sum(f({cell: r for r, cell in enumerate(ext, start=1)}) for ext in extensions),
                        len(extensions) * (d + 1) * (d + 2))

    def product(rank, a, b):
        ra, rb = sorted((rank.get(a, 0) if a != "one" else d + 1, rank.get(b, 0) if b != "one" else d + 1))
        return ra * (rb + 1)

    return expect, product, d


@pytest.mark.parametrize("N", [4, 5, 6])
def test_every_cell_is_uniform_between_its_covers(N):
    """E[(U - L)^2] = 3 E[L^2] + 3 E[U^2] - 6 E[x^2] for every cell, with L = max and U = min of its covers."""
    expect, product, d = _rank_moments(N)

    def extreme(rank, cells, pick, default):  # the cover of highest (lowest) rank, or the constant
        return pick(cells, key=lambda c: rank[c]) if cells else default

    checked = 0
    for i in range(2, N + 1):
        for j in range(1, i):
            lower, upper = cv.covers(N, (i, j))

            def moments_of(rank, lower=lower, upper=upper, x=(i, j)):
                L, U = extreme(rank, lower, max, "zero"), extreme(rank, upper, min, "one")
                return product(rank, L, L), product(rank, U, U), product(rank, x, x), product(rank, L, U)

            LL = expect(lambda r: moments_of(r)[0])
            UU = expect(lambda r: moments_of(r)[1])
            xx = expect(lambda r: moments_of(r)[2])
            LU = expect(lambda r: moments_of(r)[3])
            assert LL + UU - 2 * LU == 3 * LL + 3 * UU - 6 * xx
            checked += 1
    assert checked == d


@pytest.mark.parametrize("N", [2, 3, 5, 8])
def test_covers_are_the_hasse_diagram(N):
    hasse = nx.transitive_reduction(partial_sum_poset(N))
    for cell in hasse.nodes:
        lower, upper = cv.covers(N, cell)
        assert sorted(hasse.predecessors(cell)) == sorted(lower)
        assert sorted(hasse.successors(cell)) == sorted(upper)


@pytest.mark.parametrize("N", range(3, 13))
def test_the_spans_are_layer_N_minus_1_and_one_load_of_row_3(N):
    spans = cv.cover_spans(N)
    expected = {(N - 1, j): ((N, j),) for j in range(1, N)}
    expected[(3, 2)] = ((2, 1),) + expected.get((3, 2), ())  # N = 3: a floor load; N = 4: two cells span it
    assert spans == expected
    assert cv.one_time_rows(N) == sorted({1, 2, 3, N - 1})


@settings(max_examples=12, deadline=None)
@given(data=st.data())
def test_layer_N_minus_1_equals_the_dp(data):
    """<W_(N-1,j)> and <W_(N-1,j)^2> by the identity = the order-ideal DP's marked-chain moments, N <= 10."""
    N = data.draw(st.integers(3, 10), label="N")
    j = data.draw(st.integers(1, N - 1), label="j")
    rows = cv.cover_row_moments(N, N - 1, workers=1)
    assert len(rows[1]) == len(rows[2]) == N - 1
    assert rows[2][j - 1] == moment(N, (N - 1, j), 2)
    assert rows[1][j - 1] == mean_W_grain(N, N - 1, j)


@settings(max_examples=8, deadline=None)
@given(N=st.integers(4, 10), row=st.sampled_from([1, 2, 3]))
def test_rows_2_and_3_equal_the_dp(N, row):
    rows = cv.cover_row_moments(N, row, workers=1)
    assert rows[2] == [moment(N, (row, j), 2) for j in range(1, row + 1)]
    assert rows[1] == [mean_W_grain(N, row, j) for j in range(1, row + 1)]


def test_two_cells_spanning_one_load_agree():
    """At N = 4 both S_(2,1) and the floor's S_(4,2) lie between S_(3,1) and S_(3,2): (C) twice, one value."""
    from forcenet.exact.triangle.free_fermion.partial_sums import partial_sum_moments

    second = partial_sum_moments(4)[2]
    assert cv.cover_spans(4)[(3, 2)] == ((2, 1), (4, 2))
    assert second[1][0] == second[3][1]  # so 6 <x^2> is the same for both cells


def test_layer_N_minus_1_sums_to_the_closed_form():
    """notes/force_distribution.md Sec. 6.2: sum_j <W_(N-1,j)^2> = 3/(2N - 1), an identity proved separately."""
    for N in (5, 9, 17):
        assert sum(cv.cover_row_moments(N, N - 1)[2]) == Fraction(3, 2 * N - 1)


@pytest.mark.slow
@pytest.mark.parametrize("N", [14, 16])
def test_layer_N_minus_1_equals_de_bruijn_beyond_the_dp(N):
    rows = cv.cover_row_moments(N, N - 1)
    laws = layer_gap_laws(N, N - 1)
    assert rows[2] == [moment_from_gaps(laws[j], 2) for j in range(1, N)]
    assert rows[1] == [moment_from_gaps(laws[j], 1) for j in range(1, N)]


def test_other_rows_are_refused_and_planned():
    with pytest.raises(ArgumentError, match=r"row=5 is out of range for the cover identity.*1, 2, 3, 9"):
        cv.cover_row_moments(10, 5)
    assert cv.cover_row_plan(10, 5).refusal.startswith("row=5 is out of range")
    assert cv.cover_row_plan(201, 200).refusal.startswith("N=201 is out of range")
    plan = cv.cover_row_plan(64, 63)
    assert plan.runnable and plan.unit == "prime" and "covers" in plan.what


# ------------------------------------------------ the row routes (the front door and the command line)


def test_the_row_routes_choose_by_the_plans():
    assert choose_row("pfaffian", 40, 39, 2).route == "covers"  # the identity, the price of the mean
    assert choose_row("pfaffian", 40, 20, 2).route == "layers"  # two-time: one layer's de Bruijn Pfaffians
    assert choose_row("pfaffian", 40, 40, 2).route == "floor"
    assert choose_row("pfaffian", 40, 39, 3).route == "layers"  # the identity gives second moments only
    assert choose_row("pfaffian", 40, 2, 4).route == "lattice"  # row 2: both loads are lattice directions
    assert choose_row("pfaffian", 40, 1, 2).route == "apex"
    assert choose_row("auto", 8, 5, 2).route == "fast"  # the DP's table beats one layer's grid at small N
    assert choose_row("fast", 8, 7, 2).route == "fast"
    refused = choose_row("pfaffian", 130, 100, 2).plan
    assert not refused.runnable and "N=130 is out of range" in refused.refusal
    assert "covers, the fastest by the plans" in row_plan("pfaffian", 40, 39).what
    with pytest.raises(ArgumentError, match="row=41"):
        choose_row("pfaffian", 40, 41, 2)
    with pytest.raises(ArgumentError, match="method='x'"):
        choose_row("x", 40, 4, 2)


@pytest.mark.parametrize("route", ["covers", "layers", "pfaffian"])
def test_row_run_by_every_route_gives_the_tables_row(route):
    N, row = 7, 6
    tables = table_run("fast", N, 2)
    moments = 1 if route == "pfaffian" else 2
    out = row_run("pfaffian", N, row, moments, route=route)
    assert out == {s: tables[s][row - 1] for s in range(1, moments + 1)}


def test_row_run_lattice_and_apex():
    tables = table_run("fast", 6, 3)
    assert row_run("pfaffian", 6, 2, 3) == {s: tables[s][1] for s in (1, 2, 3)}
    assert row_run("pfaffian", 6, 1, 3) == {s: [Fraction(1)] for s in (1, 2, 3)}


def test_table_row_command(cli, tmp_path):
    code, out, _ = cli(["table", "--N", "9", "--method", "pfaffian", "--moments", "2", "--row", "8", "--format",
                        "json", "--quiet"])
    assert code == 0
    data = json.loads(out)
    assert data["N"] == 9 and data["row"] == 8 and len(data["mean_W2"]) == 8
    assert [Fraction(x) for x in data["mean_W2"]] == [moment(9, (8, j), 2) for j in range(1, 9)]
    code, again, _ = cli(["table", "--N", "9", "--method", "pfaffian", "--moments", "2", "--row", "8", "--format",
                          "json", "--quiet"])
    assert again == out  # byte-stable
    code, csv, _ = cli(["table", "--N", "9", "--moments", "2", "--row", "8", "--format", "csv", "--quiet"])
    assert code == 0 and csv.splitlines()[0] == "i,j,mean_W,mean_W2" and csv.splitlines()[1].startswith("8,1,")
    code, full, _ = cli(["table", "--N", "9", "--moments", "2", "--format", "csv", "--quiet"])
    assert [line for line in full.splitlines() if line.startswith("8,")] == csv.splitlines()[1:]
    code, _, err = cli(["table", "--N", "9", "--row", "8"])
    assert code == 2 and "--format" in err
    code, _, err = cli(["table", "--N", "9", "--row", "10", "--format", "json"])
    assert code == 2 and "argument --row: row=10 is out of range: row must be an integer in 1..9" in err
    code, again, _ = cli(["table", "--N", "9", "--method", "pfaffian", "--moments", "2", "--row", "8", "--format",
                          "json", "--quiet", "--checkpoint", str(tmp_path)])
    assert code == 0 and again == out and any(tmp_path.rglob("*"))  # the partial sums' primes recorded
    code, _, err = cli(["table", "--N", "9", "--method", "fast", "--moments", "2", "--row", "8", "--format",
                        "json", "--checkpoint", str(tmp_path)])
    assert code == 2 and "checkpoint" in err


def test_a_checkpoint_leaves_only_the_routes_over_primes(tmp_path):
    assert choose_row("pfaffian", 9, 2, 3).route == "lattice"
    assert choose_row("pfaffian", 9, 2, 3, checkpoint=str(tmp_path)).route == "layers"
