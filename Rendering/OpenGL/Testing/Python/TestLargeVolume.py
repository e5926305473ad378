"""The GPU methods at 512^3 points, where textures hold 512 MiB and float positions round 8
times more coarsely than at 64^3, against the reference on a sample of the pixels, held to the
limits the small-volume tests hold.

The volume is Marschner-Lobb on 512^3 points (float), generated here; the image is 64 x 64 and
the reference integrates a seeded half of its pixels (vtkVolumeReferenceIntegrator::PixelFraction).
- Analytic isosurface, maximum and minimum projections (TestAnalyticVolumeMapper): hit/miss
  agreement on 99.9% of the pixels, the depth within 1e-3 voxel on every hit apart from grazing
  ones and its 99th percentile below 1e-4 voxel, the extremum within 1e-3 of the data range.
- First- and second-order pre-integration (TestPreIntegrationRayCaster): the CPU twin draws the
  GPU's image, to an RMSE of at most 2e-4, and the image is as far from the reference as the
  exact segment model of its order is, within the table's own error and that difference. (The
  small test's other bound, a tenth of the table's error, does not scale: at 512^3 one voxel
  changes the scalar so little that the table is exact to 6e-5, below the 2.5e-5 that the
  texture unit's 8-bit interpolation weights leave between GPU and twin.)
- Adaptive sampling along rays (TestAdaptiveRayVolumeMapper): the oracle keeps the accuracy of
  its own full rate (MINIMUM), within 1.05 x + 2e-5.
"""

import time

import hovr
from hovr import io as hio
from hovr import methods as hm
from hovrtesting import Checker, cast_image, tf_path

c = Checker()
SIZE = (64, 64)
POINTS = 512
renderer = hm.Renderer()
reference = hm.get_method("reference", settings={"pixel_fraction": 0.5, "pixel_seed": 5})

start = time.perf_counter()
source = hovr.vtkMarschnerLobbSource()
source.SetDimensions(POINTS, POINTS, POINTS)
source.Update()
volume = source.GetOutput()
low, high = volume.GetPointData().GetScalars().GetRange()
camera = hio.default_camera(volume.GetBounds())
print("volume %d^3 in %.1f s" % (POINTS, time.perf_counter() - start))


def scene_for(blend, tf, unit=0.05):
    color, opacity, _ = hio.read_transfer_function(tf_path(tf))
    prop = hio.make_volume_property(color, opacity, unit)
    if blend == "iso":
        prop.ShadeOn()
        prop.GetIsoSurfaceValues().SetValue(0, low + 0.5 * (high - low))
    return hm.Scene(volume, prop, camera, SIZE, blend)


pixels = SIZE[0] * SIZE[1] // 2
for blend, tf, method in (("iso", "iso-opaque", "iso-analytic"),
                          ("mip", "marschner-lobb-spikes", "mip-analytic"),
                          ("minip", "marschner-lobb-spikes", "minip-analytic")):
    scene = scene_for(blend, tf)
    truth = renderer.render(reference, scene, 1.0).image
    start = time.perf_counter()
    row = hm.compare_blend(renderer.render(method, scene, 1.0).image, truth, scene)
    print("%-15s %.1f s %s" % (method, time.perf_counter() - start, hm.format_blend(row)))
    c.check(row["hits_both"] > pixels // 20, method + ": the volume is seen")
    if blend == "iso":
        c.check(row["disagreements_not_grazing"] <= 0.001 * pixels,
                "%s: hit/miss agrees on 99.9%% of the pixels apart from grazing ones (%d differ)"
                % (method, row["disagreements_not_grazing"]))
        c.check(row["depth_outliers_not_grazing"] == 0,
                "%s: depth within 1e-3 voxel on every hit that is not grazing (max %.2e)"
                % (method, row["depth_max_error_not_grazing"]))
        c.check(row["depth_p99_error_voxels"] < 1e-4,
                "%s: 99th percentile of the depth error below 1e-4 voxel (%.2e)"
                % (method, row["depth_p99_error_voxels"]))
    else:
        c.check(row["hit_miss_disagreements"] == 0, method + ": the same pixels meet the volume")
        c.check(row["extremum_max_error"] < 1e-3, "%s: extremum within 1e-3 of the data range "
                "(%.2e)" % (method, row["extremum_max_error"]))


class KeepTable(hm.PreIntegrationMethod):
    """Pre-integration with float table texels; keeps the mapper's table."""

    def __init__(self, order):
        super().__init__("preint%d" % order, "", order)
        self.table = None

    def make_mapper(self):
        mapper = super().make_mapper()
        mapper.SetTablePrecision(mapper.PRECISION_FLOAT32)
        return mapper

    def statistics(self, mapper):
        self.table = mapper.GetActiveTable()
        return super().statistics(mapper)


def rmse(a, b):
    return hm.compare(a, b)[0]["rmse"]


scene = scene_for("composite", "marschner-lobb-spikes")
truth = renderer.render(reference, scene, 1.0).image
errors = {}
for order in (1, 2):
    method = KeepTable(order)
    start = time.perf_counter()
    gpu = renderer.render(method, scene, 1.0).image
    seconds = time.perf_counter() - start
    twin = cast_image(scene, method.table, order, 1.0)
    exact = cast_image(scene, method.table, order, 1.0, exact=True)
    difference, table_error = rmse(gpu, twin), rmse(twin, exact)
    errors[order] = rmse(gpu, truth)
    model = rmse(exact, truth)
    print("preint%d %.1f s: GPU - twin %.6f, table error %.6f, GPU - reference %.6f, exact "
          "segments - reference %.6f" % (order, seconds, difference, table_error, errors[order],
                                         model))
    c.check(difference <= 2e-4, "preint%d: the twin draws the GPU's image (RMSE %.6f)"
            % (order, difference))
    c.check(abs(errors[order] - model) <= table_error + difference,
            "preint%d: as far from the reference as its exact segment model, within the table's "
            "error (%.6f against %.6f)" % (order, errors[order], model))
adaptive = {}
for oracle in ("range", "min"):
    start = time.perf_counter()
    method = hm.get_method("adaptive-ray", settings={"oracle": oracle})
    adaptive[oracle] = rmse(renderer.render(method, scene, 1.0).image, truth)
    print("%s %.1f s: GPU - reference %.6f (preint1 %.6f)" % (
        method.name, time.perf_counter() - start, adaptive[oracle], errors[1]))
c.check(adaptive["range"] <= 1.05 * adaptive["min"] + 2e-5,
        "adaptive-ray: the oracle keeps its full rate's accuracy (%.6f vs %.6f)"
        % (adaptive["range"], adaptive["min"]))
renderer.close()
c.finish()
