"""The chicken-wire model's front door (Sec. 7.4): each face equals its engine, renders the command line's bytes,
and refuses with the family's messages.

``forcenet.transfer_spectrum``, ``forcenet.bethe_ground_state``, ``forcenet.isotropic_point`` and
``forcenet.isotropic_maximum`` against :mod:`forcenet.numeric.chicken_wire` and against ``forcenet transfer``,
``bethe`` and ``entropy`` (run in-process through :func:`forcenet.cli.main`).
"""

import warnings
from fractions import Fraction

import mpmath
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import forcenet
from forcenet.cli import main
from forcenet.core.errors import ArgumentError, ArgumentTypeError, ConvergenceError, PrecisionWarning
from forcenet.core.precision import check_within_pi, within_pi
from forcenet.numeric.chicken_wire import isotropic as iso


def run(argv, capsys):
    capsys.readouterr()
    code = main([*argv, "--quiet"])
    out, err = capsys.readouterr()
    return code, out, err


def stdout_of(argv, capsys):
    code, out, err = run(argv, capsys)
    assert code == 0 and err == "", err
    return out


# ----------------------------------------------------------------------------- transfer


def test_transfer_spectrum_is_the_engines_sector_by_sector():
    from forcenet.numeric.chicken_wire.transfer import sector_entropy

    s = forcenet.transfer_spectrum(5)
    assert [x.particles for x in s.sectors] == list(range(6))
    for sector in s.sectors:
        assert (sector.eigenvalue, sector.entropy_per_site) == sector_entropy(5, particles=sector.particles)
    assert s.lambda_max == 2.0  # the empty row: a horizontal line around the cylinder
    assert s.bulk is not None and s.bulk.particles > 0
    assert s.bulk.eigenvalue == max(x.eigenvalue for x in s.sectors if x.particles > 0)
    assert forcenet.transfer_spectrum(5, particles=2).bulk is None


@pytest.mark.parametrize("argv", [["--L", "5"], ["--L", "6"], ["--L", "5", "--particles", "3"],
                                  ["--L", "4", "--particles", "0"]])
def test_transfer_spectrum_renders_the_command_lines_bytes(argv, capsys):
    L = int(argv[1])
    particles = int(argv[3]) if len(argv) > 2 else None
    s = forcenet.transfer_spectrum(L, particles)
    assert stdout_of(["transfer", *argv, "--format", "json"], capsys) == s.to_json() + "\n"
    assert stdout_of(["transfer", *argv], capsys) == s.to_text() + "\n"


def test_transfer_spectrum_refuses_a_sector_that_does_not_exist(capsys):
    plan = forcenet.transfer_spectrum_plan(4, particles=7)
    message = "particles=7 is out of range: particles must be an integer in 0..L = 0..4"
    assert not plan.runnable and plan.refusal == message
    with pytest.raises(ArgumentError, match="particles=7 is out of range"):
        forcenet.transfer_spectrum(4, particles=7)
    code, out, err = run(["transfer", "--L", "4", "--particles", "7"], capsys)
    assert code == 2 and out == "" and err == f"forcenet: error: {message}\n"
    with pytest.raises(ArgumentError, match="L=15"):
        forcenet.transfer_spectrum_plan(15)
    with pytest.raises(ArgumentTypeError, match="L=4.0"):
        forcenet.transfer_spectrum_plan(4.0)


def test_the_faces_hold_the_widths_the_command_line_offers(capsys):
    """The ranges live in the faces (the engines' limits), so Python and the command line agree: transfer's
    L = 14 is planned in both (the command line asks for --force), a Bethe width or L_max beyond its range is
    refused by the family, however large (10**100 overflowed a float in the plan before)."""
    assert forcenet.transfer_spectrum_plan(14).cost.runnable
    code, out, err = run(["transfer", "--L", "14"], capsys)
    assert code == 2 and out == "" and "--force" in err
    for huge in (5001, 10**100):
        with pytest.raises(ArgumentError, match="L must be an integer in 3..5000"):
            forcenet.bethe_ground_state_plan(huge)
        with pytest.raises(ArgumentError, match="L_max must be an integer in 60..1200"):
            forcenet.isotropic_point_plan("0.3", bethe=True, L_max=huge)
    assert forcenet.isotropic_point_plan("0.3", bethe=True, L_max=1200).cost.runnable


