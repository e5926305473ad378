"""Adversarial inputs through the Python package (hovr.io, hovr.methods): every case ends in a
correct image or a HovrError with a message, within a time bound, and never in another
exception, a crash or an empty image that nothing explains.

- Volumes (every method of its blend mode): every numpy scalar type, some NaN, all NaN, Inf,
  +-1e300, a 1e20 fill value, constant data, arrays shorter and longer than the grid, no
  scalars, three components, a slab, one voxel, spacings of 1e-30 and 1e30, zero spacing and
  a NaN origin.
- Cameras: inside the volume, along an axis, view up along the view direction, at its focal
  point, a parallel scale of 0, NaN values.
- Images of 1x1 and 100000x100000; steps 0, -1, NaN, Inf and 1e-9; opacity unit distances 0,
  NaN and 1e-300; transfer functions with 0, 1 or duplicate points, NaN, strings, opacity
  above 1; raw files of the wrong size, dimensions 0, NaN spacing, a truncated .vti.

An image counts as correct when the reference integrator draws the same scene and the image is
within the method's tolerance of it (composite RMSE, projection extremum error, isosurface hit
agreement); an image with no opacity counts only when a warning explains it. The suite prints
a table of case, method and outcome.
"""

import math
import os
import tempfile
import time

import numpy
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPiecewiseFunction
from vtkmodules.vtkRenderingCore import vtkCamera, vtkColorTransferFunction

from hovr import io as hio
from hovr import methods as hm
from hovr.io import HovrError
from hovrtesting import Checker

c = Checker()
SIZE = (24, 20)
STEP = 0.25
# A case that takes longer than this is a failure (ctest's timeout catches a hang).
CASE_SECONDS = 60.0
# Tolerances against the reference integrator at STEP on a smooth 10^3 field: they catch a
# wrong image, not inaccuracy. hovr's methods are held to 0.03 (their clean-case errors are
# under 0.001); VTK's mappers to 0.15, as their error reaches 0.12 where opacity nears 1.
# The object-order caster gets 0.05: at opacity near 1, a ray that crosses a corner of the
# volume for less than a step meets no sample there and misses a pixel the reference makes
# opaque (two pixels of this image, RMSE 0.042).
COMPOSITE_RMSE = {"stock": 0.15, "fixedpoint": 0.15, "objectorder": 0.05,
                  "objectorder-point": 0.05}
DEFAULT_COMPOSITE_RMSE = 0.03
EXTREMUM_MEAN_ERROR = 0.02  # of the data range
ISO_DISAGREEMENTS = 0.05  # of the pixels, grazing ones aside
COMPOSITE = ["stock", "preint1", "preint2", "objectorder", "objectorder-point", "fixedpoint"]
PROJECTIONS = {"mip": ["mip-analytic", "mip-stock"], "minip": ["minip-analytic", "minip-stock"],
               "iso": ["iso-analytic", "iso-stock"]}
ROWS = []


def run(case, what, call):
    """Run ``call``; return (outcome, value, message) with outcome 'ok' or 'error' (a
    HovrError). Any other exception, or a case over the time bound, fails."""
    start = time.perf_counter()
    outcome, value, message = "ok", None, ""
    with hio._VTKOutputCaptured() as captured:  # what VTK prints: warnings with no observer
        try:
            value = call()
        except HovrError as error:
            outcome, message = "error", str(error)
        except Exception as error:  # noqa: BLE001 - any other exception is the failure checked
            outcome, message = "exception", "%s: %s" % (type(error).__name__, error)
    seconds = time.perf_counter() - start
    c.check(outcome != "exception", "%s / %s: raised %s" % (case, what, message))
    c.check(outcome != "error" or message.strip(), "%s / %s: an error without a message"
            % (case, what))
    c.check(seconds < CASE_SECONDS, "%s / %s: took %.1f s" % (case, what, seconds))
    return outcome, value, message, captured.text, seconds


