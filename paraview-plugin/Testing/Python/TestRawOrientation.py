# hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
"""pvbatch test: ParaView's raw "Image Reader" reads a numpy-written volume as hovr does.

The same asymmetric field as the VTK build's TestVolumeOrientation.py (sizes 6 x 5 x 4,
spacing 0.5, 1.25, 2, value i + 10 j + 100 k at index (i, j, k), written by numpy x fastest)
is loaded with ParaView's own raw reader at its default settings, and every point must hold
the value numpy wrote there: together with TestVolumeOrientation.py, ParaView and every hovr
reader path agree point for point.

    pvbatch TestRawOrientation.py --output-dir <dir>
"""
import argparse
import os

import numpy
from paraview import servermanager
from paraview.simple import ImageReader
from vtkmodules.util.numpy_support import vtk_to_numpy

from TestHovrPlugin import Checker, run

NX, NY, NZ = 6, 5, 4
SPACING = (0.5, 1.25, 2.0)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output-dir", required=True, help="where the raw file is written")
    args = parser.parse_args()
    os.makedirs(args.output_dir, exist_ok=True)
    checker = Checker()
    k, j, i = numpy.meshgrid(numpy.arange(NZ), numpy.arange(NY), numpy.arange(NX),
                             indexing="ij")
    field = (i + 10 * j + 100 * k).astype(numpy.float32)
    path = os.path.join(args.output_dir, "orientation_field.raw")
    field.astype("<f4").tofile(path)

    reader = ImageReader(FileNames=[path])
    checker.check(reader.FileLowerLeft == 1, "ParaView's raw reader defaults to FileLowerLeft "
                  "on (rows in increasing y): %s" % reader.FileLowerLeft)
    reader.DataScalarType = "float"
    reader.DataByteOrder = "LittleEndian"
    reader.DataExtent = [0, NX - 1, 0, NY - 1, 0, NZ - 1]
    reader.DataSpacing = list(SPACING)
    reader.UpdatePipeline()
    image = servermanager.Fetch(reader)
    checker.check(image.GetDimensions() == (NX, NY, NZ), "dimensions %s" % (
        image.GetDimensions(),))
    values = vtk_to_numpy(image.GetPointData().GetScalars())
    checker.check(numpy.array_equal(values, field.ravel()),
                  "every point holds the value numpy wrote there (point id i + NX (j + NY k) "
                  "is numpy's [k, j, i])")
    pid = image.ComputePointId([2, 3, 1])
    checker.check(numpy.allclose(image.GetPoint(pid), numpy.multiply((2, 3, 1), SPACING)),
                  "point (2, 3, 1) lies at spacing times its index: %s" % (
                      image.GetPoint(pid),))
    return checker.failures


if __name__ == "__main__":
    run(main)
