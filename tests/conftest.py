"""Test configuration: Hypothesis profiles chosen by HYPOTHESIS_PROFILE (dev, ci, thorough)."""

import os

import mpmath
import pytest
from hypothesis import HealthCheck, settings

settings.register_profile("dev", max_examples=50, deadline=None)
settings.register_profile("ci", max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("thorough", max_examples=100_000, deadline=None, suppress_health_check=[HealthCheck.too_slow])
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "dev"))


@pytest.fixture(autouse=True)
def _reset_mpmath():
    """The library uses private mpmath contexts; make sure nothing leaks into the global one."""
    prec, pretty = mpmath.mp.prec, mpmath.mp.pretty
    yield
    assert mpmath.mp.prec == prec, "a test or the library changed the global mpmath precision"
    mpmath.mp.prec, mpmath.mp.pretty = prec, pretty


PROPERTY_PROFILE = {"dev": "dev", "ci": "ci", "thorough": "ci"}[os.environ.get("HYPOTHESIS_PROFILE", "dev")]


@pytest.fixture(scope="session")
def property_verdicts():
    """The verdict table at the test profile, computed once (properties and reports share it)."""
    from verify.verdicts import verdicts

    return verdicts(PROPERTY_PROFILE, workers=2)
