"""The rendering methods hovr measures, behind one interface.

A method turns a :class:`Scene` (volume, transfer functions, camera, image size) and a step
into a float RGBA image plus its cost. GPU methods share one offscreen window per
:class:`Renderer` and draw into a float colour buffer (vtkFloatRGBARenderCapture), so their
images are exact enough to measure errors of 1e-4; the CPU reference is
vtkVolumeReferenceIntegrator. Adding a method means adding one entry to ``METHODS``.
"""

import math
import statistics
import time

from vtkmodules.vtkCommonCore import vtkCommand, vtkFloatArray
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow, vtkVolume  # noqa: F401
# The OpenGL factories must be loaded for the window and mapper overrides.
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401
from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper

from . import hovrRenderingCore as core
from . import hovrRenderingOpenGL as gl
from .io import HovrError, check_volume


# The most samples a ray may take across the volume's diagonal: a GPU ray caster advances its
# position in float texture coordinates, whose rounding (6e-8 of the volume) must stay far
# below the step.
MAX_SAMPLES_PER_RAY = 100000

# Blend modes by name, with vtkVolumeMapper's values; the arrays hovr render adds for them.
BLEND_MODES = {"composite": 0, "mip": 1, "minip": 2, "iso": 5}
BLEND_ARRAYS = {"iso": "Depth", "mip": "MaxScalar", "minip": "MinScalar"}
FLOAT_MAX = 3.4028234663852886e38


class Scene:
    """What is rendered: a volume, a volume property (with the isosurface values for ``iso``),
    a camera, an image size and a blend mode (a key of BLEND_MODES). The volume is checked
    (io.check_volume): a HovrError when no method can render it, its warnings in
    ``warnings``."""

    def __init__(self, image, prop, camera, size, blend="composite"):
        self.warnings = check_volume(image)
        self.image = image
        self.prop = prop
        self.camera = camera
        self.size = (int(size[0]), int(size[1]))
        if min(self.size) < 1:
            raise HovrError("the image size must be at least 1x1, got %dx%d" % self.size)
        if blend not in BLEND_MODES:
            raise HovrError("unknown blend mode %r (known: %s)" % (blend, ", ".join(BLEND_MODES)))
        for function, what in ((prop.GetScalarOpacity(), "scalar opacity"),
                               (prop.GetRGBTransferFunction(), "colour")):
            if function.GetSize() == 0:
                raise HovrError("the %s transfer function has no points" % what)
        if blend == "iso" and prop.GetIsoSurfaceValues().GetNumberOfContours() < 1:
            raise HovrError("isosurface rendering needs at least one --isovalue")
        self.blend = blend
        # One camera model for every method: a camera the reference's rays cannot follow
        # (view up along the view, a zero parallel scale, non-finite values) is refused for all.
        rays = core.vtkCameraRayModel()
        rays.SetCamera(camera)
        rays.SetImageSize(*self.size)
        errors = _Errors(rays)
        prepared = rays.Prepare()
        try:
            errors.close()
        except HovrError as error:
            raise HovrError("the camera cannot be used: %s" % error) from None
        if not prepared:
            raise HovrError("the camera cannot be used")

    def step_length(self, step):
        """World length of a step given in units of the smallest voxel spacing; a HovrError
        when it is not positive or would take more than MAX_SAMPLES_PER_RAY samples along the
        volume's diagonal."""
        if not (step > 0 and math.isfinite(step)):
            raise HovrError("the step must be positive and finite, got %g" % step)
        length = step * min(abs(s) for s in self.image.GetSpacing())
        bounds = self.image.GetBounds()
        diagonal = sum((bounds[2 * a + 1] - bounds[2 * a]) ** 2 for a in range(3)) ** 0.5
        samples = diagonal / length if length > 0 else float("inf")
        if not samples <= MAX_SAMPLES_PER_RAY:
            raise HovrError(
                "a step of %g voxel takes %.3g samples along the volume's diagonal; at most %d "
                "are allowed (float ray positions stop advancing on the GPU, and the CPU "
                "methods would run for hours): use a step of at least %.3g" % (
                    step, samples, MAX_SAMPLES_PER_RAY,
                    step * samples / MAX_SAMPLES_PER_RAY))
        return length


