"""vtkPreIntegrationRayCaster, the CPU twin of the pre-integration shaders, draws what the GPU
draws.

The mapper renders Marschner-Lobb 41 and the blobs volume (generated here) with its measured
table (float texels, so the texture holds the CPU table's values), first and second order, at 1/2
and 2 voxels, 64 x 64. The caster is then handed the mapper's own table and the same camera and
step. The two images must agree far better than either agrees with the exact segment model of
the same order (the table's own error): a half-texel shift in a lookup, a wrong axis scale or a
compositing difference in either would show as a difference of the size of the table error.
"""

import numpy

from hovr import io as hio
from hovr import methods as hm
from hovrtesting import (Checker, blobs, cast_image, image_from_array, marschner_lobb_scene,
                         spike_property)

c = Checker()
renderer = hm.Renderer()
SIZE = (64, 64)


class KeepTable(hm.PreIntegrationMethod):
    """Pre-integration with float table texels; keeps the mapper's table after rendering."""

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


blob_image = image_from_array(blobs().astype(numpy.float32))
scenes = [("Marschner-Lobb 41", marschner_lobb_scene(SIZE)),
          ("blobs", hm.Scene(blob_image, spike_property(),
                             hio.default_camera(blob_image.GetBounds()), SIZE))]
for name, scene in scenes:
    for order in (1, 2):
        for step in (0.5, 2.0):
            method = KeepTable(order)
            gpu = renderer.render(method, scene, step)
            twin = cast_image(scene, method.table, order, step)
            exact = cast_image(scene, method.table, order, step, exact=True)
            difference, table_error = rmse(gpu.image, twin), rmse(twin, exact)
            print("%s, order %d, step %g, table %s: GPU - twin %.6f, twin - exact segments "
                  "%.6f" % (name, order, step, gpu.extra["table_size"], difference, table_error))
            c.check(difference <= 2e-4 and difference <= 0.1 * table_error,
                    "%s, order %d, step %g: the twin draws the GPU's image (RMSE %.6f, the "
                    "table's own error %.6f)" % (name, order, step, difference, table_error))
renderer.close()
c.finish()
