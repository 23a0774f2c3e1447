"""The paper's corner (Sect. 4.2: alpha = pi/6, entered at phi = pi/12) mapped over its CORs: where its statement
that repeated multiple impacts occur when the CORs are very different holds, with exact boundaries.

The maps are :func:`verify.maps.general.eps_map` over the number field of the corner's numbers: the line
eps2 = 1/1000 (the paper's eps2) with eps1 over [0, 1], from the paper's velocity (cos(pi/12), sin(pi/12), 0), over
Q(sqrt(2), sqrt(3)); and the square of both CORs as exact cells, from (1, tan(pi/12), 0) = (1, 2 - sqrt(3), 0), the
same direction at the speed 1/cos(pi/12) (:func:`verify.models.corner.direction_of`: the rule is positively
homogeneous, so the impact sets and stops are the paper's), over Q(sqrt(3)), where the cells cost a third of the time.
A run has *repeated multiple impacts* when its first two impulses are both on both walls (the paper's example:
Z12 -> Z12 -> Z2 -> Z0). Two impulses decide it; the cells run three, which decide where all but a sliver of the
square exits.

>>> found = corner_maps(line_impulses=4, plane_impulses=1)
>>> [str(piece) for piece in found.repeated_pieces()], found.repeated_plane
(['(1513/6500 + 2013*sqrt(3)/6500, 1]'], [])
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from verify.maps.general import EpsMap, eps_map
from verify.maps.plane import PlaneMap
from verify.models.corner import corner_system, direction_of, slope_of, velocity_of
from verify.numbers.backends.symbolic import Piece

#: the paper's corner and entrance direction (Sect. 4.2) and its eps2
ALPHA, PHI, EPS2 = "pi/6", "pi/12", "1/1000"
#: impulses of the line's runs, and of the cells' (two decide whether the first two are multiple impacts)
LINE_IMPULSES, PLANE_IMPULSES = 12, 3


def repeated(impact_sets: list[tuple[int, ...]]) -> bool:
    """Whether the first two impulses are both multiple impacts (on both walls)."""
    return len(impact_sets) >= 2 and all(len(J) == 2 for J in impact_sets[:2])


@dataclass
class CornerMaps:
    """The two maps and the parts of each with repeated multiple impacts."""

    line: EpsMap
    plane: EpsMap
    repeated_line: list[Any]  # Parts of the line (eps1 over [0, 1], eps2 = 1/1000)
    repeated_plane: list[Any]  # CellParts of the square

    def repeated_pieces(self) -> list[Piece]:
        """The values of eps1 on the line with repeated multiple impacts, as few intervals as they make (exact ends)."""
        out: list[Piece] = []
        for p in self.repeated_line:
            last = out[-1] if out else None
            if last is not None and last.upper == p.piece.lower and last.upper_closed != p.piece.lower_closed:
                out[-1] = Piece(last.lower, p.piece.upper, last.lower_closed, p.piece.upper_closed)
            else:
                out.append(p.piece)
        return out

    @property
    def cells(self) -> PlaneMap:
        """The cells of the square of both CORs (the map over two parameters always has them)."""
        return self.plane.cells

    def repeated_area(self) -> tuple[Fraction, Fraction]:
        """Exact bounds of the area of the square where the first two impulses are multiple impacts."""
        return self.cells.bounds_of(self.repeated_plane)


def corner_maps(*, line_impulses: int = LINE_IMPULSES, plane_impulses: int = PLANE_IMPULSES) -> CornerMaps:
    """The paper's corner mapped over eps1 (eps2 = 1/1000) and over the square of both CORs (see the module)."""
    system = corner_system(slope_of(alpha=ALPHA), "1", "1")
    line = eps_map(system, velocity_of(PHI, "1"), ["eps1", EPS2], max_impulses=line_impulses)
    plane = eps_map(system, direction_of(PHI), ["eps1", "eps2"], max_impulses=plane_impulses, cells=True)
    assert plane.plane is not None
    return CornerMaps(
        line,
        plane,
        [p for p in line.lines[0].parts if repeated(p.impact_sets)],
        [p for p in plane.plane.parts if repeated(p.impact_sets)],
    )
