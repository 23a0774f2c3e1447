"""Exact models of physics engines' own step loops, each with the engine's parameters.

:mod:`~verify.engines.models.dart` (DART: a boxed LCP per step with CFM and ERP),
:mod:`~verify.engines.models.bullet` (Bullet as pybullet runs it: sequential impulses with slop, split
impulses and a residual stop) and :mod:`~verify.engines.models.box2d` (Box2D 2.3: warm-started sequential
impulses with a velocity threshold, then position correction) run a case as the engine's adapter does,
step by step, over the case's number field (:mod:`~verify.engines.models.steps`). :data:`STEP_MODELS`
names them as the engines' ``solver`` descriptions do (``step_model``).

>>> orders(3)
[(0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)]
>>> len(orders(5)), orders(6)[1]
(120, (5, 4, 3, 2, 1, 0))
"""

from __future__ import annotations

from itertools import permutations
from typing import Any

from verify.engines.models.box2d import Box2D
from verify.engines.models.bullet import Bullet
from verify.engines.models.dart import Dart

#: the step models by the name an engine's ``solver.step_model`` gives
STEP_MODELS: dict[str, Any] = {"dart": Dart, "bullet": Bullet, "box2d": Box2D}
#: up to this many contacts every order of the solver is tried; beyond, the order given and its reverse
ALL_ORDERS = 5


def orders(r: int) -> list[tuple[int, ...]]:
    """The contact orders a model tries on ``r`` contacts."""
    if r <= ALL_ORDERS:
        return list(permutations(range(r)))
    return [tuple(range(r)), tuple(reversed(range(r)))]
