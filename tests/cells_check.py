"""An independent checker of "exits on cells" certificates: every eps of each cell exits.

Written from the mathematics, without the code that finds the cells (verify.maps.torus, verify.maps.meanvalue) or
the rule: the Gram matrix from the masses and normals, the period P as the product of its single impacts, its
characteristic polynomial factored by SymPy over Q(sqrt(d)), the projectors checked as identities over
Q(sqrt(d))(eps), and on each cell a run of its own:

- a number of the cell is a triple (value at the midpoint, value on the cell, derivative on the cell), balls of
  python-flint, and f(eps) lies in f(m) + f' [-h, h] (the mean value theorem);
- on ker q_j (q_j = lam^2 - tau_j lam + eps^2, tau_j = 2 eps cos a_j), A = P / eps turns by a_j: A^k = cos(k a_j) +
  sin(k a_j) / sin(a_j) (A - cos(a_j)), so the rates after k periods are eps^k sum_j A^k E_j y;
- the impact set is {i : rate_i < 0}; an undecided sign is followed both ways; a rate taken as negative is
  positive after its single impact, one taken as non-negative stays so while no impulse moves it;
- a cell this checker cannot decide is halved, a few times, before it is refused.
"""

from __future__ import annotations

from fractions import Fraction

import sympy as sp
from flint import arb, ctx

EPS, LAM = sp.Symbol("eps"), sp.Symbol("lam")


class _N:
    """(point, value, slope) on a cell whose half-width ball is ``h``."""

    __slots__ = ("d", "h", "p", "v")

    def __init__(self, p, v, d, h):
        self.p, self.v, self.d, self.h = p, v, d, h

    def c(self, x):
        x = x if isinstance(x, arb) else (arb(x.numerator) / x.denominator if isinstance(x, Fraction) else arb(x))
        return _N(x, x, arb(0), self.h)

    def _o(self, o):
        return o if isinstance(o, _N) else self.c(o)

    def __add__(self, o):
        o = self._o(o)
        return _N(self.p + o.p, self.v + o.v, self.d + o.d, self.h)

    def __sub__(self, o):
        o = self._o(o)
        return _N(self.p - o.p, self.v - o.v, self.d - o.d, self.h)

    def __mul__(self, o):
        o = self._o(o)
        return _N(self.p * o.p, self.v * o.v, self.d * o.v + self.v * o.d, self.h)

    def __truediv__(self, o):
        o = self._o(o)
        q = self.v / o.v
        return _N(self.p / o.p, q, (self.d - q * o.d) / o.v, self.h)

    def sin(self):
        return _N(self.p.sin(), self.v.sin(), self.v.cos() * self.d, self.h)

    def cos(self):
        return _N(self.p.cos(), self.v.cos(), -self.v.sin() * self.d, self.h)

    def acos(self):
        return _N(self.p.acos(), self.v.acos(), -self.d / (1 - self.v * self.v).sqrt(), self.h)

    def sign(self):
        if self.p == 0 and self.v == 0 and self.d == 0:
            return 0
        e = self.p + self.d * self.h
        e = e.intersection(self.v) if e.overlaps(self.v) else e
        return 1 if e > 0 else -1 if e < 0 else None


class Refused(Exception):
    pass


def _gram(masses, normals):
    N = sp.Matrix(normals)
    return N * sp.diag(*masses).inv() * N.T


def period_data(masses, normals, sets):
    """(G, P, root, taus, E1) over Q(root)(eps), every identity checked exactly."""
    G = _gram(masses, normals)
    r = G.shape[0]
    P = sp.eye(r)
    for J in sets:
        if any(G[i, j] != 0 for i in J for j in J if i != j):
            raise Refused(f"the impulse on {J} is not a product of single impacts")
        for j in J:
            T = sp.eye(r)
            T[:, j] = T[:, j] - (1 + EPS) / G[j, j] * G[:, j]
            P = T * P
    P = P.applyfunc(sp.cancel)
    chi = sp.factor(P.charpoly(LAM).as_expr())
    root = None
    for d in (2, 3, 5, 6, 7, 10, 11, 13):
        quads = [f for f, _ in sp.factor_list(chi, LAM, EPS, extension=sp.sqrt(d))[1] if sp.Poly(f, LAM).degree() > 0]
        if len(quads) == 2 and all(sp.Poly(f, LAM).degree() == 2 for f in quads):
            root = sp.sqrt(d)
            break
    if root is None:
        raise Refused("the period's characteristic polynomial is not two quadratics over a quadratic field")
    taus = []
    for f in quads:
        a2, a1, a0 = sp.Poly(f, LAM).all_coeffs()
        if sp.simplify(a0 / a2 - EPS**2) != 0:
            raise Refused("a quadratic factor's roots do not have product eps^2")
        taus.append(sp.simplify(-a1 / a2))
    q = [P * P - t * P + EPS**2 * sp.eye(r) for t in taus]
    E1 = (q[1] * (taus[0] * sp.eye(r) - P) / (EPS**2 * (taus[0] - taus[1]))).applyfunc(sp.cancel)
    E2 = sp.eye(r) - E1
    for name, X in (("q1(P) E1", q[0] * E1), ("q2(P) E2", q[1] * E2), ("E1^2 - E1", E1 * E1 - E1)):
        if any(sp.simplify(sp.radsimp(x)) != 0 for x in X):
            raise Refused(f"{name} is not 0")
    return G, P, root, taus, E1


