"""The rule on intervals with an enclosure that does not widen with the run: one ball in rates.

Component-wise interval arithmetic (:mod:`verify.numbers.backends.precision`) loses about half a
digit per impulse to the dependency problem, so long runs climb in precision: the long run
of ``verify bench`` reaches 6,400 digits at 10,000 impulses. Here the same certified rule
runs at the backend's starting precision however long the run is.

*Rate coordinates.* The rule acts on the r rates ``b = p(F)`` (eq. 2) through the Gram
matrix G alone: an impulse ``sum_j c_j U_j`` (eq. 8) changes them by ``b += G c``, with
``c_j = -(1 + e_j) b_j / G_jj`` for a single impact on j (rate j becomes exactly
``-e_j b_j``) and ``c_j = -beta (1 + e_j) b_j / G_jj`` for a multiple one (beta from
the rates, as :func:`verify.laws.rule.beta_from_rates`). Moving constraints only shift the
rates: the dynamics on b is the same. The velocity is not carried along: only the sum ``mu``
of the coefficients, and the exit velocity is ``v0 + U^T G^-1 (b - b0)``, computed once at
the end (see :func:`_velocity`).

*One ball.* The state is a midpoint ``m`` (integers ``M`` in units of ``2^-P``: fixed
point, a few guard digits beyond the backend's precision) and ONE radius ``rho`` in the
norm ``||d||^2 = d^T G^-1 d``, in which the exact rates lie. This is the kinetic-energy
norm of the velocity ``U^T G^-1 d`` that moves the rates by d (``U g U^T = G``).

*Why the radius does not grow.* A single impact on j is the linear map
``T = I - (1 + e_j) G e_j e_j^T / G_jj``; it is self-adjoint for the inner product
``<x, y> = x^T G^-1 y`` (``G T^T G^-1 = T``), with eigenvalue ``-e_j`` on ``G e_j`` and 1 on
its orthogonal complement ``{x_j = 0}``: with ``0 <= e_j <= 1`` it does not expand, so the
image of the ball lies in the ball of the same radius around ``T m``. The radius grows only
by the rounding error of computing ``T m`` (and the widths of the system's own interval
constants), bounded once per system by ``A_j |m_j| + B_j`` (:func:`ball_data`): an error
added per impulse, never a factor, so the run keeps its digits and the cost of an impulse
(a few integer products) stays the same however long the run. A multiple impact whose
``G_JJ`` is diagonal is the product of its commuting single impacts (beta = 1): the same.
A general multiple impact is not linear (beta depends on b): the mean-value form
``Phi(b) - Phi(m) = (mean of the Jacobian) (b - m)`` bounds it by ``Lambda rho`` plus the
rounding of ``Phi(m)``, Lambda a certified bound of the norm of every Jacobian over the box
that encloses the ball (``|b_i - m_i| <= sqrt(G_ii) rho``, Cauchy-Schwarz; see
:func:`lipschitz_bound`). Lambda is the map's own sensitivity, most often about 1 but larger
where beta varies fast with b (up to tens in drawn systems): such impulses cost
``log10(Lambda)`` digits each, and about a millisecond.

*Signs.* Rate i is negative (or positive) when ``|m_i| > sqrt(G_ii) rho``; a rate that the
structure of the impulses makes exactly 0 (a single impact with COR 0 on i; a constraint
with ``G_ij = 0`` for every j hit keeps its rate and its knowledge) has sign 0 whatever rho
is, as in :func:`verify.laws.rule._structure`. Another undecided sign asks the ``exact``
callback (which returns 0 for an exact 0, else raises) or raises
:class:`~verify.errors.Undecided`, and :func:`verify.laws.rule.solve` raises the precision.

>>> from verify.numbers.backends import IntervalBackend
>>> from verify.dynamics.system import System
>>> s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], ["1/2", "1/2"],
...            backend=IntervalBackend(20))
>>> out = iterate(s, s.velocity(["100", "0", "0"]), Limits(10))
>>> out.impact_sets, out.stop, [s.backend.to_decimal(x, 12) for x in out.v]
([(0,), (1,), (0,)], 'exit', ['20.3125000000', '23.4375000000', '56.2500000000'])

The corner of slope 1/10000 (all CORs 1): 4,000 impulses at 20 digits, and 12 digits of the
velocity still certified (exactly, 0.6963957919509090...), where component-wise intervals
climb to thousands of digits.

>>> from verify.models.corner import corner_system
>>> c = corner_system("1/10000", 1, 1, backend=IntervalBackend(20))
>>> run = iterate(c, c.velocity(["1", "1/30000", "0"]), Limits(4000))
>>> run.stop, len(run.impact_sets), c.backend.dps, c.backend.to_decimal(run.v[0], 12)
('max_iterations', 4000, 20, '0.696395791951')
"""

