"""vtkAdaptiveSamplingOracle against a chain of VTK's own imaging filters, and from Python.

The chain computes the paper's oracle ("Adaptive Sampling in Three Dimensions for Volume
Rendering on GPUs", lines 231-236 of the paper's text: the distance to the nearest voxel whose
opacity gradient exceeds a threshold) with stock VTK 9.1 filters and numpy only:

  alpha = vtkPiecewiseFunction.GetValue of each voxel value (numpy, as floats like the filter)
  |grad alpha| per voxel: vtkImageGradientMagnitude on spacing-1 data, the volume padded by one
      linearly extrapolated layer (2 a[0] - a[1]) so that the central difference on a face is
      the one-sided difference a[1] - a[0] the filter takes (HandleBoundaries would repeat the
      edge and halve it), then cropped back
  features: vtkImageThreshold ThresholdByUpper(eps) -> 0 (features) / 1
  squared distances: vtkImageEuclideanDistance (Initialize, ConsiderAnisotropy, MaximumDistance
      the squared cap) on the real spacing
  vtkImageMathematics SquareRoot, then vtkImageThreshold replacing values above the cap by it

and the filter in OPACITY_GRADIENT mode must give the same distances. The spacing is (1, 1, s):
vtkImageEuclideanDistance in VTK 9.1 applies the spacing of its last pass (z) only, so any
other spacing would test VTK's defect (the C++ test compares fully anisotropic spacings axis by
axis). vtkImageThreshold keeps values >= eps where the filter keeps > eps: the test checks that
no gradient lies within 1e-6 of eps, so that the two agree exactly.

Then, from Python: the transfer-function spike between voxel values 10 and 20 (OPACITY_GRADIENT
sees nothing, OPACITY_RANGE everything), MIN and MAX, the range volumes kept across a
transfer-function edit and recomputed for a new input, progress events, an error for a missing
transfer function, and DistanceTransform against vtkImageEuclideanDistance on a random mask.
"""

import numpy
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkCommand, vtkFloatArray
from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
from vtkmodules.vtkImagingCore import vtkImageThreshold
from vtkmodules.vtkImagingGeneral import vtkImageEuclideanDistance, vtkImageGradientMagnitude
from vtkmodules.vtkImagingMath import vtkImageMathematics

import hovr
from hovrtesting import Checker, Messages, blobs, image_from_array

c = Checker()
SPACING = (1.0, 1.0, 1.6)


def transfer_function():
    """Two peaks, one a Hermite curve (midpoint 0.3, sharpness 0.4), and a ramp."""
    tf = vtkPiecewiseFunction()
    tf.AddPoint(0.0, 0.0)
    tf.AddPoint(40.0, 0.0)
    tf.AddPoint(60.0, 0.45, 0.3, 0.4)
    tf.AddPoint(80.0, 0.0)
    tf.AddPoint(120.0, 0.0)
    tf.AddPoint(130.0, 0.9)
    tf.AddPoint(140.0, 0.05)
    tf.AddPoint(200.0, 0.05)
    tf.AddPoint(255.0, 0.7)
    return tf


def distances(image, name="OracleDistance"):
    nx, ny, nz = image.GetDimensions()
    array = image.GetPointData().GetArray(name)
    return None if array is None else vtk_to_numpy(array).reshape(nz, ny, nx).astype(float)


def vtk_image(values, spacing=(1.0, 1.0, 1.0)):
    return image_from_array(numpy.ascontiguousarray(values), spacing)


def pad_linear(a):
    """a with one more layer on every face, 2 a[0] - a[1] (and likewise at the far end)."""
    p = numpy.pad(a, 1, mode="edge").astype(numpy.float64)
    for axis in range(3):
        lo = [slice(None)] * 3
        lo[axis] = 0
        first = [slice(None)] * 3
        first[axis] = 1
        second = [slice(None)] * 3
        second[axis] = 2
        p[tuple(lo)] = 2.0 * p[tuple(first)] - p[tuple(second)]
        hi = [slice(None)] * 3
        hi[axis] = -1
        last = [slice(None)] * 3
        last[axis] = -2
        before = [slice(None)] * 3
        before[axis] = -3
        p[tuple(hi)] = 2.0 * p[tuple(last)] - p[tuple(before)]
    return p


