"""What the rule promises, as checks on one drawn case; and which of it the simultaneous law keeps.

A property is a check ``check(run, drawn, extra)``: ``drawn`` is a case of
:mod:`verify.properties.strategies`, ``extra`` what the property draws besides (a permutation, a
scale, a change of coordinates, a frame velocity), ``run`` runs a case record on the
engine (memoised by :mod:`verify.properties.verdicts`) under the row's law: the paper's
rule, or the simultaneous law of :mod:`verify.laws.simultaneous` (a property says which laws
it is checked for, :attr:`Property.laws`; a check reads the law off the result, ``r.law``).
It returns ``None`` when the property holds on the case, :data:`SKIP` when it does not apply
(say a comparison with a run that the budget stopped), or a sentence saying how it fails.
Outcomes worth counting (stops, branches taken by float) go to ``run.count``.

Every check compares exact values (Fractions) and computes its reference independently
where it can: :mod:`verify.properties.formulas` recomputes impulses from the raw inputs as printed in
the paper. The search and the verdicts are in :mod:`verify.properties.verdicts`, the SymPy proofs in
:mod:`verify.properties.proofs`.

>>> [p.name for p in PROPERTIES][:2]
['kinetic energy does not increase', 'the exit velocity is outgoing']
>>> [p.name for p in PROPERTIES if p.laws == ("simultaneous",)][:1]
['the simultaneous impulses satisfy restitution and complementarity']
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from enum import Enum
from fractions import Fraction
from typing import Any

from hypothesis import strategies as st

from verify.numbers.format import counted
from verify.properties import formulas
from verify.properties.strategies import FAMILIES, RULES, Drawn, small_rationals


class Outcome(Enum):
    """A check's answer that is neither a pass (None) nor a failure (a sentence saying how it fails)."""

    SKIP = "skip"  #: the property does not apply to the case (say a comparison with a run the budget stopped)


SKIP = Outcome.SKIP
#: what a check returns: None (the property holds on the case), :data:`SKIP`, or a sentence (it fails)
Answer = str | Outcome | None
#: the termination property's cap of impulses: long but finite runs exit before it (an ideal-rule case
#: of the thorough census exits after 210 impulses, ``tests/properties/test_properties.py``), and slow transients reach
#: the period whose cone proves them (one of the thorough census is proved never to exit after 1408 impulses,
#: on certified intervals: ``tests/proofs/test_periodic.py``, ``verify.properties.verdicts.CENSUS_DIGITS``)
LONG_RUNS = 4000
DONE = ("exit", "non_terminating", "max_iterations")  #: stops that do not depend on number sizes
#: the stops of a census that leave a run undecided: its cases are listed
#: (:meth:`verify.properties.verdicts.Verdict.undecided_cases`)
UNDECIDED_STOPS = ("max_iterations", "budget")


def q(result: Any, xs: Any) -> list[Fraction]:
    """Exact values of engine numbers (Fractions: every drawn input is rational)."""
    return [Fraction(result.backend.to_number(x)) for x in xs]


def _velocities_before(result: Any) -> list[list[Fraction]]:
    vs = [q(result, result.velocity_in)]
    vs += [q(result, s.velocity) for s in result.steps[:-1]]
    return vs


def _inputs(record: dict[str, Any]) -> tuple[Any, ...]:
    f = Drawn("", "", record).values
    return f("mass_matrix"), f("normals"), f("time_terms"), f("restitution")


def _show(xs: Any) -> str:
    return "(" + ", ".join(str(x) for x in xs) + ")"


# -- energy, admissibility, termination, momentum --------------------------------------------------


def energy_does_not_increase(run: Any, d: Drawn, extra: Any) -> Answer:
    """Per impulse, in the rest frame of the constraints; a failure also says whether the
    exact criterion of :func:`verify.properties.proofs.energy_increase_criterion` predicts it
    (for the simultaneous law: the identity of :func:`simultaneous_energy_rises`)."""
    r = run(d.record, d.rule)
    if r.law in ("simultaneous", "sequential"):  # the sequential law's sweeps as a whole: an engine's step
        return simultaneous_energy_rises(r, d)
    K = r.backend
    before = r.kinetic_energy_in
    for w, step in enumerate(r.steps, 1):
        after = step.kinetic_energy
        if K.sign(after - before) > 0:
            from verify.properties.proofs import energy_increase_criterion

            e = _inputs(d.record)[3]
            v = q(r, r.velocity_in) if w == 1 else q(r, r.steps[w - 2].velocity)
            lhs, rhs = energy_increase_criterion(_inputs(d.record), v, step.impact_set)
            return (
                f"impulse {w} (impact set {list(step.impact_set)}, CORs {_show(e[j] for j in step.impact_set)}) "
                f"raises the kinetic energy from {K.to_exact(before)} to {K.to_exact(after)}; as the criterion "
                f"beta ||sum (1 + e_j) V_j||^2 > 2 sum (1 + e_j) p(F_j)^2 / G_jj predicts: {lhs} > {rhs}"
            )
        before = after
    return None


