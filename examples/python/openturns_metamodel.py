#!/usr/bin/env python3
"""A kriging metamodel of a Poise study's LOS error in OpenTURNS, and its Sobol indices beside
Poise's own (`poise sensitivity`), each with its 95% interval.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/openturns_metamodel.py [--study S] [--small]

Steps:
1. Poise's own Sobol indices of the full model (poise.run with sensitivity_base): they also
   screen the inputs. A LOS study has about 50 inputs (an amplitude and a phase per bearing
   error); 200 points cannot teach a kriging 50 dimensions, so it learns the --inputs (8)
   with the largest total indices, and the rest acts as noise (a nugget).
2. Study.evaluate, wrapped as an OpenTURNS function of all the inputs (vectorized: one call
   per sample of points, no per-point Python), gives the outputs of 200 of the study's own
   draws (poise.run gives the inputs each sample drew: the input distribution the study
   samples). Inputs are standardized for the kriging (their units differ: um, arcsec, deg).
3. Kriging (constant trend, squared-exponential covariance with a nugget, OpenTURNS'
   hyperparameter fit), checked on 1000 fresh draws: Q2, the share of the output's variance
   it predicts.
4. Sobol indices of the metamodel: OpenTURNS' pick-freeze estimators (first order
   Mauntz-Kucherenko, i.e. Saltelli 2010; total Jansen 1999, as Poise uses) over the empirical
   marginals of 4096 draws (the inputs are drawn independently), with bootstrap intervals,
   then scaled by the metamodel's share of the output's variance (Var metamodel / Var output
   on the fresh draws) to be shares of the full output's variance, as Poise's are.
5. Both printed side by side; "overlap" says whether the two 95% intervals overlap. A low Q2
   explains a disagreement: the metamodel, not Poise, is then the coarse one.

Needs Debian's python3-openturns and python3-numpy, and the Poise module (PYTHONPATH).
"""
import argparse
import os
import sys

import numpy as np
import openturns as ot

import poise

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))