def test_transfer_spectrum_reports_one_tick_per_sector():
    ticks = []
    forcenet.transfer_spectrum(4, progress=lambda k=1: ticks.append(k))
    assert ticks == [1] * 5 == [1] * forcenet.transfer_spectrum_plan(4).cost.ticks


# ----------------------------------------------------------------------------- Bethe


def test_bethe_ground_state_is_the_engines_and_the_transfer_matrixs():
    from forcenet.numeric.chicken_wire.bethe_sector import ground_state

    g = forcenet.bethe_ground_state(8, 3, 1)
    sol = ground_state(8, 3, 1)
    assert (g.L, g.n, g.m) == (8, 3, 1)
    assert g.eigenvalue == pytest.approx(sol.eigenvalue, abs=1e-12)
    assert g.entropy_per_site == pytest.approx(sol.entropy_per_site, abs=1e-12)
    # a second route: the sector's largest transfer-matrix eigenvalue
    assert g.eigenvalue == pytest.approx(forcenet.transfer_spectrum(8, particles=3).sectors[0].eigenvalue, abs=1e-10)
    assert g.residual < 1e-10 and len(g.w) == 3 and len(g.u) == 1


@pytest.mark.parametrize("argv, sector", [(["--L", "6", "--n", "2", "--m", "1"], (6, 2, 1)), (["--L", "7"], (7, None, None)), (["--L", "8", "--n", "3", "--m", "1"], (8, 3, 1))])
def test_bethe_ground_state_renders_the_command_lines_bytes(argv, sector, capsys):
    g = forcenet.bethe_ground_state(*sector)
    assert stdout_of(["bethe", *argv, "--format", "json"], capsys) == g.to_json() + "\n"
    assert stdout_of(["bethe", *argv], capsys) == g.to_text() + "\n"


def test_bethe_ground_state_defaults_and_refusals(capsys):
    p = forcenet.bethe_ground_state_plan(60)
    assert (p.L, p.n, p.m) == (60, 20, 10) and p.cost.ticks == 9  # the continuation k (6, 2, 1) from L = 12
    message = "(L, n, m) = (6, 2, 2) is out of range: need 1 <= m < n < L"
    assert forcenet.bethe_ground_state_plan(6, 2, 2).refusal == message
    with pytest.raises(ArgumentError, match=r"\(L, n, m\) = \(6, 2, 2\)"):
        forcenet.bethe_ground_state(6, 2, 2)
    code, out, err = run(["bethe", "--L", "6", "--n", "2", "--m", "2"], capsys)
    assert code == 2 and out == "" and err == f"forcenet: error: {message}\n"
    with pytest.raises(ArgumentError, match="L=2 is out of range"):
        forcenet.bethe_ground_state_plan(2)
    with pytest.raises(ArgumentTypeError, match="n=2.0"):
        forcenet.bethe_ground_state_plan(6, 2.0)


def test_a_bethe_ground_state_that_does_not_converge_is_one_line(monkeypatch, capsys):
    import forcenet.chicken_wire_sectors as bethe_sector  # the front door's engine, imported at its top

    def lost(L, n, m, progress=None):
        raise ConvergenceError(f"no ground state of (L, n, m) = ({L}, {n}, {m}) converged")

    monkeypatch.setattr(bethe_sector, "ground_state", lost)
    with pytest.raises(ConvergenceError, match=r"\(6, 2, 1\) converged"):
        forcenet.bethe_ground_state(6, 2, 1)
    code, out, err = run(["bethe", "--L", "6"], capsys)
    assert (code, out) == (2, "") and err == "forcenet: error: no ground state of (L, n, m) = (6, 2, 1) converged\n"


# ----------------------------------------------------------------------------- the isotropic line


@pytest.mark.parametrize("point, dps", [({"Q": Fraction(1, 6)}, 30), ({"phi": "0.3"}, 40), ({"Q": Fraction(0)}, 20),
                                        ({"Q": Fraction(1, 3)}, 25), ({"phi": "-1.2"}, 15)])
def test_isotropic_point_is_the_closed_forms(point, dps):
    e = forcenet.isotropic_point(**point, dps=dps)
    assert e["v_per_site"] == iso.entropy(**point, dps=dps)
    assert e["empty_per_site"] == iso.empty_density(**point, dps=dps)
    assert e["s_per_tiling_vertex"] == iso.tiling_entropy(**point, dps=dps)
    assert e["g_per_grain_7_4"] == iso.entropy_per_grain(1, dps)
    inside = abs(float(point["phi"])) < 1.57 if "phi" in point else 0 < point["Q"] < Fraction(1, 3)
    assert ("mu" in e.keys()) == inside
    if inside:
        assert e["mu"] == iso.chemical_potential(**point, dps=dps)
    assert e.bethe is None and e.dps == dps
    with pytest.raises(ArgumentError, match="key='nope' is not a row here"):
        e["nope"]


