"""vtkWholeVolumeAssembler: the whole volume put together from its pieces by a maximum over
them, as the ParaView plugin does over its ranks (the maximum taken here with numpy).

A seeded random volume with an offset extent, as uint16, float with NaN values and double:
- pieces that share their boundary points, pieces that overlap by two layers (ghost points)
  and a process without data give, at stride 1, the whole volume's values bit for bit (NaN
  where it has NaN) and its geometry (extent, origin, spacing);
- at stride 2 every second point along each axis, the spacing doubled and the origin at the
  whole extent's first point;
- a point no piece holds is an error, not a silent value;
- ComputeStride: 256^3 float values fit 64 MiB at stride 1, 257^3 need stride 2;
- bad arguments (a stride of 0, scalars of two components, scalars of another type) are
  errors.
"""

import numpy
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkUnsignedCharArray
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.util.vtkConstants import VTK_DOUBLE, VTK_FLOAT, VTK_UNSIGNED_SHORT

import hovr
from hovrtesting import Checker, Messages

c = Checker()
rng = numpy.random.default_rng(7)
WHOLE = (2, 18, -3, 9, 0, 10)  # 17 x 13 x 11 points
SHAPE = (WHOLE[5] - WHOLE[4] + 1, WHOLE[3] - WHOLE[2] + 1, WHOLE[1] - WHOLE[0] + 1)  # z, y, x
ORIGIN = (0.5, -1.0, 2.0)
SPACING = (0.25, 0.5, 0.75)


def image(values, extent, name="Scalars"):
    data = vtkImageData()
    data.SetExtent(extent)
    data.SetOrigin(ORIGIN)
    data.SetSpacing(SPACING)
    array = numpy_to_vtk(numpy.ascontiguousarray(values).ravel(), deep=True)
    array.SetName(name)
    data.GetPointData().SetScalars(array)
    return data


