"""What a user installs: one package named forcenet, from a repository without symlinks (issues 24.13, 25.1).

The sources keep the project's layout (``exact/``, ``numeric/`` and ``src/forcenet/``) and pyproject.toml's
``package-dir`` maps them to ``forcenet.exact``, ``forcenet.numeric`` and ``forcenet``. These tests check
the installed package (regular or editable), the wheel built from the source distribution, the
metadata, and that a type checker resolves every ``forcenet.*`` import.
"""

from __future__ import annotations

import ast
import email.parser
import importlib.util
import json
import os
import re
import shutil
import subprocess
import sys
import sysconfig
import tarfile
import zipfile
from importlib import metadata
from pathlib import Path

import pytest
from installed import ROOT, installed_modules, packages, setuptools_config, source_dir

import forcenet

SOURCE_TOPS = ("src", "core", "exact", "numeric")  # the folders that install (pyproject.toml's package-dir)
SKIP_DIRS = {".git", "build", "dist", "__pycache__", ".hypothesis", ".pytest_cache", ".mypy_cache"}


def _project() -> dict:
    import tomllib

    with open(ROOT / "pyproject.toml", "rb") as f:
        return tomllib.load(f)["project"]


def _site_dirs() -> list[Path]:
    return [Path(sysconfig.get_paths()[key]).resolve() for key in ("purelib", "platlib")]


def _editable_root() -> Path | None:
    """The source folder of an editable install (pip's direct_url.json), None for a regular install."""
    text = metadata.distribution("forcenet").read_text("direct_url.json")
    info = json.loads(text) if text else {}
    if not info.get("dir_info", {}).get("editable"):
        return None
    return Path(info["url"].removeprefix("file://")).resolve()


# ------------------------------------------------------------------ the repository


def test_no_symlink_in_the_source_tree():
    links = []
    for top, dirs, files in os.walk(ROOT):
        dirs[:] = [d for d in dirs if d not in SKIP_DIRS and not d.endswith(".egg-info")]
        links += [str(Path(top, n).relative_to(ROOT)) for n in dirs + files if Path(top, n).is_symlink()]
    assert not links, f"symlinks in the source tree: {links}"


@pytest.mark.skipif(not (ROOT / ".git").exists() or shutil.which("git") is None, reason="not a git checkout")
def test_no_tracked_symlink():
    out = subprocess.run(["git", "ls-files", "-s"], cwd=ROOT, capture_output=True, text=True, check=True).stdout
    assert out.strip(), "git ls-files listed nothing"
    links = [line.split("\t", 1)[1] for line in out.splitlines() if line.startswith("120000 ")]
    assert not links, f"tracked symlinks (mode 120000): {links}"


def test_the_package_list_is_complete():
    """Every folder with an __init__.py under src/, exact/, numeric/ is a listed package, and the converse."""
    mapping = setuptools_config()["package-dir"]
    assert set(mapping.values()) == set(SOURCE_TOPS)
    listed = {source_dir(p).resolve(): p for p in packages()}
    on_disk = {init.parent.resolve() for top in SOURCE_TOPS for init in (ROOT / top).rglob("__init__.py")}
    assert on_disk == set(listed), (
        f"folders not listed in pyproject.toml: {sorted(map(str, on_disk - set(listed)))}; "
        f"listed but missing: {sorted(listed[d] for d in set(listed) - on_disk)}"
    )
    stray = [str(p.relative_to(ROOT)) for top in SOURCE_TOPS for p in (ROOT / top).rglob("*.py") if p.parent.resolve() not in on_disk]
    assert not stray, f"modules outside any package would not be installed: {stray}"


# ------------------------------------------------------------------ the installed package


def test_the_tests_import_the_installed_package_of_this_checkout():
    """Regular install: every module lies under site-packages and equals its source (not stale).
    Editable install: every module is the checkout's own file, reached through the package-dir mapping."""
    editable = _editable_root()
    modules = installed_modules()
    assert len(modules) > 50 and modules[0][0] == "forcenet"
    if editable is None:
        base = Path(forcenet.__file__).resolve().parent
        assert any(base.parent == site for site in _site_dirs()), f"forcenet imported from {base}, not site-packages"
        assert base.parent != ROOT.resolve()
    else:
        assert editable == ROOT.resolve(), f"the editable install points at {editable}, not this checkout {ROOT}"
    stale = []
    for name, path in modules:
        package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
        source = source_dir(package) / path.name
        if editable is not None:
            assert path.resolve() == source.resolve(), f"{name} imported from {path}, expected {source}"
        else:
            assert Path(sysconfig.get_paths()["purelib"]).resolve() in path.resolve().parents, f"{name} from {path}"
            if path.read_bytes() != source.read_bytes():
                stale.append(name)
    assert not stale, f"the installed package is older than the checkout (reinstall): {stale}"


