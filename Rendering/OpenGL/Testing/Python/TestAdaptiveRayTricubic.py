"""vtkAdaptiveRayVolumeMapper with Reconstruction RECONSTRUCTION_TRICUBIC_BSPLINE (the cubic
B-spline approximation of the data from 8 trilinear fetches) and the 16-bit upload of 8-bit
scalars.

The CPU model of the B-spline field is written here in numpy, independently of the GLSL: the
uniform cubic B-spline weights of each axis over the 4 x 4 x 4 points around a position, the
data continued beyond the outermost points by copies of them (clamp-to-edge addressing). A
fine-step integration (midpoint rule, 1/32 voxel; the transfer functions tabulated densely by
VTK itself) along the pixel rays of hovrtesting.pixel_rays integrates either field.

1. Small volume of smoothed noise (float, 20^3), spike transfer function, 40 x 40 images,
   oblique parallel and perspective cameras, OracleMode MINIMUM at 1/4 voxel: the tricubic GPU
   image is compared with the fine integration of the B-spline field. Its tolerance comes from
   the same pipeline with the trilinear field: trilinear MINIMUM against the fine integration
   of the trilinear field measures what the tables, the slice grid and the step cost; the
   tricubic error may be at most twice that plus 1e-4 (the B-spline is smoother than the
   trilinear field, so its linear-between-samples segments are, if anything, more accurate).
   The check can fail: the tricubic image must be at least 5 times farther from the trilinear
   field's integration than from the B-spline's.
2. A checkerboard of single voxels (0 and 255): the B-spline flattens it to 127.5 +- 4.7
   while the trilinear field spans 0 to 255, so the two images must differ (RMSE > 0.05),
   and the tricubic one must still match the B-spline integration as in part 1.
3. A linear ramp in x and y (constant along z): the B-spline reproduces linear functions, so
   where the rays stay more than one voxel inside the x and y faces (the clamp-to-edge copies
   break linearity only within one voxel of a face; along z the ramp is constant, so the copies
   are exact) the tricubic image equals the trilinear one up to float rounding (max 2e-3).
4. The oracle still drives the skipping with the tricubic sampler: fewer than half of
   MINIMUM's samples on sparse blobs, the RMSE to the tricubic MINIMUM image below 5e-3, and
   the oracle in use.
5. 8-bit data: the same values as uint8 (or int8) and as float32 give the same image (max
   difference 2e-3, RMSE 2e-4), trilinear and tricubic, and so do uint8 values changed in
   place between two frames of one mapper, since the 8-bit values go up as a 16-bit copy,
   whose texels hold them exactly (v * 257 / 65535 = v / 255). An 8-bit texture, which Mesa's
   llvmpipe filters at 8-bit precision, quantises the interpolated values to 1/255 of the
   range, an error of up to a whole data unit that sharp spikes of the transfer function
   turn into visible colour errors.
"""

import math

import numpy
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import VTK_SIGNED_CHAR
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkRenderingCore import vtkVolume

import hovr
from hovr import io as hio
from hovr import methods as hm
from hovrtesting import (Checker, image_from_array, offscreen_window, pixel_rays, rgba,
                         spike_property, trilinear)

c = Checker()
renderer = hm.Renderer()
SIZE = (40, 40)
FINE = 1.0 / 32.0  # independent step, in voxels
STEP = 0.25  # GPU step, in voxels


class Adaptive(hm.Method):
    """vtkAdaptiveRayVolumeMapper with its settings."""

    def __init__(self, tricubic, lmax=3, minimum=True, table=256):
        super().__init__("adaptive-ray", "")
        self.tricubic, self.lmax, self.minimum, self.table = tricubic, lmax, minimum, table

    def make_mapper(self):
        mapper = hovr.vtkAdaptiveRayVolumeMapper()
        if self.tricubic:
            mapper.SetReconstructionToTricubicBSpline()
        mapper.SetMaximumLevel(self.lmax)
        mapper.SetOracleMode(mapper.ORACLE_MINIMUM if self.minimum else mapper.ORACLE_ARRAY)
        mapper.SetTableSize(self.table)
        mapper.SetCountSamples(True)
        return mapper

    def statistics(self, mapper):
        return {"gpu_samples": mapper.GetLastFrameSampleCount(),
                "used_oracle": bool(mapper.GetLastFrameUsedOracle()),
                "reconstruction": mapper.GetReconstruction()}


