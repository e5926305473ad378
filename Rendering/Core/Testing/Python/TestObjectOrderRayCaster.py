"""vtkObjectOrderRayCaster (object-order ray casting on the CPU) against the float64 reference
and against itself.

Accuracy (96 x 96, parallel views of Marschner-Lobb 41^3 with the narrow-spike transfer
function; pre-integrated classification, and the paper's point-sampled one once): RMSE at half a voxel below 0.06 (0.1 along an axis, where samples lie on grid planes), falling with the step (first order at least:
RMSE(1/4) < 0.7 RMSE(1/2)), for an oblique view, a view exactly along an axis and one along a
diagonal, a 2-voxel-thick volume and a volume much larger than the image. The volume's
pixels (GetLastVolumePixels) hold every non-zero pixel, and none when it is out of view.

Invariants: the same image (bit for bit) with 1 and 2 threads, with tiles of 8 and 64 pixels,
and with and without hidden volume removal; leaves of 1, 2, 4 and 8 cells agree to float
rounding; on an opaque transfer function hidden volume removal keeps over 65% of the
non-transparent cells out of the work (no ray samples them), and without its node tests the
same cells are sampled but more octree nodes are visited; editing the opacity every frame
never rebuilds the octree.

Shading: on a linear field (one normal) the shaded image is the unshaded one lit by the
documented formula, exactly with post-shading and within 0.01 with pre-shading; both agree on
Marschner-Lobb within 0.04 RMSE (measured 0.026: vertex shading interpolated against gradients).

Extremes and bad input: a fully transparent transfer function gives an empty image and no
cell; a fully opaque one an opaque silhouette; NaN voxels leave no NaN; perspective cameras, a
zero or negative step, vectors and flat volumes are errors with a transparent image.
"""

import math

import numpy
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkSMPTools
from vtkmodules.vtkCommonDataModel import vtkImageData

import hovr
from hovr import io as hio
from hovrtesting import Checker, Messages, tf_path

c = Checker()
SIZE = 96


def marschner_lobb(points=41):
    source = hovr.vtkMarschnerLobbSource()
    source.SetDimensions(points, points, points)
    source.Update()
    return source.GetOutput()


def spikes(unit=0.05):
    color, opacity, _ = hio.read_transfer_function(tf_path("marschner-lobb-spikes"))
    return hio.make_volume_property(color, opacity, unit)


def parallel(image, direction=(1.0, -1.6, 0.9), view_up=(0.0, 0.0, 1.0)):
    return hio.default_camera(image.GetBounds(), direction, view_up, parallel=True)


def pixels(algorithm):
    return vtk_to_numpy(algorithm.GetOutput().GetPointData().GetScalars()).copy()


def reference(image, prop, camera, size=SIZE):
    integrator = hovr.vtkVolumeReferenceIntegrator()
    integrator.SetInputData(image)
    integrator.SetVolumeProperty(prop)
    integrator.SetCamera(camera)
    integrator.SetImageSize(size, size)
    integrator.Update()
    return pixels(integrator)


def caster(image, prop, camera, step, size=SIZE, **settings):
    algorithm = hovr.vtkObjectOrderRayCaster()
    algorithm.messages = Messages(algorithm)
    algorithm.SetInputData(image)
    algorithm.SetVolumeProperty(prop)
    algorithm.SetCamera(camera)
    algorithm.SetImageSize(size, size)
    algorithm.SetSampleDistance(step)
    for key, value in settings.items():
        getattr(algorithm, "Set" + key)(value)
    algorithm.Update()
    return algorithm


def rmse(a, b):
    return float(numpy.sqrt(((a - b) ** 2).mean()))


# Accuracy against the reference, and first-order convergence at least.
ml = marschner_lobb()
prop = spikes()
thin = vtkImageData()
thin.SetDimensions(32, 32, 2)
thin.SetSpacing(1.0 / 31, 1.0 / 31, 1.0 / 31)
thin.GetPointData().SetScalars(numpy_to_vtk(numpy.tile(numpy.linspace(0.3, 0.7, 32), 64)
                                            .astype(numpy.float32), deep=1))
