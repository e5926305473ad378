"""The reference integrator agrees with an independent fine-step integration (RMSE < 1e-3).

The independent integrator below shares no code with hovr's C++: rays from the camera
formulas of docs/cli.md, its own box clipping and trilinear interpolation in numpy, the
transfer functions tabulated densely by VTK itself (vtkPiecewiseFunction::GetTable), and
midpoint compositing with a fixed step of 1/128 of a voxel. It runs on the generated
Marschner-Lobb volume always and on the shared volumes (neghip, fuel, bucky, headsq) when
../shared/data is present. On Marschner-Lobb it also shows that the independent integration
converges to the reference: halving its step divides the difference by about 4.

The analytic blend modes are checked the same way: the first isosurface crossing found by
dense sampling (then bisected on the same trilinear interpolation) and the densely sampled
maximum and minimum against the reference's Depth, MaxScalar and MinScalar.
"""

import math
import os

import numpy
from vtkmodules.util.numpy_support import vtk_to_numpy

import hovr
from hovr import io as hio
from hovrtesting import Checker, pixel_rays, shared_volume, tf_path, trilinear

c = Checker()
SIZE = (28, 24)
FINE = 1.0 / 128.0  # independent step, in voxels


def clip_rays(image, camera, width, height):
    """Pixel rays and their parameter intervals inside the volume's box."""
    nx, ny, nz = image.GetDimensions()
    spacing = numpy.array(image.GetSpacing())
    origin = numpy.array(image.GetOrigin())
    lo, hi = origin, origin + spacing * (numpy.array([nx, ny, nz]) - 1)
    origins, directions = pixel_rays(camera, width, height)
    with numpy.errstate(divide="ignore", invalid="ignore"):
        ta = (lo - origins) / directions
        tb = (hi - origins) / directions
    t0 = numpy.nanmax(numpy.where(numpy.isfinite(ta), numpy.minimum(ta, tb), -numpy.inf), axis=1)
    t1 = numpy.nanmin(numpy.where(numpy.isfinite(ta), numpy.maximum(ta, tb), numpy.inf), axis=1)
    return origins, directions, numpy.maximum(t0, 0.0), t1


def independent_analytic(image, iso, camera, width, height, fine=FINE):
    """First crossing of iso (world depth, NaN on a miss) and the maximum and minimum along
    each ray, by dense sampling; crossings are bisected between the bracketing samples."""
    nx, ny, nz = image.GetDimensions()
    values = vtk_to_numpy(image.GetPointData().GetScalars()).astype(numpy.float64)
    values = values.reshape(nz, ny, nx)
    spacing = numpy.array(image.GetSpacing())
    origin = numpy.array(image.GetOrigin())
    origins, directions, t0, t1 = clip_rays(image, camera, width, height)
    h = fine * spacing.min()
    depth = numpy.full(len(origins), numpy.nan)
    vmax = numpy.full(len(origins), numpy.nan)
    vmin = numpy.full(len(origins), numpy.nan)

    def at(r, t):
        p = (origins[r] + numpy.atleast_1d(t)[:, None] * directions[r] - origin) / spacing
        return trilinear(values, p)

    for r in numpy.nonzero(t1 > t0)[0]:
        count = int(math.ceil((t1[r] - t0[r]) / h))
        t = t0[r] + numpy.arange(count + 1) * (t1[r] - t0[r]) / count
        v = at(r, t)
        vmax[r], vmin[r] = v.max(), v.min()
        g = v - iso
        hit = numpy.nonzero((g == 0) | (numpy.sign(g) != numpy.sign(g[0])))[0]
        if len(hit):
            n = hit[0]
            if g[n] == 0 or n == 0:
                depth[r] = t[n]
                continue
            a, b = t[n - 1], t[n]
            for _ in range(60):
                m = 0.5 * (a + b)
                if numpy.sign(at(r, m)[0] - iso) == numpy.sign(g[n - 1]):
                    a = m
                else:
                    b = m
            depth[r] = 0.5 * (a + b)
    return depth, vmax, vmin


