"""Shaded first-order pre-integration draws what the shaded reference integrates.

- VTK's stock shaded GPU ray caster converges to the reference with the specular lobe as its
  step shrinks: the reference's lighting is VTK's.
- The three gradient interpolations of vtkPreIntegrationVolumeMapper (constant, linear,
  non-linear) converge to the reference with the cone they use, and so do the matched cone,
  Gooch shading, a normal array, and several directional lights.
- The moment tables are built once per transfer function, unit distance and step: camera and
  light changes reuse them; a transfer-function edit or an interpolation that needs other
  layers rebuilds them.
- Extremes: a one-cell-thick volume, opacity saturating inside one segment, steps from 1/1000
  to 8 voxels, shininess 1 and the property's largest, flat data.
"""

import numpy
from vtkmodules.util.numpy_support import numpy_to_vtk

from vtkmodules.vtkRenderingCore import vtkVolume

from hovr import hovrRenderingOpenGL as gl
from hovr import io as hio
from hovr import methods as hm
from hovrtesting import Checker, image_from_array, marschner_lobb_scene, offscreen_window

c = Checker()
SIZE = (96, 96)


def shade(prop, ka=0.1, kd=0.6, ks=0.3, power=20.0):
    prop.ShadeOn()
    prop.SetAmbient(ka)
    prop.SetDiffuse(kd)
    prop.SetSpecular(ks)
    prop.SetSpecularPower(power)


def error(renderer, method, scene, step, reference):
    return hm.compare(renderer.render(method, scene, step).image, reference)[0]["rmse"]


renderer = hm.Renderer()
scene = marschner_lobb_scene(SIZE)
shade(scene.prop)
lobe = renderer.render("reference", scene, 1.0).image
cone = renderer.render("reference-cone", scene, 1.0).image
c.check(hm.compare(lobe, cone)[0]["rmse"] > 1e-3, "the lobe and the cone differ")

# The stock mapper's lighting converges to the lobe reference.
stock = [error(renderer, "stock", scene, step, lobe) for step in (0.25, 0.125, 0.0625)]
print("stock vs lobe reference at 1/4, 1/8, 1/16 voxel:", " ".join("%.5f" % e for e in stock))
c.check(stock[0] > stock[1] > stock[2], "stock converges to the lobe reference")
# Its error shrinks about linearly with the step; what remains at 1/16 voxel is far below
# the lobe-cone difference that a wrong lighting model would leave.
c.check(stock[2] < 0.004, "stock at 1/16 voxel is within 0.004 of the lobe reference")

# Every interpolation converges to the cone reference.
for name in ("preint1-constant", "preint1-linear", "preint1-nonlinear"):
    errors = [error(renderer, name, scene, step, cone) for step in (1.0, 0.5, 0.25)]
    print("%-18s vs cone reference at 1, 1/2, 1/4 voxel: %s" % (
        name, " ".join("%.5f" % e for e in errors)))
    c.check(errors[0] > errors[1] > errors[2], "%s converges to the cone reference" % name)
    c.check(errors[2] < 0.02, "%s at 1/4 voxel is within 0.02 of the cone reference" % name)

# The matched cone (slope (n + 1) / 2) keeps the lobe's light: its reference lies nearer the
# lobe's than the paper's cone does, and the mapper follows it.
scene.shading["cone"] = "matched"
matched = renderer.render("reference-cone", scene, 1.0).image
err = error(renderer, "preint1-nonlinear", scene, 0.25, matched)
near, far = hm.compare(matched, lobe)[0]["rmse"], hm.compare(cone, lobe)[0]["rmse"]
print("matched cone: mapper vs its reference %.5f; reference vs lobe %.5f (paper's cone %.5f)"
      % (err, near, far))
c.check(err < 0.02, "matched cone: the mapper follows its reference")
c.check(near < far, "the matched cone is nearer the lobe than the paper's")
scene.shading["cone"] = "paper"

