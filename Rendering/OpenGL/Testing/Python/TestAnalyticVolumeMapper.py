"""vtkAnalyticVolumeMapper against the float64 reference (vtkVolumeReferenceIntegrator's
isosurface and projection modes), and its handling of bad input.

Accuracy (128 x 128): on Marschner-Lobb with an oblique and an exactly axis-aligned parallel
view (some rays along grid planes and edges) and on the thin-feature volume, the analytic
first hit agrees with the reference's hit/miss on at least 99.9% of the pixels and its depth
is within 1e-3 voxel on every pixel both hit apart from grazing ones (where the reference's own
hit moves by more than that when the isovalue moves by 1e-6 of the data range: at most 0.1% of
the pixels); rays come from the double-precision camera model, and a camera it does not
describe (a window centre) goes through VTK's matrices, still within 1e-3 voxel on 99.9% of
the hits. The analytic maximum and
minimum are within 1e-3 of the data range everywhere, also where the cubic degenerates (a
quadratic with its extremum inside cells, a linear profile). On the thin-feature volume VTK's
own isosurface at a quarter-voxel step misses surfaces the analytic method finds.

Bad input: isosurface blending without isovalues and volumes one voxel thick are errors with
nothing drawn; composite blending and cropping warn once and draw VTK's stock image; NaN
voxels leave no NaN in the image.
"""

import math

import numpy
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkCommand

import hovr
from hovr import bench as hb
from hovr import io as hio
from hovr import methods as hm
from hovrtesting import Checker, Messages, image_from_array, tf_path

c = Checker()
SIZE = (128, 128)
renderer = hm.Renderer()


def property_for(isovalues=(), tf="iso-opaque"):
    color, opacity, _ = hio.read_transfer_function(tf_path(tf))
    prop = hio.make_volume_property(color, opacity, 1.0)
    prop.ShadeOn()
    for k, value in enumerate(isovalues):
        prop.GetIsoSurfaceValues().SetValue(k, value)
    return prop


def scene_for(image, blend, isovalues=(), camera=None, tf="iso-opaque"):
    camera = camera or hio.default_camera(image.GetBounds())
    return hm.Scene(image, property_for(isovalues, tf), camera, SIZE, blend)


def measure(name, scene, method, step=1.0):
    reference = renderer.render("reference", scene, 1.0).image
    result = renderer.render(method, scene, step).image
    return hm.compare_blend(result, reference, scene), result


class Watched(hm.AnalyticMethod):
    """iso-analytic, keeping its mapper to read its settings after drawing."""

    def __init__(self):
        super().__init__("iso-analytic-watched", "", "iso", True)
        self.mapper = None

    def make_mapper(self):
        self.mapper = super().make_mapper()
        return self.mapper


def ray_frame_in_use(mapper):
    return "RayFrameInUse: 1" in str(mapper)


