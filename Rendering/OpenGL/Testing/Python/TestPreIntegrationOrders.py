"""Second order against first order, with the measured table sizes (the default), on the GPU
against the reference integrator (96 x 96 images):
- on Marschner-Lobb 41 with its spike preset, on the blobs volume with 8-value spikes
  (generated here) and on neghip, fuel and bucky with their presets (skipped with a message when
  ../shared/data is absent), second order is no less accurate than first order at every step
  from 1/4 to 4 voxels, except where the exact segment models of the two orders differ by less
  than 5% (the data varies too fast between samples for the slab's middle sample to help, and
  the tables' smoothing decides: Marschner-Lobb 41 from 1 voxel up) or where first order's
  measured table beats its own exact model by more than 10% (its smoothing, not its model,
  decides); there second order must stay within 10% of first order;
- at 2 voxels the ratio of their errors is printed beside the ratio of the exact segment models
  (vtkPreIntegrationRayCaster, ExactSegments: what the quadratic model itself gains over the
  linear one, without tables), for the record: measured first-order tables, coarse along the
  chord, often beat the exact linear model (their interpolation offsets its error), which
  narrows second order's lead;
- over 20 random spike transfer functions on generated volumes (seeded), second order's error at
  2 voxels is on average at most 0.88 of first order's.
"""

import math

import numpy
from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
from vtkmodules.vtkRenderingCore import vtkColorTransferFunction, vtkVolumeProperty

import hovr
from hovr import io as hio
from hovr import methods as hm
from hovrtesting import Checker, blobs, cast_image, image_from_array, spike_scenes

c = Checker()
renderer = hm.Renderer()
STEPS = (0.25, 0.5, 1.0, 2.0, 4.0)
SIZE = (96, 96)


def error(image, reference):
    return hm.compare(image, reference)[0]["rmse"]


def exact(scene, order, step):
    """The exact segment model of an order at a step (no table)."""
    table = hovr.vtkSecondOrderPreIntegrationTable()
    table.SetTableSize(3)
    table.SetChordSize(3)
    table.SetDeviationSize(3 if order == 2 else 1)
    return cast_image(scene, table, order, step, exact=True)


scenes = spike_scenes(SIZE)
for name, scene in scenes:
    reference = renderer.render("reference", scene, 1.0).image
    runs = [(method, step) for method in ("preint1", "preint2") for step in STEPS]
    results = dict(zip(runs, renderer.render_interleaved(runs, scene)))
    for step in STEPS:
        first = error(results["preint1", step].image, reference)
        second = error(results["preint2", step].image, reference)
        print("%s, step %g: preint1 %.5f (%s), preint2 %.5f (%s), ratio %.3f" % (
            name, step, first, results["preint1", step].extra["table_size"], second,
            results["preint2", step].extra["table_size"], second / first))
        if second <= first:
            continue
        # Where the exact segment models themselves differ by less than 5%, the data varies too
        # fast between samples for the slab's middle sample to tell much, and what the tables
        # smooth away (a coarse first-order table, prefiltered or not, can beat its own exact
        # model) decides: there second order must stay within 10% of first order.
        first_exact = error(exact(scene, 1, step), reference)
        model = error(exact(scene, 2, step), reference) / first_exact
        smoothing = first / first_exact
        allowed = 1.10 if model > 0.95 or smoothing < 0.9 else 1.0
        print("%s, step %g: second order behind first order; exact segment models %.3f, first "
              "order's table over its model %.3f, allowed %.2f" % (name, step, model, smoothing,
                                                                  allowed))
        c.check(second <= allowed * first, "%s, step %g: second order %.5f against first order "
                "%.5f (allowed %.2f x: exact models %.3f)" % (name, step, second, first, allowed,
                                                             model))
    first = error(results["preint1", 2.0].image, reference)
    second = error(results["preint2", 2.0].image, reference)
    model = error(exact(scene, 2, 2.0), reference) / error(exact(scene, 1, 2.0), reference)
    print("%s, step 2: second over first order %.3f with tables, %.3f for the exact models"
          % (name, second / first, model))


# Random spike transfer functions on generated volumes.
def random_case(seed):
    rng = numpy.random.default_rng(seed)
    n = int(rng.integers(26, 37))
    kind = rng.choice(["blobs", "waves", "marschner-lobb"])
    g = numpy.linspace(0.0, 1.0, n)
    z, y, x = numpy.meshgrid(g, g, g, indexing="ij")
    if kind == "blobs":
        values = blobs(n, seed=seed) / 255.0
    elif kind == "waves":
        values = numpy.zeros_like(x)
        for _ in range(4):
            k = rng.normal(size=3) * rng.uniform(3, 12)
            values += numpy.sin(k[0] * x + k[1] * y + k[2] * z + rng.uniform(0, 6.3))
        values = (values - values.min()) / (values.max() - values.min())
    else:
        source = hovr.vtkMarschnerLobbSource()
        source.SetDimensions(n, n, n)
        source.Update()
        from vtkmodules.util.numpy_support import vtk_to_numpy
        values = vtk_to_numpy(source.GetOutput().GetPointData().GetScalars()).reshape(n, n, n)
    image = image_from_array(values.astype(numpy.float32))
    low, high = image.GetScalarRange()
    span = high - low
    nodes = {low: 0.0, high: 0.0}
    for _ in range(int(rng.integers(1, 4))):
        width = span * 10 ** rng.uniform(math.log10(0.005), math.log10(0.1))
        centre = low + span * rng.uniform(0.05, 0.95)
        height = float(10 ** rng.uniform(-1.3, 0))
        for position, alpha in ((centre - width / 2, 0.0), (centre, height),
                                (centre + width / 2, 0.0)):
            position = min(max(position, low), high)
            nodes[position] = max(nodes.get(position, 0.0), alpha)
    opacity = vtkPiecewiseFunction()
    for position in sorted(nodes):
        opacity.AddPoint(position, nodes[position])
    color = vtkColorTransferFunction()
    for position in numpy.linspace(low, high, 3):
        color.AddRGBPoint(float(position), *rng.uniform(0, 1, 3))
    prop = vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(float(10 ** rng.uniform(math.log10(0.5), math.log10(3))))
    prop.SetInterpolationTypeToLinear()
    return "%s %d^3" % (kind, n), hm.Scene(image, prop, hio.default_camera(image.GetBounds()),
                                          (64, 64))


ratios = []
for seed in range(20):
    label, scene = random_case(seed)
    reference = renderer.render("reference", scene, 1.0).image
    first, second = renderer.render_interleaved([("preint1", 2.0), ("preint2", 2.0)], scene)
    ratio = error(second.image, reference) / error(first.image, reference)
    ratios.append(ratio)
    print("random spikes %d (%s), step 2: second over first order %.3f" % (seed, label, ratio))
print("random spikes, step 2: mean ratio %.3f, median %.3f, largest %.3f" % (
    numpy.mean(ratios), numpy.median(ratios), max(ratios)))
c.check(numpy.mean(ratios) <= 0.88, "random spike transfer functions, step 2: second order's "
        "error at most 0.88 of first order's on average (%.3f)" % numpy.mean(ratios))
renderer.close()
c.finish()
