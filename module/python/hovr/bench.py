"""``hovr bench``: sweep datasets x methods x steps and measure the speed/accuracy trade.

A bench configuration is a JSON object::

    {
      "size": [512, 512],            # image size
      "repeat": 5,                   # timed frames per run (after one warm-up frame)
      "methods": ["stock", "preint1"],
      "steps": [0.5, 1, 2, 4],       # in units of the smallest voxel spacing
      "datasets": [
        {"name": "ml41", "input": "marschner-lobb:41",
         "tf": "../transfer-functions/marschner-lobb-spikes.json",
         "opacity_unit_distance": 0.05,
         "camera": "optional camera JSON; default: an oblique view of the whole volume"},
        {"name": "neghip", "input": "${HOVR_DATA}/neghip_64x64x64_uint8.raw",
         "dims": [64, 64, 64], "type": "uint8", "spacing": [1, 1, 1],
         "header_bytes": 0,           # raw input: bytes before the data (default 0)
         "tf": "...", "optional": true}
      ]
    }

Instead of methods x steps, ``"runs": [["preint1", 2], ["preint2", 2], ["stock", 0.25]]``
(top level or per dataset) lists method-step pairs, and ``"baseline": ["preint1", 2]`` names
the run that the ms and RMSE ratio columns compare with (default: stock at the same step).
``"blend": "iso" | "mip" | "minip"`` in a dataset renders that blend mode (methods
``iso-analytic``, ``iso-stock``, ...), with ``"isovalues": [v, ...]`` for ``iso`` and
``"shade": true`` to light the surface (composite datasets too: shaded pre-integration, with
``"ambient"``, ``"diffuse"``, ``"specular_coefficient"``, ``"specular_power"``,
``"gradient_interpolation"``, ``"gooch"``, ``"cone"`` ("paper" or "matched"), ``"exaggerate"``
(epsilon of vtkGradientExaggeration's normals) and, with ``"cone_reference": true``, an ``rmse_cone``
column against the reference with the cone specular term that pre-integration uses); its rows
add the measures of the analytic paper against the float64 reference: for ``iso`` the pixels
both hit, the hit/miss disagreements (surfaces the method misses, hits the reference lacks)
and the depth error in voxels (largest, 99th percentile, mean) where both hit; for the
projections the largest and mean error of the extremum as a fraction of the data range.
``"adaptive": {"lmax": 3, "epsilon": 0.002, "oracle": "range"}`` in a dataset sets the
adaptive methods' top level, oracle threshold and oracle mode (those are the defaults); a run
``[method, step, {"lmax": 2}]`` renders an adaptive method with settings of its own (its rows
are named after them, e.g. ``adaptive-cpu(lmax=2)``), and their rows add the operation counts
(``sample_ops``, ``synthesis_ops``, ``full_rate_samples``, ``sample_ratio_to_full``: samples
over those of a full-rate ray caster on the same slice grid) and the base step in voxels
(``slice_spacing_voxels``). A run's step ``"pixel"`` is that base step: the distance
between neighbouring rays of the dataset's parallel camera, in voxels. A pre-integration run
takes ``{"table_memory_mib": 256}``: the table memory limit its automatic sizes use.
``"input": "marschner-lobb:N:TYPE"`` generates the volume as uint8, uint16 or float32, and
``"tf_to_data_range": true`` maps the transfer function's nodes onto the data's range.
``"reference_pixels": f`` in a dataset has the reference integrate a seeded fraction f of the
pixels only (the others are left out of every measure), for volumes too large to integrate
every pixel. ``"memory": true`` (top level or per dataset) runs each method once more in a
process of its own and adds ``first_frame_ms`` (its first frame: uploads, tables, shader) and
``peak_rss_mib`` (the process's own peak resident memory, the volume included), and
``volume_rss_mib``, the peak of a process that only loads the volume and opens the window.
``"ray_profile": true`` in a dataset adds ``<name>_ray_profile.png``: along the ray of the
image centre, the trilinear scalar against its piecewise-linear and piecewise-quadratic
approximations with the error term xi of El Hajjar et al., section 3.2.

Paths are relative to the configuration file; ``${HOVR_DATA}`` is the shared test-data folder
(environment variable HOVR_DATA, by default ../shared/data beside the project) and
``${HOVR_ROOT}`` the project. A dataset marked optional whose input is missing is skipped with
a message. Per-dataset entries may override "methods" and "steps".

GPU runs of a dataset are timed in interleaved rounds (one frame of each method and step per
round), so that load changes on a shared machine hit them alike and the time ratios to the
stock mapper stay meaningful; against the baseline, ``ms_ratio_paired`` (with its smallest and
largest value) is the median of the per-round ratios, steadier than the ratio of the medians
(``ms_ratio_to_baseline``) when the load changes within a run. Every image is compared with
the reference integrator's (cached under ``cache/``). Written
to the output folder: ``results.csv`` (one row per dataset, method and step), ``images/``
(renderings and 10x difference images), ``tradeoff.png`` (error against time per frame) and
``summary.txt``.
"""

