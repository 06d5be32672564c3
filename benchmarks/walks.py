"""How far a command's arguments travel: validation calls and forcenet functions entered (issue 25).

    python benchmarks/walks.py table --N 12 --format json --method fast
    python benchmarks/walks.py entropy --phi 0.3 --dps 30

Runs the command line in this process under ``sys.setprofile`` and counts, over forcenet's own
functions: the calls of each argument check (``check_layers``, ``check_int``, ``check_dps``, ...; a check's
delegation to another, such as ``check_layers`` to ``check_int``, counts once),
the distinct functions entered and the modules they live in, and the deepest chain of forcenet
frames. Nothing else is timed or compared; the command's output goes to /dev/null.
"""

from __future__ import annotations

import collections
import contextlib
import io
import sys


def walk(argv: list[str]) -> dict:
    from forcenet.cli import main

    checks: collections.Counter[str] = collections.Counter()
    functions: set[tuple[str, str]] = set()
    depth = [0, 0]

    def profile(frame, event, arg):
        module = frame.f_globals.get("__name__", "")
        if not module.startswith("forcenet"):
            return
        if event == "call":
            name = frame.f_code.co_name
            functions.add((module, name))
            caller = frame.f_back.f_code.co_name if frame.f_back else ""
            if name.startswith("check_") and not caller.startswith("check_"):
                checks[name] += 1  # an argument check, not a check's own delegation (check_layers -> check_int)
            depth[0] += 1
            depth[1] = max(depth[1], depth[0])
        elif event == "return":
            depth[0] -= 1

    sink = io.StringIO()
    sys.setprofile(profile)
    try:
        with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(io.StringIO()):
            code = main(argv)
    finally:
        sys.setprofile(None)
    return {"exit": code, "checks": dict(sorted(checks.items())), "check_calls": sum(checks.values()),
            "functions": len(functions), "modules": len({m for m, _ in functions}), "depth": depth[1]}


if __name__ == "__main__":
    result = walk(sys.argv[1:])
    print(" ".join(sys.argv[1:]))
    for key, value in result.items():
        print(f"  {key}: {value}")