def _cors(d: Drawn) -> list[Fraction]:
    """The CORs the run uses: the record's, all 1 for the ideal rule."""
    e = _inputs(d.record)[3]
    return [Fraction(1)] * len(e) if d.rule == "ideal" else e


def simultaneous_energy_rises(r: Any, d: Drawn) -> Answer:
    """Whether the simultaneous law's impulse (or the sequential law's accumulated impulses) raises the kinetic
    energy, with the terms of ``Delta K = 1/2 sum lambda_i (w_i + w'_i)``
    (:func:`verify.properties.proofs.simultaneous_energy_terms`, from the raw inputs; it holds for any
    impulse ``sum lambda_i U_i``) that predict it: the constraints not incoming against the incoming ones.

    Three unit balls, every COR 1: ball 1 hits ball 2 while ball 3 moves slowly away; the impulse
    also pushes the separating contact (the run is :func:`verify.laws.rule.solve` with ``law=``):

    >>> from fractions import Fraction
    >>> from verify.properties.strategies import make_drawn
    >>> from verify.properties.verdicts import Runner
    >>> cradle = ([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], [0, 0], [1, 1])
    >>> d = make_drawn("cradle", "ideal", cradle, [1, 0, Fraction(1, 10)])
    >>> print(simultaneous_energy_rises(Runner("simultaneous")(d.record, d.rule), d))  # doctest: +ELLIPSIS
    the impulse on [0, 1] (lambda = (13/10, 3/5), ...) raises the kinetic energy from 101/200 to 107/200; ...
    """
    from verify.properties.proofs import simultaneous_energy_terms

    K = r.backend
    before, after = r.kinetic_energy_in, r.kinetic_energy_out
    if K.sign(after - before) <= 0:
        return None
    _, a, t, _ = _inputs(d.record)
    e = _cors(d)
    v, v_out, lam = d.values("velocity"), q(r, r.exit_velocity), q(r, r.impulses)
    gain, loss = simultaneous_energy_terms((a, t), v, v_out, lam)
    pushed = [i for i, x in enumerate(lam) if x != 0 and formulas.rate(a[i], t[i], v) >= 0]
    rates = [str(formulas.rate(a[i], t[i], v)) for i in pushed]
    change = Fraction(K.to_exact(after)) - Fraction(K.to_exact(before))
    what = (
        f"the impulse on {list(r.impact_sets[0])}"
        if r.law == "simultaneous"
        else f"{r.sequential}, accumulated impulses on {[i for i, x in enumerate(lam) if x]}"
    )
    return (
        f"{what} (lambda = {_show(lam)}, CORs {_show(e)}) raises the "
        f"kinetic energy from {K.to_exact(before)} to {K.to_exact(after)}; as Delta K = 1/2 sum lambda_i (w_i + w'_i) "
        f"predicts: the constraints {pushed} that are not incoming (rates {_show(rates)}) take impulses and add "
        f"{gain}, "
        f"the incoming ones add {loss}, in all {gain + loss}" + ("" if gain + loss == change else f", not {change}")
    )


def exit_is_outgoing(run: Any, d: Drawn, extra: Any) -> Answer:
    """The exit velocity's rates, recomputed from the raw inputs, are all >= 0. For the sequential law the
    velocity after the sweeps is checked whatever the run's stop (it is what an engine's step leaves with);
    for the other laws a run that does not exit does not apply."""
    r = run(d.record, d.rule)
    if r.stop != "exit" and r.law != "sequential":
        return SKIP
    _, a, t, _ = _inputs(d.record)
    v = q(r, r.exit_velocity)
    bad = [i for i in range(len(a)) if formulas.rate(a[i], t[i], v) < 0]
    what = "the exit velocity" if r.stop == "exit" else f"the velocity after {r.sequential}"
    return f"{what} {_show(v)} is incoming for constraints {bad}" if bad else None


def terminates(run: Any, d: Drawn, extra: Any) -> Answer:
    r = run(d.record, d.rule, decide=True)  # a long run past the size budget: decided on certified intervals
    run.count(f"stop {r.stop}")
    if r.stop in UNDECIDED_STOPS:  # the census lists the case
        run.keep(r.stop, d.record)
    if r.backend.name == "interval":
        run.count("decided on certified intervals past the size budget")
    if r.stop == "non_terminating":
        kind = (r.certificate or {}).get("kind", "certificate")
        after = counted(r.iterations, "impulse")
        return f"proved never to exit after {after} ({kind}; verify solve prints the certificate)"
    return None