import csv
import hashlib
import json
import os
import re
import statistics
import subprocess
import sys
import time

from . import io as hio
from . import methods as hm
from .io import HovrError

CSV_FIELDS = ["dataset", "method", "step", "width", "height", "median_ms", "min_ms", "max_ms",
              "samples_per_frame", "rmse", "rmse_cone", "max_error", "rmse_r", "rmse_g", "rmse_b", "rmse_a",
              "ms_ratio_to_stock", "rmse_ratio_to_stock", "baseline", "ms_ratio_to_baseline",
              "rmse_ratio_to_baseline", "ms_ratio_paired", "ms_ratio_paired_min",
              "ms_ratio_paired_max", "table_size", "table_sizing_ms", "table_build_ms", "table_gpu_bytes",
              "volume_gpu_bytes", "normal_gpu_bytes", "oracle_gpu_bytes", "block_gpu_bytes",
              "corner_gpu_bytes", "volume_bricks", "volume_textures",
              "hits_both", "hit_miss_disagreements", "missed_hits", "extra_hits",
              "depth_max_error_voxels", "depth_p99_error_voxels", "depth_mean_error_voxels",
              "depth_outliers", "grazing_pixels", "disagreements_not_grazing",
              "depth_max_error_not_grazing", "depth_outliers_not_grazing",
              "extremum_max_error", "extremum_mean_error",
              "nontransparent_cells", "occluded_ratio", "occluded_ratio_first_hit", "octree_nodes",
              "cpu_bytes", "instruction_set", "slice_spacing_voxels", "sample_ops",
              "synthesis_ops", "accumulate_ops", "boundary_sample_ops", "full_rate_samples",
              "sample_ratio_to_full",
              "passes_per_frame", "first_frame_ms", "peak_rss_mib", "volume_rss_mib",
              "measured_pixels"]

# Part of the reference cache key: bump when the reference's output changes.
REFERENCE_VERSION = 4

def _project_root():
    root = os.environ.get("HOVR_ROOT")
    if root:
        return root
    # Installed or build-tree package: the project root is not known; fall back to the cwd.
    return os.getcwd()


def data_folder():
    """Where the shared test volumes live (HOVR_DATA, else ../shared/data beside the project)."""
    return os.environ.get("HOVR_DATA") or os.path.join(_project_root(), os.pardir, "shared",
                                                       "data")


def _expand(value, base):
    value = value.replace("${HOVR_DATA}", data_folder()).replace("${HOVR_ROOT}", _project_root())
    return value if os.path.isabs(value) else os.path.normpath(os.path.join(base, value))


# Generated test volumes by --input prefix: the source class and its default size.
GENERATED_VOLUMES = {"marschner-lobb": ("vtkMarschnerLobbSource", 41),
                     "thin-features": ("vtkThinFeatureSource", 64),
                     "curved-shells": ("vtkCurvedShellSource", 129),
                     "blobs": ("vtkBlobSource", 129)}


