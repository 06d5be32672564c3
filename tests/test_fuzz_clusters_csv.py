"""Issue 56: users' force tables fuzzed -- ``forcenet clusters FILE.csv`` and ``forcenet.clusters(...)``.

Each hostile input is one line of a table with its verdict: a clear one-line error in the family (exit 2 at the
command line, naming the file and what is wrong) or it works (read exactly as the clean file is).  Every case
runs in this process within a bound of seconds; none may hang (a FIFO is never opened, a device never read), print
a traceback or end in an internal error.  Device nodes are made with ``os.mknod`` in a temporary folder (never
``/dev``).  Before: a FIFO or ``/dev/zero`` named as a table waited for ever in Python, a file of 3 columns on 4
lines was read as 3 rows of 4, a byte-order mark or a header in another order was "not a CSV of numbers",
bytes that are not UTF-8 were an internal error, and grain numbers beyond 2**53 merged silently.
"""

from __future__ import annotations

import errno
import os
import stat
import time

import numpy as np
import pytest

import forcenet
import forcenet.force_chains as front
from forcenet.cli import main
from forcenet.core.errors import ArgumentError, ArgumentTypeError, ForcenetError
from forcenet.force_chains import MAX_CSV_BYTES, read_networks
from forcenet.numeric.force_chains.newman_ziff import periodic_lattice

SIZES = ((6, 60), (8, 40), (12, 20))  # (L, samples): small square lattices, independent uniform forces
BOUND = 10.0  # seconds for any refusal


