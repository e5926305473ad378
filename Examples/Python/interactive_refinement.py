"""Answer first, refine after, in an interactor's event loop.

A vtkPreIntegrationVolumeMapper with RefineInBackground draws every transfer-function edit at
once, with interim table sizes or, when their rebuild is cheap, the last measured ones, while
a worker thread measures and builds the table of the last edit; the mapper watches the worker
from the interactor's timers (WatchRefinement) and fires TablesRefinedEvent when the measured
table is ready, and the observer below renders again to draw it. A measurement that confirms
the last measured sizes already drawn needs no frame: the refinement ends without an event.

With --method adaptive-ray, a vtkAdaptiveRayVolumeMapper draws through a
vtkAdaptiveSamplingOracle with RefineInBackground: every edit is drawn at once with the last
oracle distances while a worker computes those of the last edit; the timer below calls the
oracle's CheckRefinement, which fires OracleRefinedEvent when they are ready.

The edits here come from a timer, as a user's drag would: 20 of them, 100 ms apart, each
moving an opacity spike's peak. Run it with a display to watch (close the window to quit), or
with --offscreen to print the timings and quit after the refined frame:

    ./hovr python Examples/Python/interactive_refinement.py --offscreen
"""

import argparse
import time

from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
from vtkmodules.vtkRenderingCore import (vtkColorTransferFunction, vtkRenderWindow,
                                         vtkRenderWindowInteractor, vtkRenderer, vtkVolume,
                                         vtkVolumeProperty)
import vtkmodules.vtkInteractionStyle  # noqa: F401
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401

import hovr

parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("--points", type=int, default=128, help="Marschner-Lobb points a side")
parser.add_argument("--order", type=int, choices=(1, 2), default=2,
                    help="pre-integration order (--method preint)")
parser.add_argument("--method", choices=("preint", "adaptive-ray"), default="preint")
parser.add_argument("--edits", type=int, default=20)
parser.add_argument("--offscreen", action="store_true", help="quit after the refined frame")
args = parser.parse_args()

source = hovr.vtkMarschnerLobbSource()
source.SetDimensions(args.points, args.points, args.points)
source.Update()
image = source.GetOutput()
low, high = image.GetScalarRange()
span = high - low

opacity = vtkPiecewiseFunction()
for x, a in ((0.0, 0.0), (0.45, 0.0), (0.5, 0.2), (0.55, 0.0), (0.75, 0.0), (0.8, 0.6),
             (0.85, 0.0), (1.0, 0.0)):
    opacity.AddPoint(low + x * span, a)
color = vtkColorTransferFunction()
color.AddRGBPoint(low, 0.1, 0.3, 1.0)
color.AddRGBPoint(high, 1.0, 0.6, 0.1)
prop = vtkVolumeProperty()
prop.SetScalarOpacity(opacity)
prop.SetColor(color)
prop.SetInterpolationTypeToLinear()

if args.method == "preint":
    mapper = hovr.vtkPreIntegrationVolumeMapper()
    mapper.SetIntegration(args.order)
    mapper.SetInputData(image)
    mapper.SetRefineInBackground(True)
    refiner, refined_event = mapper, mapper.TablesRefinedEvent
else:
    # The oracle in the pipeline, its distances capped at the volume's diagonal (the mapper
    # clamps them to its own largest step).
    oracle = hovr.vtkAdaptiveSamplingOracle()
    oracle.SetInputData(image)
    oracle.SetScalarOpacity(opacity)
    oracle.AutomaticMaximumDistanceOff()
    oracle.SetMaximumDistance(image.GetLength())
    oracle.SetRefineInBackground(True)
    mapper = hovr.vtkAdaptiveRayVolumeMapper()
    mapper.SetInputConnection(oracle.GetOutputPort())
    refiner, refined_event = oracle, oracle.OracleRefinedEvent
mapper.SetSampleDistance(image.GetSpacing()[0])
volume = vtkVolume()
volume.SetMapper(mapper)
volume.SetProperty(prop)

renderer = vtkRenderer()
renderer.AddVolume(volume)
window = vtkRenderWindow()
window.AddRenderer(renderer)
window.SetSize(512, 512)
window.SetOffScreenRendering(1 if args.offscreen else 0)
interactor = vtkRenderWindowInteractor()
interactor.SetRenderWindow(window)
interactor.Initialize()
renderer.ResetCamera()
renderer.GetActiveCamera().Elevation(20)

state = {"edits": 0, "frames": [], "last_edit": None, "refined_after": None}


def render():
    start = time.perf_counter()
    window.Render()
    return time.perf_counter() - start


def on_refined(*_):
    """The measured table waits: draw it."""
    seconds = render()
    if state["last_edit"] is not None and state["edits"] == args.edits:
        state["refined_after"] = time.perf_counter() - state["last_edit"]
        what = "oracle"
        if args.method == "preint":
            table = mapper.GetActiveTable()
            what = "table %dx%dx%d" % (table.GetTableSize(), table.GetChordSize(),
                                       table.GetDeviationSize())
        print("refined frame %.3f s after the last edit (drawn in %.3f s); %s" % (
            state["refined_after"], seconds, what))
        if args.offscreen:
            interactor.TerminateApp()


def on_timer(_obj, _event):
    """One edit of the drag, drawn at once (the timer stays: VTK's X interactor must not
    have a timer destroyed from its own callback)."""
    if args.method != "preint":
        refiner.CheckRefinement()  # the mapper watches its own tables (WatchRefinement)
    if state["edits"] >= args.edits:
        if state["refined_after"] is None and not refiner.GetRefining():
            # No event: the measurement confirmed the provisional table (the last measured
            # sizes) that the last edit's frame drew at once, so no frame is needed.
            state["refined_after"] = time.perf_counter() - state["last_edit"]
            print("refined frame %.3f s after the last edit (the provisional table drawn with "
                  "it, confirmed by the measurement)" % state["refined_after"])
            if args.offscreen:
                interactor.TerminateApp()
        return
    k = state["edits"]
    opacity.AddPoint(low + 0.8 * span, 0.3 + 0.02 * k)
    state["frames"].append(render())
    state["edits"] += 1
    state["last_edit"] = time.perf_counter()
    if state["edits"] == args.edits:
        frames = sorted(state["frames"])
        print("drag: %d edits drawn at once, median %.3f s, longest %.3f s per frame; refining: "
              "%s" % (args.edits, frames[len(frames) // 2], frames[-1], refiner.GetRefining()))


refiner.AddObserver(refined_event, on_refined)
if args.method == "preint":
    mapper.WatchRefinement(interactor)
interactor.AddObserver("TimerEvent", on_timer)
print("first frame %.3f s (interim: %s)" % (render(), refiner.GetRefining()))
refiner.WaitForRefinement()
print("first refined frame %.3f s" % render())
start = time.perf_counter()
renderer.GetActiveCamera().Azimuth(5)
print("camera move %.3f s" % render())
interactor.CreateRepeatingTimer(100)
interactor.Start()
if args.offscreen and state["refined_after"] is None:
    raise SystemExit("no refined frame after the drag")
