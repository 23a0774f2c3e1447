"""The rule's iteration over integers, for rational systems: fraction-free and exact.

On the rational backend each ``+`` between two rationals pays greatest common divisors of
their numerators and denominators; on long runs, whose numbers grow to thousands of bits,
these gcds are most of the time. Here the velocity is one integer vector over one common
denominator, ``v = V / D``, and eqs. (2), (4) and (8) are rewritten over integers:

- rates (eq. 2): with ``L`` the common denominator of the normals and time terms
  (``A = L dF``, ``C = L dF/dt``), ``p(F_i) = B_i / (L D)`` where ``B_i = C_i D + A_i . V``:
  the sign of ``B_i`` is the sign of the rate, so the branch is decided on integers;
- a single impact on j (eq. 4), with ``U_j = Uz_j / M`` and ``-(1 + e_j)/G_jj = p_j/q_j``:
  ``V' = q_j L M V + p_j B_j Uz_j`` and ``D' = q_j L M D``;
- a multiple impact (eq. 8), with ``1/G_jj = P_j / Q_I``, ``G_jk = Gz_jk / Q_G`` and
  ``-(1 + e_j) = E_j / E``: ``Lambda_j = B_j P_j``, ``S = sum B_j Lambda_j``,
  ``N = Lambda^T Gz Lambda``, ``beta = S Q_I Q_G / N``, and
  ``V' = N E L M V + S Q_G sum_j E_j Lambda_j Uz_j``, ``D' = N E L M D``.

After each impulse the common content is divided out: the part of it that divides the
impulse's multiplier (a gcd of a small number with V, cheap), and every
:data:`FULL_CONTENT_EVERY` impulses all of ``gcd(D, V_1, ..., V_n)``; a few gcds an impulse
instead of several an operation. The values are the rule's, exactly:
:func:`verify.laws.rule.solve` takes this path on the rational backend when it records no
trace and runs no stop test, and the tests check it against the traced path.

>>> from verify.dynamics.system import System
>>> s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], ["1/2", "1/2"])
>>> out = iterate(s, s.velocity(["100", "0", "0"]), Limits(10))
>>> [s.backend.to_exact(x) for x in out.v], out.impact_sets, out.stop
(['325/16', '375/16', '225/4'], [(0,), (1,), (0,)], 'exit')
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass
from functools import partial
from typing import Any

from verify.dynamics.policy import Limits, Run, Stop
from verify.dynamics.system import System
from verify.numbers.backends import RationalBackend

try:  # GMP integers when installed: faster products and gcds on long runs
    from gmpy2 import gcd as _gcd
    from gmpy2 import mpz as _int
except ImportError:  # pragma: no cover - exercised where gmpy2 is absent
    _gcd = math.gcd
    _int = int


#: impulses between two full content reductions gcd(D, V) (the cheap one runs every impulse)
FULL_CONTENT_EVERY = 16


@dataclass(frozen=True)
class IntegerData:
    """The constants of the rule for one rational system, over integers (see the module)."""

    A: tuple[Any, ...]  # per constraint: ((k, A_ik), ...) non-zero entries of L dF_i
    C: tuple[Any, ...]  # per constraint: L dF_i/dt (0 for fixed constraints)
    Uz: tuple[Any, ...]  # per constraint: ((k, Uz_jk), ...) non-zero entries of M U_j
    single: tuple[Any, ...]  # per constraint: (q_j L M, p_j)
    P: tuple[Any, ...]  # 1/G_jj = P_j / Q_I
    QI: int
    Gz: tuple[Any, ...]  # G_jk = Gz_jk / Q_G
    QG: int
    E: tuple[Any, ...]  # -(1 + e_j) = E_j / Ed
    ELM: int  # Ed L M


#: the integer constants of each system, computed when first needed (held while the system lives)
_DATA: weakref.WeakKeyDictionary[System, IntegerData] = weakref.WeakKeyDictionary()


def integer_data(system: System) -> IntegerData:
    """The integer constants of a system on the rational backend (computed once, cached)."""
    cached = _DATA.get(system)
    if cached is not None:
        return cached
    K = system.backend
    q = K.to_number
    normals = [[q(x) for x in row] for row in system.normals]
    times = [q(x) for x in system.time_terms]
    L = math.lcm(*(x.denominator for x in [*times, *(x for row in normals for x in row)]))
    U = [[q(x) for x in row] for row in system.U]
    M = math.lcm(*(x.denominator for row in U for x in row))
    gram = [[q(x) for x in row] for row in system.gram]
    minus = [-(1 + q(e)) for e in system.restitution]
    singles = []
    for j in range(system.r):
        s = minus[j] / gram[j][j]
        singles.append((_int(s.denominator * L * M), _int(s.numerator)))
    inverse = [1 / gram[j][j] for j in range(system.r)]
    QI = math.lcm(*(x.denominator for x in inverse))
    QG = math.lcm(*(x.denominator for row in gram for x in row))
    Ed = math.lcm(*(x.denominator for x in minus))
    data = IntegerData(
        A=tuple(tuple((k, _int(a * L)) for k, a in enumerate(row) if a) for row in normals),
        C=tuple(_int(c * L) for c in times),
        Uz=tuple(tuple((k, _int(u * M)) for k, u in enumerate(row) if u) for row in U),
        single=tuple(singles),
        P=tuple(_int(x * QI) for x in inverse),
        QI=_int(QI),
        Gz=tuple(tuple(_int(x * QG) for x in row) for row in gram),
        QG=_int(QG),
        E=tuple(_int(x * Ed) for x in minus),
        ELM=_int(Ed * L * M),
    )
    _DATA[system] = data
    return data


def _canonical_bits(V: list[Any], D: Any) -> int:
    """The largest numerator-plus-denominator size of the components V_k / D in lowest terms."""
    out = 0
    for x in V:
        g = _gcd(x, D)
        out = max(out, int(x // g).bit_length() + int(D // g).bit_length())
    return out


def _size_within(V: list[Any], D: Any, bits: int | None) -> int:
    """The size :meth:`~verify.dynamics.policy.Limits.over_budget` compares with ``bits``:
    the unreduced size bounds the canonical one, so reduce only when it may be over."""
    unreduced = max(int(x.bit_length()) for x in V) + int(D.bit_length())
    return unreduced if bits is None or unreduced <= bits else _canonical_bits(V, D)


def iterate(system: System, v: tuple[Any, ...], limits: Limits) -> Run:
    """Run the rule from ``v`` (rational backend elements) as :func:`verify.laws.rule.solve` does
    without a trace or stop tests, within ``limits``."""
    K = system.backend
    if not isinstance(K, RationalBackend):
        raise ValueError(f"the integer engine runs on the rational backend, not on {K.describe()}")
    data = integer_data(system)
    limits = limits.start()
    start = [K.to_number(x) for x in v]
    D = _int(math.lcm(*(x.denominator for x in start)))
    V = [_int(x.numerator * (D // x.denominator)) for x in start]
    A, C, Uz, single, P, Gz, E = data.A, data.C, data.Uz, data.single, data.P, data.Gz, data.E
    moving = any(C)
    impact_sets: list[tuple[int, ...]] = []
    betas: list[Any] = []
    while True:
        B = []
        for Ci, row in zip(C, A):
            total = Ci * D if moving else 0
            for k, a in row:
                total += a * V[k]
            B.append(total)
        J = tuple(i for i, b in enumerate(B) if b < 0)
        if not J:
            stop: Stop = "exit"
            break
        reason = limits.stop(len(impact_sets), partial(_size_within, V, D, limits.bits))
        if reason is not None:
            stop = reason
            break
        if len(J) == 1:
            (j,) = J
            m, p = single[j]
            c = p * B[j]
            V = [m * x for x in V]
            for k, u in Uz[j]:
                V[k] += c * u
            betas.append(None)
        else:
            lam = [B[j] * P[j] for j in J]
            S = sum(B[j] * lj for j, lj in zip(J, lam))
            N = sum(lj * sum(Gz[j][k] * lk for k, lk in zip(J, lam)) for j, lj in zip(J, lam))
            betas.append(K.from_integers(S * data.QI * data.QG, N))
            m = N * data.ELM
            V = [m * x for x in V]
            factor = S * data.QG
            for j, lj in zip(J, lam):
                c = factor * E[j] * lj
                for k, u in Uz[j]:
                    V[k] += c * u
        D *= m
        impact_sets.append(J)
        # content: the factors of this impulse's multiplier m (a cheap gcd: m is small next
        # to V), and every FULL_CONTENT_EVERY impulses the whole gcd(D, V)
        g = _gcd(D if len(impact_sets) % FULL_CONTENT_EVERY == 0 else m, *V)
        if g != 1:
            D //= g
            V = [x // g for x in V]
    return Run(tuple(K.from_integers(x, D) for x in V), stop, impact_sets, betas)
