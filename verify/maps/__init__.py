"""Parameter maps: the rule for every value of one or more parameters at once, cut exactly where it changes.

:mod:`verify.maps.line` maps one parameter over an interval (and, where its run stops at the bound,
widens single runs' cones, :mod:`verify.maps.widen`); :mod:`verify.maps.general` maps
any system's CORs as expressions in parameters (one interval, or a grid of lines). The constants below
are here, apart from SymPy, for the command line's options.
"""

#: grid values per parameter of a map with two or more parameters: the default and the most
DEFAULT_LINES = 5
MAX_LINES = 65
#: rational points of each unexplored interval at which a single run's cone is widened (``--widen``): the
#: default and the most
DEFAULT_WIDEN = 1
MAX_WIDEN = 1000
#: how many times the search for turning cones below a boundary halves a piece on which no cone closes
#: (``--halvings``; each halving takes the cones nearer the boundary, at the cost of a longer search): the default
#: and the most
DEFAULT_HALVINGS = 8
MAX_HALVINGS = 40
