"""``hovr bench`` latency configurations: how long the render after each kind of change takes,
beside the render after a camera move and beside VTK's stock mapper after the same change,
and how long until the refined frame of the methods that answer first and refine after.

A latency configuration is a JSON object with ``"kind": "latency"``::

    {
      "kind": "latency",
      "size": [512, 512],
      "changes": 10,                 # changes of each kind; their median and largest time
      "methods": ["stock", "preint1", "preint2", "adaptive-ray", "iso-analytic"],
      "step": 1,                     # voxels
      "reference_pixels": 0.02,      # the seeded fraction of pixels the reference integrates
      "datasets": [{"name": "ml128", "input": "marschner-lobb:128",
                    "tf": "../transfer-functions/marschner-lobb-spikes.json",
                    "tf_to_data_range": true, "opacity_unit_distance": 0.05}]
    }

Each method is drawn in a window of its own, as an application shows one volume, with
background refinement on for the methods that have it (pre-integration: the interactive
use; batch use waits for every measured table). For every dataset and method, in order:

- ``switch``: the first frame of a new mapper (shaders, uploads, tables), as when a user
  picks the method;
- ``camera``: a frame after a camera move (an azimuth of 2 degrees), ``changes`` times;
- ``opacity``: a frame after an opacity edit (a node of the opacity function moves up and
  down), ``changes`` times, one after the other as a drag does; then the wait for the refined
  frame;
- ``colour``: the same with a colour node;
- ``step``: a frame after the sample distance changes (between 1 and 1.125 times ``step``);
- ``data``: a frame after a new time step (``marschner-lobb`` inputs: the field's alpha
  moves by 0.01 a step; other inputs: the volume scaled by 1 + 0.01 t);
- the adaptive methods draw through a vtkAdaptiveSamplingOracle kept in the pipeline, as an
  application does, with RefineInBackground on: an opacity edit or a new time step is drawn at
  once with the last distances, and the new ones are computed in the background (the refined
  frame waits for them);
- for ``opacity``, the error of the first frame after the last edit, of the first refined
  frame (a pre-integration mapper's provisional table: its last measured sizes built for the
  edit) and of the last refined one (RMSE of premultiplied RGBA against the reference on the
  sampled pixels); for every change ``first_refined_ms`` and ``refined_ms``, the time from
  the last change until the first and the last refined frames are drawn.

Each row holds the median and largest time, stock's median for the same change (VTK's own
mapper in the dataset's blend mode: ``stock``, ``iso-stock``, ``mip-stock``), the method's own
camera median, and ``bound_ratio``: the median over 1.5 times the larger of
those two (at most 1 is the target).
"""

import math
import statistics
import time

from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow, vtkVolume
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401

from . import hovrRenderingOpenGL as gl
from . import methods as hm
from .io import HovrError

LATENCY_FIELDS = ["dataset", "method", "change", "median_ms", "max_ms", "stock_ms",
                  "camera_ms", "bound_ratio", "first_refined_ms", "refined_shown_ms",
                  "refined_ms", "rmse_first",
                  "rmse_first_refined", "rmse_refined",
                  "table_size", "refinements"]

CHANGES = ("switch", "camera", "opacity", "colour", "step", "data")


def time_steps(spec, scene, count):
    """``count`` time steps of the dataset's volume (the first is the scene's own)."""
    from . import hovrFiltersSources as sources
    steps = [scene.image]
    source = spec["input"]
    for t in range(1, count):
        if source.startswith("marschner-lobb"):
            generator = sources.vtkMarschnerLobbSource()
            generator.SetDimensions(scene.image.GetDimensions())
            generator.SetOutputScalarType(scene.image.GetScalarType())
            generator.SetAlpha(generator.GetAlpha() + 0.01 * t)
            generator.Update()
            image = vtkImageData()
            image.ShallowCopy(generator.GetOutput())
        else:
            from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
            image = vtkImageData()
            image.CopyStructure(scene.image)
            values = vtk_to_numpy(scene.image.GetPointData().GetScalars())
            scaled = (values * (1.0 + 0.01 * t)).astype(values.dtype)
            array = numpy_to_vtk(scaled, deep=True)
            array.SetName(scene.image.GetPointData().GetScalars().GetName())
            image.GetPointData().SetScalars(array)
        steps.append(image)
    return steps