views = [("oblique", ml, parallel(ml), 0.06),
         ("along x", ml, hio.camera_from_dict({
             "position": [-5.0, 0.0, 0.0], "focal_point": [0.0, 0.0, 0.0], "view_up": [0, 0, 1],
             "parallel_projection": True, "parallel_scale": 1.05}), 0.1),
         ("diagonal", ml, parallel(ml, (1.0, 1.0, 1.0), (0.0, 0.0, 1.0)), 0.06),
         ("2 voxels thick", thin, parallel(thin, (0.3, -0.4, 1.0), (0.0, 1.0, 0.0)), 0.03)]
for label, image, camera, bound in views:
    expected = reference(image, prop, camera)
    errors = [rmse(pixels(caster(image, prop, camera, s * 2.0 / 40)), expected)
              for s in (0.5, 0.25)]
    print("%-15s RMSE at 1/2 voxel %.5f, at 1/4 %.5f" % (label, errors[0], errors[1]))
    c.check(expected[:, 3].max() > 0.2, "%s: the reference image is not empty" % label)
    c.check(errors[0] < bound, "%s: RMSE at half a voxel below %g (%.4f)" % (label, bound, errors[0]))
    c.check(errors[1] < 0.7 * errors[0], "%s: the error falls with the step" % label)

# The paper's point-sampled classification converges too; pre-integration (the default) is
# the more accurate at the same step.
camera = parallel(ml)
expected = reference(ml, prop, camera)
point = [rmse(pixels(caster(ml, prop, camera, s * 2.0 / 40, Classification=0)), expected)
         for s in (0.5, 0.25)]
segments = rmse(pixels(caster(ml, prop, camera, 0.5 * 2.0 / 40)), expected)
print("oblique, point-sampled: RMSE at 1/2 voxel %.5f, at 1/4 %.5f; pre-integrated %.5f"
      % (point[0], point[1], segments))
c.check(point[1] < 0.7 * point[0] and segments < point[0],
        "point-sampled classification converges, pre-integrated is closer at the same step")

# A volume much larger than the image (each pixel sees several cells across).
small = 12
camera = parallel(ml)
expected = reference(ml, prop, camera, small)
error = rmse(pixels(caster(ml, prop, camera, 0.025, small)), expected)
c.check(error < 0.1, "volume larger than a 12 x 12 image: RMSE %.4f" % error)

# The volume's pixels (what a mapper draws): the image is zero outside them; none before an
# update or when the volume is out of view.
def volume_pixels(algorithm):
    rect = [0, 0, 0, 0]
    algorithm.GetLastVolumePixels(rect)
    return rect


c.check(volume_pixels(hovr.vtkObjectOrderRayCaster())[1] < 0, "no volume pixels before an update")
camera = parallel(ml)
camera.SetParallelScale(3.0 * camera.GetParallelScale())  # the volume in the image's middle
far = caster(ml, prop, camera, 0.05)
x0, x1, y0, y1 = volume_pixels(far)
alpha = pixels(far)[:, 3].reshape(SIZE, SIZE)  # rows are y
outside = alpha.copy()
outside[y0:y1 + 1, x0:x1 + 1] = 0.0
print("volume pixels of a zoomed-out view: [%d, %d] x [%d, %d]" % (x0, x1, y0, y1))
c.check(0 < x0 <= x1 < SIZE - 1 and 0 < y0 <= y1 < SIZE - 1,
        "zoomed out: the volume's pixels lie inside the image")
c.check(alpha[y0:y1 + 1, x0:x1 + 1].max() > 0.2 and not outside.any(),
        "zoomed out: the image is zero outside the volume's pixels")
camera.SetFocalPoint(10.0, 10.0, 10.0)
camera.SetPosition(15.0, 2.0, 14.5)
away = caster(ml, prop, camera, 0.05)
rect = volume_pixels(away)
c.check((rect[1] < rect[0] or rect[3] < rect[2]) and not pixels(away).any(),
        "volume out of view: no volume pixels, an empty image")

