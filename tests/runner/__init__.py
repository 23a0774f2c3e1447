"""verify/runner/: tasks, checkpoints, Dask."""