def record(case, what, outcome, detail, seconds):
    ROWS.append((case, what, outcome, detail, seconds))


def expect_error(case, what, call):
    """A case that must be a HovrError."""
    outcome, _, message, _, seconds = run(case, what, call)
    c.check(outcome == "error", "%s / %s: no error (%s)" % (case, what, outcome))
    record(case, what, outcome, message.splitlines()[0][:90] if message else "", seconds)


# ---------------------------------------------------------------------------------------------
# Volumes
def field(n=10):
    """A smooth field over [0, 1] on an n^3 grid, indexed [z, y, x]."""
    g = numpy.linspace(0.0, 1.0, n)
    z, y, x = numpy.meshgrid(g, g, g, indexing="ij")
    return 0.5 + 0.25 * numpy.sin(5.0 * x + 1.0) * numpy.cos(4.0 * y - 0.5) + 0.2 * (z - 0.5)


def image_of(values, dims=None, spacing=1.0, origin=(0.0, 0.0, 0.0), components=1):
    image = vtkImageData()
    dims = dims or (values.shape[2], values.shape[1], values.shape[0])
    image.SetDimensions(*dims)
    image.SetSpacing(spacing, spacing, spacing)
    image.SetOrigin(origin)
    if values is not None:
        array = numpy_to_vtk(numpy.ascontiguousarray(values).reshape(-1, components), deep=1)
        array.SetName("scalars")
        image.GetPointData().SetScalars(array)
    return image


def transfer_function(low, high):
    """Colour and a mid-range opacity band over [low, high]."""
    color = vtkColorTransferFunction()
    color.AddRGBPoint(low, 0.1, 0.2, 0.9)
    color.AddRGBPoint(high, 1.0, 0.6, 0.1)
    opacity = vtkPiecewiseFunction()
    span = high - low
    for fraction, alpha in ((0.0, 0.0), (0.35, 0.0), (0.55, 0.6), (0.75, 0.1), (1.0, 0.0)):
        opacity.AddPoint(low + fraction * span, alpha)
    return color, opacity


def volume_cases():
    base = field()
    cases = []
    for name in ("int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64",
                 "float32", "float64"):
        dtype = numpy.dtype(name)
        if dtype.kind == "f":
            low, high = 0.0, 1.0
        else:
            info = numpy.iinfo(dtype)
            low, high = float(max(info.min, -1000)), float(min(info.max, 1000))
        values = (low + base * (high - low)).astype(dtype)
        cases.append((name, image_of(values), (low, high)))
    nan = base.astype(numpy.float32)
    # Fill values at a few points: each makes its 8 cells transparent.
    nan.ravel()[numpy.random.default_rng(5).choice(nan.size, 6, replace=False)] = numpy.nan
    cases.append(("some NaN", image_of(nan), (0.0, 1.0)))
    cases.append(("all NaN", image_of(numpy.full_like(nan, numpy.nan)), (0.0, 1.0)))
    inf = base.astype(numpy.float32)
    inf[4, 4, 4] = numpy.inf
    cases.append(("Inf", image_of(inf), (0.0, 1.0)))
    huge = base * 2e300 - 1e300
    cases.append(("+-1e300", image_of(huge), (-1e300, 1e300)))
    cases.append(("fill 1e20", image_of(numpy.full_like(base, 1e20)), (0.0, 1.0)))
    cases.append(("constant 0.55", image_of(numpy.full_like(base, 0.55, dtype=numpy.float32)),
                  (0.0, 1.0)))
    flat = base.astype(numpy.float32)
    cases.append(("short array", image_of(flat.ravel()[:100], dims=(10, 10, 10)), (0.0, 1.0)))
    cases.append(("long array", image_of(numpy.concatenate([flat.ravel()] * 2),
                                         dims=(10, 10, 10)), (0.0, 1.0)))
    cases.append(("no scalars", image_of(None, dims=(10, 10, 10)), (0.0, 1.0)))
    cases.append(("3 components", image_of(numpy.repeat(flat.ravel(), 3), dims=(10, 10, 10),
                                           components=3), (0.0, 1.0)))
    cases.append(("slab", image_of(flat[:1]), (0.0, 1.0)))
    cases.append(("one voxel", image_of(flat[:1, :1, :1]), (0.0, 1.0)))
    cases.append(("spacing 1e-30", image_of(flat, spacing=1e-30), (0.0, 1.0)))
    cases.append(("spacing 1e30", image_of(flat, spacing=1e30), (0.0, 1.0)))
    cases.append(("spacing 0", image_of(flat, spacing=0.0), (0.0, 1.0)))
    cases.append(("NaN origin", image_of(flat, origin=(numpy.nan, 0.0, 0.0)), (0.0, 1.0)))
    return cases


