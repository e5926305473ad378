"""The speed/accuracy trade as a picture: RMSE against time per frame, one line per method."""

import math

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402

COLORS = {"stock": "#555555", "preint1": "#1f77b4", "preint2": "#d62728", "reference": "#2ca02c"}


def tradeoff(rows, path):
    """Write a PNG with one panel per dataset: x = median ms per frame, y = RMSE (log-log),
    each method's points joined in step order and labelled with the step."""
    datasets = []
    for row in rows:
        if row["dataset"] not in datasets and row["method"] != "reference":
            datasets.append(row["dataset"])
    if not datasets:
        return
    columns = min(3, len(datasets))
    lines = int(math.ceil(len(datasets) / columns))
    figure, axes = plt.subplots(lines, columns, figsize=(5.0 * columns, 4.0 * lines),
                                squeeze=False)
    for index, name in enumerate(datasets):
        axis = axes[index // columns][index % columns]
        methods = []
        for row in rows:
            if row["dataset"] == name and row["method"] not in methods \
                    and row["method"] != "reference":
                methods.append(row["method"])
        for method in methods:
            points = sorted((r["step"], r["median_ms"], r["rmse"]) for r in rows
                            if r["dataset"] == name and r["method"] == method)
            xs = [p[1] for p in points]
            ys = [max(p[2], 1e-7) for p in points]
            axis.plot(xs, ys, "o-", label=method, color=COLORS.get(method))
            for step, x, y in zip([p[0] for p in points], xs, ys):
                axis.annotate("%g" % step, (x, y), textcoords="offset points", xytext=(4, 4),
                              fontsize=7)
        axis.set_xscale("log")
        axis.set_yscale("log")
        axis.set_xlabel("median ms per frame")
        axis.set_ylabel("RMSE vs reference (premultiplied RGBA)")
        axis.set_title(name + " (labels: step in voxels)")
        axis.grid(True, which="both", alpha=0.3)
        axis.legend()
    for index in range(len(datasets), lines * columns):
        axes[index // columns][index % columns].axis("off")
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)


def _rgb(image, array="RGBA", scale=1.0):
    """An image's RGB over black as an H x W x 3 array for imshow (row 0 at the top)."""
    import numpy
    from vtkmodules.util.numpy_support import vtk_to_numpy
    w, h, _ = image.GetDimensions()
    values = vtk_to_numpy(image.GetPointData().GetArray(array))[:, :3].reshape(h, w, 3)
    return numpy.clip(numpy.nan_to_num(values) * scale, 0.0, 1.0)[::-1]


def side_by_side(name, reference, panels, path):
    """The reference and every run side by side, each run above its 10x difference image.
    ``panels`` holds (row, image, difference) with row the bench's result row."""
    columns = len(panels) + 1
    figure, axes = plt.subplots(2, columns, figsize=(2.6 * columns, 5.6), squeeze=False)
    axes[0][0].imshow(_rgb(reference))
    axes[0][0].set_title("%s\nreference" % name, fontsize=8)
    axes[1][0].axis("off")
    for index, (row, image, difference) in enumerate(panels, start=1):
        axes[0][index].imshow(_rgb(image))
        axes[0][index].set_title("%s, step %g\nRMSE %.4f, %.1f ms" % (
            row["method"], row["step"], row["rmse"], row["median_ms"]), fontsize=8)
        axes[1][index].imshow(_rgb(difference, "Difference", 10.0))
        axes[1][index].set_title("|difference| x 10", fontsize=8)
    for line in axes:
        for axis in line:
            axis.set_xticks([])
            axis.set_yticks([])
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)


def _trilinear(values, spacing, origin, points):
    """Trilinear interpolation of values[z, y, x] at world points (N x 3)."""
    import numpy
    nz, ny, nx = values.shape
    p = (points - origin) / spacing
    cell = numpy.clip(numpy.floor(p).astype(int), 0, [nx - 2, ny - 2, nz - 2])
    f = p - cell
    i, j, k = cell[:, 0], cell[:, 1], cell[:, 2]
    fx, fy, fz = f[:, 0], f[:, 1], f[:, 2]
    result = 0.0
    for dz in (0, 1):
        for dy in (0, 1):
            for dx in (0, 1):
                weight = ((fx if dx else 1 - fx) * (fy if dy else 1 - fy)
                          * (fz if dz else 1 - fz))
                result = result + weight * values[k + dz, j + dy, i + dx]
    return result


