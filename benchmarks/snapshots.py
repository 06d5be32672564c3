"""Byte-for-byte snapshots of the command line's outputs, for refactorings that must not change them (issue 25).

    python benchmarks/snapshots.py --write DIR      # before: every command below, every format, into DIR
    python benchmarks/snapshots.py --compare DIR    # after: rerun and compare byte for byte (exit 1 on a difference)
    python benchmarks/snapshots.py --compare DIR --only sample dist   # only the cases of these commands

Each case runs ``forcenet ARGS`` with a fixed seed and stores its stdout and exit code; stderr (costs,
progress, timings) is not compared. The main job's files are compared too (``table`` without ``--format``).
"""

from __future__ import annotations

import argparse
import hashlib
import os
import shutil
import subprocess
import sys
import tempfile

CASES = [
    "count --N 12",
    "count --N 30",
    *(f"table --N {N} --format {f} --method {m}" for N, m in [(5, "fast"), (5, "thesis"), (5, "lambda"), (5, "maps"),
                                                                (7, "pfaffian"), (12, "fast"), (14, "pfaffian")]
      for f in ("json", "csv", "latex")),
    "table --N 8 --moments 3 --format json",
    "table --N 6 --moments 2 --format csv --method lambda",  # refused: stdout empty, exit 2
    "table --N 6 --moments 2 --format csv",
    "table --N 6 --moments 2 --format latex --method thesis",
    "maps --N 7",
    "maps --N 6 --format json",
    "limit --x 0.2 --z 0.6",
    "limit --x 0.2 --z 0.6 --format json --dps 30",
    "sample --N 8 --samples 2000 --seed 3",
    "sample --N 8 --samples 2000 --seed 3 --format json",
    "sample --N 6 --samples 3000 --seed 4 --sampler metropolis --format json",
    "transfer --L 6",
    "transfer --L 6 --format json",
    "bethe --L 6 --n 2 --m 1",
    "bethe --L 6 --n 2 --m 1 --format json",
    "entropy --phi 0.3",
    "entropy --phi 0.3 --format json --dps 40",
    "entropy --Q 1/3",
    "entropy --Q 0.2 --format json",
    "dist --N 8 --grain 8,4",
    "dist --N 8 --grain 8,4 --format json",
    "dist --N 7 --layer 7 --format csv",
    "dist --N 7 --contact F1 --grain 5,2 --format latex",
]
MAIN_JOB = "table --N 7 --samples 500 --seed 5"


def run(args: str, cwd: str) -> tuple[bytes, int]:
    proc = subprocess.run([sys.executable, "-m", "forcenet", *args.split()], cwd=cwd, capture_output=True, check=False)
    return proc.stdout, proc.returncode


def collect(directory: str, only: list[str] | None = None) -> None:
    os.makedirs(directory, exist_ok=True)
    for k, case in enumerate(CASES):
        if only and case.split()[0] not in only:
            continue
        out, code = run(case, directory)
        with open(os.path.join(directory, f"{k:02d}.out"), "wb") as handle:
            handle.write(f"$ forcenet {case}\nexit {code}\n".encode() + out)
    if only and "table" not in only:
        return
    work = tempfile.mkdtemp()
    try:
        out, code = run(MAIN_JOB, work)
        with open(os.path.join(directory, "main_job.out"), "wb") as handle:
            handle.write(f"$ forcenet {MAIN_JOB}\nexit {code}\n".encode() + out)
        for name in sorted(os.listdir(os.path.join(work, "forcenet-tables"))):
            shutil.copy(os.path.join(work, "forcenet-tables", name), os.path.join(directory, "main_job." + name))
    finally:
        shutil.rmtree(work)


def digest(path: str) -> str:
    with open(path, "rb") as handle:
        return hashlib.sha256(handle.read()).hexdigest()


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    group = parser.add_mutually_exclusive_group(required=True)
    group.add_argument("--write", metavar="DIR")
    group.add_argument("--compare", metavar="DIR")
    parser.add_argument("--only", nargs="+", metavar="COMMAND", help="compare only the cases of these commands")
    args = parser.parse_args(argv)
    if args.write:
        collect(args.write)
        print(f"{len(os.listdir(args.write))} snapshots in {args.write}")
        return 0
    fresh = tempfile.mkdtemp()
    try:
        collect(fresh, args.only)
        after = sorted(os.listdir(fresh))
        before = sorted(os.listdir(args.compare)) if not args.only else after
        differ = [name for name in before if name not in after or digest(os.path.join(args.compare, name)) != digest(os.path.join(fresh, name))]
        differ += [name for name in after if name not in before]
        for name in differ:
            print(f"DIFFERS: {name}")
        print(f"{len(before) - len(differ)} of {len(before)} snapshots byte-identical")
        return 1 if differ else 0
    finally:
        shutil.rmtree(fresh)


if __name__ == "__main__":
    sys.exit(main())
