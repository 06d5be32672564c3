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


class _Optioned(_Engine):
    """An engine taking options beyond the request, with a start-up every plan pays."""

    def __init__(self, name: str, seconds: float, options=(), min_plan_seconds: float = 0.0) -> None:
        super().__init__(name, seconds)
        self.options, self.min_plan_seconds, self.plans = frozenset(options), min_plan_seconds, 0

    def plan(self, request):
        self.plans += 1
        return super().plan(request)


@dataclass(frozen=True)
class _OptionRequest:
    n: int
    method: str = "auto"
    model: str = "toy"
    quantity: str = "value"
    options: tuple = ()


def test_auto_skips_an_engine_whose_start_up_a_runnable_plan_beats_and_says_so():
    registry = Registry()
    quick, slow_start = _Optioned("quick", 0.1), _Optioned("primes", 0.01, min_plan_seconds=2.0)
    registry.register(quick), registry.register(slow_start)
    decision = registry.decide(_Request(3))
    assert decision.engine is quick and decision.skipped == {"primes": 2.0} and slow_start.plans == 0
    assert list(decision.plans) == ["quick"]
    decision = registry.decide(_Request(100))  # quick's plan (10 s) no longer beats the start-up: both planned
    assert decision.engine is slow_start and slow_start.plans == 1 and set(decision.plans) == {"quick", "primes"}


def test_auto_chooses_among_the_engines_taking_the_options_and_the_candidates_given():
    registry = Registry()
    registry.register(_Optioned("plain", 0.1))
    registry.register(_Optioned("primes", 1.0, options=("workers",)))
    assert registry.decide(_OptionRequest(1)).engine.name == "plain"
    assert registry.decide(_OptionRequest(1, options=("workers",))).engine.name == "primes"
    assert registry.decide(_OptionRequest(1), ("primes",)).engine.name == "primes"
    assert registry.takes("toy", "value", "primes", "workers") and not registry.takes("toy", "value", "plain", "workers")
    with pytest.raises(ArgumentError, match="checkpoint= applies to no engine of 'value' for model 'toy'"):
        registry.decide(_OptionRequest(1, options=("checkpoint",)))


def test_a_models_policy_decides_its_quantity_and_a_named_method_too():
    from forcenet.core.registry import Decision

    registry = Registry()
    a, b = registry.register(_Engine("a", 1.0)), registry.register(_Engine("b", 5.0))
    asked = []

    def slowest(reg, request):  # a policy of its own: here, the slowest plan, with its reason
        asked.append(request.method)
        plans = {e.name: e.plan(request) for e in (a, b)}
        return Decision(b, plans["b"], plans, {}, "the policy's reason")

    registry.set_policy("toy", "value", slowest)
    decision = registry.decide(_Request(2, method="a"))
    assert decision.engine is b and decision.why == "the policy's reason" and asked == ["a"]
    assert registry.decide(_Request(2), ("a",)).engine is a  # candidates given: the fastest among them, no policy
    assert registry.run(_Request(2)) == ("b", 2)


def test_a_loader_registers_the_engines_a_module_lists(tmp_path, monkeypatch):
    module = tmp_path / "toy_listed_engines_for_registry_test.py"
    module.write_text(
        "from forcenet.core.plan import Plan\n"
        "class E:\n"
        "    name, model, quantities = 'listed', 'listed-model', frozenset({'value'})\n"
        "    def plan(self, request): return Plan('x', 1.0)\n"
        "    def run(self, request, plan, *, progress=None, executor=None): return 7\n"
        "ENGINES = (E(),)\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    registry = Registry()
    registry.add_loader("listed-model", "toy_listed_engines_for_registry_test")
    assert registry.methods("listed-model", "value") == ("listed",)
    assert registry.run(_Request(1, model="listed-model")) == 7


def test_the_one_registry_is_the_cores_and_holds_the_triangle():
    from forcenet.core.registry import REGISTRY as CORE
    from forcenet.registry import REGISTRY

    assert REGISTRY is CORE
    assert "triangle" in REGISTRY.models()
    assert REGISTRY.methods("triangle", "law") == ("ideals", "pfaffian", "floor", "layers", "pfaffians")
