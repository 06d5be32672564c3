"""One base for every result's renderings (``forcenet.rendering.Rendered``): JSON from ``to_dict``, the notebook's
display from ``to_text``, the same way for every model (notes/architecture.md, "The seam")."""

from __future__ import annotations

import json
import math

import pytest

import forcenet
from forcenet.rendering import Rendered


def _result_classes() -> list[type]:
    return [obj for name in forcenet.__all__ if isinstance(obj := getattr(forcenet, name), type)
            and hasattr(obj, "to_json")]


def test_every_result_class_of_the_front_door_shares_the_base():
    classes = _result_classes()
    assert len(classes) >= 12
    assert [c.__name__ for c in classes if not issubclass(c, Rendered)] == []


def test_the_base_refuses_a_result_without_its_values():
    class Half(Rendered):
        def to_text(self) -> str:
            return "half"

    with pytest.raises(TypeError):
        Half()


def _no_nan(value: object) -> bool:
    if isinstance(value, float):
        return math.isfinite(value)
    if isinstance(value, dict):
        return all(_no_nan(v) for v in value.values())
    if isinstance(value, (list, tuple)):
        return all(_no_nan(v) for v in value)
    return True


@pytest.mark.parametrize("make", [
    lambda: forcenet.maps(5),
    lambda: forcenet.count_plan(6).run(),
    lambda: forcenet.limit_shape("1/5", "3/5", dps=8),
    lambda: forcenet.sample(5, 200, seed=1),
    lambda: forcenet.transfer_spectrum(4, 1),
    lambda: forcenet.isotropic_point("0.3", dps=15),
    lambda: forcenet.yield_stress("hexagonal", 3, exact=False),
], ids=["maps", "count", "limit", "sample", "transfer", "entropy", "yield"])
def test_json_is_the_values_and_the_display_is_the_text(make):
    result = make()
    assert isinstance(result, Rendered)
    values = json.loads(result.to_json())
    assert values == json.loads(json.dumps(result.to_dict())) and _no_nan(values)
    assert result._repr_html_().startswith("<") and isinstance(result.to_text(), str)


def test_a_table_and_a_row_keep_their_exact_renderings():
    table, row = forcenet.table(4), forcenet.row(4, 3)
    assert json.loads(table.to_json())["mean_W"][2] == json.loads(row.to_json())["mean_W"] == ["2/7", "3/7", "2/7"]
    assert table.to_text() == table.summary()
    assert row.to_text().splitlines()[1:] == ["  <W_3,1> = 2/7", "  <W_3,2> = 3/7", "  <W_3,3> = 2/7"]
