"""vtkObjectOrderRayCaster on pieces of a volume that carry ghost points (OwnedExtent with
WholeBounds): the pieces' images composited front to back (what ParaView's ordered compositing
does on several ranks) give the whole volume's image.

The MPI test's scene: Marschner-Lobb plus a ramp along x (65 x 57 x 49 points over [-1, 1]^3,
so that each piece covers another part of the range), three narrow opacity peaks, ScalarRange
the whole range, its parallel camera, 128 x 128 float images, a step of half a voxel. Pieces:
two along x, three along y (cut_pieces), and vtkExtentTranslator's blocks for 3 and 4 pieces
(cut along two axes, as ParaView's ranks get them); each carries 3 ghost points (two sample
distances and two points, what the plugin asks for) past the faces it shares. For the
pre-integrated classification unshaded (eight rays at a time where the processor has AVX2, and
one at a time), post- and pre-shaded, and the point-sampled one, with and without interleaved
sampling:
- the pieces composited front to back equal the whole image within float rounding (max
  2e-4): each ray is walked through the whole volume's box, every piece takes the samples its
  points hold, and only the piece that owns a sample composites its step;
- without OwnedExtent (each piece drawn as a volume of its own, as before) they differ
  where rays cross the cuts (max above 1e-3), so the check can tell.
A view exactly along the x axis puts samples on the shared face between pieces along x:
each such sample is drawn by one piece only, the image again within 2e-4.
"""

import numpy
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkRenderingCore import vtkCamera

import hovr
from hovrtesting import Checker, cut_pieces, front_to_back, mpi_ramp_scene, translator_pieces

c = Checker()
SIZE = 128
GHOSTS = 3

whole, prop, oblique = mpi_ramp_scene("float32")
low, high = whole.GetPointData().GetScalars().GetRange()
step = 0.5 * min(whole.GetSpacing())


def camera_along(position):
    """The scene's camera moved to position."""
    camera = vtkCamera()
    camera.DeepCopy(oblique)
    camera.SetPosition(*position)
    return camera


def render(image, camera, classification, shading, interleaved, instructions, owned=None):
    caster = hovr.vtkObjectOrderRayCaster()
    caster.SetInputData(image)
    caster.SetVolumeProperty(prop)
    caster.SetCamera(camera)
    caster.SetImageSize(SIZE, SIZE)
    caster.SetSampleDistance(step)
    caster.SetScalarRange(low, high)
    caster.SetClassification(classification)
    caster.SetInterleavedSampling(interleaved)
    caster.SetInstructionSet(instructions)
    if shading is not None:
        caster.SetShadingMode(shading)
    if owned is not None:
        caster.SetWholeBounds(whole.GetBounds())
        caster.SetOwnedExtent(owned)
    caster.Update()
    return vtk_to_numpy(caster.GetOutput().GetPointData().GetScalars()).reshape(
        SIZE, SIZE, 4).astype(numpy.float64)


def composite(parts, camera, settings, owned_extent):
    over = None
    for k in front_to_back(parts, whole, camera):
        owned, piece = parts[k]
        image = render(piece, camera, *settings, owned=owned if owned_extent else None)
        over = image if over is None else over + (1.0 - over[..., 3:4]) * image
    return over


P, S = hovr.vtkObjectOrderRayCaster.PREINTEGRATED, hovr.vtkObjectOrderRayCaster.POINT_SAMPLED
POST = hovr.vtkObjectOrderRayCaster.POST_SHADING
PRE = hovr.vtkObjectOrderRayCaster.PRE_SHADING
AUTO, SSE2 = hovr.vtkObjectOrderRayCaster.INSTRUCTIONS_AUTOMATIC, \
    hovr.vtkObjectOrderRayCaster.INSTRUCTIONS_SSE2
cases = [("pre-integrated", P, None, True, AUTO),
         ("pre-integrated, one ray at a time (SSE2)", P, None, True, SSE2),
         ("pre-integrated, not interleaved", P, None, False, AUTO),
         ("pre-integrated, post-shaded", P, POST, True, AUTO),
         ("pre-integrated, pre-shaded", P, PRE, True, AUTO),
         ("point-sampled", S, None, True, AUTO)]
layouts = [("2 pieces along x", cut_pieces(whole, 0, 2, GHOSTS), cut_pieces(whole, 0, 2)),
           ("3 pieces along y", cut_pieces(whole, 1, 3, GHOSTS), cut_pieces(whole, 1, 3)),
           ("3 blocks", translator_pieces(whole, 3, GHOSTS), None),
           ("4 blocks", translator_pieces(whole, 4, GHOSTS), None)]
for name, classification, shading, interleaved, instructions in cases:
    prop.SetShade(shading is not None)
    settings = (classification, shading, interleaved, instructions)
    reference = render(whole, oblique, *settings)
    c.check(reference[..., 3].max() > 0.3, "%s: the whole volume is drawn" % name)
    for layout, ghosted, plain in layouts:
        difference = numpy.abs(composite(ghosted, oblique, settings, True) - reference).max()
        c.check(difference < 2e-4, "%s, %s: composited front to back, the whole volume's "
                "image (max %.2e)" % (name, layout, difference))
        if plain is not None:
            difference = numpy.abs(composite(plain, oblique, settings, False) - reference).max()
            c.check(difference > 1e-3, "%s, %s: without ghost points the cuts show (max %.2e)"
                    % (name, layout, difference))

# Along x: the samples of every ray lie on the grid's x planes, the cuts among them.
prop.SetShade(False)
along = camera_along((4.0, 0.0, 0.0))
settings = (P, None, False, AUTO)
reference = render(whole, along, *settings)
ghosted = cut_pieces(whole, 0, 2, GHOSTS)
difference = numpy.abs(composite(ghosted, along, settings, True) - reference).max()
c.check(reference[..., 3].max() > 0.3 and difference < 2e-4, "a view along x, 2 pieces along "
        "x: the whole volume's image (max %.2e)" % difference)

c.finish()