def bspline(values, p):
    """The uniform cubic B-spline approximation of values[k, j, i] at the index-space points p
    (n x 3), the data continued beyond the outermost points by copies of them."""
    shape = numpy.array(values.shape[::-1])  # nx, ny, nz
    base = numpy.floor(p).astype(int)
    f = p - base
    weights = [(1 - f) ** 3 / 6, (3 * f ** 3 - 6 * f ** 2 + 4) / 6,
               (-3 * f ** 3 + 3 * f ** 2 + 3 * f + 1) / 6, f ** 3 / 6]
    out = numpy.zeros(len(p))
    for a in range(4):
        ix = numpy.clip(base[:, 0] + a - 1, 0, shape[0] - 1)
        for b in range(4):
            iy = numpy.clip(base[:, 1] + b - 1, 0, shape[1] - 1)
            for d in range(4):
                iz = numpy.clip(base[:, 2] + d - 1, 0, shape[2] - 1)
                out += weights[a][:, 0] * weights[b][:, 1] * weights[d][:, 2] * values[iz, iy, ix]
    return out


def fine_image(image, prop, camera, field, fine=FINE):
    """Fine-step integration of ``field`` (trilinear or bspline) along the pixel rays: RGBA
    per pixel, x fastest, as the rendered images."""
    nx, ny, nz = image.GetDimensions()
    values = vtk_to_numpy(image.GetPointData().GetScalars()).astype(numpy.float64)
    values = values.reshape(nz, ny, nx)
    spacing = numpy.array(image.GetSpacing())
    origin = numpy.array(image.GetOrigin())
    lo, hi = origin, origin + spacing * (numpy.array([nx, ny, nz]) - 1)
    smin, smax = float(values.min()), float(values.max())
    table = numpy.linspace(smin, smax, 65537)
    color = numpy.array([prop.GetRGBTransferFunction().GetColor(s) for s in table])
    alpha = numpy.zeros(len(table))
    prop.GetScalarOpacity().GetTable(smin, smax, len(table), alpha)
    alpha = numpy.clip(alpha, 0.0, 1.0 - 1e-9)
    tau_table = -numpy.log1p(-alpha) / prop.GetScalarOpacityUnitDistance()
    origins, directions = pixel_rays(camera, *SIZE)
    with numpy.errstate(divide="ignore", invalid="ignore"):
        ta = (lo - origins) / directions
        tb = (hi - origins) / directions
    t0 = numpy.max(numpy.where(numpy.isfinite(ta), numpy.minimum(ta, tb), -numpy.inf), axis=1)
    t1 = numpy.min(numpy.where(numpy.isfinite(ta), numpy.maximum(ta, tb), numpy.inf), axis=1)
    t0 = numpy.maximum(t0, 0.0)
    h = fine * spacing.min()
    result = numpy.zeros((len(origins), 4))
    for r in numpy.nonzero(t1 > t0)[0]:
        count = int(math.ceil((t1[r] - t0[r]) / h))
        step = (t1[r] - t0[r]) / count
        t = t0[r] + (numpy.arange(count) + 0.5) * step
        p = (origins[r] + t[:, None] * directions[r] - origin) / spacing
        v = field(values, p)
        tau = numpy.interp(v, table, tau_table)
        rgb = numpy.stack([numpy.interp(v, table, color[:, a]) for a in range(3)], axis=1)
        piece_alpha = -numpy.expm1(-tau * step)
        transmittance = numpy.exp(-numpy.concatenate([[0.0], numpy.cumsum(tau * step)[:-1]]))
        weights = transmittance * piece_alpha
        result[r, :3] = (weights[:, None] * rgb).sum(axis=0)
        result[r, 3] = 1.0 - transmittance[-1] * (1.0 - piece_alpha[-1])
    return result


