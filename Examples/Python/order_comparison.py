"""Second-order against first-order pre-integration at the same step, with the table sizes each
order's sizer chooses, on seeded random volumes and spike transfer functions.

For each case (hovr.randomcases: a random field, 26-36 points a side, uint8, uint16 or float,
and one to three random opacity spikes) and each step (in voxels), each order's
vtkPreIntegrationTableSizer chooses its table as the mapper does (64 MiB, the prefilter measured
for first order); a judge of --judge-rays other random rays then measures both chosen tables
against the reference integrator (RMSE of premultiplied RGBA), ray for ray. It prints per case
and step the two errors, their ratio (second over first) and the ratio's lower bound (the
paired per-ray excess less two standard errors: above 1 only when the rays tell second order
is worse), then how many cases lose by more than --limit (5%) at each step, by the ratio and by
its lower bound, and each order's convergence rate between consecutive steps (the error's
growth, log(e2 / e1) / log(h2 / h1)) over the cases.

    ./hovr python Examples/Python/order_comparison.py [--cases 12] [--first-seed 5000] \\
        [--steps 0.25 0.5 1 2 4] [--judge-rays 8192] [--limit 1.05]
"""

import argparse
import math

import numpy
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkDoubleArray

import hovr
from hovr import randomcases


def chosen_error(image, prop, order, step, judge_rays):
    """The judge's error of the table order's sizer chooses, and its per-ray errors."""
    scalars = image.GetPointData().GetScalars()
    low, high = scalars.GetRange()
    table = hovr.vtkSecondOrderPreIntegrationTable()
    table.SetVolumeProperty(prop)
    table.SetScalarRange(low, high)
    table.SetSegmentLength(order * step)
    table.SetPrefilter(False)
    sizer = hovr.vtkPreIntegrationTableSizer()
    sizer.SetMeasurePrefilter(order == 1)  # as the mapper's automatic prefilter
    if not sizer.Choose(image, scalars, table, order, step):
        return math.nan, None, None
    sizes = (table.GetTableSize(), table.GetChordSize(), table.GetDeviationSize())
    judge = hovr.vtkPreIntegrationTableSizer()
    judge.SetNumberOfRays(judge_rays)
    judge.SetSeed(7)  # other rays than the sizer's (seed 1)
    judge.Prepare(image, scalars, table, order, step)
    error = judge.Measure(*sizes, table.GetChordRange(), table.GetDeviationRange())
    rays = vtkDoubleArray()
    judge.GetLastMeasurePerRay(rays)
    label = "%dx%dx%d%s" % (sizes + ("p" if table.GetPrefilter() else "",))
    return error, vtk_to_numpy(rays).copy(), label


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=12)
    parser.add_argument("--first-seed", type=int, default=5000)
    parser.add_argument("--steps", type=float, nargs="+", default=[0.25, 0.5, 1.0, 2.0, 4.0])
    parser.add_argument("--judge-rays", type=int, default=8192)
    parser.add_argument("--limit", type=float, default=1.05)
    args = parser.parse_args()

    losses = {step: [0, 0] for step in args.steps}
    ratios = {step: [] for step in args.steps}
    # Each case's errors per order and step, for the convergence rates.
    errors = {}
    print("%-5s %-28s %-5s %-12s %-12s %-16s %-16s %7s %7s"
          % ("seed", "volume", "step", "first", "second", "first table", "second table",
             "ratio", "lower"))
    for seed in range(args.first_seed, args.first_seed + args.cases):
        rng = numpy.random.default_rng(seed)
        image, volume_name = randomcases.volume(rng)
        low, high = image.GetPointData().GetScalars().GetRange()
        prop, _ = randomcases.transfer_function(rng, low, high, features=(1, 4),
                                                kinds=("spike",))
        for step in args.steps:
            first, first_rays, first_table = chosen_error(image, prop, 1, step, args.judge_rays)
            second, second_rays, second_table = chosen_error(image, prop, 2, step,
                                                             args.judge_rays)
            if not (first > 0) or first_rays is None or second_rays is None:
                print("%-5d %-28s %-5g (no error to compare: %g, %g)"
                      % (seed, volume_name, step, first, second))
                continue
            # Paired over the judge's rays: second order's excess of squared error, less two
            # standard errors, as a ratio of errors.
            differences = second_rays - first_rays
            margin = 2.0 * differences.std() / math.sqrt(differences.size)
            lower = math.sqrt(max(0.0, second ** 2 - margin)) / first
            ratio = second / first
            ratios[step].append(ratio)
            errors.setdefault(seed, {})[step] = (first, second)
            losses[step][0] += ratio > args.limit
            losses[step][1] += lower > args.limit
            print("%-5d %-28s %-5g %-12.4g %-12.4g %-16s %-16s %7.3f %7.3f"
                  % (seed, volume_name, step, first, second, first_table, second_table, ratio,
                     lower))
    print()
    print("step   cases  median ratio  largest  ratio > %g  lower bound > %g"
          % (args.limit, args.limit))
    for step in args.steps:
        r = ratios[step]
        if r:
            print("%-6g %5d  %12.3f  %7.3f  %10d  %16d"
                  % (step, len(r), float(numpy.median(r)), max(r), losses[step][0],
                     losses[step][1]))
    # The error's growth between consecutive steps, log(e2 / e1) / log(h2 / h1): a method of
    # convergence order p gives p wherever its error is C h^p.
    print()
    print("steps        first order: median [min, max]   second order: median [min, max]")
    steps = sorted(args.steps)
    for a, b in zip(steps, steps[1:]):
        rates = [[], []]
        for case in errors.values():
            if a in case and b in case:
                for k in (0, 1):
                    rates[k].append(math.log(case[b][k] / case[a][k]) / math.log(b / a))
        if rates[0]:
            print("%-5g-%-5g  %6.2f [%5.2f, %5.2f]             %6.2f [%5.2f, %5.2f]"
                  % (a, b, numpy.median(rates[0]), min(rates[0]), max(rates[0]),
                     numpy.median(rates[1]), min(rates[1]), max(rates[1])))


if __name__ == "__main__":
    main()
