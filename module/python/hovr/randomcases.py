"""Seeded random transfer functions and volumes, for checking automatic choices on cases no one
tuned.

The sizer's tests and the examples that study the table sizes draw their volumes and transfer
functions here. A volume is a field of Gaussian blobs, of plane waves or Marschner-Lobb, 26-36
points a side, stored as uint8, uint16 or float. A transfer function has one to a few opacity
features (spikes, steps, plateaus, ramps) of random width, centre and height on a zero
background, random colours and a random unit distance. The draws are made in a fixed order from
the generator given, so a seed gives the same volume and function every time.
"""

import math

import numpy
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPiecewiseFunction
from vtkmodules.vtkRenderingCore import vtkColorTransferFunction, vtkVolumeProperty


def transfer_function(rng, low, high, features=(1, 4), kinds=("spike", "step", "ramp"),
                      widths=(0.005, 0.1), centres=(0.1, 0.9), log_heights=(-1.5, 0.0),
                      colour_points=3, log_units=(-0.5, 0.5)):
    """A vtkVolumeProperty over [low, high] and a description of its features.

    ``features``: the count is drawn from [first, last) (numpy's ``integers``); ``kinds`` from
    "spike", "step", "plateau" and "ramp"; ``widths`` the range of a feature's width as a
    fraction of the span (drawn log-uniformly); ``centres`` its centre's range as a fraction;
    ``log_heights`` the range of log10 of its opacity; ``colour_points`` the colour nodes, a
    count or a [first, last) range to draw from; ``log_units`` the range of log10 of the scalar
    opacity unit distance."""
    span = high - low
    nodes = {low: 0.0, high: 0.0}
    names = []
    for _ in range(int(rng.integers(*features))):
        kind = rng.choice(list(kinds))
        w = span * 10 ** rng.uniform(math.log10(widths[0]), math.log10(widths[1]))
        c = low + span * rng.uniform(*centres)
        h = float(10 ** rng.uniform(*log_heights))
        if kind == "spike":
            new = {c - w / 2: 0.0, c: h, c + w / 2: 0.0}
        elif kind == "step":
            new = {c: 0.0, c + 0.05 * w: h, high: h}
        elif kind == "plateau":
            new = {c - 0.6 * w: 0.0, c - w / 2: h, c + w / 2: h, c + 0.6 * w: 0.0}
        else:
            new = {c: 0.0, min(c + 4 * w, high): h}
        names.append("%s %.2g wide" % (kind, w / span))
        for x, a in new.items():
            x = min(max(x, low), high)
            nodes[x] = max(nodes.get(x, 0.0), a)
    opacity = vtkPiecewiseFunction()
    for x in sorted(nodes):
        opacity.AddPoint(x, nodes[x])
    color = vtkColorTransferFunction()
    count = colour_points if isinstance(colour_points, int) else int(rng.integers(*colour_points))
    for x in numpy.linspace(low, high, count):
        color.AddRGBPoint(float(x), *rng.uniform(0, 1, 3))
    prop = vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(float(10 ** rng.uniform(*log_units)))
    return prop, ", ".join(names)


def field(kind, n, rng):
    """An n^3 field in [0, 1] of the kind "blobs", "waves" or "marschner-lobb", indexed [z, y, x]."""
    g = numpy.linspace(0.0, 1.0, n)
    z, y, x = numpy.meshgrid(g, g, g, indexing="ij")
    if kind == "blobs":
        v = numpy.zeros_like(x)
        for _ in range(rng.integers(3, 8)):
            c = rng.uniform(0.15, 0.85, 3)
            r = rng.uniform(0.06, 0.25)
            v += rng.uniform(0.3, 1.0) * numpy.exp(
                -((x - c[0]) ** 2 + (y - c[1]) ** 2 + (z - c[2]) ** 2) / (2 * r * r))
    elif kind == "waves":
        v = numpy.zeros_like(x)
        for _ in range(4):
            k = rng.normal(size=3) * rng.uniform(3, 12)
            v += numpy.sin(k[0] * x + k[1] * y + k[2] * z + rng.uniform(0, 6.3)) \
                * rng.uniform(0.3, 1.0)
    else:
        import hovr  # the package that holds this module: imported once it is loaded
        source = hovr.vtkMarschnerLobbSource()
        source.SetDimensions(n, n, n)
        source.Update()
        v = vtk_to_numpy(source.GetOutput().GetPointData().GetScalars()).reshape(n, n, n)
        v = v.astype(numpy.float64)
    return (v - v.min()) / (v.max() - v.min())


def volume(rng):
    """A vtkImageData of a random field (see the module's description), its point scalars named
    "scalars", and a description."""
    kind = rng.choice(["blobs", "waves", "marschner-lobb"])
    n = int(rng.integers(26, 37))
    v = field(kind, n, rng)
    stored = rng.choice(["uint8", "uint16", "float"])
    if stored == "uint8":
        values = numpy.round(v * 255).astype(numpy.uint8)
    elif stored == "uint16":
        values = numpy.round(v * float(rng.choice([4095, 65535]))).astype(numpy.uint16)
    else:
        low = float(rng.uniform(-100, 100))
        values = (low + v * 10 ** rng.uniform(-2, 4)).astype(numpy.float32)
    image = vtkImageData()
    image.SetDimensions(n, n, n)
    array = numpy_to_vtk(numpy.ascontiguousarray(values.ravel()), deep=True)
    array.SetName("scalars")
    image.GetPointData().SetScalars(array)
    return image, "%s %d^3 %s" % (kind, n, stored)