class View:
    """One window drawing one method's mapper, timed frame by frame."""

    def __init__(self, method, scene, step):
        self.method = method
        self.scene = scene
        self.window = vtkRenderWindow()
        self.window.SetOffScreenRendering(1)
        self.window.SetMultiSamples(0)
        self.window.SetAlphaBitPlanes(1)
        self.window.SetSize(*scene.size)
        self.renderer = vtkRenderer()
        self.renderer.SetBackgroundAlpha(0.0)
        self.window.AddRenderer(self.renderer)
        self.renderer.GetActiveCamera().DeepCopy(scene.camera)
        self.capture = gl.vtkFloatRGBARenderCapture()
        self.window.Render()
        self.capture.Attach(self.window)
        self.mapper = method.make_mapper()
        method.check_context(self.window, scene)
        method.configure(self.mapper, scene)
        if hasattr(self.mapper, "SetRefineInBackground") and self.mapper.GetTableSize() == 0:
            self.mapper.SetRefineInBackground(True)
        self.last_drawn_ms = None
        self.oracle = _oracle_filter(method, scene)
        if self.oracle is not None:
            self.oracle.SetRefineInBackground(True)
            self.mapper.SetInputConnection(self.oracle.GetOutputPort())
        self.set_input(scene.image)
        self.mapper.SetSampleDistance(scene.step_length(step))
        self.volume = vtkVolume()
        self.volume.SetMapper(self.mapper)
        self.volume.SetProperty(scene.prop)
        self.renderer.AddVolume(self.volume)
        self.renderer.ResetCameraClippingRange(scene.image.GetBounds())

    def frame(self):
        """Render once; the wall time in ms."""
        start = time.perf_counter()
        self.window.Render()
        self.window.WaitForCompletion()
        self.last_frame_ms = 1000.0 * (time.perf_counter() - start)
        return self.last_frame_ms

    def set_input(self, image):
        """The volume drawn (through the oracle, for the adaptive methods)."""
        if self.oracle is not None:
            self.oracle.SetInputData(image)
        else:
            self.mapper.SetInputData(image)

    def refining(self):
        return ((hasattr(self.mapper, "GetRefining") and self.mapper.GetRefining()) or
                (self.oracle is not None and self.oracle.GetRefining()))

    def ready(self):
        """Whether a refined table (provisional or measured) or oracle waits for a frame."""
        return ((hasattr(self.mapper, "GetRefinementReady") and
                 self.mapper.GetRefinementReady()) or
                (self.oracle is not None and self.oracle.GetRefining() and
                 (self.oracle.CheckRefinement() or self.oracle.GetRefinementReady())))

    def refine(self, since, capture=False):
        """Draw each refined frame as it becomes ready until nothing refines: (ms from
        ``since`` (perf_counter seconds) until the first refined frame is drawn, ms until the
        last, the first refined frame's image when ``capture``), or Nones when nothing was
        refining. The first is a pre-integration mapper's provisional table (its last measured
        sizes built for the change) when it has one, else the measured table or oracle."""
        if not self.refining():
            return None, None, None
        first = first_image = None
        self.last_drawn_ms = None
        while self.refining():
            if not self.ready():
                time.sleep(0.002)
                continue
            self.frame()
            self.last_drawn_ms = 1000.0 * (time.perf_counter() - since)
            if first is None:
                first = self.last_drawn_ms
                first_image = self.image() if capture else None
        return first, 1000.0 * (time.perf_counter() - since), first_image

    def image(self):
        image = vtkImageData()
        self.capture.Capture(image)
        return image

    def close(self):
        self.renderer.RemoveAllViewProps()
        self.window.Finalize()


def _edit_opacity(prop, k):
    function = prop.GetScalarOpacity()
    node = [0.0] * 4
    index = function.GetSize() // 2
    function.GetNodeValue(index, node)
    node[1] = min(1.0, max(0.0, node[1] * (1.1 if k % 2 == 0 else 1 / 1.1) + 1e-3))
    function.SetNodeValue(index, node)


def _edit_colour(prop, k):
    function = prop.GetRGBTransferFunction()
    node = [0.0] * 6
    index = function.GetSize() // 2
    function.GetNodeValue(index, node)
    for c in (1, 2, 3):
        node[c] = min(1.0, max(0.0, node[c] + (0.05 if k % 2 == 0 else -0.05)))
    function.SetNodeValue(index, node)


