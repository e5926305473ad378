# hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
"""pvbatch test of the hovr ParaView plugin.

Loads the plugin, volume renders the Marschner-Lobb source with the "hovr Volume"
representation and a narrow opacity peak, and checks that
  - the plugin's proxies and properties are there, with their documented defaults;
  - the representation draws with vtkPreIntegrationVolumeMapper and forwards its settings
    (sample distance, table size, half-float table; checked in pvbatch's built-in session);
  - the first-order image matches the baseline, and a half-float table barely changes it;
  - switching Integration to Stock changes the image (so the pre-integrated path was drawn),
    and first-order at one sample per cell is closer to a fine-step Stock reference than Stock;
  - a sample distance of 0 becomes half the grid spacing.

    pvbatch TestHovrPlugin.py --plugin <hovr.so> --baseline <png> --output-dir <dir>
    pvpython TestHovrPlugin.py ... --server <host>:<port>   (client-server, see RunClientServer.py)

Without a baseline the test image is written to the output directory and the test fails: that
is how the baseline is made (inspect the image, then copy it to the baseline path).
"""
import argparse
import os
import re

from paraview.simple import (ColorBy, Connect, CreateRenderView, Disconnect,
                             GetColorTransferFunction, GetOpacityTransferFunction, LoadPlugin,
                             Render, SaveScreenshot, Show)
import numpy
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader
# Python classes of VTK's GPU ray caster: hovr's classes are not Python-wrapped in the plugin
# build, so the mapper is seen as its nearest wrapped base class (its class name is still hovr's).
from vtkmodules import vtkRenderingVolumeOpenGL2  # noqa: F401

# Images are compared by the root-mean-square difference of their RGB values (0-255) over all
# pixels. VTK's vtkImageDifference is not used: it forgives 105 levels per pixel and shifts of
# a pixel, so it cannot tell this scene's Stock image from the first-order one.
#
# Baseline tolerance: renders on the machine kind that made the baseline repeat exactly (0, in
# pvbatch and through a pvserver alike); llvmpipe on another CPU or LLVM version may round some
# pixels differently by a few levels (not measured), which the tolerance absorbs. Stock
# compositing of the same scene differs by about 18, a half-float table by about 0.07.
BASELINE_TOLERANCE = 2.0
# Switching to Stock must change the image by at least this much: a narrow opacity peak
# sampled once per cell is where point sampling and pre-integration disagree most.
MIN_STOCK_DIFFERENCE = 8.0
# Step of the Stock reference image: 1/25 of a cell, where point sampling has converged for this
# peak far better than either method at one sample per cell.
REFERENCE_SAMPLE_DISTANCE = 2.0 / 40.0 / 25.0
# Pre-integration table entries per scalar axis: about 10 across the narrowest opacity feature
# (0.02 of the data range [0, 1]).
TABLE_SIZE = 512

IMAGE_SIZE = [256, 256]
GRID_SPACING = 2.0 / 40.0  # Marschner-Lobb default: 41 points over [-1, 1]


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plugin", required=True, help="path of the hovr plugin (hovr.so)")
    parser.add_argument("--baseline", required=True, help="baseline PNG of the first-order image")
    parser.add_argument("--output-dir", required=True, help="where test images are written")
    parser.add_argument("--server", help="host:port of a pvserver to connect to; without it the "
                        "test runs in pvbatch's built-in session")
    return parser.parse_args()


class Checker:
    """Collects failures so that one run reports all of them."""

    def __init__(self):
        self.failures = []

    def check(self, condition, message):
        print(("ok: " if condition else "FAILED: ") + message)
        if not condition:
            self.failures.append(message)
        return condition


def read_rgb(path):
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    rgb = vtk_to_numpy(image.GetPointData().GetScalars())[:, :3].astype(numpy.float64)
    return rgb, image.GetDimensions()


def image_difference(path, reference_path):
    """RMS difference of the RGB values (0-255) of two PNG files; inf if their sizes differ."""
    rgb, size = read_rgb(path)
    reference, reference_size = read_rgb(reference_path)
    if size != reference_size:
        print("image sizes differ: %s is %s, %s is %s" % (path, size, reference_path,
                                                          reference_size))
        return float("inf")
    return float(numpy.sqrt(numpy.mean((rgb - reference) ** 2)))


# The table's GPU memory also holds its zero-opacity runs: one float per table spacing.
RUNS_BYTES = (TABLE_SIZE - 1) * 4


