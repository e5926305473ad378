"""``hovr render``: the documented contract, and a clear error for every bad input.

Good input: every method writes a W x H x 1 float RGBA .vti (premultiplied, pixel (i, j) from
left and bottom) and a .png; --repeat prints one JSON line with the documented keys.
Bad input: exit code 2, a message naming the problem, no Python traceback.
"""

import json
import math
import os
import tempfile

import numpy
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPolyData
from vtkmodules.vtkIOLegacy import vtkPolyDataWriter
from vtkmodules.vtkIOXML import vtkXMLImageDataReader, vtkXMLImageDataWriter

from hovr import io as hio
from hovrtesting import Checker, run_cli, tf_path

c = Checker()
tmp = tempfile.mkdtemp(prefix="hovr-render-")
TF = tf_path("marschner-lobb-spikes")


def write_vti(path, values, spacing=(1.0, 1.0, 1.0), origin=(0.0, 0.0, 0.0), components=1):
    """Write a numpy array indexed [z, y, x] (or [z, y, x, c]) as point scalars."""
    image = vtkImageData()
    shape = values.shape[:3]
    image.SetDimensions(shape[2], shape[1], shape[0])
    image.SetSpacing(spacing)
    image.SetOrigin(origin)
    flat = numpy.ascontiguousarray(values.reshape(-1, components) if components > 1
                                   else values.ravel())
    array = numpy_to_vtk(flat, deep=True)
    array.SetName("scalars")
    image.GetPointData().SetScalars(array)
    writer = vtkXMLImageDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(image)
    writer.Write()
    return path


def read_rgba(path):
    reader = vtkXMLImageDataReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    rgba = vtk_to_numpy(image.GetPointData().GetArray("RGBA"))
    w, h, _ = image.GetDimensions()
    return image.GetDimensions(), rgba.reshape(h, w, 4)


def write_json(name, document):
    path = os.path.join(tmp, name)
    with open(path, "w") as stream:
        json.dump(document, stream)
    return path


# A volume that is opaque-ish only where x < 0 and y < 0, seen from +z with a parallel camera
# whose view up is +y: only the lower-left image quadrant may show it.
n = 17
grid = numpy.linspace(-1.0, 1.0, n)
z, y, x = numpy.meshgrid(grid, grid, grid, indexing="ij")
quadrant = numpy.where((x < -0.1) & (y < -0.1), 0.5, 0.0).astype(numpy.float32)
quadrant_vti = write_vti(os.path.join(tmp, "quadrant.vti"), quadrant,
                         spacing=(2.0 / (n - 1),) * 3, origin=(-1.0, -1.0, -1.0))
flat_tf = write_json("flat.json", [{"Name": "flat", "RGBPoints": [0, 1, 0.5, 0.25, 1, 1, 0.5, 0.25],
                                    "Points": [0, 0, 0.5, 0, 0.4, 0, 0.5, 0, 0.5, 0.6, 0.5, 0,
                                               1, 0.6, 0.5, 0]}])
top_camera = write_json("top.json", {"position": [0, 0, 5], "focal_point": [0, 0, 0],
                                     "view_up": [0, 1, 0], "parallel_projection": True,
                                     "parallel_scale": 1.2})
