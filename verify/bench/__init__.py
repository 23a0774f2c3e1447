"""The benchmarks (``verify bench``): throughput beside a baseline measured in the same run
(:mod:`~verify.bench.throughput`), the plain loop over Fractions (:mod:`~verify.bench.baselines`) and the
paper's loop in PARI/GP (:mod:`~verify.bench.gp`)."""