def table_texture_bytes(mapper):
    """GPU bytes of the mapper's table, read from its PrintSelf: hovr's getters are not
    Python-wrapped in the plugin build."""
    match = re.search(r"TableTextureMemorySize: (\d+)", str(mapper))
    return int(match.group(1)) if match else -1


def capture(view, path):
    Render(view)
    SaveScreenshot(path, view, ImageResolution=IMAGE_SIZE, TransparentBackground=0)
    return path


def main():
    args = parse_arguments()
    os.makedirs(args.output_dir, exist_ok=True)
    checker = Checker()

    # pvbatch --plugins= does not load plugins; LoadPlugin does (ns= adds the new proxies'
    # creation functions, such as MarschnerLobb, to this namespace). A client of a pvserver
    # loads it on both sides: the server draws, the client creates the same proxies.
    if args.server:
        host, port = args.server.rsplit(":", 1)
        Connect(host, int(port))
        LoadPlugin(args.plugin, remote=True, ns=globals())
    LoadPlugin(args.plugin, remote=False, ns=globals())
    if not checker.check("MarschnerLobb" in globals(), "the plugin defines the MarschnerLobb source"):
        return checker.failures

    source = globals()["MarschnerLobb"]()
    checker.check(list(source.Dimensions) == [41, 41, 41] and source.Frequency == 6 and
                  source.Alpha == 0.25, "Marschner-Lobb defaults are 41^3, f_M = 6, alpha = 0.25")

    view = CreateRenderView()
    view.ViewSize = IMAGE_SIZE
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.BackgroundColorMode = "Single Color"
    view.Background = [0.0, 0.0, 0.0]
    view.UseFXAA = 0
    view.UseToneMapping = 0

    display = Show(source, view)
    display.SetRepresentationType("hovr Volume")
    ColorBy(display, ("POINTS", "MarschnerLobb"))

    properties = display.ListProperties()
    for name in ("HovrIntegration", "HovrSampleDistance", "HovrTableSize", "HovrHalfFloatTable"):
        checker.check(name in properties, "the representation exposes %s" % name)
    checker.check(list(display.GetProperty("HovrIntegration").Available) ==
                  ["Stock", "First-order pre-integration"], "Integration choices")
    checker.check(display.HovrIntegration == "First-order pre-integration",
                  "Integration defaults to first-order pre-integration")
    checker.check(display.HovrSampleDistance == 0 and display.HovrTableSize == 0 and
                  display.HovrHalfFloatTable == 0,
                  "Sample Distance, Table Size and Half-Float Table default to 0 (automatic/off)")

    # A narrow opacity peak around 0.5: a thin shell that sampling once per cell misses or
    # aliases, while first-order pre-integration catches it between samples.
    color = GetColorTransferFunction("MarschnerLobb")
    color.AutomaticRescaleRangeMode = "Never"
    color.ColorSpace = "RGB"
    color.RGBPoints = [0.0, 0.1, 0.3, 0.9,
                       0.5, 1.0, 0.55, 0.15,
                       1.0, 1.0, 1.0, 0.9]
    opacity = GetOpacityTransferFunction("MarschnerLobb")
    opacity.Points = [0.0, 0.0, 0.5, 0.0,
                      0.48, 0.0, 0.5, 0.0,
                      0.5, 1.0, 0.5, 0.0,
                      0.52, 0.0, 0.5, 0.0,
                      1.0, 0.0, 0.5, 0.0]
    # Translucent enough that the shells behind the first one show.
    display.ScalarOpacityUnitDistance = 4.0 * GRID_SPACING

    display.HovrIntegration = "First-order pre-integration"
    display.HovrSampleDistance = GRID_SPACING  # one sample per cell: coarse on purpose
    # A fixed table size keeps the baseline independent of the mapper's automatic choice.
    display.HovrTableSize = TABLE_SIZE

    # Show() and the first render reset the camera; fix it afterwards.
    Render(view)
    view.CameraPosition = [2.2, -3.6, 2.0]
    view.CameraFocalPoint = [0.0, 0.0, 0.0]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.CameraViewAngle = 30.0
    view.CameraParallelProjection = 0

    first_order = capture(view, os.path.join(args.output_dir, "TestHovrPlugin.png"))

    # The client-side object of the composite representation is vtkPVCompositeRepresentation;
    # its active representation is ours. pvbatch holds server and client in one process, so
    # there it is the object that draws; a pvserver client holds a twin that draws only the
    # outline, so what reaches the drawing mapper is checked in the built-in session only.
    drawing_mapper_here = not args.server
    composite = display.GetClientSideObject()
    representation = composite.GetActiveRepresentation()
    checker.check(representation.GetClassName() == "vtkPreIntegrationVolumeRepresentation",
                  "the active representation is vtkPreIntegrationVolumeRepresentation (got %s)"
                  % representation.GetClassName())
    mapper = representation.GetActor().GetMapper()
    checker.check(mapper is not None and mapper.GetClassName() == "vtkPreIntegrationVolumeMapper",
                  "the representation's mapper is vtkPreIntegrationVolumeMapper (got %s)"
                  % (mapper.GetClassName() if mapper else None))
    if drawing_mapper_here:
        checker.check(abs(mapper.GetSampleDistance() - GRID_SPACING) < 1e-6,
                      "Sample Distance reaches the mapper (%g)" % mapper.GetSampleDistance())
        checker.check(table_texture_bytes(mapper) == TABLE_SIZE * TABLE_SIZE * 4 * 4 + RUNS_BYTES,
                      "Table Size reaches the mapper: a %d^2 RGBA float table (%d bytes)"
                      % (TABLE_SIZE, table_texture_bytes(mapper)))

    if not os.path.exists(args.baseline):
        checker.check(False, "no baseline at %s; the test image is %s: inspect it and copy it "
                      "there to make the baseline" % (args.baseline, first_order))
    else:
        error = image_difference(first_order, args.baseline)
        checker.check(error <= BASELINE_TOLERANCE,
                      "first-order image matches the baseline: RMS difference %g, tolerance %g "
                      "(test image %s)" % (error, BASELINE_TOLERANCE, first_order))

    display.HovrHalfFloatTable = 1
    half_float = capture(view, os.path.join(args.output_dir, "TestHovrPlugin-half.png"))
    if drawing_mapper_here:
        checker.check(table_texture_bytes(mapper) == TABLE_SIZE * TABLE_SIZE * 4 * 2 + RUNS_BYTES,
                      "Half-Float Table reaches the mapper: a %d^2 RGBA half-float table (%d "
                      "bytes)" % (TABLE_SIZE, table_texture_bytes(mapper)))
    half_float_difference = image_difference(half_float, first_order)
    checker.check(half_float_difference <= BASELINE_TOLERANCE,
                  "a half-float table barely changes the image: RMS difference %g, at most %g"
                  % (half_float_difference, BASELINE_TOLERANCE))
    display.HovrHalfFloatTable = 0

    display.HovrIntegration = "Stock"
    stock = capture(view, os.path.join(args.output_dir, "TestHovrPlugin-stock.png"))
    difference = image_difference(stock, first_order)
    checker.check(difference >= MIN_STOCK_DIFFERENCE,
                  "Stock integration changes the image: RMS difference %g, at least %g"
                  % (difference, MIN_STOCK_DIFFERENCE))

    # Reference: Stock with a fine step, where point sampling converges. Pre-integration at the
    # coarse step must be closer to it than Stock at the coarse step.
    display.HovrSampleDistance = REFERENCE_SAMPLE_DISTANCE
    reference = capture(view, os.path.join(args.output_dir, "TestHovrPlugin-reference.png"))
    first_order_error = image_difference(first_order, reference)
    stock_error = image_difference(stock, reference)
    checker.check(first_order_error < stock_error,
                  "first-order is closer to the fine-step reference than Stock: RMS %g < %g"
                  % (first_order_error, stock_error))

    display.HovrIntegration = "First-order pre-integration"
    display.HovrSampleDistance = 0.0
    Render(view)
    if drawing_mapper_here:
        checker.check(abs(mapper.GetSampleDistance() - 0.5 * GRID_SPACING) < 1e-6,
                      "Sample Distance 0 becomes half the grid spacing (%g)"
                      % mapper.GetSampleDistance())
    if args.server:
        Disconnect()  # lets the pvserver exit
    return checker.failures


if __name__ == "__main__":
    failures = main()
    if failures:
        # An exception rather than sys.exit: pvbatch exits non-zero either way, but sys.exit
        # skips its teardown of the OpenGL context (an X error is printed).
        raise RuntimeError("%d check(s) failed: %s" % (len(failures), "; ".join(failures)))
    print("all checks passed")