W, H = 40, 30
for method in ("reference", "stock", "preint1"):
    out = os.path.join(tmp, "quadrant_%s.vti" % method)
    code, stdout, stderr = run_cli("render", "--input", quadrant_vti, "--tf", flat_tf,
                                   "--camera", top_camera, "--size", W, H, "--method", method,
                                   "--step", 0.5, "--output", out, "--repeat", 2)
    line = json.loads(stdout.strip().splitlines()[-1])
    for key in ("method", "step", "width", "height", "median_ms", "min_ms", "max_ms"):
        c.check(key in line, "%s: JSON line has %s" % (method, key))
    c.check(line["method"] == method and line["width"] == W and line["height"] == H,
            "%s: JSON line describes the run" % method)
    c.check(line.get("samples_per_frame", 0) > 0, "%s: samples per frame known" % method)
    c.check(line["min_ms"] <= line["median_ms"] <= line["max_ms"], "%s: timing order" % method)
    dims, rgba = read_rgba(out)
    c.check(dims == (W, H, 1), "%s: output is W x H x 1 (%s)" % (method, dims))
    alpha = rgba[:, :, 3]
    # The view spans x in [-1.6, 1.6] over 40 columns and y in [-1.2, 1.2] over 30 rows; the
    # drawn part of the volume, x and y in [-1, -0.1], covers columns 8..18 and rows 3..13.
    lower_left = alpha[4:13, 9:18]
    others = numpy.concatenate([alpha[16:, :].ravel(), alpha[:, 21:].ravel(),
                                alpha[:2, :].ravel(), alpha[:, :7].ravel()])
    c.check(lower_left.min() > 0.3, "%s: lower-left quadrant is drawn (min alpha %.3f)"
            % (method, lower_left.min()))
    c.check(others.max() < 1e-6, "%s: the rest is transparent (max alpha %.3g)"
            % (method, others.max()))
    c.check(numpy.all(rgba[:, :, :3] <= rgba[:, :, 3:4] + 1e-5),
            "%s: colour is premultiplied (rgb <= alpha)" % method)
    # A homogeneous slab along the view: 2 world units of extinction -ln(1 - 0.6) per unit.
    expected = 1.0 - math.exp(math.log(1.0 - 0.6) * 2.0)
    c.check(abs(alpha[8, 13] - expected) < 0.02, "%s: slab opacity %.4f, expected %.4f"
            % (method, alpha[8, 13], expected))

png = os.path.join(tmp, "ml.png")
run_cli("render", "--input", "marschner-lobb:21", "--tf", TF, "--opacity-unit-distance", 0.05,
        "--size", 32, 32, "--output", png)
with open(png, "rb") as stream:
    c.check(stream.read(8) == b"\x89PNG\r\n\x1a\n", "--output .png writes a PNG")

# Raw input with --dims/--type/--spacing, little-endian, x fastest.
raw = os.path.join(tmp, "ramp.raw")
(numpy.arange(8 * 6 * 5, dtype="<u2") % 200).tofile(raw)
ramp_tf = write_json("ramp.json", {"RGBPoints": [0, 0, 0, 1, 200, 1, 0, 0],
                                   "Points": [0, 0.1, 0.5, 0, 200, 0.9, 0.5, 0]})
run_cli("render", "--input", raw, "--dims", 8, 6, 5, "--type", "uint16", "--spacing", 1, 2, 1,
        "--tf", ramp_tf, "--size", 16, 16, "--method", "preint1",
        "--output", os.path.join(tmp, "raw.vti"))

# NaN values: a warning, and a finite image.
nan_volume = quadrant.copy()
nan_volume[8, 8, 2] = numpy.nan
nan_vti = write_vti(os.path.join(tmp, "nan.vti"), nan_volume, spacing=(2.0 / (n - 1),) * 3,
                    origin=(-1.0, -1.0, -1.0))
for method in ("reference", "preint1", "stock"):
    out = os.path.join(tmp, "nan_%s.vti" % method)
    code, stdout, stderr = run_cli("render", "--input", nan_vti, "--tf", flat_tf, "--camera",
                                   top_camera, "--size", 24, 24, "--method", method,
                                   "--output", out)
    c.check("NaN" in stderr, "%s: NaN values are reported" % method)
    c.check(numpy.isfinite(read_rgba(out)[1]).all(), "%s: NaN gives no NaN pixels" % method)

# Bad inputs: exit code 2 and a message that names the problem.
multi = write_vti(os.path.join(tmp, "multi.vti"), numpy.zeros((4, 4, 4, 3), numpy.float32),
                  components=3)
thin = write_vti(os.path.join(tmp, "thin.vti"), numpy.zeros((1, 5, 5), numpy.float32))
single = write_vti(os.path.join(tmp, "single.vti"), numpy.zeros((1, 1, 1), numpy.float32))
empty = os.path.join(tmp, "empty.vti")
writer = vtkXMLImageDataWriter()
writer.SetFileName(empty)
writer.SetInputData(vtkImageData())
writer.Write()
garbage = os.path.join(tmp, "garbage.vti")
with open(garbage, "w") as stream:
    stream.write("not a VTK file")
