"""An independent checker of non-termination certificates (invariant cones, two constraints).

Written from the mathematics in the certificate's own words, without importing the code
that finds certificates (verify.proofs.termination, verify.numbers.backends.symbolic, verify.paper.cradle_map) or the
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
from fractions import Fraction

import sympy as sp

from verify.numbers.parse import parse_number  # only to read number strings without eval

EPS = sp.Symbol("eps")


def read(text: str) -> sp.Expr:
    value = parse_number(text, symbols={"eps": EPS})
    return sp.Rational(value.numerator, value.denominator) if hasattr(value, "denominator") else value


def gram(masses: list, normals: list[list[sp.Expr]]) -> sp.Matrix:
    """A M^-1 A^T for the diagonal masses (a list) or the mass matrix (a list of rows)."""
    A = sp.Matrix(normals)
    M = sp.Matrix(masses) if masses and isinstance(masses[0], list) else sp.diag(*masses)
    return A * M.inv() * A.T


def _read_masses(masses: list) -> list:
    return [[read(x) for x in row] if isinstance(row, list) else read(row) for row in masses]


def _sign_at(p: sp.Expr, point: sp.Expr) -> int:
    quick = _poly_sign_at(p, point)
    if quick is not None:
        return quick
    value = sp.radsimp(sp.expand(p.subs(EPS, point)))
    if value == 0 or sp.simplify(value) == 0:
        return 0
    return 1 if value.evalf(60) > 0 else -1


def _poly_sign_at(p: sp.Expr, point: sp.Expr) -> int | None:
    """The sign of p at the point when p is a polynomial in eps over Q and the point rational (exactly) or a real
    CRootOf of an irreducible polynomial f: p(point) = r(point) for r the remainder of p by f, which is 0 exactly
    when r is (f is the point's minimal polynomial and deg r < deg f), else has the sign of its value to 60
    digits. None for other p or points."""
    point = sp.sympify(point)
    if not _real_algebraic(point):
        return None
    c = sp.expand(EPS - p)
    if isinstance(c, sp.CRootOf) and c.is_real:  # p = eps - c: the sign of point - c
        return _compare(point, c)
    try:
        poly = sp.Poly(p, EPS, domain="QQ")
    except (sp.PolynomialError, sp.CoercionFailed, sp.GeneratorsNeeded):
        return None
    if point.is_Rational:
        value = poly.eval(point)
        return 1 if value > 0 else -1 if value < 0 else 0
    f = sp.Poly(point.poly.as_expr().subs(point.poly.gen, EPS), EPS, domain="QQ")
    if not f.is_irreducible:
        return None
    rest = poly.rem(f)
    if rest.is_zero:
        return 0
    return 1 if rest.as_expr().subs(EPS, point).evalf(60) > 0 else -1


def _real_algebraic(x: sp.Expr) -> bool:
    """A rational, or a real CRootOf."""
    return bool(x.is_Rational or (isinstance(x, sp.CRootOf) and x.is_real))


def _compare(t: sp.Expr, c: sp.Expr) -> int | None:
    """The sign of t - c for rationals and real CRootOfs: exactly when one is rational (by :func:`_poly_sign_at`);
    for two roots of the same irreducible polynomial by their indices (CRootOf numbers the real roots in
    increasing order); for roots of different irreducible polynomials (never equal) by their values to 60 digits.
    None when a polynomial is not irreducible."""
    if c.is_Rational:
        return _poly_sign_at(EPS - c, t)
    if t.is_Rational:
        back = _poly_sign_at(EPS - t, c)
        return None if back is None else -back
    f, g = (sp.Poly(x.poly.as_expr().subs(x.poly.gen, EPS), EPS, domain="QQ") for x in (t, c))
    if not (f.is_irreducible and g.is_irreducible):
        return None
    if f.monic() == g.monic():
        return (t.index > c.index) - (t.index < c.index)
    return 1 if (t - c).evalf(60) > 0 else -1


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


def _positive(p: sp.Expr, lo: sp.Expr, hi: sp.Expr, interval: tuple | None) -> bool:
    """p > 0 for every eps considered: p >= 0 there and no zero of its numerator in it."""
    if interval is None:
        return _sign_at(p, 0) > 0
    return nonnegative_on(p, lo, hi) and _strict([p], lo, hi, interval)


class _Signs:
    """Signs of rational functions of eps, the same for every eps considered: a point, or an interval
    (``closed`` says which ends belong to it)."""

    def __init__(self, interval: tuple | None, closed: tuple[bool, bool] = (True, True)):
        self.interval = interval
        self.lo, self.hi = (read(interval[0]), read(interval[1])) if interval else (sp.Integer(0), sp.Integer(0))
        self.closed = closed
        self.memo: dict = {}

    def _positive(self, x: sp.Expr) -> bool:
        """x > 0 on the interval: >= 0 on its closure, and no zero of the numerator inside it."""
        if not nonnegative_on(x, self.lo, self.hi):
            return False
        poly = sp.Poly(sp.numer(sp.together(x)), EPS)
        if poly.degree() <= 0:
            return poly.as_expr() != 0
        for r in sp.real_roots(poly):
            above, below = _sign_at(EPS - self.lo, r), _sign_at(EPS - self.hi, r)
            if (above > 0 or (above == 0 and self.closed[0])) and (below < 0 or (below == 0 and self.closed[1])):
                return False
        return True

    def nonneg(self, x: sp.Expr) -> bool:
        """x >= 0 everywhere considered."""
        if self.interval is None:
            return _sign_at(x, 0) >= 0
        return nonnegative_on(x, self.lo, self.hi)

    def __call__(self, x: sp.Expr) -> int | None:
        """-1, 0 or 1, or None when the sign changes over the interval."""
        x = sp.cancel(x)
        if x == 0:
            return 0
        if self.interval is None:
            return _sign_at(x, 0)
        if x not in self.memo:
            self.memo[x] = 1 if self._positive(x) else -1 if self._positive(-x) else None
        return self.memo[x]


def _linear(G: sp.Matrix, J: list[int]) -> bool:
    return all(sp.simplify(G[i, j]) == 0 for i in J for j in J if i < j)


def _step(G: sp.Matrix, e: list, J: list[int], x: list, beta: sp.Expr = 1) -> list:
    r = G.shape[0]
    return [sp.cancel(x[m] - beta * sum((1 + e[j]) * x[j] / G[j, j] * G[m, j] for j in J)) for m in range(r)]


def _betas(G: sp.Matrix, J: list[int], vectors: list, sign: _Signs) -> list | None:
    """[beta_lo, beta_hi] from the pairwise forms N_kl, D_kl of the vectors (the rule of
    verify.proofs.cones.period, rewritten): beta = sum x_j^2/G_jj / (lam^T G_JJ lam)."""
    GJ = sp.Matrix([[G[i, j] for j in J] for i in J])
    lam = [sp.Matrix([v[j] / G[j, j] for j in J]) for v in vectors]
    forms = [(sum(a[j] * lb[t] for t, j in enumerate(J)), (la.T * GJ * lb)[0]) for a, la in zip(vectors, lam)
             for lb in lam]  # fmt: skip
    ratios = [sp.cancel(n / d) for n, d in forms if sign(d) == 1]
    if not ratios or any(sign(d) is None for _, d in forms):
        return None
    lo = hi = ratios[0]
    for x in ratios[1:]:
        lo = x if sign(x - lo) == -1 else lo
        hi = x if sign(x - hi) == 1 else hi
    if any(sign(d) != 1 and (sign(n - lo * d) == -1 or sign(hi * d - n) == -1) for n, d in forms):
        return None
    return [lo, hi]


def _cone_lp(y: list, gens: list, strict: list, need_strict: bool) -> bool:
    """y is a non-negative combination of gens (with weight on a strict one if asked), at a rational point:
    a simplex method written here for the checker (dense tableau over Fractions, Bland's rule), apart
    from the search's (verify/proofs/cones/lp.py) and from SymPy's (whose lpmax stalled on some of them)."""
    entries = [x for g in gens for x in g] + list(y)
    number = _q if all(sp.sympify(x).is_Rational for x in entries) else _Quadratic.of
    rows = [[number(g[m]) for g in gens] + [number(y[m])] for m in range(len(y))]
    try:  # the largest strict weight (or 0 with no objective), None if y is not in the cone
        best = _simplex(rows, len(gens), [Fraction(1 if s else 0) for s in strict] if need_strict else None)
    except OverflowError:  # an unbounded strict weight: positive
        return True
    return best is not None and (best > 0 if need_strict else True)


class _Quadratic:
    """A number of a real quadratic field (a + b sqrt(d), SymPy), kept in that canonical form after every
    operation so that 0 is recognised as 0; its sign is decided exactly from a, b and d (no rounding). For
    the checker's simplex at a boundary point such as eps = 3 - 2*sqrt(2)."""

    def __init__(self, x: sp.Expr):
        self.x = sp.expand(sp.radsimp(x))

    @classmethod
    def of(cls, x: object) -> _Quadratic:
        return cls(sp.sympify(x))

    @staticmethod
    def _e(y: object) -> sp.Expr:
        if isinstance(y, _Quadratic):
            return y.x
        if isinstance(y, Fraction):
            return sp.Rational(y.numerator, y.denominator)
        return sp.sympify(y)

    def __add__(self, y: object) -> _Quadratic:
        return _Quadratic(self.x + self._e(y))

    __radd__ = __add__

    def __sub__(self, y: object) -> _Quadratic:
        return _Quadratic(self.x - self._e(y))

    def __rsub__(self, y: object) -> _Quadratic:
        return _Quadratic(self._e(y) - self.x)

    def __mul__(self, y: object) -> _Quadratic:
        return _Quadratic(self.x * self._e(y))

    __rmul__ = __mul__

    def __truediv__(self, y: object) -> _Quadratic:
        return _Quadratic(self.x / self._e(y))

    def __rtruediv__(self, y: object) -> _Quadratic:
        return _Quadratic(self._e(y) / self.x)

    def __neg__(self) -> _Quadratic:
        return _Quadratic(-self.x)

    def sign(self) -> int:
        """The sign of a + b sqrt(d), exactly: the common sign of a and b, or, where they differ, the sign of
        the larger of a^2 and b^2 d."""
        x = self.x
        if x.is_Rational:
            return int(sp.sign(x))
        roots = {p for p in x.atoms(sp.Pow) if p.exp == sp.Rational(1, 2) and p.base.is_Rational}
        if len(roots) != 1:
            raise ValueError(f"not a number of one real quadratic field: {x}")
        (s,) = roots
        b, a = sp.Poly(x, s).all_coeffs() if sp.Poly(x, s).degree() == 1 else (sp.Integer(0), x)
        if not (a.is_Rational and b.is_Rational):
            raise ValueError(f"not a number of one real quadratic field: {x}")
        sa, sb = int(sp.sign(a)), int(sp.sign(b))
        if sa == 0 or sb in (0, sa):
            return sa or sb
        return sa if a * a > b * b * s.base else sb

    def _cmp(self, y: object) -> int:
        return (self - y).sign()

    def __lt__(self, y: object) -> bool:
        return self._cmp(y) < 0

    def __gt__(self, y: object) -> bool:
        return self._cmp(y) > 0

    def __le__(self, y: object) -> bool:
        return self._cmp(y) <= 0

    def __ge__(self, y: object) -> bool:
        return self._cmp(y) >= 0

    def __eq__(self, y: object) -> bool:
        return self._cmp(y) == 0

    def __ne__(self, y: object) -> bool:
        return self._cmp(y) != 0

    __hash__ = None  # type: ignore[assignment]


def _q(x: object) -> Fraction:
    """A rational number (SymPy's, or an int) as a Fraction."""
    r = sp.Rational(x)  # raises on anything but a rational: membership is decided at a rational point only
    return Fraction(int(r.p), int(r.q))


def _simplex(rows: list[list[Fraction]], n: int, objective: list[Fraction] | None) -> Fraction | None:
    """max objective . d subject to rows (``[A | b]``, A d = b) and d >= 0 (0 with no objective), or None
    when infeasible. Phase one with an artificial column per row, then phase two; Bland's rule in both."""
    m = len(rows)
    t = [[-x for x in row] if row[n] < 0 else list(row) for row in rows]
    t = [row[:n] + [Fraction(int(i == k)) for k in range(m)] + [row[n]] for i, row in enumerate(t)]
    basis = list(range(n, n + m))

    def run(cost: list[Fraction], allowed: int) -> None:
        while True:
            reduced = [cost[j] - sum(cost[basis[i]] * t[i][j] for i in range(m)) for j in range(allowed)]
            enter = next((j for j in range(allowed) if reduced[j] > 0 and j not in basis), None)
            if enter is None:
                return
            ratios = [(t[i][-1] / t[i][enter], basis[i], i) for i in range(m) if t[i][enter] > 0]
            if not ratios:
                raise OverflowError("the objective is unbounded")
            _, _, leave = min(ratios)
            pivot(leave, enter)

    def pivot(i: int, j: int) -> None:
        t[i] = [x / t[i][j] for x in t[i]]
        for k in range(m):
            if k != i and t[k][j] != 0:
                t[k] = [a - t[k][j] * b for a, b in zip(t[k], t[i])]
        basis[i] = j

    run([Fraction(0)] * n + [Fraction(-1)] * m, n + m)  # phase one: maximise minus the artificials
    if any(basis[i] >= n and t[i][-1] != 0 for i in range(m)):
        return None
    for i in range(m):  # artificials left at 0: pivot them out, or their row is redundant
        if basis[i] >= n:
            j = next((j for j in range(n) if t[i][j] != 0), None)
            if j is not None:
                pivot(i, j)
    if objective is None:
        return Fraction(0)
    run(objective + [Fraction(0)] * m, n)
    return sum((objective[basis[i]] * t[i][-1] for i in range(m) if basis[i] < n), Fraction(0))


def _carry(G: sp.Matrix, e: list, vectors: list, p: int, *, sign: _Signs, failures: list, prune: bool) -> list:
    """The vectors after p impulses, every impact set the signs allow: S (strict vectors < 0, the others <= 0)
    must not be empty; the cone is cut by x_f = 0 for each f where the vectors disagree; each part is moved
    by its impact set, with beta = 1 (orthogonal sets) or both beta bounds."""
    r = G.shape[0]
    for n in range(p):
        parts = _parts(vectors, r, n, sign=sign, failures=failures)
        if failures:
            return []
        out: list = []
        for vs, J in parts:
            betas = [1] if len(J) == 1 or _linear(G, J) else _betas(G, J, [v for v, _ in vs], sign)
            if betas is None:
                failures.append(f"impulse {n}: no bounds of beta for the impact set {J}")
                return []
            for v, s in vs:
                for beta in betas:
                    w = _step(G, e, J, v, beta)
                    if not any(s == t and all(sp.cancel(a - b) == 0 for a, b in zip(w, u)) for u, t in out):
                        out.append((w, s))
        vectors = _pruned(out) if prune else out
    return vectors


def _parts(vectors: list, r: int, n: int, *, sign: _Signs, failures: list) -> list:
    """The parts of the cone at impulse n, each with its impact set: S (strict vectors < 0, the others <= 0)
    must not be empty; the cone is cut by x_f = 0 for each f where the vectors disagree."""
    S, F = [], []
    for i in range(r):
        signs = [(sign(v[i]), s) for v, s in vectors]
        if any(x is None for x, _ in signs):
            failures.append(f"impulse {n}: a sign of constraint {i} changes over the interval")
            return []
        if all(x >= 0 for x, _ in signs):
            continue
        (S if all(x == -1 or (x == 0 and not s) for x, s in signs) else F).append(i)
    if not S:
        failures.append(f"impulse {n}: no constraint is hit for sure")
        return []
    parts = [(vectors, list(S))]
    for f in F:
        cut = []
        for vs, J in parts:
            neg = [(v, s) for v, s in vs if sign(v[f]) == -1]
            pos = [(v, s) for v, s in vs if sign(v[f]) == 1]
            if not neg:
                cut.append((vs, J))
            elif not pos:
                cut.append((vs, [*J, f]))
            else:
                zero = [(v, s) for v, s in vs if sign(v[f]) == 0]
                cross = [([_tidy(-w[f] * a + u[f] * b) for a, b in zip(u, w)], su or sw)
                         for u, su in pos for w, sw in neg]  # fmt: skip
                cut += [(neg + zero + cross, [*J, f]), (pos + zero + cross, J)]
        parts = cut
    return parts


def _tidy(x: object) -> object:
    """A Fraction as it is, a SymPy expression cancelled."""
    return x if isinstance(x, Fraction) else sp.cancel(x)


def _pruned(vectors: list) -> list:
    kept = list(vectors)
    for item in list(vectors):
        others = [x for x in kept if x is not item]
        if others and _cone_lp(item[0], [v for v, _ in others], [s for _, s in others], item[1]):
            kept = others
    return kept


def check_period(
    cert: dict,
    masses: list,
    normals: list[list[str]],
    *,
    rates: list[str] | None = None,
    interval: tuple[str, str] | None = None,
    restitution: list[str] | None = None,
    closed: tuple[bool, bool] = (True, True),
) -> list[str]:
    """Check an "invariant cone of a period" certificate (any number of constraints): every failed
    condition (an empty list: the certificate holds).

    ``restitution`` (the system's CORs) must match the certificate's; ``closed`` says which ends of
    ``interval`` belong to it.

    The claim: carried through p impulses with every impact set their signs allow (see _carry), the
    generators' cone lands in itself (every vector carried from a strict generator with a positive weight
    on a strict generator), and the rates are the first generator (or lie in the stated box, which lies in
    the cone). The vectors are carried here by this module's own formulas; at a rational point, membership
    is decided by this module's own simplex; over an interval of eps, each vector carried here must be a positive
    multiple of a listed one whose stated combination is checked identically and for sign.
    """
    G = gram(_read_masses(masses), [[read(x) for x in row] for row in normals])
    r = G.shape[0]
    failures: list[str] = []
    stated = [[read(x) for x in row] for row in cert["gram"]]
    if sp.simplify(sp.Matrix(stated) - G) != sp.zeros(r, r):
        failures.append("the Gram matrix does not match the system")
    e = [read(x) for x in cert["restitution"]]
    if restitution is not None and any(sp.cancel(read(x) - y) != 0 for x, y in zip(restitution, e)):
        failures.append("the CORs do not match the system")
    gens = [[read(x) for x in g] for g in cert["generators"]]
    strict = list(cert["strict"])
    sign = _Signs(interval, closed)
    if cert.get("multiple impulses") == "polar values":
        if interval is not None:
            return ["polar values are checked at a rational point only"]
        failures += _check_polar(G, e, cert, gens, strict)
        return failures + _rates_in_cone(cert, gens, strict, rates)
    carried = _carry(
        G, e, list(zip(gens, strict)), int(cert["impulses"]), sign=sign, failures=failures, prune=interval is None
    )
    if failures:
        return failures
    if interval is None:
        for y, s in carried:
            if not _cone_lp(y, gens, strict, s):
                failures.append(f"a vector carried through the period is not in the cone: {y}")
    else:
        listed = [([read(x) for x in c["vector"]], {int(k): read(v) for k, v in c["combination"].items()})
                  for c in cert["carried"]]  # fmt: skip
        for y, s in carried:
            if not any(_matches(y, z, d, gens=gens, strict=strict, s=s, sign=sign) for z, d in listed):
                failures.append(f"a vector carried through the period is not a listed combination: {y}")
    return failures + _rates_in_cone(cert, gens, strict, rates)


def _rates_in_cone(cert: dict, gens: list, strict: list, rates: list[str] | None) -> list[str]:
    """The rates are the first generator (strict), or lie in the stated box, which lies in the cone."""
    if "box" in cert:
        failures = _box_in_cone(cert["box"], gens, strict)
        if rates or "rates" in cert:  # exact rates boxed by short rationals: they must lie in the box
            b = [read(x) for x in (rates or cert["rates"])]
            box = [[read(x) for x in cert["box"][k]] for k in ("center", "radius")]
            if any(abs(x - c) > w for x, c, w in zip(b, *box)):
                failures.append("the rates do not lie in the box")
        return failures
    b = [read(x) for x in (rates or cert["rates"])]
    if not strict[0] or any(sp.cancel(x - y) != 0 for x, y in zip(b, gens[0])):
        return ["the rates are not the first generator, or it is not strict"]
    return []


def _check_polar(G: sp.Matrix, e: list, cert: dict, gens: list, strict: list) -> list[str]:
    """A certificate whose multiple impulses move by polar values, checked stage by stage at a rational point:
    the vectors of stage n (stage 0 and stage p: the generators), cut and moved by impulse n+1 as in _carry,
    must lie in the cone of stage n+1. A multiple impulse moves a part by the values of the cubic form
    C(x) = D(x) x - N(x) A x on every triple of its vectors, found here by the polarization identity
    6 P(u, v, w) = C(u+v+w) - C(u+v) - C(u+w) - C(v+w) + C(u) + C(v) + C(w) (the search expands P instead)."""
    r, p = G.shape[0], int(cert["impulses"])
    Gq = [[_q(G[i, j]) for j in range(r)] for i in range(r)]
    eq = [_q(x) for x in e]
    listed = [([[_q(read(x)) for x in v] for v in st["vectors"]], list(st["strict"])) for st in cert.get("stages", [])]
    stages = [([[_q(x) for x in g] for g in gens], strict), *listed, ([[_q(x) for x in g] for g in gens], strict)]
    if len(stages) != p + 1:
        return [f"{len(stages) - 2} stages listed for a period of {p} impulses"]
    failures: list = []
    for n in range(p):
        vectors = list(zip(*stages[n]))
        sign = _Signs(None)
        parts = _parts(vectors, r, n, sign=sign, failures=failures)
        if failures:
            return failures
        target, flags = stages[n + 1]
        cone = _Facets(target)
        for vs, J in parts:
            if len(J) == 1 or all(Gq[i][j] == 0 for i in J for j in J if i < j):
                moved = [([v[m] - _push(Gq, eq, J, v)[m] for m in range(r)], t) for v, t in vs]
            else:
                found = _polar(Gq, eq, J, vs)
                if found is None:
                    return [f"impulse {n}: a strict vector's own value is 0"]
                moved = found
            for y, t in moved:
                inside = cone.contains(y) if all(flags) else _cone_lp(y, target, flags, t)
                if not inside:
                    failures.append(f"impulse {n}: a moved vector is not in the cone of the next stage: {y}")
                    return failures
    return failures


def _push(G: list, e: list, J: list, x: list) -> list:
    """A x = sum_{j in J} (1 + e_j) (x_j / G_jj) G[:, j] (Fractions)."""
    return [sum(((1 + e[j]) * x[j] / G[j][j] * G[m][j] for j in J), Fraction(0)) for m in range(len(x))]


def _cubic(G: list, e: list, J: list, x: list) -> list:
    """C(x) = D(x) x - N(x) A x, with N = sum_j x_j^2 / G_jj and D = lam^T G_JJ lam (lam_j = x_j / G_jj)."""
    lam = {j: x[j] / G[j][j] for j in J}
    N = sum((x[j] * lam[j] for j in J), Fraction(0))
    D = sum((lam[i] * G[i][j] * lam[j] for i in J for j in J), Fraction(0))
    a = _push(G, e, J, x)
    return [D * v - N * w for v, w in zip(x, a)]


def _polar(G: list, e: list, J: list, vs: list) -> list | None:
    """6 P(u, v, w) for every triple of the vectors (polarization), strict when the three are: a point with weight
    c > 0 on a strict u has weight c^3 on P(u, u, u) = C(u), which must not be 0 (else None: the point u itself
    would leave no rate)."""
    add = lambda *xs: [sum(c) for c in zip(*xs)]  # noqa: E731
    C = {}
    vecs = [v for v, _ in vs]
    for k in range(len(vecs)):
        C[(k,)] = _cubic(G, e, J, vecs[k])
    for k, l in itertools.combinations(range(len(vecs)), 2):
        C[(k, l)] = _cubic(G, e, J, add(vecs[k], vecs[l]))
    out = []
    for k, l, m in itertools.combinations_with_replacement(range(len(vecs)), 3):

        def c(*idx: int) -> list:
            key = tuple(sorted(set(idx)))
            if len(key) == 1:  # C(2u) = 8 C(u), C(3u) = 27 C(u)
                return [len(idx) ** 3 * x for x in C[key]]
            if len(idx) == 2:
                return C[key]
            return _cubic(G, e, J, add(*(vecs[i] for i in idx)))

        parts = [c(k, l, m), c(k, l), c(k, m), c(l, m), c(k), c(l), c(m)]
        y = [a - b - cc - d + f + g + h for a, b, cc, d, f, g, h in zip(*parts)]
        strict = vs[k][1] and vs[l][1] and vs[m][1]
        if any(y):
            out.append((y, strict))
        elif strict and k == l == m:
            return None
    return out


class _Facets:
    """The cone of three-dimensional generators by its facets (planes through two generators with every
    generator on one side); membership is then a list of signs. Falls back to the simplex method when the
    cone is not pointed and full (fewer than three facets)."""

    def __init__(self, gens: list):
        self.gens = gens
        self.normals = []
        for a, b in itertools.combinations(gens, 2):
            n = [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
            if not any(n):
                continue
            sides = [sum(x * y for x, y in zip(n, g)) for g in gens]
            if all(t >= 0 for t in sides):
                self.normals.append(n)
            elif all(t <= 0 for t in sides):
                self.normals.append([-x for x in n])
        # the planes through pairs are the facets only for a pointed cone with an interior: then the sum of
        # the inward normals is positive on every generator (a flat cone, or one holding a line, fails this)
        total = [sum(c) for c in zip(*self.normals)] if self.normals else [0, 0, 0]
        self.pointed = all(sum(x * v for x, v in zip(total, g)) > 0 for g in gens)

    def contains(self, y: list) -> bool:
        if len(y) != 3 or len(self.normals) < 3 or not self.pointed:
            return _cone_lp(y, self.gens, [True] * len(self.gens), False)
        return any(y) and all(sum(x * v for x, v in zip(n, y)) >= 0 for n in self.normals)


def _matches(y: list, z: list, d: dict, *, gens: list, strict: list, s: bool, sign: _Signs) -> bool:
    """y = c z with c > 0, z = sum d_k gens[k] with d_k >= 0 (and d_k > 0 on a strict k if s)."""
    k = next((i for i, x in enumerate(z) if sp.cancel(x) != 0), None)
    if k is None:
        return all(sp.cancel(x) == 0 for x in y)
    c = sp.cancel(y[k] / z[k])
    if sign(c) != 1 or any(sp.cancel(a - c * b) != 0 for a, b in zip(y, z)):
        return False
    if any(sp.cancel(z[m] - sum(v * gens[i][m] for i, v in d.items())) != 0 for m in range(len(z))):
        return False
    if not all(sign.nonneg(v) for v in d.values()):
        return False
    return not s or any(strict[i] and sign(v) == 1 for i, v in d.items())


def _box_in_cone(box: dict, gens: list[list[sp.Expr]], strict: list[bool]) -> list[str]:
    """The rates lie in the box center +- radius: the box lies in the cone when, for each of the k
    non-zero radii, center +- a_i e_i are strict generators with a_i >= k radius_i (then every point
    center + t of the box is the mean over i of points center + k t_i e_i, each between those two);
    with no non-zero radius, the center is a strict generator."""
    center = [read(x) for x in box["center"]]
    radius = [read(x) for x in box["radius"]]
    wide = [i for i, w in enumerate(radius) if w != 0]
    if any(w < 0 for w in radius):
        return ["a radius of the box is negative"]
    strict_gens = [g for g, s in zip(gens, strict) if s]
    if not wide:
        return [] if center in strict_gens else ["the center of the box (a point) is not a strict generator"]
    failures = []
    for i in wide:
        for sign in (1, -1):
            found = any(
                all(g[j] == center[j] for j in range(len(center)) if j != i)
                and sign * (g[i] - center[i]) >= len(wide) * radius[i]
                for g in strict_gens
            )
            if not found:
                failures.append(f"no strict generator center {'+' if sign > 0 else '-'} a e_{i} with a >= k radius_{i}")
    return failures


def at_point(cert: dict, values: dict[str, object]) -> dict:
    """A certificate written in parameters (a cell of ``verify map --cells``), with the parameters' exact
    ``values`` (name: a Fraction) put in: a certificate of numbers, for :func:`check` or :func:`check_period`."""
    symbols = {name: sp.Symbol(name) for name in values}
    subs = {symbols[name]: sp.sympify(str(v)) for name, v in values.items()}

    def put(x: str) -> str:
        value = parse_number(x, symbols=symbols)
        expr = sp.Rational(value.numerator, value.denominator) if hasattr(value, "denominator") else value
        return str(sp.radsimp(sp.sympify(expr).subs(subs)))

    def put_all(x: object) -> object:  # every number of a nested list or dict
        if isinstance(x, str):
            return put(x)
        if isinstance(x, list):
            return [put_all(y) for y in x]
        return {k: put_all(v) for k, v in x.items()} if isinstance(x, dict) else x

    out = dict(cert)
    for key in ("rates", "restitution", "mu", "gram", "generators", "carried", "box", "stages"):
        if key in cert:
            out[key] = put_all(cert[key])
    return out


# -- "dominant growth": never exits up to a boundary beside a turning pair (verify.maps.growth) ------------------------


def check_growth(
    cert: dict,
    masses: list[str],
    normals: list[list[str]],
    *,
    interval: tuple[sp.Expr, sp.Expr],
    closed: tuple[bool, bool] = (True, True),
    restitution: list[str] | None = None,
) -> list[str]:
    """What fails in a "dominant growth" certificate for every eps of ``interval`` (SymPy numbers: rationals or
    CRootOf; ``closed`` says which ends belong to it), the CORs eps (or ``restitution``), from the claim in its own
    words: the frame (W, U) splits the period M (built here from the masses and normals), A = M/s has determinant 1
    on W and on U, A_U keeps the form Q, t = tr A_W >= 2, s > 0, Q definite, and for every sign l < 0 the period
    needs (the constraints hit, and minus those not hit, before each impulse): l(w) < 0, l(A_W w) <= l(w) and
    Q(u) l_U Q^-1 l_U^T < l(w)^2, with w + u the certificate's rates. The signs are checked in that order, up to
    the first that fails."""
    root = read(cert["extension"])
    r = len(normals)
    G = gram(_read_masses(masses), [[read(x) for x in row] for row in normals])
    e = [read(x) for x in restitution] if restitution else [EPS] * r
    sets = [list(J) for J in cert["sets"]]
    failures = [f"the impulse on {J} is not linear" for J in sets if not _linear(G, J)]
    before, L = [], sp.eye(r)
    for J in sets:
        before.append(L)
        L = sp.Matrix.hstack(*[sp.Matrix(_step(G, e, J, list(L[:, k]))) for k in range(r)])
    frame = sp.Matrix.hstack(*[sp.Matrix([read(x) for x in col]) for col in cert["W"] + cert["U"]])
    B = frame.inv() * L * frame
    s, Q = read(cert["scale"]), sp.Matrix([[read(x) for x in row] for row in cert["form"]])
    failures += [f"M does not keep W and U apart at ({i}, {j})" for i in range(4) for j in range(4)
                 if (i < 2) != (j < 2) and not _field_zero(B[i, j])]  # fmt: skip
    A_W, A_U = B[:2, :2] / s, B[2:, 2:] / s
    failures += [f"det A_{n} is not 1" for n, A in (("W", A_W), ("U", A_U)) if not _field_zero(A.det() - 1)]
    failures += ["A_U does not keep Q" for x in (A_U.T * Q * A_U - Q) if not _field_zero(x)][:1]
    c = frame.inv() * sp.Matrix([read(x) for x in cert["rates"]])
    w, u = c[:2, :], c[2:, :]
    energy, Qi = (u.T * Q * u)[0], Q.inv()
    wanted = [(A_W.trace() - 2, "t - 2", (0, 1)), (s, "s", (1,)), (Q.det(), "det Q", (1,))]
    for k, (J, Lk) in enumerate(zip(sets, before)):
        for i in range(r):
            lf = Lk.row(i) if i in J else -Lk.row(i)
            f0, f1 = (lf * frame[:, :2] * w)[0], (lf * frame[:, :2] * A_W * w)[0]
            gamma2 = energy * (lf * frame[:, 2:] * Qi * (lf * frame[:, 2:]).T)[0]
            name = f"impulse {k}, constraint {i}"
            wanted += [(f0, f"l(w) at {name}", (-1,)), (f1 - f0, f"l(A_W w) - l(w) at {name}", (-1, 0)),
                       (gamma2 - f0**2, f"Gamma^2 - l(w)^2 at {name}", (-1,))]  # fmt: skip
    for x, name, allowed in wanted:  # the first sign that fails is enough to refuse the certificate
        if not _field_signs_within(x, root, interval, closed, allowed):
            return [*failures, f"{name} leaves the signs {allowed} on the interval"]
    return failures


def _field_parts(x: sp.Expr, root: sp.Expr) -> list[tuple[sp.Expr, sp.Expr]]:
    """[(a, b), (c, d)] with x = (a + root b) / (c + root d), polynomials in eps over Q (root = sqrt(d)): x's
    numerator and denominator as SymPy's ``together`` writes them, each split at root."""
    R = sp.Dummy("R")
    out = []
    for part in sp.fraction(sp.together(x)):
        poly = sp.Poly(sp.expand(part).subs(root, R), R)
        square = root**2
        halves = [
            sum((c * square ** (k // 2) for (k,), c in poly.terms() if k % 2 == m), sp.Integer(0)) for m in (0, 1)
        ]
        out.append((sp.expand(halves[0]), sp.expand(halves[1])))
    return out


def _field_zero(x: sp.Expr) -> bool:
    return sp.expand(sp.fraction(sp.radsimp(sp.together(x)))[0]) == 0


def _field_signs_within(
    x: sp.Expr, root: sp.Expr, interval: tuple[sp.Expr, sp.Expr], closed: tuple[bool, bool], allowed: tuple[int, ...]
) -> bool:
    """Whether x = (a + root b)/(c + root d) takes only the ``allowed`` signs on the interval (no pole): checked at
    every real root of a^2 - d b^2 and of c^2 - d d^2 in it, at its ends, and at a rational point between each two."""
    parts = _field_parts(x, root)
    norms = [sp.expand(a * a - b * b * root**2) for a, b in parts]
    lo, hi = interval
    points = [lo, hi]
    for p in norms:
        if sp.Poly(p, EPS).degree() > 0:
            points += [t for t in sp.real_roots(sp.Poly(p, EPS)) if _sign_at(EPS - lo, t) >= 0 >= _sign_at(EPS - hi, t)]
    points = sorted(set(points), key=lambda t: sp.N(t, 60))
    between = [sp.nsimplify(sp.N((s + t) / 2, 40), rational=True) for s, t in itertools.pairwise(points)]
    inside = [t for t in points if (t != lo or closed[0]) and (t != hi or closed[1])] + between

    def half_sign(a: sp.Expr, b: sp.Expr, norm: sp.Expr, t: sp.Expr) -> int:  # a + root b at t, exactly
        sa, sb = _sign_at(a, t), _sign_at(b, t)
        if sb in (0, sa):
            return sa
        if sa == 0:
            return sb
        n = _sign_at(norm, t)
        return 0 if n == 0 else sa if n > 0 else sb

    def sign(t: sp.Expr) -> int | None:
        (a, b), (c, d) = parts
        below = half_sign(c, d, norms[1], t)
        return None if below == 0 else half_sign(a, b, norms[0], t) * below

    return all(sign(t) in allowed for t in inside)
