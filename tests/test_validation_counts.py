"""Parse once (issue 51): a plan makes at most 12 calls into ``forcenet.core.validation``.

The front door builds one request, checked once (``forcenet.exact.routes.check_request``,
``forcenet.exact.law_registry.law_request``); the registry and the engines take it and check nothing again.
Every call of a function defined in ``forcenet.core.validation`` is counted (a check's delegations included:
``check_layers`` calling ``check_int`` counts two), on a cold process (no cache of an earlier plan hides a
check) and again warm, in-process. Before the seam: ``plan(40)`` 15, ``plan(40, moments=2)`` 316,
``plan(40, moments=2, row=20)`` 3138, ``law_plan(36, (36, 18))`` 21, ``law_plan(12)`` 105.
"""

from __future__ import annotations

import subprocess
import sys
import textwrap

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import forcenet
import forcenet.core.validation as validation

LIMIT = 12
CASES = [
    "forcenet.plan(40)",
    "forcenet.plan(40, moments=2)",
    "forcenet.row_plan(40, 20, moments=2)",
    "forcenet.plan(24, method='pfaffian')",
    "forcenet.law_plan(36, (36, 18))",
    "forcenet.law_plan(40, layer=40)",
    "forcenet.law_plan(12)",
    "forcenet.row_plan(12, 11, moments=2)",
]

_COUNT = textwrap.dedent("""
    import sys
    import forcenet
    import forcenet.core.validation as validation

    calls = []

    def profile(frame, event, arg):
        if event == "call" and frame.f_code.co_filename == validation.__file__:
            calls.append(frame.f_code.co_name)

    sys.setprofile(profile)
    eval(sys.argv[1], {"forcenet": forcenet})
    sys.setprofile(None)
    print(len(calls), *calls)
""")


def _counted(expression: str) -> list[str]:
    """The validation functions called while ``expression`` runs in this (warm) process."""
    calls: list[str] = []

    def profile(frame, event, arg):
        if event == "call" and frame.f_code.co_filename == validation.__file__:
            calls.append(frame.f_code.co_name)

    sys.setprofile(profile)
    try:
        eval(expression, {"forcenet": forcenet})
    finally:
        sys.setprofile(None)
    return calls


def test_the_counter_counts_a_checks_delegations():
    """The counter sees a check and what it delegates to: it could fail."""
    calls = _counted("forcenet.core.validation.check_layers(5)")
    assert calls == ["check_layers", "check_int"]


@pytest.mark.parametrize("expression", CASES)
def test_a_plan_checks_its_request_once_warm(expression):
    eval(expression, {"forcenet": forcenet})  # imports and the kernels' cache judged once
    calls = _counted(expression)
    assert 1 <= len(calls) <= LIMIT, calls


@pytest.mark.parametrize("expression", CASES[:5])
def test_a_plan_checks_its_request_once_cold(expression):
    out = subprocess.run([sys.executable, "-c", _COUNT, expression], capture_output=True, text=True, check=True).stdout
    count, *calls = out.split()
    assert 1 <= int(count) <= LIMIT, calls


@settings(max_examples=25, deadline=None)
@given(N=st.sampled_from([2, 5, 9, 13, 28, 40, 129]), moments=st.integers(1, 3),
       method=st.sampled_from(["auto", "fast", "thesis", "lambda", "maps", "pfaffian"]), row=st.integers(0, 129))
def test_every_table_plan_checks_its_request_once(N, moments, method, row):
    expression = f"forcenet.row_plan({N}, {row}, {moments}, {method!r})" if 1 <= row <= N else \
        f"forcenet.plan({N}, {moments}, {method!r})"
    eval(expression, {"forcenet": forcenet})
    assert len(_counted(expression)) <= LIMIT, expression


@settings(max_examples=20, deadline=None)
@given(N=st.sampled_from([3, 12, 30, 40, 128]), target=st.sampled_from(["grain", "edge", "layer", "ensemble", "contact"]),
       method=st.sampled_from(["auto", "ideals", "pfaffians"]))
def test_every_law_plan_checks_its_request_once(N, target, method):
    where = {"grain": f"({N}, {N // 2 + 1})", "edge": f"({N}, 1)", "layer": f"layer={N}", "ensemble": "",
             "contact": f"({N}, 2), contact='F1'"}[target]
    expression = f"forcenet.law_plan({N}{', ' + where if where else ''}, method={method!r})"
    eval(expression, {"forcenet": forcenet})
    assert len(_counted(expression)) <= LIMIT, expression