@pytest.mark.parametrize("argv, face", [
    (["--Q", "1/6"], {"Q": "1/6"}),
    (["--phi", "0.3", "--dps", "40"], {"phi": "0.3", "dps": 40}),
    (["--Q", "1/3"], {"Q": Fraction(1, 3)}),
    (["--Q", "0"], {"Q": 0}),
    (["--Q", "1e-30", "--dps", "20"], {"Q": "1e-30", "dps": 20}),
    (["--phi", "1.5707963267948966"], {"phi": "1.5707963267948966"}),
    (["--phi", "1.2", "--F", "2.5"], {"phi": "1.2", "side": "2.5"}),
])
def test_isotropic_point_renders_the_command_lines_bytes(argv, face, capsys):
    e = forcenet.isotropic_point(**face)
    assert stdout_of(["entropy", *argv, "--format", "json"], capsys) == e.to_json() + "\n"
    assert stdout_of(["entropy", *argv], capsys) == e.to_text() + "\n"


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])  # capsys: read out
@given(c=st.integers(0, 40), a=st.integers(1, 40), dps=st.integers(5, 40))
def test_isotropic_point_json_is_the_command_lines_at_any_density(c, a, dps, capsys):
    Q = Fraction(c, 3 * a) if c <= a else Fraction(a, 3 * c)  # in [0, 1/3]
    e = forcenet.isotropic_point(Q=Q, dps=dps)
    assert stdout_of(["entropy", "--Q", str(Q), "--dps", str(dps), "--format", "json"], capsys) == e.to_json() + "\n"


def test_isotropic_maximum_is_the_engines_and_the_command_lines(capsys):
    m = forcenet.isotropic_maximum(dps=30)
    engine = iso.maximum(30)
    assert m["v_max_per_site"] == engine.v_max and m["Q_max"] == engine.Q_max and m["s_max_per_tiling_vertex"] == engine.s_max
    with mpmath.workdps(40):  # the twelvefold point: Q0 = (3 - sqrt3)/6
        assert abs(m["Q0"] - (3 - mpmath.sqrt(3)) / 6) < mpmath.mpf(10) ** -29
    assert stdout_of(["entropy", "--max", "--dps", "30", "--format", "json"], capsys) == m.to_json() + "\n"
    assert stdout_of(["entropy", "--max", "--dps", "30"], capsys) == m.to_text() + "\n"
    assert forcenet.isotropic_maximum_plan(30).maximum and not forcenet.isotropic_point_plan(Q=0).maximum


def test_the_bethe_value_is_rendered_as_the_command_line_renders_it(monkeypatch, capsys):
    """The Bethe route's answer (stubbed here: its own tests are tests/test_bethe.py) in the face and in the cli."""
    import forcenet.chicken_wire_isotropic as isotropic_bethe  # the front door's engine, imported at its top

    seen = []

    def engine(Q, L_max=240):
        seen.append((Q, L_max))
        return 0.0616159805, 2.5e-9, (Fraction(1, 6),)

    monkeypatch.setattr(isotropic_bethe, "isotropic_entropy", engine)
    e = forcenet.isotropic_point(Q="1/6", bethe=True, L_max=120)
    assert seen == [(Fraction(1, 6), 120)] and e.bethe.v == 0.0616159805 and e.bethe.densities == (Fraction(1, 6),)
    assert e.to_json().endswith('"v_bethe": 0.0616159805, "v_bethe_error": 2.5e-09, "bethe_densities": ["1/6"]}')
    assert "v_bethe             = 0.061615980500 +- 2.5e-09" in e.to_text().splitlines()
    argv = ["entropy", "--Q", "1/6", "--bethe", "--L-max", "120"]
    assert stdout_of([*argv, "--format", "json"], capsys) == e.to_json() + "\n"
    assert stdout_of(argv, capsys) == e.to_text() + "\n"
    e = forcenet.isotropic_point(phi="0.5", bethe=True, L_max=120)  # from phi: the density as a float
    assert seen[-1] == (float(e["Q"]), 120)


