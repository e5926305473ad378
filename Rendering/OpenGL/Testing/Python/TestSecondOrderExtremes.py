"""Second-order pre-integration at the extremes, rendered on the GPU and compared
with closed forms or the reference integrator:
- a slab longer than the volume (the whole ray shorter than one slab);
- very small steps (1e-3 voxel: table precision and float accumulation along the ray);
- huge and tiny opacity unit distances;
- scalar values exactly at the ends of the range, with a feature at the end;
- opacity saturating inside one slab;
- a transfer function changed every frame (one rebuild per frame; the cost is printed);
- 16-bit data with opacity peaks narrower than a table spacing (the table's prefilter, and
  the measured sizes that need none).
The table diagonal (s_f = s_m = s_b) is checked exactly by the C++ table test.
"""

import math
import time

import numpy
from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
from vtkmodules.vtkRenderingCore import vtkColorTransferFunction

from hovr import io as hio
from hovr import methods as hm
from hovrtesting import Checker, image_from_array, offscreen_window, rgba

c = Checker()
renderer = hm.Renderer()
TOP = hio.camera_from_dict({"position": [0.5, 0.5, 10], "focal_point": [0.5, 0.5, 0],
                            "view_up": [0, 1, 0], "parallel_projection": True,
                            "parallel_scale": 0.6})


def property_for(points, colors, unit):
    color = vtkColorTransferFunction()
    for x, r, g, b in colors:
        color.AddRGBPoint(x, r, g, b)
    opacity = vtkPiecewiseFunction()
    for x, a in points:
        opacity.AddPoint(x, a)
    return hio.make_volume_property(color, opacity, unit)


def slab(thickness_points, value=1.0, lateral=5, spacing=0.25):
    """A homogeneous box seen along z by TOP: every centre ray crosses the full thickness."""
    values = numpy.full((thickness_points, lateral, lateral), value, numpy.float32)
    return image_from_array(values, spacing=(spacing, spacing, spacing))


