"""How far an image is from the reference: the colour error metrics (compare) and, for
isosurfaces and projections, the measures of the Depth, MaxScalar or MinScalar array
(compare_blend, format_blend)."""

from vtkmodules.vtkCommonDataModel import vtkImageData

from . import hovrRenderingCore as core
from .io import HovrError
from .registry import BLEND_ARRAYS
from .renderer import _Errors


def compare(image, reference):
    """Error metrics of ``image`` against ``reference`` (vtkRGBAErrorMetrics): a dict and the
    difference image."""
    metrics = core.vtkRGBAErrorMetrics()
    metrics.SetInputData(image)
    metrics.SetReferenceData(reference)
    errors = _Errors(metrics)
    metrics.Update()
    errors.close()
    values = {"rmse": metrics.GetRMSE(), "max_error": metrics.GetMaximumError(),
              "measured_pixels": metrics.GetNumberOfMeasuredPixels()}
    for index, channel in enumerate("rgba"):
        values["rmse_" + channel] = metrics.GetChannelRMSE(index)
        values["max_error_" + channel] = metrics.GetChannelMaximumError(index)
    difference = vtkImageData()
    difference.DeepCopy(metrics.GetOutput())
    return values, difference


def compare_blend(image, reference, scene):
    """The measures of an isosurface or projection image against the reference's Depth or
    MaxScalar/MinScalar array (see hovr.bench): a dict."""
    import numpy
    from vtkmodules.util.numpy_support import vtk_to_numpy
    name = BLEND_ARRAYS[scene.blend]
    ours_array = image.GetPointData().GetArray(name)
    theirs_array = reference.GetPointData().GetArray(name)
    if ours_array is None or theirs_array is None:
        raise HovrError("the %s array is missing from an image to compare" % name)
    # Pixels a sampled reference did not compute (NaN RGBA) are left out.
    measured = numpy.isfinite(vtk_to_numpy(reference.GetPointData().GetArray("RGBA"))).all(axis=1)
    ours = vtk_to_numpy(ours_array).astype(numpy.float64)[measured]
    theirs = vtk_to_numpy(theirs_array).astype(numpy.float64)[measured]
    hit, ref_hit = numpy.isfinite(ours), numpy.isfinite(theirs)
    both = hit & ref_hit
    if scene.blend == "iso":
        voxel = min(abs(s) for s in scene.image.GetSpacing())
        error = numpy.abs(ours[both] - theirs[both]) / voxel
        # Grazing pixels: the reference's hit moves by more than the 1e-3 voxel tolerance, or
        # appears or vanishes, when the isovalue moves by 1e-6 of the data range (its
        # DepthSpread), so no float ray caster can be held to the tolerance there.
        spread_array = reference.GetPointData().GetArray("DepthSpread")
        grazing = (vtk_to_numpy(spread_array).astype(numpy.float64)[measured] > 1e-3 * voxel
                   if spread_array is not None else numpy.zeros_like(hit))
        well_posed = ~grazing[both]
        return {"hits_both": int(both.sum()),
                "hit_miss_disagreements": int((hit != ref_hit).sum()),
                "missed_hits": int((ref_hit & ~hit).sum()),
                "extra_hits": int((hit & ~ref_hit).sum()),
                "depth_max_error_voxels": float(error.max()) if both.any() else 0.0,
                "depth_p99_error_voxels": float(numpy.percentile(error, 99)) if both.any()
                else 0.0,
                "depth_mean_error_voxels": float(error.mean()) if both.any() else 0.0,
                "depth_outliers": int((error > 1e-3).sum()),
                "grazing_pixels": int(grazing.sum()),
                "disagreements_not_grazing": int(((hit != ref_hit) & ~grazing).sum()),
                "depth_max_error_not_grazing": float(error[well_posed].max())
                if well_posed.any() else 0.0,
                "depth_outliers_not_grazing": int((error[well_posed] > 1e-3).sum())}
    scalars = scene.image.GetPointData().GetScalars()
    low, high = scalars.GetFiniteRange() if hasattr(scalars, "GetFiniteRange") \
        else scalars.GetRange()
    span = (high - low) or 1.0
    # Extrema come back from the GPU as float: the reference's, rounded the same way.
    theirs = theirs.astype(numpy.float32).astype(numpy.float64)
    error = numpy.abs(ours[both] - theirs[both]) / span
    return {"hits_both": int(both.sum()),
            "hit_miss_disagreements": int((hit != ref_hit).sum()),
            "extremum_max_error": float(error.max()) if both.any() else 0.0,
            "extremum_mean_error": float(error.mean()) if both.any() else 0.0}


def format_blend(row):
    """A short text of compare_blend's measures for log lines ('' for composite rows)."""
    if "depth_max_error_voxels" in row:
        return ("  hits %d, misses %d, extra %d, depth error max %.2e p99 %.2e voxel, "
                "%d over 1e-3; %d grazing, apart from them %d disagreements, max %.2e, "
                "%d over 1e-3" % (row["hits_both"], row["missed_hits"], row["extra_hits"],
                                  row["depth_max_error_voxels"], row["depth_p99_error_voxels"],
                                  row["depth_outliers"], row["grazing_pixels"],
                                  row["disagreements_not_grazing"],
                                  row["depth_max_error_not_grazing"],
                                  row["depth_outliers_not_grazing"]))
    if "extremum_max_error" in row:
        return "  disagreements %d, extremum error max %.2e mean %.2e of the range" % (
            row["hit_miss_disagreements"], row["extremum_max_error"], row["extremum_mean_error"])
    return ""
