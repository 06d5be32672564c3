"""The derived numbers of the frontier (notes/data/lattice_columns.json, issue 26) against a fresh exact run.

The exact lattice-direction columns are megabytes and stay out of the repository; the digest keeps
25 correctly rounded digits of each and the SHA-256 of the exact file.  Here the smallest column is
rebuilt by the command the digest names (the Pfaffian route, through ``benchmarks/scaling_refit.py``):
same bytes, same digits.  The larger ones are checked for their shape only (their rebuild takes minutes
to hours; the hash is what a rebuild is compared with).
"""

import hashlib
import importlib.util
import json
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DIGEST = ROOT / "notes" / "data" / "lattice_columns.json"


@pytest.fixture(scope="module")
def refit():
    spec = importlib.util.spec_from_file_location("forcenet_scaling_refit", ROOT / "benchmarks" / "scaling_refit.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def digest():
    return json.loads(DIGEST.read_text())


def test_the_smallest_column_rebuilds_to_the_same_bytes_and_digits(refit, digest, tmp_path, capsys):
    N = min(int(k) for k in digest["columns"])
    assert N <= 40  # seconds, not minutes
    refit.write_lattice(N, str(tmp_path))
    raw = (tmp_path / f"lattice_N{N}.json").read_bytes()
    entry = digest["columns"][str(N)]
    assert hashlib.sha256(raw).hexdigest() == entry["sha256"]
    from fractions import Fraction

    exact = [Fraction(x) for x in json.loads(raw)["W_i1"]]
    assert entry["W_i1"] == [refit.decimal_text(x) for x in exact]
    # the decimal is the correctly rounded value: within half a unit of its last digit
    for x, text in zip(exact, entry["W_i1"]):
        from decimal import Decimal

        unit = Decimal(1).scaleb(Decimal(text).adjusted() - refit.DIGEST_DIGITS + 1)
        assert abs(Fraction(Decimal(text)) - x) <= Fraction(unit) / 2


def test_every_recorded_column_has_the_shape_of_a_lattice_direction(digest):
    assert digest["format"] == 1 and digest["columns"]
    for key, entry in digest["columns"].items():
        N = int(key)
        values = [float(x) for x in entry["W_i1"]]
        assert len(values) == N and len(entry["sha256"]) == 64
        assert values[0] == 1.0  # W_11 carries the whole overload
        assert all(0 < v < 1 for v in values[1:])


def test_the_smallest_table_rebuilds_by_the_digests_command_to_the_same_bytes_and_digits(refit, digest, cli, tmp_path):
    """The command the digest names for its tables (``forcenet table --method pfaffian``) gives the recorded bytes."""
    N = min(int(k) for k in digest["tables"])
    assert N <= 40 and digest["tables_rebuild"].startswith("forcenet table --method pfaffian --N N --out ")
    out = tmp_path / f"mean_W_N{N}.json"
    code, _, err = cli(["table", "--method", "pfaffian", "--N", str(N), "--out", str(out), "--quiet"])
    assert code == 0, err
    entry = digest["tables"][str(N)]
    assert hashlib.sha256(out.read_bytes()).hexdigest() == entry["sha256"]
    from fractions import Fraction

    table = [[Fraction(x) for x in row] for row in json.loads(out.read_text())["mean_W"]]
    assert entry["W_i1"] == [refit.decimal_text(row[0]) for row in table]
    assert entry["rows"] == {str(i): [refit.decimal_text(x) for x in table[i - 1]] for i in refit.bulk_row_indices(N)}


def test_every_recorded_table_has_the_shape_of_the_triangle_and_meets_the_lattice_columns(refit, digest):
    assert digest["tables"]
    for key, entry in digest["tables"].items():
        N = int(key)
        assert N % 4 == 0 and len(entry["sha256"]) == 64 and len(entry["W_i1"]) == N
        assert sorted(map(int, entry["rows"])) == refit.bulk_row_indices(N)
        for i, row in entry["rows"].items():
            values = [float(x) for x in row]
            assert len(values) == int(i) and all(0 < v < 1 for v in values)
            assert row == row[::-1]  # the mirror symmetry of the triangle, digit for digit
            assert row[0] == entry["W_i1"][int(i) - 1]
        if key in digest["columns"]:  # two exact routes: the full table's first column is the lattice column
            assert entry["W_i1"] == digest["columns"][key]["W_i1"]


def test_recording_refuses_a_column_that_disagrees_with_its_record(refit, tmp_path, capsys):
    out, digest_path = tmp_path / "out", tmp_path / "digest.json"
    out.mkdir()
    refit.write_lattice(8, str(out))
    assert refit.record_digest(str(digest_path), str(out)) == [8]
    assert refit.record_digest(str(digest_path), str(out)) == []  # the same bytes again: nothing new
    data = json.loads((out / "lattice_N8.json").read_text())
    data["W_i1"][3] = "1/3"
    (out / "lattice_N8.json").write_text(json.dumps(data) + "\n")
    with pytest.raises(SystemExit, match="two exact runs disagree"):
        refit.record_digest(str(digest_path), str(out))


def test_the_drift_of_a_pure_two_thirds_series_is_none(refit):
    """A three-term series led by N^(-2/3) (the fourth amplitude zero): the series is recovered and the free g is 2/3."""
    import numpy as np

    Ns = [32, 48, 64, 80, 96, 112, 128]
    truth = [0.3 * N ** (-2 / 3) - 0.1 / N + 1.7 * N ** (-4 / 3) for N in Ns]
    amps, rms, drift = refit.drift_under_series(Ns, truth, [96, 128, 500])
    assert np.allclose(amps, [0.3, -0.1, 1.7, 0.0], atol=1e-8) and rms < 1e-10
    assert all(abs(g - 2 / 3) <= 0.0005 for g in drift.values())  # the grid's step is 0.001


def test_a_fourth_term_makes_the_free_exponent_drift_down_to_two_thirds(refit):
    """With a positive N^(-5/3) term the free fit starts above 2/3 and falls toward it as N_max grows."""
    Ns = list(range(32, 137, 8))
    truth = [0.3 * N ** (-2 / 3) + 0.35 / N - 0.15 * N ** (-4 / 3) + 2.5 * N ** (-5 / 3) for N in Ns]
    _, _, drift = refit.drift_under_series(Ns, truth, [96, 136, 1000, 2000])
    g = [drift[N] for N in (96, 136, 1000, 2000)]
    assert g[0] > g[1] > g[2] > g[3] > 2 / 3


def test_predictions_ahead_recover_a_series_and_separate_it_from_three_terms(refit):
    """On exact four-term series data the series' prediction at the next N is exact; the three-term fit misses."""
    Ns = list(range(32, 153, 8))
    series = lambda N: 0.28 * N ** (-2 / 3) + 0.35 / N - 0.12 * N ** (-4 / 3) + 2.46 * N ** (-5 / 3)  # noqa: E731
    ahead = refit.predict_ahead(Ns, [series(N) for N in Ns], 160)
    assert abs(ahead["series"] - series(160)) < 1e-12
    assert abs(ahead["three_term"] - series(160)) > 1e-4 * series(160)
    assert abs(ahead["free"] - series(160)) < abs(ahead["three_term"] - series(160))
    assert ahead["g_series"] <= ahead["g_stays"] + 0.0005  # the series' exponent only falls


def test_a_full_table_is_recorded_by_its_bulk_rows_and_must_meet_the_lattice_route(refit, tmp_path):
    """The digest of a full table keeps the rows z N and its first column; the first column must equal the
    lattice route's column of the same N digit for digit (two exact routes), and a changed table is refused."""
    from forcenet.exact.triangle.free_fermion.route import mean_W

    out, digest_path = tmp_path / "out", tmp_path / "digest.json"
    out.mkdir()
    refit.write_lattice(12, str(out))
    refit.load_table(12, str(out))  # N <= 40: computed on the fly and written as mean_W_N12.json
    assert refit.record_digest(str(digest_path), str(out)) == [12]
    entry = json.loads(digest_path.read_text())["tables"]["12"]
    table = mean_W(12)
    assert sorted(int(i) for i in entry["rows"]) == refit.bulk_row_indices(12) == [3, 6, 9]
    for i, row in entry["rows"].items():
        assert row == [refit.decimal_text(x) for x in table[int(i) - 1]]
    assert entry["W_i1"] == [refit.decimal_text(row[0]) for row in table]
    assert hashlib.sha256((out / "mean_W_N12.json").read_bytes()).hexdigest() == entry["sha256"]
    # the refit reads the recorded rows when the exact table is gone
    (out / "mean_W_N12.json").unlink()
    digest = refit.read_digest(str(digest_path))
    rows = refit.load_rows(12, str(out / "none"), digest)
    assert rows[6] == [float(refit.decimal_text(x)) for x in table[5]]
    # a table whose first column disagrees with the recorded lattice column is refused
    data = {"N": 12, "count": "1", "normalization": "1", "mean_W": [[str(x) for x in row] for row in table]}
    data["mean_W"][4][0] = "1/7"
    (out / "mean_W_N12.json").write_text(json.dumps(data) + "\n")
    with pytest.raises(SystemExit, match="two exact routes disagree"):
        refit.record_digest(str(digest_path), str(out))
    # and in the other order: the table recorded first, then a lattice column that disagrees with it
    other, second = tmp_path / "other", tmp_path / "second.json"
    other.mkdir()
    refit.load_table(12, str(other))
    assert refit.record_digest(str(second), str(other)) == [12]
    column = {"N": 12, "W_i1": [str(row[0]) for row in table]}
    column["W_i1"][4] = "1/7"
    (other / "lattice_N12.json").write_text(json.dumps(column) + "\n")
    with pytest.raises(SystemExit, match="two exact routes disagree"):
        refit.record_digest(str(second), str(other))


def test_bulk_predictions_recover_an_analytic_correction(refit):
    """On exact a/N + b/N^2 data the analytic fits predict the next N exactly; the edge-like series does not."""
    Ns = list(range(32, 81, 4))
    law = lambda N: 1.809 / N - 2.02 / N**2  # noqa: E731
    ahead = refit.predict_bulk(Ns, [law(N) for N in Ns], 128)
    assert abs(ahead["analytic, two terms"][0] - law(128)) < 1e-13
    assert abs(ahead["analytic, three terms"][0] - law(128)) < 1e-11
    assert ahead["analytic, two terms"][1] < 1e-12
    assert ahead["edge-like"][1] > 1e-5 and abs(ahead["edge-like"][0] - law(128)) > 1e-3 * law(128)
