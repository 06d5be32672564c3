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
