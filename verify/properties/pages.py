"""The report page of the property verdicts."""

from __future__ import annotations

from typing import TYPE_CHECKING

from verify.views.pages import block

if TYPE_CHECKING:
    from collections.abc import Sequence

    from verify.properties.verdicts import Verdict


def properties_page(profile: str, found: Sequence[Verdict]) -> str:
    """The page of the property verdicts."""
    from verify.properties.text import properties_text

    return (
        "# Properties of the rule and of the simultaneous law\n\n"
        f"Every property x law x rule x family, profile `{profile}` "
        f"(`verify properties --profile {profile}`); under the simultaneous law the rule column names the CORs.\n"
        "Each refutation comes with its shrunk exact counterexample; save it as a case file and rerun it\n"
        "with "
        "`verify solve CASE.json --rule RULE` (add `--law simultaneous` for that law's rows; or let\n"
        "`verify properties --counterexamples DIR` write the files).\n\n" + block(properties_text(profile, found))
    )
