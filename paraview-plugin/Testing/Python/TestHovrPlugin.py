# hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
"""pvbatch test of the hovr ParaView plugin.

Loads the plugin, volume renders the Marschner-Lobb source with the "hovr Volume"
representation and a narrow opacity peak, and checks that
  - the plugin's proxies and properties are there, with their documented defaults and
    enumeration entries;
  - the representation draws with vtkPreIntegrationVolumeMapper and forwards its settings
    (sample distance, table size, table precision, iterations; checked in pvbatch's built-in
    session, through the table's GPU bytes and the mapper's PrintSelf);
  - the first-order image matches its baseline, and a half-float table barely changes it;
  - the second-order image (a 3D table) matches its baseline and differs from the first-order
    one;
  - switching Integration to Stock changes the image (so the pre-integrated path was drawn),
    and first- and second-order at one sample per cell are closer to a fine-step Stock
    reference than Stock;
  - a sample distance of 0 becomes half the grid spacing.

    pvbatch TestHovrPlugin.py --plugin <hovr.so> --baseline <png> \
        --second-order-baseline <png> --output-dir <dir>
    pvpython TestHovrPlugin.py ... --server <host>:<port>   (client-server, see RunClientServer.py)

Without a baseline the test image is written to the output directory and the test fails: that
is how a baseline is made (inspect the image, then copy it to the baseline path).
"""
import argparse
import os
import re
import time

from paraview import servermanager
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
# Baseline tolerance: renders with the CPU and LLVM version that made the baseline repeat
# exactly (0, in pvbatch and through a pvserver alike); llvmpipe on another CPU or LLVM version
# may round some pixels differently by a few levels, which the tolerance absorbs. Stock
# compositing of the same scene differs by about 18, a half-float table by about 0.07; in
# second order, 128 iterations and a float table instead of 64 and half floats by about 0.17.
BASELINE_TOLERANCE = 2.0
# The second-order image must differ from the first-order one by more than rendering noise
# (half the difference the two orders' sampling of the peak makes).
MIN_ORDER_DIFFERENCE = 4.0
# Switching to Stock must change the image by at least this much: a narrow opacity peak
# sampled once per cell is where point sampling and pre-integration disagree most.
MIN_STOCK_DIFFERENCE = 8.0
# Step of the Stock reference image: 1/25 of a cell, where point sampling has converged for this
# peak far better than either method at one sample per cell.
REFERENCE_SAMPLE_DISTANCE = 2.0 / 40.0 / 25.0
# Pre-integration table entries per scalar axis: about 10 across the narrowest opacity feature
# (0.02 of the data range [0, 1]).
TABLE_SIZE = 512
# The second-order table has TABLE_SIZE_3D^3 entries (centres, chords and deviations over the
# whole range), fixed so that the baseline does not depend on the measured sizes.
TABLE_SIZE_3D = 64
# Integration steps per second-order table entry, set to check that the setting reaches the
# mapper (the initial value is 64).
ITERATIONS = 128

IMAGE_SIZE = [256, 256]
GRID_SPACING = 2.0 / 40.0  # Marschner-Lobb default: 41 points over [-1, 1]


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plugin", required=True, help="path of the hovr plugin (hovr.so)")
    parser.add_argument("--baseline", required=True, help="baseline PNG of the first-order image")
    parser.add_argument("--second-order-baseline", required=True,
                        help="baseline PNG of the second-order image")
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


def interior_difference(path, reference_path, margin=2):
    """The largest difference of the RGB values (0-255) of two PNG files of the same size over
    the pixels inside the silhouette: farther than margin pixels from any pixel that is
    background (the corner's colour) in either image."""
    rgb, size = read_rgb(path)
    reference, _ = read_rgb(reference_path)
    shape = (size[1], size[0], 3)
    rgb, reference = rgb.reshape(shape), reference.reshape(shape)
    background = (numpy.all(rgb == rgb[0, 0], axis=2) |
                  numpy.all(reference == reference[0, 0], axis=2))
    edge = background.copy()
    for dy in range(-margin, margin + 1):
        for dx in range(-margin, margin + 1):
            edge |= numpy.roll(numpy.roll(background, dy, 0), dx, 1)
    inside = numpy.abs(rgb - reference).max(axis=2)[~edge]
    return float(inside.max()) if inside.size else 0.0


