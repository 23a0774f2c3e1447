"""verify/laws/: the rule, the simultaneous and sequential laws, the fast loops."""
