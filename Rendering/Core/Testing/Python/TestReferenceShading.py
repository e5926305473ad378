"""The shaded reference integrator is right: it converges under refinement, and it agrees
with an independent fine-step integration that shares no code with hovr's C++.

The independent integrator computes each point's normal its own way: numpy central
differences of the voxel values (one-sided at the faces, not halved, as VTK's GPU ray caster
takes them), interpolated trilinearly along the ray and normalised; the lighting is VTK's
headlight written out (L = V = the reversed ray direction, two-sided), with the specular
lobe max(N.H, 0)^n and the cone max(1 + n (N.H - 1), 0); Gooch shading as the paper's
Eq. 11; and, for a normal array, the array's vectors interpolated trilinearly. Midpoint
compositing with a fixed step of 1/64 voxel. The volumes are the generated Marschner-Lobb
one and the shared headsq volume when ../shared/data is present.
"""

import math

import numpy
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

import hovr
from hovr import io as hio
from hovrtesting import (Checker, marschner_lobb_scene, pixel_rays, shared_volume, tf_path,
                         trilinear)

c = Checker()
SIZE = (24, 20)
FINE = 1.0 / 64.0
KA, KD, KS, POWER = 0.1, 0.6, 0.3, 20.0
COOL, WARM, GA, GB = numpy.array([0, 0, 0.4]), numpy.array([0.4, 0.4, 0]), 0.2, 0.6


def point_gradients(values, spacing):
    """Differences of the neighbours, one-sided at the faces, divided by the spacing."""
    g = numpy.zeros(values.shape + (3,))
    for axis, a in ((2, 0), (1, 1), (0, 2)):
        up = numpy.take(values, list(range(1, values.shape[axis])) + [values.shape[axis] - 1],
                        axis=axis)
        down = numpy.take(values, [0] + list(range(values.shape[axis] - 1)), axis=axis)
        g[..., a] = (up - down) / spacing[a]
    return g


def independent(image, prop, camera, model, normals=None):
    nx, ny, nz = image.GetDimensions()
    values = vtk_to_numpy(image.GetPointData().GetScalars()).astype(float).reshape(nz, ny, nx)
    spacing = numpy.array(image.GetSpacing())
    origin = numpy.array(image.GetOrigin())
    grads = (point_gradients(values, spacing) if normals is None
             else normals.reshape(nz, ny, nx, 3))
    smin, smax = values.min(), values.max()
    table = numpy.linspace(smin, smax, 65537)
    colour = numpy.array([prop.GetRGBTransferFunction().GetColor(s) for s in table])
    alpha = numpy.zeros(len(table))
    prop.GetScalarOpacity().GetTable(smin, smax, len(table), alpha)
    tau_table = -numpy.log1p(-numpy.clip(alpha, 0, 1 - 1e-9)) / prop.GetScalarOpacityUnitDistance()
    lo, hi = origin, origin + spacing * (numpy.array([nx, ny, nz]) - 1)
    origins, directions = pixel_rays(camera, *SIZE)
    out = numpy.zeros((len(origins), 4))
    h = FINE * spacing.min()
    for r in range(len(origins)):
        with numpy.errstate(divide="ignore", invalid="ignore"):
            ta, tb = (lo - origins[r]) / directions[r], (hi - origins[r]) / directions[r]
        t0 = max(numpy.max(numpy.minimum(ta, tb)), 0.0)
        t1 = numpy.min(numpy.maximum(ta, tb))
        if not t1 > t0:
            continue
        count = int(math.ceil((t1 - t0) / h))
        step = (t1 - t0) / count
        t = t0 + (numpy.arange(count) + 0.5) * step
        p = (origins[r] + t[:, None] * directions[r] - origin) / spacing
        v = trilinear(values, p)
        g = trilinear(grads, p)
        norm = numpy.linalg.norm(g, axis=1)
        n = numpy.where(norm[:, None] > 0, g / numpy.where(norm > 0, norm, 1)[:, None], 0.0)
        view = -directions[r]
        tau = numpy.interp(v, table, tau_table)
        c_ = numpy.stack([numpy.interp(v, table, colour[:, a]) for a in range(3)], axis=1)
        nl = n @ view  # the headlight: L = H = V
        if model == "gooch":
            q = (0.5 * (COOL + GA * KD * c_) * (1 + nl)[:, None] +
                 0.5 * (WARM + GB * KD * c_) * (1 - nl)[:, None])
        else:
            a = numpy.abs(nl)
            spec = a ** POWER if model == "lobe" else numpy.maximum(1 + POWER * (a - 1), 0)
            q = c_ * (KA + KD * a)[:, None] + KS * spec[:, None]
        piece = -numpy.expm1(-tau * step)
        trans = numpy.exp(-numpy.concatenate([[0.0], numpy.cumsum(tau * step)[:-1]]))
        w = trans * piece
        out[r, :3] = (w[:, None] * q).sum(axis=0)
        out[r, 3] = 1 - trans[-1] * (1 - piece[-1])
    return out


