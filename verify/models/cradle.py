"""Newton's cradle (Sect. 4.1): N balls on a line, built twice.

- :func:`cradle_system` uses the reduced coordinates ``(x1, ..., xN)``: ball i has mass
  m_i, and the contact between balls i and i+1 is ``S_(i,i+1)`` with normal
  ``e_(i+1) - e_i`` (the direction of the gradient of the paper's constraint function).
- :func:`cradle_system_full` starts from the paper's own constraint functions
  ``S_(i,j) = (x^j - x^i)^2 + (y^j - y^i)^2 - 4R^2`` in the full coordinates
  ``(x^i, y^i, theta^i)`` of N disks of radius R (moment of inertia m R^2 / 2); gradients
  are computed by SymPy and only the pairs in contact are kept (step a of Sect. 3.5).

Both give the same exit velocity in x; in the full model the y components stay zero and
a spin stays unchanged (tested in ``tests/models/test_cradle.py``).

>>> r = run_cradle("1/2")
>>> r.iterations, [r.backend.to_exact(x) for x in r.exit_velocity]
(3, ['325/16', '375/16', '225/4'])
"""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction
from typing import Any, TypedDict, Unpack

from verify.dynamics.system import System
from verify.errors import InvalidSystem
from verify.laws.outcome import Result
from verify.laws.rule import DEFAULT_MAX_ITERATIONS, solve_many
from verify.laws.sequential import Law
from verify.models.paper import PAPER_MAX_ITERATIONS, PAPER_READING, Reading, aeev_halt
from verify.numbers.backends import Backend
from verify.numbers.parse import to_number

MODES = ("exact", "paper")


def _restitution(eps: Any, contacts: int) -> list[Any]:
    values = list(eps) if isinstance(eps, (list, tuple)) else [eps]
    if len(values) == 1:
        values = values * contacts
    if len(values) != contacts:
        wanted = "1 COR (one contact)" if contacts == 1 else f"1 or {contacts} CORs (one per contact)"
        raise InvalidSystem(f"eps: expected {wanted}, got {len(values)}")
    return values


def _masses(masses: Sequence[Any] | None, balls: int) -> list[Any]:
    if masses is None:
        return [Fraction(1)] * balls
    if len(masses) != balls:
        raise InvalidSystem(f"masses: expected {balls} masses, got {len(masses)}")
    parsed = [to_number(m, where=f"masses[{i}]") for i, m in enumerate(masses)]
    from verify.numbers.numeric import certified_sign

    for i, m in enumerate(parsed):
        if certified_sign(m) <= 0:
            raise InvalidSystem(f"masses[{i}] = {m} must be positive")
    return parsed


def _check_balls(balls: int) -> None:
    if not isinstance(balls, int) or balls < 2:
        raise InvalidSystem(f"balls must be an integer >= 2, got {balls!r}")


def cradle_geometry(masses: Sequence[Any], *, wall: bool = False) -> tuple[list[list[Any]], list[list[Fraction]]]:
    """The cradle of ``len(masses)`` balls in reduced coordinates: the diagonal mass matrix of
    ``masses`` (as given) and the normals ``e_(i+1) - e_i`` of the contacts, as exact numbers. With
    ``wall``, a fixed wall touches the last ball on its right: one more contact, of normal ``-e_N``
    (its rate is ``-v_N``: the last ball approaches the wall when it moves right).

    >>> g, normals = cradle_geometry([Fraction(1), Fraction(2), Fraction(1)])
    >>> [str(x) for x in g[1]], [[str(a) for a in row] for row in normals]
    (['0', '2', '0'], [['-1', '1', '0'], ['0', '-1', '1']])
    >>> [[str(a) for a in row] for row in cradle_geometry([Fraction(1)] * 2, wall=True)[1]]
    [['-1', '1'], ['0', '-1']]
    """
    balls = len(masses)
    zero, one = Fraction(0), Fraction(1)
    g = [[masses[i] if i == j else zero for j in range(balls)] for i in range(balls)]
    normals = [[-one if k == i else one if k == i + 1 else zero for k in range(balls)] for i in range(balls - 1)]
    if wall:
        normals.append([-one if k == balls - 1 else zero for k in range(balls)])
    return g, normals


