"""Adaptive sampling in three dimensions as a user builds it in Python: vtkBlobSource ->
vtkAdaptiveSamplingOracle -> vtkAdaptiveSamplingRayCaster, parallel camera, 128 x 128, against
vtkVolumeReferenceIntegrator and against the same caster at full rate (the "min." oracle, on the
same slice grid). The extremes of the method, each with its expected outcome:

1. Sparse volume, default oracle (opacity range, epsilon 0.002), l_max = 3: at most 0.125 of the
   full rate's samples (the oracle's, and on the slices a pixel accumulates those that replace a
   NaN synthesised from outside the box at a point inside it, a band along each slice's outline
   that is long next to a 128 x 128 image), and an RMSE against the reference at most 1.5 times
   full rate's.
2. A transfer-function spike between two voxel values (a sheet where the scalar crosses 15
   between voxels of 10 and 20): the paper's opacity-gradient oracle sees no feature and the
   caster takes 8-slice segments through the sheet, which the table then thickens; the range
   oracle sees it and draws the full-rate image.
3. A single non-zero voxel: its 27-point neighbourhood are the features, the oracle is the
   Euclidean distance to them (checked at every point against a brute-force minimum), and the
   image equals the full-rate one.
4. No feature at all (a constant volume): every distance is the cap, the image is transparent,
   and inside the box only the top level samples (1/512 of the full rate), after one sample per
   pyramid pixel where the rays enter the box.
5. Fewer slices than 2^l_max (a volume two points thick seen along its thin axis): the image
   equals full rate's.
6. A transfer-function edit: the oracle recomputes its distances but not its range volumes,
   and the caster's next image follows the new function.
"""

import sys

import numpy
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData

import hovr
from hovr import io as hio
from hovrtesting import image_from_array, tf_path

SIZE = (128, 128)
failures = []


def check(ok, what):
    print(("ok:     " if ok else "FAILED: ") + what)
    if not ok:
        failures.append(what)


def rgba(image):
    return vtk_to_numpy(image.GetPointData().GetScalars()).astype(numpy.float64)


def rmse(a, b):
    return float(numpy.sqrt(numpy.mean((rgba(a) - rgba(b)) ** 2)))


def camera_for(image, direction=(1.0, -1.6, 0.9), view_up=(0.0, 0.0, 1.0)):
    return hio.default_camera(image.GetBounds(), direction=direction, view_up=view_up,
                              parallel=True)


def oracle_of(image, opacity, mode=hovr.vtkAdaptiveSamplingOracle.OPACITY_RANGE):
    oracle = hovr.vtkAdaptiveSamplingOracle()
    oracle.SetInputData(image)
    oracle.SetScalarOpacity(opacity)
    oracle.SetMode(mode)
    return oracle


def cast(image, prop, camera, minimum=False, lmax=3):
    caster = hovr.vtkAdaptiveSamplingRayCaster()
    caster.SetInputData(image)
    caster.SetVolumeProperty(prop)
    caster.SetCamera(camera)
    caster.SetImageSize(*SIZE)
    caster.SetMaximumLevel(lmax)
    if minimum:
        caster.SetOracleModeToMinimum()
    caster.Update()
    result = vtkImageData()
    result.DeepCopy(caster.GetOutput())
    return result, caster


def reference(image, prop, camera):
    integrator = hovr.vtkVolumeReferenceIntegrator()
    integrator.SetInputData(image)
    integrator.SetVolumeProperty(prop)
    integrator.SetCamera(camera)
    integrator.SetImageSize(*SIZE)
    integrator.Update()
    return integrator.GetOutput()


def spike_property(centre, width, height=0.9):
    color, opacity, _ = hio.transfer_function_from_preset({
        "RGBPoints": [0, 1, 0.6, 0.2, 100, 1, 1, 1],
        "Points": [0, 0, 0.5, 0, centre - width / 2, 0, 0.5, 0, centre, height, 0.5, 0,
                   centre + width / 2, 0, 0.5, 0, 100, 0, 0.5, 0]})
    return hio.make_volume_property(color, opacity, 1.0)