class RenderResult:
    """A rendered image and what it cost."""

    def __init__(self, image, times_ms, samples_per_frame=None, extra=None):
        self.image = image
        self.times_ms = list(times_ms)
        self.samples_per_frame = samples_per_frame
        self.extra = dict(extra or {})

    def summary(self, method, step):
        times = self.times_ms or [float("nan")]
        line = {"method": method, "step": step,
                "width": self.image.GetDimensions()[0], "height": self.image.GetDimensions()[1],
                "median_ms": statistics.median(times), "min_ms": min(times),
                "max_ms": max(times)}
        if self.samples_per_frame is not None:
            line["samples_per_frame"] = self.samples_per_frame
        line.update(self.extra)
        return line


class _Errors:
    """Turns VTK error events of some objects into a HovrError after a call."""

    def __init__(self, *objects):
        self.messages = []
        self.tags = [(o, o.AddObserver(vtkCommand.ErrorEvent, self._on_error)) for o in objects]

    def _on_error(self, obj, _event, message=None):
        self.messages.append("%s: %s" % (obj.GetClassName(), str(message).strip().splitlines()[-1]
                                         if message else "error"))

    _on_error.CallDataType = "string0"

    def close(self):
        for obj, tag in self.tags:
            obj.RemoveObserver(tag)
        if self.messages:
            raise HovrError("; ".join(self.messages))


class Method:
    """A rendering method: its name, what it is, and how it renders. ``kind`` "gpu": a
    vtkVolumeMapper drawn in the shared window and read back from it (VTK's CPU mappers too);
    "cpu": an image algorithm computed off-screen (``render_offline``)."""

    kind = "gpu"
    uses_step = True
    parallel_only = False  # renders parallel projections only (an error for perspective)
    description = ""
    blend = "composite"  # the blend mode the method renders; None: any (the reference)

    def __init__(self, name, description):
        self.name = name
        self.description = description

    def make_mapper(self):
        raise NotImplementedError

    def check_scene(self, scene):
        """Raise HovrError when the method cannot draw ``scene`` right. Every method but the
        reference stores the volume in float (GPU textures, the CPU casters' copies)."""
        low, high = scene.image.GetPointData().GetScalars().GetFiniteRange()
        if max(abs(low), abs(high)) > FLOAT_MAX:
            raise HovrError("the scalar range [%g, %g] exceeds float range, in which %s stores "
                            "the volume; rescale the values" % (low, high, self.name))

    def statistics(self, mapper):
        return {}

    def set_threads(self, mapper, threads):
        """Run on ``threads`` threads (0: the default): vtkSMPTools' count."""
        from vtkmodules.vtkCommonCore import vtkSMPTools
        vtkSMPTools.Initialize(threads)


class ThreadedMethod(Method):
    """A method pinned to a number of threads, named ``<method>/<threads>t``."""

    def __init__(self, method, threads):
        super().__init__("%s/%dt" % (method.name, threads), method.description)
        self.method = method
        self.threads = threads
        for attribute in ("kind", "uses_step", "parallel_only", "blend"):
            setattr(self, attribute, getattr(method, attribute))

    def make_mapper(self):
        return self.method.make_mapper()

    def statistics(self, mapper):
        return self.method.statistics(mapper)

    def check_scene(self, scene):
        self.method.check_scene(scene)

    def set_threads(self, mapper, threads):
        self.method.set_threads(mapper, threads)

    def render_offline(self, renderer, scene, step, repeat):
        return self.method.render_offline(renderer, scene, step, repeat)


class StockMethod(Method):
    def make_mapper(self):
        mapper = vtkOpenGLGPUVolumeRayCastMapper()
        mapper.SetAutoAdjustSampleDistances(0)
        return mapper


