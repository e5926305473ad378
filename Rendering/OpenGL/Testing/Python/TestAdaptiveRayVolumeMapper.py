"""vtkAdaptiveRayVolumeMapper: skipping along rays with an oracle, on the GPU.

Scenes: sparse Gaussian blobs in empty space (generated here, float, 1-voxel spacing) with the
spike transfer function of the tests (spikes 8 values wide at 44 and 104, a ramp from 180),
128 x 128 float images, tables of 256 entries unless said.

1. OracleMode MINIMUM is first-order pre-integration at step Delta on the slice grid. In an
   axis-aligned parallel view every ray enters on slice 0; with the camera a whole number of
   steps from that face, the slices are also vtkPreIntegrationVolumeMapper's samples (at whole
   steps from the camera's plane), so the image must be that mapper's up to the tables: this mapper's
   (front, back) tables and that one's (centre, chord) tables both converge to the exact
   segment model on that grid (vtkPreIntegrationRayCaster with ExactSegments). With 1024
   entries the image is within 2e-4 RMSE of the exact model, at most a third of its distance
   with 256 entries (the difference is the tables' and shrinks with them), and within 3e-4 of
   vtkPreIntegrationVolumeMapper's. (On this smooth volume the exact model at one voxel is
   already within about 2e-5 of the reference, so this part checks the tables, their lookup
   and the compositing rather than the placement of the slices; parts 3 and 4 check that.)
2. With the oracle of vtkAdaptiveSamplingOracle (Sec. 3.4's distance to the nearest opacity
   feature, l_max 3), parallel and perspective oblique views at 1 and 1/2 voxel: the RMSE
   against vtkVolumeReferenceIntegrator stays within 5% (plus 2e-5) of the MINIMUM image's
   and within 1.25 times vtkPreIntegrationVolumeMapper's at the same step (skipping happens
   where the transfer function is transparent, so it costs no accuracy), while the samples
   counted on the GPU drop below half of MINIMUM's.
3. Constant oracles, exact counts: in the axis-aligned view each ray crosses the same slices,
   so the GPU's sample count must be the number of rays times the slices that
   vtkAdaptiveSamplingRayCaster.NextSampleSlice visits from slice 0 (the CPU's closed form of
   the skip rule), for d in slices of 1.5, 2.5, 4.5, 7 and 1e6 and l_max 0, 3 and 4.
4. d >= 2^l_max everywhere: every segment spans 2^l_max slices, from the table of that length,
   so the image equals MINIMUM's at a step 2^l_max times longer (the volume spans a multiple
   of it) to float rounding (max 1e-4).
5. Tables are uploaded (GetTableBuildCount) on the first frame and again exactly when the
   colour or opacity function, the unit distance, the sample distance, MaximumLevel or the
   oracle mode (the number of layers) changes; not for re-renders or camera moves.
"""

import math

import numpy
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkRenderingCore import vtkVolume, vtkVolumeProperty

import hovr
from hovr import io as hio
from hovr import methods as hm
from hovrtesting import (Checker, cast_image, image_from_array, offscreen_window, rgba,
                         spike_property, with_oracle)

c = Checker()
renderer = hm.Renderer()
SIZE = (128, 128)


def sparse_blobs(n=65, seed=5, count=12):
    """Gaussian blobs in empty space (exactly 0 below 2 of 255), indexed [z, y, x], float."""
    rng = numpy.random.default_rng(seed)
    g = numpy.arange(n, dtype=float)
    z, y, x = numpy.meshgrid(g, g, g, indexing="ij")
    v = numpy.zeros_like(x)
    for _ in range(count):
        centre = rng.uniform(0.2 * n, 0.8 * n, 3)
        radius = rng.uniform(0.04 * n, 0.08 * n)
        v += rng.uniform(0.6, 1.0) * numpy.exp(
            -((x - centre[0]) ** 2 + (y - centre[1]) ** 2 + (z - centre[2]) ** 2) /
            (2 * radius * radius))
    v = 255.0 * v / v.max()
    v[v < 2.0] = 0.0
    return v.astype(numpy.float32)


class Adaptive(hm.Method):
    """vtkAdaptiveRayVolumeMapper with its settings; keeps the mapper."""

    def __init__(self, lmax=3, minimum=False, table=256):
        super().__init__("adaptive-ray", "")
        self.lmax, self.minimum, self.table = lmax, minimum, table
        self.mapper = None

    def make_mapper(self):
        mapper = hovr.vtkAdaptiveRayVolumeMapper()
        mapper.SetMaximumLevel(self.lmax)
        mapper.SetOracleMode(mapper.ORACLE_MINIMUM if self.minimum else mapper.ORACLE_ARRAY)
        mapper.SetTableSize(self.table)
        mapper.SetCountSamples(True)
        self.mapper = mapper
        return mapper

    def statistics(self, mapper):
        return {"gpu_samples": mapper.GetLastFrameSampleCount(),
                "used_oracle": bool(mapper.GetLastFrameUsedOracle())}


