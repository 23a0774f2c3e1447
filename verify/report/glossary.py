"""The glossary of the reports: every term a page uses, in the paper's notation (``reports/glossary.md``).

>>> [term for term, _ in GLOSSARY][:3]
['impact set', 'rate p(F_i)', 'COR (eps)']
"""

from __future__ import annotations

#: each term and what it means on the pages, in the order a reader meets them
GLOSSARY: tuple[tuple[str, str], ...] = (
    (
        "impact set",
        "the constraints an impulse acts on: those whose rate is negative (incoming) at that impulse. "
        "For the cradle, S(1,2) is the contact of balls 1 and 2 and S(2,3) that of balls 2 and 3; for the corner, "
        "S1 and S2 are the two walls.",
    ),
    (
        "rate p(F_i)",
        "how fast constraint i is approached, dF_i . v plus its time term (eq. 2): negative means "
        "incoming, an impact; zero or positive means outgoing.",
    ),
    (
        "COR (eps)",
        "the coefficient of restitution of a constraint, in [0, 1]; eps is the cradle's common COR, "
        "eps1 and eps2 the corner walls'.",
    ),
    ("beta", "the factor of a multiple impulse (eq. 8), read off the rates; 1 for a single impact."),
    (
        "the rule",
        "the paper's iteration (Sect. 3.5): impulses by eq. (8) until the velocity is outgoing; eq. (5) "
        "when every COR is 1 (ideal), (6) for equal CORs (symmetric), (7) for two constraints (asymmetric).",
    ),
    (
        "simultaneous law",
        "Newton's restitution with complementarity, every contact at once, the law physics "
        "engines approximate: a linear complementarity problem, solved exactly here.",
    ),
    (
        "sequential law",
        "single-contact impulses swept in order a fixed number of times (projected Gauss-Seidel), "
        "as most physics engines run it; computed exactly here.",
    ),
    ("exit", "a run's stop when no constraint is incoming any more: its velocity is the exit velocity."),
    (
        "never exits",
        "a run proved to go on with infinitely many impulses: a certificate (below) shows that its "
        "rates stay where an impact always remains. There is no exit velocity; the pages show the velocity when "
        "it was proved and, where that is proved too, the limit velocity.",
    ),
    (
        "limit velocity",
        "where a run that never exits tends: proved when the rates fall geometrically (over a period of "
        "impulses they are mapped by a matrix whose spectral radius is below 1, decided exactly); for the cradle, "
        "the common velocity (100/3, 100/3, 100/3) of the inelastic collapse.",
    ),
    (
        "certificate",
        "the proof that a run never exits, checked without the code that found it: an invariant cone "
        "(two constraints), a repeating direction of the rates, a cone that a period of impulses maps into itself, "
        "or the dominant growth of a turning pair (the five-ball map).",
    ),
    (
        "AEEV",
        "Almost Equal Exit Velocities: the paper's own stop (Sect. 4.1) when the differences of the three "
        "velocities fall below sigma = 10^-9 ||v0||; Table 1 prints 'AEEV' and the impulses before the stop. Of "
        "the 56 readings of that sentence tried, the one that reproduces every printed count compares the norm of "
        "all pairwise differences with c ||v||, c = 10^-9, before each impulse: paper mode uses it.",
    ),
    (
        "paper mode",
        "a run with the paper's termination: at most 10^4 impulses and the AEEV stop. Exact mode stops "
        "only at an exit, a proof, or a cap.",
    ),
    (
        "inelastic collapse",
        "infinitely many collisions in finite time among inelastic particles, known for three "
        "balls below a COR threshold (McNamara and Young 1992): here, every eps in [0, 7 - 4*sqrt(3)].",
    ),
    (
        "map",
        "the rule for every value of one or more CORs at once, cut exactly where a sign changes; a piece (one "
        "parameter) or a cell (two) has one behaviour on all of it.",
    ),
    (
        "undecided, unexplored",
        "a piece of a map the search did not decide within its budget (undecided), or did "
        "not reach (unexplored); neither is a claim.",
    ),
    (
        "verdict",
        "a property's result on a row: proved (a SymPy identity; the drawn cases still test the code), "
        "holds N (no counterexample in the N cases drawn where the property applies: fewer than the profile's "
        "count when some cases do not meet its premise), no case (none of them did), refuted (a shrunk exact "
        "counterexample). A property is checked per impulse or over the run.",
    ),
    (
        "row, family",
        "a property checked for one rule and one law on one family of systems: general (random "
        "systems of 1 to 4 constraints), cradle (2 to 5 balls) or corner (the disk between two walls).",
    ),
    ("profile", "how many cases each row draws: dev (25), ci (100, the reports'), thorough (100,000 per property)."),
    ("census", "how the runs of the termination rows end: exit, never exits (proved), at the cap, at the size budget."),
    (
        "zones",
        "the corner's regions of entrance directions (Sect. 4.2): Z12 both walls hit at once, Z1 or Z2 one "
        "wall, Z0 none (the disk leaves).",
    ),
    (
        "claim statuses",
        "reproduced (as the paper states it); reproduced under one reading (under the one reading of its words "
        "that fits); disagrees (the computation and the paper part); refuted (a case shows it false); proved; "
        "holds (on every case drawn); found (where the paper says it happens); new (a finding the paper does not "
        "state).",
    ),
    (
        "alpha, phi, slope k",
        "the corner's half-angle alpha (its walls have slopes k and -k, k = tan(alpha)) and the direction phi of "
        "the entrance velocity (Sect. 4.2).",
    ),
    (
        "cap, size budget",
        "a run stops at its cap of impulses (max_iterations) or when its exact numbers outgrow the size budget; "
        "either leaves it undecided, never claimed.",
    ),
    (
        "period",
        "a sequence of impact sets that a run repeats; over one period the rates are mapped linearly, and the "
        "eigenvalues of that map decide whether the run exits (a turning pair: two complex eigenvalues).",
    ),
    (
        "oracle classes, ulps",
        "each case an implementation answers is graded exact, within tolerance, wrong branch (another impact "
        "sequence), wrong stop, out of tolerance, momentum drift or energy error; ulps count binary64 steps "
        "between a float and the exact value.",
    ),
    (
        "relative distance",
        "between two velocities a and b of a run from v_in: max_i |a_i - b_i| / max_i |v_in_i|; two agree when "
        "it is at most 0.001.",
    ),
    (
        "explained",
        "an engine's answer is explained when an exact model of its own algorithm (the rule, the simultaneous "
        "law, or the sequential law with the engine's sweeps, order and threshold) is within the engine's "
        "precision of it: 1e-5 of the speed in float32, 1e-9 in float64.",
    ),
    (
        "backend",
        "the arithmetic of a run: exact (rationals and algebraic numbers), interval (certified "
        "enclosures), mp and float (not rigorous).",
    ),
)


def glossary_page() -> str:
    """The glossary as a page."""
    from verify.views.pages import wrapped

    lines = [
        "# Glossary",
        "",
        "The terms the pages use, in the paper's notation (S. Pasquero, J. Nonlinear Sci. 2021).",
        "",
    ]
    lines += [line for term, meaning in GLOSSARY for line in wrapped(f"**{term}**: {meaning}", bullet="- ")]
    return "\n".join(lines) + "\n"
