"""``hovr render``'s looks: named views, colour maps (ParaView presets by file or name, in
their colour space, rescaled to the data range), opacity specifications, shading, and the
one-line summary on success.

- --view: +z and -z see mirror images; --zoom 0.5 covers about four times the pixels of 0.25;
  --azimuth 90 from +x gives a +y or -y view; --camera with --view is an error.
- --colormap: an isosurface is coloured by the map at its isovalue, as VTK's
  vtkColorTransferFunction evaluates it in the preset's ColorSpace after rescaling its points
  to the data range (Diverging and RGB differ; both match). By name when ParaView's presets
  are exported (HOVR_PARAVIEW_PRESETS), with suggestions for an unknown name.
- --opacity: without --tf, MinIP defaults to ramp-down and is not black; bad specifications
  are errors.
- --shade: the analytic isosurface is lit (its colour varies over the surface) and matches
  the reference integrator's lit surface.
"""

import json
import os
import tempfile

import numpy
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkIOXML import vtkXMLImageDataReader, vtkXMLImageDataWriter
from vtkmodules.vtkRenderingCore import vtkColorTransferFunction

import hovr
from hovrtesting import Checker, run_cli

c = Checker()
tmp = tempfile.mkdtemp(prefix="hovr-appearance-")
SIZE = ["--size", 48, 40]
ML = ["--input", "marschner-lobb:21"]


def read(path, array="RGBA"):
    reader = vtkXMLImageDataReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    w, h, _ = image.GetDimensions()
    values = vtk_to_numpy(image.GetPointData().GetArray(array))
    return values.reshape(h, w, -1)


def render(name, *args, expect=0):
    out = os.path.join(tmp, name + ".vti")
    code, _, stderr = run_cli("render", *args, "--output", out, expect=expect)
    return (read(out) if code == 0 else None), stderr


def write_json(name, document):
    path = os.path.join(tmp, name)
    with open(path, "w") as stream:
        json.dump(document, stream)
    return path


# The summary line on success.
image, stderr = render("summary", *ML, *SIZE, "--method", "reference")
line = stderr.strip().splitlines()[-1]
c.check(line.startswith("hovr render: ") and "summary.vti" in line and "reference" in line
        and "48x40" in line and line.endswith(" ms"),
        "one summary line on success: path, method, size, ms (%r)" % line)

# Named views, on a volume without symmetries, as parallel maximum intensity projections by
# the reference integrator (the same from opposite sides, mirrored; no GPU rounding).
g = numpy.linspace(0.0, 1.0, 12)
z, y, x = numpy.meshgrid(g, g, g, indexing="ij")
lopsided = (0.6 * x * x + 0.3 * numpy.sin(3.0 * y + 0.4) * x + 0.25 * z * y).astype(numpy.float32)
image = vtkImageData()
image.SetDimensions(12, 12, 12)
array = numpy_to_vtk(lopsided.ravel(), deep=1)
array.SetName("scalars")
image.GetPointData().SetScalars(array)
writer = vtkXMLImageDataWriter()
writer.SetFileName(os.path.join(tmp, "lopsided.vti"))
writer.SetInputData(image)
writer.Write()
MIP = ["--input", os.path.join(tmp, "lopsided.vti"), *SIZE, "--method", "reference",
       "--blend", "mip", "--parallel"]
plus, _ = render("plus-z", *MIP, "--view", "+z")
minus, _ = render("minus-z", *MIP, "--view=-z")
mirror = numpy.abs(plus - minus[:, ::-1]).max()
c.check(mirror < 1e-4 and numpy.abs(plus - minus).max() > 0.01,
        "--view +z and -z are mirror images (%.2g apart mirrored)" % mirror)
near, _ = render("zoom", *MIP, "--view", "+z", "--zoom", 0.5)
far, _ = render("far", *MIP, "--view", "+z", "--zoom", 0.25)
ratio = (near[:, :, 3] > 0).sum() / max(1, (far[:, :, 3] > 0).sum())
c.check(3.0 < ratio < 5.0, "--zoom 0.5 against 0.25 covers about 4 times the pixels (%.2f)"
        % ratio)
x_view, _ = render("x", *MIP, "--view", "+x")
turned, _ = render("turned", *MIP, "--view", "+x", "--azimuth", 90)
y_views = [render(v, *MIP, "--view=" + v)[0] for v in ("+y", "-y")]
closest = min(numpy.abs(turned - y).max() for y in y_views)
c.check(closest < 1e-4 and numpy.abs(turned - x_view).max() > 0.01,
        "--azimuth 90 from +x gives a y view (%.2g from the nearest)" % closest)