class PreIntegrationMethod(Method):
    def __init__(self, name, description, integration):
        super().__init__(name, description)
        self.integration = integration

    def make_mapper(self):
        mapper = gl.vtkPreIntegrationVolumeMapper()
        mapper.SetIntegration(self.integration)
        return mapper

    def statistics(self, mapper):
        table = mapper.GetActiveTable()
        sizes = [table.GetTableSize(), table.GetChordSize(), table.GetDeviationSize()]
        sizer = mapper.GetTableSizer()
        return {"table_size": "x".join(str(v) for v in sizes[:3 if self.integration == 2 else 2]),
                "table_sizing_ms": 1000.0 * sizer.GetLastChooseTime()
                if mapper.GetTableSize() == 0 else 0.0,
                "table_build_ms": 1000.0 * mapper.GetLastTableBuildTime(),
                "table_on_gpu": bool(mapper.GetLastTableBuiltOnGPU()),
                "table_builds": table.GetBuildCount(),
                "table_gpu_bytes": mapper.GetTableTextureMemorySize()}


class AnalyticMethod(Method):
    """vtkAnalyticVolumeMapper: analytic (exact) or VTK's stock isosurface and projections."""

    def __init__(self, name, description, blend, analytic):
        super().__init__(name, description)
        self.blend = blend
        self.analytic = analytic

    def make_mapper(self):
        mapper = gl.vtkAnalyticVolumeMapper()
        mapper.SetMethod(mapper.ANALYTIC if self.analytic else mapper.STOCK)
        mapper.SetBlendMode(BLEND_MODES[self.blend])
        mapper.SetAutoAdjustSampleDistances(0)
        return mapper

    def statistics(self, mapper):
        if not self.analytic:
            return {}
        return {"block_gpu_bytes": mapper.GetBlockTextureMemorySize(),
                "corner_gpu_bytes": mapper.GetCornerTextureMemorySize()}


class FixedPointMethod(Method):
    """VTK's CPU ray caster, drawn in the window like the GPU mappers."""

    def make_mapper(self):
        from vtkmodules.vtkRenderingVolume import vtkFixedPointVolumeRayCastMapper
        mapper = vtkFixedPointVolumeRayCastMapper()
        mapper.SetAutoAdjustSampleDistances(0)
        mapper.SetLockSampleDistanceToInputSpacing(0)
        mapper.SetImageSampleDistance(1.0)
        return mapper

    def check_scene(self, scene):
        super().check_scene(scene)
        # Its integer copy of the volume turns NaN into arbitrary values.
        if any("NaN" in warning for warning in scene.warnings):
            raise HovrError("%s cannot render NaN values (VTK's CPU ray caster maps them to "
                            "arbitrary ones); replace them by a value the transfer function "
                            "makes transparent" % self.name)

    def set_threads(self, mapper, threads):
        import os
        mapper.SetNumberOfThreads(threads or os.cpu_count() or 1)


class ReferenceMethod(Method):
    kind = "cpu"
    uses_step = False
    blend = None

    def check_scene(self, scene):
        pass  # integrates in double

    def render_offline(self, renderer, scene, step, repeat):
        return renderer._render_reference(scene, repeat)


