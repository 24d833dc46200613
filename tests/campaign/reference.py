#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Outside references for the campaign's designs and statistics (tests/campaign/*.cpp).

  reference.py REQUEST.json ANSWER.json

REQUEST is {"task": ..., ...}; the answer is JSON. Tasks, each computed by OpenTURNS or SciPy
(never by flexloop's code):
  sobol_points     {dim, count}: the first `count` points of the unscrambled Sobol sequence
                   (scipy.stats.qmc.Sobol, Joe-Kuo direction numbers), origin included.
  quantile_ranks   {cases: [[n, p, confidence]]}: the ranks (l, u) of the narrowest
                   order-statistic interval with P(l <= B < u) >= confidence, B ~ Binomial(n, p),
                   tails as equal as possible, finite ends (1 <= l < u <= n) when any pair has
                   enough coverage, else with rank 0 / n + 1 (brute force, scipy.stats.binom).
  wilks            {cases: [[alpha, beta, i]]}: ot.Wilks.ComputeSampleSize.
  clopper_pearson  {cases: [[k, n, confidence]]}: scipy.stats.beta.ppf bounds.
  sobol_indices    {n, d, x, y} in flexloop's Saltelli layout (row b*(d+2)+j): reordered into
                   OpenTURNS's [A; B; E_1..E_d] and given to MauntzKucherenkoSensitivityAlgorithm
                   (first order: the Saltelli 2010 form) and JansenSensitivityAlgorithm (total,
                   OpenTURNS divides by 2N-1; flexloop by 2N: both answers are returned).
  c2_discrepancy   {samples: {name: [[...]]}}: ot.SpaceFillingC2 (centred L2 discrepancy).
  subset_sampling  {dim, beta, n, p0, seed}: ot.SubsetSampling of the event
                   (z_1 + ... + z_dim) / sqrt(dim) >= beta, Z ~ N(0, I), n per level: its
                   estimate, coefficient of variation, evaluations and levels, and the exact
                   Phi(-beta).
"""
import json
import sys

import numpy as np


def sobol_points(req):
    from scipy.stats import qmc
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # "balance properties need a power of 2": not our point
        return qmc.Sobol(req["dim"], scramble=False).random(req["count"]).tolist()


def quantile_ranks(req):
    from scipy.stats import binom
    out = []
    for n, p, confidence in req["cases"]:
        k = np.arange(n + 2)
        below = np.where(k == 0, 0.0, binom.cdf(k - 1, n, p))        # P(B < l)
        above = np.where(k == 0, 1.0, binom.sf(k - 1, n, p))         # P(B >= u)
        best = None
        for l_min, u_max in ((1, n), (0, n + 1)):  # finite ends first, then an infinite one
            for l in range(l_min, u_max):
                for u in range(l + 1, u_max + 1):
                    cov = 1.0 - below[l] - above[u]
                    if cov >= confidence:
                        key = (u - l, abs(below[l] - above[u]))
                        if best is None or key < best[0]:
                            best = (key, l, u, cov)
                        break  # a larger u is wider
            if best is not None:
                break
        out.append({"n": n, "p": p, "lo_rank": best[1], "hi_rank": best[2], "coverage": best[3]})
    return out


def wilks(req):
    import openturns as ot
    return [int(ot.Wilks.ComputeSampleSize(a, b, i)) for a, b, i in req["cases"]]


def clopper_pearson(req):
    from scipy.stats import beta
    out = []
    for k, n, confidence in req["cases"]:
        alpha = 1.0 - confidence
        lo = 0.0 if k == 0 else float(beta.ppf(alpha / 2, k, n - k + 1))
        hi = 1.0 if k == n else float(beta.ppf(1 - alpha / 2, k + 1, n - k))
        out.append({"lo": lo, "hi": hi})
    return out


def sobol_indices(req):
    import openturns as ot
    n, d = req["n"], req["d"]
    x = np.array(req["x"]).reshape(n, d + 2, d)
    y = np.array(req["y"]).reshape(n, d + 2)
    order = [0, 1] + list(range(2, d + 2))  # A, B, E_1..E_d: blocks of n rows each
    X = ot.Sample(np.concatenate([x[:, j, :] for j in order]))
    Y = ot.Sample(np.concatenate([y[:, j] for j in order]).reshape(-1, 1))
    first = ot.MauntzKucherenkoSensitivityAlgorithm(X, Y, n).getFirstOrderIndices()
    total = ot.JansenSensitivityAlgorithm(X, Y, n).getTotalOrderIndices()
    total_2n = [t * (2 * n - 1) / (2 * n) for t in total]
    return {"first": list(first), "total_openturns": list(total), "total": total_2n}


def c2_discrepancy(req):
    import openturns as ot
    c2 = ot.SpaceFillingC2()
    return {name: c2.evaluate(ot.Sample(pts)) for name, pts in req["samples"].items()}


def subset_sampling(req):
    import openturns as ot
    d, beta = req["dim"], req["beta"]
    ot.RandomGenerator.SetSeed(req["seed"])
    names = ["x%d" % i for i in range(d)]
    g = ot.MemoizeFunction(ot.SymbolicFunction(names, ["(%s) / sqrt(%d)" % ("+".join(names), d)]))
    event = ot.ThresholdEvent(ot.CompositeRandomVector(g, ot.RandomVector(ot.Normal(d))),
                              ot.GreaterOrEqual(), beta)
    algo = ot.SubsetSampling(event)
    algo.setMaximumOuterSampling(req["n"])
    algo.setBlockSize(1)
    algo.setConditionalProbability(req["p0"])
    algo.run()
    r = algo.getResult()
    return {"estimate": r.getProbabilityEstimate(), "cov": r.getCoefficientOfVariation(),
            "evaluations": g.getInputHistory().getSize(), "levels": algo.getStepsNumber(),
            "exact": ot.Normal().computeComplementaryCDF(beta)}


TASKS = {f.__name__: f for f in (sobol_points, quantile_ranks, wilks, clopper_pearson,
                                 sobol_indices, c2_discrepancy, subset_sampling)}

if __name__ == "__main__":
    request = json.load(open(sys.argv[1]))
    answer = TASKS[request["task"]](request)
    with open(sys.argv[2], "w") as f:
        json.dump(answer, f)