def momentum_is_conserved(run: Any, d: Drawn, extra: Any) -> Answer:
    r = run(d.record, d.rule)
    g, a, _, _ = _inputs(d.record)
    directions = formulas.kernel(a)
    if not directions:
        return SKIP
    vs = [*_velocities_before(r), q(r, r.exit_velocity)]
    for c in directions:
        p0 = formulas.phi(g, c, vs[0])
        for w, v in enumerate(vs[1:], 1):
            if formulas.phi(g, c, v) != p0:
                return f"the momentum along {_show(c)} changes at impulse {w}: {p0} -> {formulas.phi(g, c, v)}"
    return None


# -- the simultaneous law ----------------------------------------------------------------------------


def solves_complementarity(run: Any, d: Drawn, extra: Any) -> Answer:
    """The simultaneous law's impulses ``lambda`` checked from the raw inputs (:mod:`formulas`): the
    exit velocity is ``v + sum lambda_i g^-1 a_i^T``, and for every constraint ``lambda_i >= 0``,
    ``w'_i + e_i min(w_i, 0) >= 0``, with equality where ``lambda_i > 0`` (w, w' the rates before and
    after); the impact set is where ``lambda_i != 0``.

    >>> from verify.properties.strategies import make_drawn
    >>> from verify.properties.verdicts import Runner
    >>> cradle = ([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], [0, 0], ["1/2", 1])
    >>> solves_complementarity(Runner("simultaneous"), make_drawn("cradle", "general", cradle, [2, 0, 1]), None) is None
    True
    """
    r = run(d.record, d.rule)
    g, a, t, _ = _inputs(d.record)
    e, v, lam = _cors(d), d.values("velocity"), q(r, r.impulses)
    U = [formulas.solve_linear(g, row) for row in a]
    expected = [x + sum((c * u[k] for c, u in zip(lam, U)), Fraction(0)) for k, x in enumerate(v)]
    got = q(r, r.exit_velocity)
    if got != expected:
        return (
            f"the exit velocity {_show(got)} is not v + sum lambda_i g^-1 a_i = {_show(expected)} "
            f"(lambda = {_show(lam)})"
        )
    hit = tuple(i for i, c in enumerate(lam) if c != 0)
    if r.impact_sets != ([hit] if hit else []):
        return f"the impact sets {r.impact_sets} are not where lambda = {_show(lam)} is non-zero"
    for i, c in enumerate(lam):
        w, w_out = formulas.rate(a[i], t[i], v), formulas.rate(a[i], t[i], got)
        floor = -e[i] * min(w, Fraction(0))
        if c < 0 or w_out < floor or (c > 0 and w_out != floor):
            return (
                f"constraint {i} (rate {w}, COR {e[i]}) takes lambda = {c} and leaves with rate {w_out}: "
                f"complementarity asks lambda >= 0, a rate >= {floor}, and = {floor} where lambda > 0"
            )
    return None


def sweeps_reach_the_simultaneous_law(run: Any, d: Drawn, extra: Any) -> Answer:
    """After its sweeps, the sequential law (threshold 0) leaves with the simultaneous law's exit velocity:
    its accumulated impulses then solve the complementarity problem that Gauss-Seidel approaches, whose
    solution is unique. Counted: the sweeps that changed an impulse, when they stopped changing before the last.

    >>> from verify.properties.strategies import make_drawn
    >>> from verify.properties.verdicts import Runner
    >>> cradle = ([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], [0, 0], [1, 1])
    >>> d = make_drawn("cradle", "general", cradle, [1, 0, 0])
    >>> print(sweeps_reach_the_simultaneous_law(Runner("sequential"), d, None))
    sequential leaves with (-87381/262144, 349525/524288, 349525/524288), the simultaneous law with (-1/3, 2/3, 2/3) ...
    """
    r = run(d.record, d.rule)
    by_law = run(d.record, d.rule, law="simultaneous")
    got, expected = q(r, r.exit_velocity), q(by_law, by_law.exit_velocity)
    if r.iterations < r.max_iterations:
        run.count("the sweeps stopped changing")
    if got != expected:
        return (
            f"{r.sequential} leaves with {_show(got)}, the simultaneous law with {_show(expected)} "
            f"(still changing after {r.max_iterations} sweeps)"
        )
    return None


