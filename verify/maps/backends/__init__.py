"""The parametric arithmetic that only the maps use: a plane of two parameters, towers of number fields,
elimination. (The one-parameter rational functions stay in :mod:`verify.numbers.backends`: the symbolic
backend and the algebraic numbers use them too.)"""
