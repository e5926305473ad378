# hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
"""pvbatch test of the hovr plugin on distributed data (run by RunMPI.py, once on one rank and
then under MPI), or the same as the client of a pvserver on several ranks (RunClientServer.py).

Renders a semi-transparent Marschner-Lobb volume with the "hovr Volume" representation in each
of Stock, First-order, Second-order, Analytic isosurface and Object-order (CPU) integration,
and writes one image per method, then Analytic MIP and MinIP, which must draw without a
warning on any number of ranks (each pixel comes from the rank that holds its extremum, by
depth). Then a second scene whose pieces cover different parts of the scalar range (see
ramp_scene) in every method but the projections. With --compare-dir (the runs on several
ranks), it also checks that
  - pvbatch (or pvserver) runs on --ranks processes and the Marschner-Lobb source is split
    between them (in pvbatch: rank 0 holds a part of the volume, not all of it);
  - each method's image matches the one-rank image of --compare-dir: every rank draws its own
    piece, and ParaView's ordered compositing joins them without seams or doubled opacity;
  - that tolerance is well below the change a quarter more opacity makes (a piece drawn
    twice would double it), so a piece composited wrongly cannot pass;
  - in pvbatch, rank 0 draws the pre-integration tables of the one-rank run (HovrTableSizes):
    every rank measures them on the whole volume, not on its piece;
  - pre-integration (both orders, shaded and not), object order (shaded and not) and both
    adaptive methods differ from one rank by at most 3/255 inside the silhouette of the second
    scene: each piece is drawn with its ghost points.

    pvbatch TestHovrPluginMPI.py --plugin <hovr.so> --output-dir <dir>
    mpiexec -n 2 pvbatch TestHovrPluginMPI.py --plugin <hovr.so> --output-dir <dir2> \
        --compare-dir <dir> --ranks 2
    pvpython TestHovrPluginMPI.py ... --ranks 2 --server <host>:<port>   (a 2-rank pvserver)
"""
import argparse
import json
import os

from paraview import servermanager
import numpy
from paraview.simple import (ColorBy, Connect, Disconnect, GetColorTransferFunction,
                             GetOpacityTransferFunction, Hide, LoadPlugin, Render, Show)
from vtkmodules.vtkParallelCore import vtkMultiProcessController

# The checker and image helpers of the plugin's main test (this script's directory).
from TestHovrPlugin import (Checker, capture, image_difference, interior_difference, plain_view,
                            read_rgb, run)

IMAGE_SIZE = [200, 200]
DIMENSIONS = [48, 48, 48]
METHODS = ("Stock", "First-order pre-integration", "Second-order pre-integration",
           "Analytic isosurface", "Object-order ray casting (CPU)")
# RMS difference of the RGB values (0-255) allowed between Stock's distributed and one-rank
# images (VTK's own sampling restarts in each piece), far below a missing or misplaced piece;
# the hovr methods are held to RAMP_TOLERANCE and 3 inside the silhouette.
TOLERANCE = 1.5
UNIT_DISTANCE = 0.2  # of the opacity map, in world units (the volume spans [-1, 1]^3)
# The ramp scene: odd point counts, every method but the projections.
RAMP_DIMENSIONS = [65, 57, 49]
RAMP_METHODS = METHODS + ("Adaptive sampling along rays", "Adaptive sampling in 3D (pyramid)")
# RMS allowed there: 1/255, against what the pieces' 8-bit images composited leave.
RAMP_TOLERANCE = 1.0
PROJECTIONS = ("Analytic MIP", "Analytic MinIP")
# Every method but Stock, shaded too (the adaptive 3D method draws unshaded after a warning).
SHADED_METHODS = RAMP_METHODS[1:]
# The adaptive ray hands a shaded property to VTK's own path after a warning: Stock's
# sampling, reported as Stock's is.
STOCK_DRAWN = ("ramp-shaded-adaptive-sampling-along-rays.png",)


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plugin", required=True, help="path of the hovr plugin (hovr.so)")
    parser.add_argument("--output-dir", required=True, help="where the images are written")
    parser.add_argument("--compare-dir", help="images of a one-rank run to compare with")
    parser.add_argument("--ranks", type=int, default=1, help="processes expected")
    parser.add_argument("--server", help="host:port of a pvserver (on --ranks ranks) to connect "
                        "to; without it the script runs in pvbatch")
    return parser.parse_args()