# 1. Sparse blobs, the default oracle.
source = hovr.vtkBlobSource()
source.SetDimensions(65, 65, 65)
color, opacity, _ = hio.read_transfer_function(tf_path("blobs"))
prop = hio.make_volume_property(color, opacity, 2.0 / 64)
oracle = hovr.vtkAdaptiveSamplingOracle()
oracle.SetInputConnection(source.GetOutputPort())
oracle.SetScalarOpacity(opacity)
oracle.Update()
blobs = oracle.GetOutput()
camera = camera_for(blobs)
truth = reference(blobs, prop, camera)
full, full_caster = cast(blobs, prop, camera, minimum=True)
adaptive, caster = cast(blobs, prop, camera)
samples = caster.GetNumberOfSampleOperations()
rate = caster.GetFullRateSampleOperations()
error_full, error_adaptive = rmse(full, truth), rmse(adaptive, truth)
print("blobs 65^3, %dx%d: full rate %d samples, RMSE %.3g; adaptive %d samples (%.4f), "
      "%d syntheses, RMSE %.3g, RMSE to full rate %.3g" % (
          SIZE[0], SIZE[1], rate, error_full, samples, samples / rate,
          caster.GetNumberOfSynthesisOperations(), error_adaptive, rmse(adaptive, full)))
check(full_caster.GetNumberOfSampleOperations() > rate, "the min. oracle samples more than the "
      "full rate (the pyramid's coarse levels)")
check(0 < samples <= 0.125 * rate, "the default oracle takes at most 0.125 of the full rate's "
      "samples (%.4f)" % (samples / rate))
check(error_adaptive <= 1.5 * error_full, "its RMSE against the reference is at most 1.5 times "
      "full rate's (%.3g vs %.3g)" % (error_adaptive, error_full))
check(rgba(adaptive)[:, 3].max() > 0.5, "the blobs are drawn")

# 2. A spike between voxel values: a step from 10 to 20 across one cell.
values = numpy.full((24, 24, 24), 10.0)
values[:, :, 12:] = 20.0
step_volume = image_from_array(values)
spike = spike_property(15.0, 2.0)
step_camera = camera_for(step_volume)
step_full, _ = cast(step_volume, spike, step_camera, minimum=True)
for mode, name in ((hovr.vtkAdaptiveSamplingOracle.OPACITY_GRADIENT, "opacity gradient"),
                   (hovr.vtkAdaptiveSamplingOracle.OPACITY_RANGE, "opacity range")):
    step_oracle = oracle_of(step_volume, spike.GetScalarOpacity(), mode)
    step_oracle.Update()
    features = step_oracle.GetLastNumberOfFeaturePoints()
    image, _ = cast(step_oracle.GetOutput(), spike, step_camera)
    difference = rmse(image, step_full)
    print("spike between 10 and 20, %s oracle: %d feature points, RMSE to full rate %.3g" % (
        name, features, difference))
    if mode == hovr.vtkAdaptiveSamplingOracle.OPACITY_GRADIENT:
        check(features == 0 and difference > 0.01, "the paper's oracle misses the spike between "
              "voxel values, and the image departs from full rate")
    else:
        check(features > 0 and difference < 1e-6, "the range oracle sees it: the full-rate "
              "image")
check(rgba(step_full)[:, 3].max() > 0.05, "the sheet is drawn at full rate")

# 3. A single non-zero voxel.
values = numpy.zeros((20, 20, 20))
values[9, 11, 8] = 100.0
single = image_from_array(values, spacing=(1.0, 1.0, 1.5))
dot = spike_property(60.0, 80.0, 1.0)
single_oracle = oracle_of(single, dot.GetScalarOpacity())
single_oracle.AutomaticMaximumDistanceOff()
single_oracle.SetMaximumDistance(1000.0)
single_oracle.Update()
distances = vtk_to_numpy(single_oracle.GetOutput().GetPointData().GetArray("OracleDistance"))
z, y, x = numpy.meshgrid(numpy.arange(20) * 1.5, numpy.arange(20), numpy.arange(20),
                         indexing="ij")
feature = [(k * 1.5, j, i) for k in (8, 9, 10) for j in (10, 11, 12) for i in (7, 8, 9)]
expected = numpy.min([numpy.sqrt((z - fz) ** 2 + (y - fy) ** 2 + (x - fx) ** 2)
                      for fz, fy, fx in feature], axis=0).ravel()
check(single_oracle.GetLastNumberOfFeaturePoints() == 27,
      "one voxel: its 27-point neighbourhood are the features (%d)"
      % single_oracle.GetLastNumberOfFeaturePoints())