# Gooch shading against the Gooch reference.
scene.shading["gooch"] = True
gooch = renderer.render("reference", scene, 1.0).image
errors = [error(renderer, "preint1-nonlinear", scene, step, gooch) for step in (1.0, 0.25)]
print("Gooch vs Gooch reference at 1, 1/4 voxel: %.5f %.5f" % tuple(errors))
c.check(errors[1] < errors[0] and errors[1] < 0.01, "Gooch converges to its reference")
c.check(hm.compare(gooch, cone)[0]["rmse"] > 0.02, "Gooch differs from Blinn-Phong")
scene.shading["gooch"] = False

# A normal array (noisy gradients) instead of the gradient: mapper and reference follow it.
image = scene.image
points = image.GetNumberOfPoints()
rng = numpy.random.default_rng(11)
field = rng.normal(size=(points, 3))
array = numpy_to_vtk(field, deep=True)
array.SetName("RandomNormals")
image.GetPointData().AddArray(array)
scene.shading["normals"] = "RandomNormals"
random_cone = renderer.render("reference-cone", scene, 1.0).image
result = renderer.render("preint1-nonlinear", scene, 0.25)
print("normal array: RMSE %.5f" % hm.compare(result.image, random_cone)[0]["rmse"])
c.check(hm.compare(result.image, random_cone)[0]["rmse"] < 0.02,
        "a normal array: the mapper follows the reference")
c.check(hm.compare(random_cone, cone)[0]["rmse"] > 0.01, "a normal array changes the image")
scene.shading["normals"] = None

# Several directional lights: a headlight and a dimmer coloured scene light.
scene.shading["lights"] = [((0, 0, 1), (1, 1, 1), (1, 1, 1), True),
                           ((1, 1, 0.3), (0.5, 0.3, 0.2), (0.4, 0.4, 0.4), False)]
two = renderer.render("reference-cone", scene, 1.0).image
err = error(renderer, "preint1-nonlinear", scene, 0.25, two)
print("two lights: RMSE %.5f" % err)
c.check(err < 0.02, "two lights: the mapper sums them as the reference")
c.check(hm.compare(two, cone)[0]["rmse"] > 0.005, "the second light changes the image")
scene.shading["lights"] = None


# Tables are rebuilt only when what they integrate changes: one mapper in a window of its own.
window, view = offscreen_window((48, 48))
mapper = gl.vtkPreIntegrationVolumeMapper()
mapper.SetInputData(scene.image)
mapper.SetSampleDistance(scene.step_length(1.0))
volume = vtkVolume()
volume.SetMapper(mapper)
volume.SetProperty(scene.prop)
view.AddVolume(volume)
view.GetActiveCamera().DeepCopy(scene.camera)
window.Render()
table = mapper.GetActiveTable()
builds = table.GetBuildCount()
c.check(mapper.GetLastFrameShaded(), "the frame was shaded")
c.check(table.GetNumberOfLayers() == 4, "non-linear Blinn-Phong reads 4 moment layers")
view.GetActiveCamera().Azimuth(30)
window.Render()
c.check(table.GetBuildCount() == builds, "a camera change reuses the table")
view.GetLights().GetItemAsObject(0).SetIntensity(0.5)
window.Render()
c.check(table.GetBuildCount() == builds, "a light change reuses the table")
scene.prop.GetScalarOpacity().AddPoint(0.5, 0.3)
window.Render()
c.check(table.GetBuildCount() == builds + 1, "a transfer-function edit rebuilds the table once")
mapper.SetGradientInterpolation(1)
window.Render()
c.check(table.GetNumberOfLayers() == 2, "linear interpolation reads 2 moment layers")
c.check(table.GetBuildCount() == builds + 2, "fewer layers: one rebuild")
window.Render()
c.check(table.GetBuildCount() == builds + 2, "an unchanged frame reuses the table")
print("table builds: %d after camera, light, transfer-function and interpolation changes"
      % (table.GetBuildCount() - builds))
scene.prop.GetScalarOpacity().RemovePoint(0.5)
view.RemoveAllViewProps()
window.Finalize()
del window, view, mapper, volume


def finite_and_seen(image, what, least=1):
    values = hm.compare(image, image)[0]  # RMSE 0: the comparison itself must not fail
    pixels = numpy.asarray(
        [image.GetPointData().GetArray("RGBA").GetTuple4(i)
         for i in range(image.GetNumberOfPoints())])
    c.check(numpy.isfinite(pixels).all() and values["rmse"] == 0.0, "%s: finite" % what)
    c.check((pixels[:, 3] > 0.01).sum() >= least, "%s: drawn" % what)
    return pixels