def flat(image):
    return rgba(image).reshape(-1, 4).astype(numpy.float64)


def rmse(a, b):
    return float(numpy.sqrt(((a - b) ** 2).mean()))


def smoothed_noise(n=20, seed=7):
    """Noise smoothed by a 3-point box filter along each axis, scaled to [0, 255], float."""
    rng = numpy.random.default_rng(seed)
    v = rng.uniform(0.0, 1.0, (n + 2, n + 2, n + 2))
    for axis in range(3):
        v = (numpy.roll(v, 1, axis) + v + numpy.roll(v, -1, axis)) / 3.0
    v = v[1:-1, 1:-1, 1:-1]
    v = 255.0 * (v - v.min()) / (v.max() - v.min())
    return v.astype(numpy.float32)


def cameras(bounds):
    return {"parallel": hio.default_camera(bounds, parallel=True),
            "perspective": hio.default_camera(bounds)}


def against_fine(label, volume, prop, camera):
    """Part 1's comparison: returns the tricubic and trilinear images and the errors."""
    scene = hm.Scene(volume, prop, camera, SIZE)
    linear, cubic = renderer.render_interleaved(
        [(Adaptive(False), STEP), (Adaptive(True), STEP)], scene)
    c.check(cubic.extra["reconstruction"] == 1 and linear.extra["reconstruction"] == 0,
            label + ": the mappers report their reconstruction")
    fine_linear = fine_image(volume, prop, camera, trilinear)
    fine_cubic = fine_image(volume, prop, camera, bspline)
    e_linear = rmse(flat(linear.image), fine_linear)
    e_cubic = rmse(flat(cubic.image), fine_cubic)
    e_cross = rmse(flat(cubic.image), fine_linear)
    print("%s: RMSE tricubic to the B-spline field %.6f (to the trilinear field %.6f); "
          "trilinear to the trilinear field %.6f; mean alpha %.3f" % (
              label, e_cubic, e_cross, e_linear, fine_cubic[:, 3].mean()))
    c.check(fine_cubic[:, 3].max() > 0.3, label + ": the view shows something")
    c.check(e_cubic <= 2.0 * e_linear + 1e-4,
            "%s: tricubic within 2 x trilinear's error of its own field + 1e-4 (%.6f vs %.6f)"
            % (label, e_cubic, e_linear))
    c.check(e_cross >= 5.0 * e_cubic,
            "%s: the comparison tells the fields apart (%.6f >= 5 x %.6f)" % (
                label, e_cross, e_cubic))
    return cubic.image, linear.image


# 1. Smoothed noise.
prop = spike_property()
noise = image_from_array(smoothed_noise())
for label, camera in cameras(noise.GetBounds()).items():
    against_fine("noise, " + label, noise, prop, camera)

# 2. Checkerboard.
n = 16
k, j, i = numpy.meshgrid(numpy.arange(n), numpy.arange(n), numpy.arange(n), indexing="ij")
board = image_from_array((255.0 * ((i + j + k) % 2)).astype(numpy.float32))
board_prop = spike_property(centres=(128,), width=12, height=0.5, ramp=250, top=255, unit=4.0)
for label, camera in cameras(board.GetBounds()).items():
    cubic, linear = against_fine("checkerboard, " + label, board, board_prop, camera)
    difference = rmse(flat(cubic), flat(linear))
    c.check(difference > 0.05, "checkerboard, %s: tricubic and trilinear differ (RMSE %.4f)" % (
        label, difference))