poly = os.path.join(tmp, "poly.vtk")
poly_writer = vtkPolyDataWriter()
poly_writer.SetFileName(poly)
poly_writer.SetInputData(vtkPolyData())
poly_writer.Write()
no_points = write_json("nopoints.json", {"RGBPoints": [0, 0, 0, 0, 1, 1, 1, 1]})
no_rgb = write_json("norgb.json", {"Points": [0, 0, 0.5, 0, 1, 1, 0.5, 0]})
not_tf = write_json("nottf.json", {"Name": "nothing"})
bad_alpha = write_json("badalpha.json", {"RGBPoints": [0, 0, 0, 0], "Points": [0, 1.5, 0.5, 0]})
parallel_up = write_json("badcam.json", {"position": [0, 0, 5], "focal_point": [0, 0, 0],
                                         "view_up": [0, 0, 1]})
small_raw = os.path.join(tmp, "small.raw")
numpy.zeros(10, numpy.uint8).tofile(small_raw)
nan_raw = os.path.join(tmp, "allnan.raw")
numpy.full(4 * 4 * 4, numpy.nan, numpy.float32).tofile(nan_raw)
inf_raw = os.path.join(tmp, "inf.raw")
inf_values = numpy.linspace(0.0, 1.0, 4 * 4 * 4, dtype=numpy.float32)
inf_values[5] = numpy.inf
inf_values.tofile(inf_raw)
missing = os.path.join(tmp, "does-not-exist.vti")
good = ["--tf", TF, "--size", 16, 16]
cases = [
    ("isosurface without --isovalue", ["--input", "marschner-lobb:9", "--method",
                                       "iso-analytic"] + good, "--isovalue"),
    ("--blend contradicting the method", ["--input", "marschner-lobb:9", "--method",
                                          "mip-analytic", "--blend", "iso"] + good,
     "contradicts"),
    ("missing input", ["--input", missing] + good, "not found"),
    ("unreadable input", ["--input", garbage] + good, "cannot read"),
    ("a directory as input", ["--input", tmp] + good, "not found"),
    ("unknown format", ["--input", TF] + good, "unknown volume format"),
    ("not image data", ["--input", poly] + good, "not image data"),
    ("multi-component scalars", ["--input", multi] + good, "components"),
    ("1-voxel-thick volume", ["--input", thin] + good, "at least 2 points"),
    ("1-voxel volume", ["--input", single] + good, "at least 2 points"),
    ("empty volume", ["--input", empty] + good, "empty"),
    ("raw without dims", ["--input", small_raw, "--type", "uint8"] + good, "--dims"),
    ("raw too small", ["--input", small_raw, "--dims", 4, 4, 4, "--type", "uint8"] + good,
     "bytes"),
    # 10 bytes for 2 x 2 x 2: the 2 extra bytes are no guess at a header.
    ("raw larger than its dims", ["--input", small_raw, "--dims", 2, 2, 2, "--type", "uint8"]
     + good, "--header-bytes 2"),
    ("raw larger than dims and header", ["--input", small_raw, "--dims", 2, 2, 2, "--type",
                                         "uint8", "--header-bytes", 1] + good, "header"),
    ("--dims with a .vti", ["--input", quadrant_vti, "--dims", 4, 4, 4] + good,
     "raw input only"),
    ("--type with a generated volume", ["--input", "marschner-lobb:9", "--type", "uint8"]
     + good, "raw input only"),
    ("all-NaN volume", ["--input", nan_raw, "--dims", 4, 4, 4, "--type", "float32"] + good,
     "NaN"),
    # VTK's own mappers would draw it without a word: checked for every method.
    ("infinite values, stock method", ["--input", inf_raw, "--dims", 4, 4, 4, "--type",
                                       "float32", "--method", "stock"] + good, "infinite"),
    ("step too small for any ray caster", ["--input", quadrant_vti, "--tf", TF, "--step",
                                           1e-9], "samples along the volume's diagonal"),
    ("step too small, CPU method", ["--input", quadrant_vti, "--tf", TF, "--step", 1e-9,
                                    "--method", "objectorder"], "samples"),
    ("--isovalue with a projection", ["--input", "marschner-lobb:9", "--method",
                                      "mip-analytic", "--isovalue", 0.5] + good,
     "isosurface rendering only"),
    ("--isovalue with composite blending", ["--input", "marschner-lobb:9", "--isovalue", 0.5]
     + good, "isosurface rendering only"),
    ("isovalue outside the data range", ["--input", "marschner-lobb:9", "--method",
                                         "iso-analytic", "--isovalue", 7] + good,
     "outside the data range"),
    ("output into a missing folder", ["--input", quadrant_vti, "--tf", TF, "--output",
                                      os.path.join(tmp, "no-such-folder", "x.vti")],
     "does not exist"),
    ("output onto a folder", ["--input", quadrant_vti, "--tf", TF, "--output",
                              os.path.join(tmp, "a-folder.vti")], "is a folder"),
    # A folder that exists but takes no files, even for root: the write itself fails.
    ("write failure", ["--input", quadrant_vti, "--tf", TF, "--size", 8, 8, "--output",
                       "/proc/hovr-test.png"], "cannot write"),
    ("missing transfer function", ["--input", quadrant_vti, "--tf", missing, "--size", 8, 8],
     "not found"),
    ("transfer function without Points", ["--input", quadrant_vti, "--tf", no_points],
     "Points"),
    ("transfer function without RGBPoints", ["--input", quadrant_vti, "--tf", no_rgb],
     "RGBPoints"),
    ("file without a transfer function", ["--input", quadrant_vti, "--tf", not_tf],
     "no transfer function"),
    ("opacity above 1", ["--input", quadrant_vti, "--tf", bad_alpha], "outside [0, 1]"),
    ("camera view up along the view", ["--input", quadrant_vti, "--tf", TF, "--camera",
                                       parallel_up], "parallel"),
    ("missing camera", ["--input", quadrant_vti, "--tf", TF, "--camera", missing], "not found"),
    ("bad output extension", ["--input", quadrant_vti, "--tf", TF, "--output",
                              os.path.join(tmp, "x.jpg")], ".vti or .png"),
    ("zero step", ["--input", quadrant_vti, "--tf", TF, "--step", 0], "positive"),
    ("negative step", ["--input", quadrant_vti, "--tf", TF, "--step", -1], "positive"),
    ("zero unit distance", ["--input", quadrant_vti, "--tf", TF, "--opacity-unit-distance", 0],
     "positive"),
    ("negative unit distance", ["--input", quadrant_vti, "--tf", TF,
                                "--opacity-unit-distance", -2], "positive"),
    ("NaN step", ["--input", quadrant_vti, "--tf", TF, "--step", "nan"], "positive"),
    ("zero size", ["--input", quadrant_vti, "--tf", TF, "--size", 0, 10], "[1, 16384]"),
    ("unknown method", ["--input", quadrant_vti, "--tf", TF, "--method", "magic"], "magic"),
    ("--lmax out of range", ["--input", "blobs:9", "--method", "adaptive-cpu", "--lmax", 9]
     + good, "[0, 8]"),
    ("negative oracle epsilon", ["--input", "blobs:9", "--method", "adaptive-cpu",
                                 "--oracle-epsilon", -0.1] + good, "non-negative"),
    ("unknown oracle mode", ["--input", "blobs:9", "--method", "adaptive-cpu",
                             "--oracle-mode", "psychic"] + good, "psychic"),
    ("pyramid image not divisible by 2^lmax", ["--input", "blobs:9", "--method",
                                               "adaptive-cpu", "--tf", TF, "--size", 30, 30],
     "divisible"),
]
os.makedirs(os.path.join(tmp, "a-folder.vti"))
for what, args, message in cases:
    code, stdout, stderr = run_cli("render", *args, expect=None)
    c.check(code == 2, "%s: exit code 2 (got %d)" % (what, code))
    c.check(message in stderr, "%s: message mentions %r: %s" % (what, message, stderr.strip()))
    c.check("Traceback" not in stderr, "%s: no traceback" % what)
    # One line per problem: VTK's own log lines (with colour codes) stay out of it.
    c.check("\x1b[" not in stderr and "ERR|" not in stderr,
            "%s: no raw VTK log lines" % what)

