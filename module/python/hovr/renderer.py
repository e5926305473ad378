"""What is rendered and how: the Scene, the RenderResult, and the Renderer with its offscreen
float window, its timing and its image capture.

A method (hovr.registry) turns a :class:`Scene` (volume, transfer functions, camera, image
size) and a step into a float RGBA image plus its cost. Methods drawn in the window share one
offscreen window per :class:`Renderer` and draw into a float colour buffer
(vtkFloatRGBARenderCapture), so their images are exact enough to measure errors of 1e-4; the
others compute their image with an image algorithm off-screen. The Renderer asks each method
through its hooks and treats every method alike.
"""

import math
import statistics
import time

from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkRenderingCore import vtkLight, vtkRenderer, vtkRenderWindow, vtkVolume
# The OpenGL factories must be loaded for the window and mapper overrides.
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401

from . import hovrRenderingCore as core
from . import hovrRenderingOpenGL as gl
from .io import HovrError, check_volume
from .registry import BLEND_ARRAYS, BLEND_MODES, get_method


# The most samples a ray may take across the volume's diagonal: a GPU ray caster advances its
# position in float texture coordinates, whose rounding (6e-8 of the volume) must stay far
# below the step.
MAX_SAMPLES_PER_RAY = 100000


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
        # How shaded composite frames are lit and interpolated (property Shade on): the
        # gradient interpolation of pre-integration ("constant", "linear" or "nonlinear"),
        # Gooch shading, and the reference's specular term ("lobe", VTK's, or "cone").
        # "normals" names a point array to take as the normals instead of the gradient;
        # "lights" lists directional lights (towards-light direction in world coordinates,
        # diffuse colour, specular colour, headlight flag) instead of VTK's white headlight.
        # "cone" is the slope of the cone that stands for the lobe: "paper" or "matched".
        self.shading = {"interpolation": "nonlinear", "gooch": False, "specular": "lobe",
                        "normals": None, "lights": None, "cone": "paper"}
        # Adaptive sampling: the top pyramid level l_max, the oracle's feature threshold
        # epsilon and its mode (a key of ORACLE_MODES); oracle arrays computed for the scene,
        # by (mode, epsilon).
        self.adaptive = {"lmax": 3, "epsilon": 0.002, "oracle": "range"}
        self.oracles = {}
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


class Renderer:
    """Renders scenes with any method; methods drawn in the window share one offscreen float
    window."""

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
        """Render ``scene`` with ``method`` (a name or Method) at ``step`` (voxel units), the
        way the method renders (Method.render): in the window or off-screen.

        One warm-up frame (shader compilation, uploads, tables) is followed by ``repeat``
        timed frames; the image is the last frame's.
        """
        method = get_method(method) if isinstance(method, str) else method
        return method.render(self, scene, step, repeat)

    def render_offline(self, method, scene, step, repeat=0):
        """Render ``scene`` with the image algorithm of ``method`` (Method.make_algorithm):
        one untimed update followed by ``repeat`` timed ones; the image is the last one's."""
        scene.step_length(step)  # validates the step
        method.check_scene(scene)
        method.set_threads(None, method.threads)
        algorithm = method.make_algorithm(scene)
        method.configure(algorithm, scene)
        times = []
        for _ in range(max(repeat, 0) + 1):
            algorithm.Modified()
            errors = _Errors(algorithm)
            start = time.perf_counter()
            algorithm.Update()
            times.append(1000.0 * (time.perf_counter() - start))
            errors.close()
        image = vtkImageData()
        image.DeepCopy(algorithm.GetOutput())
        return RenderResult(image, times[1:] if repeat > 0 else [],
                            method.algorithm_samples(algorithm), method.statistics(algorithm))

    def render_interleaved(self, runs, scene, repeat=0):
        """Render ``scene`` with several (method, step) runs drawn in the window, timing them
        in interleaved rounds (one frame of each run per round) so that a change of machine
        load affects all of them alike and their time ratios stay meaningful. Returns one
        RenderResult per run.
        """
        runs = [(get_method(m) if isinstance(m, str) else m, step) for m, step in runs]
        for method, _ in runs:
            if method.blend is not None and method.blend != scene.blend:
                raise HovrError("method %s renders %s, the scene is set up for %s" % (
                    method.name, method.blend, scene.blend))
            method.check_scene(scene)
        self._ensure_window(scene.size)
        for method, _ in runs:
            method.check_context(self._window, scene)
        renderer = self._renderer
        renderer.RemoveAllViewProps()
        renderer.GetActiveCamera().DeepCopy(scene.camera)
        renderer.RemoveAllLights()  # none: VTK makes its headlight
        for direction, diffuse, specular, headlight in scene.shading.get("lights") or []:
            light = vtkLight()
            if headlight:
                light.SetLightTypeToHeadlight()
            else:
                light.SetLightTypeToSceneLight()
                light.SetPosition(direction)
                light.SetFocalPoint(0.0, 0.0, 0.0)
            light.SetDiffuseColor(diffuse)
            light.SetSpecularColor(specular)
            renderer.AddLight(light)
        volumes, mappers = [], []
        for method, step in runs:
            mapper = method.make_mapper()
            if mapper is None:
                raise HovrError("%s is not a GPU method" % method.name)
            method.configure(mapper, scene)
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
            runs[index][0].set_threads(mappers[index], runs[index][0].threads)
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
                samples = method.count_samples(rays, scene, step) if rays_ok else None
                stats = method.statistics(mappers[index])
                stats.update(method.count_operations(mappers[index], lambda: frame(index)))
                if "sample_ops" in stats:
                    samples = stats["sample_ops"]
                results.append(RenderResult(image, times[index], samples, stats))
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
            import numpy
            from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
            from vtkmodules.vtkCommonCore import vtkDoubleArray
            # Bricked analytic hits are in brick w - 1's grid index: back to the volume's,
            # in double.
            positions = vtk_to_numpy(raw).astype(numpy.float64)
            hit = positions[:, 3] > 0
            if mapper.IsA("vtkAnalyticVolumeMapper") and \
                    mapper.GetMethod() == mapper.ANALYTIC and hit.any():
                bricks = numpy.rint(positions[hit, 3]).astype(int) - 1
                origins = numpy.array([self._brick_origin(mapper, b)
                                       for b in range(int(bricks.max()) + 1)], dtype=float)
                positions[hit, :3] += origins[bricks]
                positions[hit, 3] = 1.0
            values = vtkDoubleArray()
            rays.ComputeDepths(scene.image, numpy_to_vtk(positions, deep=1), values)
        else:
            import numpy
            from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
            rgba = vtk_to_numpy(raw)
            values = numpy_to_vtk(numpy.where(rgba[:, 3] > 0, rgba[:, 0], numpy.nan)
                                  .astype(numpy.float64), deep=1)
        values.SetName(BLEND_ARRAYS[scene.blend])
        image.GetPointData().AddArray(values)

    @staticmethod
    def _brick_origin(mapper, brick):
        origin = [0, 0, 0]
        mapper.GetBrickOrigin(brick, origin)
        return origin

    def close(self):
        if self._window is not None:
            self._window.Finalize()
            self._window = None
