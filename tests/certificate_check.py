"""An independent checker of non-termination certificates (invariant cones, two constraints).

Written from the mathematics in the certificate's own words, without importing the code
that finds certificates (verify.core.termination, verify.core.backends.symbolic, verify.checks.paper.cradle_map) or the
rule: it recomputes the Gram matrix from the masses and normals with SymPy, applies the
impulse maps itself, and checks every condition, either exactly at a rational eps or for
every eps of an interval with algebraic endpoints (by the real roots of each polynomial).

The claim checked: if mu_0, mu_1 > 0, N_0 maps the cone C_0 into C_1, N_1 maps C_1 into
C_0 and the rates lie in C_phase, then single impacts alternate forever.

    C_k = {b != 0 : b_k <= 0, b_l >= 0, e_l b_k + mu_k b_l <= 0}, l = 1 - k
    N_k(b): b_k -> -e_k b_k, b_l -> b_l - (1 + e_k) b_k G_lk / G_kk
"""

from __future__ import annotations

import itertools

import sympy as sp

from verify.core.parse import parse_number  # only to read number strings without eval

EPS = sp.Symbol("eps")


def read(text: str) -> sp.Expr:
    value = parse_number(text, symbols={"eps": EPS})
    return sp.Rational(value.numerator, value.denominator) if hasattr(value, "denominator") else value


def gram(masses: list[sp.Expr], normals: list[list[sp.Expr]]) -> sp.Matrix:
    A = sp.Matrix(normals)
    return A * sp.diag(*masses).inv() * A.T


def _sign_at(p: sp.Expr, point: sp.Expr) -> int:
    value = sp.radsimp(sp.expand(p.subs(EPS, point)))
    if value == 0 or sp.simplify(value) == 0:
        return 0
    return 1 if value.evalf(60) > 0 else -1


def nonnegative_on(p: sp.Expr, lo: sp.Expr, hi: sp.Expr) -> bool:
    """p(eps) >= 0 for every eps in [lo, hi] (p a rational function without poles there)."""
    p = sp.together(sp.expand(p))
    num, den = sp.fraction(p)
    points = [lo, hi]
    for q in (num, den):
        poly = sp.Poly(q, EPS)
        if poly.degree() > 0:
            for r in sp.real_roots(poly):
                if _sign_at(EPS - lo, r) >= 0 and _sign_at(EPS - hi, r) <= 0:
                    points.append(r)
    points = sorted(set(points), key=lambda r: sp.N(r, 60))
    samples = list(points) + [(a + b) / 2 for a, b in itertools.pairwise(points)]
    return all(_sign_at(p, s) >= 0 for s in samples)


def check(
    cert: dict,
    masses: list[str],
    normals: list[list[str]],
    rates: list[str] | None = None,
    interval: tuple[str, str] | None = None,
) -> list[str]:
    """Every failed condition of the certificate (an empty list: the certificate holds).

    ``rates`` (default: the certificate's) are the rates when the run stopped; ``interval``
    gives eps's range for a certificate written in terms of eps (default: eps not used).
    """
    G = gram([read(m) for m in masses], [[read(x) for x in row] for row in normals])
    failures = []
    stated = [[read(x) for x in row] for row in cert["gram"]]
    if sp.simplify(sp.Matrix(stated) - G) != sp.zeros(2, 2):
        failures.append("the Gram matrix does not match the system")
    e = [read(x) for x in cert["restitution"]]
    mu = [read(x) for x in cert["mu"]]
    b = [read(x) for x in (rates or cert["rates"])]
    lo, hi = (read(interval[0]), read(interval[1])) if interval else (sp.Integer(0), sp.Integer(0))

    def holds(expr: sp.Expr) -> bool:  # expr >= 0 for every eps considered
        return nonnegative_on(expr, lo, hi) if interval else _sign_at(expr, 0) >= 0

    def N(k: int, w: list[sp.Expr]) -> list[sp.Expr]:
        l = 1 - k
        out = [None, None]
        out[k] = -e[k] * w[k]
        out[l] = w[l] - (1 + e[k]) * w[k] * G[l, k] / G[k, k]
        return out

    def in_cone(k: int, w: list[sp.Expr]) -> bool:
        l = 1 - k
        return holds(-w[k]) and holds(w[l]) and holds(-(e[l] * w[k] + mu[k] * w[l]))

    def rays(k: int) -> list[list[sp.Expr]]:
        l = 1 - k
        r1, r2 = [None, None], [None, None]
        r1[k], r1[l] = sp.Integer(-1), sp.Integer(0)
        r2[k], r2[l] = -mu[k], e[l]
        return [r1, r2]

    if not (holds(mu[0]) and holds(mu[1]) and _strict(mu, lo, hi, interval)):
        failures.append("mu_0 > 0 and mu_1 > 0 fails")
    for k in (0, 1):
        for ray in rays(k):
            if not in_cone(1 - k, N(k, ray)):
                failures.append(f"N_{k} does not map the ray {ray} of C_{k} into C_{1 - k}")
    j = cert["phase"]
    if not in_cone(j, b):
        failures.append(f"the rates {b} are not in C_{j}")
    if not holds(-b[j]) or (not interval and _sign_at(b[j], 0) == 0):
        failures.append(f"b_{j} < 0 fails")
    return failures


