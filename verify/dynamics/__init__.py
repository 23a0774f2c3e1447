"""The mechanical system: masses, constraints and CORs (:mod:`~verify.dynamics.system`), the rates of its
impact sets in closed form (:mod:`~verify.dynamics.rates`) and the limits of a run
(:mod:`~verify.dynamics.policy`). Built on :mod:`verify.numbers`."""
