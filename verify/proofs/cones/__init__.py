"""Cones that prove the rule never exits, for any number of constraints: exact cone membership
(:mod:`~verify.proofs.cones.lp`) and cones that a period of impulses maps into itself
(:mod:`~verify.proofs.cones.period`; the shapes of their generators: :mod:`~verify.proofs.cones.shape`,
:mod:`~verify.proofs.cones.stages`, :mod:`~verify.proofs.cones.face`)."""
