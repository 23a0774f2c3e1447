"""Every eps above a boundary of two turning pairs exits: the rule run on certified cells of eps.

Five unit balls repeat the period (S1,S3)(S2,S4). Its characteristic polynomial is q1 q2 over Q(sqrt(5))(eps)
(:mod:`verify.maps.turning`), each q_j = lam^2 - tau_j lam + eps^2, and above the boundary eps* both pairs of
roots are complex of modulus eps: the rates, scaled by eps per period, run on a torus, and a run that leaves the
period may follow other impacts and come back to it before it exits. The ellipse argument of
:mod:`verify.maps.leaving` does not apply. Here every eps of an interval is run instead, cell by cell, with
certified signs:

- **The period in closed form.** With c_j = tau_j / (2 eps) = cos(alpha_j) (|c_j| < 1 is checked on the cell),
  A = M/eps keeps A^2 - 2 c_j A + 1 = 0 on ker q_j(M), so A^k = U_{k-1}(c_j) A - U_{k-2}(c_j) there, with
  U_n(cos a) = sin((n + 1) a) / sin(a). The projector on ker q1(M) along ker q2(M) is
  E1 = q2(M)(tau1 - M) / (eps^2 (tau1 - tau2)) (on ker q1, q2(M) = (tau1 - tau2) M and tau1 M - M^2 = eps^2),
  E2 = 1 - E1. So the rates after k periods from y are eps^k sum_j (sin(k alpha_j) A E_j y -
  sin((k - 1) alpha_j) E_j y) / sin(alpha_j): one formula for every k, with no product of k matrices whose
  enclosure would grow with k. A block of periods is checked at once with k a ball.
- **Numbers of a cell.** Every quantity is a :class:`~verify.maps.meanvalue.MeanValue`: its value at the cell's
  midpoint and its derivative in eps on the whole cell, so its enclosure is as wide as it truly spreads over the
  cell (to first order), however many operations made it.
- **The rule, with every branch.** The impulses are the rule's (:func:`verify.dynamics.rates.coefficients`;
  a multiple impact whose Gram block is diagonal is its single impacts, beta = 1 exactly). A sign that the cell
  does not decide is followed both ways: an eps of the cell follows one of the branches, so when every branch
  exits, every eps of the cell exits. A branch knows what it chose: a rate it took as negative is positive after
  its single impact, and a rate it took as non-negative stays so while no impulse moves it.
- **Cells.** :func:`exit_cells` sweeps an interval from below, doubling a cell after a success and halving it
  after a failure; a cell narrower than ``min_width`` that still fails is left undecided.

From the period, a run checks the period's impact sets at every k (blocks of k doubling while they hold); where
they may fail it follows each branch that leaves, up to :data:`TAIL` impulses, and a branch that comes back to
the period starts its closed form again (at most :data:`ENTRIES` times).

>>> from verify.models.cradle import cradle_system
>>> build = lambda K: cradle_system(EPS, 5, backend=K)
>>> period = torus_period(build, Piece.closed("0.27", "0.28"), Pattern(2, ((0, 2), (1, 3))))
>>> period.ext, len(period.taus)
(sqrt(5), 2)
>>> found = exit_cells(period, ["1", "0", "0", "0", "0"], Fraction(27, 100), Fraction(271, 1000))
>>> found.undecided, found.decided == Fraction(1, 1000), found.deepest > 0
([], True, True)
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any, cast

import sympy as sp

from verify import bounds
from verify.dynamics.rates import coefficients
from verify.dynamics.system import System
from verify.errors import InvalidInput
from verify.maps.boundary import LAM, Pattern, characteristic, pattern_map, sympified
from verify.maps.meanvalue import MeanValue, ball, cell, working_precision
from verify.maps.turning import extension, field_factors
from verify.maps.watch import Watch
from verify.numbers.backends.ratfunc import EPS
from verify.numbers.backends.symbolic import Piece, RootCache, SymbolicBackend
from verify.numbers.format import format_decimal

#: impulses a branch may take after it leaves the period before the cell is given up
TAIL = 60
#: times a branch may come back to the period
ENTRIES = 8
#: branches (impulses followed) a cell may take in all
NODES = 20000
#: the most periods followed in one stay in the period
MAX_PERIODS = 10**6
#: the narrowest cell tried: a cell this narrow that fails is left undecided
MIN_WIDTH = Fraction(1, 10**14)
#: cells left undecided before a sweep gives up (no proof)
MAX_UNDECIDED = 64
#: the length left undecided just above the boundary, where the slow pair turns too slowly for the cells
GAP = Fraction(1, 2 * 10**6)

Build = Callable[[SymbolicBackend], System]
#: a rational function of eps with coefficients a + b sqrt(d): (numerator, denominator), each a list of (a, b)
Compiled = tuple[list[tuple[Fraction, Fraction]], list[tuple[Fraction, Fraction]]]


class CellUndecided(Exception):
    """A cell whose run the certified signs do not decide (it is halved)."""


@dataclass
class TorusPeriod:
    """The exact data of a period of two turning pairs: the system's Gram matrix and CORs, the period M on the
    rates (before the pattern's first impact set), sqrt(d) and tau1, tau2 over Q(sqrt(d))(eps), and the system
    itself (on the symbolic backend: it gives the rates of a velocity)."""

    pattern: Pattern
    gram: list[list[Fraction]]
    restitution: list[Any]
    M: sp.Matrix
    ext: Any
    taus: list[Any]
    system: System


def _fraction(x: Any) -> Fraction:
    """A SymPy rational as a Fraction (anything else is refused, never approximated)."""
    x = sp.sympify(x)
    if not x.is_Rational:
        raise InvalidInput(f"not a rational: {x}")
    return Fraction(int(x.p), int(x.q))


def torus_period(build: Build, piece: Piece, pattern: Pattern, cache: RootCache | None = None) -> TorusPeriod | None:
    """The period of ``pattern`` when its characteristic polynomial is q1 q2, two quadratics over Q(sqrt(d))(eps)
    with constant term eps^2 times the leading one (checked exactly), else None (None too for moving
    constraints)."""
    system = build(SymbolicBackend(piece, cache or RootCache()))
    M = pattern_map(system, pattern.sets) if not system.moving else None  # rates of moving constraints: not N v
    if M is None:
        return None
    ext = extension(M)
    if ext is None:
        return None
    quads = field_factors(M, ext)
    if len(quads) != 2 or any(sp.Poly(q, LAM).degree() != 2 for q in quads):
        return None
    taus = []
    for q in quads:
        a2, a1, a0 = sp.Poly(q, LAM).all_coeffs()
        if sp.simplify(a0 / a2 - EPS**2) != 0:
            return None
        taus.append(sp.cancel(-a1 / a2))
    monic = sp.Poly(characteristic(M), LAM)
    product = sp.Poly(sp.expand((LAM**2 - taus[0] * LAM + EPS**2) * (LAM**2 - taus[1] * LAM + EPS**2)), LAM)
    top = monic.all_coeffs()[0]
    if any(sp.simplify(a / top - b) != 0 for a, b in zip(monic.all_coeffs(), product.all_coeffs())):
        return None
    K = system.backend
    try:
        gram = [[_fraction(sympified(K, x)) for x in row] for row in system.gram]
    except InvalidInput:  # masses or normals that are not rational: no cells here
        return None
    restitution = [sp.cancel(sympified(K, x)) for x in system.restitution]
    return TorusPeriod(pattern, gram, restitution, M, ext, taus, system)


def _compile(expr: Any, ext: Any) -> Compiled:
    """``expr``, a rational function of eps over Q(ext), as coefficient lists for :func:`_evaluate`."""
    num, den = sp.fraction(sp.cancel(sp.together(expr)))

    def coefficients_of(p: Any) -> list[tuple[Fraction, Fraction]]:
        out = []
        for c in sp.Poly(sp.expand(p), EPS).all_coeffs():
            c = sp.expand(c)
            a = c.subs(ext, 0)
            out.append((_fraction(a), _fraction(sp.expand((c - a) / ext))))
        return out

    return coefficients_of(num), coefficients_of(den)


#: a compiled rational function's coefficients as balls (a + b sqrt(d), highest degree first): (numerator, denominator)
Balls = tuple[list[Any], list[Any]]


def _balls(f: Compiled, root: Any) -> Balls:
    """The coefficients of ``f`` as balls of the working precision (``root`` the ball of sqrt(d)): the same for
    every cell, so computed once."""
    return [root * ball(b) + ball(a) for a, b in f[0]], [root * ball(b) + ball(a) for a, b in f[1]]


def _evaluate(f: Balls, e: MeanValue) -> MeanValue:
    """The rational function at the cell's eps (Horner's scheme on each part)."""

    def horner(p: list[Any]) -> MeanValue:
        acc = e.constant(p[0])
        for c in p[1:]:
            acc = acc * e + c
        return acc

    return horner(f[0]) / horner(f[1])


@dataclass
class _Evaluators:
    """A :class:`TorusPeriod` compiled for evaluation on cells: the coefficients of its functions as balls."""

    M: list[list[Balls]]
    taus: list[Balls]
    restitution: list[Balls]


def _compiled(period: TorusPeriod) -> _Evaluators:
    """The period's functions compiled (call it in :func:`~verify.maps.meanvalue.working_precision`)."""
    r = len(period.gram)
    root = ball(_fraction(period.ext**2)).sqrt()

    def at(x: Any) -> Balls:
        return _balls(_compile(x, period.ext), root)

    return _Evaluators([[at(period.M[i, j]) for j in range(r)] for i in range(r)], [at(t) for t in period.taus],
                       [at(x) for x in period.restitution])  # fmt: skip