class PreInt1(hm.PreIntegrationMethod):
    """First-order vtkPreIntegrationVolumeMapper with a fixed table size; keeps its table."""

    def __init__(self, table=256):
        super().__init__("preint1", "", 1)
        self.size, self.table = table, None

    def make_mapper(self):
        mapper = super().make_mapper()
        mapper.SetTableSize(self.size)
        return mapper

    def statistics(self, mapper):
        self.table = mapper.GetActiveTable()
        return {}


def rmse(a, b):
    return hm.compare(a, b)[0]["rmse"]


def max_error(a, b):
    return float(numpy.abs(rgba(a) - rgba(b)).max())


def with_constant_oracle(image, value):
    out = image.NewInstance()
    out.ShallowCopy(image)
    array = numpy_to_vtk(numpy.full(image.GetNumberOfPoints(), value, numpy.float32), deep=1)
    array.SetName("OracleDistance")
    out.GetPointData().AddArray(array)
    return out


prop = spike_property()
volume = image_from_array(sparse_blobs())
data = with_oracle(volume, prop)
bounds = data.GetBounds()
axis_camera = hio.default_camera(bounds, direction=(0, 0, 1), view_up=(0, 1, 0), parallel=True)
# A whole number of unit steps from the camera's plane to the front face (z = bounds[5]).
position = list(axis_camera.GetPosition())
position[2] = bounds[5] + math.ceil(position[2] - bounds[5])
axis_camera.SetPosition(position)
axis_scene = hm.Scene(data, prop, axis_camera, SIZE)

# 1. MINIMUM against first-order pre-integration on the same grid.
reference = renderer.render("reference", axis_scene, 1.0).image
distances = {}
for size in (256, 1024):
    preint = PreInt1(size)
    first = renderer.render(preint, axis_scene, 1.0).image
    minimum = renderer.render(Adaptive(minimum=True, table=size), axis_scene, 1.0)
    exact = cast_image(axis_scene, preint.table, 1, 1.0, exact=True)
    distances[size] = (rmse(minimum.image, exact), rmse(minimum.image, first))
    print("MINIMUM, table %d: to the exact segments %.6f, to preint1 %.6f; preint1 to the exact "
          "segments %.6f; the exact segments to the reference %.6f" % (
              size, distances[size][0], distances[size][1], rmse(first, exact),
              rmse(exact, reference)))
c.check(distances[1024][0] <= 2e-4 and distances[1024][0] <= distances[256][0] / 3.0,
        "MINIMUM converges to the exact first-order segments on VTK's grid (%.6f with 1024 "
        "entries, %.6f with 256)" % (distances[1024][0], distances[256][0]))
c.check(distances[1024][1] <= 3e-4,
        "MINIMUM equals preint1 up to the tables (RMSE %.6f with 1024 entries)" %
        distances[1024][1])

# 2. The oracle against the reference, parallel and perspective.
for parallel in (True, False):
    camera = hio.default_camera(bounds, parallel=parallel)
    scene = hm.Scene(data, prop, camera, SIZE)
    reference = renderer.render("reference", scene, 1.0).image
    for step in (1.0, 0.5):
        runs = [(PreInt1(), step), (Adaptive(minimum=True), step), (Adaptive(), step)]
        first, minimum, adaptive = renderer.render_interleaved(runs, scene)
        errors = [rmse(r.image, reference) for r in (first, minimum, adaptive)]
        counts = [minimum.extra["gpu_samples"], adaptive.extra["gpu_samples"]]
        what = "%s, step %g" % ("parallel" if parallel else "perspective", step)
        print("%s: RMSE preint1 %.6f, MINIMUM %.6f, oracle %.6f; samples MINIMUM %d, oracle %d "
              "(preint1's fixed step: %d)" % (what, errors[0], errors[1], errors[2], counts[0],
                                              counts[1], first.samples_per_frame))
        c.check(adaptive.extra["used_oracle"], what + ": the oracle is used")
        c.check(errors[2] <= 1.05 * errors[1] + 2e-5,
                "%s: the oracle keeps MINIMUM's accuracy (%.6f vs %.6f)" % (
                    what, errors[2], errors[1]))
        c.check(errors[2] <= 1.25 * errors[0],
                "%s: within 1.25 x preint1's error (%.6f vs %.6f)" % (what, errors[2], errors[0]))
        c.check(0 < counts[1] < 0.5 * counts[0],
                "%s: the oracle halves the samples at least (%d of %d)" % (
                    what, counts[1], counts[0]))