# The same image whatever the threads, tiles and hidden volume removal.
camera = parallel(ml)
base = caster(ml, prop, camera, 0.025)
images = {"default": pixels(base)}
for threads in (1, 2):
    vtkSMPTools.Initialize(threads)
    images["%d threads" % threads] = pixels(caster(ml, prop, camera, 0.025))
vtkSMPTools.Initialize(0)
for tile in (8, 64):
    images["tiles of %d" % tile] = pixels(caster(ml, prop, camera, 0.025, TileSize=tile))
images["no hidden volume removal"] = pixels(caster(ml, prop, camera, 0.025,
                                                   HiddenVolumeRemoval=False))
for label, image in images.items():
    c.check(numpy.array_equal(image, images["default"]), "%s: the same image" % label)
# Both compiled copies of the sample loop: each gives the same image on 1 and 2 threads, and
# the AVX2 one (fused multiply-adds) differs from the SSE2 one by float rounding only.
loops = {}
for name, setting in (("SSE2", hovr.vtkObjectOrderRayCaster.INSTRUCTIONS_SSE2),
                      ("AVX2", hovr.vtkObjectOrderRayCaster.INSTRUCTIONS_AVX2)):
    runs = []
    for threads in (1, 2):
        vtkSMPTools.Initialize(threads)
        runs.append(caster(ml, prop, camera, 0.025, InstructionSet=setting))
    vtkSMPTools.Initialize(0)
    if runs[0].GetLastInstructionSet() != setting:
        c.check(name == "AVX2" and runs[0].messages.warnings,
                "%s asked for: %s ran, with a warning" % (name, runs[0].GetLastInstructionSet()))
        print("AVX2 asked for on a processor or build without it: the SSE2 loop ran (warned)")
        continue
    c.check(numpy.array_equal(pixels(runs[0]), pixels(runs[1])),
            "%s loop: the same image on 1 and 2 threads" % name)
    loops[setting] = pixels(runs[0])
if len(loops) == 2:
    difference = numpy.abs(loops[hovr.vtkObjectOrderRayCaster.INSTRUCTIONS_SSE2] -
                           loops[hovr.vtkObjectOrderRayCaster.INSTRUCTIONS_AVX2]).max()
    print("AVX2 against SSE2 loop: max difference %.1e" % difference)
    c.check(difference < 1e-4, "AVX2 and SSE2 loops: the same image to float rounding (%.1e)"
            % difference)
c.check(base.GetLastInstructionSet() in loops, "the automatic choice ran a tested loop")
# Leaves of any size sample the same points in the same cells: the same image to float
# rounding (leaf-local coordinates), the same samples and cells sampled.
for leaf in (1, 2, 4, 8):
    other = caster(ml, prop, camera, 0.025, LeafSize=leaf)
    difference = numpy.abs(pixels(other) - images["default"]).max()
    c.check(difference < 1e-5 and other.GetNumberOfSamples() == base.GetNumberOfSamples() and
            other.GetNumberOfNonTransparentCells() == base.GetNumberOfNonTransparentCells(),
            "leaves of %d cells: the same image (%.1e), samples and cells" % (leaf, difference))

# Opaque transfer function: hidden volume removal culls most non-transparent cells.
color, opacity, _ = hio.read_transfer_function(tf_path("marschner-lobb-opaque"))
opaque = hio.make_volume_property(color, opacity, 0.02)
with_removal = caster(ml, opaque, camera, 0.025, size=128)
in_view = with_removal.ComputeNonTransparentCells()
rendered = with_removal.GetNumberOfNonTransparentCells()
print("opaque: %d of %d non-transparent cells rendered (%.1f%% occluded), %d nodes, %d samples"
      % (rendered, in_view, 100.0 * (1 - rendered / in_view), with_removal.GetNumberOfNodesVisited(),
         with_removal.GetNumberOfSamples()))
c.check(in_view > 0 and rendered < 0.35 * in_view,
        "opaque: hidden volume removal leaves out over 65% of the non-transparent cells")
