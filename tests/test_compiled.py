"""Where the compiled kernels cache their machine code (forcenet.core.compiled): never inside the package.

The defect: numba's ``cache=True`` wrote into ``__pycache__`` beside each kernel, i.e. into
site-packages for a regular install; after ``pip uninstall`` (or the one ``pip install -e .`` does
first) the leftover ``forcenet/`` folder of cache files shadowed the editable install
("No module named 'forcenet.exact...'").
"""

from __future__ import annotations

import importlib
import os
import pkgutil
import subprocess
import sys
import textwrap
from pathlib import Path

import numba
import pytest

import forcenet
import forcenet.exact
import forcenet.numeric
from forcenet.core.compiled import cache_directory, njit

PROBE = '''
from forcenet.core.compiled import njit


@njit
def twice(x):
    return 2 * x
'''


def _package_roots() -> list[Path]:
    return [Path(p).resolve() for package in (forcenet, forcenet.exact, forcenet.numeric) for p in package.__path__]


def _kernels():
    """Every numba dispatcher defined in a module of forcenet (the Pfaffian route's and the samplers' kernels)."""
    seen = {}
    for package in (forcenet.exact, forcenet.numeric):
        for info in pkgutil.walk_packages(package.__path__, package.__name__ + "."):
            if info.name.endswith("__main__"):
                continue
            module = importlib.import_module(info.name)
            for name, value in vars(module).items():
                if isinstance(value, numba.core.dispatcher.Dispatcher) and value.__module__ == module.__name__:
                    seen[f"{module.__name__}.{name}"] = value
    return seen


def test_no_kernel_caches_inside_the_package(monkeypatch):
    kernels = _kernels()
    assert len(kernels) >= 40  # the Pfaffian route's and the samplers' kernels
    roots = _package_roots()
    inside = []
    for name, kernel in kernels.items():
        path = kernel.stats.cache_path  # numba's public statistics (None: no cache)
        if path is None:  # not cached at all: only allowed for kernels declared cache=False
            inside.append((name, "no cache"))
            continue
        if any(Path(path).resolve().is_relative_to(root) for root in roots):
            inside.append((name, path))
    assert not inside, inside


def test_the_cache_follows_xdg_cache_home_and_numba_cache_dir_still_wins(tmp_path):
    (tmp_path / "probe_kernel.py").write_text(PROBE)
    xdg, numba_dir = tmp_path / "xdg", tmp_path / "numba-dir"
    code = textwrap.dedent("""
        import sys
        sys.path.insert(0, sys.argv[1])
        import probe_kernel
        assert probe_kernel.twice(21) == 42
        print(probe_kernel.twice.stats.cache_path)
    """)
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}

    def run(extra):
        out = subprocess.run([sys.executable, "-c", code, str(tmp_path)], env={**env, **extra}, capture_output=True,
                             text=True, check=True, timeout=120)
        return Path(out.stdout.strip())

    path = run({"XDG_CACHE_HOME": str(xdg)})
    assert path.is_relative_to(xdg / "forcenet" / "numba")
    assert any(f.suffix == ".nbi" for f in path.iterdir())  # the index was written there
    assert not (tmp_path / "__pycache__").exists() or not any(
        f.suffix in (".nbi", ".nbc") for f in (tmp_path / "__pycache__").iterdir())  # and nothing beside the module
    assert run({"XDG_CACHE_HOME": str(xdg), "NUMBA_CACHE_DIR": str(numba_dir)}).is_relative_to(numba_dir)


def test_a_second_process_loads_the_cached_code(tmp_path, monkeypatch):
    from forcenet.core.plan import kernels_cached

    (tmp_path / "probe_kernel.py").write_text(PROBE)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    monkeypatch.syspath_prepend(str(tmp_path))
    module = importlib.import_module("probe_kernel")
    try:
        assert not kernels_cached([module.twice])
        assert module.twice(4) == 8
        sys.modules.pop("probe_kernel")
        fresh = importlib.import_module("probe_kernel")  # a new dispatcher: only the cache on disk can say
        assert not fresh.twice.overloads and kernels_cached([fresh.twice])
        assert fresh.twice(5) == 10 and fresh.twice.stats.cache_hits  # loaded, not compiled
    finally:
        sys.modules.pop("probe_kernel", None)