def test_only_forcenet_at_the_top_of_site_packages(tmp_path):
    """As a user's interpreter sees it (isolated mode, away from the checkout): forcenet.exact and
    forcenet.numeric import, and no generic top-level exact or numeric module exists."""
    probe = (
        "import importlib.util as u, json, forcenet.exact, forcenet.numeric, forcenet.cli;"
        "print(json.dumps([u.find_spec(n) is None for n in ('exact', 'numeric', 'cli', 'testing')]))"
    )
    proc = subprocess.run([sys.executable, "-I", "-c", probe], cwd=tmp_path, capture_output=True, text=True, check=False)
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout) == [True] * 4, "a generic top-level module is importable"
    for site in _site_dirs():
        assert not {"exact", "numeric", "cli", "testing"} & {p.name for p in site.iterdir()}


def test_typed_and_versioned():
    assert (Path(forcenet.__file__).parent / "py.typed").is_file()
    assert forcenet.__version__ == metadata.version("forcenet") == _project()["version"]
    proc = subprocess.run([sys.executable, "-m", "forcenet", "--version"], capture_output=True, text=True, check=False)
    assert proc.returncode == 0 and proc.stdout == f"forcenet {forcenet.__version__}\n"


def test_metadata():
    meta = metadata.metadata("forcenet")
    assert meta["License-Expression"] == "MIT"
    assert "LICENSE" in meta.get_all("License-File")
    classifiers = meta.get_all("Classifier")
    assert "Typing :: Typed" in classifiers and not [c for c in classifiers if c.startswith("License ::")]
    assert meta["Author"] == "The forcenet developers" and meta["Keywords"]
    assert "Copyright (c) 2026 The forcenet developers" in (ROOT / "LICENSE").read_text()


# ------------------------------------------------------------------ the distributions


def _build(kind: str, source: Path, out: Path) -> Path:
    """PEP 517 build with the installed setuptools (the test extra), in a subprocess."""
    code = f"import setuptools.build_meta as b; print(b.build_{kind}({str(out)!r}))"
    proc = subprocess.run([sys.executable, "-c", code], cwd=source, capture_output=True, text=True, check=False)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return out / proc.stdout.strip().splitlines()[-1]


@pytest.fixture(scope="module")
def distributions(tmp_path_factory):
    """The sdist built from a copy of the checkout, and the wheel built from the unpacked sdist (as `build` does)."""
    tmp = tmp_path_factory.mktemp("dist")
    ignore = shutil.ignore_patterns(*SKIP_DIRS, "*.egg-info", "*.pyc")
    for entry in ROOT.iterdir():  # the project's files; no hidden folder but .ci, no virtual environment
        if entry.name in SKIP_DIRS or entry.name.startswith(".") and entry.name != ".ci":
            continue
        if entry.is_dir() and not (entry / "pyvenv.cfg").exists():
            shutil.copytree(entry, tmp / "checkout" / entry.name, ignore=ignore)
        elif entry.is_file():
            (tmp / "checkout").mkdir(exist_ok=True)
            shutil.copyfile(entry, tmp / "checkout" / entry.name)
    sdist = _build("sdist", tmp / "checkout", tmp)
    with tarfile.open(sdist) as tar:
        tar.extractall(tmp / "unpacked", filter="data")
    (top,) = (tmp / "unpacked").iterdir()
    wheel = _build("wheel", top, tmp)
    with tarfile.open(sdist) as tar:
        sdist_names = {n.split("/", 1)[1] for n in tar.getnames() if "/" in n}
    with zipfile.ZipFile(wheel) as z:
        wheel_names = set(z.namelist())
        meta = email.parser.Parser().parsestr(z.read(f"forcenet-{forcenet.__version__}.dist-info/METADATA").decode())
    return sdist_names, wheel_names, meta


