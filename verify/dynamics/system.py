"""The mechanical system at a multiple contact (Sect. 2.3 and 3.5 of the paper).

A :class:`System` holds, at the contact configuration, the mass matrix ``g`` (the metric
Phi on vertical vectors), the r constraint covectors ``dF_i`` (the "normals"), their time
derivatives ``dF_i/dt`` (0 for fixed constraints) and one coefficient of restitution per
constraint. The admissible side of S_i is ``F_i >= 0``, so an absolute velocity with
components ``v`` is incoming for S_i (an impact) iff ``p(F_i) = dF_i/dt + dF_i . v < 0``
(eq. 2).

Every number is parsed exactly once (:func:`verify.numbers.parse.to_number`), validated, and
converted into the backend ``K`` that the rule computes with. Derived quantities that do
not depend on the velocity are computed once here:

- ``U_i = g^{-1} dF_i^T``, the Phi-normal vector of S_i (``U_S^perp`` of Sect. 2.2);
- the Gram matrix ``G_ij = Phi(U_i, U_j) = dF_i g^{-1} dF_j^T``, positive definite
  exactly when the normals are independent (condition (iii) of Sect. 2.3);
- a rest frame ``H`` of all the constraints (``dF_i/dt + dF_i . H = 0``, Sect. 2.2), the
  one of least kinetic energy, in which kinetic energies are measured.

>>> s = System([[1, 0], [0, 1]], [[-1, 1]], ["1/2"])
>>> [str(x) for x in s.rates(s.velocity(["3", "0"]))]
['-3']
"""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction
from typing import Any

from verify.errors import BadNumber, InvalidInput, InvalidSystem
from verify.numbers.backends import Backend, exact_for, get_backend
from verify.numbers.format import format_exact
from verify.numbers.linalg import NotPositiveDefinite, dot, ldl, matvec, solve_spd
from verify.numbers.numeric import certified_sign
from verify.numbers.parse import Number, to_number


def known_zero(K: Backend, x: Any) -> bool:
    """Whether ``x`` is known to be exactly 0 on ``K`` (an undecidable sign counts as non-zero).

    >>> from verify.numbers.backends import get_backend
    >>> K = get_backend("interval")
    >>> third = K.convert(Fraction(1, 3))
    >>> known_zero(K, K.zero), known_zero(K, K.one - third - third - third)
    (True, False)
    """
    return K.known_zero(x)


def _equal(a: Number, b: Number) -> bool:
    if a is b or a == b:
        return True
    if isinstance(a, Fraction) and isinstance(b, Fraction):
        return False
    return certified_sign(a - b) == 0  # a SymPy number among them: SymPy takes the Fraction exactly


def _exact_backend(g: list[list[Any]], a: list[list[Any]], e: list[Any], c: list[Any]) -> Backend:
    """The exact backend for a system's parsed numbers (:func:`verify.numbers.backends.exact_for`); an
    entry it cannot hold is named by its field, with the ``backend`` parameter that can."""
    try:
        return exact_for([x for row in (*g, *a) for x in row] + e + c)
    except BadNumber:
        pass  # name the entry (field names are made only here, off the common path)
    entries = [(f"mass_matrix[{i}][{j}]", x) for i, row in enumerate(g) for j, x in enumerate(row)]
    entries += [(f"normals[{i}][{k}]", x) for i, row in enumerate(a) for k, x in enumerate(row)]
    entries += [(f"restitution[{i}]", x) for i, x in enumerate(e)] + [(f"time_terms[{i}]", x) for i, x in enumerate(c)]
    for field, x in entries:
        if type(x) is Fraction:
            continue
        symbols = getattr(x, "free_symbols", None)
        if symbols:
            raise InvalidSystem(
                f"{field} = {x} is not a number: it depends on {', '.join(sorted(str(s) for s in symbols))}"
            )
        if not is_algebraic(x):
            raise _not_exact(field, x)
    return exact_for([x for _, x in entries])  # refused for another reason: its own message


def is_algebraic(x: Number) -> bool:
    """Whether a parsed number is rational or algebraic: what the exact backend can hold.

    >>> import sympy as sp
    >>> is_algebraic(Fraction(1, 3)), is_algebraic(sp.sqrt(2)), is_algebraic(sp.pi)
    (True, True, False)
    """
    return isinstance(x, Fraction) or getattr(x, "is_algebraic", None) is True