def _rows(L: int, K: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    lattice = periodic_lattice("square", L)
    return np.concatenate([np.column_stack([np.full(lattice.bonds, k), lattice.head, lattice.tail,
                                            rng.random(lattice.bonds)]) for k in range(K)])


def _csv(rows: np.ndarray, header: str = "sample,i,j,f", end: str = "\n") -> str:
    lines = [header] if header else []
    lines += [f"{int(s)},{int(i)},{int(j)},{float(f)!r}" for s, i, j, f in rows]
    return end.join(lines) + end


@pytest.fixture(scope="module")
def clean(tmp_path_factory):
    """Three clean files, one per size, and the first size's rows."""
    folder = tmp_path_factory.mktemp("clean")
    paths = []
    for k, (L, K) in enumerate(SIZES):
        path = folder / f"L{L}.csv"
        path.write_text(_csv(_rows(L, K, k)))
        paths.append(str(path))
    return paths, _rows(*SIZES[0], 0)


def _cli(argv, capsys):
    start = time.monotonic()
    code = main(argv)
    elapsed = time.monotonic() - start
    out, err = capsys.readouterr()
    assert elapsed < BOUND, f"{argv}: {elapsed:.1f} s"
    assert "Traceback" not in err and "internal error" not in err, err
    return code, out, err


# ------------------------------------------------------------- hostile contents: each refused in one line, named

def _text(content):
    def make(path, rows):
        path.write_bytes(content(rows) if callable(content) else content)
    return make


def _lines(rows, n=6):
    return _csv(rows[:n]).encode()


CONTENTS = {
    "empty file": (_text(b""), "no bonds"),
    "header only": (_text(b"sample,i,j,f\n"), "no bonds"),
    "blank lines only": (_text(b"\n\n  \n\r\n"), "no bonds"),
    "three columns": (_text(b"0,1,0.5\n0,2,0.7\n1,1,0.2\n1,3,0.9\n"), "has 3 columns: expected 4"),
    "five columns": (_text(b"sample,i,j,f\n0,1,2,0.5,9\n"), "has 5 columns: expected 4"),
    "one short line amid good ones": (_text(lambda r: _lines(r) + b"3,4,0.5\n" + _lines(r)[13:]), "has 3 columns"),
    "a header of other names": (_text(b"sample,i,j,force\n0,1,2,0.5\n"), "must name the columns sample,i,j,f"),
    "a header missing a column": (_text(b"sample,i,f\n0,1,0.5\n"), "must name the columns"),
    "a word for a force": (_text(b"sample,i,j,f\n0,1,2,abc\n"), "'abc' is not a number"),
    "two numbers in one field": (_text(b"sample,i,j,f\n0,1 2,3,0.5\n"), "'1 2' is not a number"),
    "an empty field": (_text(b"sample,i,j,f\n0,,3,0.5\n"), "is not a number"),
    "a NUL byte": (_text(b"sample,i,j,f\n0,1,2,0.5\x00\n"), "is not a number"),
    "NaN force": (_text(b"sample,i,j,f\n0,1,2,0.5\n0,2,3,nan\n"), "bond 2 has f=nan"),
    "+inf force": (_text(b"sample,i,j,f\n0,1,2,inf\n"), "f=inf"),
    "-inf force": (_text(b"sample,i,j,f\n0,1,2,-inf\n"), "f=-inf"),
    "NaN grain": (_text(b"sample,i,j,f\n0,nan,2,0.5\n"), "i=nan"),
    "a fractional grain": (_text(b"sample,i,j,f\n0,1.5,2,0.5\n"), "must be integers"),
    "a huge grain number": (_text(b"sample,i,j,f\n0,1e300,2,0.5\n"), "below 2**53"),
    "a grain number past float64's integers": (_text(b"sample,i,j,f\n0,9007199254740993,2,0.5\n"), "below 2**53"),
    "a huge sample number": (_text(b"sample,i,j,f\n1e20,1,2,0.5\n"), "below 2**53"),
    "a self-loop": (_text(b"sample,i,j,f\n0,1,2,0.5\n0,4,4,0.5\n"), "joins grain 4 to itself"),
    "not UTF-8": (_text(b"sample,i,j,f\n0,1,2,0.5\xff\xfe\n"), "not UTF-8 text"),
    "UTF-16 with its mark": (_text("sample,i,j,f\n0,1,2,0.5\n".encode("utf-16")), "not UTF-8 text"),
    "one sample only": (_text(lambda r: _csv(r[r[:, 0] == 0]).encode()), "at least 2 samples"),
}


@pytest.mark.parametrize("case", list(CONTENTS))
def test_hostile_contents_are_refused_in_one_line(case, clean, tmp_path, capsys):
    make, piece = CONTENTS[case]
    paths, rows = clean
    bad = tmp_path / "bad.csv"
    make(bad, rows)
    code, out, err = _cli(["clusters", str(bad), *paths[1:], "--replicas", "0", "--thresholds", "50"], capsys)
    assert code == 2 and out == "" and len(err.splitlines()) == 1, err
    assert piece in err and (str(bad) in err or "bad.csv" in err or "sources[0]" in err), err
    with pytest.raises(ForcenetError, match=None) as raised:  # the same in Python
        forcenet.clusters([str(bad), *paths[1:]], replicas=0, thresholds=50)
    assert piece in str(raised.value)


# ------------------------------------------------------------------ hostile files: never opened, never waited on

def _directory(path):
    os.mkdir(path)


def _fifo(path):
    os.mkfifo(path)  # opening it to read would wait for a writer for ever


def _device(minor):
    def make(path):
        try:
            os.mknod(path, stat.S_IFCHR | 0o666, os.makedev(1, minor))  # /dev/zero (5) never ends, /dev/null (3)
        except (PermissionError, AttributeError):
            pytest.skip("creating a device node needs CAP_MKNOD")
    return make


def _sparse(path):
    with open(path, "wb") as handle:  # declared larger than any table read here; no byte of it is read
        handle.truncate(MAX_CSV_BYTES + 1)


def _loop(path):
    os.symlink(path, path)


FILES = {
    "a directory": (_directory, "a directory, not a CSV file"),
    "a FIFO": (_fifo, "a FIFO, not a CSV file"),
    "a character device (zeros)": (_device(5), "a character device"),
    "a character device (empty)": (_device(3), "a character device"),
    "a gigantic sparse file": (_sparse, f"more than the {MAX_CSV_BYTES} bytes"),
    "a symbolic-link loop": (_loop, "cannot read it"),
}


@pytest.mark.parametrize("case", list(FILES))
def test_hostile_files_are_refused_before_reading(case, clean, tmp_path, capsys):
    make, piece = FILES[case]
    paths, _ = clean
    bad = tmp_path / "bad.csv"
    make(str(bad))
    for order in ([str(bad), *paths[1:]], [*paths[:2], str(bad)]):  # refused before any file is read
        code, out, err = _cli(["clusters", *order, "--replicas", "0"], capsys)
        assert code == 2 and out == "" and len(err.splitlines()) == 1 and piece in err and str(bad) in err, err
        start = time.monotonic()
        with pytest.raises(ArgumentError, match="bad.csv"):
            forcenet.clusters(order, replicas=0)
        assert time.monotonic() - start < BOUND


def test_an_unreadable_file_is_refused_in_one_line(clean, tmp_path, capsys, monkeypatch):
    """As root no permission bit stops a read: the refusal of ``open`` is made by hand (EACCES)."""
    paths, rows = clean
    bad = tmp_path / "bad.csv"
    bad.write_text(_csv(rows))
    real_open = os.open

    def refusing(path, *args, **kwargs):
        if os.fspath(path) == str(bad):
            raise PermissionError(errno.EACCES, "Permission denied", str(path))
        return real_open(path, *args, **kwargs)

    monkeypatch.setattr(os, "open", refusing)
    code, out, err = _cli(["clusters", str(bad), *paths[1:], "--replicas", "0"], capsys)
    assert code == 2 and len(err.splitlines()) == 1 and "cannot read it (Permission denied)" in err, err


def test_a_missing_file_and_too_few_sizes(clean, tmp_path, capsys):
    paths, _ = clean
    code, _, err = _cli(["clusters", *paths[:2], str(tmp_path / "none.csv")], capsys)
    assert code == 2 and "no such file" in err
    code, _, err = _cli(["clusters", *paths[:2]], capsys)
    assert code == 2 and "at least 3 system sizes" in err


# ---------------------------------------------------------------- Python's other sources: arrays, frames, labels

PYTHON = [
    (lambda p: [p[0].encode(), *p[1:]], ArgumentTypeError, "is bytes"),
    (lambda p: [[["a", "b", "c", "d"]], *p[1:]], ArgumentTypeError, "not a table of numbers"),
    (lambda p: [[[0, 1, 2], [0, 1, 2, 0.5]], *p[1:]], ArgumentTypeError, "not a table of numbers"),
    (lambda p: [np.zeros((4, 3)), *p[1:]], ArgumentError, "shape (bonds, 4)"),
    (lambda p: [np.zeros((0, 4)), *p[1:]], ArgumentError, "no bonds"),
    (lambda p: [np.array([[0, 1, 2, np.nan]]), *p[1:]], ArgumentError, "f=nan"),
    (lambda p: [{"sample": 1}, *p[1:]], ArgumentTypeError, "not a table of numbers"),
    (lambda p: p[0], ArgumentTypeError, "expected a list"),
]


@pytest.mark.parametrize("k", range(len(PYTHON)))
def test_python_sources_in_the_family(k, clean):
    build, kind, piece = PYTHON[k]
    paths, _ = clean
    with pytest.raises(kind) as raised:
        forcenet.clusters(build(paths), replicas=0)
    assert piece in str(raised.value)


def test_a_data_frame_without_the_columns_and_labels_in_the_family(clean):
    pandas = pytest.importorskip("pandas")
    paths, rows = clean
    frame = pandas.DataFrame(rows, columns=["sample", "i", "j", "force"])
    with pytest.raises(ArgumentError, match="columns sample, i, j, f"):
        forcenet.clusters([frame, *paths[1:]], replicas=0)
    with pytest.raises(ArgumentError, match="one number per source"):
        forcenet.clusters(paths, replicas=0, labels=[6, 8])
    with pytest.raises(ArgumentTypeError, match="labels='big' is not a number"):
        forcenet.clusters(paths, replicas=0, labels=[6, 8, "big"])


# ------------------------------------------- what works: read exactly as the clean file is (property of the reader)

def _same_networks(a, b) -> bool:
    return all(np.array_equal(x, y) for x, y in zip(read_networks(a), read_networks(b), strict=True))


def _variant(rows, kind):
    if kind == "BOM":
        return b"\xef\xbb\xbf" + _csv(rows).encode()
    if kind == "CRLF":
        return _csv(rows, end="\r\n").encode()
    if kind == "no header":
        return _csv(rows, header="").encode()
    if kind == "columns reordered":
        return ("f,j,sample,i\n" + "".join(f"{float(f)!r},{int(j)},{int(s)},{int(i)}\n" for s, i, j, f in rows)).encode()
    if kind == "blank lines and spaces":
        return _csv(rows).replace(",", " , ").replace("\n", "\n\n").encode()
    if kind == "BOM, CRLF, capital header":
        return b"\xef\xbb\xbf" + _csv(rows, header="Sample, I, J, F", end="\r\n").encode()
    raise KeyError(kind)


@pytest.mark.parametrize("kind", ["BOM", "CRLF", "no header", "columns reordered", "blank lines and spaces",
                                  "BOM, CRLF, capital header"])
def test_harmless_variants_read_as_the_clean_file(kind, clean, tmp_path):
    paths, rows = clean
    variant = tmp_path / "variant.csv"
    variant.write_bytes(_variant(rows, kind))
    assert _same_networks(str(variant), paths[0])


def test_relabelled_grains_and_samples_read_alike(clean, tmp_path):
    """Grain and sample numbers are labels: shifted far (below 2**53), negative or sparse, the networks are the same."""
    _, rows = clean
    moved = rows.copy()
    moved[:, 0] = moved[:, 0] * 1000 - 7
    moved[:, 1:3] = moved[:, 1:3] + 2**52
    assert _same_networks(moved, rows)
    flipped = rows.copy()
    flipped[:, 1:3] = -flipped[:, 1:3] - 1  # negative labels in reversed order: the same graph, relabelled
    a, b = read_networks(flipped), read_networks(rows)
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1]) and np.array_equal(a[4], b[4])


