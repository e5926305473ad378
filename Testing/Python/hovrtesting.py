"""Helpers shared by hovr's Python tests (not part of the package)."""

import os
import subprocess
import sys

SKIP = 125  # ctest SKIP_RETURN_CODE

ROOT = os.environ.get("HOVR_ROOT", os.path.abspath(os.path.join(os.path.dirname(__file__),
                                                                 os.pardir, os.pardir)))
PRESETS = os.path.join(ROOT, "presets")


def data_folder():
    return os.environ.get("HOVR_DATA") or os.path.join(ROOT, os.pardir, "shared", "data")


def shared_volume(name):
    """Path of a shared test volume, or None when the shared data is absent."""
    path = os.path.join(data_folder(), name)
    return path if os.path.isfile(path) else None


def offscreen_window(size):
    """An offscreen render window of ``size`` (width, height) made through VTK's factory, and
    its one renderer."""
    from vtkmodules.vtkRenderingCore import vtkRenderWindow, vtkRenderer
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(*size)
    view = vtkRenderer()
    window.AddRenderer(view)
    return window, view


def tf_path(name):
    return os.path.join(PRESETS, "transfer-functions", name + ".json")


def marschner_lobb_scene(size, points=41):
    """The scene most tests share: the Marschner-Lobb volume, the narrow-spike transfer
    function (unit distance 0.05) and the default oblique camera."""
    import hovr
    from hovr import io as hio
    from hovr import methods as hm
    source = hovr.vtkMarschnerLobbSource()
    source.SetDimensions(points, points, points)
    source.Update()
    color, opacity, _ = hio.read_transfer_function(tf_path("marschner-lobb-spikes"))
    return hm.Scene(source.GetOutput(), hio.make_volume_property(color, opacity, 0.05),
                    hio.default_camera(source.GetOutput().GetBounds()), size)


def image_from_array(values, spacing=(1.0, 1.0, 1.0), origin=(0.0, 0.0, 0.0)):
    """vtkImageData whose point scalars are a numpy array indexed [z, y, x]."""
    import numpy
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData
    image = vtkImageData()
    image.SetDimensions(values.shape[2], values.shape[1], values.shape[0])
    image.SetSpacing(spacing)
    image.SetOrigin(origin)
    array = numpy_to_vtk(numpy.ascontiguousarray(values.ravel()), deep=True)
    array.SetName("scalars")
    image.GetPointData().SetScalars(array)
    return image


def cut_pieces(image, axis, count, ghosts=0):
    """``image`` cut into ``count`` pieces along ``axis`` that share their boundary planes of
    points, as ParaView's pieces do: (the piece's own extent, the piece with up to ``ghosts``
    ghost points past each face it shares)."""
    import numpy
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkImagingCore import vtkExtractVOI
    extent = list(image.GetExtent())
    cuts = numpy.linspace(extent[2 * axis], extent[2 * axis + 1], count + 1).round().astype(int)
    out = []
    for k in range(count):
        owned = list(extent)
        owned[2 * axis], owned[2 * axis + 1] = int(cuts[k]), int(cuts[k + 1])
        voi = list(owned)
        voi[2 * axis] = max(owned[2 * axis] - ghosts, extent[2 * axis])
        voi[2 * axis + 1] = min(owned[2 * axis + 1] + ghosts, extent[2 * axis + 1])
        extract = vtkExtractVOI()
        extract.SetInputData(image)
        extract.SetVOI(voi)
        extract.Update()
        piece = vtkImageData()
        piece.ShallowCopy(extract.GetOutput())
        out.append((owned, piece))
    return out


