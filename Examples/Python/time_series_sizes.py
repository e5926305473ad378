"""When a new time step needs its table sizes measured again: the error of the sizes measured
on the first step, kept for later steps, over the error of sizes measured on each step.

Seeded time series generated here (each 96^3 points, 9 steps, float):
- "alpha": the Marschner-Lobb field with its alpha parameter moving by 0.02 a step (its
  shape changes, its range barely);
- "drift": the Marschner-Lobb field scaled by 1 - 0.02 t (the values shrink inside the first
  step's range);
- "grow": scaled by 1 + 0.02 t (the values leave the first step's range);
- "blobs": Gaussian blobs moving by 2% of the box a step, scaled to [0, 1] (the values'
  distribution barely moves, the field does);
- "noise": the field plus noise growing by 0.005 of the range a step, clipped to the field's
  range (chords grow).
Kept sizes keep their table's scalar range (the same entries relative to the transfer
function), extended by whole centre spacings to the new values, by at most a quarter of it;
a step whose values leave that is measured again.
For both orders, at steps of 1 and 2 voxels, with seeded random transfer functions (spikes,
steps and ramps, as TestPreIntegrationTableSizer's random cases), the sizer measures each step;
an independent judge (another seed, 4096 rays) measures the kept sizes' error on that step,
over the measured sizes' error, which is printed with the distribution shift and the chord change between the
signatures of the first step and that step (vtkPreIntegrationTableSizing::ComputeSignature).

    ./hovr python Examples/Python/time_series_sizes.py [--cases N]
"""

import argparse
import math
import os
import sys

import numpy
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkDoubleArray
from vtkmodules.vtkCommonDataModel import vtkImageData

import hovr
from hovr import randomcases


parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("--cases", type=int, default=6, help="transfer functions per series")
parser.add_argument("--points", type=int, default=96)
parser.add_argument("--steps", type=int, default=9)
args = parser.parse_args()
N = args.points


def image_of(values):
    image = vtkImageData()
    image.SetDimensions(N, N, N)
    array = numpy_to_vtk(numpy.ascontiguousarray(values.astype(numpy.float32).ravel()), deep=True)
    array.SetName("scalars")
    image.GetPointData().SetScalars(array)
    return image


def marschner_lobb(alpha):
    source = hovr.vtkMarschnerLobbSource()
    source.SetDimensions(N, N, N)
    source.SetAlpha(alpha)
    source.Update()
    return vtk_to_numpy(source.GetOutput().GetPointData().GetScalars()).reshape(N, N, N)


def blobs(t, rng_seed=7):
    rng = numpy.random.default_rng(rng_seed)
    g = numpy.linspace(0.0, 1.0, N)
    z, y, x = numpy.meshgrid(g, g, g, indexing="ij")
    v = numpy.zeros_like(x)
    for _ in range(5):
        c = rng.uniform(0.25, 0.75, 3) + 0.02 * t * rng.normal(size=3)
        r = rng.uniform(0.08, 0.2)
        v += rng.uniform(0.4, 1.0) * numpy.exp(
            -((x - c[0]) ** 2 + (y - c[1]) ** 2 + (z - c[2]) ** 2) / (2 * r * r))
    return v


def series(kind, steps):
    base = marschner_lobb(0.25)
    noise = numpy.random.default_rng(3).normal(size=base.shape)
    out = []
    for t in range(steps):
        if kind == "alpha":
            values = marschner_lobb(0.25 + 0.02 * t)
        elif kind == "drift":
            values = base * (1.0 - 0.02 * t)
        elif kind == "grow":
            values = base * (1.0 + 0.02 * t)
        elif kind == "blobs":
            values = blobs(t)
            values = values / values.max()
        else:
            values = numpy.clip(base + 0.005 * t * noise, base.min(), base.max())
        out.append(image_of(values))
    return out


