"""The Monte Carlo front door (``forcenet.sample``, ``forcenet.sample_plan``, ``forcenet.Scene``) and the sampled
comparison of a pooled law (``Law.compare_with_samples``, ``LawPlan.with_sampled_comparison``): the engines' numbers,
the command line's bytes, refusals that name the argument.
"""

from __future__ import annotations

import contextlib
import io
import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import forcenet
from forcenet.cli import main
from forcenet.core.plan import combine
from forcenet.numeric.parallel_chains import parallel_plan, sample_in_parallel
from forcenet.numeric.triangle.exact_sampler import sample_plan as exact_plan
from forcenet.numeric.triangle.force_distribution import exact_sampler_histogram, histogram_edges, metropolis_histogram
from forcenet.numeric.triangle.metropolis import metropolis_plan


def _cli(*args: str) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(args))
    return code, out.getvalue(), err.getvalue()


# ------------------------------------------------------------------ the engine's numbers


@pytest.mark.parametrize("kwargs", [
    {"sampler": "exact", "workers": 1},
    {"sampler": "exact", "workers": 2},
    {"sampler": "metropolis", "workers": 1, "move": "slice"},
])
def test_the_face_returns_the_engines_pooled_estimate(kwargs):
    s = forcenet.sample(5, 2000, seed=11, **kwargs)
    burn = 200 if kwargs["sampler"] == "metropolis" else 0
    engine = sample_in_parallel(kwargs["sampler"], 5, 2000, seed=11, workers=kwargs["workers"], burn_in=burn,
                                move=kwargs.get("move", "metropolis"))
    assert np.array_equal(s.mean, engine.mean) and np.array_equal(s.stderr, engine.stderr)
    assert s.effective_samples == engine.extra["effective_samples"] and s.kernel == engine.extra["kernel"]
    exact = forcenet.table(5).mean_W  # and the estimate is of the exact table (5 sigma)
    for i in range(5):
        for j in range(i + 1):
            assert abs(s.mean[i, j] - float(exact[i][j])) <= 5 * s.stderr[i, j] + 1e-12


def test_the_packing_through_a_top_level_scene():
    scene = forcenet.Scene(N=3, P=5, F=20.0, mg=1.0)
    s = forcenet.sample(3, 2000, sampler="metropolis", scene=scene, response=True, seed=2)
    engine = sample_in_parallel("metropolis", 3, 2000, seed=2, scene=scene, burn_in=200, response=True)
    assert np.array_equal(s.mean, engine.mean) and np.array_equal(s.G, engine.extra["G"])
    assert s.extra["scene"] == "gravity" and s.mean.shape == (3, 5)
    assert abs(s.mean[-1].sum() - (20 + 3 * 5)) < 1e-9  # the floor carries all


def test_the_plan_is_the_samplers_plan_over_the_workers():
    memory = 8 * 2**30
    p = forcenet.sample_plan(9, 5000, workers=2, memory_bytes=memory)
    assert p.cost == parallel_plan(exact_plan(9, 5000, memory), 2, memory)
    p = forcenet.sample_plan(9, 5000, sampler="metropolis", ph=0.3, workers=2, memory_bytes=memory)
    assert p.burn_in == 500 and p.cost == parallel_plan(metropolis_plan(9, 5000, 1000, memory, ph=True), 2, memory)
    refused = forcenet.sample_plan(100000, 2, memory_bytes=2**30)
    assert not refused.runnable and "GiB" in refused.refusal
    with pytest.raises(forcenet.ArgumentError, match="GiB"):
        refused.run()


# ------------------------------------------------------------------ the command line's bytes


@pytest.mark.parametrize("argv, kwargs", [
    (["--N", "6", "--samples", "300", "--seed", "4"], {"N": 6, "samples": 300, "seed": 4}),
    (["--N", "5", "--sampler", "metropolis", "--samples", "400", "--seed", "4", "--burn-in", "50"],
     {"N": 5, "samples": 400, "seed": 4, "sampler": "metropolis", "burn_in": 50}),
    (["--N", "4", "--sampler", "metropolis", "--samples", "1500", "--seed", "3", "--F", "1e300"],
     {"N": 4, "samples": 1500, "seed": 3, "sampler": "metropolis", "F": 1e300}),
    (["--N", "3", "--P", "5", "--mg", "1", "--F", "20", "--sampler", "metropolis", "--response", "--samples", "2000",
      "--seed", "2"],
     {"N": 3, "samples": 2000, "seed": 2, "sampler": "metropolis", "response": True,
      "scene": forcenet.Scene(N=3, P=5, F=20.0, mg=1.0)}),
])
@pytest.mark.parametrize("fmt", ["json", "text"])
def test_the_renderings_are_the_command_lines_bytes(argv, kwargs, fmt):
    s = forcenet.sample(**kwargs)
    code, out, _ = _cli("sample", *argv, "--format", fmt, "--quiet")
    assert code == 0 and out == (s.to_json() if fmt == "json" else s.to_text()) + "\n"