check(numpy.abs(distances - expected).max() < 1e-5, "the oracle is the Euclidean distance to "
      "them, anisotropic spacing respected (largest deviation %.2g)"
      % numpy.abs(distances - expected).max())
single_camera = camera_for(single)
single_full, _ = cast(single, dot, single_camera, minimum=True)
single_adaptive, _ = cast(single_oracle.GetOutput(), dot, single_camera)
check(rgba(single_full)[:, 3].max() > 0.05 and rmse(single_adaptive, single_full) < 1e-6,
      "the voxel is drawn, as at full rate (RMSE %.2g)" % rmse(single_adaptive, single_full))

# 4. No feature: a constant volume.
flat = image_from_array(numpy.zeros((20, 20, 20)))
flat_oracle = oracle_of(flat, dot.GetScalarOpacity())
flat_oracle.Update()
flat_distances = vtk_to_numpy(flat_oracle.GetOutput().GetPointData().GetArray("OracleDistance"))
check(flat_oracle.GetLastNumberOfFeaturePoints() == 0 and
      numpy.all(flat_distances == numpy.float32(flat_oracle.GetLastMaximumDistance())),
      "a constant volume has no feature: every distance is the cap (%g)"
      % flat_oracle.GetLastMaximumDistance())
flat_image, flat_caster = cast(flat_oracle.GetOutput(), dot, camera_for(flat))
flat_samples = flat_caster.GetNumberOfSampleOperations()
flat_rate = flat_caster.GetFullRateSampleOperations()
# Rays reach the entry face with shrinking steps (the oracle outside is the distance to the
# box); a pixel of level l then samples once inside before the cap sends it up: at most
# sum_l 1/4^l samples per level-0 pixel on top of the top level's 1/512 of the full rate.
bound = flat_rate / 512.0 + SIZE[0] * SIZE[1] * sum(0.25 ** l for l in range(4))
print("constant volume: %d samples, %.5f of the full rate's; bound %d" % (
    flat_samples, flat_samples / flat_rate, bound))
check(rgba(flat_image).max() < 1e-7, "and draws nothing (opacity 0 at 0)")
check(flat_rate / 512.0 < flat_samples <= bound, "inside the box only the top level samples, "
      "after one sample per pyramid pixel at the entry face")

# 5. Fewer slices than 2^l_max: two points thick, seen along the thin axis.
layer = numpy.fromfunction(
    lambda j, i: 100.0 * numpy.exp(-((i - 10) ** 2 + (j - 12) ** 2) / 30.0), (24, 24))
thin = image_from_array(numpy.stack([layer, layer]))
thin_camera = camera_for(thin, direction=(0.05, 0.03, 1.0), view_up=(0.0, 1.0, 0.0))
thin_oracle = oracle_of(thin, dot.GetScalarOpacity())
thin_oracle.Update()
thin_full, thin_full_caster = cast(thin, dot, thin_camera, minimum=True)
thin_adaptive, thin_caster = cast(thin_oracle.GetOutput(), dot, thin_camera, lmax=4)
print("two points thick: %d slices" % thin_caster.GetNumberOfSlices())
check(thin_caster.GetNumberOfSlices() == 16 + 1 and rgba(thin_full)[:, 3].max() > 0.01,
      "fewer slices than 2^4 padded to one block of 16 (%d slice indices), something drawn"
      % thin_caster.GetNumberOfSlices())
check(rmse(thin_adaptive, thin_full) < 1e-6, "the image equals full rate's (RMSE %.2g)"
      % rmse(thin_adaptive, thin_full))

# 6. A transfer-function edit.
opacity.AddPoint(0.3, 0.9)
oracle.Update()
check(not oracle.GetLastRecomputedRanges(), "an opacity edit recomputes the distances, not the "
      "range volumes")
edited, _ = cast(oracle.GetOutput(), prop, camera)
edited_full, _ = cast(oracle.GetOutput(), prop, camera, minimum=True)
check(rmse(edited, adaptive) > 1e-3 and rmse(edited, edited_full) <= 2.0 * rmse(adaptive, full)
      + 1e-4, "the caster follows the edit (RMSE to the old image %.3g, to the new full rate "
      "%.3g)" % (rmse(edited, adaptive), rmse(edited, edited_full)))

if failures:
    print("%d check(s) failed" % len(failures))
    sys.exit(1)
