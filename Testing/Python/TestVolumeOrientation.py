"""Every reader path gives the field numpy wrote, point for point.

A deliberately asymmetric volume (different sizes and spacings along x, y and z, values that
name their own index) is written from numpy, without VTK, as raw data of each raw type and as
.vti, .mhd, .nii and legacy .vtk files. ``hovr.io.read_volume`` must give point (i, j, k) at
origin + spacing (i, j, k) with the value numpy stored at [k, j, i]: a reader that mirrors an
axis (as vtkImageReader2 does with rows by default) fails here. ParaView's own raw reader is
checked against the same file layout by the plugin's pvbatch test TestRawOrientation.py.
Rendering the raw file and the .vti file gives the same image.
"""

import os
import struct
import tempfile

import numpy
from vtkmodules.util.numpy_support import vtk_to_numpy

from hovr import io as hio
from hovrtesting import Checker, run_cli

c = Checker()
tmp = tempfile.mkdtemp(prefix="hovr-orientation-")
NX, NY, NZ = 6, 5, 4
SPACING = (0.5, 1.25, 2.0)
k, j, i = numpy.meshgrid(numpy.arange(NZ), numpy.arange(NY), numpy.arange(NX), indexing="ij")
FIELD = (i + 10 * j + 100 * k).astype(numpy.float64)  # indexed [z, y, x]; value names (i, j, k)


def check_field(image, values, what):
    c.check(image.GetDimensions() == (NX, NY, NZ), "%s: dimensions %s" % (
        what, image.GetDimensions()))
    c.check(numpy.allclose(image.GetSpacing(), SPACING), "%s: spacing %s" % (
        what, image.GetSpacing()))
    data = vtk_to_numpy(image.GetPointData().GetScalars()).astype(numpy.float64)
    # VTK's point order is x fastest: point id i + NX (j + NY k) is numpy's [k, j, i].
    c.check(numpy.array_equal(data, values.ravel()),
            "%s: every point holds the value numpy wrote there (first mismatch at id %s)" % (
                what, numpy.flatnonzero(data != values.ravel())[:1]))
    origin = numpy.array(image.GetOrigin())
    for point in ((0, 0, 0), (NX - 1, 0, 0), (0, NY - 1, 0), (0, 0, NZ - 1), (2, 3, 1)):
        pid = image.ComputePointId(point)
        c.check(numpy.allclose(image.GetPoint(pid), origin + numpy.multiply(point, SPACING)),
                "%s: point %s lies at origin + spacing index" % (what, point))


# Raw data of every type, x fastest, rows in increasing y, slices in increasing z.
for raw_type, dtype in (("uint8", "u1"), ("uint16", "<u2"), ("int16", "<i2"),
                        ("float32", "<f4")):
    values = FIELD % 256 if raw_type == "uint8" else FIELD - (200 if raw_type == "int16" else 0)
    path = os.path.join(tmp, "field_%s.raw" % raw_type)
    values.astype(dtype).tofile(path)
    check_field(hio.read_volume(path, (NX, NY, NZ), raw_type, SPACING), values,
                "raw " + raw_type)
# With a header of its own, skipped by --header-bytes.
headed = os.path.join(tmp, "headed.raw")
with open(headed, "wb") as stream:
    stream.write(b"HEADER" * 3)
    stream.write(FIELD.astype("<f4").tobytes())
check_field(hio.read_volume(headed, (NX, NY, NZ), "float32", SPACING, header_bytes=18), FIELD,
            "raw after an 18-byte header")

# .mhd: a MetaImage header beside the raw float file.
mhd = os.path.join(tmp, "field.mhd")
with open(mhd, "w") as stream:
    stream.write("ObjectType = Image\nNDims = 3\nDimSize = %d %d %d\n"
                 "ElementSpacing = %g %g %g\nElementType = MET_FLOAT\n"
                 "ElementByteOrderMSB = False\nElementDataFile = field_float32.raw\n"
                 % ((NX, NY, NZ) + SPACING))