def ray_profile(scene, step, path, pixel=None):
    """El Hajjar et al., Figures 1, 2, 4 and 5 for one ray of ``scene`` (by default the ray
    of the image centre): the trilinear scalar (black) against its zero-, first- and
    second-order approximations (red), sampled at the dual-voxel borders and their midpoints
    (the ideal case) and at a constant ``step`` (voxels); the signed difference is shaded and
    xi, the integral of its absolute value, is given for each."""
    import numpy
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from . import hovrRenderingCore as core

    image = scene.image
    nx, ny, nz = image.GetDimensions()
    values = vtk_to_numpy(image.GetPointData().GetScalars()).astype(float).reshape(nz, ny, nx)
    spacing = numpy.array(image.GetSpacing())
    origin = numpy.array(image.GetOrigin())
    rays = core.vtkCameraRayModel()
    rays.SetCamera(scene.camera)
    rays.SetImageSize(*scene.size)
    rays.Prepare()
    start, direction = [0.0] * 3, [0.0] * 3
    i, j = pixel or (scene.size[0] // 2, scene.size[1] // 2)
    rays.GetPixelRay(i, j, start, direction)
    start, direction = numpy.array(start), numpy.array(direction)
    lo, hi = origin, origin + spacing * (numpy.array([nx, ny, nz]) - 1)
    with numpy.errstate(divide="ignore", invalid="ignore"):
        ta, tb = (lo - start) / direction, (hi - start) / direction
    t0 = max(0.0, numpy.nanmax(numpy.where(numpy.isfinite(ta), numpy.minimum(ta, tb), -numpy.inf)))
    t1 = numpy.nanmin(numpy.where(numpy.isfinite(ta), numpy.maximum(ta, tb), numpy.inf))
    if not t1 > t0:
        return
    signal = lambda t: _trilinear(values, spacing, origin, start + numpy.outer(t, direction))
    dense = numpy.linspace(t0, t1, 4000)
    ideal = signal(dense)

    # Sample positions: dual-voxel borders (where the ray crosses grid planes) ...
    borders = [t0, t1]
    for axis in range(3):
        if direction[axis] != 0.0:
            planes = origin[axis] + spacing[axis] * numpy.arange(image.GetDimensions()[axis])
            t = (planes - start[axis]) / direction[axis]
            borders.extend(t[(t > t0) & (t < t1)])
    borders = numpy.unique(numpy.array(borders))
    # ... and a constant step from the entry, the last piece ending at the exit.
    d = step * spacing.min()
    fixed = numpy.append(numpy.arange(t0, t1, d), t1)

    def piecewise(knots, order):
        approx = numpy.empty_like(dense)
        # Second order: a quadratic through each pair of knots and their midpoint.
        mids = (knots[:-1] + knots[1:]) / 2
        for k in range(len(knots) - 1):
            a, b = knots[k], knots[k + 1]
            inside = (dense >= a) & (dense <= b)
            u = (dense[inside] - a) / (b - a)
            fa, fb = signal(numpy.array([a, b]))
            if order == 0:
                approx[inside] = signal(numpy.array([(a + b) / 2]))[0]
            elif order == 1:
                approx[inside] = fa + (fb - fa) * u
            else:
                fm = signal(numpy.array([mids[k]]))[0]
                approx[inside] = fa * (1 - 3 * u + 2 * u * u) + fm * (4 * u - 4 * u * u) \
                    + fb * (2 * u * u - u)
        return approx

    fixed_slabs = numpy.append(numpy.arange(t0, t1, 2 * d), t1)
    with_mids = lambda knots: numpy.sort(numpy.concatenate([knots, (knots[:-1] + knots[1:]) / 2]))
    cases = [("zero order (midpoint), dual-voxel borders: Fig. 1", piecewise(borders, 0), borders),
             ("first order, dual-voxel borders: Fig. 2", piecewise(borders, 1), borders),
             ("second order, borders and midpoints: Fig. 4", piecewise(borders, 2),
              with_mids(borders)),
             ("first order, step %g voxel: Fig. 5a" % step, piecewise(fixed, 1), fixed),
             ("second order, slabs of 2 x %g voxel: Fig. 5b" % step, piecewise(fixed_slabs, 2),
              with_mids(fixed_slabs))]
    figure, axes = plt.subplots(len(cases), 1, figsize=(9.0, 2.2 * len(cases)), sharex=True)
    for axis, (title, approx, knots) in zip(axes, cases):
        difference = ideal - approx
        xi = numpy.trapz(numpy.abs(difference), dense)
        axis.plot(dense, ideal, color="black", linewidth=1.0, label="trilinear")
        axis.plot(dense, approx, color="red", linewidth=0.8, label="approximation")
        axis.fill_between(dense, approx, ideal, color="green", alpha=0.4, linewidth=0)
        axis.plot(knots, signal(knots), "o", color="black", markersize=2)
        axis.set_title("%s   xi = %.4g" % (title, xi), fontsize=9)
        axis.set_ylabel("scalar", fontsize=8)
    axes[-1].set_xlabel("distance along the ray (world units)")
    axes[0].legend(fontsize=7, loc="upper right")
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)