def test_a_bethe_value_that_does_not_converge_names_the_route(monkeypatch, capsys):
    import forcenet.chicken_wire_isotropic as isotropic_bethe  # the front door's engine, imported at its top

    def lost(Q, L_max=240):
        raise ConvergenceError("the continuation lost the ground state at L = 84")

    monkeypatch.setattr(isotropic_bethe, "isotropic_entropy", lost)
    with pytest.raises(ConvergenceError, match="^Bethe ansatz: the continuation lost"):
        forcenet.isotropic_point(Q="1/6", bethe=True)
    code, out, err = run(["entropy", "--Q", "1/6", "--bethe"], capsys)
    assert (code, out) == (2, "") and err == "forcenet: error: Bethe ansatz: the continuation lost the ground state at L = 84\n"


@pytest.mark.slow  # ~15 s: one Bethe-ansatz sequence of widths up to 60
def test_the_bethe_value_agrees_with_the_closed_form(capsys):
    e = forcenet.isotropic_point(Q="1/6", bethe=True, L_max=60, dps=15)
    assert abs(e.bethe.v - float(e["v_per_site"])) < max(10 * e.bethe.error, 1e-6)
    assert stdout_of(["entropy", "--Q", "1/6", "--bethe", "--L-max", "60", "--dps", "15", "--format", "json"],
                     capsys) == e.to_json() + "\n"


def test_the_plan_is_the_announcement_of_the_command_line():
    p = forcenet.isotropic_point_plan(Q="1/6", bethe=True)
    assert p.cost.what.startswith("1 Bethe-ansatz sequence") and p.cost.ticks == 1 and p.cost.unit == "sequence"
    assert p.seconds > iso.closed_form_plan(50).seconds
    assert forcenet.isotropic_point_plan(Q="1/5", bethe=True).cost.ticks == 1  # c/a with a <= 60: solved directly
    assert forcenet.isotropic_point_plan(Q="0.2001", bethe=True).cost.ticks == 2  # interpolated between two
    assert forcenet.isotropic_point_plan(phi="0.3", dps=1000).cost == iso.closed_form_plan(1000)
    assert forcenet.isotropic_maximum_plan(1000).cost == iso.closed_form_plan(1000, maximum=True)


@pytest.mark.parametrize("call, error, message", [
    (lambda: forcenet.isotropic_point_plan(phi="1.5707963267948967"), ArgumentError,
     "phi=1.5707963267948967 is out of range: phi must lie in [-pi/2, pi/2] = [-1.5707963267948966192..., "
     "1.5707963267948966192...]"),
    (lambda: forcenet.isotropic_point_plan(Q="0.4"), ArgumentError,
     "Q=0.4 is out of range: the density per direction Q must lie in [0, 1/3]"),
    (lambda: forcenet.isotropic_point_plan(Q=Fraction(-1, 7)), ArgumentError, "Q=-1/7 is out of range"),
    (lambda: forcenet.isotropic_point_plan(Q=[0.1]), ArgumentTypeError, "Q=[0.1] is not a real number"),
    (lambda: forcenet.isotropic_point_plan(Q="abc"), ArgumentTypeError, "Q='abc' is not a real number"),
    (lambda: forcenet.isotropic_point_plan(Q=float("nan")), ArgumentError, "Q=nan is out of range"),
    (lambda: forcenet.isotropic_point_plan(Q=True), ArgumentTypeError, "Q=True is not a number"),
    (lambda: forcenet.isotropic_point_plan(), ArgumentTypeError, "give exactly one of phi= and Q="),
    (lambda: forcenet.isotropic_point_plan(phi=0, Q=0), ArgumentTypeError, "give exactly one of phi= and Q="),
    (lambda: forcenet.isotropic_point_plan(Q=1 / 6, dps=40), ArgumentTypeError, "pass '1/6' or Fraction(1, 6)"),
    (lambda: forcenet.isotropic_point_plan(Q=0, L_max=100), ArgumentError,
     "L_max=100 sets the widths of bethe=True: pass bethe=True or drop L_max"),
    (lambda: forcenet.isotropic_point_plan(Q=0, side="0"), ArgumentError, "side=0 is out of range"),
    (lambda: forcenet.isotropic_point_plan(Q=0, dps=4), ArgumentError, "dps=4"),
    (lambda: forcenet.isotropic_point(Q="1/3", bethe=True), ArgumentError,
     "Q=0.333333 is out of range: the Bethe route needs 0 < Q < 1/3"),
    (lambda: forcenet.isotropic_point(Q="1/70", bethe=True, L_max=60), ArgumentError,
     "Q=0.014285714285714285: outside the fractions c/a <= 16 available to the Bethe route"),
    (lambda: forcenet.isotropic_maximum(dps=10001), ArgumentError, "dps=10001"),
])
def test_the_isotropic_faces_refuse_with_the_familys_messages(call, error, message):
    with pytest.raises(error) as info:
        call()
    assert message in str(info.value)