def piece_of(values, extent):
    """The piece of the whole volume over extent (inside WHOLE)."""
    x0, x1, y0, y1, z0, z1 = (e - WHOLE[2 * (k // 2)] for k, e in enumerate(extent))
    return image(values[z0:z1 + 1, y0:y1 + 1, x0:x1 + 1], extent)


def assemble(values, extents, stride, data_type):
    """Finish()'s output over the pieces of extents (None: a process without data), and the
    errors of the last Finish()."""
    reduced_values, reduced_coverage, last = None, None, None
    for extent in extents:
        assembler = hovr.vtkWholeVolumeAssembler()
        piece = piece_of(values, extent) if extent else None
        scalars = piece.GetPointData().GetScalars() if piece else None
        c.check(assembler.Prepare(piece, scalars, data_type, WHOLE, stride),
                "Prepare for piece %s" % (extent,))
        v = vtk_to_numpy(assembler.GetValues()).copy()
        cov = vtk_to_numpy(assembler.GetCoverage()).copy()
        reduced_values = v if reduced_values is None else numpy.maximum(reduced_values, v)
        reduced_coverage = cov if reduced_coverage is None else numpy.maximum(reduced_coverage,
                                                                              cov)
        last = assembler
    out = vtkImageData()
    values_array = numpy_to_vtk(reduced_values, deep=True)
    coverage_array = vtkUnsignedCharArray()
    coverage_array.DeepCopy(numpy_to_vtk(reduced_coverage, deep=True))
    messages = Messages(last)
    geometry = piece_of(values, (WHOLE[0], WHOLE[0], WHOLE[2], WHOLE[2], WHOLE[4], WHOLE[4]))
    ok = last.Finish(values_array, coverage_array, geometry, "Scalars", out)
    return (out if ok else None), messages.errors


def same(a, b):
    """Equal values, NaN where both are NaN."""
    return a.shape == b.shape and bool(numpy.all((a == b) | (numpy.isnan(a) & numpy.isnan(b))))


kinds = {"uint16": (rng.integers(0, 65535, SHAPE).astype(numpy.uint16), VTK_UNSIGNED_SHORT),
         "float": (rng.standard_normal(SHAPE).astype(numpy.float32), VTK_FLOAT),
         "double": (rng.standard_normal(SHAPE), VTK_DOUBLE)}
kinds["float"][0][3, 4, 5] = numpy.nan
kinds["float"][0][0, 0, 0] = numpy.nan
partitions = {
    "shared boundaries": [(2, 8, -3, 9, 0, 10), (8, 13, -3, 9, 0, 10), (13, 18, -3, 4, 0, 10),
                          (13, 18, 4, 9, 0, 10)],
    "ghost layers, a process without data": [(2, 10, -3, 9, 0, 6), (8, 18, -3, 9, 0, 6),
                                             (2, 18, -3, 9, 4, 10), None],
}
for kind, (values, data_type) in kinds.items():
    for label, extents in partitions.items():
        name = "%s, %s" % (kind, label)
        whole, errors = assemble(values, extents, 1, data_type)
        c.check(whole is not None and not errors, "%s: put together (%s)" % (name, errors))
        if whole is None:
            continue
        got = vtk_to_numpy(whole.GetPointData().GetScalars()).reshape(SHAPE)
        c.check(got.dtype == values.dtype and same(got, values),
                "%s: the whole volume's values, bit for bit" % name)
        c.check(tuple(whole.GetExtent()) == WHOLE and whole.GetOrigin() == ORIGIN and
                whole.GetSpacing() == SPACING,
                "%s: the whole volume's geometry (%s, %s, %s)" % (
                    name, whole.GetExtent(), whole.GetOrigin(), whole.GetSpacing()))
    # Every second point.
    whole, errors = assemble(values, partitions["shared boundaries"], 2, data_type)
    expected = values[::2, ::2, ::2]
    got = vtk_to_numpy(whole.GetPointData().GetScalars()).reshape(expected.shape) \
        if whole is not None else None
    first = [ORIGIN[a] + WHOLE[2 * a] * SPACING[a] for a in range(3)]
    c.check(got is not None and same(got, expected) and
            tuple(whole.GetExtent()) == (0, 8, 0, 6, 0, 5) and
            numpy.allclose(whole.GetOrigin(), first, rtol=0, atol=1e-12) and
            numpy.allclose(whole.GetSpacing(), [2 * s for s in SPACING], rtol=0, atol=0),
            "%s, stride 2: every second point, spacing doubled, origin at the first point" % kind)
    # A point no piece holds.
    whole, errors = assemble(values, [(2, 8, -3, 9, 0, 10), (10, 18, -3, 9, 0, 10)], 1,
                             data_type)
    c.check(whole is None and any("held by no piece" in e for e in errors),
            "%s: a point no piece holds is an error (%s)" % (kind, errors))

c.check(hovr.vtkWholeVolumeAssembler.ComputeStride((0, 255, 0, 255, 0, 255), 4,
                                                    64.0 * 2 ** 20) == 1 and
        hovr.vtkWholeVolumeAssembler.ComputeStride((0, 256, 0, 256, 0, 256), 4,
                                                    64.0 * 2 ** 20) == 2,
        "ComputeStride: 256^3 floats fit 64 MiB, 257^3 take every second point")

# Bad arguments.
assembler = hovr.vtkWholeVolumeAssembler()
messages = Messages(assembler)
values = kinds["float"][0]
piece = piece_of(values, WHOLE)
two = vtkImageData()
two.DeepCopy(piece)
pair = numpy_to_vtk(numpy.zeros((piece.GetNumberOfPoints(), 2), dtype=numpy.float32), deep=True)
two.GetPointData().SetScalars(pair)
c.check(not assembler.Prepare(piece, piece.GetPointData().GetScalars(), VTK_FLOAT, WHOLE, 0),
        "a stride of 0 is refused")
c.check(not assembler.Prepare(two, pair, VTK_FLOAT, WHOLE, 1), "two components are refused")
c.check(not assembler.Prepare(piece, piece.GetPointData().GetScalars(), VTK_DOUBLE, WHOLE, 1),
        "scalars of another type than the one given are refused")
c.check(len(messages.errors) == 3, "each with an error (%s)" % messages.errors)
c.finish()