def interval_text(value, lo, hi):
    return f"{value:6.3f} [{lo:6.3f}, {hi:6.3f}]"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--study", default=os.path.join(ROOT, "studies", "los_seeker_wang2011.toml"))
    parser.add_argument("--output", default=None, help="output to model (default: the study's first)")
    parser.add_argument("--training", type=int, default=200, help="training points of the kriging (200)")
    parser.add_argument("--inputs", type=int, default=8, help="inputs the kriging learns (8)")
    parser.add_argument("--base", type=int, default=2048, help="base rows of both Sobol estimates (2048)")
    parser.add_argument("--small", action="store_true", help="small sizes, for the test suite")
    args = parser.parse_args()
    if args.small:
        args.training, args.base, args.inputs = 60, 128, 4
    ot.Log.Show(ot.Log.NONE)
    ot.RandomGenerator.SetSeed(1)

    study = poise.Study(args.study)
    if not study.evaluates:
        sys.exit(f"{args.study}: {study.why_not}")
    names = study.input_names
    output = args.output or study.output_names[0]
    unit = study.output_units[output]

    # 1. Poise's indices of the full model; the inputs with the largest totals are learnt.
    sens = poise.run(args.study, seed=11, threads=0, sensitivity_base=args.base).summary["sensitivity"]
    poise_indices = {e["group"]: e for e in sens["outputs"][output]["indices"]}
    ranked = sorted((n for n in names if n in poise_indices),
                    key=lambda n: -(poise_indices[n]["total"]["value"] or 0.0))
    chosen = ranked[:args.inputs]
    cols = [names.index(n) for n in chosen]

    # 2. Study.evaluate as an OpenTURNS function of all the inputs, in their own units.
    def evaluate(points):
        y = study.evaluate(np.asarray(points, dtype=np.float64), threads=0)
        return np.asarray(y[output]).reshape(-1, 1)

    model = ot.PythonFunction(len(names), 1, func_sample=evaluate)
    model.setInputDescription(names)
    model.setOutputDescription([output])
    draws = poise.run(args.study, samples=4096 + args.training + 1000, seed=7, threads=0)
    x_all = np.column_stack([draws.inputs[n] for n in names])[draws.ok]
    x_train, x_check, x_pool = x_all[:args.training], x_all[args.training:args.training + 1000], x_all[-4096:]
    y_train = np.asarray(model(ot.Sample(x_train)))
    y_check = np.asarray(model(ot.Sample(x_check))).ravel()

    # 3. Kriging of the chosen inputs, standardized; the others are its noise (nugget).
    centre, scale = x_pool[:, cols].mean(axis=0), x_pool[:, cols].std(axis=0)
    scale[scale == 0] = 1.0
    dim = len(cols)
    covariance = ot.SquaredExponential([1.0] * dim, [float(np.std(y_train)) or 1.0])
    covariance.setNuggetFactor(0.1)
    kriging = ot.KrigingAlgorithm(ot.Sample((x_train[:, cols] - centre) / scale), ot.Sample(y_train), covariance,
                                  ot.ConstantBasisFactory(dim).build())
    kriging.setOptimizeParameters(True)
    kriging.run()
    standardized = kriging.getResult().getMetaModel()
    metamodel = ot.ComposedFunction(standardized, ot.LinearFunction(centre, [0.0] * dim, ot.Matrix(np.diag(1.0 / scale))))
    y_pred = np.asarray(metamodel(ot.Sample(x_check[:, cols]))).ravel()
    q2 = 1.0 - np.mean((y_check - y_pred) ** 2) / np.var(y_check)
    share = float(np.var(y_pred) / np.var(y_check))

    # 4. Sobol indices of the metamodel over the empirical marginals, as shares of the output.
    distribution = ot.ComposedDistribution([ot.UserDefined(ot.Sample(x_pool[:, [j]])) for j in cols])
    design = ot.SobolIndicesExperiment(distribution, args.base, False).generate()
    response = metamodel(design)
    first = ot.MauntzKucherenkoSensitivityAlgorithm(design, response, args.base)
    total = ot.JansenSensitivityAlgorithm(design, response, args.base)
    first.setBootstrapSize(300)
    total.setBootstrapSize(300)
    s1, st = first.getFirstOrderIndices(), total.getTotalOrderIndices()
    s1_ci, st_ci = first.getFirstOrderIndicesInterval(), total.getTotalOrderIndicesInterval()

    # 5. Side by side.
    print(f"{os.path.basename(args.study)}: {output} [{unit}], {len(names)} inputs; the kriging learns the {dim} "
          f"with the largest total indices (poise sensitivity, base {args.base})")
    print(f"kriging on {args.training} of the study's draws: Q2 on 1000 fresh draws = {q2:.3f} (the share of the "
          f"output's variance it predicts); its own variance is {share:.3f} of the output's, and its indices below "
          f"are scaled by that")
    if q2 < 0.5:
        print(f"warning: Q2 = {q2:.3f} < 0.5: the metamodel predicts little of {output}; its indices are no check of "
              f"Poise's (more training points, fewer inputs, or a smoother output would help)")
    print("Sobol indices as shares of the output's variance, 95% intervals: metamodel (OpenTURNS) beside the full "
          "model (poise sensitivity)")
    print(f"{'input':36s} {'S kriging':>24s} {'S poise':>24s}  {'ST kriging':>24s} {'ST poise':>24s}  overlap")
    agree = 0
    for j, name in enumerate(chosen):
        p = poise_indices[name]
        lo1, hi1 = share * s1_ci.getLowerBound()[j], share * s1_ci.getUpperBound()[j]
        lot, hit = share * st_ci.getLowerBound()[j], share * st_ci.getUpperBound()[j]
        pf, pt = p["first"], p["total"]
        pf_lo, pf_hi = (pf["ci95"][0], pf["ci95"][1]) if pf["ci95"][0] is not None else (pf["value"], pf["value"])
        pt_lo, pt_hi = (pt["ci95"][0], pt["ci95"][1]) if pt["ci95"][0] is not None else (pt["value"], pt["value"])
        overlap = hi1 >= pf_lo and pf_hi >= lo1 and hit >= pt_lo and pt_hi >= lot
        agree += overlap
        print(f"{name:36s} {interval_text(share * s1[j], lo1, hi1):>24s} {interval_text(pf['value'], pf_lo, pf_hi):>24s}  "
              f"{interval_text(share * st[j], lot, hit):>24s} {interval_text(pt['value'], pt_lo, pt_hi):>24s}  "
              f"{'yes' if overlap else 'no'}")
    print(f"{agree} of {dim} inputs: the intervals of both indices overlap")
    return 0


if __name__ == "__main__":
    sys.exit(main())