@pytest.mark.slow
def test_negative_forces_duplicate_bonds_and_mixed_counts_work(clean, tmp_path):
    """Shifting every force shifts every threshold (quantiles) and f_c by the same amount; a bond given twice is
    two parallel contacts; samples of different sizes in one file are allowed (``M`` is their mean)."""
    paths, rows = clean
    shifted = [np.loadtxt(p, delimiter=",", skiprows=1) for p in paths]
    for table in shifted:
        table[:, 3] -= 10.0
    base = forcenet.clusters(paths, replicas=0, thresholds=50)
    moved = forcenet.clusters(shifted, replicas=0, thresholds=50)
    assert moved.fit.value["f_c"] == pytest.approx(base.fit.value["f_c"] - 10.0, abs=1e-5)  # the fit's tolerance
    assert moved.fit.value["nu"] == pytest.approx(base.fit.value["nu"], rel=1e-4)
    doubled = np.concatenate([rows, rows[:3]])  # three bonds of sample 0 given twice
    starts, sites, head, tail, force = read_networks(doubled)
    assert force.size == rows.shape[0] + 3 and starts[1] - starts[0] == (rows[:, 0] == 0).sum() + 3
    mixed = rows[~((rows[:, 0] == 1) & (np.arange(rows.shape[0]) % 2 == 0))]  # sample 1 loses half its bonds
    assert read_networks(mixed)[4].size == mixed.shape[0]