def cradle_system(
    eps: Any,
    balls: int = 3,
    masses: Sequence[Any] | None = None,
    *,
    backend: str | Backend = "exact",
    dps: int | None = None,
) -> System:
    """The cradle in reduced coordinates: one COR for all contacts, or one per contact.

    >>> s = cradle_system("0.9")
    >>> s.names, [[str(a) for a in row] for row in s.normals]
    (('S(1,2)', 'S(2,3)'), [['-1', '1', '0'], ['0', '-1', '1']])
    """
    _check_balls(balls)
    g, normals = cradle_geometry(_masses(masses, balls))
    return System(
        g,
        normals,
        _restitution(eps, balls - 1),
        backend=backend,
        dps=dps,
        names=[f"S({i + 1},{i + 2})" for i in range(balls - 1)],
        coordinates=[f"x{i + 1}" for i in range(balls)],
    )


def cradle_system_full(
    eps: Any,
    balls: int = 3,
    masses: Sequence[Any] | None = None,
    *,
    radius: Any = 1,
    backend: str | Backend = "exact",
    dps: int | None = None,
) -> System:
    """The cradle from the paper's constraint functions S_(i,j) in coordinates (x, y, theta).

    All pairs i < j are given; at the configuration ``x^i = 2R(i-1), y^i = 0`` only
    neighbours touch, so only ``S_(i,i+1)`` are kept. ``eps`` gives one COR for all
    contacts or one per neighbouring contact.

    >>> s = cradle_system_full("0.9")
    >>> s.names, s.n
    (('S(1,2)', 'S(2,3)'), 9)
    """
    import sympy as sp

    _check_balls(balls)
    m = _masses(masses, balls)
    R = to_number(radius, where="radius")
    if R <= 0:
        raise InvalidSystem(f"radius must be positive, got {R}")
    x = sp.symbols(f"x1:{balls + 1}")
    y = sp.symbols(f"y1:{balls + 1}")
    th = sp.symbols(f"theta1:{balls + 1}")
    coords = [q for i in range(balls) for q in (x[i], y[i], th[i])]
    Rs = sp.Rational(R.numerator, R.denominator)
    config = {q: 0 for q in coords}
    config.update({x[i]: 2 * Rs * i for i in range(balls)})
    pairs = [(i, j) for i in range(balls) for j in range(i + 1, balls)]
    functions = [(x[j] - x[i]) ** 2 + (y[j] - y[i]) ** 2 - 4 * Rs**2 for i, j in pairs]
    neighbour_eps = _restitution(eps, balls - 1)
    cors = [neighbour_eps[i] if j == i + 1 else 1 for i, j in pairs]
    g = [[0] * (3 * balls) for _ in range(3 * balls)]
    for i in range(balls):
        g[3 * i][3 * i] = g[3 * i + 1][3 * i + 1] = m[i]
        g[3 * i + 2][3 * i + 2] = m[i] * R * R / 2
    return System.from_functions(
        functions,
        coords,
        config,
        g,
        cors,
        names=[f"S({i + 1},{j + 1})" for i, j in pairs],
        backend=backend,
        dps=dps,
    )


def cradle_velocity(balls: int, v0: Any = "100", velocity: Sequence[Any] | None = None) -> list[Any]:
    """The left velocity: ``velocity`` when given, else ball 1 at v0 and the others at rest."""
    if velocity is not None:
        if len(velocity) != balls:
            raise InvalidSystem(f"velocity: expected {balls} components, got {len(velocity)}")
        return list(velocity)
    return [v0] + [0] * (balls - 1)


def cradle_balls(balls: int | None, masses: Sequence[Any] | None, velocity: Sequence[Any] | None) -> int:
    """The number of balls: ``balls`` when given, else the length shared by ``masses`` and ``velocity``
    (those given), else 3. A list of another length raises :class:`InvalidSystem` naming it.

    >>> cradle_balls(None, ["1", "2", "1", "2"], None)
    4
    >>> cradle_balls(None, ["1", "2"], ["1", "0", "0"])
    Traceback (most recent call last):
    verify.errors.InvalidSystem: masses has 2 entries but there are 3 balls
    """
    inferred = {len(x) for x in (masses, velocity) if x is not None}
    if balls is None:
        balls = inferred.pop() if len(inferred) == 1 else 3
    for name, values in (("masses", masses), ("velocity", velocity)):
        if values is not None and len(values) != balls:
            raise InvalidSystem(f"{name} has {len(values)} entries but there are {balls} balls")
    return balls


