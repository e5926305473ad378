# hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
"""pvbatch test of the plugin's Adaptive Sampling Oracle filter.

Loads the plugin, applies the filter to ParaView's Wavelet source and checks that
  - the proxy is there with its documented defaults and mode entries;
  - the output holds the input's scalars and a float array of distances, named as
    OutputArrayName says, from 0 (features exist under the opacity points set) up to at most
    the cap of 8 smallest spacings;
  - Opacity Gradient finds features too, with other distances;
  - the opacity points reach the filter (a transfer function that is flat over the data's range
    leaves no feature: the cap everywhere), Min gives 0 everywhere, Max the cap everywhere, and
    Maximum Distance applies when Automatic Maximum Distance is off.

    pvbatch TestAdaptiveSamplingOracleFilter.py --plugin <hovr.so>
"""
import argparse

import numpy
from paraview import servermanager
from paraview.simple import LoadPlugin, Wavelet
from vtkmodules.util.numpy_support import vtk_to_numpy

from TestHovrPlugin import Checker, run


def fetch(proxy, name="OracleDistance"):
    """The distances (a flat numpy array, None without the array), the array's type and the
    fetched image."""
    proxy.UpdatePipeline()
    image = servermanager.Fetch(proxy)
    array = image.GetPointData().GetArray(name)
    if array is None:
        return None, None, image
    return vtk_to_numpy(array).astype(float), array.GetDataTypeAsString(), image


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plugin", required=True, help="path of the hovr plugin (hovr.so)")
    args = parser.parse_args()
    checker = Checker()

    LoadPlugin(args.plugin, remote=False, ns=globals())
    if not checker.check("AdaptiveSamplingOracle" in globals(),
                         "the plugin defines the AdaptiveSamplingOracle filter"):
        return checker.failures
    # RTData of the Wavelet: 21^3 points, spacing 1, values about 37 to 277.
    source = Wavelet()
    source.UpdatePipeline()
    f = globals()["AdaptiveSamplingOracle"](Input=source)

    checker.check(f.Mode == "Opacity Range" and f.Epsilon == 0.002 and
                  f.AutomaticMaximumDistance == 1 and f.MaximumDistance == 1.0 and
                  f.OutputArrayName == "OracleDistance" and
                  list(f.OpacityPoints) == [0.0, 0.0, 255.0, 1.0],
                  "defaults: Opacity Range, Epsilon 0.002, automatic cap, MaximumDistance 1, "
                  "OracleDistance, a ramp 0..255 (%s, %s, %s, %s, %s, %s)" % (
                      f.Mode, f.Epsilon, f.AutomaticMaximumDistance, f.MaximumDistance,
                      f.OutputArrayName, list(f.OpacityPoints)))
    checker.check(list(f.GetProperty("Mode").Available) ==
                  ["Opacity Gradient", "Opacity Range", "Min", "Max"], "Mode entries")
    checker.check(list(f.Scalars)[-1] == "RTData",
                  "the source's scalars are selected: %s" % list(f.Scalars))

    # A narrow opacity peak around 200: features on a shell of the wavelet, distances grow
    # away from it up to the cap.
    cap = 8.0
    f.OpacityPoints = [0.0, 0.0, 190.0, 0.0, 200.0, 0.8, 210.0, 0.0, 300.0, 0.0]
    distances, kind, image = fetch(f)
    if not checker.check(distances is not None, "the output has an OracleDistance array"):
        return checker.failures
    checker.check(kind == "float" and image.GetPointData().GetArray("RTData") is not None,
                  "a float array, the input scalars passed through")
    checker.check(distances.min() == 0.0 and 1.0 < distances.max() <= numpy.float32(cap),
                  "distances from 0 up to at most the cap of 8 spacings (range %g to %g)"
                  % (distances.min(), distances.max()))
    checker.check(0.05 < numpy.mean(distances == 0.0) < 0.95,
                  "features on part of the volume (%.2f)" % numpy.mean(distances == 0.0))
    checker.check(numpy.any((distances > 1.0) & (distances < cap)),
                  "distances between the features and the cap")

    f.Mode = "Opacity Gradient"
    gradient, _, _ = fetch(f)
    checker.check(gradient is not None and gradient.min() == 0.0 and
                  numpy.any(gradient != distances),
                  "Opacity Gradient: features too, other distances than Opacity Range")

    f.Mode = "Opacity Range"
    f.OpacityPoints = [0.0, 0.3, 300.0, 0.3]
    flat, _, _ = fetch(f)
    checker.check(flat is not None and numpy.all(flat == numpy.float32(cap)),
                  "a flat opacity: no feature, the cap everywhere")

    f.OpacityPoints = [0.0, 0.0, 190.0, 0.0, 200.0, 0.8, 210.0, 0.0, 300.0, 0.0]
    f.Mode = "Min"
    minimum, _, _ = fetch(f)
    checker.check(minimum is not None and numpy.all(minimum == 0.0),
                  "Min: all zeros (range %s)" % (None if minimum is None else
                                                  str((minimum.min(), minimum.max()))))
    f.Mode = "Max"
    maximum, _, _ = fetch(f)
    checker.check(maximum is not None and numpy.all(maximum == numpy.float32(cap)),
                  "Max: the cap everywhere")
    f.AutomaticMaximumDistance = 0
    f.MaximumDistance = 3.25
    f.OutputArrayName = "Oracle2"
    maximum, _, _ = fetch(f, "Oracle2")
    checker.check(maximum is not None and numpy.all(maximum == 3.25),
                  "Max with Maximum Distance 3.25 under OutputArrayName Oracle2")
    return checker.failures


if __name__ == "__main__":
    run(main)