# Bytes per table channel of the Table Precision entries (Automatic resolved by the caller).
PRECISION_BYTES = {"8-bit": 1, "Half float": 2, "Float": 4}


def expected_table_bytes(size, dimensions, precision):
    """GPU bytes of an RGBA table of size^dimensions entries, plus its zero-opacity runs (one
    float per table spacing)."""
    return size ** dimensions * 4 * PRECISION_BYTES[precision] + (size - 1) * 4


# The object-order caster's settings, in the order of their defaults' check.
CPU_PROPERTIES = ("HovrCPUClassification", "HovrCPUShading", "HovrInterleavedSampling",
                  "HovrHiddenVolumeRemoval", "HovrOpacityThreshold", "HovrLeafSize",
                  "HovrInstructionSet")
CPU_DEFAULTS = ("Pre-integrated", "Post-shading", 1, 1, 0.996, 8, "Automatic")


def mapper_setting(mapper, name):
    """An integer setting printed by the mapper's PrintSelf ("Name: value"), or None: hovr's
    getters are not Python-wrapped in the plugin build."""
    match = re.search(r"^\s*%s: (-?\d+)$" % name, str(mapper), re.MULTILINE)
    return int(match.group(1)) if match else None


def table_texture_bytes(mapper):
    """GPU bytes of the mapper's table."""
    value = mapper_setting(mapper, "TableTextureMemorySize")
    return -1 if value is None else value


def compare_with_baseline(checker, image, baseline, what):
    if not os.path.exists(baseline):
        checker.check(False, "no baseline at %s; the test image is %s: inspect it and copy it "
                      "there to make the baseline" % (baseline, image))
        return
    error = image_difference(image, baseline)
    checker.check(error <= BASELINE_TOLERANCE,
                  "%s image matches the baseline: RMS difference %g, tolerance %g (test image %s)"
                  % (what, error, BASELINE_TOLERANCE, image))


def plain_view(size):
    """A render view of the given size on black, without orientation axes, FXAA or tone
    mapping, so that images show only the volume."""
    view = CreateRenderView()
    view.ViewSize = size
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.BackgroundColorMode = "Single Color"
    view.Background = [0.0, 0.0, 0.0]
    view.UseFXAA = 0
    view.UseToneMapping = 0
    return view


def refinement_status(display):
    """A "HovrRefinementStatus" proxy for the display's "hovr Volume": it answers where the
    volume is drawn (the server in client-server), as the GUI's behaviour asks."""
    hovr = display.SMProxy.GetProperty("HovrRefinementState").GetParent()
    status = servermanager.ProxyManager().SMProxyManager.NewProxy("hovr_misc",
                                                                  "HovrRefinementStatus")
    status.GetProperty("Representation").AddProxy(hovr)
    status.UpdateVTKObjects()
    return status


def status_value(status, name):
    status.UpdatePropertyInformation()
    return status.GetProperty(name).GetElement(0)