def test_the_refusals_read_as_the_command_lines(capsys):
    """The same request refused by the face and by ``forcenet entropy``: one message."""
    for argv, face in [(["--Q", "1/3", "--bethe"], {"Q": "1/3", "bethe": True}),
                       (["--Q", "1/70", "--bethe", "--L-max", "60"], {"Q": "1/70", "bethe": True, "L_max": 60})]:
        with pytest.raises(ArgumentError) as info:
            forcenet.isotropic_point(**face)
        code, out, err = run(["entropy", *argv], capsys)
        assert (code, out) == (2, "") and err == f"forcenet: error: {info.value}\n"
    code, out, err = run(["entropy", "--phi", "1.5707963267948967"], capsys)
    with pytest.raises(ArgumentError) as info:
        forcenet.isotropic_point(phi="1.5707963267948967")
    assert code == 2 and err.endswith(f"argument --phi: {info.value}\n")


def test_a_binary_float_is_taken_at_its_exact_value_once():
    exact = forcenet.isotropic_point(Q=Fraction(1, 4), dps=30)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # 0.25 is exactly its decimal: no warning
        assert forcenet.isotropic_point(Q=0.25, dps=30).to_json() == exact.to_json()
    with pytest.warns(PrecisionWarning) as caught:
        e = forcenet.isotropic_point(phi=0.3, dps=12)
    with mpmath.workdps(12):  # the float's exact value, rounded to the digits asked, as mpmath.mpf(0.3) is
        assert len(caught) == 1 and e["phi"] == +mpmath.mpf(0.3) and e["Q"] == iso.density_Q(Fraction(0.3), 12)


# ----------------------------------------------------------------------------- the range check of --phi


@settings(max_examples=30, deadline=None)
@given(k=st.integers(1, 80), sign=st.sampled_from([1, -1]))
def test_within_pi_decides_at_the_digits_given(k, sign):
    with mpmath.workdps(k + 30):
        half = mpmath.pi / 2 * 10**k
        below, above = mpmath.floor(half), mpmath.ceil(half)
    digits = lambda n: f"{'-' if sign < 0 else ''}{str(int(n))[0]}.{str(int(n))[1:]}"  # noqa: E731
    assert within_pi(digits(below)) and within_pi(digits(below), strict=True)
    assert not within_pi(digits(above))
    assert within_pi(Fraction(int(below), 10**k) * sign) and not within_pi(Fraction(int(above), 10**k) * sign)
    with pytest.raises(ArgumentError, match=r"phi=.* is out of range: phi must lie in \[-pi/2, pi/2\]"):
        check_within_pi(digits(above), "phi")


def test_within_pi_refuses_what_is_not_a_finite_number():
    with pytest.raises(ArgumentTypeError, match="phi='x' is not a real number"):
        within_pi("x", name="phi")
    with pytest.raises(ArgumentError, match="phi='inf' is out of range"):
        within_pi("inf", name="phi")
    assert within_pi(mpmath.mpf(1)) and not within_pi(2) and check_within_pi(Fraction(3, 2), "phi") == Fraction(3, 2)


def test_the_cli_takes_the_front_doors_names_only():
    import ast
    import inspect

    import forcenet.cli.chicken_wire as module

    tree = ast.parse(inspect.getsource(module))
    used = {node.attr for node in ast.walk(tree) if isinstance(node, ast.Attribute)
            and isinstance(node.value, ast.Name) and node.value.id == "forcenet"}
    assert used and used <= set(forcenet.__all__)
    imported = {alias.name.split(".")[0] if isinstance(node, ast.Import) else (node.module or "").split(".")[0]
                for node in ast.walk(tree) if isinstance(node, (ast.Import, ast.ImportFrom)) for alias in node.names}
    assert not imported & {"mpmath", "numpy", "scipy", "sympy", "flint"}
