# hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
"""pvbatch test: the "hovr Volume" representation on adversarial inputs and settings.

Every rendering method of the representation draws volumes a scientist's files hold on a bad
day (NaN, Inf, +-1e300, a 1e20 fill value, arrays shorter or longer than the grid, a slab, one
voxel, three components, eight scalar types, spacings of 1e-30 and 1e30, a NaN origin), and
a good volume with bad settings (sample distances of -1, 1e-9 and 1e30, table sizes of 1 and
65536, 1 iteration, an opacity unit distance of 1e-30). Each frame must end in an image with
something drawn, or in an error or warning in ParaView's output; never a crash, or an empty
view with no message. The test prints a table of case, method and outcome.

    pvbatch TestHovrPluginAdversarial.py --plugin <hovr.so>
"""
import argparse
import sys
import time

import numpy
from paraview.simple import (ColorBy, CreateRenderView, GetColorTransferFunction,
                             GetOpacityTransferFunction, LoadPlugin, Render, Show,
                             TrivialProducer, Delete)
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkLogger, vtkOutputWindow, vtkStringOutputWindow
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter

SIZE = [64, 48]
# A frame that takes longer fails (ctest's timeout catches a hang).
FRAME_SECONDS = 60.0
METHODS = ["Stock", "First-order pre-integration", "Second-order pre-integration",
           "Analytic isosurface", "Analytic MIP", "Analytic MinIP",
           "Object-order ray casting (CPU)"]


# Where each method's messages come from (the class names in VTK's messages).
GPU_SOURCES = ("vtkExtensibleGPUVolumeRayCastMapper", "vtkGPUVolumeRayCastMapper",
               "vtkOpenGLGPUVolumeRayCastMapper", "vtkPreIntegrationTable")
SOURCES = {method: GPU_SOURCES + ("vtkPreIntegrationVolumeMapper",) for method in METHODS[:3]}
SOURCES.update({method: GPU_SOURCES + ("vtkAnalyticVolumeMapper",) for method in METHODS[3:6]})
SOURCES[METHODS[6]] = ("vtkObjectOrderVolumeMapper", "vtkObjectOrderRayCaster",
                       "vtkCameraRayModel", "vtkMinMaxOctree")


def field(n=12):
    g = numpy.linspace(0.0, 1.0, n)
    z, y, x = numpy.meshgrid(g, g, g, indexing="ij")
    return 0.5 + 0.25 * numpy.sin(5.0 * x + 1.0) * numpy.cos(4.0 * y - 0.5) + 0.2 * (z - 0.5)


def image_of(values, dims=None, spacing=1.0, origin=(0.0, 0.0, 0.0), components=1):
    image = vtkImageData()
    dims = dims or (values.shape[2], values.shape[1], values.shape[0])
    image.SetDimensions(*dims)
    image.SetSpacing(spacing, spacing, spacing)
    image.SetOrigin(origin)
    array = numpy_to_vtk(numpy.ascontiguousarray(values).reshape(-1, components), deep=1)
    array.SetName("scalars")
    image.GetPointData().SetScalars(array)
    return image


def volume_cases():
    base = field()
    flat = base.astype(numpy.float32)
    nan = flat.copy()
    nan.ravel()[numpy.random.default_rng(5).choice(nan.size, 6, replace=False)] = numpy.nan
    inf = flat.copy()
    inf[5, 5, 5] = numpy.inf
    cases = [("float32", image_of(flat)), ("some NaN", image_of(nan)),
             ("all NaN", image_of(numpy.full_like(flat, numpy.nan))), ("Inf", image_of(inf)),
             ("+-1e300", image_of(base * 2e300 - 1e300)),
             ("fill 1e20", image_of(numpy.full_like(base, 1e20))),
             ("short array", image_of(flat.ravel()[:100], dims=(12, 12, 12))),
             ("long array", image_of(numpy.concatenate([flat.ravel()] * 2), dims=(12, 12, 12))),
             ("3 components", image_of(numpy.repeat(flat.ravel(), 3), dims=(12, 12, 12),
                                       components=3)),
             ("slab", image_of(flat[:1])), ("one voxel", image_of(flat[:1, :1, :1])),
             ("spacing 1e-30", image_of(flat, spacing=1e-30)),
             ("spacing 1e30", image_of(flat, spacing=1e30)),
             ("NaN origin", image_of(flat, origin=(numpy.nan, 0.0, 0.0)))]
    for name in ("int8", "uint8", "int16", "uint16", "int32", "uint64", "float64"):
        dtype = numpy.dtype(name)
        scale = 100.0 if dtype.kind in "iu" else 1.0
        cases.append((name, image_of((base * scale).astype(dtype))))
    return cases


class Captured:
    """What VTK and ParaView print while drawing (errors and warnings), as text."""

    def __enter__(self):
        self.previous = vtkOutputWindow.GetInstance()
        self.previous.Register(None)
        self.window = vtkStringOutputWindow()
        vtkOutputWindow.SetInstance(self.window)
        self.verbosity = vtkLogger.GetCurrentVerbosityCutoff()
        vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
        return self

    def __exit__(self, *exc):
        self.text = self.window.GetOutput()
        vtkLogger.SetStderrVerbosity(self.verbosity)
        vtkOutputWindow.SetInstance(self.previous)
        self.previous.UnRegister(None)
        return False


