"""A small independent implementation of the rule (eq. 8) in plain Python floats.

It is the worked example of the README: it reads a case file on stdin and writes a result
file on stdout, so that ``verify oracle check CASES.json --impl "python3
examples/float_impl.py"`` can check it. It imports nothing from ``verify``: number strings
such as ``sqrt(3)/3`` are evaluated by a small walker over Python's expression syntax tree
(names sqrt pi sin cos tan only; nothing is executed). Like most simulators it decides
"incoming" by comparing a float rate with a small tolerance (-1e-12 |v0|) and stops after
``max_iterations`` impulses: it has no notion of a run that provably never ends.
"""

from __future__ import annotations

import ast
import json
import math
import operator
import sys

_NAMES = {"pi": math.pi}
_FUNCS = {"sqrt": math.sqrt, "sin": math.sin, "cos": math.cos, "tan": math.tan}
_OPS = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
        ast.Pow: operator.pow}  # fmt: skip


def number(text: str) -> float:
    def walk(node: ast.AST) -> float:
        if isinstance(node, ast.Expression):
            return walk(node.body)
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):
            return float(node.value)
        if isinstance(node, ast.Name) and node.id in _NAMES:
            return _NAMES[node.id]
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            return -walk(node.operand) if isinstance(node.op, ast.USub) else walk(node.operand)
        if isinstance(node, ast.BinOp) and type(node.op) in _OPS:
            return _OPS[type(node.op)](walk(node.left), walk(node.right))
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in _FUNCS:
            return _FUNCS[node.func.id](*[walk(a) for a in node.args])
        raise ValueError(f"unsupported number {text!r}")

    return walk(ast.parse(text, mode="eval"))


def solve(A: list[list[float]], b: list[float]) -> list[float]:
    n = len(A)
    M = [[*row, b[i]] for i, row in enumerate(A)]
    for c in range(n):
        p = max(range(c, n), key=lambda i: abs(M[i][c]))
        M[c], M[p] = M[p], M[c]
        for i in range(c + 1, n):
            f = M[i][c] / M[c][c]
            M[i] = [x - f * y for x, y in zip(M[i], M[c])]
    x = [0.0] * n
    for i in reversed(range(n)):
        x[i] = (M[i][n] - sum(M[i][j] * x[j] for j in range(i + 1, n))) / M[i][i]
    return x


def run(case: dict) -> dict:
    g = [[number(x) for x in row] for row in case["mass_matrix"]]
    a = [[number(x) for x in row] for row in case["normals"]]
    t = [number(x) for x in case.get("time_terms", ["0"] * len(a))]
    e = [number(x) for x in case["restitution"]]
    v = [number(x) for x in case["velocity"]]
    cap = case.get("max_iterations", 10_000)
    n, r = len(v), len(a)
    U = [solve(g, row) for row in a]  # U_i = g^-1 a_i
    G = [[sum(x * y for x, y in zip(a[i], U[j])) for j in range(r)] for i in range(r)]
    tol = 1e-12 * max(abs(x) for x in v)  # rates above -tol count as not incoming (a common choice)
    sets, betas, stop = [], [], "exit"
    while True:
        rates = [t[i] + sum(x * y for x, y in zip(a[i], v)) for i in range(r)]
        J = [i for i in range(r) if rates[i] < -tol]
        if not J:
            break
        if len(sets) >= cap:
            stop = "max_iterations"
            break
        lam = [rates[j] / G[j][j] for j in J]
        if len(J) == 1:
            beta = 1.0
        else:
            mu = solve([[G[j][k] for k in J] for j in J], [rates[j] for j in J])
            G_lam = [sum(G[j][k] * lk for k, lk in zip(J, lam)) for j in J]
            beta = sum(m * x for m, x in zip(mu, G_lam)) / sum(lj * x for lj, x in zip(lam, G_lam))
        coef = [-beta * (1 + e[j]) * lj for j, lj in zip(J, lam)]
        v = [v[i] + sum(c * U[j][i] for c, j in zip(coef, J)) for i in range(n)]
        sets.append(J)
        betas.append(repr(beta) if len(J) > 1 else None)
    return {"id": case["id"], "exit_velocity": [repr(x) for x in v], "iterations": len(sets),
            "impact_sets": sets, "betas": betas, "stop": stop}  # fmt: skip


if __name__ == "__main__":
    cases = json.load(sys.stdin)["cases"]
    json.dump({"results": [run(c) for c in cases]}, sys.stdout, indent=1)
    sys.stdout.write("\n")