def chain(values, tf, eps, cap):
    """The paper's oracle by VTK filters: (distances, gradient magnitudes, feature count)."""
    table = numpy.array([tf.GetValue(float(v)) for v in range(256)])
    alpha = table[values.astype(int)].astype(numpy.float32).astype(numpy.float64)
    gradient = vtkImageGradientMagnitude()
    gradient.SetDimensionality(3)
    gradient.HandleBoundariesOn()
    gradient.SetInputData(vtk_image(pad_linear(alpha)))
    gradient.Update()
    magnitude = vtk_to_numpy(gradient.GetOutput().GetPointData().GetScalars()).reshape(
        tuple(n + 2 for n in values.shape))[1:-1, 1:-1, 1:-1]
    threshold = vtkImageThreshold()
    threshold.SetInputData(vtk_image(magnitude, SPACING))
    threshold.ThresholdByUpper(eps)
    threshold.ReplaceInOn()
    threshold.SetInValue(0)
    threshold.ReplaceOutOn()
    threshold.SetOutValue(1)
    threshold.SetOutputScalarTypeToUnsignedChar()
    edt = vtkImageEuclideanDistance()
    edt.SetInputConnection(threshold.GetOutputPort())
    edt.InitializeOn()
    edt.ConsiderAnisotropyOn()
    edt.SetMaximumDistance(cap * cap)
    root = vtkImageMathematics()
    root.SetInputConnection(edt.GetOutputPort())
    root.SetOperationToSquareRoot()
    capped = vtkImageThreshold()
    capped.SetInputConnection(root.GetOutputPort())
    capped.ThresholdByUpper(cap)
    capped.ReplaceInOn()
    capped.SetInValue(cap)
    capped.ReplaceOutOff()
    capped.Update()
    threshold.Update()
    mask = vtk_to_numpy(threshold.GetOutput().GetPointData().GetScalars())
    result = vtk_to_numpy(capped.GetOutput().GetPointData().GetScalars()).reshape(values.shape)
    return result.astype(float), magnitude, int(numpy.sum(mask == 0))


def oracle(image, tf, mode, eps, cap=None):
    f = hovr.vtkAdaptiveSamplingOracle()
    f.SetInputData(image)
    f.SetScalarOpacity(tf)
    f.SetMode(mode)
    f.SetEpsilon(eps)
    if cap is not None:
        f.AutomaticMaximumDistanceOff()
        f.SetMaximumDistance(cap)
    f.Update()
    return f, distances(f.GetOutput())


# The paper's oracle against the chain, on a volume of smooth blobs (integer values 0..255).
values = blobs(n=36, seed=5)
volume = vtk_image(values, SPACING)
tf = transfer_function()
for eps in (0.002, 0.013, 0.05):
    for cap in (8.0, 3.3):
        label = "eps %g, cap %g" % (eps, cap)
        expected, magnitude, count = chain(values, tf, eps, cap)
        c.check(numpy.min(numpy.abs(magnitude - eps)) > 1e-6,
                "%s: no gradient within 1e-6 of eps (closest %.3g)"
                % (label, numpy.min(numpy.abs(magnitude - eps))))
        c.check(0 < count < values.size, "%s: some features, not all (%d)" % (label, count))
        f, got = oracle(volume, tf, hovr.vtkAdaptiveSamplingOracle.OPACITY_GRADIENT, eps, cap)
        c.check(f.GetLastNumberOfFeaturePoints() == count,
                "%s: the chain's %d feature points (filter: %d)"
                % (label, count, f.GetLastNumberOfFeaturePoints()))
        worst = numpy.abs(got - expected).max()
        c.check(worst <= 1e-6 * cap, "%s: equals the chain (largest difference %.3g)"
                % (label, worst))
        c.check(abs(expected.max() - cap) < 1e-12 and expected.min() == 0.0,
                "%s: distances from 0 to the cap" % label)
    # OPACITY_RANGE finds every feature of the paper's test away from the faces (where a
    # one-sided difference may exceed the neighbourhood's opacity range; on this volume it
    # does not), and more: its distances are never larger, some smaller.
    _, gradient = oracle(volume, tf, hovr.vtkAdaptiveSamplingOracle.OPACITY_GRADIENT, eps)
    _, ranged = oracle(volume, tf, hovr.vtkAdaptiveSamplingOracle.OPACITY_RANGE, eps)
    c.check(numpy.all(ranged <= gradient) and numpy.any(ranged < gradient),
            "eps %g: OPACITY_RANGE distances <= OPACITY_GRADIENT distances, some smaller" % eps)

# The transfer-function spike between voxel values 10 and 20.
n = (10, 9, 8)
z, y, x = numpy.meshgrid(*(numpy.arange(k) for k in reversed(n)), indexing="ij")
alternating = numpy.where((x + y + z) % 2 == 1, 20.0, 10.0).astype(numpy.uint8)
spike = vtkPiecewiseFunction()
for point in ((0.0, 0.0), (14.0, 0.0), (15.0, 1.0), (16.0, 0.0), (255.0, 0.0)):
    spike.AddPoint(*point)
