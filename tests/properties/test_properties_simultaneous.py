"""The property suite on the simultaneous law (:mod:`verify.laws.simultaneous`).

- Its rows of the verdict table (``law`` ``simultaneous``, computed once per session with the
  rule's): the properties that are theorems of the law are never refuted; the energy rows are
  refuted or hold as the energy identity says.
- An independent oracle: the complementarity problem solved by enumerating every active set
  (plain Fractions, :mod:`verify.properties.formulas`), against the engine's Murty
  pivoting, with the counterexamples found kept as ``@example`` regressions.
- Each of the law's properties catches a deliberately broken law (a mutant of the engine).
- The command line: ``--law``, the law in the text table, and a refutation that ``verify solve
  --law simultaneous`` reproduces.
"""

from __future__ import annotations

import itertools
import json
from fractions import Fraction

import pytest
from hypothesis import example, given

import verify.laws.simultaneous as law_module
from verify.cli import main
from verify.dynamics.system import System
from verify.properties import formulas
from verify.properties.catalogue import PROPERTIES, energy_does_not_increase, property_named
from verify.properties.proofs import prove, simultaneous_energy_terms
from verify.properties.strategies import Drawn, cases
from verify.properties.verdicts import Runner, search

LAW = "simultaneous"
#: the law's properties that are theorems of the law (or of its implementation's contract)
THEOREMS = {p.name for p in PROPERTIES if LAW in p.laws} - {
    "kinetic energy does not increase",
    "backends agree (exact, interval, mp, float)",  # see test_backends_agree_on_the_law
}


@pytest.fixture(scope="module")
def table(property_verdicts):
    return [v for v in property_verdicts if v.law == LAW]


def test_the_law_has_rows_beside_the_rule(property_verdicts, table) -> None:
    """Every row of the law sits right after the rule's row of the same property, rule and family
    (when the rule has one); the law's rows use the general, symmetric and ideal CORs."""
    assert {v.rule for v in table} == {"ideal", "symmetric", "general"}
    assert {v.property for v in table} == {p.name for p in PROPERTIES if LAW in p.laws}
    for k, v in enumerate(property_verdicts):
        if v.law == LAW and "rule" in property_named(v.property).laws:
            before = property_verdicts[k - 1]
            assert (before.law, before.property, before.rule, before.family) == ("rule", v.property, v.rule, v.family)


def test_theorems_of_the_law_are_never_refuted(table) -> None:
    refuted = [
        (v.property, v.rule, v.family, v.note) for v in table if v.verdict == "refuted" and v.property in THEOREMS
    ]
    assert refuted == []
    assert all(v.verdict == "holds" for v in table if v.property in THEOREMS)  # no SymPy proof is claimed for them


def test_backends_agree_on_the_law(table) -> None:
    rows = [v for v in table if v.property == "backends agree (exact, interval, mp, float)"]
    assert len(rows) == 9
    assert all(v.verdict == "holds" for v in rows), [(v.rule, v.family, v.note) for v in rows if v.verdict != "holds"]


def test_energy_rows_follow_the_identity(table) -> None:
    """Every refuted energy row is explained by Delta K = 1/2 sum lambda_i (w_i + w'_i) (the sums
    add up to the change), with a constraint that is not incoming taking an impulse."""
    rows = [v for v in table if v.property == "kinetic energy does not increase"]
    assert len(rows) == 9
    for v in rows:
        if v.verdict == "refuted":
            assert "predicts" in v.note and "Where it fails: Delta K = 1/2 sum lambda_i" in v.note, v.note
            assert ", not " not in v.note.split(". Where it fails")[0], v.note
            d = Drawn(v.family, v.rule, v.counterexample)
            assert _enumerated(d)["rises"], v.counterexample
        else:
            assert v.verdict == "holds", v


def test_the_energy_identity_is_proved_for_every_cor_variant() -> None:
    for rule in ("ideal", "symmetric", "general"):
        statement = prove("simultaneous_energy", rule)
        assert statement is not None and "checked by SymPy" in statement
    assert "never loses energy" in prove("simultaneous_energy", "ideal")


# -- an independent oracle: the complementarity problem by enumeration ---------------------------


def _rest_frame_energy(g: list, a: list, t: list, v: list) -> Fraction:
    """``1/2 Phi(v - H, v - H)`` with H the velocity of the constraints (``a_i H = -t_i``, H in span g^-1 a_i)."""
    U = [formulas.solve_linear(g, row) for row in a]
    G = [[sum((x * y for x, y in zip(row, u)), Fraction(0)) for u in U] for row in a]
    c = formulas.solve_linear(G, [-x for x in t])
    rel = [x - sum((ck * u[i] for ck, u in zip(c, U)), Fraction(0)) for i, x in enumerate(v)]
    return formulas.phi(g, rel, rel) / 2


