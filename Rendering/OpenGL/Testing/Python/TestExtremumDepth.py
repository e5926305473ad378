"""vtkAnalyticVolumeMapper's ExtremumDepth: pieces of a volume composited by depth (nearest
fragment wins, as IceT's z-buffer compositing does on several ParaView ranks) give the
projection of the whole volume.

Gaussian blobs (33^3, float), an opacity ramp over the range, 64 x 64 float images, MIP and
MinIP: the volume is cut into two pieces along x and into three along y (pieces share their
boundary planes of points, as ParaView's pieces do); each piece is drawn alone with
ScalarRange set to the whole volume's range and ExtremumDepth on, its colour and depth read
back; per pixel the piece of the nearest depth gives the colour. That composite must equal
the whole volume's image within float rounding (max 1e-5), and the same pieces composited
front to back ("over", what ordered compositing does) must not (a projection is not a sum of
layers). Pixels no ray meets keep the cleared depth (1). Without ExtremumDepth the depth
stays 1 everywhere (the mapper writes none).
"""

import numpy
from vtkmodules.vtkCommonCore import vtkFloatArray

import hovr
from hovr import io as hio
from hovrtesting import (Checker, FloatFrames, blobs, cut_pieces, image_from_array,
                         spike_property)

c = Checker()
SIZE = 64
frames = FloatFrames((SIZE, SIZE))

whole = image_from_array(blobs(n=33).astype(numpy.float32))
low, high = whole.GetPointData().GetScalars().GetRange()
# Opacity and colour that change along the whole range: a projection's colour tells its
# extremum (the spike function would leave most MinIP pixels transparent).
prop = spike_property()
prop.GetScalarOpacity().RemoveAllPoints()
prop.GetScalarOpacity().AddPoint(low, 0.2)
prop.GetScalarOpacity().AddPoint(high, 1.0)
camera = hio.default_camera(whole.GetBounds())


def draw(data, blend, depth):
    """Colour (float RGBA) and depth of one frame of the analytic projection of ``data``."""
    mapper = hovr.vtkAnalyticVolumeMapper()
    mapper.SetBlendMode(blend)
    mapper.SetScalarRange(low, high)
    mapper.SetExtremumDepth(depth)
    colour, messages = frames.draw(mapper, data, prop, camera)
    z = vtkFloatArray()
    frames.window.GetZbufferData(0, 0, SIZE - 1, SIZE - 1, z)
    depth_image = numpy.array([z.GetValue(i) for i in range(z.GetNumberOfTuples())])
    return colour, depth_image.reshape(SIZE, SIZE), messages.errors + messages.warnings


def pieces(axis, count):
    """The volume cut into ``count`` pieces along ``axis`` that share their boundary planes."""
    return [piece for _, piece in cut_pieces(whole, axis, count)]


for blend, name in ((hovr.vtkAnalyticVolumeMapper.MAXIMUM_INTENSITY_BLEND, "MIP"),
                    (hovr.vtkAnalyticVolumeMapper.MINIMUM_INTENSITY_BLEND, "MinIP")):
    reference, reference_depth, said = draw(whole, blend, True)
    met = reference[..., 3] > 0.0
    c.check(met.any() and not said, "%s: the whole volume draws quietly (%s)" % (name, said))
    c.check(numpy.all(reference_depth[~met] == 1.0) and numpy.all(reference_depth[met] < 0.76)
            and numpy.all(reference_depth[met] > 0.24),
            "%s: depth within [0.25, 0.75] where a ray meets the volume, 1 elsewhere" % name)
    plain, plain_depth, _ = draw(whole, blend, False)
    c.check(numpy.all(plain_depth == 1.0) and numpy.abs(plain - reference).max() < 1e-6,
            "%s: without ExtremumDepth the same colour, and no depth written" % name)
    for axis, count in ((0, 2), (1, 3)):
        parts = pieces(axis, count)
        drawn = [draw(piece, blend, True) for piece in parts]
        colours = numpy.stack([d[0] for d in drawn])
        depths = numpy.stack([d[1] for d in drawn])
        nearest = numpy.argmin(depths, axis=0)
        composite = numpy.take_along_axis(colours, nearest[None, ..., None], axis=0)[0]
        difference = numpy.abs(composite - reference).max()
        c.check(difference < 1e-5, "%s, %d pieces along %s: the nearest piece per pixel gives "
                "the whole projection (max %.2e)" % (name, count, "xyz"[axis], difference))
        # Front to back along the view (the pieces' order by their distance to the camera).
        eye = numpy.array(camera.GetPosition())
        order = sorted(range(count),
                       key=lambda k: numpy.linalg.norm(numpy.array(parts[k].GetCenter()) - eye))
        over = numpy.zeros_like(reference)
        for k in order:
            over = over + (1.0 - over[..., 3:4]) * colours[k]
        c.check(numpy.abs(over - reference).max() > 1e-2, "%s, %d pieces along %s: composited "
                "front to back they are not the projection (max %.2e)"
                % (name, count, "xyz"[axis], numpy.abs(over - reference).max()))

c.finish()