def laws_agree_after_one_orthogonal_impulse(run: Any, d: Drawn, extra: Any) -> Answer:
    """Where the rule exits after one impulse on Phi-orthogonal constraints (a single impact
    included), that impulse ``-sum (1 + e_j) V_j`` solves the simultaneous law's complementarity
    problem, whose solution is unique: the two laws give the same exit velocity.

    >>> from verify.properties.strategies import make_drawn
    >>> from verify.properties.verdicts import Runner
    >>> cradle = ([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], [0, 0], ["1/2", 1])
    >>> run, d = Runner("simultaneous"), make_drawn("cradle", "general", cradle, [1, 0, 1])
    >>> laws_agree_after_one_orthogonal_impulse(run, d, None), run.counts
    (None, Counter({'single impact': 1}))
    """
    by_rule = run(d.record, d.rule, law="rule")
    if by_rule.stop != "exit" or by_rule.iterations != 1:
        return SKIP
    (J,) = by_rule.impact_sets
    K, G = by_rule.backend, by_rule.system.gram
    if any(K.sign(G[j][k]) != 0 for j in J for k in J if j != k):
        return SKIP
    run.count("single impact" if len(J) == 1 else "orthogonal impact set")
    r = run(d.record, d.rule)
    if r.impact_sets != by_rule.impact_sets:
        return f"the rule's impact set {list(J)} becomes {r.impact_sets} under the simultaneous law"
    va, vb = q(by_rule, by_rule.exit_velocity), q(r, r.exit_velocity)
    if va != vb:
        return f"the rule exits with {_show(va)} after one impulse on {list(J)}, the simultaneous law with {_show(vb)}"
    return None


# -- the printed formulas -----------------------------------------------------------------------------


def _compare_with_printed(run: Any, d: Drawn, pick: Callable[[tuple[Any, ...], list[Any]], str | None]) -> Answer:
    """Compare every impulse of the run with eq. ``pick(J, eps)`` (None: not compared)."""
    r = run(d.record, d.rule)
    g, a, t, e = _inputs(d.record)
    if d.rule == "ideal":
        e = [Fraction(1)] * len(e)
    compared = False
    for w, (v, step) in enumerate(zip(_velocities_before(r), r.steps), 1):
        eq = pick(step.impact_set, e)
        if eq is None:
            continue
        compared = True
        expected = formulas.printed_impulse(eq, (g, a, t, e), v, step.impact_set)
        got = q(r, step.impulse)
        if got != expected:
            return (
                f"impulse {w} (impact set {list(step.impact_set)}) is {_show(got)}, eq. ({eq}) gives {_show(expected)}"
            )
    return None if compared else SKIP


def follows_eq8(run: Any, d: Drawn, extra: Any) -> Answer:
    return _compare_with_printed(run, d, lambda J, e: "8")


def single_impact_is_eq4(run: Any, d: Drawn, extra: Any) -> Answer:
    return _compare_with_printed(run, d, lambda J, e: "4" if len(J) == 1 else None)


def ideal_is_eq5(run: Any, d: Drawn, extra: Any) -> Answer:
    return _compare_with_printed(run, d, lambda J, e: "5" if len(J) == 2 else "4" if len(J) == 1 else "8")


def symmetric_is_eq6(run: Any, d: Drawn, extra: Any) -> Answer:
    return _compare_with_printed(run, d, lambda J, e: "6" if len(J) == 2 else "4" if len(J) == 1 else "8")


def asymmetric_is_eq7(run: Any, d: Drawn, extra: Any) -> Answer:
    return _compare_with_printed(run, d, lambda J, e: "7" if len(J) == 2 else "4" if len(J) == 1 else None)


def beta_is_one_for_one_constraint(run: Any, d: Drawn, extra: Any) -> Answer:
    """beta of the engine for J = {j}, and for {j, k} when V_k = 0 (Prop. 1 i, Sect. 3.2)."""
    from verify.dynamics.rates import beta_from_rates

    r = run(d.record, d.rule)
    s, K = r.system, r.backend
    for w, step in enumerate(r.steps, 1):
        zero = [k for k, b in enumerate(step.rates) if K.sign(b) == 0]
        for j in step.impact_set:
            for J in [(j,)] + [tuple(sorted((j, k))) for k in zero]:
                beta = Fraction(K.to_number(beta_from_rates(s, step.rates, J)))
                if beta != 1:
                    return f"before impulse {w}, beta for J = {list(J)} is {beta}, not 1"
    return None


