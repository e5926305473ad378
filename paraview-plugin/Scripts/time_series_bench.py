# hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
"""pvbatch: the cost of each time step of an animation, "hovr Volume" beside ParaView's
"Volume".

Writes a time series of generated volumes (the Marschner-Lobb field with its alpha parameter
moving a little at each step; --points a side, float) as .vti files, opens them with ParaView's
reader as one dataset with time steps, and renders every step in turn (the animation scene's
next step, then a render), as an animation does, for the representations compared. Prints the
median time per step of each, its ratio to "Volume", and its ratio to the frame of a camera
move of the same representation (what a frame costs without new data). pvbatch waits for measured tables:
"hovr Volume" measures a step's sizes again only when its data moved enough to matter
(vtkPreIntegrationTableSizing::ReuseForNewData).

    PYTHONPATH=<ParaView's python> pvbatch time_series_bench.py --plugin <hovr.so> \
        [--points 128] [--steps 12] [--size 512]
"""
import argparse
import os
import statistics
import tempfile
import time

from paraview.simple import (ColorBy, Delete, GetAnimationScene, GetColorTransferFunction,
                             GetOpacityTransferFunction, LoadPlugin, Render, Show,
                             UpdatePipeline, XMLImageDataReader, CreateRenderView)
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("--plugin", required=True)
parser.add_argument("--points", type=int, default=128)
parser.add_argument("--steps", type=int, default=12)
parser.add_argument("--size", type=int, default=512)
args = parser.parse_args()
LoadPlugin(args.plugin, ns=globals())

# The series, written with the plugin's generated source (ParaView's own VTK).
folder = tempfile.mkdtemp(prefix="hovr-series-")
paths = []
for t in range(args.steps):
    # alpha moves by 0.002 a step: a slowly changing field, as successive simulation steps.
    source = globals()["MarschnerLobb"](Dimensions=[args.points] * 3, Alpha=0.25 + 0.002 * t)
    source.UpdatePipeline()
    data = source.GetClientSideObject().GetOutputDataObject(0)
    path = os.path.join(folder, "step_%03d.vti" % t)
    writer = vtkXMLImageDataWriter()
    writer.SetInputData(data)
    writer.SetFileName(path)
    writer.Write()
    paths.append(path)

reader = XMLImageDataReader(FileName=paths)
reader.UpdatePipeline()
scene = GetAnimationScene()
scene.UpdateAnimationUsingDataTimeSteps()
results = {}
cameras = {}
for name, settings in (("Volume", {}), ("hovr Volume", {"HovrIntegration": 1}),
                       ("hovr Volume", {"HovrIntegration": 2})):
    label = name if not settings else "%s (%s)" % (name, "first order"
                                                   if settings["HovrIntegration"] == 1
                                                   else "second order")
    view = CreateRenderView(ViewSize=[args.size, args.size])
    display = Show(reader, view)
    ColorBy(display, ("POINTS", "MarschnerLobb"))
    display.SetRepresentationType(name)
    for key, value in settings.items():
        setattr(display, key, value)
    opacity = GetOpacityTransferFunction("MarschnerLobb")
    opacity.Points = [0.0, 0.0, 0.5, 0.0, 0.45, 0.0, 0.5, 0.0, 0.5, 0.6, 0.5, 0.0,
                      0.55, 0.0, 0.5, 0.0, 1.0, 0.0, 0.5, 0.0]
    view.ResetCamera()
    scene.AnimationTime = scene.TimeKeeper.TimestepValues[0]
    Render(view)  # the first step: shaders, uploads, tables
    times = []
    for t in scene.TimeKeeper.TimestepValues[1:]:
        start = time.perf_counter()
        scene.AnimationTime = t
        Render(view)
        times.append(time.perf_counter() - start)
    results[label] = statistics.median(times)
    # The same view turned a little, at the last step: what a frame costs without new data.
    camera = []
    for k in range(5):
        view.GetActiveCamera().Azimuth(2.0 if k % 2 == 0 else -2.0)
        start = time.perf_counter()
        Render(view)
        camera.append(time.perf_counter() - start)
    cameras[label] = statistics.median(camera)
    print("%-34s median %.3f s per step over %d steps, %.3f s per frame of a camera move" % (
        label, results[label], len(times), cameras[label]))
    # The animation scene renders every view at each step: only the one measured may exist.
    Delete(view)
    del view, display
stock = results["Volume"]
for label, seconds in results.items():
    print("%-34s %.2f x Volume per step; %.2f x its own camera move" % (
        label, seconds / stock, seconds / cameras[label]))
