"""What the reports show, each topic computed once by one library call (``verify all``, ``verify report``)."""

from __future__ import annotations

import threading
from concurrent.futures import Future
from functools import cached_property
from typing import TYPE_CHECKING

from verify.laws.outcome import Result
from verify.oracle.selfcheck import OracleFindings, oracle_findings
from verify.paper.corner_claims import CornerFindings
from verify.paper.figures import FigureRuns
from verify.paper.pages import CORNER_CASES, CORNER_EXAMPLE

if TYPE_CHECKING:
    from collections.abc import Sequence

    from verify.models.corner import CornerRun
    from verify.paper.corner_map import CornerMaps
    from verify.paper.cradle_map import MapReport
    from verify.paper.table1 import Table1
    from verify.properties.verdicts import Verdict
    from verify.runner.tasks import TaskRunner


class Findings:
    """What the reports show, each topic computed by one library call when first asked for.

    ``verdicts`` reuses property verdicts already computed for ``profile``; the long computations (the
    corner's sweeps, the property rows) are tasks of ``runner`` (a :class:`verify.runner.tasks.TaskRunner`:
    local processes or a Dask cluster, with a checkpoint or not; default one process per core).
    """

    def __init__(
        self, profile: str = "ci", runner: TaskRunner | None = None, verdicts: Sequence[Verdict] | None = None
    ) -> None:
        from verify.runner.tasks import TaskRunner

        self.profile, self.runner = profile, runner or TaskRunner(workers=None)
        self.given_verdicts = verdicts
        self._rows: Future[list[Verdict]] | None = None  # the property rows started by :meth:`start_verdicts`

    def start_verdicts(self) -> None:
        """Start the property rows now, from a thread of this process, on the runner's other processes (a cluster,
        or its :meth:`~verify.runner.tasks.TaskRunner.one_pool`), so that they run while this process computes the
        other topics; :attr:`verdicts` waits for them. Nothing to start when they were given or are started
        already, or when the rows would run in this process (then :attr:`verdicts` computes them)."""
        if self.given_verdicts or self._rows is not None or not self.runner.elsewhere:
            return
        rows: Future[list[Verdict]] = Future()

        def run() -> None:
            try:
                rows.set_result(self._verdicts())
            except BaseException as exc:  # raised again where the verdicts are asked for
                rows.set_exception(exc)

        self._rows = rows
        threading.Thread(target=run, name="verify property rows", daemon=True).start()

    @cached_property
    def table1(self) -> Table1:
        from verify.paper.table1 import table1

        return table1()

    @cached_property
    def cradle_map(self) -> MapReport:
        from verify.maps.cradle import cradle_map
        from verify.paper.cradle_map import map_report

        return map_report(cradle_map(max_impulses=40), approach=6, paper=True)

    @cached_property
    def corner_example(self) -> CornerRun:
        from verify.models.corner import run_corner

        e = CORNER_EXAMPLE
        return run_corner(alpha=e["alpha"], phi=e["phi"], eps1=e["eps1"], eps2=e["eps2"], v0=e["v0"])

    @cached_property
    def corner_maps(self) -> CornerMaps:
        from verify.paper.corner_map import corner_maps

        return corner_maps()

    @cached_property
    def corner(self) -> CornerFindings:
        from verify.paper.corner_claims import corner_findings

        return corner_findings(CORNER_CASES, seed=0, runner=self.runner)

    @cached_property
    def corner_figures(self) -> list[FigureRuns]:
        """The runs of the corner page's figures (the runner's, like the corner's sweeps)."""
        from verify.paper.figures import run_corner_figures

        return run_corner_figures(self.runner)

    @cached_property
    def fig1_runs(self) -> list[Result]:
        """The three cradle runs of the Fig. 1 page."""
        from verify.paper.figures import cradle_motion_runs

        return cradle_motion_runs()

    def computed(self, name: str) -> bool:
        """Whether the finding ``name`` (a cached property, such as ``verdicts``) has been computed already.

        >>> Findings(verdicts=[]).computed("verdicts")
        False
        """
        return name in vars(self)

    @cached_property
    def verdicts(self) -> list[Verdict]:
        return self._rows.result() if self._rows is not None else self._verdicts()

    def _verdicts(self) -> list[Verdict]:
        from verify.properties import verdicts

        if self.given_verdicts:
            return list(self.given_verdicts)
        return verdicts.verdicts(self.profile, runner=self.runner)

    @cached_property
    def oracle(self) -> OracleFindings:
        return oracle_findings()