def orthogonal_is_codimension_rule(run: Any, d: Drawn, extra: Any) -> Answer:
    """Impulses on Phi-orthogonal impact sets: -sum (1 + e_j) V_j; -(1 + e) V_J for equal CORs."""
    r = run(d.record, d.rule)
    g, a, t, e = _inputs(d.record)
    if d.rule == "ideal":
        e = [Fraction(1)] * len(e)
    K = r.backend
    compared = False
    for w, (v, step) in enumerate(zip(_velocities_before(r), r.steps), 1):
        J = step.impact_set
        if len(J) < 2 or any(K.sign(r.system.gram[j][k]) != 0 for j in J for k in J if j != k):
            continue
        compared = True
        got = q(r, step.impulse)
        parts = [formulas.orthogonal_velocity(g, a[j], t[j], v) for j in J]
        expected = [-sum(((1 + e[j]) * p[i] for j, p in zip(J, parts)), Fraction(0)) for i in range(len(v))]
        if got != expected:
            return (
                f"impulse {w} on the orthogonal set {list(J)} is {_show(got)}, "
                f"not -sum (1 + e_j) V_j = {_show(expected)}"
            )
        if len({e[j] for j in J}) == 1:
            VJ = formulas.global_orthogonal_velocity(g, a, t, v, J)
            if got != [-(1 + e[J[0]]) * x for x in VJ]:
                return f"impulse {w} on the orthogonal set {list(J)} is not -(1 + e) V_J"
    return None if compared else SKIP


# -- symmetries and invariances --------------------------------------------------------------------


def _same_outcome(
    a: Any, b: Any, label: str, map_velocity: Callable[[list[Any]], list[Any]], perm: list[int] | None = None
) -> Answer:
    """Whether run b is run a seen through a change (impact sets relabelled by ``perm``).

    Two runs proved never to exit are compared on their common prefix: the proof may fire
    a few impulses earlier or later, depending on which constraint it examines first.
    """
    if a.stop not in DONE or b.stop not in DONE:
        return SKIP  # a size budget depends on how the numbers are written
    sets_a = [tuple(sorted(perm[i] for i in J)) for J in a.impact_sets] if perm else list(a.impact_sets)
    sets_b = list(b.impact_sets)
    if a.stop != b.stop:
        return f"{label}: the stop {a.stop} becomes {b.stop}"
    if a.stop == "non_terminating":
        m = min(len(sets_a), len(sets_b))
        if sets_a[:m] != sets_b[:m]:
            return f"{label}: the impact sets {sets_a[:m]} become {sets_b[:m]}"
        return None
    if sets_a != sets_b:
        return f"{label}: the impact sets {sets_a} become {sets_b}"
    va, vb = map_velocity(q(a, a.exit_velocity)), q(b, b.exit_velocity)
    if va != vb:
        return f"{label}: the right velocity should be {_show(va)}, it is {_show(vb)}"
    return None


def _transformed(
    record: dict[str, Any],
    *,
    A: Any = None,
    perm: list[int] | None = None,
    mass: Fraction = Fraction(1),
    scale: Fraction = Fraction(1),
    frame: Any = None,
) -> dict[str, Any]:
    """The case seen after a change: x = A x', constraints relabelled (new i = perm[old i]),
    masses times ``mass``, velocity and time terms times ``scale``, a frame velocity."""
    from verify.laws.rule import DEFAULT_MAX_ITERATIONS
    from verify.records.results import case_record

    g, a, t, e = _inputs(record)
    v = Drawn("", "", record).values("velocity")
    n, r = len(v), len(a)
    if A is not None:
        g = [
            [formulas.phi(g, [A[k][i] for k in range(n)], [A[k][j] for k in range(n)]) for j in range(n)]
            for i in range(n)
        ]
        a = [[sum((row[k] * A[k][j] for k in range(n)), Fraction(0)) for j in range(n)] for row in a]
        v = formulas.solve_linear(A, v)
    if frame is not None:
        t = [ti - sum((x * u for x, u in zip(row, frame)), Fraction(0)) for ti, row in zip(t, a)]
        v = [x + u for x, u in zip(v, frame)]
    g = [[mass * x for x in row] for row in g]
    v = [scale * x for x in v]
    t = [scale * x for x in t]
    order = list(range(r))
    if perm is not None:
        order = [perm.index(i) for i in range(r)]  # new position i holds old constraint order[i]
    return case_record(
        record["id"],
        g,
        [a[i] for i in order],
        [e[i] for i in order],
        v,
        time_terms=[t[i] for i in order],
        max_iterations=record.get("max_iterations", DEFAULT_MAX_ITERATIONS),
    )


def relabelling_changes_nothing(run: Any, d: Drawn, order: list[int]) -> Answer:
    perm = [p for p in order if p < len(d.record["normals"])]  # a permutation of range(r)
    other = _transformed(d.record, perm=perm)
    return _same_outcome(run(d.record, d.rule), run(other, d.rule), f"relabelling by {perm}", lambda v: v, perm)