# Several isovalues, one outside the data range: a warning, and the surface of the other.
out = os.path.join(tmp, "iso_partly_outside.vti")
code, stdout, stderr = run_cli("render", "--input", "marschner-lobb:9", "--method",
                               "iso-analytic", "--isovalue", 7, "--isovalue", 0.5, *good,
                               "--output", out)
c.check("warning" in stderr and "outside the data range" in stderr,
        "an isovalue outside the data range is reported: %s" % stderr.strip())
c.check(read_rgba(out)[1][:, :, 3].max() > 0.5, "the isovalue inside the range is drawn")
# Isosurfaces and projections: the Depth and MaxScalar arrays, compared with the reference.
iso_ref = os.path.join(tmp, "iso_ref.vti")
iso_out = os.path.join(tmp, "iso.vti")
common = ["--input", "marschner-lobb:21", "--tf", tf_path("iso-opaque"), "--size", 48, 48,
          "--isovalue", 0.5]
run_cli("render", *common, "--method", "reference", "--blend", "iso", "--output", iso_ref)
_, stdout, _ = run_cli("render", *common, "--method", "iso-analytic", "--output", iso_out,
                       "--reference", iso_ref)
line = json.loads(stdout)
depth = vtk_to_numpy(hio.read_vti(iso_out).GetPointData().GetArray("Depth"))
c.check(numpy.isfinite(depth).sum() > 100 and numpy.isnan(depth).sum() > 100,
        "iso-analytic writes a Depth array with hits and NaN misses")
