"""How accurate can a pre-integration table get on your data? A sweep of table sizes.

On the CPU only: vtkPreIntegrationRayCaster composites the image as the GPU mapper does (to
float rounding) with a table of given sizes, and vtkVolumeReferenceIntegrator gives the exact
image. For one order and step the script prints the error of the table the sizer chooses
(vtkPreIntegrationTableSizer, what the mapper uses by default), of the exact segment model (no
table: what the order itself can reach), and of a sweep of centre sizes and chord spacings,
with and without the prefilter, over the chord and deviation ranges the sizer measured.

    ./hovr python Examples/Python/table_sweep.py [--input VOLUME [--dims X Y Z --type T]]
        [--tf TF.json] [--opacity-unit-distance U] [--order 2] [--step 2] [--size 96]

Without --input: Marschner-Lobb 41 with its spike preset (unit distance 0.05).
"""

import argparse
import os

import hovr
from hovr import io as hio

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--input")
parser.add_argument("--dims", type=int, nargs=3)
parser.add_argument("--type")
parser.add_argument("--tf")
parser.add_argument("--opacity-unit-distance", type=float)
parser.add_argument("--order", type=int, choices=(1, 2), default=2)
parser.add_argument("--step", type=float, default=2.0, help="in units of the smallest spacing")
parser.add_argument("--size", type=int, default=96, help="image width and height")
parser.add_argument("--centres", type=int, nargs="+", default=[33, 65, 129, 257],
                    help="centre-axis sizes of the sweep")
args = parser.parse_args()

if args.input:
    image = hio.read_volume(args.input, args.dims, args.type)
    unit = args.opacity_unit_distance or 1.0
else:
    source = hovr.vtkMarschnerLobbSource()
    source.SetDimensions(41, 41, 41)
    source.Update()
    image = source.GetOutput()
    unit = args.opacity_unit_distance or 0.05
tf = args.tf or os.path.join(ROOT, "presets", "transfer-functions", "marschner-lobb-spikes.json")
color, opacity, _ = hio.read_transfer_function(tf)
prop = hio.make_volume_property(color, opacity, unit)
camera = hio.default_camera(image.GetBounds())
scalars = image.GetPointData().GetScalars()
low, high = scalars.GetRange()
step = args.step * min(abs(s) for s in image.GetSpacing())

reference = hovr.vtkVolumeReferenceIntegrator()
reference.SetInputData(image)
reference.SetVolumeProperty(prop)
reference.SetCamera(camera)
reference.SetImageSize(args.size, args.size)
reference.Update()


def error(sizes, chord_range, deviation_range, prefilter=False, exact=False):
    """RMSE against the reference of the image composited with a table of these sizes."""
    table = hovr.vtkSecondOrderPreIntegrationTable()
    table.SetTableSize(sizes[0])
    table.SetChordSize(sizes[1])
    table.SetDeviationSize(sizes[2])
    table.SetChordRange(chord_range)
    table.SetDeviationRange(deviation_range)
    table.SetPrefilter(prefilter)
    caster = hovr.vtkPreIntegrationRayCaster()
    caster.SetTable(table)
    caster.SetIntegration(args.order)
    caster.SetExactSegments(exact)
    caster.SetInputData(image)
    caster.SetVolumeProperty(prop)
    caster.SetCamera(camera)
    caster.SetImageSize(args.size, args.size)
    caster.SetSampleDistance(step)
    caster.Update()
    metrics = hovr.vtkRGBAErrorMetrics()
    metrics.SetInputData(caster.GetOutput())
    metrics.SetReferenceData(reference.GetOutput())
    metrics.Update()
    return metrics.GetRMSE()


table = hovr.vtkSecondOrderPreIntegrationTable()
table.SetVolumeProperty(prop)
table.SetScalarRange(low, high)
table.SetSegmentLength(args.order * step)
sizer = hovr.vtkPreIntegrationTableSizer()
sizer.SetMeasurePrefilter(args.order == 1)  # as the mapper's automatic prefilter
if not sizer.Choose(image, scalars, table, args.order, step):
    raise SystemExit("the sizer could not choose a table")
chosen = (table.GetTableSize(), table.GetChordSize(), table.GetDeviationSize())
ranges = (table.GetChordRange(), table.GetDeviationRange())
print("order %d, step %g voxel, %dx%d image" % (args.order, args.step, args.size, args.size))
print("chosen by the sizer: %s%s, RMSE %.5f (measured in %.2f s)" % (
    "x".join(map(str, chosen)), " prefiltered" if table.GetPrefilter() else "",
    error(chosen, *ranges, prefilter=table.GetPrefilter()), sizer.GetLastChooseTime()))
print("exact segment model (no table): RMSE %.5f" % error((3, 3, 3 if args.order == 2 else 1), *ranges,
                                                               exact=True))
spacing_of = (high - low) if high > low else 1.0
for centre in args.centres:
    spacing = spacing_of / (centre - 1)
    deviation = (2 * int(ranges[1] / spacing + 1) + 1) if args.order == 2 else 1
    for factor in (1, 2, 4):
        chord = max(3, 2 * int(ranges[0] / (factor * spacing) + 1) + 1)
        sizes = (centre, chord, max(deviation, 3) if args.order == 2 else 1)
        if sizes[0] * sizes[1] * sizes[2] * 8 > sizer.GetMaximumMemory():
            continue
        print("%s: RMSE %.5f, prefiltered %.5f" % (
            "x".join(map(str, sizes)), error(sizes, *ranges), error(sizes, *ranges, True)))