def mirror_symmetry(run: Any, d: Drawn, extra: Any) -> Answer:
    n, r = len(d.record["velocity"]), len(d.record["normals"])
    A: list[list[Any]]
    if d.family == "corner":  # y -> -y, theta -> -theta: the walls swap
        A = [[Fraction(1), 0, 0], [0, Fraction(-1), 0], [0, 0, Fraction(-1)]]
        label = "the mirror image y -> -y"
    elif d.family == "cradle":  # ball i -> ball N-1-i, x -> -x: contact i -> N-2-i
        A = [[Fraction(-1) if i + j == n - 1 else Fraction(0) for j in range(n)] for i in range(n)]
        label = "the cradle read backwards"
    else:
        return SKIP
    perm = list(range(r))[::-1]
    other = _transformed(d.record, A=A, perm=perm)

    def mapped(v: list[Any]) -> list[Any]:
        return formulas.solve_linear(A, v)

    return _same_outcome(run(d.record, d.rule), run(other, d.rule), label, mapped, perm)


def homogeneous(run: Any, d: Drawn, lam: Fraction) -> Answer:
    other = _transformed(d.record, scale=lam)
    label = f"scaling the velocity (and the time terms) by {lam}"
    return _same_outcome(run(d.record, d.rule), run(other, d.rule), label, lambda v: [lam * x for x in v])


def mass_scaling_changes_nothing(run: Any, d: Drawn, c: Fraction) -> Answer:
    other = _transformed(d.record, mass=c)
    return _same_outcome(run(d.record, d.rule), run(other, d.rule), f"scaling all masses by {c}", lambda v: v)


def covariant(run: Any, d: Drawn, factors: tuple[Any, ...]) -> Answer:
    n = len(d.record["velocity"])
    A = _matrix_from_factors(n, *factors)
    other = _transformed(d.record, A=A)
    label = f"the change of coordinates x = A x', A = {_show(_show(row) for row in A)}"
    return _same_outcome(run(d.record, d.rule), run(other, d.rule), label, lambda v: formulas.solve_linear(A, v))


def frame_independent(run: Any, d: Drawn, u: list[Fraction]) -> Answer:
    u = (list(u) + [Fraction(0)] * 6)[: len(d.record["velocity"])]
    other = _transformed(d.record, frame=u)
    label = f"constraints moving with uniform velocity u = {_show(u)}, seen from the co-moving frame"
    return _same_outcome(run(d.record, d.rule), run(other, d.rule), label, lambda v: [x + y for x, y in zip(v, u)])


def _matrix_from_factors(n: int, lower: list[Any], diagonal: list[Any], upper: list[Any]) -> list[list[Fraction]]:
    """A = L D U with unit triangular L, U and a non-zero diagonal D: invertible by construction."""
    L = [
        [Fraction(1) if i == j else lower[(i * n + j) % len(lower)] if j < i else Fraction(0) for j in range(n)]
        for i in range(n)
    ]
    U = [
        [Fraction(1) if i == j else upper[(i * n + j) % len(upper)] if j > i else Fraction(0) for j in range(n)]
        for i in range(n)
    ]
    D = [diagonal[i % len(diagonal)] for i in range(n)]
    return [[sum((L[i][k] * D[k] * U[k][j] for k in range(n)), Fraction(0)) for j in range(n)] for i in range(n)]


# -- backends -------------------------------------------------------------------------------------------


