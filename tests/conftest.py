import os

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
