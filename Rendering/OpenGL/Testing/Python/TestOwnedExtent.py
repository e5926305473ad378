"""OwnedExtent with WholeBounds: pieces of a volume that carry ghost points, drawn by
pre-integration and composited front to back (what ParaView's ordered compositing does on
several ranks), give the whole volume's image.

Marschner-Lobb plus a ramp along x (33 x 29 x 25, so that each piece covers another part of
the range), three narrow opacity peaks, ScalarRange the whole range, the table sizes measured
on the whole volume (SizingVolume), 96 x 96 float images, a step of half a voxel: the volume is cut into two pieces along x and into three along y; each
piece carries 4 ghost points past its own points where it has a neighbour, and OwnedExtent
gives its own points. For both orders, unshaded and shaded, parallel and perspective:
- the pieces composited front to back equal the whole volume's image within float rounding
  (max 1e-4): a segment or slab that starts in a piece's own points is drawn whole from its
  ghost points, and the next piece starts where it ends;
- without OwnedExtent (each piece drawn as a volume of its own, as before ghost points were
  used) they differ where rays cross the cuts (max above 1e-3), so the check can tell.
The adaptive ray (l_max 3, its oracle computed on each piece with its ghost points, which
reach 2^(l_max + 1) sample distances and two points), parallel and perspective: within 5e-4
(perspective slices are spheres, whose coordinates round differently in each piece's frame),
and above 5e-3 for pieces without ghost points; and the same for blocks cut along two axes
(vtkExtentTranslator's 3 and 4 pieces) of the MPI test's scene and view.
The adaptive 3D method (the slice pyramid, l_max 3) on that scene, with ghost points
2^(l_max + 2) slice spacings and two points deep: within 5e-4 for 2 pieces along x, 3 along y
and the 3 and 4 blocks; with 4 ghost points, too few, each piece is drawn as a volume of its
own (GetLastFrameJoinedPieces false) and the cuts show.
VTK's own path (the adaptive ray's fallback for a shaded property) draws a piece's owned points
alone: its pieces composited are nearer the whole image than the ghost points drawn twice.
"""

import numpy
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
from vtkmodules.vtkRenderingCore import vtkColorTransferFunction, vtkVolumeProperty

import hovr
from hovr import io as hio
from hovrtesting import (Checker, FloatFrames, cut_pieces, front_to_back, image_from_array,
                         mpi_ramp_scene, translator_pieces, with_oracle)

c = Checker()
frames = FloatFrames((96, 96))
GHOSTS = 4

source = hovr.vtkMarschnerLobbSource()
source.SetDimensions(33, 29, 25)
source.Update()
dims = source.GetOutput().GetDimensions()
values = vtk_to_numpy(source.GetOutput().GetPointData().GetScalars()).reshape(
    dims[2], dims[1], dims[0])
x = numpy.linspace(-1.0, 1.0, dims[0])
# Away from the origin: the whole box in a piece's grid index is computed from its bounds.
whole = image_from_array((values + 1.5 * x[None, None, :]).astype(numpy.float32),
                         origin=(5.0, -3.0, 2.0))
low, high = whole.GetPointData().GetScalars().GetRange()

colour = vtkColorTransferFunction()
for s, r, g, b in ((low, 0.1, 0.3, 0.9), (0.5 * (low + high), 1.0, 0.55, 0.15),
                   (high, 1.0, 1.0, 0.9)):
    colour.AddRGBPoint(s, r, g, b)
opacity = vtkPiecewiseFunction()
opacity.AddPoint(low, 0.0)
for f, height in ((0.3, 0.8), (0.5, 0.9), (0.7, 0.9)):
    peak = low + f * (high - low)
    width = 0.01 * (high - low)
    opacity.AddPoint(peak - width, 0.0)
    opacity.AddPoint(peak, height)
    opacity.AddPoint(peak + width, 0.0)
opacity.AddPoint(high, 0.0)
prop = vtkVolumeProperty()
prop.SetColor(colour)
prop.SetScalarOpacity(opacity)
prop.SetScalarOpacityUnitDistance(2.0)
prop.SetInterpolationTypeToLinear()
step = 0.5 * min(whole.GetSpacing())


def mapper(order):
    m = hovr.vtkPreIntegrationVolumeMapper()
    m.SetIntegration(order)
    m.SetSampleDistance(step)
    m.SetScalarRange(low, high)
    m.SetWholeBounds(whole.GetBounds())
    # Every piece's table measured on the whole volume, as the plugin does on every rank.
    m.SetSizingVolume(whole)
    return m


def oblique_camera(perspective):
    """The whole volume seen obliquely to the cuts."""
    camera = hio.default_camera(whole.GetBounds())
    camera.SetParallelProjection(not perspective)
    camera.Azimuth(30.0)
    camera.Elevation(20.0)
    return camera


def pieces(axis, count):
    """(owned extent, the piece with its ghost points) for count pieces along axis."""
    return cut_pieces(whole, axis, count, GHOSTS)