from __future__ import annotations

import math
import weakref
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import mpmath

from verify.dynamics.policy import Limits, Run, Stop
from verify.dynamics.system import System, known_zero
from verify.errors import Undecided
from verify.numbers.backends import Backend, IntervalBackend
from verify.numbers.format import counted, format_decimal
from verify.numbers.linalg import NotPositiveDefinite, ldl, solve_spd

try:  # GMP rationals where installed: the exact bounds of the set-up are faster (verify bench measures it)
    from gmpy2 import mpq as _rational
except ImportError:  # pragma: no cover - exercised where gmpy2 is absent
    _rational = Fraction

#: an exact rational: gmpy2's mpq, or a Fraction without gmpy2 (the same operations)
Rational = Any
#: binary64 estimates of eigenvalues (53 bits), in an mpmath context of its own: the same on every install
_ESTIMATE = mpmath.MPContext()
_ESTIMATE.prec = 53

#: decimal digits of the fixed-point midpoint (and of the multiple-impulse arithmetic) beyond the backend's
GUARD_DIGITS = 10
#: mantissa bits of the rigorous upper bounds (error constants, square roots)
BOUND_BITS = 48

#: ``exact(system, impact_sets, i, exc)``: 0 when rate i after ``impact_sets`` is exactly 0, else raises
#: Undecided (the contract of ``verify.laws.rule._ExactRates``)
ExactCheck = Callable[[System, Sequence[tuple[int, ...]], int, Undecided], int]

Pair = tuple[int, int]  #: a number ``q 2^-s`` (s >= 0) as ``(q, s)``


# -- exact bounds ---------------------------------------------------------------------------------


def _exact(raw: tuple[int, int, int, int]) -> Rational:
    """The exact value of a raw mpmath number ``(sign, mantissa, exponent, bits)``."""
    sign, man, exp, _ = raw
    if not man and exp:
        raise Undecided("an unbounded interval (a division by an interval around 0)")
    value = _rational(int(man) << exp) if exp >= 0 else _rational(int(man), 1 << -exp)
    return -value if sign else value


def _bounds(x: Any) -> tuple[Rational, Rational]:
    """The exact endpoints of an interval (Undecided for an unbounded one)."""
    lo, hi = x._mpi_
    return _exact(lo), _exact(hi)


def _exponent(x: Rational) -> int:
    """An integer e with ``2^(e-1) < |x| < 2^(e+1)`` (x non-zero)."""
    return x.numerator.bit_length() - x.denominator.bit_length() if x > 0 else _exponent(-x)


def _scaled(x: Rational, bits: int) -> tuple[Rational, int]:
    """``(x 2^s, s)`` with s >= 0 and ``|x| 2^s`` about ``2^bits`` (or larger when s = 0)."""
    s = max(bits - _exponent(x), 0) if x else 0
    return x * (1 << s), s


def _upper(x: Rational, bits: int = BOUND_BITS) -> Pair:
    """``(q, s)`` with ``q 2^-s >= x >= 0``, q of about ``bits`` bits."""
    y, s = _scaled(x, bits)
    return math.ceil(y), s


