"""Seeded random opacity bands on a volume: how the adaptive-sampling pyramid's samples
(vtkAdaptiveSamplingRayCaster, the default range oracle, lmax 3, slices one pixel apart, a
parallel view) follow the fraction of the volume's points the oracle marks as features
(vtkAdaptiveSamplingOracle distance 0), the paper's sparse-volume claim tested on transfer
functions nobody chose.

Each case: an opacity tent over a random band of the data range (start anywhere in the lower
8% to 92% of the range, width 1.5% to 31%, peak 0.2 to 1), on the volume given (default the
buckyball from the shared test volumes, HOVR_DATA, default ../shared/data), or on a generated
one (blobs:N, marschner-lobb:N).

    ./hovr python Examples/Python/adaptive_random_bands.py [--input blobs:65] [--cases 12]
"""

import argparse
import os

import numpy
from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
from vtkmodules.vtkRenderingCore import vtkColorTransferFunction
from vtkmodules.util.numpy_support import vtk_to_numpy

import hovr
from hovr import io as hio
from hovr import methods as hm
from hovr.bench import load_volume

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUCKY = os.path.join(os.environ.get("HOVR_DATA", os.path.join(ROOT, "..", "shared", "data")),
                     "bucky_32x32x32_uint8.raw")


def load(name):
    if name == "bucky":
        if not os.path.isfile(BUCKY):
            raise SystemExit("bucky not found at %s (set HOVR_DATA), or pass --input blobs:65"
                             % BUCKY)
        return hio.read_volume(BUCKY, dims=(32, 32, 32), scalar_type="uint8")
    return load_volume({"input": name})


def band(rng, low, high):
    """A random opacity tent over a band of [low, high], white to blue colours."""
    span = high - low
    start = low + span * rng.uniform(0.08, 0.92)
    end = min(start + span * rng.uniform(0.015, 0.31), high)
    opacity, color = vtkPiecewiseFunction(), vtkColorTransferFunction()
    opacity.AddPoint(low, 0.0)
    opacity.AddPoint(start, 0.0)
    opacity.AddPoint(0.5 * (start + end), rng.uniform(0.2, 1.0))
    opacity.AddPoint(end, 0.0)
    opacity.AddPoint(high, 0.0)
    color.AddRGBPoint(low, 0.2, 0.3, 0.9)
    color.AddRGBPoint(high, 1.0, 0.9, 0.8)
    return color, opacity, (start, end)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--input", default="bucky")
    parser.add_argument("--cases", type=int, default=12)
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--seed", type=int, default=7)
    args = parser.parse_args()
    image = load(args.input)
    low, high = image.GetPointData().GetScalars().GetFiniteRange()
    rng = numpy.random.default_rng(args.seed)
    renderer = hm.Renderer()
    camera = hio.default_camera(image.GetBounds(), parallel=True)
    rows = []
    for case in range(args.cases):
        color, opacity, (start, end) = band(rng, low, high)
        oracle = hovr.vtkAdaptiveSamplingOracle()
        oracle.SetInputData(image)
        oracle.SetScalarOpacity(opacity)
        oracle.Update()
        distance = vtk_to_numpy(oracle.GetOutput().GetPointData().GetArray("OracleDistance"))
        features = float(numpy.mean(distance == 0))
        prop = hio.make_volume_property(color, opacity, 1.0)
        scene = hm.Scene(image, prop, camera, (args.size, args.size))
        stats = renderer.render("adaptive-cpu", scene, 1.0).extra
        ratio = stats["sample_ratio_to_full"]
        rows.append((features, ratio))
        print("case %2d: band [%.4g, %.4g]: feature points %.3f, pyramid samples / full rate %.3f"
              % (case, start, end, features, ratio), flush=True)
    excess = [r - f for f, r in rows]
    print("samples over the full rate minus the feature fraction: median %.3f, range %.3f to "
          "%.3f; cases at or below 0.1 of the full rate: %d of %d"
          % (numpy.median(excess), min(excess), max(excess),
             sum(r <= 0.1 for _, r in rows), len(rows)))
    renderer.close()


if __name__ == "__main__":
    main()