@settings(max_examples=8, deadline=None)
@given(N=st.integers(2, 6), samples=st.integers(2, 300), seed=st.integers(0, 2**63 - 1), workers=st.integers(1, 2))
def test_the_json_is_a_function_of_the_arguments_seed_and_workers(N, samples, seed, workers):
    s = forcenet.sample(N, samples, seed=seed, workers=workers)
    code, out, _ = _cli("sample", "--N", str(N), "--samples", str(samples), "--seed", str(seed), "--workers",
                        str(workers), "--format", "json", "--quiet")
    assert code == 0 and out == s.to_json() + "\n" == forcenet.sample(N, samples, seed=seed, workers=workers).to_json() + "\n"
    rows = json.loads(out)["mean_W"]
    assert [len(r) for r in rows] == list(range(1, N + 1)) and rows[0] == [1.0]


def test_timing_adds_the_rate():
    s = forcenet.sample(4, 200, seed=1)
    data = json.loads(s.to_json(timing=2.0))
    assert data["seconds"] == 2.0 and data["effective_samples_per_second"] == 100.0
    assert list(data)[-2:] == ["mean_W", "stderr_W"] and "seconds" not in s.to_json()


# ------------------------------------------------------------------ refusals name the Python argument


@pytest.mark.parametrize("kwargs, error, needle", [
    ({"ph": 0.5}, forcenet.ArgumentError, "ph=0.5 applies to sampler='metropolis' only"),
    ({"burn_in": 10}, forcenet.ArgumentError, "burn_in=10 applies to sampler='metropolis' only"),
    ({"move": "slice"}, forcenet.ArgumentError, "move='slice' applies to sampler='metropolis' only"),
    ({"scene": forcenet.Scene(N=4, P=3, mg=1.0)}, forcenet.ArgumentError, "scene=Scene("),
    ({"sampler": "gibbs"}, forcenet.ArgumentError, "sampler='gibbs' is not one of 'exact', 'metropolis'"),
    ({"sampler": "metropolis", "move": "heat bath"}, forcenet.ArgumentError, "move='heat bath' is not one of"),
    ({"sampler": "metropolis", "response": True}, forcenet.ArgumentError, "response=True needs the full packing"),
    ({"workers": 5, "samples": 4}, forcenet.ArgumentError, "workers=5: more workers than samples (4); use at most 4"),
    ({"workers": 65}, forcenet.ArgumentError, "workers=65 is out of range"),
    ({"samples": 1}, forcenet.ArgumentError, "samples=1 is out of range"),
    ({"seed": -1}, forcenet.ArgumentError, "seed=-1 is out of range"),
    ({"F": float("nan")}, forcenet.ArgumentError, "F=nan is out of range"),
    ({"sampler": "metropolis", "ph": 1e300, "F": 1e-10}, forcenet.ArgumentError, "the ratio ph/F must lie in"),
    ({"sampler": "metropolis", "scene": forcenet.Scene(N=4, P=3, mg=1e300)}, forcenet.ArgumentError,
     "mg=1e+300 is out of range: the packing's loads F, pv, mg, ph (scene=) must lie in [1e-100, 1e+100]"),
    ({"sampler": "metropolis", "scene": forcenet.Scene(N=3, P=3, mg=1.0)}, forcenet.ArgumentError,
     "N=4 and scene.N=3 differ"),
    ({"sampler": "metropolis", "scene": forcenet.Scene(N=4, P=3, mg=1.0), "F": 2.0}, forcenet.ArgumentError,
     "F=2.0 and scene.F=1.0"),
    ({"sampler": "metropolis", "scene": forcenet.Scene(N=4, P=3, mg=1.0), "ph": 2.0}, forcenet.ArgumentError,
     "ph=2.0 and scene.ph=None"),
    ({"sampler": "metropolis", "scene": (4, 3)}, forcenet.ArgumentTypeError, "scene=(4, 3) is not a scene"),
    ({"N": 1}, forcenet.ArgumentError, "N=1 is out of range"),
])
def test_refusals_name_the_argument(kwargs, error, needle):
    kwargs = {"N": 4, "samples": 100, **kwargs}
    with pytest.raises(error) as caught:
        forcenet.sample_plan(**kwargs)
    assert needle in str(caught.value)