def load_volume(spec, base=None):
    """A volume from a dataset entry or an --input string: a path, ``marschner-lobb[:N]``,
    ``thin-features[:N]`` (vtkThinFeatureSource), ``curved-shells[:N]``
    (vtkCurvedShellSource) or ``blobs[:N]`` (vtkBlobSource)."""
    source = spec["input"]
    for prefix, (class_name, default_size) in GENERATED_VOLUMES.items():
        if source == prefix or source.startswith(prefix + ":"):
            from . import hovrFiltersSources as sources
            raw_options = [key for key in ("dims", "type", "spacing", "header_bytes")
                           if spec.get(key) is not None]
            if raw_options:
                raise HovrError("%s is generated: %s apply to raw input only" % (
                    prefix, ", ".join("--" + k.replace("_", "-") for k in raw_options)))
            parts = source.split(":")
            try:
                size = int(parts[1]) if len(parts) > 1 else default_size
            except ValueError:
                raise HovrError("%s:N needs an integer N, got %r" % (prefix, source)) from None
            if size < 2:
                raise HovrError("%s needs at least 2 points per axis" % prefix)
            generator = getattr(sources, class_name)()
            if len(parts) > 2:
                # marschner-lobb:N:TYPE, the field scaled to the type's range.
                types = {"float32": 10, "uint8": 3, "uint16": 5}
                if prefix != "marschner-lobb" or parts[2] not in types or len(parts) > 3:
                    raise HovrError("only marschner-lobb:N:TYPE takes a type (%s), got %r" % (
                        ", ".join(sorted(types)), source))
                generator.SetOutputScalarType(types[parts[2]])
            generator.SetDimensions(size, size, size)
            generator.Update()
            return generator.GetOutput()
    path = _expand(source, base) if base else source
    return hio.read_volume(path, spec.get("dims"), spec.get("type"), spec.get("spacing"),
                           spec.get("header_bytes"))


EXAGGERATED_NORMALS = "ExaggeratedNormals"


def make_oracle(image, opacity, mode, epsilon, name):
    """vtkAdaptiveSamplingOracle on ``image`` for the opacity function (``mode`` a key of
    ORACLE_MODES, feature threshold ``epsilon``), writing the point array ``name``. The
    distances are not capped below the volume's diagonal, so every l_max and step can use
    them."""
    from . import hovrFiltersImaging as imaging
    from .registry import ORACLE_MODES
    oracle = imaging.vtkAdaptiveSamplingOracle()
    oracle.SetInputData(image)
    oracle.SetMode(ORACLE_MODES[mode])
    oracle.SetScalarOpacity(opacity)
    oracle.SetEpsilon(float(epsilon))
    bounds = image.GetBounds()
    diagonal = sum((bounds[2 * a + 1] - bounds[2 * a]) ** 2 for a in range(3)) ** 0.5
    oracle.AutomaticMaximumDistanceOff()
    oracle.SetMaximumDistance(max(diagonal, min(abs(s) for s in image.GetSpacing())))
    oracle.SetOutputArrayName(name)
    return oracle


def oracle_name(mode, epsilon):
    """The name of the oracle array of ``mode`` and ``epsilon`` (add_oracle)."""
    return "OracleDistance_%s_%g" % (mode, float(epsilon))


def add_oracle(scene, mode, epsilon):
    """Adds to the scene's volume the oracle of adaptive sampling for its opacity
    (make_oracle), once per (mode, epsilon); returns the array's name."""
    from .renderer import _Errors
    key = (mode, float(epsilon))
    if key in scene.oracles:
        return scene.oracles[key]
    name = oracle_name(mode, epsilon)
    image = scene.image
    oracle = make_oracle(image, scene.prop.GetScalarOpacity(), mode, epsilon, name)
    errors = _Errors(oracle)
    oracle.Update()
    errors.close()
    image.GetPointData().AddArray(oracle.GetOutput().GetPointData().GetArray(name))
    scene.oracles[key] = name
    return name