def backends_agree(run: Any, d: Drawn, extra: Any) -> Answer:
    """Exact inside the interval enclosure with the same branches; mp and float close where
    they take the exact branches (counted where they do not)."""
    from verify.errors import NoConvergence
    from verify.numbers.format import format_decimal

    exact = run(d.record, d.rule)
    if exact.stop not in DONE:
        return SKIP
    ve = q(exact, exact.exit_velocity)
    scale = max([abs(x) for x in q(exact, exact.velocity_in)] + [Fraction(1)])
    try:
        iv = run(d.record, d.rule, "interval")
    except NoConvergence:
        run.count("interval undecided (a rate exactly 0)")
        iv = None
    # two proofs that the rule never exits may come at different impulses (a cone of a period is
    # searched from other numbers on intervals): then the branches taken by both must agree
    proved = iv is not None and iv.stop == exact.stop == "non_terminating"
    n = min(len(iv.impact_sets), len(exact.impact_sets)) if iv is not None else 0
    if proved and len(iv.impact_sets) != len(exact.impact_sets) and iv.impact_sets[:n] == exact.impact_sets[:n]:
        run.count("proved never to exit on both, at different impulses")
        iv = None
    if iv is not None:
        if (iv.stop, iv.impact_sets) != (exact.stop, exact.impact_sets):
            return (
                f"the interval backend takes the branches {iv.impact_sets} ({iv.stop}), "
                f"exact {exact.impact_sets} ({exact.stop})"
            )
        outside = [i for i, (x, y) in enumerate(zip(iv.exit_velocity, ve)) if not iv.backend.contains(x, y)]
        if outside:
            return f"the exact right velocity is outside the interval enclosure in components {outside}"
    for name, tol in (("mp", Fraction(1, 10**20)), ("float", Fraction(1, 10**9))):
        other = run(d.record, d.rule, name)
        if (other.stop, other.impact_sets) != (exact.stop, exact.impact_sets):
            run.count(f"{name} takes another branch")
            continue
        approx = [
            Fraction(other.backend.to_decimal(x, 40)) if name == "mp" else Fraction(x) for x in other.exit_velocity
        ]
        err = max(abs(x - y) for x, y in zip(approx, ve))
        if err > tol * scale:
            return (
                f"{name} takes the exact branches but its right velocity is off by {format_decimal(err, 3)} "
                f"(more than {format_decimal(tol, 1)} x |v|)"
            )
    return None


# -- the registry -------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Property:
    """A property: its name (stable: it is the key of the JSON output), its check, what it
    draws besides the case, the rules, families and laws it is stated for, a SymPy proof.

    ``proof`` and ``explain`` are the rule's; ``simultaneous_proof`` and ``simultaneous_explain``
    the simultaneous law's (:meth:`statement` picks them by law).

    >>> property_named("kinetic energy").statement("simultaneous")
    (None, 'simultaneous_energy')
    """

    name: str
    check: Callable[[Any, Drawn, Any], Answer]
    extra: st.SearchStrategy[Any] | None = None
    rules: tuple[str, ...] = RULES
    families: tuple[str, ...] = FAMILIES
    proof: str | None = None  #: name of the proof in :mod:`verify.properties.proofs`
    census: bool = False  #: count the outcomes of every case of a refuted row, not only up to the first failure
    #: where the property fails: a proof's name in :mod:`verify.properties.proofs`, or a sentence
    explain: str | None = None
    #: the impact laws it is checked for: ``rule`` (the paper's), ``simultaneous``
    laws: tuple[str, ...] = ("rule",)
    simultaneous_proof: str | None = None
    simultaneous_explain: str | None = None
    sequential_explain: str | None = None
    #: the cap of impulses of its runs, if not the drawn records' (``strategies.MAX_ITERATIONS``)
    max_iterations: int | None = None
    #: what one check covers: each impulse of a run, or the run as a whole (its exit, or every step of it)
    scope: str = "over the run"

    def statement(self, law: str) -> tuple[str | None, str | None]:
        """The proof and the explanation of a failure for the law (names or a sentence)."""
        if law == "simultaneous":
            return self.simultaneous_proof, self.simultaneous_explain
        if law == "sequential":
            return None, self.sequential_explain
        return self.proof, self.explain


_ENTRIES = st.lists(small_rationals(2, 2), min_size=1, max_size=6)
_DIAGONAL = st.lists(st.sampled_from([Fraction(1), Fraction(-1), Fraction(2), Fraction(1, 2)]), min_size=1, max_size=6)
_SCALES = st.sampled_from([Fraction(2), Fraction(1, 3), Fraction(7, 2), Fraction(10**6), Fraction(1, 10**6)])
BOTH = ("rule", "simultaneous")  #: the laws of a property that the simultaneous law should keep too
#: the laws of a property that the sequential law (engines' sweeps) is also checked for
ALL = ("rule", "simultaneous", "sequential")
_ORDER = "the sequential law visits the constraints in the order given: relabelling them changes that order"

