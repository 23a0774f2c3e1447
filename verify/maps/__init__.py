"""Parameter maps: the rule for every value of one or more parameters at once, cut exactly where it changes.

:mod:`verify.maps.line` maps one parameter over an interval; :mod:`verify.maps.general` maps
any system's CORs as expressions in parameters (one interval, or a grid of lines). The constants below
are here, apart from SymPy, for the command line's options.
"""

#: grid values per parameter of a map with two or more parameters: the default and the most
DEFAULT_LINES = 5
MAX_LINES = 65
