"""Issue 56 items 2, 7 and 8: settings of the environment and addresses that crashed the command line.

Each case runs the installed ``forcenet`` command in a fresh process (the environment is read before numba is
imported) and must end in one line on stderr from the exception family, exit 2, or work; never an abort inside
LLVM, a traceback or an internal error. The host-name cases need no process: the parser refuses them.
"""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from forcenet.cli.cluster import scheduler_address
from forcenet.cli.common import UsageError
from forcenet.core.compiled import cache_home, check_environment
from forcenet.core.errors import ArgumentError

_COMMAND = [sys.executable, "-m", "forcenet", "count", "--N", "6"]

ENVIRONMENTS = [  # (setting, value, a piece of the one line) -- each crashed the command line before issue 56
    ("NUMBA_DISABLE_JIT", "1", "NUMBA_DISABLE_JIT='1' turns off the compiled kernels"),
    ("NUMBA_NUM_THREADS", "0", "NUMBA_NUM_THREADS='0' must be a whole number of at least 1"),
    ("NUMBA_NUM_THREADS", "-3", "NUMBA_NUM_THREADS='-3' must be"),
    ("NUMBA_NUM_THREADS", "two", "NUMBA_NUM_THREADS='two' must be"),
    ("NUMBA_CPU_FEATURES", "garbage", "NUMBA_CPU_FEATURES='garbage' is not a list of +feature/-feature items"),
    ("NUMBA_CPU_FEATURES", "+avx,sse2", "NUMBA_CPU_FEATURES='+avx,sse2' is not a list"),
]


def _run(env: dict[str, str], argv: list[str] = _COMMAND, cwd: str | None = None) -> subprocess.CompletedProcess:
    full = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_")}
    full.update(env)
    return subprocess.run(argv, env=full, capture_output=True, text=True, timeout=120, cwd=cwd, check=False)


@pytest.mark.parametrize("name, value, piece", ENVIRONMENTS, ids=[f"{n}={v}" for n, v, _ in ENVIRONMENTS])
def test_a_setting_numba_cannot_work_with_is_one_line_and_exit_2(name, value, piece):
    result = _run({name: value})
    assert result.returncode == 2, result.stderr
    assert result.stderr.count("\n") == 1 and result.stderr.startswith("forcenet: error: ") and piece in result.stderr
    with pytest.raises(ArgumentError, match=piece.replace("+", r"\+").replace("(", r"\(")):
        check_environment({name: value})


@pytest.mark.parametrize("env", [{"NUMBA_DISABLE_JIT": "0"}, {"NUMBA_NUM_THREADS": "1"},
                                 {"NUMBA_CPU_FEATURES": "+avx,,-foo"}, {}])
def test_settings_that_work_are_left_alone(env):
    check_environment(env)  # no refusal


def test_too_few_open_files_are_refused_in_one_line_and_enough_work():
    prlimit = "/usr/bin/prlimit"
    if not os.path.exists(prlimit):
        pytest.skip("prlimit (util-linux) is not installed")
    low = _run({}, [prlimit, "--nofile=12", *_COMMAND])
    assert low.returncode == 2 and low.stderr.count("\n") == 1, low.stderr
    assert "the limit on open files is 12 (ulimit -n)" in low.stderr
    soft = _run({}, [prlimit, "--nofile=12:4096", *_COMMAND])  # a low soft limit under a high hard one: raised
    assert soft.returncode == 0 and soft.stdout.strip().endswith("286"), soft.stderr


def test_a_relative_cache_home_is_ignored_as_the_xdg_rules_say(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", "relative/cache")
    assert cache_home() == os.path.join(os.path.expanduser("~"), ".cache")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert cache_home() == str(tmp_path)
    result = _run({"XDG_CACHE_HOME": "relative"}, cwd=str(tmp_path))
    assert result.returncode == 0, result.stderr
    assert not os.path.exists(tmp_path / "relative")  # nothing written into the working folder


@pytest.mark.parametrize("address, piece", [
    ("tcp://" + "a" * 64 + ".example:8786", "a label of the host name is empty or longer than 63 characters"),
    ("tcp://" + "ab." * 1700 + "x:8786", "the host name has 5101 characters, more than DNS allows (253)"),
    ("tls://a..b:8786", "a label of the host name is empty"),
])
def test_a_host_name_dns_cannot_hold_is_one_short_line(address, piece):
    with pytest.raises(UsageError) as refusal:
        scheduler_address(address)
    message = str(refusal.value)
    assert piece in message and "\n" not in message and len(message) < 300


def test_valid_addresses_still_pass():
    assert scheduler_address("tcp://" + "a" * 63 + ".example:8786")[3] == 8786
    assert scheduler_address("tls://[::1]:8786")[2] == "::1"
