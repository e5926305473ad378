"""Seeded random transfer functions, for checking automatic choices on cases no one tuned.

The sizer's tests and the examples that study the table sizes draw their transfer functions
here: one to a few opacity features (spikes, steps, plateaus, ramps) of random width, centre and
height on a zero background, random colours and a random unit distance. The draws are made in
a fixed order from the generator given, so a seed gives the same function every time.
"""

import math

import numpy
from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
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