def _oracle_filter(method, scene):
    """For the adaptive methods that read an oracle array, the filter that computes it in the
    view's pipeline (the array the method is configured to read); None for the others."""
    from .registry import AdaptiveMethod
    if not isinstance(method, AdaptiveMethod) or method.oracle_array(scene) is None:
        return None
    from .bench import make_oracle, oracle_name
    values = method.settings(scene)
    return make_oracle(scene.image, scene.prop.GetScalarOpacity(), values["oracle"],
                       values["epsilon"], oracle_name(values["oracle"], values["epsilon"]))


def measure(method, scene, step, steps, changes, reference=None, log=print):
    """The latency rows of one method (a dict per change), and its images after the last
    opacity edit: (rows, first image, refined image)."""
    rows = {}
    start = time.perf_counter()
    view = View(method, scene, step)
    try:
        switch = view.frame()
        view.refine(start)
        rows["switch"] = [switch]
        camera = []
        for k in range(changes):
            view.renderer.GetActiveCamera().Azimuth(2.0 if k % 2 == 0 else -2.0)
            camera.append(view.frame())
        rows["camera"] = camera
        first = refined = provisional = None
        refine_ms = {}
        for change, apply in (("opacity", lambda k: _edit_opacity(scene.prop, k)),
                              ("colour", lambda k: _edit_colour(scene.prop, k)),
                              ("step", lambda k: view.mapper.SetSampleDistance(
                                  scene.step_length(step * (1.125 if k % 2 == 0 else 1.0)))),
                              ("data", lambda k: view.set_input(steps[(k + 1) % len(steps)]))):
            times = []
            for k in range(changes):
                last = time.perf_counter()
                apply(k)
                times.append(view.frame() + 1000.0 * (time.perf_counter() - last) -
                             view.last_frame_ms)
            rows[change] = times
            if change == "opacity":
                first = view.image()
            first_ms, refine_ms[change], early = view.refine(last, capture=change == "opacity")
            if first_ms is None and refine_ms[change] is not None:
                # The refinement ended without asking for a frame: the frame after the change
                # drew the provisional table, which the measurement confirmed.
                first_ms = times[-1]
            refine_ms[change + "-first"] = first_ms
            # When the refined image went on screen: the last frame drawn before the
            # refinement ended (a measurement that confirms the table drawn adds none).
            if refine_ms[change] is not None:
                refine_ms[change + "-shown"] = (view.last_drawn_ms if view.last_drawn_ms
                                                is not None else times[-1])
            if change == "opacity":
                refined = view.image()
                provisional = early if early is not None else refined
            # Back to the starting state for the next kind of change.
            if change == "step":
                view.mapper.SetSampleDistance(scene.step_length(step))
            if change == "data":
                view.set_input(scene.image)
            view.frame()
            view.refine(time.perf_counter())
        statistics_row = method.statistics(view.mapper)
        return rows, refine_ms, first, (provisional, refined), statistics_row
    finally:
        view.close()


def _snapshot(prop):
    """Copies of the property's opacity and colour functions, to restore it after a method."""
    from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
    from vtkmodules.vtkRenderingCore import vtkColorTransferFunction
    opacity = vtkPiecewiseFunction()
    opacity.DeepCopy(prop.GetScalarOpacity())
    colour = vtkColorTransferFunction()
    colour.DeepCopy(prop.GetRGBTransferFunction())
    return opacity, colour


def _restore(prop, snapshot):
    prop.GetScalarOpacity().DeepCopy(snapshot[0])
    prop.GetRGBTransferFunction().DeepCopy(snapshot[1])