def camera_for_nothing():
    result = vtkCamera()
    result.SetParallelProjection(1)
    return result


def parallel_camera(bounds):
    """An oblique parallel view of ``bounds`` that fills the image (the object-order methods
    render parallel projections only)."""
    try:
        camera = hio.default_camera(bounds)
    except HovrError:  # degenerate bounds: any camera, the volume is refused
        return camera_for_nothing()
    camera.SetParallelProjection(1)
    if all(map(math.isfinite, bounds)):
        camera.SetParallelScale(0.6 * max(bounds[1] - bounds[0], bounds[3] - bounds[2],
                                          bounds[5] - bounds[4]))
    return camera


def alpha_sum(image):
    return float(vtk_to_numpy(image.GetPointData().GetArray("RGBA"))[:, 3].sum())


def judge(case, method, result, reference, warnings, scene):
    """The outcome of an image: correct against the reference, or empty with a warning."""
    image = result.image
    if scene.blend == "composite":
        if reference is None:
            c.check(False, "%s / %s: an image where the reference integrator refuses the scene"
                    % (case, method))
            return "image, reference refused"
        if alpha_sum(image) == 0.0:
            c.check(warnings.strip() or alpha_sum(reference.image) == 0.0,
                    "%s / %s: an empty image and no warning" % (case, method))
        error = hm.compare(image, reference.image)[0]["rmse"]
        bound = COMPOSITE_RMSE.get(method, DEFAULT_COMPOSITE_RMSE)
        c.check(error <= bound, "%s / %s: RMSE %.4f against the reference (at most %g)"
                % (case, method, error, bound))
        return "image, RMSE %.4f" % error
    if reference is None:
        c.check(False, "%s / %s: an image where the reference integrator refuses the scene"
                % (case, method))
        return "image, reference refused"
    row = hm.compare_blend(image, reference.image, scene)
    pixels = scene.size[0] * scene.size[1]
    if scene.blend == "iso":
        bad = row["disagreements_not_grazing"]
        c.check(bad <= ISO_DISAGREEMENTS * pixels,
                "%s / %s: %d of %d pixels disagree with the reference on a hit"
                % (case, method, bad, pixels))
        return "image, %d hits, %d disagree" % (row["hits_both"], bad)
    c.check(row["extremum_mean_error"] <= EXTREMUM_MEAN_ERROR,
            "%s / %s: extremum error %.4f of the range" % (case, method,
                                                           row["extremum_mean_error"]))
    c.check(row["hit_miss_disagreements"] <= ISO_DISAGREEMENTS * pixels,
            "%s / %s: %d pixels disagree with the reference on coverage"
            % (case, method, row["hit_miss_disagreements"]))
    return "image, extremum error %.4f" % row["extremum_mean_error"]