def _evaluator(expr, root):
    num, den = sp.fraction(sp.cancel(sp.together(expr)))

    def coeffs(p):
        out = []
        for c in sp.Poly(sp.expand(p), EPS).all_coeffs():
            c = sp.expand(c)
            a = c.subs(root, 0)
            b = sp.expand((c - a) / root)
            assert a.is_Rational and b.is_Rational, (a, b)
            out.append((Fraction(int(a.p), int(a.q)), Fraction(int(b.p), int(b.q))))
        return out

    return coeffs(num), coeffs(den)


def _at(f, e, s):
    def h(cs):
        acc = e.c(0)
        for a, b in cs:
            acc = acc * e + s * e.c(b) + e.c(a)
        return acc

    return h(f[0]) / h(f[1])


class _Check:
    def __init__(self, data, lo, hi, sets, tail=60):
        G, _P, _root, _taus, E1 = data["G"], data["P"], data["root"], data["taus"], data["E1"]
        self.G = [[Fraction(str(x)) for x in row] for row in G.tolist()]
        self.r, self.sets, self.tail, self.count = len(self.G), tuple(tuple(J) for J in sets), tail, 0
        a, b = arb(lo.numerator) / lo.denominator, arb(hi.numerator) / hi.denominator
        h = (b - a) / 2 * arb(0, 1)
        m = (a + b) / 2
        self.e = e = _N(m, m + h, arb(1), h)
        s = e.c(arb(data["d"]).sqrt())
        self.P = [[_at(f, e, s) for f in row] for row in data["P_c"]]
        E1 = [[_at(f, e, s) for f in row] for row in data["E1_c"]]
        E2 = [[e.c(1 if i == j else 0) - E1[i][j] for j in range(self.r)] for i in range(self.r)]
        self.E = (E1, E2)
        self.cos = [_at(f, e, s) / (e * 2) for f in data["taus_c"]]
        for c in self.cos:
            if not abs(c.p + c.d * c.h) < 1 or not abs(c.v) < 1:
                raise Refused("a pair of the period's eigenvalues may be real on the cell")
        self.angles = [c.acos() for c in self.cos]

    def constants(self):
        """G as numbers of the cell, 1 + e and -e: the single kicks' (the same numbers each time)."""
        if not hasattr(self, "_constants"):
            e = self.e
            self._constants = ([[e.c(x) for x in row] for row in self.G], e + 1, e.c(0) - e)
        return self._constants

    def mv(self, A, x):
        return [sum((A[i][j] * x[j] for j in range(self.r)), self.e.c(0)) for i in range(self.r)]

    def kick(self, b, J):
        G, e, b = self.G, self.e, list(b)
        if all(G[i][j] == 0 for i in J for j in J if i != j):
            Gc, plus, minus = self.constants()
            for j in J:
                c = b[j] * plus / Gc[j][j]
                b = [b[i] - c * Gc[i][j] if i != j else b[i] * minus for i in range(self.r)]
            return b
        lam = {j: b[j] / G[j][j] for j in J}
        beta = sum((b[j] * lam[j] for j in J), e.c(0)) / sum((lam[i] * lam[j] * G[i][j] for i in J for j in J), e.c(0))
        c = {j: beta * (e + 1) * lam[j] for j in J}
        return [b[i] - sum((c[j] * G[i][j] for j in J), e.c(0)) for i in range(self.r)]

    def paths(self, b, steps):
        out, todo = [], [((), b, [False] * self.r)]
        while todo:
            sets, b, known = todo.pop()
            if len(sets) == steps:
                out.append((sets, b, False))
                continue
            sg = [1 if known[i] else b[i].sign() for i in range(self.r)]
            free = [i for i in range(self.r) if sg[i] is None]
            if len(free) > 3:
                raise Refused("too many undecided signs")
            for choice in range(1 << len(free)):
                J = tuple(
                    sorted(
                        [i for i in range(self.r) if sg[i] == -1] + [i for t, i in enumerate(free) if choice >> t & 1]
                    )
                )
                self.count += 1
                if self.count > 100000:
                    raise Refused("too many branches")
                if not J:
                    out.append((sets, b, True))
                    continue
                single = all(self.G[i][j] == 0 for i in J for j in J if i != j)
                nk = [single if i in J else (known[i] or i in free) and all(self.G[i][j] == 0 for j in J)
                      for i in range(self.r)]  # fmt: skip
                todo.append(((*sets, J), self.kick(b, J), nk))
        return out

    def run(self, b, tail=0, entries=0):
        if tail > self.tail or entries > 8:
            raise Refused("a branch does not exit soon enough")
        for sets, after, exited in self.paths(b, len(self.sets)):
            if exited:
                continue
            if sets == self.sets:
                self.follow(b, entries + 1)
            else:
                self.run(after, tail + len(sets), entries)

    def planes(self, y):
        """For each turning pair: z = E y, (A - cos(a)) z and sin(a), which the powers of A combine."""
        out = []
        for E, a, c in zip(self.E, self.angles, self.cos):
            z = self.mv(E, y)
            Az = [x / self.e for x in self.mv(self.P, z)]
            out.append((a, z, [Az[i] - c * z[i] for i in range(self.r)], a.sin()))
        return out

    def powers(self, planes, k):
        out = [self.e.c(0)] * self.r
        for a, z, turned, s in planes:
            ck, sk = (a * k).cos(), (a * k).sin() / s
            out = [out[i] + ck * z[i] + sk * turned[i] for i in range(self.r)]
        return out

    def follow(self, y, entries):
        planes = self.planes(y)
        k, step, cap, cap_end = 1, 1, 10**6, 0  # a block that failed: blocks within half of it up to its end
        while k < 10**6:
            ks = arb(k) if step == 1 else arb(k) + (step - 1) * arb(0.5, 0.5)
            try:
                found = self.paths(self.powers(planes, ks), len(self.sets))
            except Refused:
                if step == 1:
                    raise
                found = None
            if found is not None and all(s == self.sets and not x for s, _, x in found):
                k += step
                cap = cap if k < cap_end else 10**6
                step = min(step * 2, cap)
                continue
            if step > 1:
                cap, cap_end = step // 2, k + step
                step = step // 2
                continue
            stays = False
            for s, after, x in found:
                if x:
                    continue
                if s == self.sets:
                    stays = True
                else:
                    self.run(after, len(s), entries)
            if not stays:
                return
            k += 1
        raise Refused("a branch stays in the period")