def mpi_ramp_scene(dtype="float64"):
    """The MPI test's second scene: (image, property, camera). Marschner-Lobb plus a ramp along
    x, 65 x 57 x 49 points over [-1, 1]^3 stored as ``dtype`` (so that each piece covers another
    part of the range), three narrow opacity peaks (unit distance 0.2, linear interpolation,
    unshaded), and the test's parallel camera (parallel scale 1.6)."""
    import numpy
    import hovr
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
    from vtkmodules.vtkRenderingCore import (vtkCamera, vtkColorTransferFunction,
                                             vtkVolumeProperty)
    source = hovr.vtkMarschnerLobbSource()
    source.SetDimensions(65, 57, 49)
    source.Update()
    grid = source.GetOutput()
    dims = grid.GetDimensions()
    values = vtk_to_numpy(grid.GetPointData().GetScalars()).reshape(dims[2], dims[1], dims[0])
    x = numpy.linspace(-1.0, 1.0, dims[0])
    image = image_from_array((values + 1.5 * x[None, None, :]).astype(dtype),
                             spacing=grid.GetSpacing(), origin=grid.GetOrigin())
    colour = vtkColorTransferFunction()
    for s, r, g, b in ((-1.5, 0.1, 0.3, 0.9), (0.5, 1.0, 0.55, 0.15), (2.5, 1.0, 1.0, 0.9)):
        colour.AddRGBPoint(s, r, g, b)
    opacity = vtkPiecewiseFunction()
    opacity.AddPoint(-1.5, 0.0)
    for peak, height in ((-0.5, 0.8), (0.5, 0.9), (1.5, 0.9)):
        opacity.AddPoint(peak - 0.02, 0.0)
        opacity.AddPoint(peak, height)
        opacity.AddPoint(peak + 0.02, 0.0)
    opacity.AddPoint(2.5, 0.0)
    prop = vtkVolumeProperty()
    prop.SetColor(colour)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(0.2)
    prop.SetInterpolationTypeToLinear()
    camera = vtkCamera()
    camera.ParallelProjectionOn()
    camera.SetPosition(3.0, -2.2, 1.6)
    camera.SetFocalPoint(0.0, 0.0, 0.0)
    camera.SetViewUp(0.0, 0.0, 1.0)
    camera.SetParallelScale(1.6)
    return image, prop, camera


def translator_pieces(image, count, ghosts=0):
    """``image`` cut into ``count`` blocks by vtkExtentTranslator, as ParaView's ranks get them
    (along several axes): (the block's own extent, the block with ``ghosts`` ghost points)."""
    from vtkmodules.vtkCommonExecutionModel import vtkExtentTranslator
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkImagingCore import vtkExtractVOI
    translator = vtkExtentTranslator()
    translator.SetWholeExtent(image.GetExtent())
    translator.SetNumberOfPieces(count)
    out = []
    for k in range(count):
        translator.SetPiece(k)
        translator.SetGhostLevel(0)
        translator.PieceToExtent()
        owned = list(translator.GetExtent())
        translator.SetGhostLevel(ghosts)
        translator.PieceToExtent()
        extract = vtkExtractVOI()
        extract.SetInputData(image)
        extract.SetVOI(translator.GetExtent())
        extract.Update()
        piece = vtkImageData()
        piece.ShallowCopy(extract.GetOutput())
        out.append((owned, piece))
    return out


def front_to_back(parts, image, camera):
    """The indices of ``parts`` (from cut_pieces or translator_pieces of ``image``), nearest to
    a parallel ``camera`` first: by their own middles along the view (slabs and blocks of a
    grid)."""
    import numpy
    spacing, origin = image.GetSpacing(), image.GetOrigin()
    direction = numpy.array(camera.GetDirectionOfProjection())
    middle = [numpy.array([origin[a] + 0.5 * (o[2 * a] + o[2 * a + 1]) * spacing[a]
                           for a in range(3)]) for o, _ in parts]
    return sorted(range(len(parts)), key=lambda k: numpy.dot(middle[k], direction))


def with_oracle(image, prop, lmax=3):
    """``image`` with the oracle of vtkAdaptiveSamplingOracle for ``prop``'s opacity, its
    distances capped at 2^lmax of the smallest spacing."""
    import hovr
    oracle = hovr.vtkAdaptiveSamplingOracle()
    oracle.SetInputData(image)
    oracle.SetScalarOpacity(prop.GetScalarOpacity())
    oracle.SetAutomaticMaximumDistance(0)
    oracle.SetMaximumDistance(2.0 ** lmax * min(image.GetSpacing()))
    oracle.Update()
    return oracle.GetOutput()


