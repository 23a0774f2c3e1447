"""Physics engines as implementations under test: what a case looks like to an engine.

:mod:`~verify.physics.scene` recognises the cases that an engine can build (cradles and
corners, exactly); :mod:`~verify.physics.protocol` is the adapter program's frame (a case
file on stdin, a velocity-only result file on stdout); one module per engine holds its
adapter (``python -m verify.physics.box2d``). Engine outputs are binary floats: nothing
here is an exact path.
"""

#: the engines: report name -> adapter module (``python -m MODULE`` reads a case file on stdin)
ENGINES: dict[str, str] = {
    "box2d": "verify.physics.box2d",
    "pymunk": "verify.physics.pymunk",
    "pybullet": "verify.physics.pybullet",
    "mujoco": "verify.physics.mujoco",
    "dartpy": "verify.physics.dartpy",
    "nimblephysics": "verify.physics.nimble",
    "sapien": "verify.physics.sapien",
    "newton": "verify.physics.newton",
    "mujoco_warp": "verify.physics.mujoco_warp",
    "genesis": "verify.physics.genesis",
}