check_field(hio.read_volume(mhd), FIELD, ".mhd")

# .nii: a NIfTI-1 header (348 bytes, 4 of extension flags), then the float data.
nii = os.path.join(tmp, "field.nii")
header = bytearray(348)
struct.pack_into("<i", header, 0, 348)
struct.pack_into("<8h", header, 40, 3, NX, NY, NZ, 1, 1, 1, 1)
struct.pack_into("<hh", header, 70, 16, 32)  # datatype FLOAT32, bitpix
struct.pack_into("<8f", header, 76, 1.0, *SPACING, 1, 1, 1, 1)  # pixdim, qfac 1
struct.pack_into("<f", header, 108, 352.0)  # vox_offset
struct.pack_into("<f", header, 112, 1.0)  # scl_slope
header[344:348] = b"n+1\0"
with open(nii, "wb") as stream:
    stream.write(bytes(header) + b"\0" * 4 + FIELD.astype("<f4").tobytes())
check_field(hio.read_volume(nii), FIELD, ".nii")

# Legacy .vtk structured points, ASCII.
legacy = os.path.join(tmp, "field.vtk")
with open(legacy, "w") as stream:
    stream.write("# vtk DataFile Version 3.0\nfield\nASCII\nDATASET STRUCTURED_POINTS\n"
                 "DIMENSIONS %d %d %d\nSPACING %g %g %g\nORIGIN 0 0 0\nPOINT_DATA %d\n"
                 "SCALARS scalars float 1\nLOOKUP_TABLE default\n" % (
                     (NX, NY, NZ) + SPACING + (FIELD.size,)))
    stream.write("\n".join("%g" % v for v in FIELD.ravel()) + "\n")
check_field(hio.read_volume(legacy), FIELD, "legacy .vtk")

# .vti, ASCII XML.
vti = os.path.join(tmp, "field.vti")
with open(vti, "w") as stream:
    extent = "0 %d 0 %d 0 %d" % (NX - 1, NY - 1, NZ - 1)
    stream.write('<?xml version="1.0"?>\n<VTKFile type="ImageData" version="0.1" '
                 'byte_order="LittleEndian">\n<ImageData WholeExtent="%s" Origin="0 0 0" '
                 'Spacing="%g %g %g">\n<Piece Extent="%s">\n<PointData Scalars="scalars">\n'
                 '<DataArray type="Float32" Name="scalars" format="ascii">\n%s\n'
                 '</DataArray>\n</PointData>\n<CellData/>\n</Piece>\n</ImageData>\n'
                 '</VTKFile>\n' % ((extent,) + SPACING + (extent, " ".join(
                     "%g" % v for v in FIELD.ravel()))))
check_field(hio.read_volume(vti), FIELD, ".vti")

# The raw file and the .vti file render the same image (a transfer function over the field's
# range, seen obliquely so that a mirrored axis would show).
tf = os.path.join(tmp, "field_tf.json")
with open(tf, "w") as stream:
    stream.write('{"RGBPoints": [0, 0, 0, 1, 200, 0, 1, 0, 345, 1, 0, 0], '
                 '"Points": [0, 0, 0.5, 0, 345, 0.5, 0.5, 0]}')
images = []
for args in (["--input", os.path.join(tmp, "field_float32.raw"), "--dims", NX, NY, NZ,
              "--type", "float32", "--spacing", *SPACING], ["--input", vti]):
    out = os.path.join(tmp, "render_%d.vti" % len(images))
    run_cli("render", *args, "--tf", tf, "--size", 24, 24, "--method", "reference",
            "--output", out)
    images.append(vtk_to_numpy(hio.read_vti(out).GetPointData().GetArray("RGBA")))
c.check(images[0].max() > 0.1 and numpy.array_equal(images[0], images[1]),
        "raw and .vti inputs render the same image")
c.finish()