# 3. A ramp in x and y, seen obliquely through the z faces of a volume long in x and y.
nx, ny, nz = 40, 40, 12
k, j, i = numpy.meshgrid(numpy.arange(nz), numpy.arange(ny), numpy.arange(nx), indexing="ij")
ramp = image_from_array((2.0 * i + 3.0 * j).astype(numpy.float32))
ramp_prop = spike_property(centres=(40, 90, 140), width=20, height=0.3, ramp=170, top=200,
                           unit=2.0)
bounds = ramp.GetBounds()
ramp_camera = hio.default_camera(bounds, direction=(0.25, 0.2, 1.0), view_up=(0, 1, 0),
                                 parallel=True)
scene = hm.Scene(ramp, ramp_prop, ramp_camera, SIZE)
linear, cubic = renderer.render_interleaved(
    [(Adaptive(False), STEP), (Adaptive(True), STEP)], scene)
origins, directions = pixel_rays(ramp_camera, *SIZE)
# Where each ray crosses the z faces (it enters and leaves through them where it stays inside).
inside = numpy.ones(len(origins), bool)
for z in (bounds[4], bounds[5]):
    t = (z - origins[:, 2]) / directions[:, 2]
    p = origins + t[:, None] * directions
    inside &= (p[:, 0] > 1.0) & (p[:, 0] < nx - 2.0) & (p[:, 1] > 1.0) & (p[:, 1] < ny - 2.0)
a, b = flat(cubic.image), flat(linear.image)
peak = float(numpy.abs(a[inside] - b[inside]).max())
outside = float(numpy.abs(a[~inside] - b[~inside]).max())
print("ramp: %d interior rays, max difference %.2e there, %.2e at the borders; alpha there "
      "%.3f to %.3f" % (inside.sum(), peak, outside, a[inside, 3].min(), a[inside, 3].max()))
c.check(inside.sum() > 200 and numpy.median(a[inside, 3]) > 0.1,
        "ramp: interior rays see the ramp")
c.check(peak <= 2e-3, "ramp: tricubic equals trilinear inside (max difference %.2e)" % peak)

# 4. The oracle with the tricubic sampler on sparse blobs.
g = numpy.arange(48, dtype=float)
z, y, x = numpy.meshgrid(g, g, g, indexing="ij")
v = numpy.zeros_like(x)
for centre, radius in (((14, 20, 30), 4.0), ((32, 30, 16), 5.0), ((24, 12, 12), 3.0)):
    v += numpy.exp(-((x - centre[0]) ** 2 + (y - centre[1]) ** 2 + (z - centre[2]) ** 2) /
                   (2 * radius * radius))
v = 255.0 * v / v.max()
v[v < 2.0] = 0.0
blobs = image_from_array(v.astype(numpy.float32))
oracle = hovr.vtkAdaptiveSamplingOracle()
oracle.SetInputData(blobs)
oracle.SetScalarOpacity(prop.GetScalarOpacity())
oracle.SetAutomaticMaximumDistance(0)
oracle.SetMaximumDistance(8.0)
oracle.Update()
blob_data = oracle.GetOutput()
for label, camera in cameras(blob_data.GetBounds()).items():
    scene = hm.Scene(blob_data, prop, camera, (64, 64))
    minimum, adaptive = renderer.render_interleaved(
        [(Adaptive(True), 0.5), (Adaptive(True, minimum=False), 0.5)], scene)
    counts = (minimum.extra["gpu_samples"], adaptive.extra["gpu_samples"])
    error = rmse(flat(adaptive.image), flat(minimum.image))
    print("blobs, %s: tricubic samples MINIMUM %d, oracle %d; RMSE %.6f; mean alpha %.3f" % (
        label, counts[0], counts[1], error, flat(minimum.image)[:, 3].mean()))
    c.check(adaptive.extra["used_oracle"], "blobs, %s: the oracle is used" % label)
    c.check(0 < counts[1] < 0.5 * counts[0], "blobs, %s: the oracle halves the samples at least "
            "(%d of %d)" % (label, counts[1], counts[0]))
    c.check(error < 5e-3, "blobs, %s: the oracle keeps the tricubic image (RMSE %.6f)" % (
        label, error))