without = caster(ml, opaque, camera, 0.025, size=128, HiddenVolumeRemoval=False)
c.check(without.GetNumberOfNonTransparentCells() == rendered and
        without.GetNumberOfNodesVisited() > with_removal.GetNumberOfNodesVisited() and
        numpy.array_equal(pixels(without), pixels(with_removal)),
        "opaque: without the node tests the same image and cells, more nodes visited (%d, %d)"
        % (without.GetNumberOfNodesVisited(), with_removal.GetNumberOfNodesVisited()))

# Editing the opacity every frame: no octree rebuild, and the image follows.
algorithm = caster(ml, spikes(), camera, 0.05)
builds = algorithm.GetOctree().GetBuildCount()
previous = pixels(algorithm)
changed = True
for frame in range(3):
    algorithm.GetVolumeProperty().GetScalarOpacity().AddPoint(0.5, 0.2 + 0.2 * frame)
    algorithm.Update()
    now = pixels(algorithm)
    changed = changed and not numpy.array_equal(now, previous)
    previous = now
c.check(algorithm.GetOctree().GetBuildCount() == builds and changed,
        "opacity edited every frame: the image changes, the octree is not rebuilt")

# Extremes of the transfer function.
transparent = spikes()
transparent.GetScalarOpacity().RemoveAllPoints()
transparent.GetScalarOpacity().AddPoint(0.0, 0.0)
transparent.GetScalarOpacity().AddPoint(1.0, 0.0)
empty = caster(ml, transparent, camera, 0.05)
c.check(not pixels(empty).any() and empty.GetNumberOfNonTransparentCells() == 0 and
        empty.GetNumberOfSamples() == 0, "fully transparent: empty image, no cell, no sample")
solid = spikes(1.0)
solid.GetScalarOpacity().RemoveAllPoints()
solid.GetScalarOpacity().AddPoint(0.0, 1.0)
solid.GetScalarOpacity().AddPoint(1.0, 1.0)
solid_caster = caster(ml, solid, camera, 0.05)
full = pixels(solid_caster)
threshold = solid_caster.GetOpacityThreshold()
covered = reference(ml, solid, camera)[:, 3] > threshold
c.check(covered.any() and (full[covered, 3] >= threshold).all() and
        (full[~covered, 3] < threshold).all(), "fully opaque: exactly the silhouette is opaque")

# NaN voxels: transparent cells, a finite image.
holes = vtkImageData()
holes.DeepCopy(ml)
values = vtk_to_numpy(holes.GetPointData().GetScalars())
values[::7] = numpy.nan
holes.GetPointData().GetScalars().Modified()
c.check(numpy.isfinite(pixels(caster(holes, prop, camera, 0.05))).all(), "NaN voxels: finite image")

# Bad input: errors and a transparent image.
perspective = hio.default_camera(ml.GetBounds())
bad = caster(ml, prop, perspective, 0.05)
c.check(bad.messages.errors and "parallel" in bad.messages.errors[0] and not pixels(bad).any(),
        "perspective camera: error, transparent image")
for step in (0.0, -1.0):
    bad = caster(ml, prop, camera, step)
    c.check(bad.messages.errors and "sample distance" in bad.messages.errors[0],
            "sample distance %g: error" % step)
# A step so fine that a frame would take hours: an error before any work.
bad = caster(ml, prop, camera, 1e-9)
c.check(bad.messages.errors and "MaximumSamplesPerRay" in bad.messages.errors[0]
        and not pixels(bad).any(), "sample distance 1e-9: error, transparent image")
# A long frame (2^28 samples expected) is walked in parts with progress events; aborting from
# the first event stops the walk: the tiles not walked stay transparent.
long_frame = hovr.vtkObjectOrderRayCaster()
long_frame.SetInputData(ml)
long_frame.SetVolumeProperty(prop)
long_frame.SetCamera(camera)
long_frame.SetImageSize(256, 256)
long_frame.SetSampleDistance(2.0 * 3 ** 0.5 / 8000)
long_frame.SetHiddenVolumeRemoval(False)
progress = []


