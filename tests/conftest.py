import errno
import io
import os
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

# Fixed examples (derandomize) so that CI runs are reproducible.
settings.register_profile(
    "ci", deadline=None, derandomize=True, max_examples=25, suppress_health_check=[HealthCheck.too_slow]
)
settings.register_profile("dev", deadline=None, max_examples=50)
settings.load_profile(os.environ.get("FORCENET_HYPOTHESIS_PROFILE", "ci"))


def pytest_report_header(config):
    """Which forcenet the run tests: the installed package (tests/test_packaging.py checks it is this checkout's)."""
    import forcenet

    return f"forcenet {forcenet.__version__} imported from {os.path.dirname(forcenet.__file__)}"


@pytest.fixture
def cli(capsys):
    """``cli(argv)``: forcenet's ``main`` run in this process, ``(exit code, stdout, stderr)``."""
    from forcenet.cli import main

    def run(argv):
        code = main(argv)
        out, err = capsys.readouterr()
        return code, out, err

    return run


def listing(root):
    """Every path under ``root`` (hidden ones too), relative and sorted."""
    return sorted(str(p.relative_to(root)) for p in Path(root).rglob("*"))


@pytest.fixture
def files():
    """``files(root)``: :func:`listing`."""
    return listing


class FullStream(io.StringIO):
    """Standard output on a full disk: every write fails with ENOSPC."""

    def write(self, text):
        raise OSError(errno.ENOSPC, "No space left on device")

    def fileno(self):
        raise io.UnsupportedOperation("fileno")


@pytest.fixture
def full_stream():
    """A :class:`FullStream`, to put in place of ``sys.stdout``."""
    return FullStream()


def layer_agrees_with_the_exact_sampler(laws, N, i, samples=20000, seed=2811):
    """Every load of layer ``i``: its exact ``<W^2>`` and ``P(W <= <W>)`` from its gap law (``{j: GapCounts}``)
    against ``samples`` exact samples, at the testing toolkit's false-alarm rate 1e-3 for the whole set.

    Every sample lies in [0, 1] (a load is a share of the unit overload, ``W^2`` too; the CDF's indicator is 0
    or 1): the bounded test, valid at any number of rows. Without bounds the t route cannot judge 20000 rows
    here (``W^2`` of a corner load has skewness about 9: its tail is trusted from about 72000 rows on)."""
    from fractions import Fraction

    import numpy as np
    from scipy.stats import binom

    from forcenet.exact.triangle.distribution import moment_from_gaps
    from forcenet.exact.triangle.staircase import dimension
    from forcenet.numeric.agreement import compare_samples
    from forcenet.numeric.triangle.exact_sampler import ExactSampler

    d = dimension(N)
    cuts = [float(laws[j].mean() / (d + 1)) for j in range(1, i + 1)]
    second = [float(moment_from_gaps(laws[j], 2)) for j in range(1, i + 1)]
    exact_cdf = [sum(float(Fraction(c, laws[j].total)) * binom.sf(g - 1, d, w) for g, c in enumerate(laws[j].counts) if c)
                 for j, w in zip(range(1, i + 1), cuts)]  # I_w(g, d+1-g) = P(Binomial(d, w) >= g); floats at this edge
    sampler, rows, drawn = ExactSampler(N, seed=seed), [], 0
    while drawn < samples:
        W = sampler.sample_W(min(sampler.batch, samples - drawn))
        rows.append(W[:, i - 1, :i])
        drawn += W.shape[0]
    X = np.concatenate(rows)
    assert X.min() >= 0 and X.max() <= 1
    data = np.concatenate([X**2, (X <= np.array(cuts)).astype(float)], axis=1)
    keys = [f"W2_{j}" for j in range(1, i + 1)] + [f"cdf_{j}" for j in range(1, i + 1)]
    return compare_samples(data, second + exact_cdf, keys=keys, alpha=1e-3, bounds=(0, 1))


@pytest.fixture
def against_the_sampler():
    """:func:`layer_agrees_with_the_exact_sampler`."""
    return layer_agrees_with_the_exact_sampler


@pytest.fixture(scope="module")
def de_bruijn_compiled():
    """The de Bruijn kernels (floor, floor grains, layers) compiled in this process, so the plans the module's
    tests check choose their route as on a machine that ran them once, whatever ran before on this worker (a
    cold cache adds the compile time, and the order-ideal DP can then win at N ~ 20)."""
    from forcenet.exact.triangle.de_bruijn.floor import floor_gap_laws, floor_pooled_gap_law
    from forcenet.exact.triangle.de_bruijn.layers import layer_gap_laws, layer_pooled_gap_law

    floor_pooled_gap_law(5), floor_gap_laws(5), layer_pooled_gap_law(6, 4), layer_gap_laws(6, 4)

