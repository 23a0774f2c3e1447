"""verify/bench/: the benchmarks."""