def _enumerated(d: Drawn) -> dict:
    """The simultaneous law by brute force: every active set S, ``G_SS lambda_S = -q_S``, kept
    when ``lambda >= 0`` and ``G lambda + q >= 0``; the solution must be unique (G is positive definite)."""
    g, a, t, e = (d.values(k) for k in ("mass_matrix", "normals", "time_terms", "restitution"))
    if d.rule == "ideal":
        e = [Fraction(1)] * len(e)
    v, r = d.values("velocity"), len(a)
    U = [formulas.solve_linear(g, row) for row in a]
    G = [[sum((x * y for x, y in zip(row, u)), Fraction(0)) for u in U] for row in a]
    w = [formulas.rate(a[i], t[i], v) for i in range(r)]
    q = [(1 + e[i]) * w[i] if w[i] < 0 else w[i] for i in range(r)]
    solutions = set()
    for size in range(r + 1):
        for S in itertools.combinations(range(r), size):
            lam = [Fraction(0)] * r
            if S:
                sol = formulas.solve_linear([[G[i][k] for k in S] for i in S], [-q[i] for i in S])
                for i, x in zip(S, sol):
                    lam[i] = x
            if all(x >= 0 for x in lam) and all(q[i] + sum(G[i][k] * lam[k] for k in range(r)) >= 0 for i in range(r)):
                solutions.add(tuple(lam))
    assert len(solutions) == 1, solutions
    (lam,) = solutions
    out = [x + sum((lam[i] * U[i][k] for i in range(r)), Fraction(0)) for k, x in enumerate(v)]
    before, after = _rest_frame_energy(g, a, t, v), _rest_frame_energy(g, a, t, out)
    return {"lambda": list(lam), "exit": out, "rises": after > before, "change": after - before, "rates": w}


def _case(family: str, rule: str, system: tuple, v: list) -> Drawn:
    """A case record of the system ``(g, normals, CORs)`` (fixed constraints) and the velocity v."""
    g, a, e = system
    record = {"id": f"{family}-{rule}-simultaneous", "max_iterations": 200, "mass_matrix": g, "normals": a,
              "restitution": e, "time_terms": ["0"] * len(a), "velocity": v}  # fmt: skip
    return Drawn(family, rule, record)


_I3 = [["1", "0", "0"], ["0", "1", "0"], ["0", "0", "1"]]
_I4 = [["1", "0", "0", "0"], ["0", "1", "0", "0"], ["0", "0", "1", "0"], ["0", "0", "0", "1"]]
_I5 = [["1" if i == j else "0" for j in range(5)] for i in range(5)]
_CRADLE3 = [["-1", "1", "0"], ["0", "-1", "1"]]
_CRADLE4 = [["-1", "1", "0", "0"], ["0", "-1", "1", "0"], ["0", "0", "-1", "1"]]
_CRADLE5 = [
    ["-1", "1", "0", "0", "0"],
    ["0", "-1", "1", "0", "0"],
    ["0", "0", "-1", "1", "0"],
    ["0", "0", "0", "-1", "1"],
]

#: kinetic energy gained by the simultaneous law: the ci profile's shrunk counterexamples, then
#: those of longer searches (3000 cases a row: the corner; equal CORs below 1; two constraints
#: with unequal CORs below 1)
FOUND_ENERGY_GAINS = [
    _case("general", "ideal", ([["1", "0", "0", "0", "0"], ["0", "1", "1", "0", "0"], ["0", "1", "2", "0", "0"],
          ["0", "0", "0", "1", "0"], ["0", "0", "0", "0", "1"]], _I5[:4], ["1"] * 4), ["0", "1", "-1", "0", "0"]),
    _case("cradle", "ideal", (_I5, _CRADLE5, ["1"] * 4), ["3/4", "-1/4", "-1/4", "-1/4", "0"]),
    _case("cradle", "general", (_I4, _CRADLE4, ["1", "0", "0"]), ["2/3", "-1/3", "-1/3", "0"]),
    _case("corner", "ideal", (_I3, [["-1/2", "1", "0"], ["-1/2", "-1", "0"]], ["1", "1"]), ["2/5", "-4/5", "0"]),
    _case("corner", "general", (_I3, [["-1/3", "1", "0"], ["-1/3", "-1", "0"]], ["2/3", "0"]), ["3/10", "-9/10", "0"]),
    _case("cradle", "symmetric", ([["1", "0", "0", "0"], ["0", "1", "0", "0"], ["0", "0", "1", "0"],
          ["0", "0", "0", "2"]], _CRADLE4, ["4/5"] * 3), ["1/2", "-1/2", "0", "0"]),
    _case("general", "symmetric", ([["1", "0", "1"], ["0", "1", "1"], ["1", "1", "3"]],
          [["1", "1", "0"], ["0", "-1", "1"]], ["1/2", "1/2"]), ["-1/2", "-1/2", "1/3"]),
    _case("cradle", "general", ([["1", "0", "0"], ["0", "1", "0"], ["0", "0", "2"]], _CRADLE3, ["0", "5/6"]),
          ["2", "8/3", "5/3"]),
]  # fmt: skip


