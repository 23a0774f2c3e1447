"""The hard-case generator (verify.oracle.hardcases): stable bytes, exact sides, valid records."""

from __future__ import annotations

import hashlib
import json
import os
import re
import subprocess
import sys
from fractions import Fraction
from functools import cache
from pathlib import Path

import pytest
import sympy as sp

from verify.laws.rule import solve
from verify.numbers.algebraic import RealAlgebraic
from verify.numbers.numeric import certified_sign
from verify.oracle.hardcases import beside, generate, generate_file_text, level_spec
from verify.records.results import Case, case_from_record
from verify.records.schema import validate

ROOT = Path(__file__).resolve().parents[2]


@cache
def text(level: int, seed: int) -> str:
    return generate_file_text(level, seed)


def cases(level: int = 1, seed: int = 0) -> list[dict]:
    return json.loads(text(level, seed))["cases"]


def by_id(records: list[dict]) -> dict[str, dict]:
    return {c["id"]: c for c in records}


def load(record: dict) -> Case:
    return case_from_record({k: v for k, v in record.items() if k != "why"}, record["id"])


def test_the_same_bytes_twice_and_under_another_hash_seed() -> None:
    assert generate_file_text(1, 0) == text(1, 0)
    code = "import sys; from verify.oracle.hardcases import generate_file_text as g; sys.stdout.write(g(1, 0))"
    env = {**os.environ, "PYTHONHASHSEED": "12345"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, env=env, check=True, cwd=ROOT).stdout
    assert hashlib.sha256(out).hexdigest() == hashlib.sha256(text(1, 0).encode()).hexdigest()


def test_level_1_has_both_sides_of_3_minus_2_sqrt_2_within_1e_12() -> None:
    b = 3 - 2 * sp.sqrt(2)
    sides = set()
    for c in cases():
        if c["normals"] != [["-1", "1", "0"], ["0", "-1", "1"]] or c["mass_matrix"][0] != ["1", "0", "0"]:
            continue
        if "sqrt" in c["restitution"][0]:
            continue
        eps = Fraction(c["restitution"][0])
        d = sp.Rational(eps.numerator, eps.denominator) - b
        if certified_sign(d - sp.Rational(1, 10**12)) <= 0 and certified_sign(d + sp.Rational(1, 10**12)) >= 0:
            sides.add(certified_sign(d))
    assert sides == {-1, 1}
    found = by_id(cases())
    below, above = (load(found[f"cradle3-eps-3-2sqrt2-{s}-1e-12"]) for s in ("minus", "plus"))
    assert solve(below.system, below.velocity_source, trace=False).iterations == 4
    assert solve(above.system, above.velocity_source, trace=False).iterations == 3


def test_beside_is_within_the_distance_on_the_right_side() -> None:
    b = RealAlgebraic.from_number(7 - 4 * sp.sqrt(3))
    for k in (6, 30):
        for side in (-1, 1):
            eps = beside(b, k, side)
            exact = sp.Rational(eps.numerator, eps.denominator) - (7 - 4 * sp.sqrt(3))
            assert certified_sign(exact) == side
            assert certified_sign(sp.Rational(1, 10**k) - side * exact) >= 0
    assert beside(RealAlgebraic.rational(Fraction(1)), 12, -1) == 1 - Fraction(1, 10**12)


def test_grazing_cases_have_a_rate_exactly_zero() -> None:
    found = by_id(cases())
    for case_id, index in (
        ("grazing-cradle3-cors-1", 1),
        ("corner-slope-1/2-along-wall-1", 0),
        ("corner-pi6-along-wall-1", 0),  # in Q(sqrt(3))
        ("wedge-e-1/4-slope-1/3-along-wall", 0),
    ):
        c = load(found[case_id])
        rates = c.system.rates(c.velocity)
        assert c.system.backend.to_exact(rates[index]) == "0", case_id
        assert c.system.backend.sign(rates[index]) == 0


def test_some_level_1_cases_are_proved_never_to_exit() -> None:
    found = by_id(cases())
    for case_id in ("cradle3-eps-7-4sqrt3-minus-1e-12", "wedge-e-1/4-slope-1/3-along-wall"):
        c = load(found[case_id])
        r = solve(c.system, c.velocity_source, trace=False)
        assert r.stop == "non_terminating" and r.certificate is not None


def test_every_case_loads_and_says_why() -> None:
    records = cases()
    assert 20 <= len(records) <= 50
    assert len({c["id"] for c in records}) == len(records)
    for c in records:
        assert c["why"] and "\n" not in c["why"] and len(c["why"]) < 400
        load(c)
    validate({"cases": [{k: v for k, v in c.items() if k != "why"} for c in records]}, "case")


def test_level_1_solves_as_its_reasons_say() -> None:
    """Every level-1 case ends (exit or proved never to exit); counts named in ``why`` are the exact ones."""
    for c in cases():
        case = load(c)
        r = solve(case.system, case.velocity_source, max_iterations=case.max_iterations, trace=False)
        assert r.stop in ("exit", "non_terminating"), c["id"]
        claimed = re.search(r": (\d+) impulses", c["why"])
        if claimed:
            assert r.stop == "exit" and r.iterations == int(claimed.group(1)), c["id"]
        if "never exits" in c["why"].rsplit(";", 1)[-1]:
            assert r.stop == "non_terminating", c["id"]


def test_the_seed_drives_the_random_cases_only() -> None:
    a, b = by_id(cases(1, 0)), by_id(cases(1, 1))
    assert a.keys() == b.keys()
    random_ids = [i for i in a if i.startswith(("general-", "illcond-"))]
    assert random_ids
    assert all(a[i] != b[i] for i in random_ids)
    assert all(a[i] == b[i] for i in a if i not in random_ids)


def test_level_2_contains_level_1_and_more() -> None:
    one, two = by_id(cases(1)), by_id(cases(2))
    assert len(two) > 2 * len(one)
    assert all(two.get(i) == c for i, c in one.items())


def test_levels_are_checked() -> None:
    assert level_spec(3).distances[-1] == 30
    with pytest.raises(ValueError, match="level"):
        generate(4, 0)
