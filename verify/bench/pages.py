"""The report page of the benchmarks: the figures of ``reports/bench.json`` (``verify bench --save``)."""

from __future__ import annotations

from pathlib import Path

from verify.views.pages import block, wrapped


def performance_page(out: Path) -> str:
    """The page of ``out/bench.json`` (copied there from ``reports/bench.json`` when missing)."""
    import json

    from verify.bench.throughput import bench_text, requirements
    from verify.records.files import write_atomic

    saved = out / "bench.json"
    source = saved if saved.exists() else Path("reports") / "bench.json"
    if not source.exists():
        return (
            "# Performance\n\nNo benchmark record yet: run `verify bench --save reports/bench.json`, then "
            "`verify report`.\n"
        )
    data = source.read_bytes()
    if source != saved:  # keep the record beside the page it feeds
        write_atomic(saved, data)
    record = json.loads(data)
    targets = requirements(record)
    met = [t for t in targets if t.endswith(": met")]
    missed = [t.rsplit(":", 1)[0] for t in targets if t.endswith(": NOT met")]
    found = (f"**What was found.** {len(met)} of the {len(met) + len(missed)} speed targets the project set are met"
             + (f"; not met: {'; '.join(missed)}." if missed else "."))  # fmt: skip
    return (
        "# Performance\n\n"
        + "\n".join(wrapped(found))
        + "\n\nFigures of `verify bench --save reports/bench.json` (the record is `bench.json`, beside this page;\n"
        "`verify report` renders it and never times anything, so the reports stay reproducible). Each ratio is\n"
        "against a baseline timed alternately in the same run, best of 3; see `verify bench --help`.\n\n"
        "## The targets\n\n"
        + "\n".join(f"- {line}" for line in targets)
        + "\n\n## The figures\n\n"
        + block(bench_text(record))
        + "\n## Appendix: how the figures are made\n\n"
        + PERFORMANCE_NOTES
    )


PERFORMANCE_NOTES = """\
- Each batch (`batch` in `bench.json`; `verify bench --help`) has its own plain loop over
  `fractions.Fraction`, timed in the same run: the corner's eq. (10) with the paper's closed forms, or
  a textbook loop written for this benchmark for the cradle and general systems. Every
  contestant keeps what the plain loop keeps: the branch sequence and the last velocity of each case.
- The exact engine is the general one: a `System` built and checked per case (symmetric positive
  definite mass matrix, independent normals, CORs in [0, 1]), then `solve` without a trace. It runs
  the rule in rate coordinates (the impulses act on the r rates
  through the Gram matrix alone, and the velocity is formed once, at the end), and a long run over
  integers with one common denominator. The cradle batch uses the
  batch entry point `solve_many`: the geometry is built once and each COR shares it.
- `corner_short` is where the set-up of a case is most of the work. `bare_rates` is the same
  computation written out bare (nothing checked, no object built): a
  bound on what Python code reaches there. PARI/GP does the set-up in a few calls into its C library.
- Table 1: `table1.runs` computes the 17 rows in exact and paper mode (exact numbers; exact mode also
  proves that the two lowest rows never exit); `table1.gp` is the paper's loop in GP's reals, the
  paper's own arithmetic, and `table1.gp_rationals` the same loop on exact rationals.
- The certified float path certifies every branch: for two
  constraints the rounding error is bounded in the frame of the rates themselves, so it does not grow
  with alternating impacts; a sign it cannot certify is decided by an exact catch-up over integers
  from the case's last exact state (`float_path_rung_catch_up`), and a case redone exactly only when
  floats cannot hold it (`float_path_rung_exact`). The plain float loop takes a wrong branch sequence
  on `float_loop_wrong_branches` cases.
- Intervals run on rate midpoints with one radius in the kinetic-energy norm,
  which single impacts do not expand, so the precision stays at its
  start (`interval_digits`) and the cost per impulse stays flat while the exact numbers grow
  (`exact_bits`). A run pays a fixed set-up (the constants of the system, the enclosure of the
  exit velocity), so on short runs (`impulse_cost.interval.10`) intervals cost more than exact numbers.
"""