def check_iso(name, scene, model_rays=True):
    method = Watched()
    row, _ = measure(name, scene, method)
    pixels = SIZE[0] * SIZE[1]
    print("%-22s %s" % (name, hm.format_blend(row)))
    c.check(ray_frame_in_use(method.mapper) == model_rays, "%s: rays %s" % (
        name, "from the camera model" if model_rays else "through VTK's matrices"))
    c.check(row["hits_both"] > pixels // 20, "%s: the surface is seen" % name)
    c.check(row["hit_miss_disagreements"] <= 0.001 * pixels,
            "%s: hit/miss agrees on 99.9%% of the pixels (%d differ)"
            % (name, row["hit_miss_disagreements"]))
    c.check(row["grazing_pixels"] <= 0.001 * pixels,
            "%s: at most 0.1%% of the pixels are grazing (%d)" % (name, row["grazing_pixels"]))
    if model_rays:
        c.check(row["depth_outliers_not_grazing"] == 0,
                "%s: depth within 1e-3 voxel on every hit that is not grazing (%d outliers, "
                "max %.2e)" % (name, row["depth_outliers_not_grazing"],
                               row["depth_max_error_not_grazing"]))
    else:
        c.check(row["depth_outliers"] <= 0.001 * row["hits_both"],
                "%s: depth within 1e-3 voxel on 99.9%% of the hits (%d outliers)"
                % (name, row["depth_outliers"]))
    c.check(row["depth_p99_error_voxels"] < 1e-4, "%s: 99th percentile of the depth error "
            "below 1e-4 voxel (%.2e)" % (name, row["depth_p99_error_voxels"]))
    return row


def check_projection(name, scene, method):
    row, _ = measure(name, scene, method)
    print("%-22s %s" % (name, hm.format_blend(row)))
    c.check(row["hits_both"] > SIZE[0] * SIZE[1] // 10, "%s: the volume is seen" % name)
    c.check(row["hit_miss_disagreements"] == 0, "%s: the same pixels meet the volume" % name)
    c.check(row["extremum_max_error"] < 1e-3, "%s: extremum within 1e-3 of the data range "
            "(%.2e)" % (name, row["extremum_max_error"]))


ml = hb.load_volume({"input": "marschner-lobb:41"})
thin = hb.load_volume({"input": "thin-features:48"})
axis_ml = hio.camera_from_dict({"position": [-5.0, -0.0035, 0.0], "focal_point": [0.0, -0.0035, 0.0],
                                "view_up": [0, 0, 1], "parallel_projection": True,
                                "parallel_scale": 0.9})
check_iso("ml41 oblique", scene_for(ml, "iso", [0.5]))
check_iso("ml41 axis, 3 isovalues", scene_for(ml, "iso", [0.3, 0.5, 0.7], axis_ml))
check_iso("thin48 oblique", scene_for(thin, "iso", [0.5]))
parallel = hio.default_camera(ml.GetBounds())
parallel.SetParallelProjection(True)
parallel.SetParallelScale(0.9)
check_iso("ml41 oblique parallel", scene_for(ml, "iso", [0.5], parallel))
# A window centre 1e-7 (in normalised device coordinates) off the middle: the camera model
# does not describe it (rays through VTK's matrices) but the image is the same to 1e-5 pixel.
shifted = hio.default_camera(ml.GetBounds())
shifted.SetWindowCenter(1e-7, 0.0)
check_iso("ml41 window centre", scene_for(ml, "iso", [0.5], shifted), model_rays=False)
check_projection("ml41 mip", scene_for(ml, "mip", tf="marschner-lobb-spikes"), "mip-analytic")
check_projection("ml41 minip", scene_for(ml, "minip", tf="marschner-lobb-spikes"),
                 "minip-analytic")
check_projection("thin48 mip axis", scene_for(thin, "mip", camera=hio.camera_from_dict({
    "position": [23.5, 23.5, 100.0], "focal_point": [23.5, 23.5, 23.5], "view_up": [0, 1, 0],
    "parallel_projection": True, "parallel_scale": 22.0})), "mip-analytic")
# Degenerate cubics, on rays along the xy diagonal (through cell edges): x (2 - y) is a
# concave quadratic there (its maximum inside cells, the cubic's leading coefficient 0),
# 4 - x (2 - y) a convex one (its minimum inside cells), and x + y + z is linear along every
# ray (no critical point at all). Without the interior search both quadratics fail by 6%.
zz, yy, xx = numpy.mgrid[0:3, 0:3, 0:3].astype(numpy.float32)
diagonal = hio.camera_from_dict({"position": [-4.0, -4.0, 1.0], "focal_point": [1.0, 1.0, 1.0],
                                 "view_up": [0, 0, 1], "parallel_projection": True,
                                 "parallel_scale": 1.6})
for name, values, blend in (("quadratic mip", xx * (2 - yy), "mip"),
                            ("quadratic minip", 4 - xx * (2 - yy), "minip"),
                            ("linear mip", xx + yy + zz, "mip"),
                            ("linear minip", xx + yy + zz, "minip")):
    check_projection(name, scene_for(image_from_array(values), blend, camera=diagonal,
                                     tf="marschner-lobb-spikes"), blend + "-analytic")

# Thin features: the sampled isosurface misses films and threads thinner than its step.
thin_scene = scene_for(thin, "iso", [0.5])
stock, _ = measure("thin48 stock", thin_scene, "iso-stock", 0.25)
analytic, _ = measure("thin48 analytic", thin_scene, "iso-analytic")
print("thin48: reference hits missed by iso-stock@0.25: %d, by iso-analytic: %d" % (
    stock["missed_hits"], analytic["missed_hits"]))
c.check(stock["missed_hits"] > 20 and analytic["missed_hits"] * 10 < stock["missed_hits"],
        "thin features: iso-stock at 1/4 voxel misses surfaces the analytic method finds")


# Block skipping (BlockSize) jumps over blocks that cannot matter: the same images as
# reading every cell, for isosurfaces and projections, and a texture of the expected size.
# Corner packing reads the same values in 2 fetches instead of 8: the same images too, for
# float, 8-bit and 16-bit data (each stored in its own type).
class Blocked(hm.AnalyticMethod):
    def __init__(self, blend, size, packing=True, packing_limit=None):
        super().__init__("%s-blocks%d" % (blend, size), "", blend, True)
        self.size = size
        self.packing = packing
        self.packing_limit = packing_limit
        self.mapper = None

    def make_mapper(self):
        self.mapper = super().make_mapper()
        self.mapper.SetBlockSize(self.size)
        self.mapper.SetCornerPacking(self.packing)
        if self.packing_limit is not None:
            self.mapper.SetCornerPackingMemoryLimit(self.packing_limit)
        # The textures are released with the volume after the frame: read their size then.
        self.bytes = 0
        self.mapper.AddObserver(vtkCommand.VolumeMapperRenderEndEvent, self.on_end)
        return self.mapper

    def on_end(self, mapper, _event):
        self.bytes = mapper.GetCornerTextureMemorySize()


def as_type(image, kind, scale):
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData
    copy = vtkImageData()
    copy.CopyStructure(image)
    values = numpy.round(vtk_to_numpy(image.GetPointData().GetScalars()) * scale).astype(kind)
    array = numpy_to_vtk(values, deep=1)
    array.SetName("scalars")
    copy.GetPointData().SetScalars(array)
    return copy


thin8 = as_type(thin, numpy.uint8, 200)
ml16 = as_type(ml, numpy.uint16, 60000)
for label, volume, blend, isovalues in (("thin48", thin, "iso", [0.5]),
                                        ("thin48", thin, "mip", []),
                                        ("ml41", ml, "iso", [0.3, 0.7]),
                                        ("ml41", ml, "minip", []),
                                        ("thin48 uint8", thin8, "mip", []),
                                        ("ml41 uint16", ml16, "iso", [30000.5])):
    scene = scene_for(volume, blend, isovalues)
    dims = volume.GetDimensions()
    per_point = {"uint8": 4, "uint16": 8}.get(label.split()[-1], 16)
    expected = (dims[0] - 1) * (dims[1] - 1) * dims[2] * per_point
    # The last one's copy would be a byte over CornerPackingMemoryLimit: it reads VTK's texture.
    methods = [Blocked(blend, size) for size in (0, 3, 8)] + [Blocked(blend, 8, False),
                                                               Blocked(blend, 8, True, expected - 1)]
    images = [renderer.render(m, scene, 1.0).image for m in methods]
    arrays = [vtk_to_numpy(i.GetPointData().GetScalars()) for i in images]
    extra = [vtk_to_numpy(i.GetPointData().GetArray(hm.BLEND_ARRAYS[blend])) for i in images]
    # The projections may differ in the last bits: with blocks, the cells of the most
    # promising block are walked from that block's entry point (hovr_blockBound).
    low, high = volume.GetPointData().GetScalars().GetRange()
    same = all(numpy.array_equal(arrays[0], a) for a in arrays[1:]) and all(
        numpy.array_equal(numpy.isnan(extra[0]), numpy.isnan(e)) and
        numpy.nanmax(numpy.abs(extra[0] - e)) <= 1e-5 * (high - low) for e in extra[1:])
    c.check(same, "%s %s: block sizes 0, 3 and 8, with and without corner packing, give the "
            "same image and %s (to 1e-5 of the range)" % (label, blend, hm.BLEND_ARRAYS[blend]))
    c.check(methods[0].bytes == expected and methods[3].bytes == 0 and methods[4].bytes == 0,
            "%s: the packed corners take %d bytes per point (%d), none without packing or "
            "over CornerPackingMemoryLimit" % (label, per_point, methods[0].bytes))
mapper = hovr.vtkAnalyticVolumeMapper()
c.check(mapper.GetBlockSize() == 8 and mapper.GetBlockTextureMemorySize() == 0 and
        mapper.GetCornerPacking() and mapper.GetCornerTextureMemorySize() == 0 and
        mapper.GetCornerPackingMemoryLimit() == 256 * 2 ** 20 and
        mapper.GetMaximumTextureBytes() == 2 ** 30,
        "block size 8, corner packing up to 256 MiB and textures up to 1 GiB by default, no "
        "texture before the first frame")


# Bad input, through the mapper itself.


def draw(image, blend, isovalues=(), setup=None):
    """Draw with the analytic mapper: (RGBA numpy array, mapper messages, frames drawn with
    the analytic shader)."""
    from vtkmodules.vtkRenderingCore import vtkVolume
    # Not a Scene, which refuses bad volumes and isosurfaces without values: the mapper must
    # refuse them too.
    prop = property_for(isovalues)
    if blend == "iso" and not isovalues:
        # VTK's volume property starts with one isovalue, 0: remove it.
        prop.GetIsoSurfaceValues().SetNumberOfContours(0)
    renderer._ensure_window(SIZE)
    view = renderer._renderer
    view.RemoveAllViewProps()
    view.GetActiveCamera().DeepCopy(hio.default_camera(image.GetBounds()))
    mapper = hovr.vtkAnalyticVolumeMapper()
    mapper.SetBlendMode(hm.BLEND_MODES[blend])
    mapper.SetInputData(image)
    if setup:
        setup(mapper)
    messages = Messages(mapper)
    volume = hm.vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    view.AddVolume(volume)
    view.ResetCameraClippingRange(image.GetBounds())
    renderer._window.Render()
    renderer._window.Render()
    result = vtk_to_numpy(renderer._capture_image().GetPointData().GetScalars()).copy()
    view.RemoveAllViewProps()
    return result, messages, mapper.GetExtensionFrameCount()


image, messages, frames = draw(ml, "iso")
c.check(any("at least one finite isosurface value" in m for m in messages.errors)
        and image.max() == 0.0, "isosurface without isovalues: an error, nothing drawn")
flat = image_from_array(numpy.zeros((1, 8, 8), dtype=numpy.float32))
image, messages, frames = draw(flat, "mip")
c.check(any("at least 2 points along each axis" in m for m in messages.errors)
        and image.max() == 0.0, "one voxel thick volume: an error, nothing drawn")
image, messages, frames = draw(ml, "composite")
c.check(len(messages.warnings) == 1 and "isosurface, maximum and minimum" in messages.warnings[0]
        and frames == 0 and image[:, 3].max() > 0.0,
        "composite blending: one warning, drawn by VTK's stock shader")
image, messages, frames = draw(ml, "mip", setup=lambda m: (
    m.SetCropping(1), m.SetCroppingRegionPlanes(-1, 0.5, -1, 1, -1, 1)))
c.check(len(messages.warnings) == 1 and "cropping" in messages.warnings[0] and frames == 0,
        "cropping: one warning, drawn by VTK's stock shader")
# A volume the GPU cannot hold in one texture (over MaximumTextureBytes, or an axis beyond
# GL_MAX_3D_TEXTURE_SIZE) is drawn in bricks, with no message.
image, messages, frames = draw(ml, "mip")
split, messages, frames = draw(ml, "mip", setup=lambda m: m.SetMaximumTextureBytes(41 ** 3 * 4 - 1))
c.check(not messages.errors and not messages.warnings and frames > 0 and
        numpy.abs(split - image).max() < 1e-4 and image[:, 3].max() > 0.0,
        "a volume over MaximumTextureBytes: drawn in bricks, the image of one piece (%.2g)"
        % numpy.abs(split - image).max())
long_axis = image_from_array(numpy.tile(numpy.linspace(0.0, 1.0, 2100, dtype=numpy.float32),
                                        (3, 3, 1)))
image, messages, frames = draw(long_axis, "mip")
c.check(not messages.errors and frames > 0 and image[:, 3].max() > 0.0,
        "an axis beyond GL_MAX_3D_TEXTURE_SIZE: drawn in bricks, no error")
values = vtk_to_numpy(ml.GetPointData().GetScalars()).reshape(41, 41, 41).copy()
values[20, 20, 10:30] = numpy.nan
nan_volume = image_from_array(values, ml.GetSpacing(), ml.GetOrigin())
for blend, iso in (("iso", [0.5]), ("mip", [])):
    image, messages, frames = draw(nan_volume, blend, iso)
    c.check(numpy.isfinite(image).all() and frames > 0 and not messages.errors
            and image[:, 3].max() > 0.0,
            "NaN voxels (%s): drawn analytically, no NaN in the image" % blend)

renderer.close()
c.finish()
