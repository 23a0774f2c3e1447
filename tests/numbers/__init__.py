"""verify/numbers/: the parser, exact formatting, the backends, rational functions."""
