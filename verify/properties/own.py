"""The property suite on your own family of systems: a Hypothesis strategy, or a case file.

The built-in rows draw general systems, cradles and corners (:mod:`verify.properties.strategies`).
:func:`family_verdicts` runs the same properties (those stated for general systems) on the cases
of your own strategy, which draws ``(system, velocity)`` pairs (a :class:`~verify.dynamics.system.System`
of rational numbers, e.g. from :meth:`~verify.dynamics.system.System.from_functions`, and its entrance
velocity), or on the cases of a case file (``docs/records.md``). The verdicts are those of
``verify properties``: proved, holds on N cases, or refuted with a shrunk, exact counterexample (a
case record that ``verify solve`` reproduces) and, for termination, the census of how the runs end.

The rule column: ``general`` runs your systems with their own CORs, ``ideal`` with every COR 1,
``symmetric`` with every COR equal to the first contact's.

>>> from hypothesis import strategies as st
>>> from verify.dynamics.system import System, default_names, source_numbers
>>> def slide(e):  # a block hitting a wall, COR e, from velocity -1
...     return System([[1]], [[1]], [e]), ["-1"]
>>> found = family_verdicts(st.sampled_from(["0", "1/2", "1"]).map(slide), "block",
...                         properties=["the exit velocity is outgoing"], examples=10)
>>> [(v.family, v.rule, v.verdict) for v in found]
[('block', 'general', 'holds')]
"""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction
from typing import Any

from verify.dynamics.system import System, default_names, source_numbers
from verify.errors import InvalidInput
from verify.numbers.parse import to_number
from verify.properties.catalogue import PROPERTIES, property_named
from verify.properties.strategies import MAX_ITERATIONS, Drawn
from verify.properties.verdicts import LAW_RULES, Verdict, search
from verify.records.results import case_record

#: the rules an own family can be run under (the asymmetric rule is stated for two constraints only)
OWN_RULES = ("general", "ideal", "symmetric")


def drawn_case(name: str, rule: str, system: System, velocity: Sequence[Any]) -> Drawn:
    """A system and its entrance velocity as a drawn case of the family ``name`` under ``rule`` (its
    CORs replaced as the rule says: see the module).

    >>> drawn_case("block", "ideal", System([[1]], [[1]], ["1/2"]), ["-1"]).record["restitution"]
    ['1']
    """
    if rule not in OWN_RULES:
        raise InvalidInput(f"rule {rule!r}: an own family runs under {', '.join(OWN_RULES)}")
    src = system.source
    if isinstance(velocity, str) or len(velocity) != system.n:
        raise InvalidInput(f"{name}: the velocity needs {system.n} numbers")
    v = [to_number(x, where=f"velocity[{i}]") for i, x in enumerate(velocity)]
    if not all(isinstance(x, Fraction) for x in [*source_numbers(system), *v]):
        raise InvalidInput(f"{name}: the property suite draws systems of rational numbers")
    cors = list(src["restitution"])
    if rule == "ideal":
        cors = [Fraction(1)] * system.r
    elif rule == "symmetric":
        cors = [cors[0]] * system.r
    named = None if system.names == default_names(system.r) else system.names
    record = case_record(f"{name}-{rule}", src["mass_matrix"], src["normals"], cors, v,
                         time_terms=src["time_terms"], max_iterations=MAX_ITERATIONS, names=named)  # fmt: skip
    return Drawn(name, rule, record)


def _strategy(cases: Any, name: str, rule: str) -> Any:
    from hypothesis import strategies as st

    if isinstance(cases, str):
        from verify.records.results import load_cases

        loaded = load_cases(cases)
        if not loaded:
            raise InvalidInput(f"{cases}: no case")
        drawn = [drawn_case(name, rule, c.system, c.velocity_source) for c in loaded]
        return st.sampled_from(drawn)
    return cases.map(lambda pair: drawn_case(name, rule, pair[0], pair[1]))


def family_verdicts(
    cases: Any,
    name: str = "own",
    *,
    properties: Sequence[str] | None = None,
    rules: Sequence[str] = ("general",),
    laws: Sequence[str] = ("rule",),
    examples: int = 100,
) -> list[Verdict]:
    """The property suite's verdicts on your family: ``cases`` is a Hypothesis strategy of
    ``(system, velocity)`` pairs, or the path of a case file; ``name`` names the family in the verdicts
    and in the counterexamples' ids. ``properties`` default to every property stated for general
    systems; each is a property's name, the start of one name, or a part found in one name only
    (:func:`~verify.properties.catalogue.property_named`: ``"termination"`` is the rule's
    termination); ``examples`` is the number of cases a row searches (the search is derandomised: the
    same cases, verdicts and counterexamples on every run). See the module's example.

    >>> from hypothesis import strategies as st
    >>> wall = st.just((System([[1]], [[1]], ["1/2"]), ["-1"]))  # a block hitting a wall
    >>> [v.property for v in family_verdicts(wall, "block", properties=["outgoing"], examples=2)]
    ['the exit velocity is outgoing']
    """
    chosen = [property_named(p) for p in properties] if properties else list(PROPERTIES)
    out = []
    for prop in chosen:
        if "general" not in prop.families:
            continue
        for rule in rules:
            strategy = _strategy(cases, name, rule)
            if rule not in prop.rules:
                continue
            for law in laws:
                if law in prop.laws and rule in LAW_RULES[law]:
                    out.append(search(prop, name, rule, examples, law=law, strategy=strategy))
    return out
