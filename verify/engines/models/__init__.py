"""Exact models of physics engines' own step loops, each with the engine's parameters.

:mod:`~verify.engines.models.dart` (DART: a boxed LCP per step with CFM and ERP),
:mod:`~verify.engines.models.bullet` (Bullet as pybullet runs it: sequential impulses with slop, split
impulses and a residual stop) and :mod:`~verify.engines.models.box2d` (Box2D 2.3: warm-started sequential
impulses with a velocity threshold, then position correction and its time of impact,
:mod:`~verify.engines.models.toi`) run a case as the engine's adapter does,
step by step, over the case's number field (:mod:`~verify.engines.models.steps`). :data:`STEP_MODELS`
names them as the engines' ``solver`` descriptions do (``step_model``).

>>> sorted(STEP_MODELS), orders(3)[:2]
(['box2d', 'bullet', 'dart'], [(0, 1, 2), (0, 2, 1)])
"""

from __future__ import annotations

from typing import Any

from verify.engines.models.box2d import Box2D
from verify.engines.models.bullet import Bullet
from verify.engines.models.dart import Dart
from verify.engines.models.steps import ALL_ORDERS, orders

__all__ = ["ALL_ORDERS", "STEP_MODELS", "Box2D", "Bullet", "Dart", "orders"]

#: the step models by the name an engine's ``solver.step_model`` gives
STEP_MODELS: dict[str, Any] = {"dart": Dart, "bullet": Bullet, "box2d": Box2D}