def test_a_chain_too_short_to_judge_is_a_convergence_error_and_the_cli_keeps_its_line():
    with pytest.raises(forcenet.ConvergenceError, match=r"^samples=50: .*too short.*; run more sweeps$"):
        forcenet.sample(6, 50, sampler="metropolis")
    code, out, err = _cli("sample", "--N", "6", "--sampler", "metropolis", "--samples", "50")
    assert code == 2 and out == "" and err.startswith("forcenet: ") and "samples=50: " in err and "run more sweeps" in err


def test_a_non_finite_result_is_refused(monkeypatch):
    from forcenet.numeric import parallel_chains

    real = parallel_chains._combine_chains

    def overflowing(parts):
        mean, stderr, extra = real(parts)
        return mean, stderr * math.nan, extra

    monkeypatch.setattr(parallel_chains, "_combine_chains", overflowing)
    with pytest.raises(forcenet.ArgumentError, match=r"non-finite values .*give loads in \[1e-100, 1e\+100\]"):
        forcenet.sample(4, 600, sampler="metropolis")


def test_the_cli_keeps_its_flag_worded_packing_refusal():
    code, out, err = _cli("sample", "--N", "4", "--sampler", "metropolis", "--samples", "100", "--P", "3", "--mg",
                          "1e300")
    assert code == 2 and out == "" and "mg=1e+300 is out of range: with --P the loads --F, --pv, --mg, --ph" in err


# ------------------------------------------------------------------ the sampled comparison of a pooled law


def test_the_comparison_is_the_engines_histograms_against_the_exact_bins():
    law = forcenet.law(5, layer=4)
    c = law.compare_with_samples(samples=300, sweeps=300, bins=6, f_max=3.0, seed=5)
    edges = histogram_edges(3.0, 6)
    exact = exact_sampler_histogram(5, 300, edges, 4, 5)
    chain = metropolis_histogram(5, 300, edges, 4, seed=5)
    a, b = c.histograms.values()
    assert np.array_equal(a.density, exact.density) and np.array_equal(b.density, chain.density) and b.tau == chain.tau
    assert sum(c.exact_bins) == law.cdf_at(3) and all(x >= 0 for x in c.exact_bins)
    assert len(c.notes) == 2 and c.notes[0].startswith("exact sampler: chi2 = ") and c.title.endswith(c.notes[1])


def test_the_comparison_plan_is_the_laws_and_the_samplers_announcement():
    request = forcenet.law_plan(6)
    p = request.with_sampled_comparison(samples=1000, sweeps=500)
    memory = request.memory_bytes
    expected = combine(f"{request.cost.what} with its sampled comparison",
                       [request.cost, exact_plan(6, 1000, memory), metropolis_plan(6, 500, 100, memory)], "step")
    assert p.cost == expected and p.pool == "ensemble" and (p.bins, p.f_max, p.seed) == (40, 4.0, 0)


@pytest.mark.parametrize("call, needle", [
    (lambda: forcenet.law(5, (5, 2)).compare_with_samples(), "compare_with_samples compares a pooled P(f)"),
    (lambda: forcenet.law_plan(5, (5, 2), contact="F1").with_sampled_comparison(), "a pooled P(f)"),
    (lambda: forcenet.law_plan(5).with_sampled_comparison(samples=1), "samples=1 is out of range"),
    (lambda: forcenet.law_plan(5).with_sampled_comparison(bins=1001), "bins=1001 is out of range"),
    (lambda: forcenet.law_plan(5).with_sampled_comparison(f_max=-1), "f_max=-1 is out of range"),
    (lambda: forcenet.law_plan(5).with_sampled_comparison(seed=-2), "seed=-2 is out of range"),
])
def test_the_comparison_refuses_what_it_cannot_compare(call, needle):
    with pytest.raises(forcenet.ArgumentError) as caught:
        call()
    assert needle in str(caught.value)


def test_dist_plot_writes_the_faces_png_and_notes(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, out, err = _cli("dist", "--N", "5", "--layer", "5", "--plot", "p.png", "--samples", "300", "--sweeps", "300",
                          "--bins", "6", "--seed", "3", "--format", "json")
    c = forcenet.law_plan(5, layer=5).with_sampled_comparison(samples=300, sweeps=300, bins=6, seed=3).run()
    assert code == 0 and out == c.law.to_json() + "\n"
    assert [line for line in err.splitlines() if "chi2" in line] == [f"forcenet: {line}" for line in c.notes]
    assert (tmp_path / "p.png").read_bytes() == c.png()