rows = []
for kind in ("alpha", "drift", "grow", "blobs", "noise"):
    images = series(kind, args.steps)
    first = images[0].GetPointData().GetScalars()
    low, high = first.GetRange()
    reference_signature = vtkDoubleArray()
    for case in range(args.cases):
        rng = numpy.random.default_rng(2000 + case)
        prop, tf_name = randomcases.transfer_function(rng, low, high)
        hovr.vtkPreIntegrationTableSizing.ComputeSignature(first, images[0].GetDimensions(),
                                                          (low, high), reference_signature)
        for order in (1, 2):
            for step in (1.0, 2.0):
                kept = None
                for t, image in enumerate(images):
                    scalars = image.GetPointData().GetScalars()
                    lo, hi = scalars.GetRange()
                    table = hovr.vtkSecondOrderPreIntegrationTable()
                    table.SetVolumeProperty(prop)
                    table.SetScalarRange(lo, hi)
                    table.SetSegmentLength(order * step)
                    sizer = hovr.vtkPreIntegrationTableSizer()
                    sizer.SetMeasurePrefilter(order == 1)
                    sizer.Choose(image, scalars, table, order, step)
                    measured = (table.GetTableSize(), table.GetChordSize(),
                                table.GetDeviationSize(), table.GetChordRange(),
                                table.GetDeviationRange(), table.GetPrefilter(), (lo, hi))
                    if kept is None:
                        kept = measured
                        continue
                    # Both tables are judged on rays of their own (another seed, twice the
                    # rays): measured on the sizer's rays, the sizes chosen on them would be
                    # favoured.
                    judge = hovr.vtkPreIntegrationTableSizer()
                    judge.SetSeed(100 + t)
                    judge.SetNumberOfRays(4096)
                    judge.Prepare(image, scalars, table, order, step)
                    error = judge.Measure(*measured[:5])
                    # The kept table keeps its range too (the same entries relative to the
                    # transfer function), extended by whole centre spacings to the new step's
                    # values, by at most a quarter of it (as vtkPreIntegrationTableSizing).
                    spacing = (kept[6][1] - kept[6][0]) / (kept[0] - 1)
                    below = max(0, math.ceil((kept[6][0] - lo) / spacing - 1e-9))
                    above = max(0, math.ceil((hi - kept[6][1]) / spacing - 1e-9))
                    if below + above > 0.25 * (kept[0] - 1):
                        rows.append((kind, case, order, step, t, -1.0, -1.0, float("nan")))
                        print("%-6s case %d order %d step %g t %d: range [%g, %g] beyond the "
                              "kept [%g, %g]: measured again" % (kind, case, order, step, t, lo,
                                                                 hi, *kept[6]))
                        continue
                    extended = (kept[6][0] - below * spacing, kept[6][1] + above * spacing)
                    table.SetPrefilter(kept[5])
                    table.SetScalarRange(*extended)
                    judge.Prepare(image, scalars, table, order, step)
                    kept_error = judge.Measure(kept[0] + below + above, *kept[1:5])
                    signature = vtkDoubleArray()
                    hovr.vtkPreIntegrationTableSizing.ComputeSignature(
                        scalars, image.GetDimensions(), extended, signature)
                    shift = hovr.vtkPreIntegrationTableSizing.DistributionShift(
                        reference_signature, signature)
                    chord = hovr.vtkPreIntegrationTableSizing.ChordChange(
                        reference_signature, signature)
                    ratio = kept_error / error if error > 0 else 1.0
                    rows.append((kind, case, order, step, t, shift, chord, ratio))
                    print("%-6s case %d order %d step %g t %d: shift %.4f chord %.3f kept/measured "
                          "%.3f" % (kind, case, order, step, t, shift, chord, ratio))
                    sys.stdout.flush()

outside = sum(1 for r in rows if r[5] < 0)
print("\n%d of %d later steps had values beyond a quarter more than the first step's range "
      "(measured again)"
      % (outside, len(rows)))
rows = numpy.array([r[5:] for r in rows if r[5] >= 0])
print("kept sizes and range over measured sizes, by distribution shift and chord change:")
for shift_limit in (0.005, 0.01, 0.02, 0.05, 1e9):
    for chord_limit in (0.05, 0.1, 0.2, 1e9):
        selected = rows[(rows[:, 0] <= shift_limit) & (rows[:, 1] <= chord_limit)]
        if len(selected):
            print("shift <= %-6g chord <= %-5g: %4d cases, ratio median %.3f, 95th %.3f, worst %.3f"
                  % (shift_limit, chord_limit, len(selected), numpy.median(selected[:, 2]),
                     numpy.percentile(selected[:, 2], 95), selected[:, 2].max()))
