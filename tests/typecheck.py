"""mypy and ruff over the checkout, as the project runs them (``python tests/typecheck.py [PATH ...]``).

mypy cannot follow pyproject.toml's ``package-dir`` mapping (``exact/`` installs as ``forcenet.exact``), so
the modules are laid out under their import names in a temporary folder (hard links, no copies), mypy reads
that tree with the project's configuration, and its findings are reported under the checkout's paths.
Given paths (files or folders of the checkout) restrict the report to them. Used by tests/test_lint.py.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from installed import ROOT, packages, source_dir  # the tests folder is not a package: its path first


def checkout_modules() -> dict[Path, Path]:
    """``{path under its import name: path in the checkout}`` for every module of the distribution."""
    out: dict[Path, Path] = {}
    for package in packages():
        folder = source_dir(package)
        for file in sorted(folder.glob("*.py")):
            out[Path(*package.split(".")) / file.name] = file
    return out


def mypy(view_root: Path | None = None) -> tuple[int, list[str]]:
    """mypy's exit code and findings (lines ``checkout/path:line: error: ...``)."""
    modules = checkout_modules()
    with tempfile.TemporaryDirectory() as tmp:
        view = Path(view_root or tmp)
        for rel, src in modules.items():
            (view / rel).parent.mkdir(parents=True, exist_ok=True)
            os.link(src, view / rel) if not (view / rel).exists() else None
        proc = subprocess.run(
            [sys.executable, "-m", "mypy", "-p", "forcenet", "--config-file", str(ROOT / "pyproject.toml"),
             "--cache-dir", str(Path(tempfile.gettempdir()) / "forcenet-mypy-cache")],
            cwd=view, capture_output=True, text=True, check=False,
        )
    back = {str(rel): str(src.relative_to(ROOT)) for rel, src in modules.items()}
    lines = []
    for line in proc.stdout.splitlines():
        match = re.match(r"([^:]+\.py)(:.*)", line)
        if match and match[1] in back:
            lines.append(back[match[1]] + match[2])
    return proc.returncode, lines


def ruff(paths: list[str] | None = None) -> tuple[int, list[str]]:
    """ruff's exit code and findings over the checkout (the project's configuration)."""
    proc = subprocess.run([sys.executable, "-m", "ruff", "check", "--output-format", "concise", *(paths or ["."])],
                          cwd=ROOT, capture_output=True, text=True, check=False)
    return proc.returncode, [line for line in proc.stdout.splitlines() if re.match(r"\S+\.py:\d+", line)]


def main(argv: list[str]) -> int:
    wanted = [str(Path(p).resolve().relative_to(ROOT)) for p in argv]
    code_m, found_m = mypy()
    code_r, found_r = ruff(wanted or None)
    found_m = [line for line in found_m if not wanted or any(line.startswith(w) for w in wanted)]
    print("\n".join(found_m + found_r))
    print(f"mypy: {len(found_m)} findings; ruff: {len(found_r)} findings")
    return 1 if found_m or found_r else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