# Extremes.
for step in (1.0 / 64.0, 8.0):
    result = renderer.render("preint1-nonlinear", scene, step)
    finite_and_seen(result.image, "step %g voxel" % step, 100)
c.check(error(renderer, "preint1-nonlinear", scene, 8.0, cone) < 0.2,
        "step 8 voxels: still an image of the volume")
# A step of 1/1000 voxel, on a small volume (12 voxels across: 12000 samples per ray).
small = marschner_lobb_scene((24, 24), points=9)
shade(small.prop)
small_cone = renderer.render("reference-cone", small, 1.0).image
err = error(renderer, "preint1-nonlinear", small, 1e-3, small_cone)
print("step 1/1000 voxel: RMSE %.5f" % err)
c.check(err < 0.01, "step 1/1000 voxel: close to the reference")
for power in (1.0, 128.0):
    scene.prop.SetSpecularPower(power)
    ref = renderer.render("reference-cone", scene, 1.0).image
    err = error(renderer, "preint1-nonlinear", scene, 0.25, ref)
    print("shininess %g: RMSE %.5f" % (power, err))
    c.check(err < 0.02, "shininess %g: close to the reference" % power)
scene.prop.SetSpecularPower(20.0)

# Opacity saturating inside one segment (a unit distance of 1e-3): shading adds no error to
# what the unshaded table makes of it, and the result stays well ahead of stock's.
scene.prop.SetScalarOpacityUnitDistance(1e-3)
ref = renderer.render("reference-cone", scene, 1.0).image
err = error(renderer, "preint1-nonlinear", scene, 1.0, ref)
stock_err = error(renderer, "stock", scene, 1.0, ref)
scene.prop.ShadeOff()
unshaded = error(renderer, "preint1", scene, 1.0, renderer.render("reference", scene, 1.0).image)
shade(scene.prop)
print("opacity saturating within a segment: RMSE %.5f (unshaded %.5f, stock %.5f)" % (
    err, unshaded, stock_err))
c.check(err < 1.25 * unshaded, "saturating opacity: shading adds little to the table's error")
c.check(err < 0.75 * stock_err, "saturating opacity: ahead of stock")
scene.prop.SetScalarOpacityUnitDistance(0.05)

# A one-cell-thick volume (two points: the thinnest a trilinear field has) and flat data:
# one-sided or no gradients, still drawn as the reference draws them. A 1-point-thick volume
# has no cells to shade: an error, as unshaded.
ramp = numpy.linspace(0.0, 1.0, 32)
slab = image_from_array(numpy.tile(ramp, (2, 32, 1)).astype(numpy.float32))
try:
    hm.Scene(image_from_array(numpy.tile(ramp, (1, 32, 1)).astype(numpy.float32)), scene.prop,
             scene.camera, (8, 8))
    c.check(False, "a 1-point-thick volume is refused")
except hio.HovrError as refusal:
    print("1-point-thick volume: %s" % refusal)
flat = image_from_array(numpy.full((16, 16, 16), 0.5, numpy.float32))
color, opacity, _ = hio.transfer_function_from_preset({
    "RGBPoints": [0, 0.2, 0.4, 1, 1, 1, 0.6, 0.2], "Points": [0, 0.2, 0.5, 0, 1, 0.9, 0.5, 0]})
for name, volume in (("one cell thick", slab), ("flat", flat)):
    prop = hio.make_volume_property(color, opacity, 0.1)
    shade(prop)
    thin = hm.Scene(volume, prop, hio.default_camera(volume.GetBounds()), (48, 48))
    ref = renderer.render("reference-cone", thin, 1.0).image
    for method in ("preint1-constant", "preint1-linear", "preint1-nonlinear"):
        err = error(renderer, method, thin, 0.5, ref)
        print("%s, %s: RMSE %.5f" % (name, method, err))
        c.check(err < 0.02, "%s, %s: close to the reference" % (name, method))

renderer.close()
c.finish()