def exaggerate_normals(image, epsilon, neighborhood=5):
    """A shallow copy of ``image`` with the normals of vtkGradientExaggeration (epsilon, a
    neighborhood**3 box) as the point array EXAGGERATED_NORMALS."""
    from . import hovrFiltersImaging as imaging
    from .renderer import _Errors
    exaggeration = imaging.vtkGradientExaggeration()
    exaggeration.SetInputData(image)
    exaggeration.SetEpsilon(float(epsilon))
    exaggeration.SetNeighborhoodSize(int(neighborhood))
    exaggeration.SetOutputArrayName(EXAGGERATED_NORMALS)
    errors = _Errors(exaggeration)
    exaggeration.Update()
    errors.close()
    from vtkmodules.vtkCommonDataModel import vtkImageData
    result = vtkImageData()
    result.ShallowCopy(exaggeration.GetOutput())
    return result


def load_config(path):
    config = hio.read_json(path, "bench configuration")
    if not isinstance(config, dict) or not isinstance(config.get("datasets"), list):
        raise HovrError("%s: a bench configuration is an object with a 'datasets' list" % path)
    for name in config.get("methods", []):
        hm.get_method(name)
    for entry in config.get("runs", []) + [r for d in config["datasets"] for r in d.get("runs", [])]:
        if (not isinstance(entry, list) or len(entry) not in (2, 3)
                or not (entry[1] == "pixel" or isinstance(entry[1], (int, float))
                        and entry[1] > 0)
                or (len(entry) == 3 and not (isinstance(entry[2], int) and entry[2] >= 1)
                    and not isinstance(entry[2], dict))):
            raise HovrError("%s: a run is [method, positive step], [method, positive step, "
                            "threads] or [method, positive step, {settings}], got %r"
                            % (path, entry))
        hm.get_method(entry[0], settings=entry[2] if len(entry) == 3 and
                      isinstance(entry[2], dict) else None)
    for step in config.get("steps", []):
        if not (isinstance(step, (int, float)) and step > 0):
            raise HovrError("%s: steps must be positive numbers, got %r" % (path, step))
    return config


def _reference_key(spec, image, prop_desc, camera, size):
    digest = hashlib.sha256()
    scalars = image.GetPointData().GetScalars()
    from vtkmodules.util.numpy_support import vtk_to_numpy
    digest.update(vtk_to_numpy(scalars).tobytes())
    digest.update(json.dumps([image.GetDimensions(), image.GetSpacing(), image.GetOrigin(),
                              prop_desc, hio.camera_to_dict(camera), size,
                              REFERENCE_VERSION],
                             sort_keys=True).encode())
    return digest.hexdigest()[:20]


def rescale_transfer_function(color, opacity, image):
    """Map the transfer functions' nodes from their own value range onto the data's."""
    low, high = image.GetPointData().GetScalars().GetFiniteRange()
    for function, width in ((color, 6), (opacity, 4)):
        nodes = []
        for k in range(function.GetSize()):
            node = [0.0] * width
            function.GetNodeValue(k, node)
            nodes.append(node)
        first, last = nodes[0][0], nodes[-1][0]
        for k, node in enumerate(nodes):
            node[0] = low + (node[0] - first) / ((last - first) or 1.0) * (high - low)
            function.SetNodeValue(k, node)


