"""Never exits up to and at the boundary beside a turning pair: the rates' part on W grows away, the part on U turns.

Below the boundary eps* of :mod:`verify.maps.turning` (five unit balls, the period (S1,S3)(S2,S4)) the turning
cones stop short of eps*: no polyhedral cone is mapped into itself there. This argument needs no cone. With the
frame W = ker q(M), U = ker of the other factor over Q(sqrt(d))(eps), s the modulus of U's eigenvalues, and
A = M/s, write the rates at the start of a period x = w + u (w in W, u in U). After k periods the rates are
x_k = s^k (A_W^k w + A_U^k u). For a linear form l of the rates that must be negative for the run to follow the
period (l = b_j, or -b_j, of the rates before each impulse of the period, a linear map of x):

- **The part on W.** f(k) = l(A_W^k w) satisfies f(k+1) = t f(k) - f(k-1) (Cayley-Hamilton: det A_W = 1,
  t = tr A_W). Where t >= 2 (q's roots are real and positive, as below and at eps*), f(1) <= f(0) < 0 gives
  f(k) <= f(0) for every k, by induction: f(k+1) - f(k) = (t - 2) f(k) + (f(k) - f(k-1)) <= 0.
- **The part on U.** A_U keeps a definite quadratic form Q (A_U^T Q A_U = Q, as in :mod:`verify.maps.leaving`), so
  A_U^k u stays on the ellipse Q(y) = Q(u), on which l(y)^2 <= Gamma^2 = Q(u) l_U Q^-1 l_U^T.

So l(x_k) <= s^k (f(0) + Gamma) < 0 for every k when f(0)^2 > Gamma^2: every sign the period needs holds after
every number of periods, and the run follows the period forever. Each condition is the sign of a rational
function of eps over Q(sqrt(d)) on the piece, decided exactly (:func:`signs_on`: cut at the real roots of its
norm, each part's sign read off those of a, b and a^2 - d b^2 for a + sqrt(d) b), up to and at eps* itself, where
t = 2 (a double eigenvalue: f(k) then falls linearly).

>>> from verify.numbers.backends.symbolic import EPS
>>> from verify.models.cradle import cradle_system
>>> build = lambda K: cradle_system(EPS, 5, backend=K)
>>> cache = RootCache()
>>> d = grown_below(build, ["1", "0", "0", "0", "0"], Piece.closed("0.259", "0.26"), Pattern(2, ((0, 2), (1, 3))),
...                 bound=20, cache=cache)
>>> str(d.piece), d.iterations, d.certificate["kind"], d.certificate["boundary"]["reached"]
('[259/1000, CRootOf(x**4 - 44*x**3 + 166*x**2 - 44*x + 1, 1)]', 4, 'dominant growth', True)
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import sympy as sp
from sympy.polys.matrices import DomainMatrix

from verify.laws.rule import solve
from verify.maps.boundary import Build, Decided, Pattern, pattern_map, sympified
from verify.maps.leaving import kept_form
from verify.maps.turning import extension, field_collisions, nearest_above, turning_frame
from verify.numbers.algebraic import RealAlgebraic, X
from verify.numbers.backends.symbolic import Piece, RootCache, Split, SymbolicBackend

STATEMENT = (
    "From this state on the run follows the period forever: after k periods the rates are s^k (A_W^k w + A_U^k u) "
    "in the frame (W, U); for each sign l < 0 the period needs, l(A_W^k w) <= l(w) (t = tr A_W >= 2, det A_W = 1, "
    "l(A_W w) <= l(w) < 0), and A_U keeps the definite form Q, so l(A_U^k u)^2 <= Q(u) l_U Q^-1 l_U^T < l(w)^2."
)


def signs_on(x: Any, piece: Piece) -> list[tuple[Piece, int]] | None:
    """The sign of ``x`` (an element of Q(sqrt(d))(eps), SymPy's field of fractions over the number field) on the
    parts of ``piece`` cut at the real roots of the norms of its numerator and denominator, in increasing order
    (points and open intervals between them); None at a pole in the piece or when the field's generator is not
    sqrt(d). Exact: each polynomial is a + sqrt(d) b (a, b over Q), whose sign at a real algebraic x is read off
    the signs of a, b and a^2 - d b^2 there.

    >>> from verify.numbers.backends.symbolic import EPS
    >>> D = sp.QQ.algebraic_field(sp.sqrt(2)).frac_field(EPS)
    >>> [(str(part), sign) for part, sign in signs_on(D.from_sympy((EPS - sp.sqrt(2)) / EPS), Piece.closed(1, 2))]
    [('[1, sqrt(2))', -1), ('{sqrt(2)}', 0), ('(sqrt(2), 2]', 1)]
    """
    num, den = _halves(x.numer), _halves(x.denom)
    if num is None or den is None:
        return None
    cuts: list[RealAlgebraic] = []
    for norm in (num[2], den[2]):
        if norm.degree() > 0:
            cuts += RealAlgebraic.roots_in(norm)
    out = []
    for part in piece.cut(cuts):
        at = part.lower if part.is_point else RealAlgebraic.rational(part.sample())
        below = _sign_at(den, at)
        if below == 0:
            return None
        out.append((part, _sign_at(num, at) * below))
    return out


def _halves(p: Any) -> tuple[sp.Poly, sp.Poly, sp.Poly] | None:
    """(a, b, a^2 - d b^2) for a polynomial p = a + sqrt(d) b of eps over Q(sqrt(d)) (a PolyElement whose
    coefficients are written in the generator sqrt(d)), a and b over Q in the variable
    :data:`~verify.numbers.algebraic.X`; None when the field's generator is not a square root."""
    halves: list[dict[int, Any]] = [{}, {}]
    d = None
    for (k,), c in p.terms():
        modulus = [sp.Rational(m) for m in c.mod_to_list()]
        if len(modulus) != 3 or modulus[0] != 1 or modulus[1] != 0:
            return None
        d = -modulus[2]
        coeffs = [sp.Rational(t) for t in c.to_list()]
        a_k, b_k = (coeffs[-1], coeffs[0] if len(coeffs) == 2 else 0) if coeffs else (0, 0)
        halves[0][k], halves[1][k] = a_k, b_k
    values = [v for h in halves for v in h.values() if v]
    if values:  # one positive scale for a and b: the signs stay, the numbers get short
        scale = sp.Rational(math.lcm(*[int(v.q) for v in values]), math.gcd(*[int(v.p) for v in values]))
        halves = [{k: v * scale for k, v in h.items()} for h in halves]
    a, b = (sp.Poly.from_dict({(k,): v for k, v in h.items() if v}, X, domain="QQ") for h in halves)
    return a, b, a * a - b * b * (d if d is not None else 0)


def _sign_at(halves: tuple[sp.Poly, sp.Poly, sp.Poly], x: RealAlgebraic) -> int:
    """The sign of a + sqrt(d) b at x, exactly."""
    a, b, norm = (x.sign_of(p) if not p.is_zero else 0 for p in halves)
    if b in (0, a):
        return a
    if a == 0:
        return b
    return a * norm  # opposite signs: a's when a^2 > d b^2, b's when less, 0 when equal


def grown_below(
    build: Build,
    velocity: Sequence[Any],
    piece: Piece,
    pattern: Pattern,
    *,
    bound: int,
    cache: RootCache,
) -> Decided | None:
    """The top part of ``piece`` (up to its upper end, or up to and with the boundary eps* over Q(sqrt(d)) when the
    piece holds it) on which the argument of the module proves that every eps never exits, for the first phase of
    ``pattern`` where it holds, from the rates at that phase's start after 0, 1, ... periods (up to ``bound``
    impulses: the first for which it holds); None when it holds nowhere at the top. The certificate names the
    boundary reached (``"reached": True``) when the part ends there."""
    p = len(pattern.sets)
    for j in range(p):
        phase = Pattern(pattern.start + j, pattern.sets[j:] + pattern.sets[:j])
        system = build(SymbolicBackend(piece, cache))
        M = pattern_map(system, phase.sets)
        ext = extension(M) if M is not None else None
        if M is None or ext is None:
            return None
        for star, q in field_collisions(M, ext, piece) or nearest_above(M, ext, piece):
            top = Piece(piece.lower, star, piece.lower_closed, True) if piece.contains(star) else piece
            if top.lower.cmp(top.upper) >= 0:
                continue
            found = _grown(build, velocity, top, phase, (M, q, ext), bound=bound, cache=cache)
            if found is not None:
                reached = top.upper.cmp(star) == 0
                found.certificate["boundary"] = {"pattern": str(pattern), "eps": str(star), "factor": str(q),
                                                 "no_cone_beyond": False, "reached": reached,
                                                 "extension": str(ext)}  # fmt: skip
                return found
    return None


def _grown(
    build: Build,
    velocity: Sequence[Any],
    piece: Piece,
    phase: Pattern,
    period: tuple[sp.Matrix, Any, Any],
    *,
    bound: int,
    cache: RootCache,
) -> Decided | None:
    M, q, ext = period
    f = turning_frame(M, q, ext)
    if f is None or f.M.shape[0] != 4:  # U must be one plane, turned by a pair of modulus s
        return None
    D = f.domain
    basis, inverse = f.inverse.inv(), f.inverse
    W, U = basis[:, :2], basis[:, 2:]
    turn = D.one / f.scale
    A_W = inverse[:2, :] * f.M * W * turn
    Q = _kept_form(inverse[2:, :] * f.M * U * turn, D)
    if Q is None or not _zero(A_W.det() - D.one):
        return None
    system = build(SymbolicBackend(piece, cache))
    forms = [DomainMatrix.from_Matrix(row).convert_to(D) for row in _forms(system, phase)]
    if not forms:  # an impulse of the period is not linear: no signs to check, so no proof
        return None
    p = len(phase.sets)
    for start in range(phase.start, bound + 1, p):  # later rates: a U-part smaller against W's
        try:
            run = solve(system, list(velocity), max_iterations=start, trace=False, certify=False)
        except Split:
            return None
        if run.stop != "max_iterations" or run.iterations != start:
            return None
        rates = [sympified(system.backend, x) for x in system.rates(run.exit_velocity)]
        c = inverse * DomainMatrix.from_Matrix(sp.Matrix(rates)).convert_to(D)
        part = _top_where(_conditions(forms, (W, U, A_W, Q, f.scale), c), piece)
        if part is not None:
            shown = [sp.sympify(system.backend.to_number(x)) for x in run.exit_velocity]
            certificate = _certificate(phase, start, rates, f)
            if certificate is None:
                return None
            return Decided(part, start, list(run.impact_sets), shown, certificate)
    return None


def _normalised(basis: Any) -> Any:
    """The basis with each column divided by its first entry that is not 0 (the same planes, shorter numbers)."""
    cols = []
    for j in range(basis.shape[1]):
        col = basis[:, j]
        first = next(col[i, 0].element for i in range(col.shape[0]) if not _zero(col[i, 0].element))
        cols.append(col * (basis.domain.one / first))
    return cols[0].hstack(*cols[1:])


def _kept_form(A: Any, D: Any) -> Any | None:
    """The quadratic form Q that the 2 x 2 matrix A of determinant 1 keeps (A^T Q A = Q), over D, checked; None
    when det A is not 1 or the check fails."""
    if not _zero(A.det() - D.one):
        return None
    Q = DomainMatrix(kept_form(*(A[i, j].element for i, j in ((0, 0), (0, 1), (1, 0), (1, 1)))), (2, 2), D)
    kept = A.transpose() * Q * A - Q
    return Q if all(_zero(kept[i, j].element) for i in range(2) for j in range(2)) else None


def _zero(x: Any) -> bool:
    """Whether an element of the field of fractions is 0 (its numerator; the field does not normalise a fraction
    whose numerator and denominator differ by a constant of the number field)."""
    return bool(x.numer.is_zero)


def _forms(system: Any, phase: Pattern) -> list[sp.Matrix]:
    """The linear forms of the rates at the period's start that must be < 0 (the constraints hit at each impulse)
    or <= 0 (minus those not hit) for the run to follow the period once; none when an impulse is not linear."""
    out = []
    for i, J in enumerate(phase.sets):
        L = pattern_map(system, phase.sets[:i])  # the rates before the i-th impulse
        if L is None:
            return []
        out += [L.row(c) if c in J else -L.row(c) for c in range(system.r)]
    return out


def _conditions(forms: list[Any], frame: tuple[Any, Any, Any, Any, Any], c: Any) -> list[tuple[Any, tuple[int, ...]]]:
    """The functions of eps (elements of the frame's field) with the signs each must keep (see the module):
    t - 2 >= 0, s > 0, det Q > 0, and for each form l(w) < 0, l(A_W w) - l(w) <= 0, Gamma^2 - l(w)^2 < 0."""
    W, U, A_W, Q, scale = frame
    w, u = c[:2, :], c[2:, :]
    energy = (u.transpose() * Q * u)[0, 0].element
    Qi = Q.inv()
    two = A_W.domain.one + A_W.domain.one
    out: list[tuple[Any, tuple[int, ...]]] = [(A_W[0, 0].element + A_W[1, 1].element - two, (0, 1)),
                                              (scale, (1,)), (Q.det(), (1,))]  # fmt: skip
    for lf in forms:
        lw, lu = lf * W, lf * U
        f0, f1 = (lw * w)[0, 0].element, (lw * A_W * w)[0, 0].element
        out += [(f0, (-1,)), (f1 - f0, (-1, 0)), (energy * (lu * Qi * lu.transpose())[0, 0].element - f0 * f0, (-1,))]
    return out


def _certificate(phase: Pattern, start: int, rates: list[Any], f: Any) -> dict[str, Any] | None:
    """The certificate, in the frame with each column divided by its first entry that is not 0 (the same planes,
    shorter numbers), and the form U keeps in it."""
    D = f.domain

    def text(x: Any) -> str:
        return str(sp.cancel(sp.radsimp(D.to_sympy(x))))

    basis = _normalised(f.inverse.inv())
    W, U = basis[:, :2], basis[:, 2:]
    Q = _kept_form(basis.inv()[2:, :] * f.M * U * (D.one / f.scale), D)
    if Q is None:
        return None
    return {
        "kind": "dominant growth",
        "statement": STATEMENT,
        "pattern": str(phase),
        "sets": [list(J) for J in phase.sets],
        "impulses": start,
        "rates": [str(x) for x in rates],
        "extension": str(f.ext),
        "scale": text(f.scale),
        "W": [[text(W[i, j].element) for i in range(W.shape[0])] for j in range(2)],
        "U": [[text(U[i, j].element) for i in range(U.shape[0])] for j in range(2)],
        "form": [[text(Q[i, j].element) for j in range(2)] for i in range(2)],
    }


def _top_where(conditions: list[tuple[Any, tuple[int, ...]]], piece: Piece) -> Piece | None:
    """The largest part of ``piece`` that holds its upper end on which every condition keeps its allowed signs."""
    cuts: list[RealAlgebraic] = []
    signed = []
    for x, allowed in conditions:
        found = signs_on(x, piece)
        if found is None:
            return None
        signed.append((found, allowed))
        cuts += [y for part, _ in found for y in (part.lower, part.upper)]
    good: list[Piece] = []
    for part in reversed(piece.cut(cuts)):
        at = part.lower if part.is_point else RealAlgebraic.rational(part.sample())
        if not all(_sign_of(found, at) in allowed for found, allowed in signed):
            break
        good.append(part)
    if not good:
        return None
    low = good[-1]
    return Piece(low.lower, piece.upper, low.lower_closed, piece.upper_closed)


def _sign_of(found: list[tuple[Piece, int]], x: RealAlgebraic) -> int:
    return next(sign for part, sign in found if part.contains(x))