def independent_image(image, prop, camera, width, height, fine=FINE):
    nx, ny, nz = image.GetDimensions()
    values = vtk_to_numpy(image.GetPointData().GetScalars()).astype(numpy.float64)
    values = values.reshape(nz, ny, nx)
    spacing = numpy.array(image.GetSpacing())
    origin = numpy.array(image.GetOrigin())
    lo, hi = origin, origin + spacing * (numpy.array([nx, ny, nz]) - 1)
    smin, smax = float(numpy.nanmin(values)), float(numpy.nanmax(values))
    table = numpy.linspace(smin, smax, 65537)
    color = numpy.array([prop.GetRGBTransferFunction().GetColor(s) for s in table])
    alpha = numpy.zeros(len(table))
    prop.GetScalarOpacity().GetTable(smin, smax, len(table), alpha)
    alpha = numpy.clip(alpha, 0.0, 1.0 - 1e-9)
    tau_table = -numpy.log1p(-alpha) / prop.GetScalarOpacityUnitDistance()

    origins, directions, t0, t1 = clip_rays(image, camera, width, height)
    h = fine * spacing.min()
    result = numpy.zeros((len(origins), 4))
    for r in numpy.nonzero(t1 > t0)[0]:
        count = int(math.ceil((t1[r] - t0[r]) / h))
        step = (t1[r] - t0[r]) / count
        t = t0[r] + (numpy.arange(count) + 0.5) * step
        p = (origins[r] + t[:, None] * directions[r] - origin) / spacing
        v = trilinear(values, p)
        tau = numpy.interp(v, table, tau_table)
        rgb = numpy.stack([numpy.interp(v, table, color[:, a]) for a in range(3)], axis=1)
        piece_alpha = -numpy.expm1(-tau * step)
        transmittance = numpy.exp(-numpy.concatenate([[0.0], numpy.cumsum(tau * step)[:-1]]))
        weights = transmittance * piece_alpha
        result[r, :3] = (weights[:, None] * rgb).sum(axis=0)
        result[r, 3] = 1.0 - transmittance[-1] * (1.0 - piece_alpha[-1])
    return result


def reference_image(image, prop, camera, width, height, blend=0, array="RGBA"):
    integrator = hovr.vtkVolumeReferenceIntegrator()
    integrator.SetInputData(image)
    integrator.SetVolumeProperty(prop)
    integrator.SetCamera(camera)
    integrator.SetImageSize(width, height)
    integrator.SetBlendMode(blend)
    integrator.Update()
    return vtk_to_numpy(integrator.GetOutput().GetPointData().GetArray(array)).astype(float)


def compare_analytic(name, image, prop, camera, label, iso):
    """Depth of the first crossing and the extrema, reference against dense sampling."""
    prop.GetIsoSurfaceValues().SetValue(0, iso)
    depth = reference_image(image, prop, camera, *SIZE, blend=5, array="Depth")
    vmax = reference_image(image, prop, camera, *SIZE, blend=1, array="MaxScalar")
    vmin = reference_image(image, prop, camera, *SIZE, blend=2, array="MinScalar")
    d2, max2, min2 = independent_analytic(image, iso, camera, *SIZE)
    h = FINE * min(image.GetSpacing())
    both = numpy.isfinite(depth) & numpy.isfinite(d2)
    disagree = int((numpy.isfinite(depth) != numpy.isfinite(d2)).sum())
    derr = numpy.abs(depth[both] - d2[both]).max() if both.any() else 0.0
    srange = float(numpy.nanmax(max2) - numpy.nanmin(min2))
    merr = numpy.nanmax(numpy.abs(vmax - max2)) / srange
    nerr = numpy.nanmax(numpy.abs(vmin - min2)) / srange
    print("%-8s %-11s iso %g: %d hits, %d hit/miss disagreements, depth difference %.1e "
          "(fine step %.1e); max %.1e, min %.1e of the range" % (
              name, label, iso, int(both.sum()), disagree, derr, h, merr, nerr))
    c.check(both.sum() > 20, "%s %s: the isosurface is seen" % (name, label))
    # A dense scan can step over a crossing pair thinner than its step: allow one such ray.
    c.check(disagree <= 1, "%s %s: hit/miss agrees (%d differ)" % (name, label, disagree))
    # Where both find the same crossing they agree to the bisection, here to the float32 of
    # the Depth array; a different crossing (one the scan stepped over) would differ by more.
    same = numpy.abs(depth[both] - d2[both]) <= 4e-7 * numpy.abs(d2[both]) + 1e-12
    c.check(same.mean() >= 0.99, "%s %s: depths agree to float precision on %.1f%% of the hits"
            % (name, label, 100 * same.mean()))
    # Sampling can only underestimate the maximum (overestimate the minimum), by O(h^2)
    # times the profile's curvature, which uint8 cells make large.
    scale = numpy.nanmax(numpy.abs(max2)) + numpy.nanmax(numpy.abs(min2))
    c.check(numpy.nanmax(max2 - vmax) <= 1e-7 * scale and merr < 2e-3,
            "%s %s: exact maximum >= sampled maximum, within 2e-3" % (name, label))
    c.check(numpy.nanmax(vmin - min2) <= 1e-7 * scale and nerr < 2e-3,
            "%s %s: exact minimum <= sampled minimum, within 2e-3" % (name, label))