def test_the_wheel_maps_the_source_folders(distributions):
    _, names, meta = distributions
    info = f"forcenet-{forcenet.__version__}.dist-info/"
    expected = {"forcenet/py.typed"}
    for package in packages():
        folder = source_dir(package)
        expected |= {"/".join([*package.split("."), p.name]) for p in folder.glob("*.py")}
    assert {n for n in names if not n.startswith(info)} == expected
    assert {n.split("/", 1)[0] for n in names} == {"forcenet", info.rstrip("/")}
    assert f"{info}licenses/LICENSE" in names and f"{info}entry_points.txt" in names
    assert meta["License-Expression"] == "MIT" and meta["Name"] == "forcenet"


def test_the_sdist_holds_what_the_package_page_names(distributions):
    """The README is the package page: every notes/ or benchmarks/ path it names is in the source distribution."""
    sdist, _, meta = distributions
    readme = (ROOT / "README.md").read_text()
    named = set(re.findall(r"\b((?:notes|benchmarks)/[\w./-]*\w)", readme))
    assert "notes/architecture.md" in named
    missing = sorted(n for n in named if not any(s == n or s.startswith(n + "/") for s in sdist))
    assert not missing, f"the README names files the source distribution lacks: {missing}"
    assert {"LICENSE", "README.md", "pyproject.toml", ".ci/run", "tests/test_packaging.py"} <= sdist
    assert meta.get_payload().startswith(readme.split("\n", 1)[0])


# ------------------------------------------------------------------ a type checker reads the package


def _mypy(view: Path) -> tuple[str, list[str]]:
    """mypy over the module tree in ``view`` alone (not site-packages; third-party code is not read)."""
    proc = subprocess.run(
        [sys.executable, "-m", "mypy", "-p", "forcenet", "--config-file", str(ROOT / "pyproject.toml"),
         "--follow-imports=skip", "--no-site-packages", "--cache-dir", str(view / ".mypy_cache")],
        cwd=view, capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert proc.returncode in (0, 1), proc.stderr
    unresolved = [
        line for line in proc.stdout.splitlines()
        if re.search(r"\[(import-not-found|import-untyped|import)\]$", line) and '"forcenet' in line
        or re.search(r'Module "forcenet[\w.]*" has no attribute', line)
    ]  # fmt: skip
    return proc.stdout, unresolved


def _lay_out(modules, view: Path) -> None:
    for name, path in modules:
        rel = Path(*name.split("."))
        target = view / rel / "__init__.py" if path.name == "__init__.py" else view / rel.with_suffix(".py")
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(path, target)


def test_a_type_checker_resolves_every_forcenet_import(tmp_path):
    """mypy over the installed module tree (copied as the import system finds it: site-packages or the
    editable mapping): no forcenet.* import left unresolved. Its other findings are issue 25.5's."""
    modules = installed_modules()
    _lay_out(modules, tmp_path / "installed")
    (tmp_path / "installed" / "forcenet" / "py.typed").touch()
    out, unresolved = _mypy(tmp_path / "installed")
    assert not unresolved, "\n".join(unresolved)
    checked = re.search(r"(?:checked|no issues found in) (\d+) source files?", out)
    assert checked and int(checked[1]) == len(modules), out[-500:]
    # the detector catches what it is for: a tree without forcenet.numeric
    control = [(n, p) for n, p in modules if n in ("forcenet", "forcenet.cli", "forcenet.cli.common", "forcenet.cli.limit")]
    _lay_out(control, tmp_path / "control")
    _, unresolved = _mypy(tmp_path / "control")
    assert any("forcenet.numeric" in line for line in unresolved)


def test_tests_and_benchmarks_import_forcenet_names_only():
    """From the checkout root exact/ and numeric/ are importable as generic names: nothing may use that."""
    bad = []
    for path in sorted([*(ROOT / "tests").rglob("*.py"), *(ROOT / "benchmarks").rglob("*.py")]):
        for node in ast.walk(ast.parse(path.read_text())):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else []
            if isinstance(node, ast.ImportFrom) and node.level == 0:
                names = [node.module or ""]
            bad += [f"{path.relative_to(ROOT)}:{node.lineno} {n}" for n in names if n.split(".")[0] in ("exact", "numeric")]
    assert not bad, f"generic imports: {bad}"


def test_the_checkout_root_cannot_shadow_the_package():
    """`python -m pytest` puts the checkout root on sys.path: it holds no forcenet/ folder to shadow the install."""
    assert not (ROOT / "forcenet").exists()
    spec = importlib.util.find_spec("forcenet")
    assert spec is not None and Path(spec.origin).resolve() == Path(forcenet.__file__).resolve()