def _not_exact(field: str, x: Any) -> BadNumber:
    return BadNumber(
        f"{field} = {x} is not an algebraic number, so the exact backend cannot hold it: "
        'pass backend="interval" (certified) or backend="mp"'
    )


def _sympy_entries(matrix: Any) -> list[tuple[str, Any]]:
    """``(mass_matrix[i][j], entry)`` for the SymPy entries of a matrix given as rows (others skipped)."""
    import sympy as sp

    if isinstance(matrix, (str, bytes)) or not isinstance(matrix, Sequence):
        return []
    return [
        (f"mass_matrix[{i}][{j}]", x)
        for i, row in enumerate(matrix)
        if not isinstance(row, (str, bytes)) and isinstance(row, Sequence)
        for j, x in enumerate(row)
        if isinstance(x, sp.Basic)
    ]


def _at_configuration(matrix: Any, subs: dict[Any, Any]) -> Any:
    """A mass matrix with its SymPy entries evaluated exactly at a configuration ``subs``.

    Anything that is not a matrix of rows is returned as it is (the constructor names the
    problem); an entry that still has free symbols after the substitution is an error.
    """
    import sympy as sp

    entries = dict(_sympy_entries(matrix))
    if not entries:
        return matrix
    values = {}
    for where, x in entries.items():
        value = x.subs(subs)
        if value.free_symbols:
            names = ", ".join(sorted(str(s) for s in value.free_symbols))
            raise InvalidSystem(f"{where} = {x} depends on {names}, which has no value in the configuration")
        values[where] = sp.simplify(value)
    return [
        [values.get(f"mass_matrix[{i}][{j}]", x) for j, x in enumerate(row)]
        if not isinstance(row, (str, bytes)) and isinstance(row, Sequence)
        else row
        for i, row in enumerate(matrix)
    ]


def _refuse_binary_float(where: str, value: Any) -> None:
    """Refuse a binary float (a Python float, or a SymPy ``Float`` inside an expression): ``0.3``
    is not 3/10, and the message says how to write the number exactly.

    >>> import sympy as sp
    >>> x, y = sp.symbols("x y")
    >>> _refuse_binary_float("functions[0]", y - 0.3 * x)
    Traceback (most recent call last):
    ...
    verify.errors.BadNumber: functions[0] = -0.3*x + y holds the binary float 0.3, which is not 3/10:
    write it exactly, as sympy.Rational("0.3") or Fraction(3, 10)
    >>> _refuse_binary_float("functions[0]", y - sp.Rational("0.3") * x)  # exact: accepted
    """
    import sympy as sp

    if isinstance(value, float):
        floats = [sp.Float(value)]
    elif isinstance(value, sp.Basic):
        floats = sorted(value.atoms(sp.Float), key=abs)
    else:
        return
    if not floats:
        return
    binary = abs(floats[0])
    mantissa, _, exponent = str(binary).partition("e")  # SymPy prints 15 digits: strip what typing did not add
    text = (mantissa.rstrip("0").rstrip(".") if "." in mantissa else mantissa) + (f"e{exponent}" if exponent else "")
    if isinstance(value, float):
        text = repr(abs(value))  # Python's shortest repr: what was typed
    try:
        exact = Fraction(text)  # the decimal read exactly from its text, never through the float
    except ValueError:  # nan, inf
        raise BadNumber(f"{where} = {value} is not a finite number") from None
    alternative = f"Fraction({exact.numerator}, {exact.denominator})" if exact.denominator != 1 else f"the int {exact}"
    if sp.Rational(binary) != exact:  # the float's own value, exactly
        why = f", which is not {exact}"
    else:
        why = " (binary floats are refused: most decimals, such as 0.1, are not one)"
    if isinstance(value, float) or value == floats[0]:
        said = f"{where} = {text} is a binary float"
    else:
        said = f"{where} = {value} holds the binary float {text}"
    raise BadNumber(f'{said}{why}: write it exactly, as sympy.Rational("{text}") or {alternative}')