def prepare(masses, normals, sets):
    """The period's data, checked exactly, compiled for the cells."""
    G, P, root, taus, E1 = period_data(masses, normals, sets)
    r = G.shape[0]
    return {"G": G, "P": P, "root": root, "taus": taus, "E1": E1, "d": int(root**2),
            "P_c": [[_evaluator(P[i, j], root) for j in range(r)] for i in range(r)],
            "E1_c": [[_evaluator(E1[i, j], root) for j in range(r)] for i in range(r)],
            "taus_c": [_evaluator(t, root) for t in taus]}  # fmt: skip


def check_cells(cells, masses, normals, velocity, sets, *, halvings=4, data=None):
    """What fails in a list of cells [[lo, hi], ...] (strings) claimed to exit from ``velocity``: [] when every
    cell is proved here."""
    before = ctx.prec
    ctx.prec = 160
    try:
        data = data or prepare(masses, normals, sets)
        rates = [sum((Fraction(n) * Fraction(v) for n, v in zip(row, velocity)), Fraction(0)) for row in normals]
        failures = []
        for lo, hi in cells:
            todo = [(Fraction(lo), Fraction(hi), 0)]
            while todo:
                a, b, depth = todo.pop()
                try:
                    c = _Check(data, a, b, sets)
                    c.run([c.e.c(x) for x in rates])
                except Refused as why:
                    if depth >= halvings:
                        failures.append(f"[{lo}, {hi}]: {why}")
                        break
                    m = (a + b) / 2
                    todo += [(a, m, depth + 1), (m, b, depth + 1)]
        return failures
    finally:
        ctx.prec = before