def file_name(method):
    return "-".join(method.lower().replace("(", "").replace(")", "").split()) + ".png"


def main():
    args = parse_arguments()
    os.makedirs(args.output_dir, exist_ok=True)
    checker = Checker()
    check = checker.check

    if args.server:
        host, port = args.server.rsplit(":", 1)
        Connect(host, int(port))
        LoadPlugin(args.plugin, remote=True, ns=globals())
        ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()
        check(ranks == args.ranks, "pvserver runs on %d processes (%d)" % (args.ranks, ranks))
    LoadPlugin(args.plugin, remote=False, ns=globals())
    if not args.server:
        ranks = vtkMultiProcessController.GetGlobalController().GetNumberOfProcesses()
        check(ranks == args.ranks, "pvbatch runs on %d processes (%d)" % (args.ranks, ranks))

    source = globals()["MarschnerLobb"](Dimensions=DIMENSIONS)
    source.UpdatePipeline()
    # This script runs on rank 0 (pvbatch's satellites only serve it): its local output is
    # rank 0's piece.
    whole = DIMENSIONS[0] * DIMENSIONS[1] * DIMENSIONS[2]
    if ranks > 1 and not args.server:  # a pvserver's client holds no piece
        local = source.GetClientSideObject().GetOutputDataObject(0).GetNumberOfPoints()
        check(0 < local < whole, "the source is split: rank 0 holds %d of %d points"
              % (local, whole))

    view = plain_view(IMAGE_SIZE)
    display = Show(source, view)
    display.SetRepresentationType("hovr Volume")
    ColorBy(display, ("POINTS", "MarschnerLobb"))
    display.IsosurfaceValues = [0.5]  # for Analytic isosurface
    color = GetColorTransferFunction("MarschnerLobb")
    color.AutomaticRescaleRangeMode = "Never"
    color.ColorSpace = "RGB"
    color.RGBPoints = [0.0, 0.1, 0.3, 0.9, 0.5, 1.0, 0.55, 0.15, 1.0, 1.0, 1.0, 0.9]
    # Semi-transparent: every piece's samples show through, so a seam or a piece composited
    # twice would change the image.
    opacity = GetOpacityTransferFunction("MarschnerLobb")
    opacity.Points = [0.0, 0.0, 0.5, 0.0, 0.4, 0.0, 0.5, 0.0, 0.6, 0.5, 0.5, 0.0,
                      1.0, 0.5, 0.5, 0.0]
    display.ScalarOpacityUnitDistance = UNIT_DISTANCE
    # The camera after the first render, which resets it. Oblique to the pieces' boundary
    # planes, so that most rays cross a boundary.
    Render(view)
    view.CameraParallelProjection = 1
    view.CameraPosition = [3.0, -2.2, 1.6]
    view.CameraFocalPoint = [0.0, 0.0, 0.0]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.CameraParallelScale = 1.6

    images = {}
    for method in METHODS:
        display.HovrIntegration = method
        path = capture(view, os.path.join(args.output_dir, file_name(method)), IMAGE_SIZE)
        images[method] = path
        check(read_rgb(path)[0].max() > 100, "%s draws the volume" % method)

    # The projections: on several ranks the mapper writes each pixel's depth from its extremum
    # and the representation asks for no ordered compositing, so that IceT's z-buffer
    # compositing keeps the pixel of the rank that holds the extremum; no warning (it warns
    # only when another representation makes the view composite in order). pvbatch holds rank
    # 0's representation in this process: the composite representation's active one is hovr's.
    representation = display.GetClientSideObject().GetActiveRepresentation()
    warnings = []

    def on_warning(_caller, _event, message):
        warnings.append(message)

    on_warning.CallDataType = "string0"
    representation.AddObserver("WarningEvent", on_warning)
    ramp_opacity = list(opacity.Points)
    opacity.Points = [0.0, 0.3, 0.5, 0.0, 1.0, 0.8, 0.5, 0.0]  # every extremum shows
    for method in PROJECTIONS:
        display.HovrIntegration = method
        path = capture(view, os.path.join(args.output_dir, file_name(method)), IMAGE_SIZE)
        images[method] = path
        check(read_rgb(path)[0].max() > 100, "%s draws the volume" % method)
    if not args.server:  # a pvserver's ranks warn in their own log
        check(not warnings, "the projections on %d rank(s) draw without a warning (%s)"
              % (ranks, warnings))
        # Beside a representation that needs ordered compositing (ParaView's own volume), the
        # pieces are composited front to back: on several ranks Analytic MIP says so, once.
        other = globals()["MarschnerLobb"](Dimensions=[9, 9, 9])
        other_display = Show(other, view)
        other_display.SetRepresentationType("Volume")
        display.HovrIntegration = "Analytic MIP"
        Render(view)
        Render(view)
        beside = [w for w in warnings if "needs ordered compositing" in w]
        check(len(beside) == (1 if ranks > 1 else 0) and len(warnings) == len(beside),
              "Analytic MIP beside ParaView's volume on %d rank(s): %d warning(s) about "
              "compositing in order, %d in all" % (ranks, len(beside), len(warnings)))
        Hide(other, view)
    opacity.Points = ramp_opacity

    if args.compare_dir:
        for method in METHODS:
            reference = os.path.join(args.compare_dir, file_name(method))
            difference = image_difference(images[method], reference)
            if method == "Stock":
                check(difference < TOLERANCE, "%s on %d ranks matches one rank (RMS %.2f < "
                      "%.2f)" % (method, ranks, difference, TOLERANCE))
                continue
            largest = interior_difference(images[method], reference)
            check(difference < RAMP_TOLERANCE and largest <= 3, "%s on %d ranks matches one "
                  "rank (RMS %.2f < %.2f, largest difference inside the silhouette %d <= 3)"
                  % (method, ranks, difference, RAMP_TOLERANCE, largest))
        for method in PROJECTIONS:
            reference = os.path.join(args.compare_dir, file_name(method))
            difference = image_difference(images[method], reference)
            largest = numpy.abs(read_rgb(images[method])[0] - read_rgb(reference)[0]).max()
            check(difference < RAMP_TOLERANCE and largest <= 3, "%s on %d ranks matches one "
                  "rank (RMS %.2f < %.2f, largest difference %d <= 3)"
                  % (method, ranks, difference, RAMP_TOLERANCE, largest))
        # What a wrongly composited piece would do, on a smaller scale: the whole volume's
        # opacity raised by a quarter (a piece drawn twice doubles it).
        display.HovrIntegration = METHODS[-1]
        display.ScalarOpacityUnitDistance = 0.8 * UNIT_DISTANCE
        path = capture(view, os.path.join(args.output_dir, "denser.png"), IMAGE_SIZE)
        denser = image_difference(path, images[METHODS[-1]])
        check(denser > 2.0 * TOLERANCE, "the tolerance is well below the change of a quarter "
              "more opacity (RMS %.2f)" % denser)

    ramp_scene(args, ranks, view, source, check)
    if args.server:
        Disconnect()  # lets the pvserver exit
    return checker.failures


