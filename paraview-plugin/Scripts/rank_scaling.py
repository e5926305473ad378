# hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
"""pvbatch under MPI: the time of a frame on N ranks, and the part of it that is compositing.

Renders the generated Marschner-Lobb volume (--points a side, float, split between the ranks
by the source) with "hovr Volume" in each of the methods given, at each image size given,
parallel view: --frames camera moves (an azimuth step each), and prints per method and size
the median time of a frame (Render, as a script sees it), the median time of a frame of an
empty view of the same size (the volume hidden: what rendering and compositing the image cost
without the volume), and the time of the first frame after switching to the method from one
that reads no ghost points (the data update: ghost points, oracle, sizing volume, tables), all
in ms. Run it under mpiexec with each rank count:

    mpiexec -n N pvbatch rank_scaling.py --plugin <hovr.so> [--points 128] [--sizes 256 512] \
        [--methods "Stock" "First-order pre-integration"] [--frames 10]
"""
import argparse
import statistics
import time

from paraview.simple import (ColorBy, CreateRenderView, GetColorTransferFunction,
                             GetOpacityTransferFunction, Hide, LoadPlugin, Render, Show)
from vtkmodules.vtkParallelCore import vtkMultiProcessController

parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("--plugin", required=True)
parser.add_argument("--points", type=int, default=128)
parser.add_argument("--sizes", type=int, nargs="+", default=[256, 512])
parser.add_argument("--methods", nargs="+", default=[
    "Stock", "First-order pre-integration", "Second-order pre-integration",
    "Object-order ray casting (CPU)", "Adaptive sampling along rays",
    "Adaptive sampling in 3D (pyramid)"])
parser.add_argument("--frames", type=int, default=10)
args = parser.parse_args()
LoadPlugin(args.plugin, ns=globals())
ranks = vtkMultiProcessController.GetGlobalController().GetNumberOfProcesses()

source = globals()["MarschnerLobb"](Dimensions=[args.points] * 3)
view = CreateRenderView()
view.OrientationAxesVisibility = 0
display = Show(source, view)
display.SetRepresentationType("hovr Volume")
ColorBy(display, ("POINTS", "MarschnerLobb"))
color = GetColorTransferFunction("MarschnerLobb")
color.RGBPoints = [0.0, 0.1, 0.3, 0.9, 0.5, 1.0, 0.55, 0.15, 1.0, 1.0, 1.0, 0.9]
opacity = GetOpacityTransferFunction("MarschnerLobb")
opacity.Points = [0.0, 0.0, 0.5, 0.0, 0.4, 0.0, 0.5, 0.0, 0.6, 0.5, 0.5, 0.0, 1.0, 0.5, 0.5, 0.0]
display.ScalarOpacityUnitDistance = 0.05
view.CameraParallelProjection = 1
Render(view)


def median_frame(frames):
    """Median ms of a render after an azimuth step (after one frame that sets things up)."""
    view.GetActiveCamera().Azimuth(5)
    Render(view)
    times = []
    for _ in range(frames):
        view.GetActiveCamera().Azimuth(5)
        start = time.perf_counter()
        Render(view)
        times.append(1000.0 * (time.perf_counter() - start))
    return statistics.median(times)


def first_frame(method):
    """ms of the first frame after switching to method: the data update (ghost points, oracle,
    sizing volume, tables) and the frame."""
    display.HovrIntegration = "Analytic isosurface"  # reads no ghost points: a new update
    Render(view)
    display.HovrIntegration = method
    start = time.perf_counter()
    Render(view)
    return 1000.0 * (time.perf_counter() - start)


print("ranks %d, Marschner-Lobb %d^3" % (ranks, args.points))
print("%-34s %6s %10s %10s %10s" % ("method", "size", "frame ms", "empty ms", "switch ms"))
for size in args.sizes:
    view.ViewSize = [size, size]
    Hide(source, view)
    empty = median_frame(args.frames)
    Show(source, view)
    for method in args.methods:
        switch = first_frame(method)
        print("%-34s %6d %10.1f %10.1f %10.1f"
              % (method, size, median_frame(args.frames), empty, switch))