c.check(line["hit_miss_disagreements"] == 0 and line["depth_max_error_voxels"] < 1e-3,
        "iso-analytic against the reference from the command line: %s" % stdout.strip())
mip_out = os.path.join(tmp, "mip.vti")
run_cli("render", "--input", "marschner-lobb:21", "--tf", TF, "--size", 32, 32, "--method",
        "mip-stock", "--step", 0.5, "--output", mip_out)
maximum = vtk_to_numpy(hio.read_vti(mip_out).GetPointData().GetArray("MaxScalar"))
c.check(numpy.nanmax(maximum) <= 1.0 + 1e-6 and numpy.isfinite(maximum).sum() > 100,
        "mip-stock writes a MaxScalar array in data units")
# Adaptive sampling from the command line: the pyramid on the CPU with the default oracle
# on the generated blobs, against the reference and against its own full rate.
common = ["--input", "blobs:33", "--tf", tf_path("blobs"), "--opacity-unit-distance", 0.0625,
          "--size", 64, 64, "--parallel"]
blobs_ref = os.path.join(tmp, "blobs_ref.vti")
run_cli("render", *common, "--method", "reference", "--output", blobs_ref)
lines = {}
for mode in ("min", "range"):
    _, stdout, _ = run_cli("render", *common, "--method", "adaptive-cpu", "--oracle-mode", mode,
                           "--repeat", 1, "--reference", blobs_ref)
    lines[mode] = json.loads(stdout)
c.check(lines["min"]["sample_ratio_to_full"] > 1.0 and
        lines["range"]["sample_ratio_to_full"] < 0.25 and
        lines["range"]["samples_per_frame"] == lines["range"]["sample_ops"],
        "adaptive-cpu reports its samples against the full rate: %.3f (min oracle), %.3f "
        "(range oracle)" % (lines["min"]["sample_ratio_to_full"],
                            lines["range"]["sample_ratio_to_full"]))
c.check(lines["range"]["rmse"] <= 1.5 * lines["min"]["rmse"] + 1e-6,
        "and an error close to full rate's: %.3g vs %.3g" % (lines["range"]["rmse"],
                                                             lines["min"]["rmse"]))
c.finish()