class _RuleOnCell:
    """The system as :func:`~verify.dynamics.rates.coefficients` reads it, in numbers of the cell."""

    def __init__(self, gram: list[list[Fraction]], restitution: list[MeanValue]):
        e0 = restitution[0]
        self.gram = [[e0.constant(x) for x in row] for row in gram]
        self.inverse_gram_diag = [e0.constant(1 / gram[j][j]) for j in range(len(gram))]
        self.minus_one_plus_e = [0 - (e + 1) for e in restitution]
        self.single_coefficient = [m * self.inverse_gram_diag[j] for j, m in enumerate(self.minus_one_plus_e)]
        self.restitution = restitution


class _Cell:
    """One cell of eps: the period's closed form there and the rule's runs with every branch."""

    def __init__(self, period: TorusPeriod, compiled: _Evaluators, lo: Fraction, hi: Fraction):
        self.pattern = period.pattern
        self.G = period.gram
        self.Gb = [[ball(x) for x in row] for row in self.G]
        self.r = len(self.G)
        self.e = e = cell(lo, hi)
        self.rule = _RuleOnCell(self.G, [_evaluate(x, e) for x in compiled.restitution])
        self.M = [[_evaluate(x, e) for x in row] for row in compiled.M]
        taus = [_evaluate(t, e) for t in compiled.taus]
        cosines = [t / (e * 2) for t in taus]
        if not all(c.below(1) for c in cosines):
            raise CellUndecided("a pair of the period's eigenvalues may be real on the cell")
        self.alphas = [c.acos() for c in cosines]
        self.E = self._projectors(taus)
        self.nodes = 0
        self.deepest = 0

    def _matmul(self, A: list[list[MeanValue]], B: list[list[MeanValue]]) -> list[list[MeanValue]]:
        r = self.r
        return [[sum((A[i][k] * B[k][j] for k in range(r)), self.e.constant(0)) for j in range(r)] for i in range(r)]

    def _projectors(self, taus: list[MeanValue]) -> list[list[list[MeanValue]]]:
        r, M, e = self.r, self.M, self.e
        t1, t2 = taus
        e2 = e * e
        one = [[e.constant(1 if i == j else 0) for j in range(r)] for i in range(r)]
        MM = self._matmul(M, M)
        q2 = [[MM[i][j] - M[i][j] * t2 + one[i][j] * e2 for j in range(r)] for i in range(r)]
        shifted = [[one[i][j] * t1 - M[i][j] for j in range(r)] for i in range(r)]
        scale = e2 * (t1 - t2)
        E1 = [[x / scale for x in row] for row in self._matmul(q2, shifted)]
        return [E1, [[one[i][j] - E1[i][j] for j in range(r)] for i in range(r)]]

    def _matvec(self, A: list[list[MeanValue]], x: Sequence[MeanValue]) -> list[MeanValue]:
        return [sum((A[i][j] * x[j] for j in range(self.r)), self.e.constant(0)) for i in range(self.r)]

    def impulse(self, b: list[MeanValue], J: tuple[int, ...]) -> list[MeanValue]:
        """The rates after the rule's impulse on J (eq. 8 through ``coefficients``)."""
        G, rule = self.G, cast(System, self.rule)
        b = list(b)
        if all(G[i][j] == 0 for i in J for j in J if i != j):  # single impacts that commute: beta = 1
            for j in J:
                ((_, c),) = coefficients(rule, b, (j,))[0]
                b = [b[i] + c * self.Gb[i][j] if G[i][j] and i != j else b[i] for i in range(self.r)]
                b[j] = -(self.rule.restitution[j] * b[j])
            return b
        pairs, _ = coefficients(rule, b, J)
        for j, c in pairs:
            b = [b[i] + c * self.Gb[i][j] if G[i][j] else b[i] for i in range(self.r)]
        return b

    def branches(
        self, b: list[MeanValue], steps: int
    ) -> list[tuple[tuple[tuple[int, ...], ...], list[MeanValue], bool]]:
        """Every branch of the rule from the rates ``b`` for ``steps`` impulses: (impact sets, rates, exited)."""
        out = []
        stack: list[tuple[tuple[tuple[int, ...], ...], list[MeanValue], list[bool]]] = [((), b, [False] * self.r)]
        while stack:
            sets, b, known = stack.pop()
            if len(sets) == steps:
                out.append((sets, b, False))
                continue
            signs = [1 if known[i] else b[i].sign() for i in range(self.r)]
            open_ = [i for i in range(self.r) if signs[i] is None]
            if len(open_) > 2:
                raise CellUndecided("more than two signs undecided at once")
            negative = [i for i in range(self.r) if signs[i] == -1]
            for mask in range(1 << len(open_)):
                J = tuple(sorted(negative + [i for t, i in enumerate(open_) if mask >> t & 1]))
                self.nodes += 1
                if self.nodes > NODES:
                    bounds.reached("cell_branches")
                    raise CellUndecided(f"more than {NODES} branches")
                if not J:
                    out.append((sets, b, True))
                    continue
                stack.append(((*sets, J), self.impulse(b, J), self._known(known, open_, J)))
        return out

    def _known(self, known: list[bool], open_: list[int], J: tuple[int, ...]) -> list[bool]:
        """The rates whose sign (non-negative) a branch knows after its impulse on J."""
        G = self.G
        diagonal = all(G[i][j] == 0 for i in J for j in J if i != j)
        out = []
        for i in range(self.r):
            if i in J:
                out.append(diagonal)  # -e_i times a negative rate
            else:
                out.append(all(G[i][j] == 0 for j in J) and (known[i] or i in open_))
        return out

    def run(self, b: list[MeanValue], tail: int = 0, entries: int = 0, *, steps: int = 0) -> None:
        """Prove that every branch from the rates ``b`` exits (else raise :class:`CellUndecided`), looking for the
        period every p impulses (after ``steps`` impulses first, when given: the pattern's start modulo p)."""
        p = len(self.pattern.sets)
        if tail > TAIL:
            bounds.reached("cell_tail")
            raise CellUndecided(f"a branch still impacting {TAIL} impulses after it left the period")
        found = self.branches(b, steps or p)
        if all(exited for _, _, exited in found):
            bounds.use("cell_tail", tail)
        for sets, after, exited in found:
            if exited:
                continue
            if sets == self.pattern.sets:
                if entries >= ENTRIES:
                    bounds.reached("cell_entries")
                    raise CellUndecided(f"a branch came back to the period {ENTRIES} times")
                bounds.use("cell_entries", entries + 1)
                self.period(b, entries + 1)
            else:
                self.run(after, tail + len(sets), entries)

    def _closed(self, y: list[MeanValue]) -> list[tuple[list[MeanValue], list[MeanValue], MeanValue, MeanValue]]:
        parts = []
        for E, alpha in zip(self.E, self.alphas):
            ey = self._matvec(E, y)
            ay = [x / self.e for x in self._matvec(self.M, ey)]
            parts.append((ay, ey, alpha, alpha.sin()))
        return parts

    def _after(self, parts: list[Any], k: Any) -> list[MeanValue]:
        """The rates after k periods, divided by eps^k (k an integer, or a ball of integers)."""
        out = [self.e.constant(0)] * self.r
        for ay, ey, alpha, s in parts:
            now, before = (alpha * k).sin() / s, (alpha * (k - 1)).sin() / s
            out = [out[i] + now * ay[i] - before * ey[i] for i in range(self.r)]
        return out

    def _forms(self, parts: list[Any]) -> _Forms | None:
        """The signs that keep a run in the period, as linear forms of the rates at its start, each evaluated on
        the parts of :meth:`_closed` (l(A E_j y), l(E_j y)), with the sign it must have (-1: hit, 1: not hit);
        None when an impulse of the period is not linear."""
        r, G = self.r, self.G
        columns = [[self.e.constant(1 if i == j else 0) for i in range(r)] for j in range(r)]
        out = []
        for J in self.pattern.sets:
            for i in range(r):
                row = [col[i] for col in columns]
                values = [(self._dot(row, ay), self._dot(row, ey)) for ay, ey, _, _ in parts]
                out.append((values, -1 if i in J else 1))
            if any(G[i][j] for i in J for j in J if i != j):
                return None
            columns = [self.impulse(col, J) for col in columns]
        return _Forms(out, self.e.h)

    def _dot(self, row: list[MeanValue], x: list[MeanValue]) -> MeanValue:
        return sum((a * b for a, b in zip(row[1:], x[1:])), row[0] * x[0])

    def _stays(self, forms: _Forms, parts: list[Any], k: Any) -> bool:
        """Every eps of the cell follows the period at its k-th time (k an integer or a ball of them), certified
        by the signs of the forms alone."""
        weights = []
        for _, _, alpha, s in parts:
            weights += [(alpha * k).sin() / s, -((alpha * (k - 1)).sin() / s)]
        return forms.signs(weights) == forms.wanted

    def period(self, y: list[MeanValue], entries: int) -> None:
        """Follow the period from the rates ``y`` (before its first impact set) while any branch does, and every
        branch that leaves it."""
        parts, k, step = self._closed(y), 1, 1
        # a block that failed is not tried again whole: blocks stay within half its length until its end
        cap, cap_end = MAX_PERIODS, 0
        forms = self._forms(parts)
        arb = type(ball(0))
        while k <= MAX_PERIODS:
            ks = ball(k) if step == 1 else ball(k) + (step - 1) * arb(0.5, 0.5)
            passed = forms is not None and self._stays(forms, parts, ks)
            if not passed:
                try:
                    found = self.branches(self._after(parts, ks), len(self.pattern.sets))
                except CellUndecided:
                    if step == 1:
                        raise
                    found = None
                passed = found is not None and all(sets == self.pattern.sets and not ex for sets, _, ex in found)
            if passed:
                k += step
                if k >= cap_end:
                    cap = MAX_PERIODS
                step = min(step * 2, cap)
                continue
            if step > 1:
                cap, cap_end = step // 2, k + step
                step = step // 2
                continue
            assert found is not None
            stays = False
            for sets, after, exited in found:
                if sets == self.pattern.sets and not exited:
                    stays = True
                elif not exited:
                    self.run(after, len(sets), entries)
            self.deepest = max(self.deepest, k)
            bounds.use("cell_periods", k)
            if not stays:
                return
            k += 1
        bounds.reached("cell_periods")
        raise CellUndecided(f"a branch follows the period for more than {MAX_PERIODS} periods")