def _strict(mu: list[sp.Expr], lo: sp.Expr, hi: sp.Expr, interval: tuple | None) -> bool:
    """mu_k > 0 everywhere: no zero of mu_k in the interval (or at the point)."""
    for m in mu:
        if interval:
            poly = sp.Poly(sp.numer(sp.together(m)), EPS)
            if poly.degree() > 0 and any(
                _sign_at(EPS - lo, r) >= 0 and _sign_at(EPS - hi, r) <= 0 for r in sp.real_roots(poly)
            ):
                return False
            if poly.degree() <= 0 and poly.as_expr() == 0:
                return False
        elif _sign_at(m, 0) <= 0:
            return False
    return True


def check_repeating(cert: dict, masses: list[str], normals: list[list[str]]) -> list[str]:
    """Check a "repeating direction" certificate: run the cycle of impacts on the rates with
    this module's own formulas and compare with the stated rates and factor.

    Rates evolve by b -> b - beta * sum_{j in J} (1 + e_j) (b_j / G_jj) G[:, j], with beta = 1
    for one constraint and beta = (sum b_j^2 / G_jj) / (lam^T G_JJ lam), lam_j = b_j / G_jj,
    for several (Sect. 3.5 c-d written in rates).
    """
    G = gram([read(m) for m in masses], [[read(x) for x in row] for row in normals])
    e = [read(x) for x in cert["restitution"]]
    b = [read(x) for x in cert["rates_earlier"]]
    failures = []
    for J in cert["cycle"]:
        if sorted(J) != [j for j in range(len(b)) if _sign_at(b[j], 0) < 0]:
            failures.append(f"the impact set {J} is not the set of incoming constraints at {b}")
            return failures
        lam = {j: b[j] / G[j, j] for j in J}
        if len(J) == 1:
            beta = 1
        else:
            num = sum(b[j] ** 2 / G[j, j] for j in J)
            den = sum(lam[i] * G[i, j] * lam[j] for i in J for j in J)
            beta = num / den
        b = [sp.radsimp(sp.expand(b[m] - beta * sum((1 + e[j]) * lam[j] * G[m, j] for j in J))) for m in range(len(b))]
    now = [read(x) for x in cert["rates_now"]]
    c = read(cert["factor"])
    if any(sp.simplify(x - y) != 0 for x, y in zip(b, now)):
        failures.append("running the cycle does not give the stated rates")
    if any(sp.simplify(y - c * x) != 0 for x, y in zip([read(v) for v in cert["rates_earlier"]], now)):
        failures.append("the rates are not the stated multiple of the earlier ones")
    if _sign_at(c, 0) <= 0:
        failures.append("the factor is not positive")
    return failures