image = vtk_image(alternating, (0.5, 0.75, 1.0))
cap = numpy.float32(8 * 0.5)
f, got = oracle(image, spike, hovr.vtkAdaptiveSamplingOracle.OPACITY_GRADIENT, 0.002)
c.check(numpy.all(got == cap) and f.GetLastNumberOfFeaturePoints() == 0,
        "spike at 15, voxels 10 and 20: OPACITY_GRADIENT sees no feature (all the cap)")
f, got = oracle(image, spike, hovr.vtkAdaptiveSamplingOracle.OPACITY_RANGE, 0.002)
c.check(numpy.all(got == 0.0) and f.GetLastNumberOfFeaturePoints() == alternating.size,
        "spike at 15, voxels 10 and 20: OPACITY_RANGE sees features everywhere (all 0)")
_, got = oracle(image, spike, hovr.vtkAdaptiveSamplingOracle.MIN, 0.002)
c.check(got is not None and numpy.all(got == 0.0), "MIN: 0 everywhere")
_, got = oracle(image, spike, hovr.vtkAdaptiveSamplingOracle.MAX, 0.002)
c.check(got is not None and numpy.all(got == cap), "MAX: the cap (8 smallest spacings)")
_, got = oracle(image, spike, hovr.vtkAdaptiveSamplingOracle.MAX, 0.002, 2.5)
c.check(got is not None and numpy.all(got == 2.5), "MAX with MaximumDistance 2.5")

# The range volumes are kept across transfer-function edits and recomputed for a new input;
# progress events arrive and rise to 1.
f = hovr.vtkAdaptiveSamplingOracle()
c.check(f.GetMode() == hovr.vtkAdaptiveSamplingOracle.OPACITY_RANGE and
        f.GetEpsilon() == 0.002 and f.GetAutomaticMaximumDistance() == 1 and
        f.GetOutputArrayName() == "OracleDistance", "the documented initial values")
progress = []
f.AddObserver(vtkCommand.ProgressEvent, lambda obj, event: progress.append(obj.GetProgress()))
f.SetInputData(volume)
f.SetScalarOpacity(tf)
f.Update()
c.check(f.GetLastRecomputedRanges(), "the first update computes the ranges")
c.check(len(progress) >= 10 and progress == sorted(progress) and progress[-1] == 1.0,
        "progress events rise to 1 (%d)" % len(progress))
before = distances(f.GetOutput())
tf.AddPoint(90.0, 0.3)
f.Update()
after = distances(f.GetOutput())
c.check(not f.GetLastRecomputedRanges(), "a transfer-function edit reuses the ranges")
c.check(numpy.any(after != before), "and changes the distances")
f.SetInputData(vtk_image(values[:, :, ::-1], SPACING))
f.Update()
c.check(f.GetLastRecomputedRanges(), "a new input recomputes the ranges")

# A missing transfer function: an error and an empty output.
g = hovr.vtkAdaptiveSamplingOracle()
messages = Messages(g)
g.SetInputData(volume)
g.Update()
c.check(len(messages.errors) == 1 and "ScalarOpacity" in messages.errors[0],
        "no transfer function is reported: %s" % messages.errors)
c.check(g.GetOutput().GetNumberOfPoints() == 0, "and the output is empty")

# DistanceTransform on a random mask against vtkImageEuclideanDistance.
rng = numpy.random.default_rng(7)
mask = (rng.random((21, 26, 30)) < 0.01).astype(numpy.uint8)
spacing = (1.0, 1.0, 2.2)
cap = 7.5
distances_array = vtkFloatArray()
c.check(hovr.vtkAdaptiveSamplingOracle.DistanceTransform(
    numpy_to_vtk(mask.ravel(), deep=True), list(mask.shape[::-1]), spacing, cap,
    distances_array), "DistanceTransform accepts the mask")
edt = vtkImageEuclideanDistance()
edt.SetInputData(vtk_image(1 - mask, spacing))
edt.SetMaximumDistance(cap * cap)
edt.Update()
expected = numpy.sqrt(vtk_to_numpy(edt.GetOutput().GetPointData().GetScalars()))
got = vtk_to_numpy(distances_array).astype(float)
c.check(numpy.abs(got - expected).max() <= 1e-6 * cap,
        "DistanceTransform equals vtkImageEuclideanDistance (largest difference %.3g)"
        % numpy.abs(got - expected).max())
c.finish()