for perspective in (False, True):
    camera = oblique_camera(perspective)
    eye = numpy.array(camera.GetPosition())
    for order in (1, 2):
        for shade in (False, True):
            prop.SetShade(shade)
            name = "order %d, %s, %s" % (order, "shaded" if shade else "unshaded",
                                         "perspective" if perspective else "parallel")
            reference, _ = frames.draw(mapper(order), whole, prop, camera)
            c.check(reference[..., 3].max() > 0.3, "%s: the whole volume is drawn" % name)
            for axis, count in ((0, 2), (1, 3)):
                parts = pieces(axis, count)
                # Front to back: by the distance of each piece's own middle from the eye
                # along the cut axis.
                spacing = whole.GetSpacing()[axis]
                origin = whole.GetOrigin()[axis]
                middle = [origin + 0.5 * (o[2 * axis] + o[2 * axis + 1]) * spacing
                          for o, _ in parts]
                ranked = sorted(range(count), key=lambda k: abs(middle[k] - eye[axis]))
                for owned_extent in (True, False):
                    over = numpy.zeros_like(reference)
                    for k in ranked:
                        owned, piece = parts[k]
                        m = mapper(order)
                        if owned_extent:
                            m.SetOwnedExtent(owned)
                        image, _ = frames.draw(m, piece, prop, camera)
                        over = over + (1.0 - over[..., 3:4]) * image
                    difference = numpy.abs(over - reference).max()
                    label = "%s, %d pieces along %s" % (name, count, "xyz"[axis])
                    if owned_extent:
                        c.check(difference < 1e-4, "%s: composited front to back, the whole "
                                "volume's image (max %.2e)" % (label, difference))
                    else:
                        c.check(difference > 1e-3, "%s: without OwnedExtent the cuts show "
                                "(max %.2e)" % (label, difference))
# The adaptive ray with its oracle (l_max 3): each piece's oracle is computed with the piece's
# ghost points, which reach 2^(l_max + 1) sample distances and two points past its own.
LEVELS = 3
AHEAD = int(numpy.ceil(2 ** (LEVELS + 1) * step / min(whole.GetSpacing()))) + 2


def adaptive():
    m = hovr.vtkAdaptiveRayVolumeMapper()
    m.SetMaximumLevel(LEVELS)
    m.SetOracleMode(m.ORACLE_ARRAY)
    m.SetTableSize(256)
    m.SetSampleDistance(step)
    m.SetScalarRange(low, high)
    m.SetWholeBounds(whole.GetBounds())
    return m


prop.SetShade(False)
for perspective in (False, True):
    camera = oblique_camera(perspective)
    eye = numpy.array(camera.GetPosition())
    name = "adaptive ray, %s" % ("perspective" if perspective else "parallel")
    reference, _ = frames.draw(adaptive(), with_oracle(whole, prop, LEVELS), prop, camera)
    c.check(reference[..., 3].max() > 0.3, "%s: the whole volume is drawn" % name)
    for axis, count in ((0, 2), (1, 3)):
        parts = cut_pieces(whole, axis, count, AHEAD)
        spacing = whole.GetSpacing()[axis]
        origin = whole.GetOrigin()[axis]
        middle = [origin + 0.5 * (o[2 * axis] + o[2 * axis + 1]) * spacing for o, _ in parts]
        ranked = sorted(range(count), key=lambda k: abs(middle[k] - eye[axis]))
        for owned_extent in (True, False):
            over = numpy.zeros_like(reference)
            for k in ranked:
                owned, piece = parts[k]
                m = adaptive()
                if owned_extent:
                    m.SetOwnedExtent(owned)
                else:
                    # Without ghost points: each piece walked as a volume of its own.
                    piece = cut_pieces(whole, axis, count)[k][1]
                image, _ = frames.draw(m, with_oracle(piece, prop, LEVELS), prop, camera)
                over = over + (1.0 - over[..., 3:4]) * image
            difference = numpy.abs(over - reference).max()
            label = "%s, %d pieces along %s" % (name, count, "xyz"[axis])
            print("%s, %s: max %.2e" % (label, "owned" if owned_extent else "plain", difference))
            if owned_extent:
                # (Perspective slices are spheres: their coordinates round differently in
                # each piece's frame.)
                c.check(difference < 5e-4, "%s: composited front to back, the whole volume's "
                        "image (max %.2e)" % (label, difference))
            else:
                c.check(difference > 5e-3, "%s: without ghost points the cuts show (max %.2e)"
                        % (label, difference))

# Blocks cut along two axes (vtkExtentTranslator's 3 and 4 pieces, as ParaView's ranks get
# them) of the MPI test's scene: Marschner-Lobb plus a ramp, 65 x 57 x 49 points over
# [-1, 1]^3, its camera, 200 x 200 pixels. A ray that enters a piece through a face of its own
# that is also the input's starts as the whole volume's walk does (a piece told this by the
# rounded distance to its own box started some rays on the next aligned slice instead).

