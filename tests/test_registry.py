"""The model seam (forcenet.core.registry): engines keyed by model, quantity and method; auto by the plans."""

from __future__ import annotations

from dataclasses import dataclass

import pytest

from forcenet.core.errors import ArgumentError, ArgumentTypeError
from forcenet.core.plan import Plan
from forcenet.core.registry import Engine, Registry


@dataclass(frozen=True)
class _Request:
    n: int
    method: str = "auto"
    model: str = "toy"
    quantity: str = "value"


class _Engine:
    def __init__(self, name: str, seconds: float, refusal: str | None = None, quantities=("value",)) -> None:
        self.name, self.model, self.quantities = name, "toy", frozenset(quantities)
        self.seconds, self.refusal, self.runs = seconds, refusal, 0

    def plan(self, request):
        return Plan(self.name, seconds=self.seconds * request.n, refusal=self.refusal)

    def run(self, request, plan, *, progress=None, executor=None):
        self.runs += 1
        return (self.name, request.n)


def test_auto_takes_the_fastest_runnable_plan_and_skips_refusals():
    registry = Registry()
    slow, fast, refused = _Engine("slow", 2.0), _Engine("fast", 1.0), _Engine("never", 0.0, refusal="too big")
    for engine in (slow, refused, fast):
        registry.register(engine)
    assert registry.methods("toy", "value") == ("slow", "never", "fast")
    assert registry.choose(_Request(3))[0] is fast
    assert registry.run(_Request(3)) == ("fast", 3) and fast.runs == 1 and slow.runs == 0


def test_a_named_method_runs_that_engine_and_a_refused_plan_raises_before_running():
    registry = Registry()
    refused = registry.register(_Engine("never", 0.0, refusal="N=99 is out of range"))
    with pytest.raises(ArgumentError, match="N=99 is out of range"):
        registry.run(_Request(1, method="never"))
    assert refused.runs == 0


def test_all_refused_reports_the_first_refusal():
    registry = Registry()
    registry.register(_Engine("a", 1.0, refusal="a refuses"))
    registry.register(_Engine("b", 1.0, refusal="b refuses"))
    engine, plan = registry.choose(_Request(1))
    assert engine.name == "a" and plan.refusal == "a refuses"


def test_unknown_method_model_and_quantity_name_the_choices():
    registry = Registry()
    registry.register(_Engine("a", 1.0))
    with pytest.raises(ArgumentError, match="method='b' is out of range: method must be one of a, auto"):
        registry.engine("toy", "value", "b")
    with pytest.raises(ArgumentError, match="no engine computes 'value' for model 'other'"):
        registry.choose(_Request(1, model="other"))
    with pytest.raises(ArgumentError, match="no engine computes 'mean'"):
        registry.engine("toy", "mean", "a")


def test_registration_is_checked():
    registry = Registry()
    registry.register(_Engine("a", 1.0))
    with pytest.raises(ArgumentError, match="registered twice"):
        registry.register(_Engine("a", 1.0))
    with pytest.raises(ArgumentError, match="'auto' is the registry's choice"):
        registry.register(_Engine("auto", 1.0))
    with pytest.raises(ArgumentTypeError, match="is not an Engine"):
        registry.register(object())  # type: ignore[arg-type]
    assert isinstance(_Engine("x", 1.0), Engine)


def test_a_loader_registers_a_model_on_first_use(tmp_path, monkeypatch):
    module = tmp_path / "toy_engines_for_registry_test.py"
    module.write_text(
        "from forcenet.core.plan import Plan\n"
        "from tests_registry_target import registry\n"
        "class E:\n"
        "    name, model, quantities = 'loaded', 'lazy', frozenset({'value'})\n"
        "    def plan(self, request): return Plan('x', 1.0)\n"
        "    def run(self, request, plan, *, progress=None, executor=None): return 42\n"
        "registry.register(E())\n")
    target = tmp_path / "tests_registry_target.py"
    target.write_text("from forcenet.core.registry import Registry\nregistry = Registry()\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    import tests_registry_target

    registry = tests_registry_target.registry
    registry.add_loader("lazy", "toy_engines_for_registry_test")
    assert "lazy" in registry.models()
    assert registry.run(_Request(1, model="lazy")) == 42
    assert registry.methods("lazy", "value") == ("loaded",)