def _scene_for(spec, base, size):
    image = load_volume(spec, base)
    warnings = hio.check_volume(image)
    tf_path = _expand(spec["tf"], base)
    color, opacity, _ = hio.read_transfer_function(tf_path)
    if spec.get("tf_to_data_range"):
        rescale_transfer_function(color, opacity, image)
    unit = float(spec.get("opacity_unit_distance", 1.0))
    prop = hio.make_volume_property(color, opacity, unit)
    if spec.get("camera"):
        camera = hio.read_camera(_expand(spec["camera"], base))
    else:
        camera = hio.default_camera(image.GetBounds(), parallel=bool(spec.get("parallel")))
    with open(tf_path, "rb") as stream:
        prop_desc = [hashlib.sha256(stream.read()).hexdigest(), unit,
                     bool(spec.get("tf_to_data_range"))]
    if spec.get("shade"):
        prop.ShadeOn()
    blend = spec.get("blend", "composite")
    isovalues = [float(v) for v in spec.get("isovalues", [])]
    if blend == "iso" and not isovalues:
        raise HovrError("dataset %s: an iso dataset needs \"isovalues\"" % spec.get("name", ""))
    for k, value in enumerate(isovalues):
        prop.GetIsoSurfaceValues().SetValue(k, value)
    shading = {"interpolation": spec.get("gradient_interpolation", "nonlinear"),
               "gooch": bool(spec.get("gooch")), "specular": spec.get("specular", "lobe"),
               "normals": None, "cone": spec.get("cone", "paper")}
    if spec.get("exaggerate") is not None:
        image = exaggerate_normals(image, float(spec["exaggerate"]))
        shading["normals"] = EXAGGERATED_NORMALS
    prop_desc += [blend, isovalues, bool(spec.get("shade"))]
    if spec.get("shade"):
        for key in ("ambient", "diffuse", "specular_coefficient", "specular_power"):
            if key in spec:
                {"ambient": prop.SetAmbient, "diffuse": prop.SetDiffuse,
                 "specular_coefficient": prop.SetSpecular,
                 "specular_power": prop.SetSpecularPower}[key](float(spec[key]))
        prop_desc += [shading, prop.GetAmbient(), prop.GetDiffuse(), prop.GetSpecular(),
                      prop.GetSpecularPower()]
    scene = hm.Scene(image, prop, camera, size, blend)
    scene.shading = shading
    scene.adaptive.update(spec.get("adaptive", {}))
    return scene, warnings, prop_desc