def test_a_reinstalled_source_keeps_its_cache_and_an_edited_one_does_not(tmp_path, monkeypatch):
    """numba stamps its index with the source's content: the same bytes with a later modification time (a
    reinstall) are still cached, and numba loads them; changed bytes are not. A FIFO in the index's place is
    never opened (the check returns at once)."""
    from forcenet.core.plan import kernels_cached

    source = tmp_path / "probe_stamp.py"
    source.write_text(PROBE)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    monkeypatch.syspath_prepend(str(tmp_path))

    def fresh_dispatcher():
        sys.modules.pop("probe_stamp", None)
        importlib.invalidate_caches()
        return importlib.import_module("probe_stamp").twice

    try:
        assert fresh_dispatcher()(4) == 8  # compiled and cached
        later = source.stat().st_mtime + 3600
        os.utime(source, (later, later))  # pip install . again: the same bytes, a new time
        twice = fresh_dispatcher()
        assert kernels_cached([twice])
        assert twice(5) == 10 and twice.stats.cache_hits  # numba agrees: loaded, not compiled
        source.write_text(PROBE.replace("2 * x", "x + x"))  # an edited kernel
        assert not kernels_cached([fresh_dispatcher()])
        twice = fresh_dispatcher()
        index = next(Path(twice.stats.cache_path).glob("probe_stamp.twice-*.nbi"))
        index.unlink()
        os.mkfifo(index)
        assert not kernels_cached([twice])
    finally:
        sys.modules.pop("probe_stamp", None)


def test_an_unwritable_cache_home_falls_back_to_numbas_choice(tmp_path, monkeypatch):
    (tmp_path / "probe_kernel.py").write_text(PROBE)
    blocker = tmp_path / "not-a-folder"
    blocker.write_text("")
    monkeypatch.setenv("XDG_CACHE_HOME", str(blocker))  # cannot hold a folder
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    monkeypatch.syspath_prepend(str(tmp_path))
    try:
        module = importlib.import_module("probe_kernel")
        assert module.twice(3) == 6
        assert not Path(module.twice.stats.cache_path).is_relative_to(blocker)
    finally:
        sys.modules.pop("probe_kernel", None)


def test_njit_keeps_numbas_options_and_cache_false():
    @njit(cache=False, fastmath={"contract"})
    def fma(a, b, c):
        return a * b + c

    assert fma(2.0, 3.0, 1.0) == 7.0
    assert fma.stats.cache_path is None  # numba's NullCache: nothing cached
    assert fma.targetoptions.get("fastmath")
    assert cache_directory().endswith(os.path.join("forcenet", "numba"))


