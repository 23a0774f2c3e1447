"""Long runs as tasks: local processes or a Dask cluster, with a checkpoint (:mod:`~verify.runner.tasks`).
Infrastructure below the features: the properties, the paper's sweeps and the reports use it."""