def render_all(renderer, case, scene, methods):
    """The reference first, then each method, judged against it."""
    outcome, reference, message, warnings, seconds = run(
        case, "reference", lambda: renderer.render("reference", scene, STEP))
    record(case, scene.blend + " reference", outcome,
           message.splitlines()[0][:90] if message else "", seconds)
    if outcome != "ok":
        reference = None
    elif scene.blend == "composite" and alpha_sum(reference.image) == 0.0:
        c.check(warnings.strip(), "%s / reference: an empty image and no warning" % case)
    for method in methods:
        outcome, result, message, warnings, seconds = run(
            case, method, lambda: renderer.render(method, scene, STEP))
        if outcome == "ok":
            detail = judge(case, method, result, reference, warnings, scene)
        else:
            detail = message.splitlines()[0][:90] if message else ""
            # A method may refuse what the reference renders only with a reason (the checks
            # above); refusing a volume the reference accepts is worth seeing in the table.
            if reference is not None:
                detail = "(reference drew it) " + detail
        record(case, method, outcome, detail, seconds)


def scene_for(image, low, high, camera, blend, unit=None):
    """The scene of a volume case. The opacity unit distance is the voxel spacing unless given,
    so that tiny and huge spacings change the geometry, not the opacity per voxel."""
    color, opacity = transfer_function(low, high)
    spacing = min(abs(s) for s in image.GetSpacing())
    if unit is None:
        unit = spacing if 0.0 < spacing < float("inf") else 1.0
    prop = hio.make_volume_property(color, opacity, unit)
    if blend == "iso":
        prop.GetIsoSurfaceValues().SetValue(0, low + 0.5 * (high - low))
    return hm.Scene(image, prop, camera, SIZE, blend)


def check_volumes(renderer):
    for case, image, (low, high) in volume_cases():
        checked = run(case, "check_volume", lambda: hio.check_volume(image))
        record(case, "check_volume", checked[0],
               (checked[2] or "; ".join(checked[1] or [])).splitlines()[0][:90]
               if (checked[2] or checked[1]) else "", checked[4])
        camera = parallel_camera(image.GetBounds())
        for blend, methods in [("composite", COMPOSITE)] + list(PROJECTIONS.items()):
            made = run(case, blend + " scene", lambda: scene_for(image, low, high, camera, blend))
            if made[0] != "ok":
                record(case, blend + " scene", made[0], made[2][:90], made[4])
                continue
            render_all(renderer, case, made[1], methods)


# ---------------------------------------------------------------------------------------------
# Cameras, image sizes, steps, properties
def clean_scene(camera=None, size=SIZE):
    image = image_of(field().astype(numpy.float32))
    color, opacity = transfer_function(0.0, 1.0)
    prop = hio.make_volume_property(color, opacity, 1.0)
    return hm.Scene(image, prop, camera or hio.default_camera(image.GetBounds()), size)


def camera(position, focal, up=(0.0, 0.0, 1.0), parallel=False, scale=1.0):
    result = vtkCamera()
    result.SetPosition(position)
    result.SetFocalPoint(focal)
    result.SetViewUp(up)
    result.SetParallelProjection(parallel)
    result.SetParallelScale(scale)
    return result


def check_cameras(renderer):
    centre = (4.5, 4.5, 4.5)
    cameras = [
        ("camera inside", camera((4.0, 4.2, 4.4), centre)),
        ("camera along +x", camera((40.0, 4.5, 4.5), centre)),
        # Rays along z with pixels 0.75 apart (all values exact in binary): those of every
        # fourth row and column lie in the grid planes 1, 4 and 7, so they run along cell faces
        # and edges. None lies in a face of the box [0, 9]: such a ray is a tie that the
        # reference (closed box) and the rasteriser (half-open pixels) break apart.
        ("camera along +z, parallel", camera((5.875, 5.875, 40.0), (5.875, 5.875, 4.5),
                                             (0.0, 1.0, 0.0), True, 7.5)),
        ("view up along view", camera((4.5, 4.5, 40.0), centre, (0.0, 0.0, 1.0))),
        ("parallel scale 0", camera((40.0, 30.0, 20.0), centre, parallel=True, scale=0.0)),
        ("NaN position", camera((numpy.nan, 30.0, 20.0), centre)),
    ]
    for case, cam in cameras:
        made = run(case, "Scene", lambda: clean_scene(cam))
        if made[0] != "ok":
            record(case, "Scene", made[0], made[2][:90], made[4])
            continue
        scene = made[1]
        render_all(renderer, case, scene,
                   ["stock", "preint1", "preint2"]
                   + (["objectorder"] if cam.GetParallelProjection() else []))