def compare(name, image, tf, unit, convergence=False, iso=None):
    color, opacity, _ = hio.read_transfer_function(tf_path(tf))
    prop = hio.make_volume_property(color, opacity, unit)
    bounds = image.GetBounds()
    center = [(bounds[2 * a] + bounds[2 * a + 1]) / 2 for a in range(3)]
    extent = max(bounds[2 * a + 1] - bounds[2 * a] for a in range(3))
    cameras = {
        "perspective": hio.default_camera(bounds),
        "parallel": hio.camera_from_dict({
            "position": [center[0] + 0.3 * extent, center[1] - 2 * extent, center[2] + 0.7 * extent],
            "focal_point": center, "view_up": [0, 0, 1], "parallel_projection": True,
            "parallel_scale": 0.75 * extent}),
    }
    for label, camera in cameras.items():
        if iso is not None:
            compare_analytic(name, image, prop, camera, label, iso)
        ours = reference_image(image, prop, camera, *SIZE)
        theirs = independent_image(image, prop, camera, *SIZE)
        rmse = math.sqrt(((ours - theirs) ** 2).mean())
        peak = abs(ours - theirs).max()
        print("%-8s %-11s RMSE %.2e  max %.2e  (mean alpha %.3f)" % (
            name, label, rmse, peak, theirs[:, 3].mean()))
        c.check(theirs[:, 3].max() > 0.2, "%s %s: the view shows something" % (name, label))
        c.check(rmse < 1e-3, "%s %s: reference within RMSE 1e-3 of the independent integration"
                % (name, label))
        if convergence:
            coarse = independent_image(image, prop, camera, *SIZE, fine=2 * FINE)
            coarse_rmse = math.sqrt(((ours - coarse) ** 2).mean())
            print("%-8s %-11s independent step %g: RMSE %.2e, ratio %.1f" % (
                name, label, 2 * FINE, coarse_rmse, coarse_rmse / rmse))
            c.check(coarse_rmse / rmse > 3.0, "%s %s: the independent integration converges to "
                    "the reference (ratio %.2f for half the step)" % (name, label,
                                                                     coarse_rmse / rmse))


source = hovr.vtkMarschnerLobbSource()
source.SetDimensions(41, 41, 41)
source.Update()
compare("ml41", source.GetOutput(), "marschner-lobb-spikes", 0.05, convergence=True, iso=0.5)

shared = [("neghip", "neghip_64x64x64_uint8.raw", (64, 64, 64), "uint8", (1, 1, 1), 1.0),
          ("fuel", "fuel_64x64x64_uint8.raw", (64, 64, 64), "uint8", (1, 1, 1), 1.0),
          ("bucky", "bucky_32x32x32_uint8.raw", (32, 32, 32), "uint8", (1, 1, 1), 1.0),
          ("headsq", "headsq_64x64x93_uint16le.raw", (64, 64, 93), "uint16", (3.2, 3.2, 1.5),
           1.5)]
tfs = {"neghip": "neghip-spikes", "fuel": "fuel-spikes", "bucky": "bucky-spikes",
       "headsq": "ct-spikes"}
isos = {"neghip": 60.5, "fuel": 40.5, "bucky": 100.5, "headsq": 900.5}
for name, filename, dims, kind, spacing, unit in shared:
    path = shared_volume(filename)
    if path is None:
        print("skipping %s: %s not found (shared test data absent)" % (name, filename))
        continue
    compare(name, hio.read_volume(path, dims, kind, spacing), tfs[name], unit, iso=isos[name])
c.finish()