class ObjectOrderMethod(Method):
    """vtkObjectOrderVolumeMapper: object-order ray casting on the CPU (parallel projection),
    drawn in the window like VTK's CPU mapper."""

    parallel_only = True

    def __init__(self, name, description, classification):
        super().__init__(name, description)
        self.classification = classification

    def make_mapper(self):
        mapper = gl.vtkObjectOrderVolumeMapper()
        mapper.GetCaster().SetClassification(self.classification)
        return mapper

    def statistics(self, mapper):
        caster = mapper.GetCaster()
        in_view = caster.ComputeNonTransparentCells()

        def occluded(rendered):
            return 1.0 - rendered / in_view if in_view > 0 else 0.0

        rendered = caster.GetNumberOfNonTransparentCells()
        stats = {"samples_per_frame": caster.GetNumberOfSamples(),
                 "nontransparent_cells": rendered,
                 "occluded_ratio": occluded(rendered),
                 "octree_nodes": caster.GetNumberOfNodesVisited(),
                 "cpu_bytes": caster.GetMemorySize(),
                 "instruction_set": {caster.INSTRUCTIONS_SSE2: "sse2",
                                     caster.INSTRUCTIONS_AVX2: "avx2"}.get(
                     caster.GetLastInstructionSet(), "")}
        # The same frame with every ray stopped at its first non-negligible opacity (the
        # smallest threshold, 1e-3): the cells seen first along the rays must be rendered by
        # any method, so this bounds the occluded ratio for the scene's geometry. Restoring
        # the threshold marks the caster modified: the mapper's next frame renders anew.
        threshold = caster.GetOpacityThreshold()
        caster.SetOpacityThreshold(1e-3)
        caster.Update()
        stats["occluded_ratio_first_hit"] = occluded(caster.GetNumberOfNonTransparentCells())
        caster.SetOpacityThreshold(threshold)
        return stats


METHODS = {m.name: m for m in (
    ReferenceMethod("reference", "CPU ground truth: exact cubic per cell, adaptive pieces "
                                 "(vtkVolumeReferenceIntegrator)"),
    StockMethod("stock", "VTK's vtkOpenGLGPUVolumeRayCastMapper, composite, unchanged"),
    PreIntegrationMethod("preint1", "first-order pre-integration, 2D table "
                                    "(vtkPreIntegrationVolumeMapper)",
                         gl.vtkPreIntegrationVolumeMapper.FIRST_ORDER),
    PreIntegrationMethod("preint2", "second-order pre-integration, 3D table over (front, "
                                    "middle, back) (vtkPreIntegrationVolumeMapper)",
                         gl.vtkPreIntegrationVolumeMapper.SECOND_ORDER),
    AnalyticMethod("iso-analytic", "exact first hit of the trilinear isosurface, integer "
                   "traversal, cubic per cell (vtkAnalyticVolumeMapper)", "iso", True),
    AnalyticMethod("mip-analytic", "exact maximum intensity projection of the trilinear field "
                   "(vtkAnalyticVolumeMapper)", "mip", True),
    AnalyticMethod("minip-analytic", "exact minimum intensity projection of the trilinear "
                   "field (vtkAnalyticVolumeMapper)", "minip", True),
    AnalyticMethod("iso-stock", "VTK's sampled isosurface (ISOSURFACE_BLEND) at the step",
                   "iso", False),
    AnalyticMethod("mip-stock", "VTK's sampled maximum intensity projection at the step",
                   "mip", False),
    AnalyticMethod("minip-stock", "VTK's sampled minimum intensity projection at the step",
                   "minip", False),
    ObjectOrderMethod("objectorder", "object-order ray casting on the CPU: min-max octree, "
                      "hidden volume removal, pre-integrated segments, parallel projection "
                      "(vtkObjectOrderVolumeMapper)", core.vtkObjectOrderRayCaster.PREINTEGRATED),
    ObjectOrderMethod("objectorder-point", "object-order ray casting with the paper's "
                      "point-sampled classification (vtkObjectOrderVolumeMapper)",
                      core.vtkObjectOrderRayCaster.POINT_SAMPLED),
    FixedPointMethod("fixedpoint", "VTK's CPU ray caster (vtkFixedPointVolumeRayCastMapper)"),
)}


def get_method(name, threads=None):
    """The method of that name; with ``threads``, pinned to that many threads."""
    if name not in METHODS:
        raise HovrError("unknown method %r (known: %s)" % (name, ", ".join(METHODS)))
    if threads is None:
        return METHODS[name]
    if not (isinstance(threads, int) and threads >= 1):
        raise HovrError("the thread count must be a positive integer, got %r" % (threads,))
    return ThreadedMethod(METHODS[name], threads)


