# hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
"""pvbatch test of the plugin's Gradient Exaggeration filter.

Loads the plugin, applies the filter to the Marschner-Lobb source and checks that
  - the proxy is there with its documented defaults and enumeration entries;
  - the output holds the input's scalars and a 3-component array of unit (or zero) normals,
    named as OutputArrayName says;
  - Epsilon changes the normals (eps = 0 differs from eps = 1, and eps = 0 gives the
    normalised central differences of the fetched scalars in the interior), the Sobel
    operator gives other unit normals, and a NeighborhoodSize of 1 cancels the exaggeration.

    pvbatch TestGradientExaggerationFilter.py --plugin <hovr.so>
"""
import argparse

import numpy
from paraview import servermanager
from paraview.simple import LoadPlugin
from vtkmodules.util.numpy_support import vtk_to_numpy

from TestHovrPlugin import Checker, run

DIMS = (25, 23, 21)


def fetch_normals(proxy, name="ExaggeratedNormals"):
    """The (z, y, x, 3) normals and (z, y, x) scalars of the filter's output."""
    proxy.UpdatePipeline()
    image = servermanager.Fetch(proxy)
    nx, ny, nz = image.GetDimensions()
    array = image.GetPointData().GetArray(name)
    scalars = image.GetPointData().GetArray("MarschnerLobb")
    normals = None if array is None else \
        vtk_to_numpy(array).reshape(nz, ny, nx, array.GetNumberOfComponents()).astype(float)
    values = None if scalars is None else vtk_to_numpy(scalars).reshape(nz, ny, nx).astype(float)
    return normals, values, image.GetSpacing()


def unit_or_zero(normals):
    lengths = numpy.linalg.norm(normals, axis=-1)
    return bool(numpy.all((lengths == 0.0) | (numpy.abs(lengths - 1.0) < 1e-6)))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plugin", required=True, help="path of the hovr plugin (hovr.so)")
    args = parser.parse_args()
    checker = Checker()

    # ns= adds the plugin's creation functions (MarschnerLobb, GradientExaggeration) here.
    LoadPlugin(args.plugin, remote=False, ns=globals())
    if not checker.check("GradientExaggeration" in globals(),
                         "the plugin defines the GradientExaggeration filter"):
        return checker.failures
    source = globals()["MarschnerLobb"]()
    source.Dimensions = list(DIMS)
    # The input array list comes from the source's data information, as after Apply in the GUI.
    source.UpdatePipeline()
    f = globals()["GradientExaggeration"](Input=source)

    checker.check(f.Epsilon == 1.0 and f.NeighborhoodSize == 5 and
                  f.GradientMethod == "Central Difference" and
                  f.OutputArrayName == "ExaggeratedNormals",
                  "defaults: Epsilon 1, NeighborhoodSize 5, Central Difference, "
                  "ExaggeratedNormals (%s, %s, %s, %s)" % (
                      f.Epsilon, f.NeighborhoodSize, f.GradientMethod, f.OutputArrayName))
    checker.check(list(f.GetProperty("GradientMethod").Available) ==
                  ["Central Difference", "Sobel"], "GradientMethod entries")
    checker.check(list(f.Scalars)[-1] == "MarschnerLobb",
                  "the source's scalars are selected: %s" % list(f.Scalars))

    exaggerated, values, spacing = fetch_normals(f)
    if not checker.check(exaggerated is not None and exaggerated.shape[-1] == 3,
                         "the output has a 3-component ExaggeratedNormals array"):
        return checker.failures
    checker.check(values is not None, "the input scalars pass through")
    checker.check(unit_or_zero(exaggerated), "eps = 1: unit (or zero) normals")
    checker.check(numpy.mean(numpy.linalg.norm(exaggerated, axis=-1) > 0.5) > 0.99,
                  "almost every point has a normal")

    f.Epsilon = 0.0
    plain, _, _ = fetch_normals(f)
    checker.check(unit_or_zero(plain), "eps = 0: unit (or zero) normals")
    change = numpy.linalg.norm(plain - exaggerated, axis=-1)
    checker.check(change.max() > 0.1, "eps = 0 differs from eps = 1 (largest change %.3g)"
                  % change.max())
    # eps = 0 is the normalised central difference of the scalars (interior points: the
    # faces take one-sided differences).
    g = numpy.stack([
        (values[1:-1, 1:-1, 2:] - values[1:-1, 1:-1, :-2]) / (2 * spacing[0]),
        (values[1:-1, 2:, 1:-1] - values[1:-1, :-2, 1:-1]) / (2 * spacing[1]),
        (values[2:, 1:-1, 1:-1] - values[:-2, 1:-1, 1:-1]) / (2 * spacing[2])], axis=-1)
    g /= numpy.linalg.norm(g, axis=-1, keepdims=True)
    # Float scalars differenced in double here and in the filter; float normals.
    worst = numpy.linalg.norm(plain[1:-1, 1:-1, 1:-1] - g, axis=-1).max()
    checker.check(worst < 1e-5, "eps = 0: the normalised central differences (worst %.3g)"
                  % worst)

    f.Epsilon = 1.0
    f.NeighborhoodSize = 1
    single, _, _ = fetch_normals(f)
    worst = numpy.linalg.norm(single - plain, axis=-1).max()
    checker.check(worst < 1e-6, "NeighborhoodSize 1: N_m = N, no exaggeration (worst %.3g)"
                  % worst)

    f.NeighborhoodSize = 5
    f.GradientMethod = "Sobel"
    f.OutputArrayName = "SobelNormals"
    sobel, _, _ = fetch_normals(f, "SobelNormals")
    checker.check(sobel is not None and unit_or_zero(sobel),
                  "Sobel under OutputArrayName SobelNormals: unit (or zero) normals")
    checker.check(sobel is not None and
                  numpy.linalg.norm(sobel - exaggerated, axis=-1).max() > 0.01,
                  "Sobel differs from central differences")
    return checker.failures


if __name__ == "__main__":
    run(main)