blocks_frames = FloatFrames((200, 200))
ramp, prop, camera = mpi_ramp_scene()
low, high = ramp.GetPointData().GetScalars().GetRange()
step = 0.5 * min(ramp.GetSpacing())
whole = ramp
ahead = int(numpy.ceil(2 ** (LEVELS + 1) * step / min(ramp.GetSpacing()))) + 2
reference, _ = blocks_frames.draw(adaptive(), with_oracle(ramp, prop, LEVELS), prop, camera)
for count in (3, 4):
    parts = translator_pieces(ramp, count, ahead)
    over = numpy.zeros_like(reference)
    for k in front_to_back(parts, ramp, camera):
        m = adaptive()
        m.SetOwnedExtent(parts[k][0])
        image, _ = blocks_frames.draw(m, with_oracle(parts[k][1], prop, LEVELS), prop, camera)
        over = over + (1.0 - over[..., 3:4]) * image
    difference = numpy.abs(over - reference).max()
    c.check(difference < 5e-4, "adaptive ray, %d blocks of the MPI scene: composited front to "
            "back, the whole volume's image (max %.2e)" % (count, difference))

# The adaptive 3D method (the slice pyramid, l_max 3) on the MPI scene: its slices are one
# pixel apart (Delta = 2 ParallelScale / height), its walks join on the slices of 2^l_max, and
# its ghost points must reach 2^(l_max + 2) slice spacings and two points.
delta = 2.0 * camera.GetParallelScale() / 200.0
deep = int(numpy.ceil(2 ** (LEVELS + 2) * delta / min(ramp.GetSpacing()))) + 2


def pyramid():
    m = hovr.vtkAdaptiveSamplingVolumeMapper()
    m.SetMaximumLevel(LEVELS)
    m.SetOracleModeToArray()
    m.SetScalarRange(low, high)
    m.SetWholeBounds(ramp.GetBounds())
    return m


reference, _ = blocks_frames.draw(pyramid(), with_oracle(ramp, prop, LEVELS), prop, camera)
c.check(reference[..., 3].max() > 0.3, "adaptive 3D: the whole volume is drawn")
layouts = [("2 pieces along x", cut_pieces(ramp, 0, 2, deep)),
           ("3 pieces along y", cut_pieces(ramp, 1, 3, deep)),
           ("3 blocks", translator_pieces(ramp, 3, deep)),
           ("4 blocks", translator_pieces(ramp, 4, deep)),
           ("2 pieces along x, 4 ghost points", cut_pieces(ramp, 0, 2, 4))]
for label, parts in layouts:
    over = numpy.zeros_like(reference)
    joined = []
    for k in front_to_back(parts, ramp, camera):
        m = pyramid()
        m.SetOwnedExtent(parts[k][0])
        image, _ = blocks_frames.draw(m, with_oracle(parts[k][1], prop, LEVELS), prop, camera)
        joined.append(m.GetLastFrameJoinedPieces())
        over = over + (1.0 - over[..., 3:4]) * image
    difference = numpy.abs(over - reference).max()
    print("adaptive 3D, %s: max %.2e, joined %s" % (label, difference, joined))
    if "4 ghost points" in label:
        # Too few for the slice spacing: each piece drawn as a volume of its own.
        c.check(not any(joined) and difference > 5e-3, "adaptive 3D, %s: too few, the owned "
                "points drawn as a volume of their own (max %.2e)" % (label, difference))
    else:
        c.check(all(joined) and difference < 5e-4, "adaptive 3D, %s of the MPI scene (%d ghost "
                "points): composited front to back, the whole volume's image (max %.2e)"
                % (label, deep, difference))

# VTK's own path (here the adaptive ray's fallback for a shaded property) draws a piece's owned
# points alone: cropped to them, the pieces composited are as close to the whole volume's image
# as pieces without ghost points (VTK samples each piece anew), and much closer than the
# ghost points drawn twice.
prop.SetShade(True)
shaded, _ = frames.draw(adaptive(), ramp, prop, camera)


def stock_pieces(ghosts, owned_extent):
    parts = cut_pieces(ramp, 0, 2, ghosts)
    over = numpy.zeros_like(shaded)
    for k in front_to_back(parts, ramp, camera):
        m = adaptive()
        m.SetOracleModeToMinimum()
        if owned_extent:
            m.SetOwnedExtent(parts[k][0])
        image, messages = frames.draw(m, parts[k][1], prop, camera)
        c.check(any("does not shade" in w for w in messages.warnings),
                "a shaded adaptive ray: drawn by VTK's own path after a warning")
        over = over + (1.0 - over[..., 3:4]) * image
    return float(numpy.sqrt(((over - shaded)[..., :3] ** 2).mean()))


cropped, plain, twice = stock_pieces(16, True), stock_pieces(0, False), stock_pieces(16, False)
c.check(cropped < 1.5 * plain and cropped < 0.5 * twice, "VTK's own path on pieces with ghost "
        "points draws the owned points alone (RMS %.4f; pieces without ghost points %.4f, the "
        "ghost points drawn twice %.4f)" % (cropped, plain, twice))
prop.SetShade(False)

c.finish()