def ramp_scene(args, ranks, view, source, check):
    """Data whose pieces cover different parts of the scalar range (Marschner-Lobb plus a ramp
    along x, odd point counts) and narrow opacity peaks: a rank that sized its tables or
    classification over its own piece's range, or anchored its sampling grid to its own box,
    would draw its piece differently from one rank drawing the whole. The representation must
    give every rank the whole range and bounds, and every hovr method must then match the
    one-rank image within RAMP_TOLERANCE (Stock, VTK's own mapper, is reported only)."""
    from paraview.simple import Calculator
    Hide(source, view)
    field = globals()["MarschnerLobb"](Dimensions=RAMP_DIMENSIONS)
    ramp = Calculator(Input=field, ResultArrayName="Ramp",
                      Function="MarschnerLobb + 1.5*coordsX")
    ramp.UpdatePipeline()
    display = Show(ramp, view)
    display.SetRepresentationType("hovr Volume")
    ColorBy(display, ("POINTS", "Ramp"))
    display.IsosurfaceValues = [0.5]
    color = GetColorTransferFunction("Ramp")
    color.AutomaticRescaleRangeMode = "Never"
    color.ColorSpace = "RGB"
    color.RGBPoints = [-1.5, 0.1, 0.3, 0.9, 0.5, 1.0, 0.55, 0.15, 2.5, 1.0, 1.0, 0.9]
    opacity = GetOpacityTransferFunction("Ramp")
    points = [-1.5, 0.0, 0.5, 0.0]
    for peak, height in ((-0.5, 0.8), (0.5, 0.9), (1.5, 0.9)):
        points += [peak - 0.02, 0.0, 0.5, 0.0, peak, height, 0.5, 0.0,
                   peak + 0.02, 0.0, 0.5, 0.0]
    opacity.Points = points + [2.5, 0.0, 0.5, 0.0]
    display.ScalarOpacityUnitDistance = UNIT_DISTANCE
    Render(view)

    whole = ramp.PointData["Ramp"].GetRange()
    if not args.server:
        # The information property asks rank 0's representation (pvbatch's scripts run there;
        # a pvserver's client would ask its own twin, which holds no data).
        hovr = display.SMProxy.GetProperty("HovrWholeScalarRange").GetParent()
        hovr.UpdatePropertyInformation()
        spanned = [hovr.GetProperty("HovrWholeScalarRange").GetElement(k) for k in (0, 1)]
        local = ramp.GetClientSideObject().GetOutputDataObject(0).GetPointData().GetArray(
            "Ramp").GetRange()
        check(abs(spanned[0] - whole[0]) < 1e-9 and abs(spanned[1] - whole[1]) < 1e-9,
              "rank 0's representation spans the whole range %s (%s), not its piece's %s"
              % (whole, spanned, local))
        if ranks > 1:
            check(local[0] > whole[0] + 0.1 or local[1] < whole[1] - 0.1,
                  "rank 0's piece covers a part of the range (%s of %s)" % (local, whole))

    # Unshaded, then shaded (the methods that shade: their gradients at a piece's boundary
    # come from the piece's own points).
    runs = [(method, "ramp-" + file_name(method)) for method in RAMP_METHODS]
    runs += [(method, "ramp-shaded-" + file_name(method)) for method in SHADED_METHODS]
    images = {}
    sizes = {}
    for method, name in runs:
        display.Shade = 1 if name.startswith("ramp-shaded-") else 0
        display.HovrIntegration = method
        images[name] = capture(view, os.path.join(args.output_dir, name), IMAGE_SIZE)
        if "pre-integration" in method and not args.server:
            # Rank 0's table (pvbatch's scripts run there).
            hovr = display.SMProxy.GetProperty("HovrTableSizes").GetParent()
            hovr.UpdatePropertyInformation()
            sizes[name] = [hovr.GetProperty("HovrTableSizes").GetElement(k) for k in range(3)]
        # (Shading darkens: object order's headlight leaves its brightest pixel near 94.)
        bright = 50 if name.startswith("ramp-shaded-") else 100
        check(read_rgb(images[name])[0].max() > bright, "%s: %s draws the volume" % (name, method))
    display.Shade = 0
    if not args.server:
        with open(os.path.join(args.output_dir, "table-sizes.json"), "w") as f:
            json.dump(sizes, f)
    if args.compare_dir and not args.server:
        # Every rank measures the sizes on the whole volume: rank 0 draws one rank's table
        # (measured on its own piece, it would not).
        with open(os.path.join(args.compare_dir, "table-sizes.json")) as f:
            single = json.load(f)
        for name, drawn in sorted(sizes.items()):
            check(drawn == single.get(name), "%s: the table on %d ranks is one rank's (%s, %s)"
                  % (name, ranks, drawn, single.get(name)))
    if args.compare_dir:
        for method, name in runs:
            difference = image_difference(images[name], os.path.join(args.compare_dir, name))
            if method == "Stock" or name in STOCK_DRAWN:
                largest = interior_difference(images[name], os.path.join(args.compare_dir, name))
                print("%s: %s on %d ranks differs from one rank by RMS %.2f, %d inside the "
                      "silhouette (VTK's own sampling and tables, not checked)"
                      % (name, method, ranks, difference, largest))
                continue
            check(difference < RAMP_TOLERANCE, "%s: %s on %d ranks matches one rank (RMS %.2f "
                  "< %.2f)" % (name, method, ranks, difference, RAMP_TOLERANCE))
            # Each piece with its ghost points: every segment and slab drawn whole, by the piece
            # where it starts (object order: where its sample lies; the adaptive methods' walks
            # joined on the slices every walk samples), so only the 8-bit compositing differs.
            largest = interior_difference(images[name], os.path.join(args.compare_dir, name))
            check(largest <= 3, "%s: %s on %d ranks differs by at most 3/255 inside the "
                  "silhouette (%d)" % (name, method, ranks, largest))

if __name__ == "__main__":
    run(main)
