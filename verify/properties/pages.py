"""The report page of the property verdicts: a grid of property by CORs for each law, the termination census,
then the refutations, each property's explanation said once, with their exact counterexamples."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from collections.abc import Sequence

    from verify.properties.verdicts import Verdict

#: the laws, as the page names them
LAWS = {"rule": "the paper's rule", "simultaneous": "the simultaneous law", "sequential": "the sequential law"}
#: the CORs of a row, as the page names them
CORS = ("ideal", "symmetric", "asymmetric", "general")
FAMILIES = ("general", "cradle", "corner")
#: where a refuted row's note says why the property fails (the rest says what the counterexample does)
_WHY = ". Where it fails: "
#: where it says how to rerun the counterexample
_RERUN = "; reproduce with: "


def _cell(rows: dict[str, Verdict]) -> str:
    """A grid cell: the verdict of each family (general / cradle / corner), ``-`` where not stated."""
    if not rows:
        return ""
    return " / ".join("-" if f not in rows else _verdict(rows[f]) for f in FAMILIES)


def _verdict(v: Verdict) -> str:
    """``proved``, ``refuted``, ``holds N``, or ``no case`` (holds, but no case drawn met its premise)."""
    if v.verdict != "holds":
        return v.verdict
    return f"holds {v.cases}" if v.cases else "no case"


def _grid(found: Sequence[Verdict], law: str) -> list[str]:
    """The verdicts of one law: a row per property (with its scope), a column per kind of CORs."""
    from verify.properties.catalogue import property_named

    rows = [v for v in found if v.law == law]
    if not rows:
        return []
    names = list(dict.fromkeys(v.property for v in rows))
    cors = [r for r in CORS if any(v.rule == r for v in rows)]
    lines = ["| property (the cell: general / cradle / corner) | checked | " + " | ".join(f"{r} CORs" for r in cors)
             + " |", "|---|---|" + "---|" * len(cors)]  # fmt: skip
    for name in names:
        cells = [_cell({v.family: v for v in rows if v.property == name and v.rule == r}) for r in cors]
        lines.append(f"| {name} | {property_named(name).scope} | " + " | ".join(cells) + " |")
    return lines


def _summary(found: Sequence[Verdict]) -> list[str]:
    """The page's opening: the count of each verdict by law, and the properties refuted under it."""
    from verify.properties.verdicts import verdict_counts
    from verify.views.pages import wrapped

    out = []
    for law, words in LAWS.items():
        rows = [v for v in found if v.law == law]
        if not rows:
            continue
        counts = ", ".join(f"{n} {k}" for k, n in verdict_counts(rows).items())
        refuted = list(dict.fromkeys(v.property for v in rows if v.verdict == "refuted"))
        failing = "; ".join(
            f"{p} ({sum(v.property == p and v.verdict == 'refuted' for v in rows)} of "
            f"{sum(v.property == p for v in rows)} rows)"
            for p in refuted
        )
        text = f"Under {words}: {counts} (of {len(rows)} rows)" + (f". Refuted: {failing}." if refuted else ".")
        out += wrapped(text, bullet="- ")
    return out


def _parts(note: str) -> tuple[str, str, str]:
    """A refuted row's note as (what the counterexample does, where the property fails, the command to rerun);
    what the note says after the command (a census row's census) goes with what the counterexample does.

    >>> _parts("impulse 1 raises K. Where it fails: beta; reproduce with: verify solve CASE.json; a census: 3")
    ('impulse 1 raises K; a census: 3', 'beta', 'verify solve CASE.json')
    """
    note, _, rerun = note.partition(_RERUN)
    command, _, more = rerun.partition("; ")
    what, _, why = note.partition(_WHY)
    return what + (f"; {more}" if more else ""), why, command


def _refutations(found: Sequence[Verdict]) -> list[str]:
    """Every refuted row, grouped by property; why the property fails is said once for the rows that share it."""
    from verify.views.pages import wrapped

    lines: list[str] = []
    refuted = [v for v in found if v.verdict == "refuted"]
    said: dict[str, str] = {}  # each explanation once: a later property that shares it points to the first
    for name in dict.fromkeys(v.property for v in refuted):
        lines += ["", f"### {name}", ""]
        rows = [v for v in refuted if v.property == name]
        for why in dict.fromkeys(_parts(v.note)[1] for v in rows):
            if why in said and said[why] != name:
                lines += [*wrapped(f'Where it fails: as for "{said[why]}" above.'), ""]
            elif why:
                said.setdefault(why, name)
                lines += [*wrapped("Where it fails: " + why + "."), ""]
            same: dict[str, list[Verdict]] = {}  # rows with one counterexample are listed together
            for v in rows:
                if _parts(v.note)[1] == why:
                    same.setdefault(_parts(v.note)[0], []).append(v)
            for what, group in same.items():
                which = "; ".join(
                    (f"{v.rule} CORs" if v.law == "rule" else f"{LAWS[v.law]}, {v.rule} CORs") + f", {v.family}"
                    for v in group
                )
                counts = list(dict.fromkeys(v.cases for v in group))
                each = len(counts) == 1 and len(group) > 1
                cases = f"{counts[0]} cases each" if each else " and ".join(map(str, counts)) + " cases"
                rerun = "; ".join(f"`{c}`" for c in dict.fromkeys(_parts(v.note)[2] for v in group) if c)
                text = f"**{which}** (after {cases}): {what}." + (f" Rerun: {rerun}." if rerun else "")
                lines += wrapped(text, bullet="- ")
            lines.append("")
    return lines


def properties_page(profile: str, found: Sequence[Verdict]) -> str:
    """The page of the property verdicts (its record, with every counterexample as a case file, is
    ``properties.json`` beside it)."""
    from verify.properties.text import census_lines
    from verify.views.pages import block, wrapped

    lines = ["# Properties of the rule and of the simultaneous law", "", "**What was found.**", ""]
    lines += [*_summary(found), ""]
    lines += wrapped(
        "Each property the paper states in Sects. 2-3 (and a few a reader expects of an impact law) is checked on "
        "exact rational cases drawn at random: general systems, cradles and corners, under four kinds of CORs, for "
        "the paper's rule and for the two laws engines run. A verdict is **proved** (an exact symbolic proof covers "
        "every case), **holds N** (no counterexample among the N cases drawn), or **refuted** (an exact, shrunk "
        f"counterexample below). Profile `{profile}`: `verify properties --profile {profile}`. A property is checked "
        "either per impulse or over the run; the column says which."
    )
    for law, words in LAWS.items():
        table = _grid(found, law)
        if table:
            lines += ["", f"## {words[0].upper()}{words[1:]}", "", *table]
    census = census_lines(found)
    if census:
        lines += ["", "## How the runs end (termination census)", ""]
        lines += wrapped(
            "Every case drawn for a termination row of the paper's rule, by how its run ends. A row is refuted by "
            "the first run its search proves never to exit; the census is a separate sample of the same row, so a "
            "refuted row may show none there."
        )
        lines += ["", block("\n".join(census[3:])).rstrip("\n")]
    lines += ["", "## The refutations", ""]
    lines += wrapped(
        "Each refutation's counterexample is an exact case file in the record `properties.json` beside this page "
        f"(`verify properties --profile {profile} --counterexamples DIR` writes them as files); rerun one with "
        "`verify solve CASE.json --rule RULE` (add `--law simultaneous` or `--law sequential` for those laws)."
    )
    lines += _refutations(found)
    return "\n".join(lines).rstrip("\n") + "\n"