code, _, stderr = run_cli("render", *ML, *SIZE, "--camera", write_json(
    "cam.json", {"position": [0, 0, 5], "focal_point": [0, 0, 0], "view_up": [0, 1, 0]}),
    "--view", "+x", expect=2)
c.check("does not combine" in stderr, "--camera with --view is an error (%s)" % stderr.strip())

# Colour maps: an unshaded isosurface takes the colour map's colour at its isovalue.
ISO = 0.3
source = hovr.vtkMarschnerLobbSource()
source.SetDimensions(21, 21, 21)
source.Update()
LOW, HIGH = source.GetOutput().GetPointData().GetScalars().GetFiniteRange()
for space in ("Diverging", "RGB", "Lab"):
    preset = write_json("map-%s.json" % space, [{
        "Name": "test", "ColorSpace": space,
        "RGBPoints": [-1.0, 0.23, 0.30, 0.75, 0.0, 0.87, 0.87, 0.87, 1.0, 0.71, 0.02, 0.15]}])
    surface, _ = render("iso-%s" % space, *ML, *SIZE, "--method", "reference", "--blend", "iso",
                        "--isovalue", ISO, "--colormap", preset)
    expected = vtkColorTransferFunction()
    getattr(expected, "SetColorSpaceTo" + space)()
    # The preset's [-1, 1] rescaled to the data range.
    for x, rgb in ((0.0, (0.23, 0.30, 0.75)), (0.5, (0.87, 0.87, 0.87)),
                   (1.0, (0.71, 0.02, 0.15))):
        expected.AddRGBPoint(LOW + x * (HIGH - LOW), *rgb)
    want = numpy.array(expected.GetColor(ISO))
    hits = surface[:, :, 3] > 0.5
    got = surface[hits][:, :3]
    c.check(hits.sum() > 50 and numpy.abs(got - want).max() < 1e-5,
            "--colormap in %s: the surface's colour is the map's at the isovalue (%s, want %s)"
            % (space, got.mean(axis=0).round(4), want.round(4)))
presets_file = os.environ.get("HOVR_PARAVIEW_PRESETS", "")
if os.path.isfile(presets_file):
    surface, _ = render("viridis", *ML, *SIZE, "--method", "reference", "--blend", "iso",
                        "--isovalue", ISO, "--colormap", "viridis (matplotlib)")
    c.check(surface is not None and (surface[:, :, 3] > 0.5).sum() > 50,
            "--colormap by ParaView preset name (case-insensitive)")
    code, _, stderr = run_cli("render", *ML, *SIZE, "--colormap", "viridis", expect=2)
    c.check("Viridis (matplotlib)" in stderr, "an unknown name suggests presets that contain it "
            "(%s)" % stderr.strip()[-120:])
else:
    print("skipped: colour maps by name (no exported ParaView presets at %r; ./hovr setup "
          "exports them)" % presets_file)

# Opacity: MinIP without --tf shows its minimum (ramp-down), MIP its maximum (ramp).
for method in ("minip-analytic", "mip-analytic"):
    projection, _ = render(method, *ML, *SIZE, "--method", method)
    drawn = (projection[:, :, 3] > 0.05).mean()
    c.check(drawn > 0.3, "%s without --tf is visible: %.0f%% of the pixels" % (
        method, 100 * drawn))
for spec in ("ramp-sideways", "0:0,1:1.5", "0:0;1:1", "flat:x"):
    code, _, stderr = run_cli("render", *ML, *SIZE, "--opacity", spec, expect=2)
    c.check("--opacity" in stderr, "--opacity %s is an error (%s)" % (spec, stderr.strip()))

# Shading: the lit analytic surface varies in colour and matches the lit reference.
lit, _ = render("lit", *ML, *SIZE, "--method", "iso-analytic", "--isovalue", ISO, "--shade")
flat, _ = render("flat", *ML, *SIZE, "--method", "iso-analytic", "--isovalue", ISO)
lit_ref, _ = render("lit-ref", *ML, *SIZE, "--method", "reference", "--blend", "iso",
                    "--isovalue", ISO, "--shade")
hits = (lit[:, :, 3] > 0.5) & (lit_ref[:, :, 3] > 0.5)
c.check(lit[hits][:, 0].std() > 0.02 and flat[hits][:, 0].std() < 1e-4,
        "--shade lights the isosurface (colour spread %.3f lit, %.2g unlit)"
        % (lit[hits][:, 0].std(), flat[hits][:, 0].std()))
difference = numpy.abs(lit[hits][:, :3] - lit_ref[hits][:, :3])
c.check(numpy.percentile(difference, 99) < 0.01,
        "the lit analytic surface matches the lit reference (99th percentile %.4f)"
        % numpy.percentile(difference, 99))

c.finish()