def run(config_path, output, log=print, renderer=None):
    """Run a bench; returns the list of result rows. A configuration of ``"kind": "latency"``
    runs hovr.latency instead."""
    config = load_config(config_path)
    base = os.path.dirname(os.path.abspath(config_path))
    if config.get("kind") == "latency":
        from . import latency
        os.makedirs(os.path.join(output, "cache"), exist_ok=True)
        return latency.run(config, base, output, log)
    size = tuple(config.get("size", (512, 512)))
    repeat = int(config.get("repeat", 5))
    os.makedirs(os.path.join(output, "images"), exist_ok=True)
    os.makedirs(os.path.join(output, "cache"), exist_ok=True)
    own_renderer = renderer is None
    renderer = renderer or hm.Renderer()
    rows = []
    skipped = []
    try:
        for spec in config["datasets"]:
            name = spec.get("name") or os.path.basename(spec["input"])
            try:
                scene, warnings, prop_desc = _scene_for(spec, base, size)
            except HovrError as error:
                if spec.get("optional") and "not found" in str(error):
                    log("skipping %s: %s" % (name, error))
                    skipped.append(name)
                    continue
                raise
            for warning in warnings:
                log("%s: warning: %s" % (name, warning))
            fraction = spec.get("reference_pixels")
            if fraction is not None:
                prop_desc = prop_desc + ["pixels", fraction]
            reference = _reference(renderer, scene, name, output,
                                   _reference_key(spec, scene.image, prop_desc, scene.camera,
                                                  size), log,
                                   settings={"pixel_fraction": fraction} if fraction else None)
            hio.rgba_to_png(reference, os.path.join(output, "images", name + "_reference.png"))
            # Shaded datasets: also the ground truth with the cone that pre-integration uses,
            # which splits a method's error into the cone's and the rest.
            cone = None
            if spec.get("shade") and spec.get("cone_reference"):
                cone = _reference(renderer, scene, name, output,
                                  _reference_key(spec, scene.image, prop_desc + ["cone"],
                                                 scene.camera, size), log, "reference-cone")
            dataset_rows = []
            pairs = [(hm.get_method(n, threads, settings), _resolve_step(step, scene))
                     for n, step, threads, settings in _runs_of(spec, config)]
            runs = [(m, step) for m, step in pairs if m.kind == "gpu"]
            results = renderer.render_interleaved(runs, scene, repeat) if runs else []
            for m, step in pairs:
                if m.kind == "cpu":
                    runs.append((m, step))
                    results.append(renderer.render(m, scene, step, repeat))
            memory = {}
            if spec.get("memory", config.get("memory")):
                volume_rss = _isolated_frame(spec, base, size, None, None, None)["peak_rss_mib"]
                for n, step, threads, settings in _runs_of(spec, config):
                    step = _resolve_step(step, scene)
                    measured = _isolated_frame(spec, base, size, n, step, settings)
                    measured["volume_rss_mib"] = volume_rss
                    memory[(hm.get_method(n, threads, settings).name, step)] = measured
                    log("%-10s %-9s step %-5g first frame %9.0f ms, peak %7.0f MiB (volume "
                        "alone %.0f)" % (name, n, step, measured["first_frame_ms"],
                                         measured["peak_rss_mib"], volume_rss))
            panels = []
            for (method, step), result in zip(runs, results):
                errors, difference = hm.compare(result.image, reference)
                row = result.summary(method.name, step)
                # GPU runs were timed in interleaved rounds: their frames pair up by round.
                row["_times"] = result.times_ms
                row["_interleaved"] = method.kind == "gpu"
                row.update(errors)
                if cone is not None:
                    row["rmse_cone"] = hm.compare(result.image, cone)[0]["rmse"]
                if scene.blend != "composite":
                    row.update(hm.compare_blend(result.image, reference, scene))
                row["dataset"] = name
                row.update(memory.get((method.name, step), {}))
                dataset_rows.append(row)
                stem = "%s_%s_step%g" % (name, re.sub(r"[^A-Za-z0-9.=_-]+", "-", method.name),
                                         step)
                hio.rgba_to_png(result.image, os.path.join(output, "images", stem + ".png"))
                hio.rgba_to_png(difference, os.path.join(output, "images", stem + "_diff.png"),
                                array="Difference", scale=10.0)
                panels.append((row, result.image, difference))
                log("%-10s %-9s step %-5g %9.2f ms  rmse %.5f  max %.4f%s" % (
                    name, method.name, step, row["median_ms"], row["rmse"], row["max_error"],
                    hm.format_blend(row)))
            from . import plot
            plot.side_by_side(name, reference, panels,
                              os.path.join(output, name + "_side_by_side.png"))
            if spec.get("ray_profile"):
                plot.ray_profile(scene, float(spec.get("ray_profile_step", 2.0)),
                                 os.path.join(output, name + "_ray_profile.png"))
            baseline = spec.get("baseline", config.get("baseline"))
            if baseline:
                baseline = [baseline[0], _resolve_step(baseline[1], scene)]
            _add_ratios(dataset_rows, baseline)
            rows.extend(dataset_rows)
    finally:
        if own_renderer:
            renderer.close()
    write_csv(rows, os.path.join(output, "results.csv"))
    from . import plot
    plot.tradeoff(rows, os.path.join(output, "tradeoff.png"))
    summary = format_summary(rows, skipped)
    with open(os.path.join(output, "summary.txt"), "w", encoding="utf-8") as stream:
        stream.write(summary)
    return rows, summary


def _reference(renderer, scene, name, output, key, log, method="reference", settings=None):
    path = os.path.join(output, "cache", "%s_%s_%s.vti" % (method, name, key))
    if os.path.isfile(path):
        return hio.read_vti(path)
    log("%-10s computing the %s %dx%d ..." % (name, method, scene.size[0], scene.size[1]))
    result = renderer.render(hm.get_method(method, settings=settings), scene, 1.0, 0)
    hio.write_vti(result.image, path)
    return result.image