def reference(image, prop, camera, model, tolerance=1.0 / 64.0, normals=None):
    integrator = hovr.vtkVolumeReferenceIntegrator()
    integrator.SetInputData(image)
    integrator.SetVolumeProperty(prop)
    integrator.SetCamera(camera)
    integrator.SetImageSize(*SIZE)
    integrator.SetScalarTolerance(tolerance)
    shading = hovr.vtkVolumeShadingModel()
    shading.SetFromProperty(prop)
    shading.AddLight((0, 0, 1), (1, 1, 1), (1, 1, 1), True)
    shading.SetSpecularModel(shading.CONE if model == "cone" else shading.LOBE)
    shading.SetGooch(model == "gooch")
    integrator.SetShadingModel(shading)
    integrator.SetNormalArrayName(normals)
    integrator.Update()
    return vtk_to_numpy(integrator.GetOutput().GetPointData().GetArray("RGBA")).astype(float)


def rmse(a, b):
    return float(numpy.sqrt(numpy.mean((a - b) ** 2)))


def shade(prop):
    prop.ShadeOn()
    prop.SetAmbient(KA)
    prop.SetDiffuse(KD)
    prop.SetSpecular(KS)
    prop.SetSpecularPower(POWER)


def check_volume(name, image, prop, camera):
    shade(prop)
    for model in ("lobe", "cone", "gooch"):
        ours = reference(image, prop, camera, model)
        theirs = independent(image, prop, camera, model)
        error = rmse(ours, theirs)
        print("%-8s %-6s reference vs independent: RMSE %.2e, covered %d" % (
            name, model, error, int((theirs[:, 3] > 0.01).sum())))
        c.check((theirs[:, 3] > 0.01).sum() > len(theirs) // 8, "%s %s: the volume is seen"
                % (name, model))
        # The independent step of 1/64 voxel and the reference's pieces each leave errors
        # far below the 1e-3 that separates the methods compared with the reference.
        c.check(error < 1e-3, "%s %s: agrees with the independent integration (%.2e)" % (
            name, model, error))
    # Shading changes the image: an unshaded reference would not pass the checks above.
    prop.ShadeOff()
    unshaded = reference(image, prop, camera, "lobe")
    shade(prop)
    c.check(rmse(unshaded, reference(image, prop, camera, "lobe")) > 1e-2,
            "%s: the lobe reference is lit" % name)


scene = marschner_lobb_scene(SIZE)
check_volume("ml41", scene.image, scene.prop, scene.camera)

# Convergence under refinement: halving the tolerance shrinks the change.
shade(scene.prop)
images = [reference(scene.image, scene.prop, scene.camera, "lobe", 1.0 / t)
          for t in (4, 8, 16, 32)]
changes = [rmse(a, b) for a, b in zip(images, images[1:])]
print("refinement changes (tolerance 1/4 -> 1/32):", " ".join("%.2e" % x for x in changes))
for coarse, fine in zip(changes, changes[1:]):
    c.check(fine < 0.6 * coarse or fine < 1e-6, "the change shrinks under refinement "
            "(%.2e -> %.2e)" % (coarse, fine))

# A normal array instead of the gradient: its vectors interpolated and normalised.
nx, ny, nz = scene.image.GetDimensions()
values = vtk_to_numpy(scene.image.GetPointData().GetScalars()).astype(float).reshape(nz, ny, nx)
rng = numpy.random.default_rng(7)
field = point_gradients(values, numpy.array(scene.image.GetSpacing()))
field += 0.3 * numpy.linalg.norm(field, axis=-1, keepdims=True) * rng.normal(size=field.shape)
array = numpy_to_vtk(field.reshape(-1, 3).copy(), deep=True)
array.SetName("Normals")
scene.image.GetPointData().AddArray(array)
ours = reference(scene.image, scene.prop, scene.camera, "lobe", normals="Normals")
theirs = independent(scene.image, scene.prop, scene.camera, "lobe", normals=field.reshape(-1, 3))
error = rmse(ours, theirs)
print("normal array: reference vs independent RMSE %.2e" % error)
c.check(error < 1e-3, "a normal array: agrees with the independent integration")
c.check(rmse(ours, reference(scene.image, scene.prop, scene.camera, "lobe")) > 1e-3,
        "a normal array changes the image")

path = shared_volume("headsq_64x64x93_uint16le.raw")
if path is None:
    print("skipping headsq: headsq_64x64x93_uint16le.raw not found (shared test data absent)")
else:
    volume = hio.read_volume(path, (64, 64, 93), "uint16", (3.2, 3.2, 1.5))
    color, opacity, _ = hio.read_transfer_function(tf_path("ct-opaque"))
    prop = hio.make_volume_property(color, opacity, 1.5)
    check_volume("headsq", volume, prop, hio.default_camera(volume.GetBounds()))

c.finish()