def rgba(image):
    """The RGBA array of a rendered image as an (H, W, 4) numpy array."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    w, h, _ = image.GetDimensions()
    return vtk_to_numpy(image.GetPointData().GetArray("RGBA")).reshape(h, w, 4)


def run_cli(*args, expect=0):
    """Run ``python3 -m hovr.cli`` and return (exit code, stdout, stderr)."""
    process = subprocess.run([sys.executable, "-m", "hovr.cli"] + [str(a) for a in args],
                             capture_output=True, text=True, env=dict(os.environ))
    if expect is not None and process.returncode != expect:
        raise AssertionError("hovr %s: exit %d (expected %d)\nstdout: %s\nstderr: %s" % (
            " ".join(str(a) for a in args), process.returncode, expect, process.stdout,
            process.stderr))
    return process.returncode, process.stdout, process.stderr


class Checker:
    """Collects failed checks; exit(1) at the end if any failed."""

    def __init__(self):
        self.failures = 0

    def check(self, condition, what):
        if not condition:
            print("FAILED: " + what)
            self.failures += 1
        return condition

    def finish(self):
        if self.failures:
            print("%d checks failed" % self.failures)
            sys.exit(1)
        print("all checks passed")
        sys.exit(0)


class Messages:
    """Collects the error and warning messages a VTK object emits."""

    def __init__(self, obj):
        from vtkmodules.vtkCommonCore import vtkCommand
        self.errors, self.warnings = [], []
        obj.AddObserver(vtkCommand.ErrorEvent, self.on_error)
        obj.AddObserver(vtkCommand.WarningEvent, self.on_warning)

    def on_error(self, _obj, _event, message):
        self.errors.append(message)

    def on_warning(self, _obj, _event, message):
        self.warnings.append(message)

    on_error.CallDataType = "string0"
    on_warning.CallDataType = "string0"


class FloatFrames:
    """An offscreen window of `size` pixels with a transparent black background, whose frames
    are read back as float RGBA (vtkFloatRGBARenderCapture): one volume at a time."""

    def __init__(self, size):
        import hovr
        from vtkmodules.vtkRenderingCore import vtkRenderWindow, vtkRenderer
        import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
        self.window = vtkRenderWindow()
        self.window.SetOffScreenRendering(1)
        self.window.SetMultiSamples(0)
        self.window.SetAlphaBitPlanes(1)
        self.view = vtkRenderer()
        self.view.SetBackground(0.0, 0.0, 0.0)
        self.view.SetBackgroundAlpha(0.0)
        self.window.AddRenderer(self.view)
        # A first frame at 1 x 1 makes the context before the capture attaches to it.
        self.window.SetSize(1, 1)
        self.window.Render()
        self.window.SetSize(*size)
        self.capture = hovr.vtkFloatRGBARenderCapture()
        self.capture.Attach(self.window)

    def draw(self, mapper, data, prop, camera):
        """The float (H, W, 4) image of one frame of `mapper` drawing `data` with `prop` seen by
        `camera`, and the mapper's messages (a Messages)."""
        from vtkmodules.vtkCommonDataModel import vtkImageData
        from vtkmodules.vtkRenderingCore import vtkVolume
        mapper.SetInputData(data)
        messages = Messages(mapper)
        actor = vtkVolume()
        actor.SetMapper(mapper)
        actor.SetProperty(prop)
        self.view.RemoveAllViewProps()
        self.view.AddVolume(actor)
        self.view.GetActiveCamera().DeepCopy(camera)
        self.view.ResetCameraClippingRange()
        self.window.Render()
        image = vtkImageData()
        self.capture.Capture(image)
        return rgba(image).astype("float64"), messages


def blobs(n=48, seed=3, count=6):
    """A smooth volume of Gaussian blobs, values 0 to 255 rounded to integers, indexed [z, y, x]:
    regions where the scalar lingers near each blob's maximum, where a table that blurs the
    transfer function gives rays opacity they should not have."""
    import numpy
    rng = numpy.random.default_rng(seed)
    g = numpy.linspace(0.0, 1.0, n)
    z, y, x = numpy.meshgrid(g, g, g, indexing="ij")
    v = numpy.zeros_like(x)
    for _ in range(count):
        c = rng.uniform(0.2, 0.8, 3)
        r = rng.uniform(0.08, 0.25)
        v += rng.uniform(0.5, 1.0) * numpy.exp(
            -((x - c[0]) ** 2 + (y - c[1]) ** 2 + (z - c[2]) ** 2) / (2 * r * r))
    return numpy.round(255.0 * v / v.max())


def spike_property(centres=(44, 104), width=8, height=0.8, ramp=180, top=255, unit=1.0):
    """Opacity spikes `width` wide at `centres` plus a ramp from `ramp` to `top`, over [0, top]."""
    from hovr import io as hio
    points = [0, 0, 0.5, 0]
    for c in centres:
        points += [c - width / 2, 0, 0.5, 0, c, height, 0.5, 0, c + width / 2, 0, 0.5, 0]
    points += [ramp, 0, 0.5, 0, top, 0.6, 0.5, 0]
    color, opacity, _ = hio.transfer_function_from_preset({
        "RGBPoints": [0, 0.2, 0.4, 1, 100, 1, 0.6, 0.2, 255, 1, 1, 1], "Points": points})
    return hio.make_volume_property(color, opacity, unit)


# The shared volumes and their spike presets: file, dimensions, raw type, preset.
SHARED_VOLUMES = {
    "neghip": ("neghip_64x64x64_uint8.raw", (64, 64, 64), "uint8", "neghip-spikes"),
    "fuel": ("fuel_64x64x64_uint8.raw", (64, 64, 64), "uint8", "fuel-spikes"),
    "bucky": ("bucky_32x32x32_uint8.raw", (32, 32, 32), "uint8", "bucky-spikes"),
}


