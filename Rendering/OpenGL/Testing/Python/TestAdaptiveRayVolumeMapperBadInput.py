"""vtkAdaptiveRayVolumeMapper on bad input: a clear message and a safe image, never a crash.

Gaussian blobs (33^3, float) with their vtkAdaptiveSamplingOracle array, 64 x 64 float images:
- an oracle it cannot use (a missing array, three components, too few values, a NaN, an
  infinite value, cell scalars) gives one warning naming the cause and the image of
  OracleMode MINIMUM (every slice sampled), to float rounding (max 1e-6); the next frame
  warns no more; a usable oracle then draws quietly again;
- MaximumLevel outside [0, 8] is clamped with a warning; an unknown Reconstruction gives a
  warning and trilinear;
- the tricubic B-spline on a constant volume (where its clamp-to-edge borders matter most) and
  on a volume of 2 x 2 x 2 points draws quietly the trilinear image (a constant field in both;
  max 1e-5);
- a sample distance of 0, -1, NaN or infinity is an error and draws nothing (alpha 0);
- Shade on, and cropping, give a warning and VTK's stock image (the same as
  vtkOpenGLGPUVolumeRayCastMapper's, max 1e-6);
- a volume one voxel thick is an error and draws nothing; so is one that MaximumTextureBytes
  would split into more textures than the atlas's 8 pages;
- a camera inside the volume (rays start on the near plane) draws without a message the image
  of vtkPreIntegrationVolumeMapper up to their tables: within 5e-3 RMSE, what tables of 128
  entries on different axes make of the outside views below (about 6e-3 there, 8e-4 here; a
  lost or doubled segment in an image this opaque would differ by far more);
- a volume whose matrix scales, rotates and moves it, parallel and perspective, is as close to
  vtkPreIntegrationVolumeMapper's image (within 25%) as without the matrix: the slices live in
  the volume's data coordinates, where VTK measures the sample distance (the two images differ
  by their tables: 6e-3 RMSE with 128 entries, 2e-3 with 256, 8e-4 with 512).
"""

import math

import numpy
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow, vtkVolume
from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401

import hovr
from hovr import io as hio
from hovrtesting import Checker, Messages, blobs, image_from_array, rgba, spike_property

c = Checker()

window = vtkRenderWindow()
window.SetOffScreenRendering(1)
window.SetMultiSamples(0)
window.SetAlphaBitPlanes(1)
view = vtkRenderer()
view.SetBackground(0.0, 0.0, 0.0)
view.SetBackgroundAlpha(0.0)
window.AddRenderer(view)
window.SetSize(1, 1)
window.Render()
window.SetSize(64, 64)
capture = hovr.vtkFloatRGBARenderCapture()
capture.Attach(window)

prop = spike_property()
volume_image = image_from_array(blobs(n=33).astype(numpy.float32))
oracle = hovr.vtkAdaptiveSamplingOracle()
oracle.SetInputData(volume_image)
oracle.SetScalarOpacity(prop.GetScalarOpacity())
oracle.Update()
good = oracle.GetOutput()
camera = hio.default_camera(good.GetBounds())


def draw(mapper, data, shade=False, cam=camera, transformed=False):
    """The float image of one frame of ``mapper`` on ``data`` (with ``transformed``, through a
    volume matrix that scales, rotates and moves it), and the messages it gave."""
    mapper.SetInputData(data)
    messages = Messages(mapper)
    own = prop.NewInstance()
    own.DeepCopy(prop)
    own.SetShade(shade)
    actor = vtkVolume()
    actor.SetMapper(mapper)
    actor.SetProperty(own)
    if transformed:
        actor.SetScale(1.5, 1.0, 0.7)
        actor.RotateZ(30.0)
        actor.SetPosition(3.0, -2.0, 1.0)
    view.RemoveAllViewProps()
    view.AddVolume(actor)
    view.GetActiveCamera().DeepCopy(cam)
    view.ResetCameraClippingRange()
    window.Render()
    image = vtkImageData()
    capture.Capture(image)
    return rgba(image), messages


def adaptive(**settings):
    mapper = hovr.vtkAdaptiveRayVolumeMapper()
    mapper.SetSampleDistance(0.5)
    mapper.SetTableSize(128)
    for name, value in settings.items():
        getattr(mapper, "Set" + name)(value)
    return mapper


