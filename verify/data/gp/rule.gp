\\ The multiple-impact rule of Pasquero (2021), eqs. (4)-(8): the paper's loop in PARI/GP.
\\
\\ Written the way a GP user would write it, for any n coordinates and r constraints; the
\\ numbers are whatever the inputs are: t_INT/t_FRAC give exact rational arithmetic, t_REAL
\\ the floating point of the current realprecision. verify/bench/gp.py drives it (it times
\\ the loop inside GP and compares the impact sets with the exact engine's).
\\
\\   S = rule_system(g, A, e)   the system: mass matrix g (n x n), normals A (r x n, row i =
\\                              dF_i), CORs e (r); precomputes U = g^-1 A~ and G = A U
\\   rule_run(S, v, maxit, halt) one run from the velocity v (column): returns
\\                              [impact sets (1-based), exit velocity, stop]; stop is "exit",
\\                              "max_iterations" (maxit impulses made) or "aeev" (halt(v) fired)

rule_system(g, A, e) = my(U = g^-1 * A~); [A, U, A * U, e];

\\ Before each impulse: rates b = A v, impact set J = {i : b_i < 0}; exit when J is empty;
\\ otherwise the stop test halt (if any), the cap on impulses, then the impulse of eq. (8):
\\ single impact J = {j}: v -= (1 + e_j) (b_j / G_jj) U_j;
\\ multiple: lambda_j = b_j / G_jj, beta = (sum b_j lambda_j) / (lambda G_JJ lambda~),
\\           v -= beta sum (1 + e_j) lambda_j U_j.
rule_run(S, v, maxit, halt = 0) =
{
  my([A, U, G, e] = S, sets = List(), b, J, lam, beta);
  while (1,
    b = A * v;
    J = [i | i <- [1 .. #b], b[i] < 0];
    if (!#J, return ([Vec(sets), v, "exit"]));
    if (halt && halt(v), return ([Vec(sets), v, "aeev"]));
    if (#sets == maxit, return ([Vec(sets), v, "max_iterations"]));
    if (#J == 1,
      my(j = J[1]);
      v -= (1 + e[j]) * (b[j] / G[j, j]) * U[, j]
    ,
      lam = vector(#J, a, b[J[a]] / G[J[a], J[a]]);
      beta = sum(a = 1, #J, b[J[a]] * lam[a]) / (lam * vecextract(G, J, J) * lam~);
      v -= beta * sum(a = 1, #J, (1 + e[J[a]]) * lam[a] * U[, J[a]])
    );
    listput(sets, J)
  );
}

\\ Batches: one run per case, the system built (U and G computed) per case.
\\ systems: a vector of [g, A, e, v]
rule_systems(systems, maxit) =
  vector(#systems, i, my([g, A, e, v] = systems[i]); rule_run(rule_system(g, A, e), Col(v), maxit));

\\ The disk in a corner (Sect. 4.2): unit mass matrix, walls of slope k with normals (-k, 1, 0)
\\ and (-k, -1, 0); cases: a vector of [k, xd, yd, e1, e2].
corner_system(k, e1, e2) = rule_system(matid(3), [-k, 1, 0; -k, -1, 0], [e1, e2]);
rule_corners(cases, maxit) =
  vector(#cases, i, my([k, xd, yd, e1, e2] = cases[i]); rule_run(corner_system(k, e1, e2), [xd, yd, 0]~, maxit));

\\ Timing: f() run n times in a row, n doubled until the n runs take at least minms
\\ milliseconds (the clock counts whole ms: minms = 200 keeps its resolution under 1%), then
\\ `repeats` measurements of n runs in all (the last doubling counts as the first).
\\ Returns [best seconds for one run, n, the last result of f()].
rule_time(f, repeats, minms = 200) =
{
  my(n = 1, t, out, best);
  while (1,
    t = getabstime();
    for (i = 1, n, out = f());
    t = getabstime() - t;
    if (t >= minms, break);
    n *= 2
  );
  best = t;
  for (r = 2, repeats,
    t = getabstime();
    for (i = 1, n, out = f());
    best = min(best, getabstime() - t)
  );
  [best / 1000 / n, n, out];
}

\\ The report read by verify/bench/gp.py: a header line, then one line per run:
\\ stop|impact sets (indices joined by ",", sets by ";")|exit velocity (joined by ";").
rule_join(v, sep) = my(s = ""); for (i = 1, #v, s = Str(s, if (i > 1, sep, ""), v[i])); s;
rule_report(timed) =
{
  my([seconds, n, runs] = timed);
  print("gp-rule ", seconds * 1., " ", n, " ", default(realprecision), " ", default(realbitprecision));
  for (i = 1, #runs,
    my([sets, v, stop] = runs[i]);
    print(stop, "|", rule_join(apply(J -> rule_join(J, ","), sets), ";"), "|", rule_join(v, ";"))
  );
}