PROPERTIES: tuple[Property, ...] = (
    Property(
        "kinetic energy does not increase",
        energy_does_not_increase,
        scope="per impulse",
        proof="energy",
        explain="energy_change",
        laws=ALL,
        simultaneous_explain="simultaneous_energy",
        sequential_explain="Delta K = 1/2 sum lambda_i (w_i + w'_i) for any impulse: a contact that is not incoming "
        "but takes an impulse adds energy, and so does an incoming one that the sweeps leave faster than its "
        "restitution target",
    ),
    Property(
        "the exit velocity is outgoing",
        exit_is_outgoing,
        laws=ALL,
        sequential_explain="a sweep's later impulses make an earlier constraint incoming again, and the sweeps end",
    ),
    Property("each impulse is eq. (8) as printed", follows_eq8, scope="per impulse"),
    Property(
        "the simultaneous impulses satisfy restitution and complementarity",
        solves_complementarity,
        scope="per impulse",
        laws=("simultaneous",),
    ),
    Property("a single impact gives eq. (4)", single_impact_is_eq4, proof="single", laws=BOTH, scope="per impulse"),
    Property("beta = 1 for one constraint", beta_is_one_for_one_constraint, proof="beta_one", scope="per impulse"),
    Property("all CORs 1 give the ideal rule (5)", ideal_is_eq5, rules=("ideal",), proof="ideal", scope="per impulse"),
    Property(
        "equal CORs give the symmetric rule (6)",
        symmetric_is_eq6,
        rules=("symmetric",),
        proof="symmetric",
        scope="per impulse",
    ),
    Property(
        "two constraints: eq. (8) is the asymmetric rule (7)",
        asymmetric_is_eq7,
        scope="per impulse",
        rules=("asymmetric",),
        proof="asymmetric",
    ),
    Property(
        "orthogonal constraints give the codimension > 1 rule (Prop. 1)",
        orthogonal_is_codimension_rule,
        scope="per impulse",
        proof="orthogonal",
        laws=BOTH,
    ),
    Property(
        "relabelling the constraints changes nothing",
        relabelling_changes_nothing,
        extra=st.permutations(range(4)),
        laws=ALL,
        sequential_explain=_ORDER,
    ),
    Property(
        "mirror symmetry (corner y -> -y; cradle read backwards)",
        mirror_symmetry,
        families=("cradle", "corner"),
        laws=ALL,
        sequential_explain=_ORDER,
    ),
    Property(
        "homogeneity: scaling the velocity by lambda > 0 scales the result", homogeneous, extra=_SCALES, laws=BOTH
    ),
    Property("scaling all masses changes nothing", mass_scaling_changes_nothing, extra=_SCALES, laws=BOTH),
    Property(
        "covariance under a linear change of coordinates",
        covariant,
        extra=st.tuples(_ENTRIES, _DIAGONAL, _ENTRIES),
        laws=BOTH,
    ),
    Property(
        "frame independence (constraints in uniform motion)",
        frame_independent,
        extra=st.lists(small_rationals(2, 3), min_size=6, max_size=6),
        laws=BOTH,
    ),
    Property(
        "the rule exits (termination)",
        terminates,
        census=True,
        max_iterations=LONG_RUNS,
        explain=(
            "for two constraints the rule never exits exactly when the run enters the invariant cones of its "
            "certificate; for three unit balls that is eps <= 7 - 4*sqrt(3) (verify cradle-map), for "
            "the symmetric corner tan(alpha) <= (1 - sqrt(e))/(1 + sqrt(e)) (verify corner-claims)"
        ),
    ),
    Property("momentum along directions free of constraints is conserved", momentum_is_conserved, laws=ALL),
    Property("backends agree (exact, interval, mp, float)", backends_agree, laws=BOTH),
    Property(
        "the laws agree where the rule exits after one impulse on orthogonal constraints",
        laws_agree_after_one_orthogonal_impulse,
        laws=("simultaneous",),
    ),
    Property(
        "the sequential sweeps reach the simultaneous law",
        sweeps_reach_the_simultaneous_law,
        laws=("sequential",),
        sequential_explain="Gauss-Seidel approaches the simultaneous law's impulses geometrically: a finite "
        "number of sweeps reaches them exactly only where the sweeps stop changing",
    ),
)


def property_named(name: str) -> Property:
    """The property with this name, or whose name has ``name`` as its only prefix, or else as a
    part found in one name only (letter case ignored for prefixes and parts).

    >>> property_named("kinetic").name, property_named("termination").name
    ('kinetic energy does not increase', 'the rule exits (termination)')
    >>> property_named("rule")
    Traceback (most recent call last):
    ...
    verify.errors.InvalidInput: property 'rule' is ambiguous: it is part of ... names (see verify properties --list)
    """
    folded = name.casefold()
    hits = (
        [p for p in PROPERTIES if p.name == name]
        or [p for p in PROPERTIES if p.name.casefold().startswith(folded)]
        or [p for p in PROPERTIES if folded in p.name.casefold()]
    )
    if len(hits) != 1:
        from verify.errors import InvalidInput

        if hits:
            raise InvalidInput(
                f"property {name!r} is ambiguous: it is part of {len(hits)} names (see verify properties --list)"
            )
        raise InvalidInput(f"unknown property {name!r} (see verify properties --list)")
    return hits[0]
