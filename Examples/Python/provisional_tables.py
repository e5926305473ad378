"""How good a provisional table is: the last measured sizes, built for an edited transfer
function, against the sizes measured for the edit.

With RefineInBackground, a vtkPreIntegrationVolumeMapper answers a transfer-function edit at
once, then builds the last measured sizes for the edit (the provisional table, see
vtkPreIntegrationTableRefiner) before it measures the sizes again. This script says how often
that provisional table is as accurate as the measured one, on seeded random cases generated
here:
- volumes of 64^3 points (float): Marschner-Lobb, Gaussian blobs, or a sum of random waves;
- transfer functions of one to three random features (spikes, steps, ramps; 0.5% to 10% of
  the range wide, random heights and unit distance);
- two edits of each: a drag step (one opacity node's height times 0.7 to 1.3, or its position
  moved by up to 1% of the range) and a new spike (1% to 5% of the range wide);
- both orders, at a step of 1 voxel.
The sizer measures the sizes before and after each edit (the second time for a table that
holds the first sizes, as the mapper's does); an independent judge (another seed, 4096 rays)
measures both tables on the edited transfer function, and the script prints the provisional
table's error over the measured one's.

    ./hovr python Examples/Python/provisional_tables.py [--cases N]
"""

import argparse

import numpy
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData

import hovr
from hovr import randomcases

parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("--cases", type=int, default=12, help="random cases")
parser.add_argument("--points", type=int, default=64)
args = parser.parse_args()
N = args.points


def volume(rng):
    kind = rng.choice(["marschner-lobb", "blobs", "waves"])
    g = numpy.linspace(0.0, 1.0, N)
    z, y, x = numpy.meshgrid(g, g, g, indexing="ij")
    if kind == "marschner-lobb":
        source = hovr.vtkMarschnerLobbSource()
        source.SetDimensions(N, N, N)
        source.Update()
        values = vtk_to_numpy(source.GetOutput().GetPointData().GetScalars()).reshape(N, N, N)
    elif kind == "blobs":
        values = numpy.zeros_like(x)
        for _ in range(6):
            c = rng.uniform(0.2, 0.8, 3)
            r = rng.uniform(0.05, 0.2)
            values += rng.uniform(0.3, 1.0) * numpy.exp(
                -((x - c[0]) ** 2 + (y - c[1]) ** 2 + (z - c[2]) ** 2) / (2 * r * r))
    else:
        values = numpy.zeros_like(x)
        for _ in range(4):
            k = rng.normal(size=3) * rng.uniform(3, 12)
            values += numpy.sin(k[0] * x + k[1] * y + k[2] * z + rng.uniform(0, 6.3))
    values = (values - values.min()) / (values.max() - values.min())
    image = vtkImageData()
    image.SetDimensions(N, N, N)
    array = numpy_to_vtk(numpy.ascontiguousarray(values.astype(numpy.float32).ravel()), deep=True)
    array.SetName("scalars")
    image.GetPointData().SetScalars(array)
    return kind, image


def edit(rng, prop, kind, low, high):
    opacity = prop.GetScalarOpacity()
    span = high - low
    if kind == "drag":
        k = int(rng.integers(1, opacity.GetSize() - 1)) if opacity.GetSize() > 2 else 0
        node = [0.0] * 4
        opacity.GetNodeValue(k, node)
        if rng.uniform() < 0.5:
            node[1] = float(min(1.0, node[1] * rng.uniform(0.7, 1.3)))
        else:
            before, after = [0.0] * 4, [0.0] * 4
            opacity.GetNodeValue(max(k - 1, 0), before)
            opacity.GetNodeValue(min(k + 1, opacity.GetSize() - 1), after)
            moved = node[0] + span * rng.uniform(-0.01, 0.01)
            node[0] = float(min(max(moved, before[0] + 1e-6 * span), after[0] - 1e-6 * span))
        opacity.SetNodeValue(k, node)
    else:
        c = low + span * rng.uniform(0.1, 0.9)
        w = span * rng.uniform(0.01, 0.05)
        opacity.AddPoint(c - w, 0.0)
        opacity.AddPoint(c, float(rng.uniform(0.1, 1.0)))
        opacity.AddPoint(c + w, 0.0)


def measure(image, prop, order, previous=None):
    """The sizer's sizes for the property (sizes, chord and deviation ranges, prefilter), for a
    table that holds `previous` (as the mapper's table holds its last measured sizes)."""
    scalars = image.GetPointData().GetScalars()
    table = hovr.vtkSecondOrderPreIntegrationTable()
    table.SetVolumeProperty(prop)
    table.SetScalarRange(*scalars.GetRange())
    table.SetSegmentLength(order * 1.0)
    if previous:
        for setter, value in zip(("TableSize", "ChordSize", "DeviationSize", "ChordRange",
                                  "DeviationRange", "Prefilter"), previous):
            getattr(table, "Set" + setter)(value)
    sizer = hovr.vtkPreIntegrationTableSizer()
    sizer.SetMeasurePrefilter(order == 1)
    sizer.Choose(image, scalars, table, order, 1.0)
    return (table.GetTableSize(), table.GetChordSize(), table.GetDeviationSize(),
            table.GetChordRange(), table.GetDeviationRange(), table.GetPrefilter())


def judge(image, prop, order, sizes):
    scalars = image.GetPointData().GetScalars()
    table = hovr.vtkSecondOrderPreIntegrationTable()
    table.SetVolumeProperty(prop)
    table.SetScalarRange(*scalars.GetRange())
    table.SetSegmentLength(order * 1.0)
    table.SetPrefilter(sizes[5])
    sizer = hovr.vtkPreIntegrationTableSizer()
    sizer.SetSeed(101)
    sizer.SetNumberOfRays(4096)
    sizer.Prepare(image, scalars, table, order, 1.0)
    return sizer.Measure(*sizes[:5])


rows = []
for case in range(args.cases):
    rng = numpy.random.default_rng(3000 + case)
    kind, image = volume(rng)
    low, high = image.GetPointData().GetScalars().GetRange()
    for order in (1, 2):
        prop, _ = randomcases.transfer_function(numpy.random.default_rng(4000 + case), low,
                                                 high)
        last = measure(image, prop, order)
        for change in ("drag", "spike"):
            edit(rng, prop, change, low, high)
            measured = measure(image, prop, order, last)
            ratio = judge(image, prop, order, last) / judge(image, prop, order, measured)
            rows.append((order, change, last[:3] == measured[:3], ratio))
            print("case %2d %-14s order %d %-5s provisional %-16s measured %-16s error ratio %.4f"
                  % (case, kind, order, change, "x".join(map(str, last[:3])),
                     "x".join(map(str, measured[:3])), ratio), flush=True)
            last = measured

print()
for order in (1, 2):
    for change in ("drag", "spike"):
        ratios = numpy.array([r[3] for r in rows if r[0] == order and r[1] == change])
        same = sum(1 for r in rows if r[0] == order and r[1] == change and r[2])
        print("order %d, %-5s: %d edits, sizes unchanged in %d; provisional over measured error: "
              "median %.4f, within 2%% in %d, worst %.3f"
              % (order, change, len(ratios), same, numpy.median(ratios),
                 int((ratios <= 1.02).sum()), ratios.max()))
