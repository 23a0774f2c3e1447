"""Termination in the wedge: when does the disk leave the corner?

A case is decided by running it exactly: it exits, or it is proved never to exit by the
invariant cones of :mod:`verify.proofs.termination` (two walls alternately, forever), with a
certificate. For the symmetric corner (one COR eps) the cones exist exactly when the
alternating two-step map has real eigenvalues, ``c^2 >= 4 eps`` with
``c = (1 + eps)(1 - k^2)/(1 + k^2)`` and ``k = tan(alpha) < 1``; :func:`symmetric_boundary`
solves this for the slope, symbolically, giving the exact boundary in the (alpha, eps)
plane. Below it (narrower corners, smaller eps) a disk that enters the cones never leaves;
above it, every alternating run is rotated out and leaves, after a number of rebounds
that grows without bound as the corner narrows towards the boundary.

>>> k_star, alpha_star = symmetric_boundary()
>>> k_star, alpha_star
(-(sqrt(eps) - 1)/(sqrt(eps) + 1), -atan(sqrt(eps)) + pi/4)
"""

from __future__ import annotations

from fractions import Fraction
from typing import TYPE_CHECKING, Any

from verify.numbers.format import format_exact

if TYPE_CHECKING:
    import sympy as sp


def symmetric_boundary() -> tuple[sp.Expr, sp.Expr]:
    """The boundary slope k*(eps) and angle alpha*(eps), derived with SymPy.

    Solves ``(1 + eps)(1 - k^2) = 2 sqrt(eps) (1 + k^2)`` (that is c = 2 sqrt(eps), the
    double eigenvalue) for the root k > 0 when 0 < eps < 1, with eps = s^2; then checks
    symbolically that tan(pi/4 - atan(s)) is that root, so alpha* = pi/4 - atan(sqrt(eps)).
    """
    import sympy as sp

    k, s = sp.symbols("k s", positive=True)
    eps = sp.Symbol("eps", positive=True)
    roots = sp.solve(sp.Eq((1 + s**2) * (1 - k**2), 2 * s * (1 + k**2)), k)
    half = sp.Rational(1, 2)
    (k_star,) = [sp.factor(r) for r in roots if r.subs(s, half) > 0]
    candidate = sp.pi / 4 - sp.atan(s)
    if sp.simplify(sp.expand_trig(sp.tan(candidate)) - k_star) != 0:  # pragma: no cover - a SymPy regression
        raise ArithmeticError("the boundary angle did not simplify")
    return sp.factor(k_star.subs(s, sp.sqrt(eps))), candidate.subs(s, sp.sqrt(eps))


def below_boundary(slope: Fraction, eps: Fraction) -> bool:
    """Whether the symmetric corner of slope k admits never-ending alternation: c^2 >= 4 eps
    (decided exactly, on rationals)."""
    if slope >= 1:
        return False
    c = (1 + eps) * (1 - slope * slope) / (1 + slope * slope)
    return c * c >= 4 * eps


def rebounds_by_slope(
    eps: str, velocity: list[str], slopes: list[str], max_iterations: int = 100_000
) -> list[dict[str, Any]]:
    """Exact runs of one entrance velocity in narrower and narrower symmetric corners."""
    from verify.models.corner import run_corner

    out = []
    for k in slopes:
        run = run_corner(slope=k, velocity=velocity, eps1=eps, eps2=eps, trace=False, max_iterations=max_iterations)
        out.append(
            {
                "slope": k,
                "stop": run.result.stop,
                "iterations": run.result.iterations,
                "below_boundary": below_boundary(Fraction(k), Fraction(eps)),
            }
        )
    return out


def approach_slopes(eps: Fraction, count: int = 6) -> list[str]:
    """Rational slopes just above the boundary slope k*(eps), ten times closer each time."""
    import sympy as sp

    k_star, _ = symmetric_boundary()
    value = k_star.subs(sp.Symbol("eps", positive=True), sp.Rational(eps.numerator, eps.denominator))
    out = []
    for j in range(1, count + 1):
        scale = 10 ** (j + 3)
        upper = sp.ceiling((value + sp.Rational(1, 10**j)) * scale)
        out.append(format_exact(Fraction(int(upper), scale)))
    return out