def test_the_command_line_reads_a_hostile_but_valid_file(clean, tmp_path, capsys):
    """End to end: a BOM, CRLF and a capitalized header give the clean files' result."""
    paths, rows = clean
    variant = tmp_path / "variant.csv"
    variant.write_bytes(_variant(rows, "BOM, CRLF, capital header"))
    code, clean_out, err = _cli(["clusters", *paths, "--replicas", "0", "--thresholds", "50", "--format", "json"],
                                capsys)
    assert code == 0, err
    code, out, err = _cli(["clusters", str(variant), *paths[1:], "--replicas", "0", "--thresholds", "50",
                           "--format", "json"], capsys)
    assert code == 0, err

    def fit(text):
        return text[text.index('"f_c"'):text.index('"seconds"')] if '"seconds"' in text else text

    assert fit(out).replace(str(variant), paths[0]) == fit(clean_out).replace(str(variant), paths[0])


def test_a_table_read_in_pieces_is_the_whole_and_names_the_right_line(clean, tmp_path, monkeypatch):
    """A large table is parsed in pieces (bounded memory): the same rows, and a bad line's number counted over
    the whole file."""
    paths, rows = clean
    whole = read_networks(paths[0])
    monkeypatch.setattr(front, "_PIECE", 100)  # ~3 lines a piece
    assert all(np.array_equal(a, b) for a, b in zip(read_networks(paths[0]), whole, strict=True))
    text = _csv(rows[:50], end="\r\n").splitlines()
    text[37] = "1,2,x,0.5"  # data line 37 (line 38 of the file, after the header)
    bad = tmp_path / "bad.csv"
    bad.write_text("\n\n" + "\n".join(text) + "\n")
    with pytest.raises(ArgumentError, match="data line 37: 'x' is not a number"):
        read_networks(str(bad))
    text[37] = "1,2,3"
    bad.write_text("\n".join(text) + "\n")
    with pytest.raises(ArgumentError, match="data line 37 .* has 3 columns"):
        read_networks(str(bad))