@pytest.mark.parametrize("options", [{}, {"nogil": True, "boundscheck": False}])
def test_njit_as_bare_and_configured_decorator(options, tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    source = tmp_path / "probe_options.py"
    decorator = "@njit" if not options else "@njit(" + ", ".join(f"{k}={v!r}" for k, v in options.items()) + ")"
    source.write_text(f"from forcenet.core.compiled import njit\n\n\n{decorator}\ndef add(x, y):\n    return x + y\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    try:
        module = importlib.import_module("probe_options")
        assert module.add(2, 3) == 5
        assert Path(module.add.stats.cache_path).is_relative_to(tmp_path / "forcenet" / "numba")
        for key, value in options.items():
            assert module.add.targetoptions[key] == value
    finally:
        sys.modules.pop("probe_options", None)


@pytest.mark.slow
def test_a_regular_install_then_an_editable_one_imports(tmp_path):
    """The reported sequence, end to end: ``pip install .``, a compiled run, ``pip install -e .``, import."""
    root = Path(__file__).resolve().parents[1]
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True, timeout=300)
    python = venv / "bin" / "python"
    env = {**{k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}, "XDG_CACHE_HOME": str(tmp_path / "xdg")}

    def run(*args):
        return subprocess.run([str(python), *args], env=env, capture_output=True, text=True, timeout=1200,
                              check=False, cwd=tmp_path)

    assert run("-m", "pip", "install", "-q", str(root)).returncode == 0
    from forcenet.exact.triangle.staircase import count_by_hooks

    expected = str(count_by_hooks(9))  # the hook-length formula: a second route to the Pfaffian count
    probe = "from forcenet.exact.triangle.free_fermion.route import count; print(count(9))"
    first = run("-c", probe)
    assert first.returncode == 0 and first.stdout.strip() == expected, first.stderr
    site = Path(run("-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])").stdout.strip())
    assert not [f for f in (site / "forcenet").rglob("*") if f.suffix in (".nbi", ".nbc")]
    assert run("-m", "pip", "install", "-q", "-e", str(root)).returncode == 0
    assert not (site / "forcenet").exists()  # nothing left behind to shadow the editable install
    second = run("-c", probe)
    assert second.returncode == 0 and second.stdout.strip() == expected, second.stderr


def _has_avx512() -> bool:
    from llvmlite import binding

    return "+avx512f" in binding.get_host_cpu_features().flatten().split(",")


def test_the_users_choice_and_an_imported_numba_keep_the_vector_width():
    from forcenet.core.compiled import prefer_wide_vectors

    assert prefer_wide_vectors({"NUMBA_CPU_NAME": "generic"}) is None
    assert prefer_wide_vectors({"NUMBA_CPU_FEATURES": "+avx2"}) is None
    environ: dict = {}
    assert prefer_wide_vectors(environ) is None and environ == {}  # numba is imported here: too late to choose


_WIDTH_PROBE = '''
import sys
from forcenet.core.compiled import prefer_wide_vectors
chosen = prefer_wide_vectors()
from forcenet.exact.triangle.free_fermion import engine, kernels
residues = engine.prime_residues(9, 8388593).tolist()
[asm] = kernels._gko_sites.inspect_asm().values()
print(repr((chosen, asm.count("zmm"), residues)))
'''


def test_the_command_lines_processes_compile_the_route_with_512_bit_vectors_and_the_same_residues(tmp_path):
    """``forcenet.__main__.run`` first: the hot loop of the table becomes 512-bit vector code, the residues stay."""
    import ast

    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}  # compiled here, so the machine code can be read
    env.pop("NUMBA_CPU_FEATURES", None)
    env.pop("NUMBA_CPU_NAME", None)
    out = subprocess.run([sys.executable, "-c", _WIDTH_PROBE], env=env, capture_output=True, text=True, check=True)
    chosen, zmm, residues = ast.literal_eval(out.stdout.strip().splitlines()[-1])
    from forcenet.exact.triangle.free_fermion import engine

    assert residues == engine.prime_residues(9, 8388593).tolist()  # this process: numba's own choice
    if _has_avx512():
        assert chosen.endswith(",-prefer-256-bit") and zmm > 0
    else:
        assert chosen is None


def test_the_forcenet_command_prints_the_bytes_of_the_library(tmp_path, cli):
    """The console entry (wide vectors in its processes) and ``main`` in this process give the same table."""
    env = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CPU_FEATURES", "NUMBA_CPU_NAME")}
    argv = ["table", "--N", "14", "--method", "pfaffian", "--format", "json"]
    run = subprocess.run([sys.executable, "-m", "forcenet", *argv], env=env, capture_output=True, text=True, check=True)
    code, out, _ = cli(argv)
    assert code == 0 and run.stdout == out


