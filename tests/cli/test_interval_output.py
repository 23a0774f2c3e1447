"""Interval results on the command line: exact zeros decided, and only certified digits printed."""

from __future__ import annotations

import json
from fractions import Fraction

import pytest

from verify.cli import main
from verify.numbers.format import format_decimal
from verify.numbers.parse import parse_number

CORNER_COR_0 = ["corner", "--slope", "1/2", "--phi", "0", "--eps1", "0", "--eps2", "1", "--v0", "2"]
CRADLE = ["cradle", "--eps", "0.9"]


def _record(capsys: pytest.CaptureFixture[str], args: list[str]) -> dict:
    assert main([*args, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def _significant_digits(text: str) -> int:
    mantissa = text.lstrip("-").lower().split("e")[0]
    return len(mantissa.replace(".", "").lstrip("0"))


def _certified(text: str, exact: Fraction) -> bool:
    """Whether ``text`` is ``exact`` correctly rounded to the digits that ``text`` shows."""
    if Fraction(text) == exact:
        return True
    return exact != 0 and Fraction(text) == Fraction(format_decimal(exact, _significant_digits(text)))


def test_the_corner_with_a_cor_of_0_finishes_on_intervals_as_exactly(capsys):
    # issue 14: "a sign stayed undecided at the precision limit", exit code 2
    exact = _record(capsys, CORNER_COR_0)
    interval = _record(capsys, [*CORNER_COR_0, "--backend", "interval"])
    assert (interval["impact_sets"], interval["stop"], interval["zones"]) == (
        exact["impact_sets"],
        exact["stop"],
        exact["zones"],
    )
    assert interval["rigorous"] and "notes" not in interval  # decided at once, not chased in precision
    for (lo, hi), x in zip(interval["exit_velocity_enclosure"], exact["exit_velocity"], strict=True):
        assert Fraction(lo) <= parse_number(x) <= Fraction(hi)


def test_interval_text_prints_only_certified_digits(capsys):
    exact = [parse_number(x) for x in _record(capsys, CRADLE)["exit_velocity"]]
    assert main([*CRADLE, "--backend", "interval", "--dps", "20"]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("exit velocity ("))
    printed = line.split(": ", 1)[1].split(", ")
    assert len(printed) == len(exact)
    for text, x in zip(printed, exact, strict=True):
        assert _certified(text, x), (text, x)
        assert _significant_digits(text) < 30  # 20-digit intervals cannot certify 30 digits


def test_interval_json_claims_only_certified_digits(capsys):
    exact = _record(capsys, CRADLE)
    interval = _record(capsys, [*CRADLE, "--backend", "interval", "--dps", "20"])
    for field in ("exit_velocity", "exit_velocity_decimal"):
        for text, x in zip(interval[field], exact["exit_velocity"], strict=True):
            assert _certified(text, parse_number(x)), (field, text, x)
    assert _certified(interval["kinetic_energy_out"], parse_number(exact["kinetic_energy_out"]))
    for (lo, hi), x in zip(interval["exit_velocity_enclosure"], exact["exit_velocity"], strict=True):
        assert Fraction(lo) <= parse_number(x) <= Fraction(hi)