def _check_functions(
    functions: Sequence[Any], coords: list[Any], subs: dict[Any, Any], time: Any, mass_matrix: Any
) -> None:
    """The checks of :meth:`System.from_functions`: every coordinate has a value, every function
    is a SymPy expression in known symbols, and the time has a value when something uses it."""
    import sympy as sp

    missing = [str(q) for q in coords if q not in subs]
    if missing:
        raise InvalidSystem(f"configuration: no value for {', '.join(missing)}")
    for i, F in enumerate(functions):
        if not isinstance(F, sp.Basic):  # never sympify text: it would be evaluated
            raise InvalidSystem(f"functions[{i}]: expected a SymPy expression, got {type(F).__name__}")
    known = set(coords) | set(subs) | ({time} if time is not None else set())
    for i, F in enumerate(functions):
        unknown = sorted(str(s) for s in F.free_symbols - known)
        if unknown:
            raise InvalidSystem(
                f"functions[{i}] = {F} depends on {', '.join(unknown)}, which is not a coordinate, not the "
                "time (pass time=...) and has no value in the configuration"
            )
    if time is not None and time not in subs:
        users = [f"functions[{i}]" for i, F in enumerate(functions) if time in F.free_symbols]
        users += [w for w, x in _sympy_entries(mass_matrix) if time in x.free_symbols]
        if users:
            raise InvalidSystem(
                f"configuration: no value for the time {time}, on which {', '.join(users)} depends "
                f"(give the instant of the impact, e.g. {{{time}: 0}})"
            )


def _contacts(
    functions: Sequence[Any],
    coords: list[Any],
    subs: dict[Any, Any],
    *,
    time: Any,
    names: list[str],
    restitution: Sequence[Any],
) -> tuple[list[str], list[list[Number]], list[Number], list[Any]]:
    """Step a) of Sect. 3.5 for :meth:`System.from_functions`: the names, normals ``dF_i``, time
    terms ``dF_i/dt`` and CORs of the functions that are 0 at the configuration (exactly)."""
    import sympy as sp

    kept: list[str] = []
    normals: list[list[Number]] = []
    time_terms: list[Number] = []
    cors: list[Any] = []
    for i, F in enumerate(functions):
        if sp.simplify(F.subs(subs)) != 0:
            continue
        kept.append(names[i])
        gradient = [sp.simplify(sp.diff(F, q).subs(subs)) for q in coords]
        normals.append([to_number(d, where=f"d{names[i]}/d{q}") for d, q in zip(gradient, coords)])
        dt = sp.diff(F, time).subs(subs) if time is not None else sp.Integer(0)
        time_terms.append(to_number(sp.simplify(dt), where=f"d{names[i]}/dt"))
        cors.append(restitution[i])
    if not kept:
        raise InvalidSystem("from_functions: no constraint is in contact at this configuration")
    return kept, normals, time_terms, cors


_ZERO = Fraction(0)


def _check_vector(values: Any, length: int | None, field: str) -> list[Any]:
    if type(values) not in (list, tuple) and (isinstance(values, (str, bytes)) or not isinstance(values, Sequence)):
        raise InvalidSystem(f"{field}: expected a list of numbers, got {type(values).__name__}")
    if length is not None and len(values) != length:
        raise InvalidSystem(f"{field}: expected {length} numbers, got {len(values)}")
    if set(map(type, values)) <= {Fraction}:  # already exact numbers: nothing to parse
        return list(values)
    return [x if type(x) is Fraction else to_number(x, where=f"{field}[{i}]") for i, x in enumerate(values)]


def _check_cors(e: list[Number]) -> None:
    """Every COR that is a number lies in [0, 1] (those with a parameter are checked on the backend)."""
    for i, ei in enumerate(e):
        if type(ei) is Fraction:
            if 0 <= ei.numerator <= ei.denominator:  # a Fraction's denominator is positive
                continue
        elif getattr(ei, "free_symbols", None):
            continue  # a parameter such as eps: checked by the backend over its range
        elif certified_sign(ei) >= 0 and certified_sign(1 - ei) >= 0:
            continue
        raise InvalidSystem(f"restitution[{i}] = {format_exact(ei)} is outside [0, 1]")


def default_names(r: int) -> tuple[str, ...]:
    """The contacts' names when none are given: ``S1, S2, ...``.

    >>> default_names(3)
    ('S1', 'S2', 'S3')
    """
    return tuple(f"S{i + 1}" for i in range(r))