# 3. Constant oracles: exact counts. A step of 0.96 puts the exit face between slices 66 and
# 67, away from any rounding; a long unit distance keeps every ray below the opacity at which
# early termination would shorten it.
step = 0.96
last = int(numpy.floor(64.0 / step))
thin = spike_property(unit=50.0)
thin_scene = hm.Scene(volume, thin, axis_camera, SIZE)
minimum = renderer.render(Adaptive(minimum=True), thin_scene, step)
rays, remainder = divmod(minimum.extra["gpu_samples"], last + 1)
c.check(rays > 1000 and remainder == 0 and rgba(minimum.image)[..., 3].max() < 0.9,
        "MINIMUM samples every slice 0..%d of each ray (%d samples)" % (
            last, minimum.extra["gpu_samples"]))
for lmax in (0, 3, 4):
    for d in (1.5, 2.5, 4.5, 7.0, 1e6):
        scene = hm.Scene(with_constant_oracle(volume, d * step), thin, axis_camera, SIZE)
        count = renderer.render(Adaptive(lmax=lmax), scene, step).extra["gpu_samples"]
        per_ray, i = 1, 0
        while True:
            i = hovr.vtkAdaptiveSamplingRayCaster.NextSampleSlice(i, d, lmax)
            if i > last:
                break
            per_ray += 1
        c.check(count == rays * per_ray,
                "d = %g slices, l_max %d: %d samples = %d rays x %d (got %d)" % (
                    d, lmax, rays * per_ray, rays, per_ray, count))

# 4. d >= 2^l_max everywhere: MINIMUM at 2^l_max times the step.
for lmax in (2, 3):
    scene = hm.Scene(with_constant_oracle(volume, 1e6), prop, axis_camera, SIZE)
    skipping = renderer.render(Adaptive(lmax=lmax), scene, 1.0).image
    coarse = renderer.render(Adaptive(minimum=True), axis_scene, 2.0 ** lmax).image
    difference = max_error(skipping, coarse)
    c.check(difference <= 1e-4 and rgba(coarse)[..., 3].max() > 0.5,
            "l_max %d, d >= 2^l_max: MINIMUM's image at step %d (max difference %.2g)" % (
                lmax, 2 ** lmax, difference))

# 5. Table uploads.
window, view = offscreen_window((64, 64))
mapper = hovr.vtkAdaptiveRayVolumeMapper()
mapper.SetInputData(data)
mapper.SetSampleDistance(1.0)
mapper.SetTableSize(64)
own = vtkVolumeProperty()
own.DeepCopy(prop)
actor = vtkVolume()
actor.SetMapper(mapper)
actor.SetProperty(own)
view.AddVolume(actor)
view.GetActiveCamera().DeepCopy(axis_camera)
view.ResetCameraClippingRange()
expected = 0


def frames(change, rebuilds, what):
    global expected
    change()
    window.Render()
    expected += rebuilds
    c.check(mapper.GetTableBuildCount() == expected,
            "%s: %d uploads in all, got %d" % (what, expected, mapper.GetTableBuildCount()))
    window.Render()
    c.check(mapper.GetTableBuildCount() == expected, what + ": none on the next frame")


frames(lambda: None, 1, "first frame")
c.check(mapper.GetNumberOfTables() == 8 and mapper.GetEffectiveTableSize() == 64,
        "8 layers of 64 x 64 entries for l_max 3")
frames(lambda: view.GetActiveCamera().Azimuth(30.0), 0, "camera moved")
frames(lambda: own.GetRGBTransferFunction().AddRGBPoint(50.0, 1.0, 0.0, 0.0), 1, "colour edit")
frames(lambda: own.GetScalarOpacity().AddPoint(120.0, 0.3), 1, "opacity edit")
frames(lambda: own.SetScalarOpacityUnitDistance(2.0), 1, "unit distance")
frames(lambda: mapper.SetSampleDistance(0.5), 1, "sample distance")
frames(lambda: mapper.SetMaximumLevel(2), 1, "MaximumLevel 2")
c.check(mapper.GetNumberOfTables() == 4, "4 layers for l_max 2")
frames(lambda: mapper.SetOracleModeToMinimum(), 1, "MINIMUM (one layer)")
c.check(mapper.GetNumberOfTables() == 1, "1 layer for MINIMUM")
frames(lambda: mapper.SetCountSamples(True), 0, "counting switched on")
window.Finalize()

renderer.close()
c.finish()