# 5. 8-bit data against the same values in float: unsigned, signed (values - 128, with the
# transfer function moved along), and unsigned data changed in place after a first frame (the
# 16-bit copy must follow).
values = numpy.round(smoothed_noise(24, seed=11))
changed = numpy.round(smoothed_noise(24, seed=12))
shifted = spike_property(centres=(44 - 128, 104 - 128), ramp=180 - 128, top=127)
cases = [("uint8", values, numpy.uint8, prop), ("int8", values - 128.0, numpy.int8, shifted)]
camera = hio.default_camera(image_from_array(values).GetBounds())


def eight_bit_check(label, a, b):
    peak, error = float(numpy.abs(a - b).max()), rmse(a, b)
    print("8-bit, %s: max difference to float %.2e, RMSE %.2e; mean alpha %.3f" % (
        label, peak, error, a[:, 3].mean()))
    c.check(a[:, 3].max() > 0.3, "8-bit, %s: the view shows something" % label)
    c.check(peak <= 2e-3 and error <= 2e-4,
            "8-bit, %s: the 8-bit image equals the float one (max %.2e, RMSE %.2e)" % (
                label, peak, error))


def typed_image(data, dtype):
    """image_from_array with int8 as VTK_SIGNED_CHAR (numpy_to_vtk makes VTK_CHAR of it, which
    VTK's ray caster refuses as platform dependent)."""
    image = image_from_array(data.astype(dtype))
    if dtype == numpy.int8:
        array = numpy_to_vtk(data.astype(numpy.int8).ravel(), deep=1,
                             array_type=VTK_SIGNED_CHAR)
        array.SetName("scalars")
        image.GetPointData().SetScalars(array)
    return image


for tricubic in (False, True):
    name = "tricubic" if tricubic else "trilinear"
    for kind, data, dtype, own in cases:
        images = [renderer.render(Adaptive(tricubic), hm.Scene(typed_image(data, t), own,
                                                               camera, (64, 64)), 0.5).image
                  for t in (numpy.float32, dtype)]
        eight_bit_check("%s %s" % (kind, name), flat(images[0]), flat(images[1]))

# In place: one mapper, two frames.
window, view = offscreen_window((1, 1))
window.SetMultiSamples(0)
window.SetAlphaBitPlanes(1)
view.SetBackground(0.0, 0.0, 0.0)
view.SetBackgroundAlpha(0.0)
window.Render()
window.SetSize(64, 64)
capture = hovr.vtkFloatRGBARenderCapture()
capture.Attach(window)
mapper = hovr.vtkAdaptiveRayVolumeMapper()
mapper.SetOracleModeToMinimum()
mapper.SetSampleDistance(0.5)
mapper.SetTableSize(256)
in_place = image_from_array(values.astype(numpy.uint8))
mapper.SetInputData(in_place)
actor = vtkVolume()
actor.SetMapper(mapper)
actor.SetProperty(prop)
view.AddVolume(actor)
view.GetActiveCamera().DeepCopy(camera)
view.ResetCameraClippingRange()
window.Render()
array = in_place.GetPointData().GetScalars()
vtk_to_numpy(array)[:] = changed.ravel().astype(numpy.uint8)
array.Modified()
window.Render()
frame = vtkImageData()
capture.Capture(frame)
window.Finalize()
expected = renderer.render(Adaptive(False), hm.Scene(image_from_array(
    changed.astype(numpy.float32)), prop, camera, (64, 64)), 0.5).image
eight_bit_check("uint8 changed in place", flat(expected), flat(frame))

renderer.close()
c.finish()