def with_array(name, values, cells=False):
    out = vtkImageData()
    out.ShallowCopy(volume_image)
    array = numpy_to_vtk(numpy.ascontiguousarray(values), deep=1)
    array.SetName(name)
    (out.GetCellData() if cells else out.GetPointData()).AddArray(array)
    return out


def said(messages, kind, fragment):
    return any(fragment in m for m in getattr(messages, kind))


quiet, messages = draw(adaptive(), good)
c.check(not messages.errors and not messages.warnings and quiet[..., 3].max() > 0.3,
        "a usable oracle draws quietly (%s)" % (messages.errors + messages.warnings))
minimum, _ = draw(adaptive(OracleMode=1), good)
points = good.GetNumberOfPoints()
distances = numpy.full(points, 2.0, numpy.float32)
nan = distances.copy()
nan[points // 2] = numpy.nan
inf = distances.copy()
inf[7] = numpy.inf
cells = volume_image.GetNumberOfCells()
cell_scalars = vtkImageData()
cell_scalars.ShallowCopy(volume_image)
cases = [
    ("a missing array", good, "Missing", "no point array"),
    ("three components", with_array("OracleDistance", numpy.ones((points, 3), numpy.float32)),
     None, "one component per point"),
    ("too few values", with_array("OracleDistance", distances[: points // 2]), None,
     "one component per point"),
    ("a NaN", with_array("OracleDistance", nan), None, "not finite"),
    ("an infinite value", with_array("OracleDistance", inf), None, "not finite"),
    ("a cell array", with_array("OracleDistance", numpy.ones(cells, numpy.float32), cells=True),
     None, "no point array"),
]
for what, data, name, fragment in cases:
    mapper = adaptive(OracleArrayName=name) if name else adaptive()
    image, messages = draw(mapper, data)
    difference = float(numpy.abs(image - minimum).max())
    c.check(said(messages, "warnings", fragment) and not messages.errors,
            "%s: a warning with \"%s\" (%s %s)" % (what, fragment, messages.warnings,
                                                   messages.errors))
    c.check(difference <= 1e-6 and not mapper.GetLastFrameUsedOracle(),
            "%s: MINIMUM's image (max difference %.2g)" % (what, difference))
    window.Render()
    c.check(len(messages.warnings) == 1, "%s: one warning over two frames, got %d" % (
        what, len(messages.warnings)))
    mapper.SetInputData(good)
    mapper.SetOracleArrayName("OracleDistance")
    window.Render()
    c.check(len(messages.warnings) == 1 and mapper.GetLastFrameUsedOracle(),
            "%s: a usable oracle afterwards draws quietly with it" % what)

for level, clamped in ((9, 8), (-1, 0)):
    mapper = hovr.vtkAdaptiveRayVolumeMapper()
    messages = Messages(mapper)
    mapper.SetMaximumLevel(level)
    c.check(mapper.GetMaximumLevel() == clamped and said(messages, "warnings", "outside [0, 8]"),
            "MaximumLevel %d: clamped to %d with a warning" % (level, clamped))

for value in (-1, 2):
    mapper = hovr.vtkAdaptiveRayVolumeMapper()
    mapper.SetReconstructionToTricubicBSpline()
    messages = Messages(mapper)
    mapper.SetReconstruction(value)
    c.check(mapper.GetReconstruction() == mapper.RECONSTRUCTION_TRILINEAR and
            said(messages, "warnings", "unknown"),
            "Reconstruction %d: a warning and trilinear" % value)

for shape in ((33, 33, 33), (2, 2, 2)):
    constant = image_from_array(numpy.full(shape, 104.0, numpy.float32))
    images = []
    for reconstruction in (0, 1):
        image, messages = draw(adaptive(OracleMode=1, Reconstruction=reconstruction), constant,
                               cam=hio.default_camera(constant.GetBounds()))
        c.check(not messages.errors and not messages.warnings and numpy.isfinite(image).all(),
                "constant %s, reconstruction %d: no message" % (shape, reconstruction))
        images.append(image)
    difference = float(numpy.abs(images[0] - images[1]).max())
    c.check(difference <= 1e-5 and images[0][..., 3].max() > 0.05,
            "constant %s: tricubic draws the trilinear image (max difference %.2g, alpha %.2f)"
            % (shape, difference, images[0][..., 3].max()))

for distance in (0.0, -1.0, math.nan, math.inf):
    image, messages = draw(adaptive(SampleDistance=distance), good)
    c.check(said(messages, "errors", "positive and finite") and image[..., 3].max() == 0.0,
            "sample distance %g: an error, nothing drawn" % distance)

stock = vtkOpenGLGPUVolumeRayCastMapper()
stock.SetAutoAdjustSampleDistances(0)
stock.SetSampleDistance(0.5)
stock_image, _ = draw(stock, good, shade=True)
image, messages = draw(adaptive(), good, shade=True)
difference = float(numpy.abs(image - stock_image).max())
c.check(said(messages, "warnings", "does not shade") and difference <= 1e-6 and
        stock_image[..., 3].max() > 0.3,
        "Shade on: a warning and VTK's stock image (max difference %.2g; %s)" % (
            difference, messages.warnings))

mapper = adaptive()
mapper.CroppingOn()
mapper.SetCroppingRegionPlanes(0.0, 10.0, 0.0, 32.0, 0.0, 32.0)
stock.CroppingOn()
stock.SetCroppingRegionPlanes(0.0, 10.0, 0.0, 32.0, 0.0, 32.0)
stock_image, _ = draw(stock, good)
image, messages = draw(mapper, good)
difference = float(numpy.abs(image - stock_image).max())
c.check(said(messages, "warnings", "cropping") and difference <= 1e-6,
        "cropping: a warning and VTK's stock image (max difference %.2g)" % difference)

slab = image_from_array(numpy.full((1, 33, 33), 100.0, numpy.float32))
image, messages = draw(adaptive(OracleMode=1), slab)
c.check(said(messages, "errors", "at least 2 points") and image[..., 3].max() == 0.0,
        "one voxel thick: an error, nothing drawn (%s)" % messages.errors)

# 33^3 float points (140 KiB, the oracle as much) within textures of at most 4 KiB: more than
# the atlas's 8 pages.
image, messages = draw(adaptive(MaximumTextureBytes=4096), good)
c.check(said(messages, "errors", "do not fit in 8 3D textures") and
        image[..., 3].max() == 0.0,
        "a volume beyond 8 textures of MaximumTextureBytes: an error, nothing drawn (%s)"
        % messages.errors)

inside = hio.default_camera(good.GetBounds())
centre = [0.5 * (good.GetBounds()[2 * a] + good.GetBounds()[2 * a + 1]) for a in range(3)]
inside.SetPosition(centre[0] + 3.0, centre[1] - 2.0, centre[2] + 1.0)
image, messages = draw(adaptive(), good, cam=inside)
preint = hovr.vtkPreIntegrationVolumeMapper()
preint.SetSampleDistance(0.5)
preint.SetTableSize(128)
preint_image, _ = draw(preint, good, cam=inside)
difference = float(numpy.sqrt(((image - preint_image) ** 2).mean()))
c.check(numpy.isfinite(image).all() and not messages.errors and not messages.warnings and
        difference <= 5e-3 and image[..., 3].mean() > 0.5,
        "a camera inside the volume: no message, vtkPreIntegrationVolumeMapper's image up to the "
        "tables (RMSE %.2g; %s)" % (difference, messages.errors + messages.warnings))

for parallel in (True, False):
    cam = hio.default_camera(good.GetBounds(), parallel=parallel)
    differences = []
    for transformed in (False, True):
        preint_image, _ = draw(preint, good, cam=cam, transformed=transformed)
        image, messages = draw(adaptive(), good, cam=cam, transformed=transformed)
        differences.append(float(numpy.sqrt(((image - preint_image) ** 2).mean())))
    c.check(not messages.errors and not messages.warnings and
            differences[1] <= 1.25 * differences[0] + 1e-4 and image[..., 3].mean() > 0.1,
            "a scaled, rotated and moved volume (%s): as close to vtkPreIntegrationVolumeMapper's "
            "image as without the matrix (RMSE %.2g, %.2g without)" % (
                "parallel" if parallel else "perspective", differences[1], differences[0]))

window.Finalize()
c.finish()
