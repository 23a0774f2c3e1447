"""One adapter per physics engine (``python -m verify.engines.adapters.NAME`` reads a case file on stdin):
each module holds only what its engine does differently from :mod:`verify.engines.protocol` and
:mod:`verify.engines.common`."""