def drawn_pixels(view):
    """Pixels of the view's image that differ from its black background."""
    grab = vtkWindowToImageFilter()
    grab.SetInput(view.GetRenderWindow())
    grab.ReadFrontBufferOff()
    grab.Update()
    rgb = vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars())[:, :3]
    return int((rgb.max(axis=1) > 0).sum())


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plugin", required=True)
    args = parser.parse_args()
    LoadPlugin(args.plugin, remote=False, ns=globals())
    view = CreateRenderView()
    view.ViewSize = SIZE
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.BackgroundColorMode = "Single Color"
    view.Background = [0.0, 0.0, 0.0]
    view.UseFXAA = 0
    # Object-order ray casting draws parallel projections (it hands perspective ones to VTK's
    # CPU ray caster).
    view.CameraParallelProjection = 1
    failures, rows = [], []

    def frame(case, method, captured):
        start = time.perf_counter()
        Render(view)
        pixels = drawn_pixels(view)
        seconds = time.perf_counter() - start
        # The mappers report a reason once, perhaps in a render ParaView made before this
        # frame: the messages of the case so far, from the classes drawing this method.
        sources = SOURCES[method]
        text = captured.window.GetOutput()
        # A message is a block ("ERROR: In <file>, line <n>" and "<class> (<address>): ...").
        blocks = [" ".join(block.split()) for block in text.split("\n\n")]
        message = " ".join(block for block in blocks
                           if ("ERR" in block or "WARN" in block or "Error" in block
                               or "Warning" in block) and any(s in block for s in sources))
        outcome = "image" if pixels else ("message" if message else "EMPTY, NO MESSAGE")
        if not pixels and not message:
            failures.append("%s / %s: an empty view and no message" % (case, method))
        if seconds > FRAME_SECONDS:
            failures.append("%s / %s: %.1f s" % (case, method, seconds))
        rows.append((case, method, outcome, pixels, seconds, message[:110]))

    def show(case, image, methods, settings=None):
        with Captured() as captured:
            show_captured(case, image, methods, settings, captured)

    def show_captured(case, image, methods, settings, captured):
        producer = TrivialProducer()
        producer.GetClientSideObject().SetOutput(image)
        display = Show(producer, view)
        display.SetRepresentationType("hovr Volume")
        if image.GetPointData().GetScalars() is not None:
            ColorBy(display, ("POINTS", "scalars"))
            low, high = image.GetPointData().GetScalars().GetFiniteRange()
            if not (low <= high):
                low, high = 0.0, 1.0
            # ParaView's transfer function proxies assert on an empty range.
            high = max(high, low + max(1.0, abs(low) * 1e-6))
            color = GetColorTransferFunction("scalars")
            color.AutomaticRescaleRangeMode = "Never"
            color.RGBPoints = [low, 0.1, 0.3, 0.9, high, 1.0, 0.6, 0.1]
            opacity = GetOpacityTransferFunction("scalars")
            span = high - low
            opacity.Points = [low, 0.0, 0.5, 0.0, low + 0.4 * span, 0.0, 0.5, 0.0,
                              low + 0.6 * span, 0.8, 0.5, 0.0, high, 0.1, 0.5, 0.0]
            display.IsosurfaceValues = [low + 0.5 * span]
        display.ScalarOpacityUnitDistance = 1.0
        for name, value in (settings or {}).items():
            setattr(display, name, value)
        view.ResetCamera()
        for method in methods:
            display.HovrIntegration = method
            frame(case, method, captured)
        Delete(display)
        Delete(producer)

    for case, image in volume_cases():
        show(case, image, METHODS)
    good = image_of(field().astype(numpy.float32))
    settings = [("sample distance -1", {"HovrSampleDistance": -1.0}),
                ("sample distance 1e-9", {"HovrSampleDistance": 1e-9}),
                ("sample distance 1e30", {"HovrSampleDistance": 1e30}),
                ("table size 1", {"HovrTableSize": 1}),
                ("table size 65536", {"HovrTableSize": 65536}),
                ("iterations 1", {"HovrIterations": 1}),
                ("unit distance 1e-30", {"ScalarOpacityUnitDistance": 1e-30})]
    for case, values in settings:
        show(case, good, METHODS[:3] + METHODS[6:], values)

    print("%-22s %-32s %-18s %7s %6s  %s" % ("case", "method", "outcome", "pixels", "s",
                                            "message"))
    for case, method, outcome, pixels, seconds, message in rows:
        print("%-22s %-32s %-18s %7d %6.2f  %s" % (case, method, outcome, pixels, seconds,
                                                  message))
    print("%d frames" % len(rows))
    for failure in failures:
        print("FAILED: " + failure)
    Delete(view)
    return 1 if failures else 0


sys.exit(main())
