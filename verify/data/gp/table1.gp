\\ Table 1 of Pasquero (2021), Sect. 4.1: the three-ball Newton's cradle, unit masses, ball 1
\\ at v0 and the others at rest, one COR eps for both contacts, in the paper's mode: at most
\\ maxit impulses (10^4) and the "almost equal exit velocities" (AEEV) stop. Needs rule.gp.
\\
\\ The AEEV stop is the reading paper mode uses (verify/models/paper.py, PAPER_READING
\\ l2_pair/v/before): before each impulse, once an impact remains, stop when the Euclidean
\\ norm of the pairwise differences of the velocities is strictly below sigma ||v||
\\ (sigma = 10^-9), compared squared so that it is exact on rationals.

cradle_system(eps) = rule_system(matid(3), [-1, 1, 0; 0, -1, 1], [eps, eps]);
aeev(v, sigma) = sum(i = 1, #v, sum(j = i + 1, #v, (v[i] - v[j])^2)) < sigma^2 * norml2(v);
table1_run(eps, v0, maxit, sigma) = rule_run(cradle_system(eps), [v0, 0, 0]~, maxit, v -> aeev(v, sigma));
\\ every row: a vector of [impact sets, exit velocity, stop]
table1(epss, v0, maxit, sigma) = vector(#epss, i, table1_run(epss[i], v0, maxit, sigma));