def _sqrt_upper(x: Rational, bits: int = BOUND_BITS) -> Rational:
    """A rational upper bound of ``sqrt(x)`` (x >= 0), within a relative ``2^-bits``."""
    if x <= 0:
        return _rational(0)
    t = max(bits - _exponent(x) // 2, 0)
    n = math.ceil(x * (1 << (2 * t)))
    root = math.isqrt(n)
    if root * root < n:
        root += 1
    return _rational(root, 1 << t)


def _approx(x: Any, bits: int) -> tuple[Pair, Rational]:
    """An interval constant as ``(q, s)`` near its midpoint, and a bound ``delta`` of the distance
    from ``q 2^-s`` to every point of the interval (so to the true value it encloses)."""
    lo, hi = _bounds(x)
    y, s = _scaled((lo + hi) / 2, bits)
    q = round(y)
    value = _rational(q, 1 << s)
    return (q, s), max(hi - value, value - lo)


def _abs_upper(x: Any) -> Rational:
    lo, hi = _bounds(x)
    return max(-lo, hi)


def _ceil_mul(pair: Pair, n: int) -> int:
    """``ceil(q 2^-s n)`` for ``n >= 0``."""
    q, s = pair
    return -((-q * n) >> s)


# -- the constants of a system ------------------------------------------------------------------


#: the backends with guard digits, by precision (an mpmath context is slow to make; they hold no state)
_WIDE: dict[int, IntervalBackend] = {}


def _wide_backend(dps: int) -> IntervalBackend:
    W = _WIDE.get(dps)
    if W is None:
        W = _WIDE[dps] = IntervalBackend(dps)
    return W


@dataclass(frozen=True)
class Wide:
    """The constants of the general multiple impulses, on a backend with guard digits."""

    backend: IntervalBackend
    gram: tuple[tuple[Any, ...], ...]
    inverse: tuple[tuple[Any, ...], ...]
    one_plus_e: tuple[Any, ...]


@dataclass
class BallData:
    """The constants of the ball engine for one system on an interval backend (see the module).

    For a single impact on j: ``kappa[j]`` approximates ``-(1 + e_j) / G_jj``, ``own[j]``
    approximates ``-e_j`` (the new rate j), ``column[j]`` lists ``(i, G_ij)`` for the i != j
    with ``G_ij`` not known to be 0; ``growth[j]`` and ``offset[j]`` bound the radius added by
    the impulse, ``A_j |M_j| + B_j`` units. ``root[i]`` bounds ``sqrt(G_ii)`` (signs and
    boxes); ``spread[k]`` bounds ``sqrt((U^T G^-1 U)_kk)``, the error of velocity component k
    per unit of radius. ``wide`` is built with the first general multiple impulse.
    """

    bits: int
    couplings: tuple[frozenset[int], ...]
    kappa: tuple[Pair, ...]
    own: tuple[Pair, ...]
    own_zero: tuple[bool, ...]
    column: tuple[tuple[tuple[int, int, int], ...], ...]
    growth: tuple[Pair, ...]
    offset: tuple[int, ...]
    root: tuple[Pair, ...]
    inverse_abs: tuple[tuple[Rational, ...], ...]  #: entry-wise upper bounds of |G^-1|
    inverse: tuple[tuple[Any, ...], ...]  #: an enclosure of G^-1 (backend elements)
    spread: tuple[Rational, ...]
    wide: Wide | None = None

    def widened(self, system: System) -> Wide:
        """The constants of the general multiple impulses (built once)."""
        if self.wide is None:
            K = _interval(system)
            W = _wide_backend(K.dps + GUARD_DIGITS)
            c = W.ctx.convert
            self.wide = Wide(
                W,
                tuple(tuple(c(x) for x in row) for row in system.gram),
                tuple(tuple(c(x) for x in row) for row in self.inverse),
                tuple(W.one + c(e) for e in system.restitution),
            )
        return self.wide


def _interval(system: System) -> IntervalBackend:
    """The system's backend, which must be the interval backend."""
    K = system.backend
    if not isinstance(K, IntervalBackend):
        raise ValueError(f"the ball engine runs on the interval backend, not on {K.describe()}")
    return K


def norm_bound(inverse_abs: Sequence[Sequence[Rational]], w: Sequence[Rational]) -> Rational:
    """An upper bound of ``||d|| = sqrt(d^T G^-1 d)`` over the box ``|d_i| <= w_i``, given
    entry-wise upper bounds ``inverse_abs`` of ``|G^-1|``."""
    A = inverse_abs
    total = sum((A[i][k] * wi * wk for i, wi in enumerate(w) if wi for k, wk in enumerate(w) if wk), _rational(0))
    return _sqrt_upper(total)


def _inverse(K: Backend, gram: Sequence[Sequence[Any]]) -> tuple[tuple[Any, ...], ...]:
    """An enclosure of ``G^-1`` (an LDL^T solve per column, in interval arithmetic)."""
    r = len(gram)
    factors = ldl(K, gram)
    columns = [solve_spd(K, factors, [K.one if i == k else K.zero for i in range(r)]) for k in range(r)]
    return tuple(tuple(columns[k][i] for k in range(r)) for i in range(r))


#: the constants of each system, computed when first needed (held while the system lives)
_DATA: weakref.WeakKeyDictionary[System, BallData] = weakref.WeakKeyDictionary()


def ball_data(system: System) -> BallData:
    """The constants of a system on an interval backend (computed once, cached).

    The radius bound of a single impact on j: with ``u = 2^-P`` (a unit of the midpoint) and
    the true constants within ``delta`` of their approximations, the computed midpoint
    ``m'`` differs from the exact image ``T m`` by at most, component-wise,

    - ``|m_j| delta(e_j) + u`` in component j (``m'_j = -e_j m_j`` rounded down),
    - ``|m_j| (|G_ij| delta(kappa_j) + delta(G_ij) (|kappa_j| + delta(kappa_j))) + u (1 + delta(G_ij)
      + |G_ij|)`` in a component i != j with ``G_ij`` not known to be 0 (``c = kappa_j m_j`` and
      ``G_ij c`` each rounded down once), and 0 in the others;

    that is ``|m_j| a + u b``; split the error accordingly and bound each part in the norm.
    """
    cached = _DATA.get(system)
    if cached is not None:
        return cached
    K = _interval(system)
    r, n, G = system.r, system.n, system.gram
    bits = int(K.ctx.prec) + math.ceil(GUARD_DIGITS * math.log2(10))
    couplings = tuple(frozenset(k for k in range(r) if k == i or not known_zero(K, G[i][k])) for i in range(r))
    inverse = _inverse(K, G)
    inverse_abs = tuple(tuple(_abs_upper(x) for x in row) for row in inverse)
    kappa, own, own_zero, column, growth, offset = [], [], [], [], [], []
    for j in range(r):
        qk, dk = _approx(system.single_coefficient[j], bits)
        minus_e = K.zero - system.restitution[j]
        qe, de = _approx(minus_e, bits)
        kappa.append(qk)
        own.append(qe)
        own_zero.append(known_zero(K, minus_e))
        abs_k = _abs_upper(system.single_coefficient[j])
        a = [_rational(0)] * r
        b = [_rational(0)] * r
        a[j], b[j] = de, _rational(1)
        entries = []
        for i in range(r):
            if i == j or i not in couplings[j]:
                continue
            qg, dg = _approx(G[i][j], bits)
            entries.append((i, *qg))
            g = _abs_upper(G[i][j])
            a[i] = g * dk + dg * (abs_k + dk)
            b[i] = 1 + dg + g
        column.append(tuple(entries))
        growth.append(_upper(norm_bound(inverse_abs, a)))
        offset.append(math.ceil(norm_bound(inverse_abs, b)))
    root = tuple(_upper(_sqrt_upper(_abs_upper(G[i][i]))) for i in range(r))
    spread = []
    for k in range(n):
        total = K.zero
        for i in range(r):
            for j in range(r):
                total = total + system.U[i][k] * inverse[i][j] * system.U[j][k]
        spread.append(_sqrt_upper(_abs_upper(total)))
    data = BallData(
        bits,
        couplings,
        tuple(kappa),
        tuple(own),
        tuple(own_zero),
        tuple(column),
        tuple(growth),
        tuple(offset),
        root,
        inverse_abs,
        inverse,
        tuple(spread),
    )
    _DATA[system] = data
    return data


# -- the general multiple impulse -----------------------------------------------------------------


@dataclass(frozen=True)
class _Impulse:
    """A multiple impulse on J evaluated on the wide backend (eq. 8 in rates)."""

    rates: list[Any]  #: b' = b + G[:, J] c
    beta: Any
    c: dict[int, Any]
    lam: dict[int, Any]  #: lambda_j = b_j / G_jj
    norm: Any  #: N = lambda^T G_JJ lambda


def _phi(wide: Wide, b: Sequence[Any], J: tuple[int, ...]) -> _Impulse:
    """The multiple impulse on J from rates ``b`` (intervals of the wide backend)."""
    W, G = wide.backend, wide.gram
    lam = {j: b[j] / G[j][j] for j in J}
    S = W.zero
    N = W.zero
    for j in J:
        S = S + b[j] * lam[j]
        N = N + lam[j] * sum((G[j][k] * lam[k] for k in J), W.zero)
    if W.sign(N) <= 0:  # raises Undecided when N straddles 0
        raise Undecided("the norm of the sum of the orthogonal components is not certified positive")
    beta = S / N
    c = {j: W.zero - beta * wide.one_plus_e[j] * lam[j] for j in J}
    out = [b[i] + sum((G[i][j] * c[j] for j in J), W.zero) for i in range(len(b))]
    return _Impulse(out, beta, c, lam, N)


def _jacobian(wide: Wide, box: Sequence[Any], J: tuple[int, ...]) -> tuple[list[list[Any]], Any]:
    """An interval matrix containing the Jacobian of the multiple impulse on J at every point
    of ``box``, and an enclosure of beta there.

    With ``lambda = b_J / G_jj``, ``N = lambda^T G_JJ lambda``, ``beta = sum b_j lambda_j / N``:
    ``d beta / d lambda_k = (2 / N) (b_k - beta (G_JJ lambda)_k)`` and
    ``d c_j / d b_k = -(1 + e_j) (beta delta_jk + lambda_j d beta / d lambda_k) / G_kk``.
    """
    W, G = wide.backend, wide.gram
    r = len(box)
    at = _phi(wide, box, J)
    beta, lam = at.beta, at.lam
    two_over_n = (W.one + W.one) / at.norm
    slope = {k: two_over_n * (box[k] - beta * sum((G[k][l] * lam[l] for l in J), W.zero)) for k in J}
    jac = [[W.one if i == k else W.zero for k in range(r)] for i in range(r)]
    for k in J:
        dc = {j: W.zero - wide.one_plus_e[j] * ((beta if j == k else W.zero) + lam[j] * slope[k]) / G[k][k] for j in J}
        for i in range(r):
            jac[i][k] = jac[i][k] + sum((G[i][j] * dc[j] for j in J), W.zero)
    return jac, beta


def _mid(x: Any) -> Rational:
    lo, hi = _bounds(x)
    return (lo + hi) / 2


def _enclose(ctx: Any, x: Rational) -> Any:
    """An interval of ``ctx`` that contains the rational x."""
    return ctx.mpf(x.numerator) / ctx.mpf(x.denominator)


def lipschitz_bound(wide: Wide, jac: Sequence[Sequence[Any]]) -> Rational:
    """An upper bound of ``||M||`` (the operator norm for ``d^T G^-1 d``) for every M in the
    interval matrix ``jac``: ``sqrt(s)`` with ``s G^-1 - M^T G^-1 M`` certified positive definite,
    s a little above the largest generalised eigenvalue found in floats; else the square root of
    the trace of ``G M^T G^-1 M`` (the Frobenius norm of ``L^-1 M L`` for G = L L^T)."""
    W, Gi, G = wide.backend, wide.inverse, wide.gram
    r = len(jac)
    MtGi = [[sum((jac[l][i] * Gi[l][k] for l in range(r)), W.zero) for k in range(r)] for i in range(r)]
    Q = [[sum((MtGi[i][l] * jac[l][k] for l in range(r)), W.zero) for k in range(r)] for i in range(r)]
    fallback = _abs_upper(sum((G[i][l] * Q[l][i] for i in range(r) for l in range(r)), W.zero))
    try:  # the estimate in binary64 of mpmath (its own context): the same bits on every install
        Gf = _ESTIMATE.matrix([[float(_mid(x)) for x in row] for row in G])
        Qf = _ESTIMATE.matrix([[float(_mid(x)) for x in row] for row in Q])
        top = float(max(abs(e) for e in _ESTIMATE.eig(Gf * Qf, left=False, right=False)))
    except (ArithmeticError, ValueError, RuntimeError):  # no convergence: the certified fallback
        top = math.nan
    if not math.isfinite(top):
        return _sqrt_upper(fallback)
    candidate = _rational(top) * (1 + _rational(1, 1 << 20)) + _rational(1, 1 << 40)
    if candidate >= fallback:
        return _sqrt_upper(fallback)
    s = _enclose(W.ctx, candidate)
    try:
        ldl(W, [[s * Gi[i][k] - Q[i][k] for k in range(r)] for i in range(r)])
    except (NotPositiveDefinite, Undecided):
        return _sqrt_upper(fallback)
    return _sqrt_upper(candidate)


# -- the run ----------------------------------------------------------------------------------------


def _no_size() -> int:
    return 0  # fixed precision: no size budget applies (as K.size on interval backends)


@dataclass
class _Ball:
    """The state of a run: the midpoint rates ``M u`` and coefficients ``mu u`` (fixed point, unit
    ``u = 2^-P``), the radius ``rho u`` (an integer rounded up) and the rates known to be 0."""

    M: list[int]
    mu: list[int]
    rho: int
    P: int
    zero: list[bool]

    @property
    def unit(self) -> Rational:
        return _rational(1, 1 << self.P) if self.P >= 0 else _rational(1 << -self.P)


def _start(data: BallData, boxes: Sequence[tuple[Rational, Rational]]) -> _Ball:
    """The ball of the rates of the left velocity: around their midpoints, over their intervals."""
    mids = [(lo + hi) / 2 for lo, hi in boxes]
    top = max(abs(x) for x in mids)
    P = data.bits - _exponent(top) if top else data.bits
    ball = _Ball([], [0] * len(boxes), 0, P, [lo == hi == 0 for lo, hi in boxes])
    unit = ball.unit
    ball.M = [round(x / unit) for x in mids]
    w = [max(hi - m * unit, m * unit - lo) for m, (lo, hi) in zip(ball.M, boxes)]
    ball.rho = math.ceil(norm_bound(data.inverse_abs, w) / unit)
    return ball


def iterate(system: System, v: tuple[Any, ...], limits: Limits, *, exact: ExactCheck | None = None) -> Run:
    """Run the rule from ``v`` (interval backend elements) as :func:`verify.laws.rule.solve` does
    without a trace or stop tests, within ``limits``, at the backend's precision; see the module.

    The impact sets are the exact run's (every sign certified); the betas of multiple impacts
    and the exit velocity are intervals that enclose the exact ones. A sign that the ball does
    not decide goes to ``exact`` (0 when the rate is exactly 0, else Undecided), or raises
    :class:`~verify.errors.Undecided` without it.
    """
    K = _interval(system)
    data = ball_data(system)
    limits = limits.start()
    r = system.r
    b0 = system.rates(v)
    boxes = [_bounds(x) for x in b0]
    ball = _start(data, boxes)
    M, mu, zero = ball.M, ball.mu, ball.zero
    rho = ball.rho
    kappa, own, own_zero, column = data.kappa, data.own, data.own_zero, data.column
    growth, offset, root = data.growth, data.offset, data.root
    impact_sets: list[tuple[int, ...]] = []
    betas: list[Any] = []
    structures: dict[tuple[int, ...], tuple[bool, tuple[int, ...]]] = {}
    first = True
    while True:
        J = []
        for i in range(r):
            if zero[i]:
                continue
            x = M[i]
            q, s = root[i]
            if (x if x >= 0 else -x) << s > q * rho:  # |m_i| > sqrt(G_ii) rho
                if x < 0:
                    J.append(i)
                continue
            if first:  # the rates of the left velocity: their own intervals may decide
                lo, hi = boxes[i]
                if hi < 0:
                    J.append(i)
                    continue
                if lo > 0:
                    continue
            ball.rho = rho
            _undecided(system, data, i, ball, exact=exact, impact_sets=impact_sets)
            zero[i] = True  # proved 0 (else raised)
        first = False
        if not J:
            stop: Stop = "exit"
            break
        reason = limits.stop(len(impact_sets), _no_size)
        if reason is not None:
            stop = reason
            break
        hit = tuple(J)
        structure = structures.get(hit)
        if structure is None:
            structure = structures[hit] = _structure(data.couplings, hit)
        if structure[0]:  # single, or G_JJ diagonal: commuting single impacts (beta = 1)
            for j in hit:
                mj = M[j]
                q, s = kappa[j]
                c = (q * mj) >> s
                mu[j] += c
                for i, g, t in column[j]:
                    M[i] += (g * c) >> t
                    zero[i] = False
                q, s = own[j]
                M[j] = (q * mj) >> s
                zero[j] = own_zero[j]
                rho += _ceil_mul(growth[j], mj if mj >= 0 else -mj) + offset[j]
            betas.append(None if len(hit) == 1 else K.one)
        else:
            ball.rho = rho
            betas.append(K.ctx.convert(_general(system, data, ball, hit, structure[1])))
            rho = ball.rho
        impact_sets.append(hit)
    ball.rho = rho
    return Run(_velocity(system, data, v, b0, ball), stop, impact_sets, betas)


def _structure(couplings: Sequence[frozenset[int]], J: tuple[int, ...]) -> tuple[bool, tuple[int, ...]]:
    """(G_JJ is diagonal, the constraints whose rate the impulse on J leaves unchanged); see
    :func:`verify.laws.rule._structure`."""
    hit = frozenset(J)
    diagonal = all(couplings[j] & hit == {j} for j in J)
    untouched = tuple(i for i, c in enumerate(couplings) if i not in hit and not c & hit)
    return diagonal, untouched


def _undecided(
    system: System, data: BallData, i: int, ball: _Ball, *, exact: ExactCheck | None, impact_sets: list[tuple[int, ...]]
) -> None:
    """A sign the ball leaves undecided: returns when ``exact`` proves the rate 0, else raises."""
    q, s = data.root[i]
    radius = _rational(q * ball.rho, 1 << s) * ball.unit
    mid = ball.M[i] * ball.unit
    exc = Undecided(
        f"the ball encloses it in [{format_decimal(mid - radius, 6, 'floor')}, "
        f"{format_decimal(mid + radius, 6, 'ceiling')}], which contains 0, at {system.backend.dps} digits"
    )
    if exact is None:
        raise Undecided(f"the rate of {system.names[i]} after {counted(len(impact_sets), 'impulse')}: {exc}")
    if exact(system, impact_sets, i, exc) != 0:  # the callback returns 0 or raises
        raise exc


def _general(system: System, data: BallData, ball: _Ball, J: tuple[int, ...], untouched: tuple[int, ...]) -> Any:
    """A multiple impulse on J with G_JJ not diagonal, in place on ``ball``: the mean-value form
    (see the module). Returns beta (an interval of the wide backend)."""
    wide = data.widened(system)
    ctx = wide.backend.ctx
    P, unit, M = ball.P, ball.unit, ball.M
    point = [ctx.ldexp(ctx.convert(x), -P) for x in M]
    box = []
    for i, x in enumerate(M):
        q, s = data.root[i]
        R = -((-q * ball.rho) >> s)  # ceil(sqrt(G_ii) rho), in units
        box.append(ctx.ldexp(ctx.mpf([ctx.convert(x - R).a, ctx.convert(x + R).b]), -P))
    jac, beta = _jacobian(wide, box, J)
    lip = lipschitz_bound(wide, jac)
    image = _phi(wide, point, J)
    for j in J:
        ball.mu[j] += round(_mid(image.c[j]) / unit)
    keep = set(untouched)
    w = [_rational(0)] * len(M)
    for i in range(len(M)):
        if i in keep:
            continue  # its rate, and what is known of it, is unchanged
        lo, hi = _bounds(image.rates[i])
        M[i] = round((lo + hi) / 2 / unit)
        w[i] = max(hi - M[i] * unit, M[i] * unit - lo)
        ball.zero[i] = False
    ball.rho = math.ceil(lip * ball.rho + norm_bound(data.inverse_abs, w) / unit)
    return beta


def _velocity(system: System, data: BallData, v0: tuple[Any, ...], b0: tuple[Any, ...], ball: _Ball) -> tuple[Any, ...]:
    """The exit velocity from the ball of rates ``b`` and the coefficients ``mu`` (see the module):

    ``v = v0 + U^T G^-1 (b - b0) = v0 + U^T mu + U^T G^-1 (b - m + e)`` with ``e = m - b0 - G mu``
    (any mu: the sum of the computed coefficients makes e tiny). The last term's kinetic-energy
    norm is at most ``rho + ||e||``, so component k is off by at most ``spread[k]`` times that."""
    K = _interval(system)
    ctx = K.ctx
    r, P = system.r, ball.P
    mu = [ctx.ldexp(ctx.convert(x), -P) for x in ball.mu]
    m = [ctx.ldexp(ctx.convert(x), -P) for x in ball.M]
    G = system.gram
    e = [m[i] - b0[i] - sum((G[i][j] * mu[j] for j in range(r)), K.zero) for i in range(r)]
    radius = ball.rho * ball.unit + norm_bound(data.inverse_abs, [_abs_upper(x) for x in e])
    out = []
    for k, x in enumerate(v0):
        for j in range(r):
            x = x + mu[j] * system.U[j][k]
        bound = data.spread[k] * radius
        if bound:
            top = _enclose(ctx, bound).b
            x = x + ctx.mpf([-top, top])
        out.append(x)
    return tuple(out)