def check_settings(renderer):
    scene = clean_scene()
    for step in (0.0, -1.0, float("nan"), float("inf"), 1e-9):
        expect_error("step %g" % step, "preint1",
                     lambda: renderer.render("preint1", scene, step))
        expect_error("step %g" % step, "reference step",
                     lambda: renderer.render("objectorder", scene, step))
    for size in ((0, 5), (-3, 4)):
        expect_error("size %dx%d" % size, "Scene", lambda: clean_scene(size=size))
    image = image_of(field().astype(numpy.float32))
    for unit in (1e-3, 1e-6):
        # Opacity near 1 within a step: the first non-transparent sample decides the colour.
        near_opaque = scene_for(image, 0.0, 1.0, parallel_camera(image.GetBounds()),
                                "composite", unit)
        render_all(renderer, "unit distance %g" % unit, near_opaque, COMPOSITE)
    tiny = clean_scene(size=(1, 1))
    render_all(renderer, "image 1x1", tiny, ["stock", "preint1", "preint2"])
    huge = clean_scene(size=(100000, 100000))
    for method in ("preint1", "reference"):
        expect_error("image 100000x100000", method, lambda: renderer.render(method, huge, 1.0))
    # The renderer still works after a refused size.
    render_all(renderer, "after 100000x100000", clean_scene(), ["preint1"])
    for distance in (0.0, float("nan"), -1.0, float("inf")):
        expect_error("unit distance %g" % distance, "make_volume_property",
                     lambda: hio.make_volume_property(vtkColorTransferFunction(),
                                                      vtkPiecewiseFunction(), distance))
    no_iso = hio.make_volume_property(scene.prop.GetRGBTransferFunction(),
                                      scene.prop.GetScalarOpacity())
    no_iso.GetIsoSurfaceValues().SetNumberOfContours(0)
    expect_error("blend iso, no isovalue", "Scene",
                 lambda: hm.Scene(scene.image, no_iso, scene.camera, SIZE, "iso"))
    expect_error("blend 'volume'", "Scene",
                 lambda: hm.Scene(scene.image, scene.prop, scene.camera, SIZE, "volume"))
    expect_error("method 'nope'", "get_method", lambda: hm.get_method("nope"))
    expect_error("threads 0", "get_method", lambda: hm.get_method("preint1", 0))
    expect_error("iso method, composite scene", "render",
                 lambda: renderer.render("iso-analytic", scene, 1.0))


def check_transfer_functions(renderer):
    rgb = [0.0, 0.1, 0.2, 0.9, 1.0, 1.0, 0.6, 0.1]
    bad = [
        ("no opacity points", {"RGBPoints": rgb, "Points": []}),
        ("opacity 1.5", {"RGBPoints": rgb, "Points": [0.0, 0.0, 0.5, 0.0, 1.0, 1.5, 0.5, 0.0]}),
        ("NaN opacity point", {"RGBPoints": rgb, "Points": [0.0, float("nan"), 0.5, 0.0]}),
        ("string point", {"RGBPoints": rgb, "Points": [0.0, "a", 0.5, 0.0]}),
        ("ragged points", {"RGBPoints": rgb, "Points": [0.0, 0.5, 0.5]}),
        ("no colour", {"Points": [0.0, 0.5, 0.5, 0.0]}),
        ("not a preset", [1, 2, 3]),
    ]
    for case, document in bad:
        expect_error(case, "transfer_function_from_preset",
                     lambda: hio.transfer_function_from_preset(document, case))
    image = image_of(field().astype(numpy.float32))
    camera_ = parallel_camera(image.GetBounds())
    good = [
        ("one opacity point", [0.6, 0.3, 0.5, 0.0]),
        ("duplicate opacity points", [0.0, 0.0, 0.5, 0.0, 0.6, 0.0, 0.5, 0.0, 0.6, 0.8, 0.5,
                                      0.0, 1.0, 0.0, 0.5, 0.0]),
        ("transparent everywhere", [0.0, 0.0, 0.5, 0.0, 1.0, 0.0, 0.5, 0.0]),
    ]
    for case, points in good:
        made = run(case, "preset", lambda: hio.transfer_function_from_preset(
            {"RGBPoints": rgb, "Points": points}, case))
        c.check(made[0] == "ok", "%s: the preset is refused (%s)" % (case, made[2]))
        if made[0] != "ok":
            continue
        color, opacity, _ = made[1]
        scene = hm.Scene(image, hio.make_volume_property(color, opacity, 1.0), camera_, SIZE)
        render_all(renderer, case, scene, COMPOSITE)
    expect_error("empty functions", "Scene", lambda: hm.Scene(
        image, hio.make_volume_property(vtkColorTransferFunction(), vtkPiecewiseFunction(), 1.0),
        camera_, SIZE))