class _Forms:
    """The forms of :meth:`_Cell._forms` as three matrices of balls (values at the midpoint, on the cell, slopes),
    a row a form and a column a value: the combination of every form with the same weights is three products of
    a matrix with a vector, made by FLINT (one rounding a dot product); each form's sign as
    :meth:`~verify.maps.meanvalue.MeanValue.sign` gives it."""

    def __init__(self, forms: list[tuple[list[tuple[MeanValue, MeanValue]], int]], h: Any) -> None:
        from flint import arb_mat

        self.h, self.wanted = h, [wanted for _, wanted in forms]
        rows = [[x for pair in values for x in pair] for values, _ in forms]
        self.rows, self.columns = len(rows), len(rows[0])
        self.point, self.value, self.slope = (
            arb_mat(self.rows, self.columns, [getattr(x, part) for row in rows for x in row])
            for part in ("point", "value", "slope")
        )

    def _vector(self, xs: list[Any]) -> Any:
        """A column of ``xs`` (arb_mat: python-flint's matrices of balls)."""
        from flint import arb_mat

        return arb_mat(self.columns, 1, xs)

    def signs(self, weights: list[MeanValue]) -> list[int | None]:
        """The sign of each form combined with ``weights`` (one per column)."""
        vector = self._vector
        point = (self.point * vector([w.point for w in weights])).entries()
        on_cell = vector([w.value for w in weights])
        value = (self.value * on_cell).entries()
        slope = (self.slope * on_cell + self.value * vector([w.slope for w in weights])).entries()
        return [MeanValue(p, v, d, self.h).sign() for p, v, d in zip(point, value, slope)]


