"""Resultants and discriminants in y of polynomials in (x, y), by evaluation at integers and interpolation.

python-flint's own (``fmpq_mpoly.resultant``, ``.discriminant``) run a subresultant sequence over Q[x]: for
the curves of degree 20 and more that a map of cells meets (norms over a number field, long runs), one
of them takes tens of seconds. Here the same polynomial is built from univariate resultants over the
integers (FLINT's ``fmpz_poly.resultant``), which are fast:

1. p and q are scaled to integer coefficients, P = c_p p and Q = c_q q, so that
   Res_y(P, Q) = c_p^e c_q^d Res_y(p, q), with d, e their degrees in y (and disc_y(P) = c_p^(2d-2) disc_y(p));
2. the degree in x of the result is bounded, by the smaller of Bezout's bound (the product of the total
   degrees) and the Sylvester matrix's (e deg_x p + d deg_x q);
3. the result is evaluated at that many consecutive integers plus one, none a root of a leading coefficient
   in y (there the resultant of the values is the value of the resultant), and interpolated exactly
   (Newton's forward differences, then the basis of powers);
4. the interpolant is checked at one more integer; a mismatch (it cannot happen if the bound holds) falls
   back to flint's own.

The result is the polynomial flint's own gives, coefficient for coefficient (the tests compare them).

>>> import flint
>>> ctx = flint.fmpq_mpoly_ctx.get(("x", "y"))
>>> x, y = ctx.gens()
>>> f = x * y**2 - 3 * y + x**2 - 1
>>> discriminant_y(f, threshold=0) == f.discriminant("y"), resultant_y(f, y - x, threshold=0) == f.resultant(y - x, "y")
(True, True)
"""

from __future__ import annotations

from collections.abc import Callable
from math import factorial, lcm
from typing import Any

#: called between evaluations; it may raise to stop a long elimination (a map's wall-clock budget)
Stop = Callable[[], None] | None

#: the least degree bound (points to interpolate) from which interpolation is used; below, flint's own is faster
THRESHOLD = 60


def resultant_y(p: Any, q: Any, *, threshold: int = THRESHOLD, stop: Stop = None) -> Any:
    """The resultant in y of two ``fmpq_mpoly`` in (x, y), a polynomial in x (same context), as
    ``p.resultant(q, "y")`` gives it; ``stop`` is called every 32 evaluations."""
    d, e = _degree_y(p), _degree_y(q)
    if d < 1 or e < 1:
        return p.resultant(q, "y")
    bound = min(p.total_degree() * q.total_degree(), e * _degree_x(p) + d * _degree_x(q))
    if bound < threshold:
        return p.resultant(q, "y")
    (P, cp), (Q, cq) = _integer_rows(p), _integer_rows(q)
    found = _interpolated(lambda a, b: a.resultant(b), P, Q, bound, stop)
    if found is None:
        return p.resultant(q, "y")
    return _in_context(p, found, cp**e * cq**d)


def discriminant_y(p: Any, *, threshold: int = THRESHOLD, stop: Stop = None) -> Any:
    """The discriminant in y of an ``fmpq_mpoly`` in (x, y) of degree at least 2 in y, as
    ``p.discriminant("y")`` gives it; ``stop`` as for :func:`resultant_y`."""
    d = _degree_y(p)
    if d < 2:
        return p.discriminant("y")
    total = p.total_degree()
    bound = min(total * (total - 1), (2 * d - 1) * _degree_x(p))
    if bound < threshold:
        return p.discriminant("y")
    P, cp = _integer_rows(p)
    found = _interpolated(lambda a, _: a.discriminant(), P, None, bound, stop)
    if found is None:
        return p.discriminant("y")
    return _in_context(p, found, cp ** (2 * d - 2))


def _degree_y(p: Any) -> int:
    return int(p.degrees()[1])


def _degree_x(p: Any) -> int:
    return max(int(p.degrees()[0]), 0)


def _integer_rows(p: Any) -> tuple[list[Any], int]:
    """c p with integer coefficients (c the least common denominator), as its coefficients in y (``fmpz_poly``
    in x, lowest degree first), and c."""
    import flint

    terms = p.to_dict()
    c = lcm(*(int(v.q) for v in terms.values()))
    rows: dict[int, dict[int, int]] = {}
    for (i, j), v in terms.items():
        rows.setdefault(int(j), {})[int(i)] = int(v.p) * (c // int(v.q))
    top = max(rows)
    out = []
    for j in range(top + 1):
        row = rows.get(j, {})
        out.append(flint.fmpz_poly([row.get(i, 0) for i in range(max(row, default=0) + 1)]))
    return out, c


def _interpolated(op: Any, P: list[Any], Q: list[Any] | None, bound: int, stop: Stop = None) -> Any:
    """The polynomial in x (``fmpz_poly``) of degree at most ``bound`` whose value at each integer x is
    ``op(P(x, y), Q(x, y))``, or None when the check at one more point fails."""
    import flint

    lead = [P[-1]] + ([Q[-1]] if Q is not None else [])
    start = -(bound // 2)
    while any(f(x) == 0 for f in lead for x in range(start, start + bound + 2)):
        start += bound + 2

    def value(x: int) -> int:
        if stop is not None and x % 32 == 0:
            stop()
        a = flint.fmpz_poly([c(x) for c in P])
        b = flint.fmpz_poly([c(x) for c in Q]) if Q is not None else None
        return int(op(a, b))

    values = [value(x) for x in range(start, start + bound + 1)]
    newton = []
    for _ in range(bound + 1):  # forward differences: the k-th is k! times the k-th Newton coefficient
        newton.append(values[0])
        values = [values[i + 1] - values[i] for i in range(len(values) - 1)]
    coeffs = []
    for k, c in enumerate(newton):
        q, r = divmod(c, factorial(k))
        if r:
            return None
        coeffs.append(q)
    x = flint.fmpz_poly([0, 1])
    poly = flint.fmpz_poly([coeffs[-1]])
    for k in range(bound - 1, -1, -1):
        poly = poly * (x - (start + k)) + coeffs[k]
    check = start + bound + 1
    return poly if int(poly(check)) == value(check) else None


def _in_context(p: Any, poly: Any, scale: int) -> Any:
    """The ``fmpz_poly`` in x divided by ``scale``, as a polynomial of p's context."""
    import flint

    ctx = p.context()
    return ctx.from_dict({(i, 0): flint.fmpq(int(c), scale) for i, c in enumerate(poly.coeffs()) if c})