class CradleOptions(TypedDict, total=False):
    """The options of :func:`run_cradle` and :func:`run_cradle_many` besides eps (their defaults are there)."""

    v0: Any
    balls: int
    masses: Sequence[Any] | None
    velocity: Sequence[Any] | None
    mode: str
    backend: str | Backend
    dps: int | None
    max_iterations: int | None
    trace: bool
    sigma_relative: Fraction | None
    certify: bool
    aeev: Reading | str
    sigma_squared: Fraction | None
    law: Law


def run_cradle(eps: Any, **options: Unpack[CradleOptions]) -> Result:
    """Run the cradle (reduced coordinates) in ``exact`` mode or in the paper's ``paper`` mode; the options and
    their defaults are :func:`run_cradle_many`'s.

    ``mode="paper"`` applies the paper's own termination (Sect. 4.1): at most 10^4
    impulses and the almost-equal-exit-velocities stop of :func:`verify.models.paper.aeev_halt`
    under the reading ``aeev`` (a :class:`verify.models.paper.Reading` or its name, such as
    ``"max_pair/v0/before"``) with threshold ``sigma_relative`` times the reading's norm
    (default :func:`verify.models.paper.default_sigma`; see :mod:`verify.models.paper`), or
    with ``sigma_squared`` its square.
    ``mode="exact"`` stops when the velocity exits, when the run is proved never to exit
    (stop ``"non_terminating"`` with a certificate, :mod:`verify.proofs.termination`), or at
    ``max_iterations``. ``certify=False`` turns the proofs off (to follow a run that
    never exits for as long as ``max_iterations``). ``law="simultaneous"`` applies the
    simultaneous law instead (:mod:`verify.laws.simultaneous`; exact mode only).

    >>> [str(x) for x in run_cradle("1", law="simultaneous").exit_velocity]
    ['-100/3', '200/3', '200/3']
    >>> run_cradle("0", mode="paper").stop, run_cradle("0", mode="paper").iterations
    ('aeev', 32)
    """
    return run_cradle_many([eps], **options)[0]


def run_cradle_many(
    eps_values: Sequence[Any],
    *,
    v0: Any = "100",
    balls: int = 3,
    masses: Sequence[Any] | None = None,
    velocity: Sequence[Any] | None = None,
    mode: str = "exact",
    backend: str | Backend = "exact",
    dps: int | None = None,
    max_iterations: int | None = None,
    trace: bool = True,
    sigma_relative: Fraction | None = None,
    certify: bool = True,
    aeev: Reading | str = PAPER_READING,
    sigma_squared: Fraction | None = None,
    law: Law = "rule",
) -> list[Result]:
    """:func:`run_cradle` for each of ``eps_values`` (the other options as there): the cradle is
    built once and every COR shares its geometry (:func:`verify.laws.rule.solve_many`).

    >>> [r.iterations for r in run_cradle_many(["1", "0.5", "0"], mode="paper", trace=False)]
    [2, 3, 32]
    """
    if mode not in MODES:
        raise InvalidSystem(f"unknown mode {mode!r} (choose from {', '.join(MODES)})")
    if law != "rule" and mode == "paper":
        raise InvalidSystem("paper mode is the paper's rule: the simultaneous law has no AEEV stop")
    if not eps_values:
        return []
    system = cradle_system(eps_values[0], balls, masses, backend=backend, dps=dps)
    v = [to_number(c, where=f"velocity[{i}]") for i, c in enumerate(cradle_velocity(balls, v0, velocity))]
    halt = None
    if mode == "paper":
        reading = Reading.parse(aeev) if isinstance(aeev, str) else aeev
        halt = aeev_halt(v, sigma_relative, reading=reading, sigma_squared=sigma_squared)
        cap = PAPER_MAX_ITERATIONS if max_iterations is None else max_iterations
    else:
        cap = DEFAULT_MAX_ITERATIONS if max_iterations is None else max_iterations
    cors = [[to_number(e, where="eps") for e in _restitution(eps, balls - 1)] for eps in eps_values]
    # paper mode reproduces the paper's own termination, which had no proof of non-termination
    return solve_many(system, [v] * len(cors), restitutions=cors, law=law, max_iterations=cap, halt=halt, trace=trace,
                      certify=certify and mode == "exact")  # fmt: skip