def shared_scene(name, size):
    """The scene of a shared volume with its spike preset (unit distance 1, default camera), or
    None when ../shared/data is absent."""
    from hovr import io as hio
    from hovr import methods as hm
    file_name, dims, raw_type, preset = SHARED_VOLUMES[name]
    path = shared_volume(file_name)
    if path is None:
        return None
    image = hio.read_volume(path, dims, raw_type)
    color, opacity, _ = hio.read_transfer_function(tf_path(preset))
    prop = hio.make_volume_property(color, opacity, 1.0)
    return hm.Scene(image, prop, hio.default_camera(image.GetBounds()), size)


def spike_scenes(size):
    """Marschner-Lobb 41, the uint8 blobs volume with 8-value spikes and (when ../shared/data is
    present; skipped with a message otherwise) neghip, fuel and bucky, each with its spike
    transfer function: a list of (name, scene)."""
    import numpy
    from hovr import io as hio
    from hovr import methods as hm
    blob_image = image_from_array(blobs().astype(numpy.uint8))
    scenes = [("Marschner-Lobb 41", marschner_lobb_scene(size)),
              ("blobs", hm.Scene(blob_image, spike_property(),
                                 hio.default_camera(blob_image.GetBounds()), size))]
    for name in SHARED_VOLUMES:
        scene = shared_scene(name, size)
        if scene is None:
            print("skipping %s: ../shared/data is absent" % name)
        else:
            scenes.append((name, scene))
    return scenes


def cast_image(scene, table, order, step, exact=False, threshold=None):
    """The image of vtkPreIntegrationRayCaster (the shaders' CPU twin) for a scene with a table
    (for the exact segment model, a table of any sizes holding only the settings), order and
    step in voxels; ``threshold`` sets its OpacityThreshold (the mapper's default if None)."""
    import hovr
    caster = hovr.vtkPreIntegrationRayCaster()
    caster.SetTable(table)
    caster.SetIntegration(order)
    caster.SetExactSegments(exact)
    caster.SetInputData(scene.image)
    caster.SetVolumeProperty(scene.prop)
    caster.SetCamera(scene.camera)
    caster.SetImageSize(*scene.size)
    caster.SetSampleDistance(scene.step_length(step))
    if threshold is not None:
        caster.SetOpacityThreshold(threshold)
    caster.Update()
    return caster.GetOutput()


def pixel_rays(camera, width, height):
    """The pixel rays of a vtkCamera as docs/cli.md defines them, in numpy (no hovr code):
    origins and unit directions, one row per pixel, x fastest."""
    import math
    import numpy
    position = numpy.array(camera.GetPosition())
    forward = numpy.array(camera.GetFocalPoint()) - position
    forward /= numpy.linalg.norm(forward)
    right = numpy.cross(forward, camera.GetViewUp())
    right /= numpy.linalg.norm(right)
    up = numpy.cross(right, forward)
    i, j = numpy.meshgrid(numpy.arange(width), numpy.arange(height))
    x = (2.0 * (i + 0.5) / width - 1.0).ravel()[:, None]
    y = (2.0 * (j + 0.5) / height - 1.0).ravel()[:, None]
    aspect = width / height
    if camera.GetParallelProjection():
        scale = camera.GetParallelScale()
        origins = position + x * scale * aspect * right + y * scale * up
        directions = numpy.repeat(forward[None, :], len(x), axis=0)
    else:
        t = math.tan(math.radians(camera.GetViewAngle()) / 2.0)
        origins = numpy.repeat(position[None, :], len(x), axis=0)
        directions = forward + x * t * aspect * right + y * t * up
        directions /= numpy.linalg.norm(directions, axis=1)[:, None]
    return origins, directions


def trilinear(values, p):
    """Trilinear interpolation of values[k, j, i] (or values[k, j, i, :]) at the index-space
    points p (n x 3), in numpy."""
    import numpy
    nz, ny, nx = values.shape[:3]
    cell = numpy.clip(numpy.floor(p).astype(int), 0, [nx - 2, ny - 2, nz - 2])
    f = p - cell
    out = 0.0
    for dz in (0, 1):
        for dy in (0, 1):
            for dx in (0, 1):
                w = ((f[:, 0] if dx else 1 - f[:, 0]) * (f[:, 1] if dy else 1 - f[:, 1]) *
                     (f[:, 2] if dz else 1 - f[:, 2]))
                v = values[cell[:, 2] + dz, cell[:, 1] + dy, cell[:, 0] + dx]
                out = out + (w[:, None] * v if v.ndim > 1 else w * v)
    return out
