"""Second order gives rays the opacity they have, where the scalar lingers near a spike.

The blobs volume (48^3, values 0-255, generated here, as uint8 and as float) with opacity spikes
8 values wide at 44 and 104 and a ramp from 180, 64 x 64 images against the reference
integrator. Near a blob's maximum a ray's scalar stays close to one value for many voxels; a
table that blurs the transfer function along its scalar axes (the box prefilter) keeps the
transfer function's integral over scalar values but not the integral along such a ray, and
gives it opacity the transfer function does not.

With the defaults (measured table sizes and, for first order, measured prefilter), at 1 and 2 voxels, second order's mean
alpha is within 3% of the reference's and its RMSE within 5% of first order's or below (at 1
voxel both sit at the tables' floor, where the orders differ by the sizer's own tolerance; the
strict order comparison is TestPreIntegrationOrders). The same table size with the prefilter
(TableSize 49 on every axis, prefilter on) is rendered too, to show that the checks see a
blurred table: its RMSE must be more than 3 times first order's.
"""

import numpy
from vtkmodules.util.numpy_support import vtk_to_numpy

from hovr import io as hio
from hovr import methods as hm
from hovrtesting import Checker, blobs, image_from_array, spike_property

c = Checker()
renderer = hm.Renderer()


class Settings(hm.PreIntegrationMethod):
    """Pre-integration of an order with a fixed table size and prefilter, or the defaults."""

    def __init__(self, order, size=0, prefilter=None):
        super().__init__("preint%d" % order, "", order)
        self.size, self.prefilter = size, prefilter

    def make_mapper(self):
        mapper = super().make_mapper()
        mapper.SetTableSize(self.size)
        if self.prefilter is not None:
            mapper.SetTablePrefilter(self.prefilter)
        return mapper


def mean_alpha(image):
    rgba = vtk_to_numpy(image.GetPointData().GetScalars())
    return float(rgba[:, 3].mean())


values = blobs()
prop = spike_property()
for kind, array in (("uint8", values.astype(numpy.uint8)), ("float", values.astype(numpy.float32))):
    image = image_from_array(array)
    scene = hm.Scene(image, prop, hio.default_camera(image.GetBounds()), (64, 64))
    reference = renderer.render("reference", scene, 1.0).image
    true_alpha = mean_alpha(reference)
    for step in (1.0, 2.0):
        runs = [(Settings(1), step), (Settings(2), step), (Settings(2, 49, True), step)]
        first, second, old = renderer.render_interleaved(runs, scene)
        errors = [hm.compare(r.image, reference)[0]["rmse"] for r in (first, second, old)]
        alphas = [mean_alpha(r.image) for r in (first, second, old)]
        print("%s, step %g: mean alpha reference %.4f, first order %.4f, second order %.4f "
              "(table %s), 49^3 prefiltered %.4f; RMSE %.5f, %.5f, %.5f"
              % (kind, step, true_alpha, alphas[0], alphas[1], second.extra["table_size"],
                 alphas[2], *errors))
        c.check(abs(alphas[1] / true_alpha - 1.0) <= 0.03,
                "%s, step %g: second order's mean alpha %.4f within 3%% of the reference's %.4f"
                % (kind, step, alphas[1], true_alpha))
        c.check(errors[1] <= 1.05 * errors[0], "%s, step %g: second order's RMSE %.5f within 5%% "
                "of first order's %.5f or below" % (kind, step, errors[1], errors[0]))
        c.check(errors[2] > 3.0 * errors[0], "%s, step %g: the checks see a blurred table (49^3 "
                "prefiltered: RMSE %.5f against first order's %.5f)" % (kind, step, errors[2],
                                                                         errors[0]))
renderer.close()
c.finish()
