"""A time step is written into the textures already made, and draws what a new mapper draws.

A new volume in the same layout and format (a time step of an animation) is uploaded into the
brick textures (and the analytic mapper's packed-corner textures) of the last one, slice by
slice, instead of creating them again. On Marschner-Lobb volumes generated here (72^3 float and
uint8; the second step has another alpha, so every value changes), 64 x 64, for each method
below, one mapper draws step 1 and then step 2, and a new mapper draws step 2:
- the images are the same (float capture, within 1e-6: the same textures, tables and rays);
- step 2 uploaded every brick again (the upload count grows) and created no texture;
- a volume of other dimensions creates its textures anew, and again draws what a new mapper
  draws.
The methods: first-order pre-integration in forced bricks of 24 cells (with and without shading,
whose gradients have their own bricks), the tricubic adaptive ray in atlas pages of at most
1 MiB, and the analytic maximum projection and isosurface in bricks of 24 cells (with packed
corners).
"""

import copy
import time

import numpy
from vtkmodules.vtkCommonCore import VTK_FLOAT, VTK_UNSIGNED_CHAR
from vtkmodules.vtkCommonDataModel import vtkImageData

import hovr
from hovr import io as hio
from hovr import methods as hm
from hovr.bench import rescale_transfer_function
from hovr.latency import View
from hovrtesting import Checker, rgba, tf_path

c = Checker()
SIZE = (64, 64)


def configured(name, bricks, texture_bytes):
    """The method, its mapper with MaximumBrickSize and MaximumTextureBytes."""
    method = copy.copy(hm.get_method(name))
    make = method.make_mapper

    def make_mapper():
        mapper = make()
        mapper.SetMaximumBrickSize(bricks)
        if texture_bytes:
            mapper.SetMaximumTextureBytes(texture_bytes)
        return mapper

    method.make_mapper = make_mapper
    return method


def step(n, alpha, scalar_type):
    source = hovr.vtkMarschnerLobbSource()
    source.SetDimensions(n, n, n)
    source.SetOutputScalarType(scalar_type)
    source.SetAlpha(alpha)
    source.Update()
    image = vtkImageData()
    image.DeepCopy(source.GetOutput())
    return image


def scene_for(volume, blend, shade):
    color, opacity, _ = hio.read_transfer_function(
        tf_path("iso-opaque" if blend == "iso" else "marschner-lobb-spikes"))
    low, high = volume.GetPointData().GetScalars().GetRange()
    rescale_transfer_function(color, opacity, volume)  # onto 0-1 (float) or 0-255 (uint8)
    prop = hio.make_volume_property(color, opacity, 0.05)
    if blend == "iso":
        prop.GetIsoSurfaceValues().SetValue(0, low + 0.5 * (high - low))
    if shade or blend == "iso":
        prop.ShadeOn()
    return hm.Scene(volume, prop, hio.default_camera(volume.GetBounds()), SIZE, blend)


def settle(view):
    """Draw, then every refined frame, and return the final image."""
    view.frame()
    view.refine(time.perf_counter())
    return rgba(view.image())


def fresh(method, scene, volume):
    view = View(method, scene, 1.0)
    view.set_input(volume)
    image = settle(view)
    view.close()
    return image


cases = [("preint1", "composite", False, 25, 0), ("preint1-nonlinear", "composite", True, 25, 0),
         ("adaptive-ray-tricubic", "composite", False, 0, 1 << 20),
         ("mip-analytic", "mip", False, 25, 0), ("iso-analytic", "iso", False, 25, 0)]
for scalar_type, type_name in ((VTK_FLOAT, "float"), (VTK_UNSIGNED_CHAR, "uint8")):
    first, second = step(72, 0.25, scalar_type), step(72, 0.3, scalar_type)
    other = step(60, 0.3, scalar_type)
    for name, blend, shade, bricks, texture_bytes in cases:
        method = configured(name, bricks, texture_bytes)
        label = "%s %s%s" % (type_name, name, " shaded" if shade else "")
        scene = scene_for(first, blend, shade)
        view = View(method, scene, 1.0)
        mapper = view.mapper
        settle(view)
        uploads, created = mapper.GetBrickUploadCount(), mapper.GetBrickTextureCreateCount()
        view.set_input(second)
        image = settle(view)
        uploads2, created2 = mapper.GetBrickUploadCount(), mapper.GetBrickTextureCreateCount()
        difference = numpy.abs(image - fresh(method, scene, second)).max()
        print("%-32s %d bricks; step 2: %d uploads, %d textures created; largest difference to a "
              "new mapper %.2e" % (label, view.mapper.GetNumberOfBricks(), uploads2 - uploads,
                                   created2 - created, difference))
        c.check(view.mapper.GetNumberOfBricks() >= (8 if bricks else 1) and
                uploads2 - uploads >= view.mapper.GetNumberOfBricks() and created2 == created,
                "%s: the time step is written into the textures already made" % label)
        c.check(difference <= 1e-6, "%s: the time step draws what a new mapper draws (%.2e)"
                % (label, difference))
        view.set_input(other)
        image = settle(view)
        difference = numpy.abs(image - fresh(method, scene, other)).max()
        c.check(view.mapper.GetBrickTextureCreateCount() > created2 and difference <= 1e-6,
                "%s: a volume of other dimensions gets new textures and the new mapper's image "
                "(%.2e)" % (label, difference))
        view.close()

c.finish()