def check_files(folder):
    raw = os.path.join(folder, "volume.raw")
    field().astype(numpy.uint8).tofile(raw)
    expect_error("raw of the wrong size", "read_volume",
                 lambda: hio.read_volume(raw, dims=(10, 10, 9), scalar_type="uint8"))
    expect_error("raw dims 0", "read_volume",
                 lambda: hio.read_volume(raw, dims=(0, 10, 100), scalar_type="uint8"))
    expect_error("raw NaN spacing", "read_volume",
                 lambda: hio.read_volume(raw, dims=(10, 10, 10), scalar_type="uint8",
                                         spacing=(1.0, float("nan"), 1.0)))
    expect_error("raw unknown type", "read_volume",
                 lambda: hio.read_volume(raw, dims=(10, 10, 10), scalar_type="complex64"))
    expect_error("raw negative header", "read_volume",
                 lambda: hio.read_volume(raw, dims=(10, 10, 10), scalar_type="uint8",
                                         header_bytes=-1))
    vti = os.path.join(folder, "volume.vti")
    hio.write_vti(image_of(field().astype(numpy.float32)), vti)
    with open(vti, "rb") as stream:
        data = stream.read()
    truncated = os.path.join(folder, "truncated.vti")
    with open(truncated, "wb") as stream:
        stream.write(data[:len(data) // 2])
    expect_error("truncated .vti", "read_volume", lambda: hio.read_volume(truncated))
    expect_error("missing file", "read_volume",
                 lambda: hio.read_volume(os.path.join(folder, "none.vti")))
    garbage = os.path.join(folder, "garbage.mhd")
    with open(garbage, "w") as stream:
        stream.write("NDims = 3\nDimSize = 10 10\nElementDataFile = nowhere.raw\n")
    expect_error("broken .mhd", "read_volume", lambda: hio.read_volume(garbage))
    for case, values in (("camera NaN", {"position": [float("nan"), 0, 0]}),
                         ("camera strings", {"position": ["a", 0, 0]}),
                         ("camera unknown key", {"zoom": 2})):
        expect_error(case, "camera_from_dict", lambda: hio.camera_from_dict(values))


def main():
    renderer = hm.Renderer()
    try:
        check_volumes(renderer)
        check_cameras(renderer)
        check_settings(renderer)
        check_transfer_functions(renderer)
        with tempfile.TemporaryDirectory() as folder:
            check_files(folder)
    finally:
        renderer.close()
    print("%-28s %-30s %-9s %6s  %s" % ("case", "what", "outcome", "s", "detail"))
    for case, what, outcome, detail, seconds in ROWS:
        print("%-28s %-30s %-9s %6.2f  %s" % (case, what, outcome, seconds, detail))
    print("%d cases" % len(ROWS))
    c.finish()


main()
