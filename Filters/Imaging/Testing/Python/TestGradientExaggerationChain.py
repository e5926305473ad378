"""vtkGradientExaggeration against a chain of VTK's own imaging filters, and from Python.

The chain computes N' = N + eps (N - N_m) (Guetat et al. 2010, line 99 of the paper's text)
with stock VTK 9.1 filters only:

  vtkImageGradient (3D, HandleBoundaries on) or vtkImageSobel3D  -> G
  vtkImageNormalize                                             -> N
  vtkImageConvolve, a k^3 kernel of ones                         -> M (the box sum)
  vtkImageNormalize                                             -> N_m
  vtkImageWeightedSum of (N, N_m), weights (1 + eps, -eps)       -> N' (per component)
  vtkImageNormalize                                             -> the output

on the Marschner-Lobb volume with anisotropic spacing, for both gradient methods, several eps
and k = 3 and 5. The two agree in the interior, at least k/2 + 1 voxels from every face: on
the faces vtkImageGradient and vtkImageSobel3D repeat the edge value where the filter takes a
one-sided difference (half the face-normal component; a linear field would not keep its
normal), and a box reaching a face voxel inherits that difference. (vtkImageConvolve counts
neighbours outside the image as zero, which would be the truncated box sum at the faces.)

Then the filter runs with a progress observer (events arrive, rising to 1), reports a bad
setting through its error observers, and is reachable as hovr.vtkGradientExaggeration.
"""

import numpy
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import VTK_DOUBLE, vtkCommand
from vtkmodules.vtkImagingCore import (vtkImageAppendComponents, vtkImageChangeInformation,
                                       vtkImageExtractComponents)
from vtkmodules.vtkImagingGeneral import (vtkImageConvolve, vtkImageGradient, vtkImageNormalize,
                                          vtkImageSobel3D)
from vtkmodules.vtkImagingMath import vtkImageWeightedSum

import hovr
from hovrtesting import Checker, Messages

c = Checker()
DIMS = (33, 29, 25)
SPACING = (0.06, 0.075, 0.09)
# Both sides store floats (2^-24, about 6e-8, per component and step) through about a dozen
# steps (vtkImageNormalize even sums the squares in float), and N' = (1 + eps) N - eps N_m
# multiplies an error in N or N_m by up to 1 + 2 eps (7 for eps = 3).
TOLERANCE = 1e-5

source = hovr.vtkMarschnerLobbSource()
source.SetDimensions(*DIMS)
# Double values: vtkImageSobel3D adds neighbours in the input type, which in float loses
# digits of the small differences it then takes.
source.SetOutputScalarType(VTK_DOUBLE)
spacing = vtkImageChangeInformation()
spacing.SetInputConnection(source.GetOutputPort())
spacing.SetOutputSpacing(*SPACING)
spacing.Update()
volume = spacing.GetOutput()


def as_vectors(image, name=None):
    """The (z, y, x, 3) array of an image's 3-component point array (default: the scalars)."""
    data = image.GetPointData()
    array = data.GetArray(name) if name else data.GetScalars()
    nx, ny, nz = image.GetDimensions()
    return vtk_to_numpy(array).reshape(nz, ny, nx, 3).astype(numpy.float64)


def chain(method, eps, k):
    gradient = vtkImageSobel3D() if method == "sobel" else vtkImageGradient()
    if method != "sobel":
        gradient.SetDimensionality(3)
        gradient.HandleBoundariesOn()
    gradient.SetInputData(volume)
    normals = vtkImageNormalize()
    normals.SetInputConnection(gradient.GetOutputPort())
    box = vtkImageConvolve()
    box.SetInputConnection(normals.GetOutputPort())
    if k == 5:
        box.SetKernel5x5x5([1.0] * 125)
    else:
        box.SetKernel3x3x3([1.0] * 27)
    mean = vtkImageNormalize()
    mean.SetInputConnection(box.GetOutputPort())
    # vtkImageWeightedSum makes one-component output (it walks three-component inputs as if
    # they had one), so it sums each component apart.
    exaggerated = vtkImageAppendComponents()
    for component in range(3):
        parts = []
        for image in (normals, mean):
            part = vtkImageExtractComponents()
            part.SetInputConnection(image.GetOutputPort())
            part.SetComponents(component)
            parts.append(part)
        weighted = vtkImageWeightedSum()
        weighted.AddInputConnection(parts[0].GetOutputPort())
        weighted.AddInputConnection(parts[1].GetOutputPort())
        weighted.SetWeight(0, 1.0 + eps)
        weighted.SetWeight(1, -eps)
        exaggerated.AddInputConnection(weighted.GetOutputPort())
    output = vtkImageNormalize()
    output.SetInputConnection(exaggerated.GetOutputPort())
    output.Update()
    return as_vectors(output.GetOutput()), as_vectors(normals.GetOutput())


