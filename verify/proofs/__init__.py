"""Proofs that a run never exits: termination certificates (:mod:`~verify.proofs.termination`) and the
cones that a period of impulses maps into itself (:mod:`~verify.proofs.cones`). They read the system and
its rates (:mod:`verify.dynamics`); the laws stop a run with them."""