def test_a_home_that_does_not_exist_is_never_created(tmp_path):
    """The kernel cache's anchor missing (HOME gone, no XDG_CACHE_HOME): a private folder, removed at exit."""
    import subprocess
    import sys

    home = tmp_path / "no" / "such" / "home"
    env = {k: v for k, v in os.environ.items() if k not in ("XDG_CACHE_HOME", "NUMBA_CACHE_DIR")}
    env["HOME"] = str(home)
    code = ("from forcenet.core.compiled import njit\n"
            "@njit\n"
            "def twice(x):\n"
            "    return 2 * x\n"
            "print(twice(21), twice.stats.cache_path.startswith(__import__('tempfile').gettempdir()))\n")
    script = tmp_path / "kernel.py"
    script.write_text(code)
    out = subprocess.run([sys.executable, str(script)], env=env, capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["42", "True"]
    assert not (tmp_path / "no").exists()


def test_a_kernel_of_a_subpackage_is_seen_cached_by_a_second_process(tmp_path):
    """numba names a kernel's cache index by its file's stem, not its dotted module: a second process's plan
    counts no compilation for a kernel of a package (as every kernel of forcenet is)."""
    package = tmp_path / "probe_pkg" / "inner"
    package.mkdir(parents=True)
    (tmp_path / "probe_pkg" / "__init__.py").write_text("")
    (package / "__init__.py").write_text("")
    (package / "kernels.py").write_text(PROBE)
    code = ("import sys; sys.path.insert(0, sys.argv[1])\n"
            "from probe_pkg.inner.kernels import twice\n"
            "from forcenet.core.plan import kernels_cached\n"
            "print(kernels_cached([twice]), twice(4))\n")
    env = {**{k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}, "XDG_CACHE_HOME": str(tmp_path / "xdg")}

    def run():
        return subprocess.run([sys.executable, "-c", code, str(tmp_path)], env=env, capture_output=True, text=True,
                              check=True, timeout=120).stdout.split()

    assert run() == ["False", "8"]  # compiled (and cached) here
    assert run() == ["True", "8"]  # found in the cache by the next process


def test_a_local_pools_workers_take_the_command_lines_vector_width(monkeypatch):
    """forcenet's own worker processes compile as the command line's do (512-bit vectors on AVX-512), so a
    table from Python costs what ``forcenet table`` costs; the caller's process keeps its settings, and a
    choice of the caller's (NUMBA_CPU_FEATURES) reaches the workers unchanged."""
    from llvmlite import binding

    from forcenet.core.compiled import WIDE_VECTOR_FEATURE
    from forcenet.core.execution import local_pool

    monkeypatch.delenv("NUMBA_CPU_FEATURES", raising=False)
    monkeypatch.delenv("NUMBA_CPU_NAME", raising=False)
    features = binding.get_host_cpu_features().flatten()
    expected = f"{features},{WIDE_VECTOR_FEATURE}" if "+avx512f" in features.split(",") else None
    with local_pool(1) as pool:
        assert pool.submit(os.getenv, "NUMBA_CPU_FEATURES").result(timeout=120) == expected
    assert "NUMBA_CPU_FEATURES" not in os.environ  # this process is left as it was
    monkeypatch.setenv("NUMBA_CPU_FEATURES", "+avx2")
    with local_pool(1) as pool:
        assert pool.submit(os.getenv, "NUMBA_CPU_FEATURES").result(timeout=120) == "+avx2"


def _compile_probe_here():
    """In a worker process: import the probe (its kernel compiled, or loaded, for the worker's CPU features)."""
    import probe_variant

    return probe_variant.twice(3)


def test_the_cache_is_judged_for_the_cpu_features_the_run_compiles_for(tmp_path, monkeypatch):
    """numba keys cached machine code by CPU features. forcenet's workers compile for their own (512-bit vectors on
    AVX-512), so code cached by this process does not spare them a compilation, and the other way round; a plan
    asks for the features of the processes that will run (kernels_cached(..., in_workers))."""
    from forcenet.core.compiled import WIDE_VECTOR_FEATURE, compile_features, host_features
    from forcenet.core.execution import local_pool
    from forcenet.core.plan import kernels_cached

    monkeypatch.delenv("NUMBA_CPU_FEATURES", raising=False)
    monkeypatch.delenv("NUMBA_CPU_NAME", raising=False)
    wide = "+avx512f" in host_features().split(",")
    assert compile_features() == host_features()
    assert compile_features(workers=True) == (f"{host_features()},{WIDE_VECTOR_FEATURE}" if wide else host_features())
    (tmp_path / "probe_variant.py").write_text(PROBE)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    monkeypatch.syspath_prepend(str(tmp_path))
    try:
        with local_pool(1) as pool:  # only a worker compiles
            assert pool.submit(_compile_probe_here).result(timeout=300) == 6
        twice = importlib.import_module("probe_variant").twice
        assert kernels_cached([twice], in_workers=True)
        assert kernels_cached([twice]) == (not wide)  # this process needs its own variant on AVX-512
        assert twice(4) == 8  # compiled here (or loaded: the same features)
        sys.modules.pop("probe_variant")
        fresh = importlib.import_module("probe_variant").twice  # only the disk can say now
        assert kernels_cached([fresh]) and kernels_cached([fresh], in_workers=True)
    finally:
        sys.modules.pop("probe_variant", None)