def capture(view, path, size=IMAGE_SIZE):
    Render(view)
    SaveScreenshot(path, view, ImageResolution=size, TransparentBackground=0)
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

    view = plain_view(IMAGE_SIZE)

    display = Show(source, view)
    display.SetRepresentationType("hovr Volume")
    ColorBy(display, ("POINTS", "MarschnerLobb"))

    properties = display.ListProperties()
    for name in ("HovrIntegration", "HovrSampleDistance", "HovrTableSize", "HovrTablePrecision",
                 "HovrIterations", "HovrTablePrefilter", "HovrTableMemoryLimit",
                 "HovrVolumePrecision") + CPU_PROPERTIES:
        checker.check(name in properties, "the representation exposes %s" % name)
    checker.check("HovrHalfFloatTable" not in properties,
                  "HovrHalfFloatTable is gone (replaced by HovrTablePrecision)")
    integrations = list(display.GetProperty("HovrIntegration").Available)
    checker.check(integrations == ["Stock", "First-order pre-integration",
                                   "Second-order pre-integration", "Analytic isosurface",
                                   "Analytic MIP", "Analytic MinIP",
                                   "Object-order ray casting (CPU)",
                                   "Adaptive sampling along rays",
                                   "Adaptive sampling in 3D (pyramid)"],
                  "Integration choices (%s)" % integrations)
    precisions = list(display.GetProperty("HovrTablePrecision").Available)
    checker.check(precisions == ["Automatic", "8-bit", "Half float", "Float"],
                  "Table Precision choices (%s)" % precisions)
    checker.check(display.HovrIntegration == "First-order pre-integration",
                  "Integration defaults to first-order pre-integration")
    checker.check(display.HovrSampleDistance == 0 and display.HovrTableSize == 0,
                  "Sample Distance and Table Size default to 0 (automatic)")
    checker.check(display.HovrTablePrecision == "Automatic",
                  "Table Precision defaults to Automatic (%s)" % display.HovrTablePrecision)
    checker.check(display.HovrIterations == 64,
                  "Iterations defaults to 64 (%s)" % display.HovrIterations)
    prefilters = list(display.GetProperty("HovrTablePrefilter").Available)
    checker.check(prefilters == ["Off", "On", "Automatic"],
                  "Table Prefilter choices (%s)" % prefilters)
    checker.check(display.HovrTablePrefilter == "Automatic",
                  "Table Prefilter defaults to Automatic (%s)" % display.HovrTablePrefilter)
    volume_precisions = list(display.GetProperty("HovrVolumePrecision").Available)
    checker.check(volume_precisions == ["Automatic", "Native", "16-bit", "Float"],
                  "Volume Precision choices (%s)" % volume_precisions)
    checker.check(display.HovrVolumePrecision == "Automatic",
                  "Volume Precision defaults to Automatic (%s)" % display.HovrVolumePrecision)
    checker.check(display.HovrTableMemoryLimit == 64 * 2 ** 20,
                  "Table Memory Limit defaults to 64 MiB (%s)" % display.HovrTableMemoryLimit)
    cpu_defaults = [display.GetPropertyValue(name) for name in CPU_PROPERTIES]
    checker.check(cpu_defaults == list(CPU_DEFAULTS),
                  "the object-order settings default to the caster's documented initial "
                  "values (%s)" % cpu_defaults)

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
    checker.check(representation.GetClassName() == "vtkHovrVolumeRepresentation",
                  "the active representation is vtkHovrVolumeRepresentation (got %s)"
                  % representation.GetClassName())
    mapper = representation.GetActor().GetMapper()
    checker.check(mapper is not None and mapper.GetClassName() == "vtkPreIntegrationVolumeMapper",
                  "the representation's mapper is vtkPreIntegrationVolumeMapper (got %s)"
                  % (mapper.GetClassName() if mapper else None))
    if drawing_mapper_here:
        checker.check(abs(mapper.GetSampleDistance() - GRID_SPACING) < 1e-6,
                      "Sample Distance reaches the mapper (%g)" % mapper.GetSampleDistance())
        # Automatic precision: 32-bit floats for the 2D table.
        checker.check(table_texture_bytes(mapper) == expected_table_bytes(TABLE_SIZE, 2, "Float"),
                      "Table Size reaches the mapper: a %d^2 RGBA float table (%d bytes)"
                      % (TABLE_SIZE, table_texture_bytes(mapper)))
        checker.check(mapper_setting(mapper, "Integration") == 1 and
                      mapper_setting(mapper, "TablePrecision") == 0 and
                      mapper_setting(mapper, "Iterations") == 64,
                      "the mapper has Integration 1, TablePrecision 0 and Iterations 64")

    compare_with_baseline(checker, first_order, args.baseline, "first-order")

    display.HovrTablePrecision = "Half float"
    half_float = capture(view, os.path.join(args.output_dir, "TestHovrPlugin-half.png"))
    if drawing_mapper_here:
        checker.check(mapper_setting(mapper, "TablePrecision") == 2 and
                      table_texture_bytes(mapper) == expected_table_bytes(TABLE_SIZE, 2,
                                                                          "Half float"),
                      "Table Precision reaches the mapper: a %d^2 RGBA half-float table (%d "
                      "bytes)" % (TABLE_SIZE, table_texture_bytes(mapper)))
    half_float_difference = image_difference(half_float, first_order)
    checker.check(half_float_difference <= BASELINE_TOLERANCE,
                  "a half-float table barely changes the image: RMS difference %g, at most %g"
                  % (half_float_difference, BASELINE_TOLERANCE))
    display.HovrTablePrecision = "8-bit"
    Render(view)
    if drawing_mapper_here:
        checker.check(mapper_setting(mapper, "TablePrecision") == 1 and
                      table_texture_bytes(mapper) == expected_table_bytes(TABLE_SIZE, 2, "8-bit"),
                      "8-bit Table Precision reaches the mapper: a %d^2 RGBA8 table (%d bytes)"
                      % (TABLE_SIZE, table_texture_bytes(mapper)))
    display.HovrTablePrecision = "Automatic"

    # Second order: slabs of two sample distances, a 3D table (automatic precision: half
    # floats).
    display.HovrIntegration = "Second-order pre-integration"
    display.HovrTableSize = TABLE_SIZE_3D
    second_order = capture(view, os.path.join(args.output_dir, "TestHovrPlugin-second.png"))
    if drawing_mapper_here:
        checker.check(mapper_setting(mapper, "Integration") == 2 and
                      table_texture_bytes(mapper) == expected_table_bytes(TABLE_SIZE_3D, 3,
                                                                          "Half float"),
                      "second order reaches the mapper: a %d^3 RGBA half-float table (%d bytes)"
                      % (TABLE_SIZE_3D, table_texture_bytes(mapper)))
    compare_with_baseline(checker, second_order, args.second_order_baseline, "second-order")
    orders_difference = image_difference(second_order, first_order)
    checker.check(orders_difference >= MIN_ORDER_DIFFERENCE,
                  "the second-order image differs from the first-order one: RMS difference %g, "
                  "at least %g" % (orders_difference, MIN_ORDER_DIFFERENCE))

    display.HovrIterations = ITERATIONS
    display.HovrTablePrecision = "Float"
    more_iterations = capture(view, os.path.join(args.output_dir,
                                                 "TestHovrPlugin-second-iterations.png"))
    if drawing_mapper_here:
        checker.check(mapper_setting(mapper, "Iterations") == ITERATIONS,
                      "Iterations reaches the mapper (%s)" % mapper_setting(mapper, "Iterations"))
        checker.check(mapper_setting(mapper, "TablePrecision") == 3 and
                      table_texture_bytes(mapper) == expected_table_bytes(TABLE_SIZE_3D, 3,
                                                                          "Float"),
                      "Table Precision reaches the mapper: a %d^3 RGBA float table (%d bytes)"
                      % (TABLE_SIZE_3D, table_texture_bytes(mapper)))
    iterations_difference = image_difference(more_iterations, second_order)
    checker.check(iterations_difference <= BASELINE_TOLERANCE,
                  "%d iterations and a float table barely change the second-order image: RMS "
                  "difference %g, at most %g" % (ITERATIONS, iterations_difference,
                                                 BASELINE_TOLERANCE))
    display.HovrIterations = 64
    display.HovrTablePrecision = "Automatic"

    display.HovrTablePrefilter = "On"
    display.HovrTableMemoryLimit = 2 ** 20
    display.HovrVolumePrecision = "Float"
    Render(view)
    if drawing_mapper_here:
        checker.check(mapper_setting(mapper, "TablePrefilter") == 1,
                      "Table Prefilter reaches the mapper (%s)"
                      % mapper_setting(mapper, "TablePrefilter"))
        checker.check(mapper_setting(mapper, "VolumePrecision") == 3,
                      "Volume Precision reaches the mapper (%s)"
                      % mapper_setting(mapper, "VolumePrecision"))
        checker.check(mapper_setting(mapper, "TableMemoryLimit") == 2 ** 20,
                      "Table Memory Limit reaches the mapper (%s)"
                      % mapper_setting(mapper, "TableMemoryLimit"))
    display.HovrTablePrefilter = "Automatic"
    display.HovrTableMemoryLimit = 64 * 2 ** 20
    display.HovrVolumePrecision = "Automatic"
    display.HovrTableSize = TABLE_SIZE

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
    second_order_error = image_difference(second_order, reference)
    stock_error = image_difference(stock, reference)
    checker.check(first_order_error < stock_error,
                  "first-order is closer to the fine-step reference than Stock: RMS %g < %g"
                  % (first_order_error, stock_error))
    checker.check(second_order_error < stock_error,
                  "second-order is closer to the fine-step reference than Stock: RMS %g < %g"
                  % (second_order_error, stock_error))

    # Analytic isosurface: the exact first hit of the Volume representation's isosurface
    # values, drawn by vtkAnalyticVolumeMapper, which the representation swaps in; then MIP,
    # and back to pre-integration with the user's blend mode.
    display.HovrSampleDistance = GRID_SPACING
    display.IsosurfaceValues = [0.5]
    display.Shade = 1
    display.HovrIntegration = "Analytic isosurface"
    analytic = capture(view, os.path.join(args.output_dir, "TestHovrPlugin-analytic.png"))
    compare_with_baseline(checker, analytic,
                          os.path.join(os.path.dirname(args.baseline),
                                       "TestHovrPlugin-analytic.png"), "analytic isosurface")
    if drawing_mapper_here:
        analytic_mapper = representation.GetActor().GetMapper()
        checker.check(analytic_mapper.GetClassName() == "vtkAnalyticVolumeMapper" and
                      mapper_setting(analytic_mapper, "BlendMode") == 5 and
                      mapper_setting(analytic_mapper, "ExtensionFrameCount") > 0,
                      "Analytic isosurface draws with vtkAnalyticVolumeMapper, isosurface blend")
    display.HovrIntegration = "Analytic MIP"
    mip = capture(view, os.path.join(args.output_dir, "TestHovrPlugin-mip.png"))
    checker.check(image_difference(mip, analytic) > MIN_STOCK_DIFFERENCE,
                  "Analytic MIP draws another image than the isosurface")
    if drawing_mapper_here:
        checker.check(mapper_setting(representation.GetActor().GetMapper(), "BlendMode") == 1,
                      "Analytic MIP sets maximum intensity blending")
    display.Shade = 0

    # Object-order ray casting on the CPU, in parallel projection: vtkObjectOrderVolumeMapper
    # draws (no fallback) the same view as first-order pre-integration at the same sample
    # distance; they differ by the methods' sampling of the narrow opacity peak (as much as
    # Stock against first order), far less than a wrong view or placement would.
    view.CameraParallelProjection = 1
    display.HovrSampleDistance = 0.5 * GRID_SPACING
    display.HovrIntegration = "Object-order ray casting (CPU)"
    cpu = capture(view, os.path.join(args.output_dir, "TestHovrPlugin-objectorder.png"))
    display.HovrIntegration = "First-order pre-integration"
    parallel_first = capture(view, os.path.join(args.output_dir,
                                                "TestHovrPlugin-parallel-first.png"))
    difference = image_difference(cpu, parallel_first)
    cpu_rgb, _ = read_rgb(cpu)
    checker.check(difference < 12.0 and cpu_rgb.max() > 100,
                  "object-order draws the view first order draws in parallel projection: RMS "
                  "difference %g" % difference)
    display.HovrIntegration = "Object-order ray casting (CPU)"
    Render(view)
    if drawing_mapper_here:
        cpu_mapper = representation.GetActor().GetMapper()
        checker.check(cpu_mapper.GetClassName() == "vtkObjectOrderVolumeMapper" and
                      mapper_setting(cpu_mapper, "LastFrameFellBack") == 0 and
                      mapper_setting(cpu_mapper, "NumberOfSamples") > 0,
                      "Object-order draws with vtkObjectOrderVolumeMapper, no fallback")
    # Its settings reach the caster; hidden volume removal leaves the image as it is, and
    # point-sampled classification changes it (the narrow peak).
    display.HovrHiddenVolumeRemoval = 0
    no_removal = capture(view, os.path.join(args.output_dir,
                                            "TestHovrPlugin-objectorder-noremoval.png"))
    checker.check(image_difference(cpu, no_removal) == 0.0,
                  "object-order draws the same image without hidden volume removal")
    display.HovrCPUClassification = "Point-sampled"
    display.HovrCPUShading = "Pre-shading"
    display.HovrInterleavedSampling = 0
    display.HovrOpacityThreshold = 0.99
    display.HovrLeafSize = 4
    display.HovrInstructionSet = "SSE2"
    point = capture(view, os.path.join(args.output_dir, "TestHovrPlugin-objectorder-point.png"))
    checker.check(image_difference(cpu, point) > 0.0,
                  "point-sampled classification draws another image than pre-integration")
    if drawing_mapper_here:
        caster_settings = {name: mapper_setting(cpu_mapper, name) for name in (
            "Classification", "ShadingMode", "InterleavedSampling", "HiddenVolumeRemoval",
            "LeafSize", "InstructionSet", "LastInstructionSet")}
        checker.check(caster_settings == {"Classification": 0, "ShadingMode": 1,
                                          "InterleavedSampling": 0, "HiddenVolumeRemoval": 0,
                                          "LeafSize": 4, "InstructionSet": 1,
                                          "LastInstructionSet": 1},
                      "the object-order settings reach the caster (%s)" % caster_settings)
        threshold = re.search(r"^\s*OpacityThreshold: (\S+)$", str(cpu_mapper), re.MULTILINE)
        checker.check(threshold is not None and float(threshold.group(1)) == 0.99,
                      "the opacity threshold reaches the caster (%s)"
                      % (threshold.group(1) if threshold else None))
    for name, value in zip(CPU_PROPERTIES, CPU_DEFAULTS):
        display.SetPropertyWithName(name, value)
    view.CameraParallelProjection = 0

    # Answer first, refine after, asked where the volume is drawn as the GUI's behaviour asks
    # (a "HovrRefinementStatus" proxy on the render server: a pvserver client's own twin of
    # the representation draws no volume). The image measured at once for an edit of the
    # opacity peak, then the same edit with Refine In Background. A pvserver draws the edit at
    # once and measures its table in the background: the status's count of completed
    # measurements grows (the state may have gone from 1 to 2 before it is first asked, or to
    # 0 when the measurement confirmed the last measured sizes the edit's render drew at
    # once), and the next render draws the measured image, leaving nothing to refine (state
    # 0). pvbatch
    # ignores the setting (its frames are its results): the edit's own render draws the
    # measured image, and nothing is measured in the background.
    display.HovrIntegration = "First-order pre-integration"
    display.HovrSampleDistance = GRID_SPACING
    display.HovrTableSize = 0
    peak = list(opacity.Points)
    moved = list(peak)
    moved[8] = 0.505  # the peak's position
    opacity.Points = moved
    measured = capture(view, os.path.join(args.output_dir, "TestHovrPlugin-refine-measured.png"))
    opacity.Points = peak
    Render(view)
    display.HovrRefineInBackground = 1
    status = refinement_status(display)
    count = status_value(status, "Count")
    opacity.Points = moved
    Render(view)
    deadline = time.time() + 120.0
    while (args.server and status_value(status, "Count") == count and
           time.time() < deadline):
        time.sleep(0.1)
    state = status_value(status, "State")
    refined = capture(view, os.path.join(args.output_dir, "TestHovrPlugin-refine-refined.png"))
    after = status_value(status, "State")
    completed = status_value(status, "Count") - count
    difference = image_difference(refined, measured)
    if args.server:
        checker.check(completed >= 1 and state in (0, 2) and after == 0 and difference == 0.0,
                      "Refine In Background through a pvserver: the table is measured in the "
                      "background (%d measurements, then state %d), and the next render draws "
                      "the measured image (state %d, RMS difference %g)"
                      % (completed, state, after, difference))
    else:
        checker.check(completed == 0 and after == 0 and difference == 0.0,
                      "Refine In Background is ignored in pvbatch: the edit's render draws the "
                      "measured image (%d background measurements, state %d, RMS difference %g)"
                      % (completed, after, difference))
    display.HovrRefineInBackground = 0
    display.HovrTableSize = TABLE_SIZE
    opacity.Points = peak

    display.HovrIntegration = "First-order pre-integration"
    display.HovrSampleDistance = 0.0
    Render(view)
    if drawing_mapper_here:
        back = representation.GetActor().GetMapper()
        checker.check(back.GetClassName() == "vtkPreIntegrationVolumeMapper" and
                      mapper_setting(back, "BlendMode") == 0,
                      "back to first order: the pre-integration mapper, composite blending")
    if drawing_mapper_here:
        checker.check(abs(mapper.GetSampleDistance() - 0.5 * GRID_SPACING) < 1e-6,
                      "Sample Distance 0 becomes half the grid spacing (%g)"
                      % mapper.GetSampleDistance())
    if args.server:
        Disconnect()  # lets the pvserver exit
    return checker.failures


def run(main):
    """Runs a test's main, which returns its failures; a failure raises."""
    failures = main()
    if failures:
        # An exception rather than sys.exit: pvbatch exits non-zero either way, but sys.exit
        # skips its teardown of the OpenGL context (an X error is printed).
        raise RuntimeError("%d check(s) failed: %s" % (len(failures), "; ".join(failures)))
    print("all checks passed")


if __name__ == "__main__":
    run(main)
