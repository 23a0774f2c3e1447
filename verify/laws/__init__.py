"""The impact laws: the paper's rule (eqs. 4-8, :mod:`~verify.laws.rule`), the simultaneous and the
sequential laws, their results (:mod:`~verify.laws.outcome`) and the rule's fast loops over integers,
balls and floats (:mod:`~verify.laws.loops`). The rule stops a run that never exits with a proof from
:mod:`verify.proofs`."""
