"""Where a run that never exits tends: the limit velocity of an endless alternation, proved exactly.

A run proved never to exit by an alternating invariant cone (:func:`verify.proofs.termination.cone_certificate`)
applies single impulses to its two constraints alternately, forever. Over one period (an impulse on each) the
rates ``b`` of the two constraints are mapped linearly, ``b -> P b`` with ``P = N_1 N_0``. When P's spectral
radius is below 1 (Jury's test for a 2 x 2 matrix: ``|det P| < 1`` and ``|tr P| < 1 + det P``, decided exactly)
the rates fall to 0 geometrically, the impulses form a convergent series, and the velocity tends to the one
velocity that the two constraints' impulses can reach with both rates 0: ``v + sum_j c_j U_j`` with
``G c = -b`` (G the Gram matrix of the two constraints). For Newton's cradle this is the three-particle
inelastic collapse: every ball tends to the common velocity.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from collections.abc import Sequence

    from verify.dynamics.system import System


@dataclass(frozen=True)
class Limit:
    """The proved limit of a run that never exits: its velocity and kinetic energy (backend numbers), and
    how it was proved (the period map's trace and determinant, exact)."""

    velocity: tuple[Any, ...]
    kinetic_energy: Any
    trace: Any
    determinant: Any

    def statement(self, show: Any = str) -> str:
        """How the limit is proved, in words (``show`` writes a number).

        >>> Limit((), 0, "1/4", "0").statement()[:96]
        'the rates of the two constraints fall geometrically: over a period (an impulse on each) they are'
        """
        return (
            "the rates of the two constraints fall geometrically: over a period (an impulse on each) they are "
            f"mapped by P with det P = {show(self.determinant)}, tr P = {show(self.trace)}, so |det P| < 1 and "
            "|tr P| < 1 + det P (Jury): its spectral radius is below 1, and the velocity tends to the one with "
            "both rates 0"
        )


def jury(K: Any, trace: Any, det: Any) -> bool:
    """Whether a real 2 x 2 matrix of this trace and determinant (numbers of the backend ``K``) has both
    eigenvalues inside the unit circle (Jury's test: ``|det| < 1`` and ``|trace| < 1 + det``), decided by
    exact (or certified) signs; a sign the backend cannot decide answers False (nothing is claimed).

    >>> from fractions import Fraction as F
    >>> from verify.numbers.backends import get_backend
    >>> K = get_backend("exact")
    >>> [jury(K, F(t), F(d)) for t, d in [("1/2", "2/5"), ("3/2", "2/5"), ("-3/2", "2/5"), ("0", "1"), ("0", "-1")]]
    [True, False, False, False, False]
    """
    from verify.errors import Undecided
    from verify.numbers.backends.symbolic import Split

    one = K.one
    try:
        return all(K.sign(x) > 0 for x in (one - det, one + det, one + det - trace, one + det + trace))
    except (Undecided, Split):  # a sign that is not one sign on the whole: no claim
        return False


def alternation_limit(system: System, velocity: Sequence[Any], certificate: dict[str, Any] | None) -> Limit | None:
    """The limit of a run from ``velocity`` (the state its certificate was found at) when ``certificate`` is an
    alternating invariant cone of a two-constraint system and the period map is proved to contract; None
    otherwise (nothing is claimed).

    Three unit balls, eps = 1/100, ball 1 at 100: the run never exits, and tends to the common velocity.

    >>> from verify.laws.rule import solve
    >>> from verify.models.cradle import cradle_system
    >>> s = cradle_system("1/100")
    >>> r = solve(s, ["100", "0", "0"])
    >>> limit = alternation_limit(s, r.exit_velocity, r.certificate)
    >>> [str(x) for x in limit.velocity], str(limit.kinetic_energy)
    (['100/3', '100/3', '100/3'], '5000/3')
    """
    if certificate is None or certificate.get("kind") != "alternating invariant cone" or system.r != 2:
        return None
    K = system.backend
    if system.moving or not K.is_rigorous:  # a claim needs exact (or certified) signs, and rates that are N v
        return None
    G, e = system.gram, system.restitution
    one = K.one
    # N_0: b_0 -> -e_0 b_0, b_1 -> b_1 - (1 + e_0) (G_10 / G_00) b_0; N_1 likewise with 0 and 1 swapped
    n0 = ((-e[0], K.zero), (-(one + e[0]) * G[1][0] / G[0][0], one))
    n1 = ((one, -(one + e[1]) * G[0][1] / G[1][1]), (K.zero, -e[1]))
    p = [[sum((n1[i][k] * n0[k][j] for k in range(2)), K.zero) for j in range(2)] for i in range(2)]
    trace, det = p[0][0] + p[1][1], p[0][0] * p[1][1] - p[0][1] * p[1][0]
    if not jury(K, trace, det):
        return None
    b = system.rates(velocity)
    # G c = -b, for the two constraints
    d = G[0][0] * G[1][1] - G[0][1] * G[1][0]
    c0 = (-b[0] * G[1][1] + b[1] * G[0][1]) / d
    c1 = (-b[1] * G[0][0] + b[0] * G[1][0]) / d
    v = tuple(x + u for x, u in zip(velocity, system.combine_normals([(0, c0), (1, c1)])))
    return Limit(v, system.kinetic_energy(v), trace, det)