@dataclass
class Cells:
    """What :func:`exit_cells` proves on [lower, upper]: every eps of each cell of ``cells`` exits; the cells of
    ``undecided`` (narrower than the least width) are not decided."""

    lower: Fraction
    upper: Fraction
    cells: list[tuple[Fraction, Fraction]]
    undecided: list[tuple[Fraction, Fraction]]
    deepest: int = 0  #: the most periods a branch followed in one stay

    @property
    def decided(self) -> Fraction:
        return sum((b - a for a, b in self.cells), Fraction(0))


def _initial_rates(period: TorusPeriod, velocity: Sequence[Any]) -> list[Fraction]:
    system = period.system
    rates = system.rates(system.velocity(velocity))  # a number that is not one (a binary float) is refused here
    try:
        return [_fraction(sympified(system.backend, x)) for x in rates]
    except InvalidInput:
        raise InvalidInput("the certified cells of eps start from a rational velocity") from None


def exit_cells(
    period: TorusPeriod,
    velocity: Sequence[Any],
    lower: Fraction,
    upper: Fraction,
    *,
    min_width: Fraction = MIN_WIDTH,
    watch: Watch | None = None,
) -> Cells:
    """Sweep [lower, upper] with cells on which every eps exits from ``velocity`` (see the module). A ``watch``'s
    clock or Ctrl-C stops the sweep: what is left is then undecided (``watch.stopped`` says why)."""
    rates = _initial_rates(period, velocity)
    out = Cells(lower, upper, [], [])
    a, width = lower, (upper - lower) / 8
    with working_precision():
        compiled = _compiled(period)
        while a < upper:
            if watch is not None and watch.check():
                out.undecided.append((a, upper))
                break
            b = min(upper, a + width)
            try:
                c = _Cell(period, compiled, a, b)
                c.run([c.e.constant(x) for x in rates], steps=period.pattern.start % len(period.pattern.sets))
            except CellUndecided:
                if b - a >= min_width:
                    width = (b - a) / 2
                    continue
                out.undecided.append((a, b))
                if len(out.undecided) > MAX_UNDECIDED:
                    bounds.reached("cell_undecided")
                    out.undecided.append((b, upper))
                    break
                a = b
                continue
            bounds.use("cell_branches", c.nodes)
            out.cells.append((a, b))
            out.deepest = max(out.deepest, c.deepest)
            a, width = b, width * 2
            if watch is not None and watch.progress is not None and len(out.cells) % 200 == 0:
                watch.progress(f"cells of eps: {len(out.cells)}, up to eps = {format_decimal(a, 12)} of "
                               f"[{format_decimal(lower, 12)}, {format_decimal(upper, 12)}], "
                               f"deepest period {out.deepest}")  # fmt: skip
    return out