def _compare_with_enumeration(d: Drawn) -> None:
    runner = Runner(LAW)
    r = runner(d.record, d.rule)
    expected = _enumerated(d)
    K = r.backend
    assert [Fraction(K.to_number(x)) for x in r.impulses] == expected["lambda"]
    assert [Fraction(K.to_number(x)) for x in r.exit_velocity] == expected["exit"]
    change = Fraction(K.to_number(r.kinetic_energy_out - r.kinetic_energy_in))
    assert change == expected["change"]
    assert (energy_does_not_increase(runner, d, None) is not None) == expected["rises"]
    # the identity Delta K = 1/2 sum lambda_i (w_i + w'_i), evaluated without the engine
    gain, loss = simultaneous_energy_terms((d.values("normals"), d.values("time_terms")), d.values("velocity"),
                                           expected["exit"], expected["lambda"])  # fmt: skip
    assert gain + loss == expected["change"] and gain >= 0 and loss <= 0
    assert (gain > 0) == any(x > 0 and w > 0 for x, w in zip(expected["lambda"], expected["rates"]))


@given(cases("cradle", "general"))
@example(FOUND_ENERGY_GAINS[0])
@example(FOUND_ENERGY_GAINS[1])
@example(FOUND_ENERGY_GAINS[2])
@example(FOUND_ENERGY_GAINS[3])
@example(FOUND_ENERGY_GAINS[4])
@example(FOUND_ENERGY_GAINS[5])
@example(FOUND_ENERGY_GAINS[6])
@example(FOUND_ENERGY_GAINS[7])
def test_the_law_agrees_with_enumeration_on_cradles(d: Drawn) -> None:
    _compare_with_enumeration(d)


@given(cases("general", "general"))
def test_the_law_agrees_with_enumeration_on_general_systems(d: Drawn) -> None:
    _compare_with_enumeration(d)


def test_the_found_energy_gains_still_gain() -> None:
    for d in FOUND_ENERGY_GAINS:
        assert _enumerated(d)["rises"], d.record
        assert "predicts" in energy_does_not_increase(Runner(LAW), d, None)
    equal_below_one = [d for d in FOUND_ENERGY_GAINS if len(set(d.values("restitution"))) == 1]
    assert any(d.values("restitution")[0] < 1 for d in equal_below_one)  # equal CORs below 1 gain too


# -- tests of the tests: each property catches a broken law ---------------------------------------

_original_lcp = law_module.lcp_vector
_original_active = law_module._on_active_set


def _reversed_cors(system, rates, hits=None):
    return _original_lcp(system.with_restitution(list(system.source["restitution"])[::-1]), rates, hits)


def _first_cor_for_all(system, rates, hits=None):
    return _original_lcp(system.with_restitution([system.source["restitution"][0]] * system.r), rates, hits)


def _restitution_on_every_constraint(system, rates, hits=None):  # the other reading: e_i w_i when separating too
    return _original_lcp(system, rates, (True,) * system.r)


def _over_restitution(system, rates, hits=None):
    K = system.backend
    return tuple(x * K.convert(Fraction(3, 2)) for x in _original_lcp(system, rates, hits))


def _quadratic_in_rates(system, rates, hits=None):
    K = system.backend
    q = _original_lcp(system, rates, hits)
    return tuple(x * (K.zero - w) if K.sign(w) < 0 else x * w for x, w in zip(q, rates))


def _times_gram_diagonal(system, rates, hits=None):
    return tuple(x * d for x, d in zip(_original_lcp(system, rates, hits), system.gram_diag))


def _ignores_time_terms(system, rates, hits=None):
    return _original_lcp(system, [x - t for x, t in zip(rates, system.time_terms)], hits)


def _half_impulses(system, v, hits, S):
    K = system.backend
    return tuple(x * K.convert(Fraction(1, 2)) for x in _original_active(system, v, hits, S))


def _inexact_off_by_a_little(system, v, hits, S):
    lam = _original_active(system, v, hits, S)
    K = system.backend
    return lam if K.is_exact else tuple(x * K.convert(Fraction(10**12 + 1, 10**12)) for x in lam)


def _euclidean_direction(self, coefficients):  # sum c_j dF_j^T instead of sum c_j g^-1 dF_j^T
    K = self.backend
    return tuple(sum((c * self.normals[j][k] for j, c in coefficients), K.zero) for k in range(self.n))