def run(config, base, output, log=print):
    """Run a latency configuration; returns (rows, summary text)."""
    import os
    from .bench import _reference, _reference_key, _scene_for, write_csv
    size = tuple(config.get("size", (512, 512)))
    changes = int(config.get("changes", 10))
    step = float(config.get("step", 1.0))
    fraction = config.get("reference_pixels")
    rows = []
    for spec in config["datasets"]:
        name = spec.get("name") or os.path.basename(spec["input"])
        scene, _, prop_desc = _scene_for(spec, base, size)
        steps = time_steps(spec, scene, 2)
        original = _snapshot(scene.prop)
        # The reference after the opacity edits (the same edits for every method).
        for k in range(changes):
            _edit_opacity(scene.prop, k)
        edited = hm.Scene(scene.image, scene.prop, scene.camera, size, scene.blend)
        reference = None
        if spec.get("blend", "composite") == "composite":
            key = _reference_key(spec, scene.image, prop_desc + ["latency-edits", changes,
                                                                  fraction], scene.camera, size)
            reference = _reference(hm.Renderer(), edited, name + "-edited", output, key, log,
                                   settings={"pixel_fraction": fraction} if fraction else None)
        _restore(scene.prop, original)
        by_method = {}
        for method_name in spec.get("methods", config["methods"]):
            method = hm.get_method(method_name)
            if method.kind != "gpu" or (method.blend or "composite") != scene.blend:
                continue
            if method.parallel_only and not scene.camera.GetParallelProjection():
                log("%s %s: skipped (parallel projection only)" % (name, method_name))
                continue
            times, refine_ms, first, refined, stats = measure(method, scene, step, steps,
                                                              changes, log=log)
            _restore(scene.prop, original)
            by_method[method_name] = times
            for change in CHANGES:
                row = {"dataset": name, "method": method_name, "change": change,
                       "median_ms": statistics.median(times[change]),
                       "max_ms": max(times[change]),
                       "refined_ms": refine_ms.get(change),
                       "first_refined_ms": refine_ms.get(change + "-first"),
                       "refined_shown_ms": refine_ms.get(change + "-shown"),
                       "table_size": stats.get("table_size")}
                if change == "opacity" and reference is not None:
                    row["rmse_first"] = hm.compare(first, reference)[0]["rmse"]
                    row["rmse_first_refined"] = hm.compare(refined[0], reference)[0]["rmse"]
                    row["rmse_refined"] = hm.compare(refined[1], reference)[0]["rmse"]
                rows.append(row)
                log("%-8s %-22s %-8s median %8.1f ms  max %8.1f ms%s%s" % (
                    name, method_name, change, row["median_ms"], row["max_ms"],
                    "  refined after %.0f ms (first %.0f ms)" % (row["refined_ms"],
                                                                 row["first_refined_ms"])
                    if row["refined_ms"] is not None else "",
                    "  rmse first %.5f first refined %.5f refined %.5f" % (
                        row["rmse_first"], row["rmse_first_refined"], row["rmse_refined"])
                    if "rmse_first" in row else ""))
        # VTK's own mapper in the dataset's blend mode: stock, iso-stock, mip-stock, ...
        stock = by_method.get("stock" if scene.blend == "composite" else scene.blend + "-stock")
        for row in rows:
            if row["dataset"] != name:
                continue
            own = by_method[row["method"]]
            row["camera_ms"] = statistics.median(own["camera"])
            if stock is not None:
                row["stock_ms"] = statistics.median(stock[row["change"]])
                bound = 1.5 * max(row["stock_ms"], row["camera_ms"])
                row["bound_ratio"] = row["median_ms"] / bound
    write_csv_rows(rows, os.path.join(output, "latency.csv"))
    summary = format_summary(rows)
    with open(os.path.join(output, "summary.txt"), "w", encoding="utf-8") as stream:
        stream.write(summary)
    return rows, summary


def write_csv_rows(rows, path):
    import csv
    with open(path, "w", newline="", encoding="utf-8") as stream:
        writer = csv.DictWriter(stream, fieldnames=LATENCY_FIELDS, extrasaction="ignore")
        writer.writeheader()
        for row in rows:
            writer.writerow(row)


def format_summary(rows):
    """One line per dataset, method and change: the median, stock's, the method's camera
    move, the ratio to the target bound, and the refinement."""
    lines = ["%-8s %-22s %-8s %9s %9s %9s %7s %11s %10s %10s" % (
        "dataset", "method", "change", "ms", "stock ms", "camera", "bound", "1st refined",
        "shown", "refined")]
    for row in rows:
        def value(key, form):
            return form % row[key] if row.get(key) is not None else "-"
        lines.append("%-8s %-22s %-8s %9s %9s %9s %7s %11s %10s %10s" % (
            row["dataset"], row["method"], row["change"], value("median_ms", "%.0f"),
            value("stock_ms", "%.0f"), value("camera_ms", "%.0f"), value("bound_ratio", "%.2f"),
            value("first_refined_ms", "%.0f"), value("refined_shown_ms", "%.0f"),
            value("refined_ms", "%.0f")))
    return "\n".join(lines) + "\n"