class Renderer:
    """Renders scenes with any method; GPU methods share one offscreen float window."""

    def __init__(self):
        self._window = None
        self._renderer = None
        self._capture = None
        self._size = None

    def _ensure_window(self, size):
        if self._window is not None and self._size == size:
            return
        if self._window is None:
            self._window = vtkRenderWindow()
            self._window.SetOffScreenRendering(1)
            self._window.SetMultiSamples(0)
            self._window.SetAlphaBitPlanes(1)
            self._renderer = vtkRenderer()
            self._renderer.SetBackground(0.0, 0.0, 0.0)
            self._renderer.SetBackgroundAlpha(0.0)
            self._window.AddRenderer(self._renderer)
            self._capture = gl.vtkFloatRGBARenderCapture()
            self._window.SetSize(1, 1)
            self._window.Render()  # a context, to ask for its limits
        # A window beyond the framebuffer limits makes the X server or the driver abort the
        # process rather than report an error: refuse the size first.
        from vtkmodules.vtkRenderingOpenGL2 import vtkTextureObject
        limit = vtkTextureObject.GetMaximumTextureSize(self._window)
        if limit > 0 and max(size) > limit:
            raise HovrError("an image of %dx%d exceeds the largest framebuffer of this OpenGL "
                            "(%d pixels a side)" % (size[0], size[1], limit))
        self._window.SetSize(*size)
        self._size = size
        errors = _Errors(self._capture)
        self._capture.Attach(self._window)
        errors.close()

    def render(self, method, scene, step, repeat=0):
        """Render ``scene`` with ``method`` (a name or Method) at ``step`` (voxel units).

        One warm-up frame (shader compilation, uploads, tables) is followed by ``repeat``
        timed frames; the image is the last frame's.
        """
        method = get_method(method) if isinstance(method, str) else method
        if method.kind == "cpu":
            scene.step_length(step)  # validates the step
            method.check_scene(scene)
            method.set_threads(None, getattr(method, "threads", 0))
            return method.render_offline(self, scene, step, repeat)
        return self.render_interleaved([(method, step)], scene, repeat)[0]

    def render_interleaved(self, runs, scene, repeat=0):
        """Render ``scene`` with several GPU (method, step) runs, timing them in interleaved
        rounds (one frame of each run per round) so that a change of machine load affects all
        of them alike and their time ratios stay meaningful. Returns one RenderResult per run.
        """
        runs = [(get_method(m) if isinstance(m, str) else m, step) for m, step in runs]
        for method, _ in runs:
            if method.blend is not None and method.blend != scene.blend:
                raise HovrError("method %s renders %s, the scene is set up for %s" % (
                    method.name, method.blend, scene.blend))
            method.check_scene(scene)
        self._ensure_window(scene.size)
        renderer = self._renderer
        renderer.RemoveAllViewProps()
        renderer.GetActiveCamera().DeepCopy(scene.camera)
        volumes, mappers = [], []
        for method, step in runs:
            if method.kind != "gpu":
                raise HovrError("%s is not a GPU method" % method.name)
            mapper = method.make_mapper()
            mapper.SetInputData(scene.image)
            mapper.SetSampleDistance(scene.step_length(step))
            volume = vtkVolume()
            volume.SetMapper(mapper)
            volume.SetProperty(scene.prop)
            volume.SetVisibility(0)
            renderer.AddVolume(volume)  # hidden volumes keep their GPU resources
            volumes.append(volume)
            mappers.append(mapper)
        renderer.ResetCameraClippingRange(scene.image.GetBounds())
        errors = _Errors(self._window, *mappers)

        def frame(index):
            for other, volume in enumerate(volumes):
                volume.SetVisibility(other == index)
            runs[index][0].set_threads(mappers[index], getattr(runs[index][0], "threads", 0))
            start = time.perf_counter()
            self._window.Render()
            self._window.WaitForCompletion()
            return 1000.0 * (time.perf_counter() - start)

        results = []
        try:
            for index in range(len(runs)):
                frame(index)  # warm-up: shaders, uploads, tables
            times = [[] for _ in runs]
            for _ in range(max(repeat, 0)):
                for index in range(len(runs)):
                    times[index].append(frame(index))
            rays = core.vtkCameraRayModel()
            rays.SetCamera(scene.camera)
            rays.SetImageSize(*scene.size)
            rays_ok = rays.Prepare()
            for index, (method, step) in enumerate(runs):
                frame(index)
                image = self._capture_image()
                if method.blend in BLEND_ARRAYS:
                    self._add_blend_array(image, scene, rays, mappers[index],
                                          lambda: frame(index))
                if not rays_ok:
                    samples = None
                elif isinstance(method, AnalyticMethod) and method.analytic:
                    samples = rays.CountCellVisits(scene.image)  # cells, not samples
                else:
                    samples = rays.CountFixedStepSamples(scene.image, scene.step_length(step))
                results.append(RenderResult(image, times[index], samples,
                                            method.statistics(mappers[index])))
        finally:
            renderer.RemoveAllViewProps()
            errors.close()
        return results

    def _capture_image(self):
        image = vtkImageData()
        errors = _Errors(self._capture)
        self._capture.Capture(image)
        errors.close()
        return image

    def _add_blend_array(self, image, scene, rays, mapper, draw):
        """Draw once more writing hit positions or extrema and add them as the Depth,
        MaxScalar or MinScalar array of ``image`` (NaN where nothing was hit)."""
        iso = scene.blend == "iso"
        mapper.SetOutputQuantity(mapper.OUTPUT_POSITION if iso else mapper.OUTPUT_SCALAR)
        try:
            draw()
            raw = self._capture_image().GetPointData().GetScalars()
        finally:
            mapper.SetOutputQuantity(mapper.OUTPUT_COLOR)
        if iso:
            values = vtkFloatArray()
            rays.ComputeDepths(scene.image, raw, values)
        else:
            import numpy
            from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
            rgba = vtk_to_numpy(raw)
            values = numpy_to_vtk(numpy.where(rgba[:, 3] > 0, rgba[:, 0], numpy.nan)
                                  .astype(numpy.float32), deep=1)
        values.SetName(BLEND_ARRAYS[scene.blend])
        image.GetPointData().AddArray(values)

    def _render_reference(self, scene, repeat):
        integrator = core.vtkVolumeReferenceIntegrator()
        integrator.SetBlendMode(BLEND_MODES[scene.blend])
        integrator.SetInputData(scene.image)
        integrator.SetVolumeProperty(scene.prop)
        integrator.SetCamera(scene.camera)
        integrator.SetImageSize(*scene.size)
        times = []
        for _ in range(max(repeat, 0) + 1):
            integrator.Modified()
            errors = _Errors(integrator)
            start = time.perf_counter()
            integrator.Update()
            times.append(1000.0 * (time.perf_counter() - start))
            errors.close()
        image = vtkImageData()
        image.DeepCopy(integrator.GetOutput())
        return RenderResult(image, times[1:] if repeat > 0 else [],
                            integrator.GetNumberOfSamples())

    def close(self):
        if self._window is not None:
            self._window.Finalize()
            self._window = None