def _check_names(names: Any, r: int) -> tuple[str, ...]:
    """The contacts' names: one non-empty string per constraint, no two alike."""
    if isinstance(names, (str, bytes)) or not isinstance(names, Sequence):
        raise InvalidSystem(f"names: expected a list of {r} strings, got {type(names).__name__}")
    if len(names) != r:
        raise InvalidSystem(f"names: expected {r} names (one per row of normals), got {len(names)}")
    for i, name in enumerate(names):
        if not isinstance(name, str) or not name.strip():
            raise InvalidSystem(f"names[{i}]: expected a non-empty string, got {name!r}")
        if name in names[:i]:
            first = list(names).index(name)
            raise InvalidSystem(f"names[{i}] = {name!r} repeats names[{first}] (each contact's name must be unique)")
    return tuple(names)


class System:
    """A system in multiple contact with r frictionless codimension-1 constraints.

    ``mass_matrix`` is n x n, symmetric positive definite; ``normals`` is r x n (row i is
    ``dF_i``); ``restitution`` has r CORs in [0, 1]; ``time_terms`` has r entries
    (default 0). Numbers may be strings (``"0.1"`` is read as 1/10), ints, Fractions or
    SymPy numbers; floats are refused. ``names`` labels the contacts in every output (one
    non-empty string per row of ``normals``, no two alike; default ``S1, S2, ...``).
    Raises :class:`~verify.errors.InvalidSystem` with the offending field and value.

    >>> s = System([["2", "0"], ["0", "1"]], [["-1", "1"]], ["0.5"])
    >>> s.n, s.r, s.backend.name, [str(u) for u in s.U[0]]
    (2, 1, 'exact', ['-1/2', '1'])
    """

    __slots__ = (
        "U",
        "__weakref__",
        "_energy_terms",
        "_gram_columns",
        "_inverse_gram_diag",
        "_minus_one_plus_e",
        "_moving",
        "_single_coefficient",
        "_sparse_U",
        "_sparse_normals",
        "backend",
        "coordinates",
        "g",
        "gram",
        "gram_diag",
        "n",
        "names",
        "normals",
        "r",
        "rest_frame",
        "restitution",
        "source",
        "time_terms",
    )
    _energy_terms: tuple[tuple[int, int, Any], ...] | None  # computed by kinetic_energy when first asked

    def __init__(
        self,
        mass_matrix: Sequence[Sequence[Any]],
        normals: Sequence[Sequence[Any]],
        restitution: Sequence[Any],
        time_terms: Sequence[Any] | None = None,
        *,
        backend: str | Backend = "exact",
        dps: int | None = None,
        names: Sequence[str] | None = None,
        coordinates: Sequence[str] | None = None,
    ):
        K = get_backend(backend, dps=dps)
        if isinstance(mass_matrix, (str, bytes)) or not isinstance(mass_matrix, Sequence) or not mass_matrix:
            raise InvalidSystem("mass_matrix: expected a non-empty square matrix (a list of rows)")
        n = len(mass_matrix)
        g = [_check_vector(row, n, f"mass_matrix[{i}]") for i, row in enumerate(mass_matrix)]
        if isinstance(normals, (str, bytes)) or not isinstance(normals, Sequence) or not normals:
            raise InvalidSystem("normals: expected at least one constraint normal (a list of rows)")
        r = len(normals)
        a = [_check_vector(row, n, f"normals[{i}]") for i, row in enumerate(normals)]
        e = _check_vector(restitution, r, "restitution")
        c = _check_vector(time_terms, r, "time_terms") if time_terms is not None else [_ZERO] * r
        for i in range(n):
            for j in range(i + 1, n):
                if not _equal(g[i][j], g[j][i]):
                    raise InvalidSystem(
                        f"mass_matrix is not symmetric: entry [{i}][{j}] = {format_exact(g[i][j])} "
                        f"but [{j}][{i}] = {format_exact(g[j][i])}"
                    )
        _check_cors(e)
        self.names = _check_names(names, r) if names is not None else default_names(r)
        self.coordinates = tuple(coordinates) if coordinates is not None else tuple(f"x{i + 1}" for i in range(n))
        if len(self.coordinates) != n:
            raise InvalidSystem(f"coordinates: expected {n} names, got {len(self.coordinates)}")
        self.source = {
            "mass_matrix": tuple(map(tuple, g)),
            "normals": tuple(map(tuple, a)),
            "time_terms": tuple(c),
            "restitution": tuple(e),
        }
        if backend == "exact" and K.widens_to_inputs:
            K = _exact_backend(g, a, e, c)  # algebraic inputs: exact too
        self.backend, self.n, self.r = K, n, r
        self._derive()
        self._check_parameter_cors()

    def _check_parameter_cors(self) -> None:
        """The CORs that depend on a parameter (eps) lie in [0, 1] over its whole range."""
        K = self.backend
        for i, ei in enumerate(self.source["restitution"]):
            if type(ei) is not Fraction and getattr(ei, "free_symbols", None):
                x = self.restitution[i]
                if not (K.nonnegative(x) and K.nonnegative(K.one - x)):
                    raise InvalidSystem(f"restitution[{i}] = {ei} is outside [0, 1] for some parameter value")

    def _derive(self) -> None:
        """Convert the source numbers into the backend and compute U, G and H.

        Built once per system, so written for short runs too: zeros are found once (the
        sparse rows), G is computed on its upper triangle (it is symmetric), and what only
        some callers need (the kinetic-energy terms) is computed when first asked for.
        """
        K, src, n, r = self.backend, self.source, self.n, self.r
        zero = K.known_zero
        flat = K.convert_all([x for row in src["mass_matrix"] for x in row] + [x for row in src["normals"] for x in row]
                             + list(src["time_terms"]) + list(src["restitution"]))  # fmt: skip
        nn, nr = n * n, n * (n + r)
        g = tuple([tuple(flat[i : i + n]) for i in range(0, nn, n)])
        self.g = g
        self.normals = tuple([tuple(flat[i : i + n]) for i in range(nn, nr, n)])
        self.time_terms = tuple(flat[nr : nr + r])
        self.restitution = tuple(flat[nr + r :])
        sparse = tuple([tuple([(k, x) for k, x in enumerate(row) if not zero(x)]) for row in self.normals])
        for i, row in enumerate(sparse):
            if not row and all(K.sign(x) == 0 for x in self.normals[i]):
                raise InvalidSystem(f"normals[{i}] is zero: a constraint needs a non-zero gradient")
        self._sparse_normals = sparse
        diagonal = all([zero(x) for i, row in enumerate(g) for j, x in enumerate(row) if i != j])
        if diagonal:  # U_i = dF_i / diag(g), entry by entry, on the non-zero pattern of dF_i
            for i in range(n):
                if K.sign(g[i][i]) <= 0:
                    self._not_positive_definite(i, g[i][i])
            U, sparse_U, none = [], [], K.zero
            for row in sparse:
                pairs = tuple([(k, a / g[k][k]) for k, a in row])
                u = [none] * n
                for k, x in pairs:
                    u[k] = x
                U.append(tuple(u))
                sparse_U.append(pairs)
            self.U = tuple(U)
            self._sparse_U = tuple(sparse_U)
        else:
            try:
                g_factors = ldl(K, g)
            except NotPositiveDefinite as exc:
                self._not_positive_definite(exc.index, exc.pivot)
            self.U = tuple(solve_spd(K, g_factors, row) for row in self.normals)
            self._sparse_U = tuple([tuple([(k, x) for k, x in enumerate(row) if not zero(x)]) for row in self.U])
        gram = [[K.zero] * r for _ in range(r)]
        for i, ai in enumerate(sparse):
            for j in range(i, r):
                uj = self.U[j]
                total = None
                for k, a in ai:
                    total = a * uj[k] if total is None else total + a * uj[k]
                gram[i][j] = gram[j][i] = K.zero if total is None else total
        self.gram = tuple([tuple(row) for row in gram])
        try:
            gram_factors = ldl(K, self.gram)
        except NotPositiveDefinite as exc:
            raise InvalidSystem(
                f"normals are dependent: normals[{exc.index}] is a combination of the normals before it "
                "(the paper requires independent constraints, Sect. 2.3 (iii))"
            ) from None
        self.gram_diag = tuple([self.gram[i][i] for i in range(r)])
        self._gram_columns = tuple(
            [tuple([(i, gram[i][j]) for i in range(r) if i != j and not zero(gram[i][j])]) for j in range(r)]
        )
        self._inverse_gram_diag = tuple([K.one / d for d in self.gram_diag])
        self._cor_constants()
        self._energy_terms = None  # computed by kinetic_energy when first needed
        self._moving = not all(zero(ci) or K.sign(ci) == 0 for ci in self.time_terms)
        if not self._moving:
            self.rest_frame = (K.zero,) * n
        else:
            mu = solve_spd(K, gram_factors, self.time_terms)
            self.rest_frame = tuple(K.zero - dot(K, mu, [u[k] for u in self.U]) for k in range(n))

    def _cor_constants(self) -> None:
        """The constants of eq. (8) that depend on the CORs, computed once: ``-(1 + e_j)`` and
        ``-(1 + e_j) / G_jj``."""
        K = self.backend
        self._minus_one_plus_e = tuple([K.zero - (K.one + e) for e in self.restitution])
        self._single_coefficient = tuple([m / d for m, d in zip(self._minus_one_plus_e, self.gram_diag)])

    # -- the constants of eq. (8), computed once (read-only) -------------------------------
    @property
    def minus_one_plus_e(self) -> tuple[Any, ...]:
        """``-(1 + e_j)`` for every constraint j (the factor of every impulse, eq. 8)."""
        return self._minus_one_plus_e

    @property
    def inverse_gram_diag(self) -> tuple[Any, ...]:
        """``1 / G_jj`` for every constraint j (``lambda_j = p(F_j) / G_jj``)."""
        return self._inverse_gram_diag

    @property
    def single_coefficient(self) -> tuple[Any, ...]:
        """``-(1 + e_j) / G_jj``: a single impact on j is ``single_coefficient[j] p(F_j) U_j`` (eq. 4).

        >>> [str(x) for x in System([[2, 0], [0, 1]], [[1, 0]], ["1/2"]).single_coefficient]
        ['-3']
        """
        return self._single_coefficient

    @property
    def sparse_U(self) -> tuple[tuple[tuple[int, Any], ...], ...]:
        """For each constraint j, the entries ``(k, U_jk)`` of U_j not known to be 0 (read-only)."""
        return self._sparse_U

    @property
    def gram_columns(self) -> tuple[tuple[tuple[int, Any], ...], ...]:
        """For each constraint j, the entries ``(i, G_ij)``, i != j, not known to be 0 (read-only):
        the rates that an impulse on j changes besides its own."""
        return self._gram_columns

    @property
    def moving(self) -> bool:
        """Whether some constraint moves (a time term ``dF_i/dt`` is not 0)."""
        return self._moving

    def _not_positive_definite(self, index: int, pivot: Any) -> None:
        raise InvalidSystem(
            f"mass_matrix is not positive definite (pivot {index} of its LDL^T factorisation "
            f"is {self.backend.to_decimal(pivot, 12)})"
        )

    # -- derived systems --------------------------------------------------------------
    def convert_to(self, backend: str | Backend, *, dps: int | None = None) -> System:
        """The same system on another backend (numbers re-converted from their exact source).

        >>> System([[1]], [[1]], [1]).convert_to("interval").backend.name
        'interval'
        """
        new = object.__new__(System)
        for slot in ("n", "r", "names", "coordinates", "source"):
            setattr(new, slot, getattr(self, slot))
        new.backend = get_backend(backend, dps=dps)
        new._derive()
        return new

    def with_restitution(self, restitution: Sequence[Any]) -> System:
        """The same system with other CORs (validated like the constructor's).

        Only what depends on the CORs is computed again: the geometry (U, G and its
        factorisation, checked once) is shared with this system, so a sweep over CORs costs
        little per value (:func:`verify.laws.rule.solve_many`).

        >>> [str(e) for e in System([[1]], [[1]], ["1/2"]).with_restitution([1]).restitution]
        ['1']
        """
        e = _check_vector(restitution, self.r, "restitution")
        _check_cors(e)
        new = object.__new__(System)
        for slot in _SHARED_SLOTS:  # everything but the CORs and what depends on them
            setattr(new, slot, getattr(self, slot))
        new.source = {**self.source, "restitution": tuple(e)}
        try:
            new.restitution = tuple(self.backend.convert_all(e))
        except InvalidInput:  # BadNumber: a COR outside the number field of an exact system
            if not self.backend.widens_to_inputs:
                raise
            src = self.source  # the exact field of every input, new CORs included
            return System(src["mass_matrix"], src["normals"], e, src["time_terms"], names=self.names,
                          coordinates=self.coordinates)  # fmt: skip
        new._cor_constants()
        new._check_parameter_cors()
        return new

    # -- the quantities the rule needs --------------------------------------------------
    def velocity(self, values: Sequence[Any], field: str = "velocity") -> tuple[Any, ...]:
        """Parse and convert a velocity vector (n components) into the backend."""
        return tuple(self.backend.convert_all(_check_vector(values, self.n, field)))

    def rates(self, v: Sequence[Any]) -> tuple[Any, ...]:
        """``p(F_i) = dF_i/dt + dF_i . v`` for every constraint (negative: an impact, eq. 2)."""
        out = []
        for ci, row in zip(self.time_terms, self._sparse_normals):
            total = ci if self._moving else None  # fixed constraints: no "0 +" on every rate
            for k, a in row:
                total = a * v[k] if total is None else total + a * v[k]
            out.append(total)
        return tuple(out)

    def combine_normals(self, coefficients: Sequence[tuple[int, Any]]) -> tuple[Any, ...]:
        """``sum c_j U_j`` over the pairs ``(j, c_j)``: the shape of every impulse."""
        out: list[Any] = [None] * self.n
        for j, c in coefficients:
            for k, u in self._sparse_U[j]:
                out[k] = c * u if out[k] is None else out[k] + c * u
        zero = self.backend.zero
        return tuple(zero if x is None else x for x in out)

    def phi(self, u: Sequence[Any], w: Sequence[Any]) -> Any:
        """The metric ``Phi(u, w) = u^T g w``."""
        return dot(self.backend, u, matvec(self.backend, self.g, w))

    def kinetic_energy(self, v: Sequence[Any]) -> Any:
        """``1/2 Phi(v - H, v - H)`` in the rest frame H of the constraints (Sect. 2.1)."""
        rel = tuple(x - h for x, h in zip(v, self.rest_frame))
        K = self.backend
        if self._energy_terms is None:
            half = K.convert(Fraction(1, 2))
            self._energy_terms = tuple(
                (i, j, half * self.g[i][j] if i == j else self.g[i][j])
                for i in range(self.n)
                for j in range(i, self.n)
                if not K.known_zero(self.g[i][j])
            )
        total = K.zero
        for i, j, c in self._energy_terms or ():  # 1/2 g_ii r_i^2 and g_ij r_i r_j (i < j)
            total = total + c * rel[i] * rel[j]
        return total

    # -- construction from constraint functions ---------------------------------------------
    @classmethod
    def from_functions(
        cls,
        functions: Sequence[Any],
        coordinates: Sequence[Any],
        configuration: dict[Any, Any],
        mass_matrix: Sequence[Sequence[Any]],
        restitution: Sequence[Any],
        *,
        time: Any = None,
        names: Sequence[str] | None = None,
        backend: str | Backend = "exact",
        dps: int | None = None,
    ) -> System:
        """A system from SymPy constraint functions ``F_i(t, x)`` and a configuration.

        Step a) of Sect. 3.5: only the constraints with ``F_i = 0`` at the configuration
        (exactly) are in contact; the others are left out. Gradients ``dF_i`` and time
        derivatives ``dF_i/dt`` are computed exactly by SymPy and evaluated there.
        ``restitution`` gives one COR per function. The kept constraints are named by
        ``names`` (default ``F1, F2, ...``), so ``system.names`` tells which are in contact.

        ``configuration`` maps every coordinate to its value (and may give values to other
        symbols of the functions, such as a radius). The time: when some function or the
        mass matrix depends on the symbol ``time``, the configuration must give its value
        (the instant of the impact), else :class:`~verify.errors.InvalidSystem` says that the
        time is missing; the contact, the gradients and ``dF_i/dt`` are evaluated at that
        instant. When nothing depends on it, no value is needed (every ``dF_i/dt`` is 0). A
        symbol that is neither a coordinate, nor ``time``, nor given a value is an error
        naming it (a time-dependent function passed without ``time=t`` is such an error).

        ``mass_matrix`` may depend on the configuration (SymPy expressions in the
        coordinates, and the time): it is evaluated exactly there, like the gradients; an
        entry that still has free symbols is an error naming it.

        Binary floats are refused (``0.3`` is not 3/10), whether a Python float in the
        configuration or a SymPy ``Float`` in a function, the mass matrix or a COR: the error
        names the input and how to write the number exactly (``sympy.Rational("0.3")``).

        >>> import sympy as sp
        >>> x1, x2 = sp.symbols("x1 x2")
        >>> s = System.from_functions([(x2 - x1)**2 - 4, x2 - 10], [x1, x2], {x1: 0, x2: 2},
        ...                           [[1, 0], [0, 1]], [1, 1])
        >>> s.names, [format_exact(x) for x in s.source["normals"][0]]
        (('F1',), ['-4', '4'])
        >>> t = sp.Symbol("t")
        >>> s = System.from_functions([x2 - x1 - t], [x1, x2], {x1: 0, x2: 1, t: 1},
        ...                           [[1 + x2**2, 0], [0, 1]], [1], time=t)
        >>> [format_exact(x) for x in s.source["mass_matrix"][0]], [format_exact(c) for c in s.time_terms]
        (['2', '0'], ['-1'])
        """
        coords = list(coordinates)
        names = list(names) if names is not None else [f"F{i + 1}" for i in range(len(functions))]
        if len(names) != len(functions) or len(restitution) != len(functions):
            raise InvalidSystem("from_functions: names and restitution need one entry per function")
        subs = dict(configuration)
        _check_functions(functions, coords, subs, time, mass_matrix)
        inputs = [(f"configuration[{q}]", v) for q, v in subs.items()]
        inputs += [(f"functions[{i}]", F) for i, F in enumerate(functions)] + _sympy_entries(mass_matrix)
        for where, value in inputs + [(f"restitution[{i}]", e) for i, e in enumerate(restitution)]:
            _refuse_binary_float(where, value)
        g = _at_configuration(mass_matrix, subs)
        kept, normals, time_terms, cors = _contacts(
            functions, coords, subs, time=time, names=names, restitution=restitution
        )
        return cls(
            g,
            normals,
            cors,
            time_terms,
            backend=backend,
            dps=dps,
            names=kept,
            coordinates=[str(q) for q in coords],
        )