def on_progress(algorithm, _event):
    progress.append(algorithm.GetProgress())
    if algorithm.GetProgress() > 0.5:  # about half of the image's tiles walked
        algorithm.SetAbortExecute(1)


long_frame.AddObserver("ProgressEvent", on_progress)
long_frame.Update()
drawn = numpy.count_nonzero(pixels(long_frame)[:, 3])
c.check(len(progress) >= 5 and progress[2] < 0.5 and 0 < drawn,
        "a long frame reports progress in parts (%s) and stops when aborted (%d pixels drawn)"
        % (["%.2f" % p for p in progress[:4]], drawn))
c.check(drawn < 0.8 * numpy.count_nonzero(pixels(caster(ml, prop, camera, 0.05, 256))[:, 3]),
        "the aborted frame left the tiles after the abort transparent")
vectors = vtkImageData()
vectors.SetDimensions(4, 4, 4)
vectors.AllocateScalars(11, 3)
bad = caster(vectors, prop, camera, 0.05)
c.check(bad.messages.errors and "single-component" in bad.messages.errors[0], "vectors: error")
flat = vtkImageData()
flat.SetDimensions(8, 8, 1)
flat.AllocateScalars(11, 1)
bad = caster(flat, prop, camera, 0.05)
c.check(bad.messages.errors and "2 points" in bad.messages.errors[0], "flat volume: error")

# Shading. A linear field has one normal everywhere, so the shaded image is the unshaded one
# times (ambient + diffuse |n.l|) plus specular |n.l|^power times alpha, exactly for post-
# shading and to the quantization of the normal (8100 directions) for pre-shading.
ramp = vtkImageData()
ramp.SetDimensions(24, 20, 16)
ramp.SetSpacing(1.0, 1.5, 0.8)
gx, gy, gz = numpy.meshgrid(numpy.arange(24), numpy.arange(20) * 1.5, numpy.arange(16) * 0.8,
                            indexing="ij")
field = (0.02 * gx + 0.01 * gy - 0.015 * gz + 0.3).transpose(2, 1, 0).ravel()
ramp.GetPointData().SetScalars(numpy_to_vtk(field.astype(numpy.float32), deep=1))
lit = spikes(5.0)
lit.SetAmbient(0.2)
lit.SetDiffuse(0.7)
lit.SetSpecular(0.3)
lit.SetSpecularPower(8.0)
view = parallel(ramp, (0.4, -1.0, 0.7))
plain = pixels(caster(ramp, lit, view, 0.4))
lit.ShadeOn()
normal = numpy.array([0.02, 0.01, -0.015])
normal /= numpy.linalg.norm(normal)
light = -numpy.array(view.GetDirectionOfProjection())
nl = abs(float(normal @ light))
expected = plain.copy()
expected[:, :3] = plain[:, :3] * (0.2 + 0.7 * nl) + (0.3 * nl ** 8.0) * plain[:, 3:4]
for mode, tolerance in (("PostShading", 1e-4), ("PreShading", 0.01)):
    shaded = caster(ramp, lit, view, 0.4, ShadingMode=getattr(hovr.vtkObjectOrderRayCaster,
                                                              mode.upper().replace("SHADING",
                                                                                   "_SHADING")))
    error = numpy.abs(pixels(shaded) - expected).max()
    print("%s on a linear field: largest difference %.2e" % (mode, error))
    c.check(plain[:, 3].max() > 0.3 and error < tolerance and not shaded.messages.warnings,
            "%s: the linear field shaded as expected (%.1e)" % (mode, error))
# Pre- and post-shading agree on Marschner-Lobb.
ml_lit = spikes()
ml_lit.ShadeOn()
post = pixels(caster(ml, ml_lit, camera, 0.05))
pre = pixels(caster(ml, ml_lit, camera, 0.05, ShadingMode=1))
print("Marschner-Lobb, pre- against post-shading: RMSE %.4f" % rmse(pre, post))
c.check(rmse(pre, post) < 0.04 and not numpy.array_equal(pre, post),
        "pre- and post-shading agree within 0.04 RMSE (they interpolate different things)")
c.finish()
