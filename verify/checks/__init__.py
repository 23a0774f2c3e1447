"""The checks: the property suite, the paper's claims, the reference oracle, the benchmarks."""