def _isolated_frame(spec, base, size, method, step, settings):
    """One frame of ``method`` (None: none, the window only) in a process of its own: its
    first frame's time and the process's peak resident memory, in a dict."""
    request = json.dumps({"spec": spec, "base": base, "size": list(size), "method": method,
                          "step": step, "settings": settings})
    child = subprocess.run([sys.executable, "-c", "import sys; from hovr import bench; "
                            "bench._isolated_frame_child(sys.argv[1])", request],
                           stdout=subprocess.PIPE, env=dict(os.environ), check=False)
    if child.returncode != 0:
        raise HovrError("the isolated frame of %s failed (status %d)" % (method,
                                                                        child.returncode))
    return json.loads(child.stdout.decode().strip().splitlines()[-1])


def peak_resident_mib():
    """This process's peak resident memory in MiB, of its own address space only: the kernel's
    high-water mark (VmHWM). The maximum resident size that wait4 and getrusage report for a
    child also counts the parent's pages the child shared before its exec, so a child of a
    large process would report at least the parent's size."""
    try:
        with open("/proc/self/status") as status:
            for line in status:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    import resource
    scale = 1024.0 * 1024.0 if sys.platform == "darwin" else 1024.0  # bytes on macOS
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / scale


def _isolated_frame_child(request):
    request = json.loads(request)
    scene, _, _ = _scene_for(request["spec"], request["base"], tuple(request["size"]))
    renderer = hm.Renderer()
    renderer._ensure_window(scene.size)
    elapsed = 0.0
    if request["method"]:
        method = hm.get_method(request["method"], settings=request["settings"])
        start = time.perf_counter()
        renderer.render(method, scene, request["step"], 0)
        elapsed = time.perf_counter() - start
    renderer.close()
    print(json.dumps({"first_frame_ms": 1000.0 * elapsed, "peak_rss_mib": peak_resident_mib()}))


def _runs_of(spec, config):
    """The (method name, step, threads, adaptive settings) of a dataset: explicit runs
    ([name, step], [name, step, threads] or [name, step, {settings}]), else methods x steps;
    threads None is the default, settings None the scene's."""
    runs = spec.get("runs", config.get("runs"))
    if runs:
        return [(run[0], run[1] if run[1] == "pixel" else float(run[1]),
                 run[2] if len(run) > 2 and not isinstance(run[2], dict) else None,
                 run[2] if len(run) > 2 and isinstance(run[2], dict) else None)
                for run in runs]
    steps = spec.get("steps", config.get("steps", [1]))
    names = spec.get("methods", config.get("methods", ["stock", "preint1"]))
    return [(name, step, None, None) for name in names
            for step in (steps if hm.get_method(name).uses_step else [min(steps)])]


def _resolve_step(step, scene):
    """A run's step in voxels; "pixel" is the distance between neighbouring rays of the
    scene's parallel camera, the base step of adaptive sampling's slice grid."""
    if step != "pixel":
        return step
    if not scene.camera.GetParallelProjection():
        raise HovrError("a run at step \"pixel\" needs a parallel camera (\"parallel\": true)")
    spacing = min(abs(s) for s in scene.image.GetSpacing())
    return 2.0 * scene.camera.GetParallelScale() / scene.size[1] / spacing


def _add_ratios(rows, baseline=None):
    stock = {row["step"]: row for row in rows if row["method"] == "stock"}
    base_row = None
    if baseline:
        base_row = next((row for row in rows if row["method"] == baseline[0]
                         and row["step"] == float(baseline[1])), None)
    for row in rows:
        base = stock.get(row["step"])
        if base and base["median_ms"] > 0 and base["rmse"] > 0:
            row["ms_ratio_to_stock"] = row["median_ms"] / base["median_ms"]
            row["rmse_ratio_to_stock"] = row["rmse"] / base["rmse"]
        # The time ratio does not need an RMSE ratio: a baseline may match the reference
        # exactly (a MIP whose transfer function is flat where the methods differ).
        if base_row and base_row["median_ms"] > 0:
            row["baseline"] = "%s@%g" % (base_row["method"], base_row["step"])
            row["ms_ratio_to_baseline"] = row["median_ms"] / base_row["median_ms"]
            row["rmse_ratio_to_baseline"] = (row["rmse"] / base_row["rmse"]
                                             if base_row["rmse"] > 0 else float("nan"))
            row.update(paired_ratio(row, base_row))