# -- widening the exact field for a velocity ---------------------------------------------------


def exact_backend_for_velocity(system: System, velocity: Sequence[Any]) -> tuple[System, tuple[Any, ...]]:
    """On the exact backend, widen the number field when the velocity needs it; returns the
    system and the velocity converted into its backend.

    >>> from verify.dynamics.system import System
    >>> s, v = exact_backend_for_velocity(System([[1]], [[1]], [1]), ["sqrt(2)"])
    >>> s.backend.describe()[:18], s.backend.to_exact(v[0])
    ('exact (number fiel', 'sqrt(2)')
    """
    values = velocity_numbers(velocity)
    try:
        return system, system.velocity(values)
    except InvalidInput:  # not in this field (BadNumber): build the field of every input
        for i, x in enumerate(values):
            if not is_algebraic(x):
                raise _not_exact(f"velocity[{i}]", x) from None
        system = on_exact_field(system, values)
        return system, system.velocity(values)


def velocity_numbers(velocity: Sequence[Any]) -> list[Any]:
    """The components of a velocity as exact numbers (errors name ``velocity[i]``)."""
    return [x if type(x) is Fraction else to_number(x, where=f"velocity[{i}]") for i, x in enumerate(velocity)]


def on_exact_field(system: System, values: list[Any]) -> System:
    """The system on the exact backend of all its inputs and ``values`` (the rationals, or their
    number field); InvalidInput (BadNumber) when one of them is not algebraic."""
    return system.convert_to(exact_for(source_numbers(system) + values))


def source_numbers(system: System) -> list[Any]:
    """Every number the system was built from (mass matrix, normals, time terms, CORs), exactly."""
    src = system.source
    everything = [x for row in src["mass_matrix"] for x in row] + [x for row in src["normals"] for x in row]
    return everything + list(src["time_terms"]) + list(src["restitution"])


#: the slots that :meth:`System.with_restitution` shares (the geometry); the others it sets anew
_SHARED_SLOTS = tuple(
    s for s in System.__slots__ if s not in ("__weakref__", "source", "restitution", "_minus_one_plus_e",
                                              "_single_coefficient")
)  # fmt: skip
