"""Physics engines as implementations under test: what a case looks like to an engine.

:mod:`~verify.engines.scene` recognises the cases that an engine can build (cradles and
corners, exactly); :mod:`~verify.engines.protocol` is the adapter program's frame (a case
file on stdin, a velocity-only result file on stdout); one module per engine holds its
adapter in :mod:`verify.engines.adapters` (``python -m verify.engines.adapters.box2d``);
:mod:`~verify.engines.run` runs them on the oracle's cases (``verify engines``) and
:mod:`~verify.engines.explain` explains each answer by an exact model. Engine outputs are binary
floats: nothing here is an exact path.
"""

#: the engines: report name -> adapter module (``python -m MODULE`` reads a case file on stdin)
ENGINES: dict[str, str] = {
    "box2d": "verify.engines.adapters.box2d",
    "pymunk": "verify.engines.adapters.pymunk",
    "pybullet": "verify.engines.adapters.pybullet",
    "mujoco": "verify.engines.adapters.mujoco",
    "dartpy": "verify.engines.adapters.dartpy",
    "nimblephysics": "verify.engines.adapters.nimble",
    "sapien": "verify.engines.adapters.sapien",
    "newton": "verify.engines.adapters.newton",
    "mujoco_warp": "verify.engines.adapters.mujoco_warp",
    "genesis": "verify.engines.adapters.genesis",
}