def run_filter(method, eps, k):
    f = hovr.vtkGradientExaggeration()
    f.SetInputData(volume)
    if method == "sobel":
        f.SetGradientMethodToSobel()
    f.SetEpsilon(eps)
    f.SetNeighborhoodSize(k)
    f.Update()
    return as_vectors(f.GetOutput(), "ExaggeratedNormals")


for method in ("central", "sobel"):
    for eps, k in ((0.0, 5), (1.0, 5), (3.0, 5), (1.0, 3)):
        label = "%s, eps %g, k %d" % (method, eps, k)
        expected, normals = chain(method, eps, k)
        got = run_filter(method, eps, k)
        m = k // 2 + 1
        inner = (slice(m, -m),) * 3
        # The chain has no zero-gradient mask: compare where the gradient is not zero (all of
        # the interior here; checked so that the comparison covers it).
        nonzero = numpy.linalg.norm(normals[inner], axis=-1) > 0.5
        c.check(nonzero.mean() > 0.99, "%s: gradients non-zero in the interior" % label)
        difference = numpy.linalg.norm(got[inner] - expected[inner], axis=-1)[nonzero]
        c.check(difference.max() < TOLERANCE,
                "%s: equals the VTK chain in the interior (largest difference %.3g)"
                % (label, difference.max()))
        lengths = numpy.linalg.norm(got, axis=-1)
        c.check(numpy.all(numpy.abs(lengths - 1.0) < 1e-6),
                "%s: unit normals everywhere" % label)
        if eps == 0.0:
            # On the faces the chain's gradient has half the face-normal component, so the two
            # differ there: the comparison above is restricted for a reason.
            face = numpy.linalg.norm(got[0, 1:-1, 1:-1] - expected[0, 1:-1, 1:-1], axis=-1)
            c.check(face.max() > 1e-3, "%s: differs from the chain on the z = 0 face (%.3g)"
                    % (label, face.max()))
        else:
            # Exaggeration changes the normals: far from the eps = 0 ones.
            plain = run_filter(method, 0.0, k)
            c.check(numpy.linalg.norm(got - plain, axis=-1).max() > 0.1,
                    "%s: differs from eps = 0" % label)

# From Python: progress events arrive and rise to 1.
f = hovr.vtkGradientExaggeration()
f.SetInputData(volume)
progress = []
f.AddObserver(vtkCommand.ProgressEvent, lambda obj, event: progress.append(obj.GetProgress()))
f.Update()
c.check(len(progress) >= 10, "progress events arrive (%d)" % len(progress))
c.check(progress == sorted(progress) and progress[-1] == 1.0, "progress rises to 1")
c.check(f.GetEpsilon() == 1.0 and f.GetNeighborhoodSize() == 5 and
        f.GetGradientMethod() == hovr.vtkGradientExaggeration.CENTRAL_DIFFERENCE and
        f.GetOutputArrayName() == "ExaggeratedNormals", "the documented initial values")
output = f.GetOutput()
c.check(output.GetPointData().GetScalars().GetName() == "MarschnerLobb",
        "the input scalars pass through")
normals = output.GetPointData().GetArray("ExaggeratedNormals")
c.check(normals is not None and normals.GetNumberOfComponents() == 3 and
        normals.GetDataTypeAsString() == "float", "a 3-component float array of normals")

# A bad setting: an error to the observers and an empty output.
messages = Messages(f)
f.SetNeighborhoodSize(4)
f.Update()
c.check(len(messages.errors) == 1 and "odd" in messages.errors[0],
        "an even NeighborhoodSize is reported: %s" % messages.errors)
c.check(f.GetOutput().GetNumberOfPoints() == 0, "and the output is empty")
c.finish()
