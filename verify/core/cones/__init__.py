"""Cones that prove the rule never exits, for any number of constraints: exact cone membership
(:mod:`~verify.core.cones.lp`) and cones that a period of impulses maps into itself
(:mod:`~verify.core.cones.period`; the shapes of their generators: :mod:`~verify.core.cones.shape`,
:mod:`~verify.core.cones.stages`, :mod:`~verify.core.cones.face`)."""