def compare(image, reference):
    """Error metrics of ``image`` against ``reference`` (vtkRGBAErrorMetrics): a dict and the
    difference image."""
    metrics = core.vtkRGBAErrorMetrics()
    metrics.SetInputData(image)
    metrics.SetReferenceData(reference)
    errors = _Errors(metrics)
    metrics.Update()
    errors.close()
    values = {"rmse": metrics.GetRMSE(), "max_error": metrics.GetMaximumError()}
    for index, channel in enumerate("rgba"):
        values["rmse_" + channel] = metrics.GetChannelRMSE(index)
        values["max_error_" + channel] = metrics.GetChannelMaximumError(index)
    difference = vtkImageData()
    difference.DeepCopy(metrics.GetOutput())
    return values, difference


def compare_blend(image, reference, scene):
    """The measures of an isosurface or projection image against the reference's Depth or
    MaxScalar/MinScalar array (see hovr.bench): a dict."""
    import numpy
    from vtkmodules.util.numpy_support import vtk_to_numpy
    name = BLEND_ARRAYS[scene.blend]
    ours_array = image.GetPointData().GetArray(name)
    theirs_array = reference.GetPointData().GetArray(name)
    if ours_array is None or theirs_array is None:
        raise HovrError("the %s array is missing from an image to compare" % name)
    ours = vtk_to_numpy(ours_array).astype(numpy.float64)
    theirs = vtk_to_numpy(theirs_array).astype(numpy.float64)
    hit, ref_hit = numpy.isfinite(ours), numpy.isfinite(theirs)
    both = hit & ref_hit
    if scene.blend == "iso":
        voxel = min(abs(s) for s in scene.image.GetSpacing())
        error = numpy.abs(ours[both] - theirs[both]) / voxel
        # Grazing pixels: the reference's hit moves by more than the 1e-3 voxel tolerance, or
        # appears or vanishes, when the isovalue moves by 1e-6 of the data range (its
        # DepthSpread), so no float ray caster can be held to the tolerance there.
        spread_array = reference.GetPointData().GetArray("DepthSpread")
        grazing = (vtk_to_numpy(spread_array).astype(numpy.float64) > 1e-3 * voxel
                   if spread_array is not None else numpy.zeros_like(hit))
        well_posed = ~grazing[both]
        return {"hits_both": int(both.sum()),
                "hit_miss_disagreements": int((hit != ref_hit).sum()),
                "missed_hits": int((ref_hit & ~hit).sum()),
                "extra_hits": int((hit & ~ref_hit).sum()),
                "depth_max_error_voxels": float(error.max()) if both.any() else 0.0,
                "depth_p99_error_voxels": float(numpy.percentile(error, 99)) if both.any()
                else 0.0,
                "depth_mean_error_voxels": float(error.mean()) if both.any() else 0.0,
                "depth_outliers": int((error > 1e-3).sum()),
                "grazing_pixels": int(grazing.sum()),
                "disagreements_not_grazing": int(((hit != ref_hit) & ~grazing).sum()),
                "depth_max_error_not_grazing": float(error[well_posed].max())
                if well_posed.any() else 0.0,
                "depth_outliers_not_grazing": int((error[well_posed] > 1e-3).sum())}
    scalars = scene.image.GetPointData().GetScalars()
    low, high = scalars.GetFiniteRange() if hasattr(scalars, "GetFiniteRange") \
        else scalars.GetRange()
    span = (high - low) or 1.0
    error = numpy.abs(ours[both] - theirs[both]) / span
    return {"hits_both": int(both.sum()),
            "hit_miss_disagreements": int((hit != ref_hit).sum()),
            "extremum_max_error": float(error.max()) if both.any() else 0.0,
            "extremum_mean_error": float(error.mean()) if both.any() else 0.0}


def format_blend(row):
    """A short text of compare_blend's measures for log lines ('' for composite rows)."""
    if "depth_max_error_voxels" in row:
        return ("  hits %d, misses %d, extra %d, depth error max %.2e p99 %.2e voxel, "
                "%d over 1e-3; %d grazing, apart from them %d disagreements, max %.2e, "
                "%d over 1e-3" % (row["hits_both"], row["missed_hits"], row["extra_hits"],
                                  row["depth_max_error_voxels"], row["depth_p99_error_voxels"],
                                  row["depth_outliers"], row["grazing_pixels"],
                                  row["disagreements_not_grazing"],
                                  row["depth_max_error_not_grazing"],
                                  row["depth_outliers_not_grazing"]))
    if "extremum_max_error" in row:
        return "  disagreements %d, extremum error max %.2e mean %.2e of the range" % (
            row["hit_miss_disagreements"], row["extremum_max_error"], row["extremum_mean_error"])
    return ""