def paired_ratio(row, base_row):
    """The time ratio of two runs timed in the same interleaved rounds, round by round: the
    median, smallest and largest of the per-round ratios. A change of machine load between
    rounds affects both frames of a round alike, so these vary less between bench runs than
    the ratio of the medians. Empty when the runs were not interleaved."""
    times, base = row.get("_times") or [], base_row.get("_times") or []
    if not (row.get("_interleaved") and base_row.get("_interleaved") and times and
            len(times) == len(base) and all(b > 0 for b in base)):
        return {}
    ratios = [t / b for t, b in zip(times, base)]
    return {"ms_ratio_paired": statistics.median(ratios), "ms_ratio_paired_min": min(ratios),
            "ms_ratio_paired_max": max(ratios)}


def write_csv(rows, path):
    with open(path, "w", newline="", encoding="utf-8") as stream:
        writer = csv.DictWriter(stream, fieldnames=CSV_FIELDS, extrasaction="ignore")
        writer.writeheader()
        for row in rows:
            writer.writerow({k: (_fmt(row[k]) if k in row else "") for k in CSV_FIELDS})


def _fmt(value):
    if isinstance(value, float):
        return "%.6g" % value
    return value


# Each hovr method and the VTK method it is measured against in the demo's headline.
COUNTERPARTS = {"preint1": "stock", "preint2": "stock", "iso-analytic": "iso-stock",
                "mip-analytic": "mip-stock", "minip-analytic": "minip-stock",
                "objectorder": "fixedpoint", "objectorder-point": "fixedpoint"}


def format_headline(rows, step=1.0):
    """One line per dataset and hovr method: its error and time against its VTK counterpart's
    at the same step (``step`` voxels): the ratios a user weighs."""
    lines = ["%-10s %-16s %-12s %10s %10s %9s %9s" % (
        "dataset", "hovr method", "VTK method", "hovr RMSE", "VTK RMSE", "RMSE/VTK",
        "time/VTK")]
    for row in rows:
        other = COUNTERPARTS.get(row["method"])
        if other is None or row["step"] != step:
            continue
        base = next((r for r in rows if r["dataset"] == row["dataset"] and r["method"] == other
                     and r["step"] == step), None)
        if base is None:
            continue
        lines.append("%-10s %-16s %-12s %10.5f %10.5f %9s %9s" % (
            row["dataset"], row["method"], other, row["rmse"], base["rmse"],
            "%.2f" % (row["rmse"] / base["rmse"]) if base["rmse"] > 0 else "-",
            "%.2f" % (row["median_ms"] / base["median_ms"]) if base["median_ms"] > 0 else "-"))
    return "\n".join(lines) + "\n"


def format_summary(rows, skipped=()):
    with_baseline = any("baseline" in row for row in rows)
    lines = ["%-10s %-14s %6s %10s %10s %10s %9s" % ("dataset", "method", "step", "ms/frame",
                                                   "RMSE", "max err", "ms/stock")
             + ("  %-12s %8s %8s %8s" % ("baseline", "ms/base", "rmse/base", "paired")
                if with_baseline else "")]
    for row in rows:
        ratio = row.get("ms_ratio_to_stock")
        line = "%-10s %-14s %6g %10.2f %10.5f %10.4f %9s" % (
            row["dataset"], row["method"], row["step"], row["median_ms"], row["rmse"],
            row["max_error"], "%.2f" % ratio if ratio is not None else "-")
        if with_baseline and "baseline" in row:
            paired = row.get("ms_ratio_paired")
            line += "  %-12s %8.2f %8.2f %8s" % (row["baseline"], row["ms_ratio_to_baseline"],
                                               row["rmse_ratio_to_baseline"],
                                               "%.2f" % paired if paired is not None else "-")
        lines.append(line)
    for name in skipped:
        lines.append("%-10s skipped (data not found)" % name)
    return "\n".join(lines) + "\n"