MUTANTS = {
    "kinetic energy does not increase": ("lcp_vector", _over_restitution, "corner", "ideal"),
    "the exit velocity is outgoing": ("_on_active_set", _half_impulses, "corner", "general"),
    "the simultaneous impulses satisfy restitution and complementarity": (
        "lcp_vector",
        _restitution_on_every_constraint,
        "cradle",
        "general",
    ),
    "a single impact gives eq. (4)": ("lcp_vector", _reversed_cors, "general", "general"),
    "orthogonal constraints give the codimension > 1 rule (Prop. 1)": (
        "lcp_vector",
        _reversed_cors,
        "corner",
        "general",
    ),
    "relabelling the constraints changes nothing": ("lcp_vector", _first_cor_for_all, "corner", "general"),
    "mirror symmetry (corner y -> -y; cradle read backwards)": ("lcp_vector", _first_cor_for_all, "corner", "general"),
    "homogeneity: scaling the velocity by lambda > 0 scales the result": (
        "lcp_vector",
        _quadratic_in_rates,
        "corner",
        "general",
    ),
    "scaling all masses changes nothing": ("lcp_vector", _times_gram_diagonal, "cradle", "general"),
    "covariance under a linear change of coordinates": ("combine_normals", _euclidean_direction, "corner", "general"),
    "frame independence (constraints in uniform motion)": ("lcp_vector", _ignores_time_terms, "corner", "general"),
    "momentum along directions free of constraints is conserved": (
        "combine_normals",
        _euclidean_direction,
        "cradle",
        "general",
    ),
    "backends agree (exact, interval, mp, float)": ("_on_active_set", _inexact_off_by_a_little, "corner", "general"),
    "the laws agree where the rule exits after one impulse on orthogonal constraints": (
        "lcp_vector",
        _reversed_cors,
        "general",
        "general",
    ),
}


def test_every_property_of_the_law_has_a_mutant() -> None:
    assert set(MUTANTS) == {p.name for p in PROPERTIES if LAW in p.laws}


@pytest.mark.parametrize("name", list(MUTANTS))
def test_each_property_catches_a_broken_law(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    attribute, mutant, family, rule = MUTANTS[name]
    monkeypatch.setattr(System if attribute == "combine_normals" else law_module, attribute, mutant)
    verdict = search(property_named(name), family, rule, 100, law=LAW)
    assert verdict.verdict == "refuted", f"{name}: the mutant {mutant.__name__} was not caught ({verdict.note})"
    assert "the engine raised" not in verdict.note, verdict.note  # caught by the property, not by a crash


# -- the command line ---------------------------------------------------------------------------------


def test_cli_law_option_and_text_table(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["properties", "--profile", "dev", "--property", "the exit velocity", "--family", "corner",
                 "--law", LAW, "--workers", "1", "--quiet"])  # fmt: skip
    text = capsys.readouterr().out
    assert code == 0
    assert "rows (property x law x rule x family)" in text
    lines = [line.split() for line in text.splitlines() if line.startswith("  the exit velocity is outgoing")]
    assert [(words[5], words[6], words[7], words[8]) for words in lines] == [
        (LAW, rule, "corner", "holds") for rule in ("ideal", "symmetric", "general")
    ]


def test_cli_list_names_the_laws(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["properties", "--list"]) == 0
    listed = capsys.readouterr().out.splitlines()
    for prop in PROPERTIES:
        (line,) = [x for x in listed if x.startswith(prop.name + "  [")]
        assert ("rule: " in line) == ("rule" in prop.laws), line
        assert ("simultaneous: " in line) == (LAW in prop.laws), line
        if LAW in prop.laws:  # the law's rows use the ideal, symmetric and general CORs
            assert "simultaneous: ideal, symmetric, general;" in line, line


def test_cli_law_refutation_is_reproduced_by_verify_solve(tmp_path, capsys: pytest.CaptureFixture[str]) -> None:
    folder = tmp_path / "found"
    code = main(["properties", "--property", "kinetic energy", "--rule", "ideal", "--family", "cradle",
                 "--law", LAW, "--workers", "1", "--quiet", "--counterexamples", str(folder)])  # fmt: skip
    text = capsys.readouterr().out
    assert code == 1 and "REFUTED: kinetic energy does not increase (simultaneous law, ideal CORs, cradle)" in text
    (path,) = folder.iterdir()
    assert path.name == "cradle-ideal-simultaneous-kinetic-energy-does-not-increase.json"
    assert main(["solve", str(path), "--rule", "ideal", "--law", LAW, "--json"]) == 0
    result = json.loads(capsys.readouterr().out)["results"][0]
    assert result["law"] == LAW and result["stop"] == "exit"
    assert Fraction(result["kinetic_energy_out"]) > Fraction(result["kinetic_energy_in"])
