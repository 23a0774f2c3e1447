"""A system of your own, end to end: a rod whose two ends touch the floor at once.

Read it as a notebook, cell by cell (``# %%``), or run it whole::

    python3 examples/rod_on_floor.py                 # the map and the verdict table, as text
    python3 examples/rod_on_floor.py --figure rod.png   # also the map as a figure (extra: figures)

1. The system, from its constraint functions (``System.from_functions``): a uniform rod of mass m and
   length L in the plane, coordinates (x, y, theta), lying flat on the floor y = 0. Its ends are at
   height ``y -+ (L/2) sin(theta)``: two contacts at once, whose normals are not orthogonal.
2. One run, exactly.
3. Its map over the two CORs (one per end) on an exact grid of lines (``eps_map``).
4. The property suite on a family of rods (a Hypothesis strategy): the verdict table, with the
   counterexamples as case records that ``verify solve`` reproduces.
"""

from __future__ import annotations

import sys
from fractions import Fraction

import sympy as sp
from hypothesis import strategies as st

from verify.dynamics.system import System
from verify.laws.rule import solve
from verify.maps.general import eps_map
from verify.maps.text import eps_map_text
from verify.properties.own import family_verdicts
from verify.properties.text import properties_text

x, y, theta = sp.symbols("x y theta")


# %% 1. The system
def rod(mass: object = 1, length: object = 2, cors: tuple[object, object] = (1, 1)) -> System:
    """The rod of ``mass`` and ``length`` flat on the floor, ends named ``left`` and ``right``."""
    m, half = sp.nsimplify(mass), sp.nsimplify(length) / 2
    inertia = m * (2 * half) ** 2 / 12
    ends = [y - half * sp.sin(theta), y + half * sp.sin(theta)]  # the heights of the two ends
    return System.from_functions(
        ends,
        [x, y, theta],
        {x: 0, y: 0, theta: 0},
        [[m, 0, 0], [0, m, 0], [0, 0, inertia]],
        list(cors),
        names=["left", "right"],
    )


# %% 2. One run: falling at speed 1 and turning, the left end first harder
def one_run() -> str:
    return solve(rod(cors=("1/2", "1/2")), ["0", "-1", "1/4"]).summary()


# %% 3. The map over (e_left, e_right)
def rod_map(lines: int = 3):
    return eps_map(rod(), ["0", "-1", "1/4"], ["e_left", "e_right"], lines=lines, max_impulses=40)


# %% 4. The property suite on a family of rods
@st.composite
def rods(draw) -> tuple[System, list[Fraction]]:
    """Rods of rational mass and length, rational CORs, falling (y' = -1) and turning."""
    mass = draw(st.integers(1, 6)) / Fraction(draw(st.integers(1, 3)))
    length = draw(st.integers(1, 6)) / Fraction(draw(st.integers(1, 3)))
    cors = tuple(Fraction(draw(st.integers(0, 10)), 10) for _ in range(2))
    spin = Fraction(draw(st.integers(-8, 8)), 4) / length
    return rod(mass, length, cors), [Fraction(0), Fraction(-1), spin]


def verdict_table(examples: int = 50) -> str:
    found = family_verdicts(rods(), "rod", rules=("general", "symmetric"), examples=examples)
    return properties_text(f"{examples} rods a row", found)


def main(argv: list[str]) -> int:
    print(one_run(), "\n")
    m = rod_map()
    print(eps_map_text(m))
    if "--figure" in argv:
        from verify.maps.figures import eps_map_figure

        path = argv[argv.index("--figure") + 1]
        eps_map_figure(m, path)
        print(f"figure written to {path}", file=sys.stderr)
    print(verdict_table())
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
