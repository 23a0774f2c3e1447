"""The property suite's profiles: how many cases each row (or property) is checked on.

Kept apart from :mod:`verify.properties.verdicts`, which loads Hypothesis and SymPy,
so that the command line can offer the profiles without loading them.

>>> list(PROFILES)
['dev', 'ci', 'thorough']
"""

from __future__ import annotations

#: cases per row of the verdict table (per property for the profiles of :data:`PER_PROPERTY`)
PROFILES = {"dev": 25, "ci": 100, "thorough": 100_000}
#: profiles whose count is per property (shared by its rows), not per row
PER_PROPERTY = {"thorough"}