def centre(image):
    values = rgba(image)
    h, w, _ = values.shape
    return values[h // 2, w // 2]


# A homogeneous medium: opacity 0.5 per unit, colour (0.8, 0.4, 0.2); along a chord L the
# exact result is alpha = 1 - 0.5^L (unit 1), colour = c alpha.
FLAT = property_for([(0.0, 0.5), (2.0, 0.5)], [(0.0, 0.8, 0.4, 0.2), (2.0, 0.8, 0.4, 0.2)], 1.0)


def expected(length, unit=1.0, alpha=0.5):
    a = 1.0 - (1.0 - alpha) ** (length / unit)
    return numpy.array([0.8 * a, 0.4 * a, 0.2 * a, a])


# 1. A slab longer than the volume: 3 points (0.5 thick) at steps up to 4 voxels (slab 2
#    world units, 4x the volume), with and without jittering of the first sample.
volume = slab(3)
for step in (1.0, 2.0, 3.0, 4.0):
    got = centre(renderer.render("preint2", hm.Scene(volume, FLAT, TOP, (24, 24)), step).image)
    error = numpy.abs(got - expected(0.5)).max()
    print("slab longer than the volume, step %g voxel: %s (error %.2e)" % (step, got, error))
    # Constant scalar: the partial slab is exact up to 16-bit table storage (5e-4 relative).
    c.check(error < 2e-3, "step %g: the one partial slab gives 1 - 0.5^0.5" % step)

# 2. Very small steps: 1e-3 voxel through a 0.5-thick slab: 2000 samples, 1000 slabs, each
#    with opacity ~3.5e-4. Float accumulation of 1000 terms and the half-float table cost at
#    most ~1e-3 relative.
volume = slab(3)
start = time.perf_counter()
got = centre(renderer.render("preint2", hm.Scene(volume, FLAT, TOP, (8, 8)), 1e-3).image)
error = numpy.abs(got - expected(0.5)).max()
print("step 1e-3 voxel: %s (error %.2e, %.1f s)" % (got, error, time.perf_counter() - start))
c.check(error < 1e-3 * expected(0.5)[3] * 3, "step 1e-3 voxel accumulates correctly")
for step in (0.01, 0.1):
    got = centre(renderer.render("preint2", hm.Scene(volume, FLAT, TOP, (8, 8)), step).image)
    c.check(numpy.abs(got - expected(0.5)).max() < 1e-3, "step %g voxel is exact" % step)

# 3. Huge and tiny opacity unit distances over a 2.5-thick slab (11 points).
volume = slab(11)
for unit in (1e-4, 1e-2, 1e2, 1e4):
    prop = property_for([(0.0, 0.5), (2.0, 0.5)], [(0.0, 0.8, 0.4, 0.2), (2.0, 0.8, 0.4, 0.2)],
                        unit)
    got = centre(renderer.render("preint2", hm.Scene(volume, prop, TOP, (16, 16)), 1.0).image)
    want = expected(2.5, unit)
    print("unit distance %g: %s, expected %s" % (unit, got, want))
    c.check(numpy.isfinite(got).all(), "unit distance %g: finite" % unit)
    c.check(numpy.abs(got - want).max() < 2e-3 * max(want[3], 1e-3) + 1e-6,
            "unit distance %g: 1 - 0.5^(L/U) and colour c alpha" % unit)

# 4. Scalars exactly at the range ends, each with a feature right at that end: a box at the
#    maximum (or minimum) whose far column holds the other end (it sets the range, the centre
#    ray never sees it). The ends must map to the first and last table entries exactly.
SIDE = 9
for end, points in ((1.0, [(0.0, 0.0), (0.99, 0.0), (1.0, 0.8)]),
                    (0.0, [(0.0, 0.8), (0.01, 0.0), (1.0, 0.0)])):
    values = numpy.full((SIDE, SIDE, SIDE), end, numpy.float32)
    values[:, :, 0] = 1.0 - end
    box = image_from_array(values, spacing=(1.0 / (SIDE - 1),) * 3)
    prop = property_for(points, [(0.0, 0.8, 0.4, 0.2), (1.0, 0.8, 0.4, 0.2)], 1.0)
    want = 1.0 - (1.0 - 0.8) ** 1.0  # a chord of 1 through opacity 0.8 per unit
    for method in ("preint1", "preint2"):
        for step in (0.5, 1.0, 2.0):
            got = centre(renderer.render(method, hm.Scene(box, prop, TOP, (16, 16)), step).image)
            print("range end %g, %s step %g: alpha %.5f, expected %.5f" % (end, method, step,
                                                                        got[3], want))
            c.check(abs(got[3] - want) < 2e-3 and abs(got[0] - 0.8 * got[3]) < 2e-3,
                    "range end %g: %s at step %g looks up the end entry exactly"
                    % (end, method, step))

# 5. Opacity saturating inside one slab: opacity 1 (capped at 1 - 1e-9) over a 2.5 slab.
volume = slab(11)
prop = property_for([(0.0, 1.0), (2.0, 1.0)], [(0.0, 0.8, 0.4, 0.2), (2.0, 0.8, 0.4, 0.2)], 1.0)
for step in (1.0, 4.0):
    got = centre(renderer.render("preint2", hm.Scene(volume, prop, TOP, (16, 16)), step).image)
    print("saturating, step %g: %s" % (step, got))
    c.check(abs(got[3] - 1.0) < 1e-3 and numpy.abs(got[:3] - [0.8, 0.4, 0.2]).max() < 2e-3,
            "opacity saturates inside one slab (step %g)" % step)

# 6. A transfer function changed every frame: one table build per frame.
scene = hm.Scene(box, prop, hio.default_camera(box.GetBounds()), (64, 64))
method = hm.get_method("preint2")
mapper = method.make_mapper()
results = []
from vtkmodules.vtkRenderingCore import vtkVolume  # noqa: E402
window, view = offscreen_window((64, 64))
volume = vtkVolume()
volume.SetMapper(mapper)
volume.SetProperty(prop)
mapper.SetInputData(box)
mapper.SetSampleDistance(0.125)
view.AddVolume(volume)
view.GetActiveCamera().DeepCopy(scene.camera)
view.ResetCameraClippingRange()
window.Render()
table = mapper.GetActiveTable()
builds, frame_ms, build_ms = [], [], []
for frame in range(5):
    prop.GetScalarOpacity().AddPoint(0.5, 0.05 + 0.1 * frame)
    start = time.perf_counter()
    window.Render()
    window.WaitForCompletion()
    frame_ms.append(1000 * (time.perf_counter() - start))
    builds.append(table.GetBuildCount())
    build_ms.append(1000 * mapper.GetLastTableBuildTime())
print("transfer function changed every frame: %d-entry table, builds %s, build %.1f ms (median), "
      "frame %.1f ms (median)" % (table.GetTableSize(), builds, sorted(build_ms)[2],
                                  sorted(frame_ms)[2]))
c.check(builds == list(range(builds[0], builds[0] + 5)) and builds[0] >= 2,
        "one rebuild per changed frame")
window.Finalize()

# 7. 16-bit data with an opacity peak a quarter of a table spacing wide (a fixed table of 51
#    entries on every axis), centred on an entry or between two: with the table's prefilter the
#    error against the reference does not depend on where the peak falls; without it, a peak on
#    an entry is magnified over the whole spacing. The measured sizes (the default: no
#    prefilter) do as well as the prefiltered fixed table, within 15%.
from vtkmodules.vtkCommonCore import VTK_UNSIGNED_SHORT  # noqa: E402
import hovr  # noqa: E402

source = hovr.vtkMarschnerLobbSource()
source.SetDimensions(33, 33, 33)
source.SetOutputScalarType(VTK_UNSIGNED_SHORT)
source.Update()
ml16 = source.GetOutput()
low, high = ml16.GetScalarRange()
entries = 51
spacing = (high - low) / (entries - 1)


class SecondOrder(hm.PreIntegrationMethod):
    def __init__(self, name, size, prefilter):
        super().__init__(name, "", hovr.vtkPreIntegrationVolumeMapper.SECOND_ORDER)
        self.size = size
        self.prefilter = prefilter

    def make_mapper(self):
        mapper = super().make_mapper()
        mapper.SetTableSize(self.size)
        mapper.SetTablePrefilter(self.prefilter)
        return mapper


for peak in (0.9, 1.0):
    errors = {}
    for offset in (0.0, 0.5):
        centre = low + (30 + offset) * spacing
        narrow = property_for([(low, 0.0), (centre - 0.25 * spacing, 0.0), (centre, peak),
                               (centre + 0.25 * spacing, 0.0), (high, 0.0)],
                              [(low, 1.0, 0.5, 0.2), (centre, 0.2, 0.6, 1.0), (high, 1.0, 1.0, 1.0)],
                              2.0)
        scene = hm.Scene(ml16, narrow, hio.default_camera(ml16.GetBounds()), (96, 96))
        reference = renderer.render("reference", scene, 1.0).image
        runs = [(SecondOrder("prefiltered", entries, True), 2.0),
                (SecondOrder("unfiltered", entries, False), 2.0),
                (SecondOrder("measured", 0, False), 2.0)]
        for (method, _), result in zip(runs, renderer.render_interleaved(runs, scene)):
            errors[method.name, offset] = hm.compare(result.image, reference)[0]["rmse"]
    print("16-bit, peak %.1f a quarter spacing wide: RMSE %s" % (peak, ", ".join(
        "%s at offset %g: %.5f" % (name, offset, value)
        for (name, offset), value in sorted(errors.items()))))
    placement = errors["prefiltered", 0.0] / errors["prefiltered", 0.5]
    c.check(abs(placement - 1.0) < 0.15,
            "peak %.1f: with the prefilter the error does not depend on where the peak falls "
            "(ratio %.3f)" % (peak, placement))
    c.check(errors["unfiltered", 0.0] > 1.3 * errors["prefiltered", 0.0],
            "peak %.1f: without the prefilter a peak on an entry costs more than 1.3x (%.5f vs "
            "%.5f)" % (peak, errors["unfiltered", 0.0], errors["prefiltered", 0.0]))
    for offset in (0.0, 0.5):
        c.check(errors["measured", offset] < 1.15 * errors["prefiltered", offset],
                "peak %.1f at offset %g: measured sizes within 15%% of the prefiltered fixed "
                "table (%.5f vs %.5f)" % (peak, offset, errors["measured", offset],
                                          errors["prefiltered", offset]))
renderer.close()
c.finish()
