"""Test configuration: Hypothesis profiles chosen by HYPOTHESIS_PROFILE (ci, dev, thorough).

``ci`` is the default, so the README's test command, run as it is, is the proof CI gives: an
unset or empty ``HYPOTHESIS_PROFILE`` means ``ci``. ``dev`` is a quicker local run and
``thorough`` a long one, both chosen by name (``HYPOTHESIS_PROFILE=dev python3 -m pytest``).

No profile keeps an example database: a test's outcome never depends on what an earlier run
left in ``.hypothesis/``. ``ci`` is also derandomised, so the suite passes or fails the same
way on every run; the failures Hypothesis has found are kept as ``@example`` lines instead.
"""

import json
import os

import mpmath
import pytest
from hypothesis import HealthCheck, settings

from tests.helpers import shared

settings.register_profile(
    "ci",
    max_examples=200,
    deadline=None,
    database=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile("dev", max_examples=50, deadline=None, database=None)
settings.register_profile(
    "thorough", max_examples=100_000, deadline=None, database=None, suppress_health_check=[HealthCheck.too_slow]
)
#: The Hypothesis profile of this run: HYPOTHESIS_PROFILE, or ``ci`` when it is unset or empty.
PROFILE = os.environ.get("HYPOTHESIS_PROFILE", "").strip() or "ci"
settings.load_profile(PROFILE)


def _seconds(item: pytest.Item) -> float:
    """How long a test takes on one core, about: its ``slow`` marker's ``seconds`` (10 without), or 0."""
    marker = item.get_closest_marker("slow")
    if marker is None:
        return 0
    return float(marker.kwargs.get("seconds", marker.args[0] if marker.args else 10))


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """The longest tests first (their ``slow`` markers' seconds), the others in their order: pytest-xdist then
    hands them out to the test processes in turn before any short test, so that both processes end together
    instead of one running a long test alone at the end (tests/README.md lists them)."""
    items.sort(key=lambda item: -_seconds(item))  # stable: the same order in every test process


@pytest.fixture(autouse=True)
def _reset_mpmath():
    """The library uses private mpmath contexts; make sure nothing leaks into the global one."""
    prec, pretty = mpmath.mp.prec, mpmath.mp.pretty
    yield
    assert mpmath.mp.prec == prec, "a test or the library changed the global mpmath precision"
    mpmath.mp.prec, mpmath.mp.pretty = prec, pretty


#: The property suite's profile (verify properties) that goes with the test profile.
PROPERTY_PROFILE = {"dev": "dev", "ci": "ci", "thorough": "ci"}.get(PROFILE, "ci")


@pytest.fixture(scope="session")
def property_verdicts(tmp_path_factory):
    """The verdict table at the test profile, computed once per command (properties and reports share it), on
    both cores, and written exactly (the checkpoints' encoding) for the other test process (:func:`shared`)."""
    from verify.properties.verdicts import verdicts
    from verify.runner.tasks import decode, encode

    return shared(tmp_path_factory, f"property-verdicts-{PROPERTY_PROFILE}",
                  lambda: verdicts(PROPERTY_PROFILE, workers=2),
                  dump=lambda found: json.dumps(encode(found)).encode(),
                  load=lambda text: decode(json.loads(text)))  # fmt: skip


@pytest.fixture(scope="session")
def paper_corner_maps():
    """The paper's corner mapped over its CORs as the corner report maps it (``corner_maps``: half a minute of
    exact cells), once per test process (its number fields' arithmetic does not pickle, so it is not shared
    between processes as ``property_verdicts`` is)."""
    from verify.paper.corner_map import corner_maps

    return corner_maps()