def exits_on_cells(
    build: Build,
    velocity: Sequence[Any],
    piece: Piece,
    pattern: Pattern,
    cache: RootCache | None = None,
    *,
    above_boundary: bool = False,
    watch: Watch | None = None,
) -> Cells | None:
    """The cells on which every eps of ``piece`` (whose runs repeat ``pattern`` up to the map's bound) exits, when
    the pattern's period is two turning pairs (:func:`torus_period`), else None; None too when the sweep gives up
    (more than :data:`MAX_UNDECIDED` cells undecided). The cells start at a rational within 1e-15 below the piece,
    or, ``above_boundary`` (the piece's lower end is the boundary eps*), within 1e-15 above eps* + :data:`GAP`;
    they end within 1e-15 above the piece."""
    width = Fraction(1, 10**15)
    lower = piece.lower.narrowed(width)[0] if not above_boundary else piece.lower.narrowed(width)[1] + GAP
    upper = piece.upper.narrowed(width)[1]
    if lower >= upper:
        return None
    period = torus_period(build, Piece.closed(lower, upper), pattern, cache)
    if period is None:
        return None
    found = exit_cells(period, velocity, lower, upper, watch=watch)
    if len(found.undecided) > MAX_UNDECIDED:
        return None
    bounds.use("cell_undecided", len(found.undecided))
    return found
