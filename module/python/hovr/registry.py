"""The rendering methods hovr measures: the Method classes, their registry METHODS and the
blend modes they render.

A method says what it is and how it renders, through hooks the Renderer (hovr.renderer) calls
without knowing the method: ``render`` picks how the method is rendered (drawn in the shared
window, or computed off-screen), ``make_mapper`` / ``make_algorithm`` build what draws or
computes the image, ``count_samples`` and ``statistics`` report its cost. Adding a method
means adding one entry to ``METHODS``.
"""

import math

from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper

from . import hovrRenderingCore as core
from . import hovrRenderingOpenGL as gl
from .io import HovrError


# Blend modes by name, with vtkVolumeMapper's values; the arrays hovr render adds for them.
BLEND_MODES = {"composite": 0, "mip": 1, "minip": 2, "iso": 5}
BLEND_ARRAYS = {"iso": "Depth", "mip": "MaxScalar", "minip": "MinScalar"}
# Gradient interpolations of shaded pre-integration, with vtkVolumeShadingModel's values, and
# the reference's specular terms.
INTERPOLATIONS = {"constant": 0, "linear": 1, "nonlinear": 2}
SPECULAR_MODELS = {"lobe": 0, "cone": 1}
# The cone's slope: the paper's (n) or the one that keeps the lobe's light ((n + 1) / 2).
CONES = {"paper": 0, "matched": 1}
FLOAT_MAX = 3.4028234663852886e38
# Oracle modes of adaptive sampling by name: vtkAdaptiveSamplingOracle's feature tests (the
# paper's opacity gradient, the range-aware default) and its constant oracles.
ORACLE_MODES = {"gradient": 0, "range": 1, "min": 2, "max": 3}
# Settings of adaptive sampling a run may override (scene.adaptive holds the scene's).
ADAPTIVE_SETTINGS = ("lmax", "epsilon", "oracle")
# The GPU adaptive mappers' texture limits (MaximumTextureBytes in MiB, MaximumBrickSize):
# smaller ones split the volume into more bricks and atlas textures.
ATLAS_SETTINGS = ("texture_mib", "brick_points")


class Method:
    """A rendering method: its name, what it is, and how it renders. ``kind`` "gpu": a
    vtkVolumeMapper drawn in the shared window and read back from it (VTK's CPU mappers too);
    "cpu": an image algorithm computed off-screen (``make_algorithm``)."""

    kind = "gpu"
    uses_step = True
    parallel_only = False  # renders parallel projections only (an error for perspective)
    description = ""
    blend = "composite"  # the blend mode the method renders; None: any (the reference)
    threads = 0  # the thread count it is pinned to; 0: the default
    settings_names = ()  # the settings a bench run may give the method (``variant``)
    overrides = {}  # this variant's settings

    def __init__(self, name, description):
        self.name = name
        self.description = description

    def variant(self, settings):
        """A copy of this method with settings of its own (names in ``settings_names``),
        named after them, e.g. ``adaptive-cpu(lmax=2)``."""
        if not self.settings_names:
            raise HovrError("method %s takes no settings" % self.name)
        unknown = sorted(set(settings) - set(self.settings_names))
        if unknown:
            raise HovrError("unknown setting(s) %s of %s (known: %s)" % (
                ", ".join(unknown), self.name, ", ".join(self.settings_names)))
        copy = type(self).__new__(type(self))
        copy.__dict__.update(self.__dict__)
        copy.overrides = dict(self.overrides, **settings)
        copy.name = "%s(%s)" % (self.name, ",".join(
            "%s=%s" % (k, copy.overrides[k]) for k in self.settings_names
            if k in copy.overrides))
        return copy

    def render(self, renderer, scene, step, repeat):
        """Render ``scene`` through ``renderer`` (a hovr.renderer.Renderer): drawn in its
        window, alone in the interleaved rounds."""
        return renderer.render_interleaved([(self, step)], scene, repeat)[0]

    def make_mapper(self):
        """The vtkVolumeMapper that draws the method in the window; None for a method that
        computes its image off-screen."""
        raise NotImplementedError

    def make_algorithm(self, scene):
        """The image algorithm, set up for ``scene``, that computes the method's image
        off-screen and counts its samples (GetNumberOfSamples)."""
        raise NotImplementedError

    def configure(self, target, scene):
        """Set up the mapper or algorithm made for ``scene`` with what the scene asks beyond
        the volume and its property (scene.shading)."""

    def check_scene(self, scene):
        """Raise HovrError when the method cannot draw ``scene`` right. Every method but the
        reference stores the volume in float (GPU textures, the CPU casters' copies)."""
        low, high = scene.image.GetPointData().GetScalars().GetFiniteRange()
        if max(abs(low), abs(high)) > FLOAT_MAX:
            raise HovrError("the scalar range [%g, %g] exceeds float range, in which %s stores "
                            "the volume; rescale the values" % (low, high, self.name))

    def check_context(self, window, scene):
        """Raise HovrError when the method cannot draw ``scene`` in the OpenGL context of
        ``window`` (a rendered vtkOpenGLRenderWindow)."""

    def count_samples(self, rays, scene, step):
        """The samples a frame takes along ``rays`` (a prepared vtkCameraRayModel of the
        scene): one every ``step`` voxels inside the volume."""
        return rays.CountFixedStepSamples(scene.image, scene.step_length(step))

    def algorithm_samples(self, algorithm):
        """The samples the image algorithm (``make_algorithm``) took in its last update."""
        return algorithm.GetNumberOfSamples()

    def statistics(self, mapper):
        """What the mapper (or the algorithm) reports after a frame, for the result's row."""
        return {}

    def count_operations(self, mapper, draw):
        """Counts that cost a frame of their own (a GPU counter read back): switch counting
        on, ``draw()`` once, read, switch it off; a dict for the result's row."""
        return {}

    def set_threads(self, mapper, threads):
        """Run on ``threads`` threads (0: the default): vtkSMPTools' count."""
        from vtkmodules.vtkCommonCore import vtkSMPTools
        vtkSMPTools.Initialize(threads)


class ThreadedMethod(Method):
    """A method pinned to a number of threads, named ``<method>/<threads>t``."""

    def __init__(self, method, threads):
        super().__init__("%s/%dt" % (method.name, threads), method.description)
        self.method = method
        self.threads = threads
        for attribute in ("kind", "uses_step", "parallel_only", "blend"):
            setattr(self, attribute, getattr(method, attribute))

    def render(self, renderer, scene, step, repeat):
        # The wrapped method's way of rendering, run as this method: with its name and threads.
        return type(self.method).render(self, renderer, scene, step, repeat)

    def make_mapper(self):
        return self.method.make_mapper()

    def make_algorithm(self, scene):
        return self.method.make_algorithm(scene)

    def configure(self, target, scene):
        self.method.configure(target, scene)

    def statistics(self, mapper):
        return self.method.statistics(mapper)

    def check_scene(self, scene):
        self.method.check_scene(scene)

    def check_context(self, window, scene):
        self.method.check_context(window, scene)

    def count_samples(self, rays, scene, step):
        return self.method.count_samples(rays, scene, step)

    def algorithm_samples(self, algorithm):
        return self.method.algorithm_samples(algorithm)

    def count_operations(self, mapper, draw):
        return self.method.count_operations(mapper, draw)

    def set_threads(self, mapper, threads):
        self.method.set_threads(mapper, threads)


class StockMethod(Method):
    # hovr's mappers hold no texture over this (their MaximumTextureBytes): OpenGL
    # implementations accept larger ones and read them wrongly.
    TEXTURE_BYTES = 2**30

    def make_mapper(self):
        mapper = vtkOpenGLGPUVolumeRayCastMapper()
        mapper.SetAutoAdjustSampleDistances(0)
        return mapper

    def check_context(self, window, scene):
        """VTK 9.1's mapper draws nothing, with log lines but no error, from a volume texture
        it cannot create; its partitions misplace each block's texels. Refuse such volumes."""
        from vtkmodules.vtkRenderingOpenGL2 import vtkTextureObject
        dims = scene.image.GetDimensions()
        largest = vtkTextureObject.GetMaximumTextureSize3D(window)
        scalars = scene.image.GetPointData().GetScalars()
        # VTK uploads 64-bit types as 32-bit floats.
        size = min(scalars.GetDataTypeSize(), 4) * scalars.GetNumberOfComponents()
        texture = float(size) * dims[0] * dims[1] * dims[2]
        if largest > 0 and max(dims) > largest:
            raise HovrError("%s cannot draw a volume of %d x %d x %d points: VTK's mapper needs "
                            "one 3D texture and this OpenGL holds at most %d points a side; "
                            "hovr's GPU methods draw it in bricks" % ((self.name,) + dims +
                                                                      (largest,)))
        if texture > self.TEXTURE_BYTES:
            raise HovrError("%s cannot draw a volume of %d x %d x %d points: VTK's mapper needs "
                            "one 3D texture of %.0f MiB, over the %d MiB a texture may safely "
                            "take; hovr's GPU methods draw it in bricks" % (
                                (self.name,) + dims + (texture / 2**20,
                                                       self.TEXTURE_BYTES // 2**20)))


class PreIntegrationMethod(Method):
    """vtkPreIntegrationVolumeMapper; ``interpolation`` fixes the gradient interpolation of
    shaded frames (None: the scene's). Setting ``table_memory_mib``: the mapper's
    TableMemoryLimit in MiB (default 64)."""

    settings_names = ("table_memory_mib",)

    def __init__(self, name, description, integration, interpolation=None):
        super().__init__(name, description)
        self.integration = integration
        self.interpolation = interpolation

    def make_mapper(self):
        mapper = gl.vtkPreIntegrationVolumeMapper()
        mapper.SetIntegration(self.integration)
        return mapper

    def configure(self, target, scene):
        target.SetGradientInterpolation(
            INTERPOLATIONS[self.interpolation or scene.shading["interpolation"]])
        target.SetGooch(bool(scene.shading["gooch"]))
        target.SetNormalArrayName(scene.shading.get("normals") or None)
        target.GetShadingModel().SetSpecularCone(CONES[scene.shading.get("cone") or "paper"])
        if "table_memory_mib" in self.overrides:
            mib = self.overrides["table_memory_mib"]
            if not (isinstance(mib, (int, float)) and 0 < mib < 1e6):
                raise HovrError("table_memory_mib must be a positive number of MiB, got %r"
                                % (mib,))
            target.SetTableMemoryLimit(float(mib) * 2.0**20)

    def statistics(self, mapper):
        table = mapper.GetActiveTable()
        sizes = [table.GetTableSize(), table.GetChordSize(), table.GetDeviationSize()]
        sizer = mapper.GetTableSizer()
        return {"table_size": "x".join(str(v) for v in sizes[:3 if self.integration == 2 else 2]),
                "table_sizing_ms": 1000.0 * sizer.GetLastChooseTime()
                if mapper.GetTableSize() == 0 else 0.0,
                "table_build_ms": 1000.0 * mapper.GetLastTableBuildTime(),
                "table_on_gpu": bool(mapper.GetLastTableBuiltOnGPU()),
                "table_builds": table.GetBuildCount(),
                "table_gpu_bytes": mapper.GetTableTextureMemorySize(),
                "volume_gpu_bytes": mapper.GetBrickTextureMemorySize(),
                "normal_gpu_bytes": mapper.GetNormalTextureMemorySize()}


class AnalyticMethod(Method):
    """vtkAnalyticVolumeMapper: analytic (exact) or VTK's stock isosurface and projections."""

    def __init__(self, name, description, blend, analytic):
        super().__init__(name, description)
        self.blend = blend
        self.analytic = analytic

    def make_mapper(self):
        mapper = gl.vtkAnalyticVolumeMapper()
        mapper.SetMethod(mapper.ANALYTIC if self.analytic else mapper.STOCK)
        mapper.SetBlendMode(BLEND_MODES[self.blend])
        mapper.SetAutoAdjustSampleDistances(0)
        return mapper

    def count_samples(self, rays, scene, step):
        """The analytic mappers visit cells instead of sampling: the cells the rays cross."""
        if not self.analytic:
            return super().count_samples(rays, scene, step)
        return rays.CountCellVisits(scene.image)

    def statistics(self, mapper):
        if not self.analytic:
            return {}
        return {"block_gpu_bytes": mapper.GetBlockTextureMemorySize(),
                "corner_gpu_bytes": mapper.GetCornerTextureMemorySize(),
                "volume_gpu_bytes": mapper.GetBrickTextureMemorySize()}


class FixedPointMethod(Method):
    """VTK's CPU ray caster, drawn in the window like the GPU mappers."""

    def make_mapper(self):
        from vtkmodules.vtkRenderingVolume import vtkFixedPointVolumeRayCastMapper
        mapper = vtkFixedPointVolumeRayCastMapper()
        mapper.SetAutoAdjustSampleDistances(0)
        mapper.SetLockSampleDistanceToInputSpacing(0)
        mapper.SetImageSampleDistance(1.0)
        return mapper

    def check_scene(self, scene):
        super().check_scene(scene)
        # Its integer copy of the volume turns NaN into arbitrary values.
        if any("NaN" in warning for warning in scene.warnings):
            raise HovrError("%s cannot render NaN values (VTK's CPU ray caster maps them to "
                            "arbitrary ones); replace them by a value the transfer function "
                            "makes transparent" % self.name)

    def set_threads(self, mapper, threads):
        import os
        mapper.SetNumberOfThreads(threads or os.cpu_count() or 1)


class ReferenceMethod(Method):
    """vtkVolumeReferenceIntegrator: the ground truth, computed off-screen in double for any
    blend mode, with a step of its own. Shaded composite scenes are lit by the scene's lights
    (by default a white headlight, as VTK) with the specular term ``specular`` ("lobe", VTK's, or "cone"; None: the scene's).
    Settings ``pixel_fraction`` and ``pixel_seed``: integrate a random sample of the pixels
    only (the others NaN, left out of the measures), for large volumes."""

    kind = "cpu"
    uses_step = False
    blend = None
    settings_names = ("pixel_fraction", "pixel_seed")

    def __init__(self, name, description, specular=None):
        super().__init__(name, description)
        self.specular = specular

    def configure(self, target, scene):
        fraction = self.overrides.get("pixel_fraction", 1.0)
        if not (isinstance(fraction, (int, float)) and 0.0 < fraction <= 1.0):
            raise HovrError("pixel_fraction must be in (0, 1], got %r" % (fraction,))
        target.SetPixelFraction(float(fraction))
        target.SetPixelSeed(int(self.overrides.get("pixel_seed", 1)))
        if not scene.prop.GetShade():
            return
        model = core.vtkVolumeShadingModel()
        model.SetFromProperty(scene.prop)
        lights = scene.shading.get("lights") or [((0.0, 0.0, 1.0), (1.0, 1.0, 1.0),
                                                   (1.0, 1.0, 1.0), True)]
        for direction, diffuse, specular, headlight in lights:
            model.AddLight(direction, diffuse, specular, headlight)
        model.SetSpecularModel(SPECULAR_MODELS[self.specular or scene.shading["specular"]])
        model.SetGooch(bool(scene.shading["gooch"]))
        model.SetSpecularCone(CONES[scene.shading.get("cone") or "paper"])
        target.SetShadingModel(model)
        target.SetNormalArrayName(scene.shading.get("normals") or None)

    def render(self, renderer, scene, step, repeat):
        return renderer.render_offline(self, scene, step, repeat)

    def make_mapper(self):
        return None  # it computes its image off-screen

    def make_algorithm(self, scene):
        integrator = core.vtkVolumeReferenceIntegrator()
        integrator.SetBlendMode(BLEND_MODES[scene.blend])
        integrator.SetInputData(scene.image)
        integrator.SetVolumeProperty(scene.prop)
        integrator.SetCamera(scene.camera)
        integrator.SetImageSize(*scene.size)
        return integrator

    def check_scene(self, scene):
        pass  # integrates in double


class ObjectOrderMethod(Method):
    """vtkObjectOrderVolumeMapper: object-order ray casting on the CPU (parallel projection),
    drawn in the window like VTK's CPU mapper."""

    parallel_only = True

    def __init__(self, name, description, classification):
        super().__init__(name, description)
        self.classification = classification

    def make_mapper(self):
        mapper = gl.vtkObjectOrderVolumeMapper()
        mapper.GetCaster().SetClassification(self.classification)
        return mapper

    def statistics(self, mapper):
        caster = mapper.GetCaster()
        in_view = caster.ComputeNonTransparentCells()

        def occluded(rendered):
            return 1.0 - rendered / in_view if in_view > 0 else 0.0

        rendered = caster.GetNumberOfNonTransparentCells()
        stats = {"samples_per_frame": caster.GetNumberOfSamples(),
                 "nontransparent_cells": rendered,
                 "occluded_ratio": occluded(rendered),
                 "octree_nodes": caster.GetNumberOfNodesVisited(),
                 "cpu_bytes": caster.GetMemorySize(),
                 "instruction_set": {caster.INSTRUCTIONS_SSE2: "sse2",
                                     caster.INSTRUCTIONS_AVX2: "avx2"}.get(
                     caster.GetLastInstructionSet(), "")}
        # The same frame with every ray stopped at its first non-negligible opacity (the
        # smallest threshold, 1e-3): the cells seen first along the rays must be rendered by
        # any method, so this bounds the occluded ratio for the scene's geometry. Restoring
        # the threshold marks the caster modified: the mapper's next frame renders anew.
        threshold = caster.GetOpacityThreshold()
        caster.SetOpacityThreshold(1e-3)
        caster.Update()
        stats["occluded_ratio_first_hit"] = occluded(caster.GetNumberOfNonTransparentCells())
        caster.SetOpacityThreshold(threshold)
        return stats


class AdaptiveMethod(Method):
    """Adaptive sampling driven by an oracle volume (vtkAdaptiveSamplingOracle on the scene's
    volume and opacity): the settings are the scene's (scene.adaptive: "lmax", "epsilon",
    "oracle") unless the method is a variant with its own (``variant``)."""

    settings_names = ADAPTIVE_SETTINGS

    def settings(self, scene):
        values = dict(scene.adaptive, **self.overrides)
        if not (isinstance(values["lmax"], int) and 0 <= values["lmax"] <= 8):
            raise HovrError("lmax must be an integer in [0, 8], got %r" % (values["lmax"],))
        if values["oracle"] not in ORACLE_MODES:
            raise HovrError("unknown oracle mode %r (known: %s)" % (
                values["oracle"], ", ".join(ORACLE_MODES)))
        if not (values["epsilon"] >= 0 and math.isfinite(values["epsilon"])):
            raise HovrError("the oracle epsilon must be finite and >= 0, got %r" % (
                values["epsilon"],))
        return values

    def count_samples(self, rays, scene, step):
        """Unknown from the rays alone: the mappers count their own (count_operations)."""
        return None

    def configure(self, target, scene):
        """The settings, on any of the three adaptive classes (same setter names)."""
        values = self.settings(scene)
        if values.get("texture_mib"):
            target.SetMaximumTextureBytes(int(values["texture_mib"] * 2**20))
        if values.get("brick_points"):
            target.SetMaximumBrickSize(int(values["brick_points"]))
        target.SetMaximumLevel(values["lmax"])
        array = self.oracle_array(scene)
        if array is None:
            target.SetOracleModeToMinimum()
        else:
            target.SetOracleModeToArray()
            target.SetOracleArrayName(array)

    def oracle_array(self, scene):
        """The name of the scene volume's oracle array for this method's settings, computed
        on first use (None for the "min" oracle, which the renderers know without an array)."""
        values = self.settings(scene)
        if values["oracle"] == "min":
            return None
        from .bench import add_oracle
        return add_oracle(scene, values["oracle"], values["epsilon"])


class AdaptivePyramidCPUMethod(AdaptiveMethod):
    """vtkAdaptiveSamplingRayCaster: the slice pyramid on the CPU, in double (the
    specification of the GPU pyramid), counting its operations. Its step is the distance
    between neighbouring rays, set by the camera and the image size, not by --step."""

    kind = "cpu"
    uses_step = False
    parallel_only = True

    def render(self, renderer, scene, step, repeat):
        return renderer.render_offline(self, scene, step, repeat)

    def make_mapper(self):
        return None  # it computes its image off-screen

    def make_algorithm(self, scene):
        caster = core.vtkAdaptiveSamplingRayCaster()
        caster.SetInputData(scene.image)
        caster.SetVolumeProperty(scene.prop)
        caster.SetCamera(scene.camera)
        caster.SetImageSize(*scene.size)
        return caster

    def algorithm_samples(self, algorithm):
        return algorithm.GetNumberOfSampleOperations()

    def statistics(self, caster):
        full = caster.GetFullRateSampleOperations()
        spacing = min(abs(s) for s in caster.GetInput().GetSpacing())
        return {"sample_ops": caster.GetNumberOfSampleOperations(),
                "synthesis_ops": caster.GetNumberOfSynthesisOperations(),
                "accumulate_ops": caster.GetNumberOfAccumulateOperations(),
                "boundary_sample_ops": caster.GetNumberOfBoundarySampleOperations(),
                "full_rate_samples": full,
                "sample_ratio_to_full": caster.GetNumberOfSampleOperations() / full
                if full > 0 else float("nan"),
                "slice_spacing_voxels": caster.GetSliceSpacing() / spacing}


class AdaptiveRayMethod(AdaptiveMethod):
    """vtkAdaptiveRayVolumeMapper: first-order pre-integration in VTK's ray caster whose
    samples skip along each ray as the oracle allows (the paper's Sec. 3.1 alone), on a global
    slice grid of the step; perspective too. ``tricubic``: the volume reconstructed by the
    cubic B-spline from 8 trilinear fetches per sample (an expensive sampler, where skipping
    pays most)."""

    settings_names = ADAPTIVE_SETTINGS + ATLAS_SETTINGS

    def __init__(self, name, description, tricubic=False):
        super().__init__(name, description)
        self.tricubic = tricubic

    def make_mapper(self):
        mapper = gl.vtkAdaptiveRayVolumeMapper()
        if self.tricubic:
            mapper.SetReconstructionToTricubicBSpline()
        return mapper

    def count_operations(self, mapper, draw):
        mapper.CountSamplesOn()
        draw()
        count = mapper.GetLastFrameSampleCount()
        mapper.CountSamplesOff()
        return {"sample_ops": count} if count >= 0 else {}

    def statistics(self, mapper):
        return {"table_size": "%dx%dx%d" % (mapper.GetEffectiveTableSize(),
                                            mapper.GetEffectiveTableSize(),
                                            mapper.GetNumberOfTables()),
                "table_build_ms": 1000.0 * mapper.GetLastTableBuildTime(),
                "table_gpu_bytes": mapper.GetTableTextureMemorySize(),
                "volume_gpu_bytes": mapper.GetBrickTextureMemorySize(),
                "oracle_gpu_bytes": mapper.GetOracleTextureMemorySize(),
                "volume_bricks": mapper.GetNumberOfBricks(),
                "volume_textures": mapper.GetNumberOfBrickTextures()}


class AdaptivePyramidMethod(AdaptiveMethod):
    """vtkAdaptiveSamplingVolumeMapper: the slice pyramid on the GPU (parallel projection);
    its step is the distance between neighbouring rays, set by the camera and the image
    size."""

    uses_step = False
    parallel_only = True
    settings_names = ADAPTIVE_SETTINGS + ATLAS_SETTINGS

    def make_mapper(self):
        return gl.vtkAdaptiveSamplingVolumeMapper()

    def count_operations(self, mapper, draw):
        mapper.CountOperationsOn()
        draw()
        stats = {"sample_ops": mapper.GetLastFrameSampleOperations(),
                 "synthesis_ops": mapper.GetLastFrameSynthesisOperations(),
                 "accumulate_ops": mapper.GetLastFrameAccumulateOperations(),
                 "boundary_sample_ops": mapper.GetLastFrameBoundarySampleOperations(),
                 "full_rate_samples": mapper.GetLastFrameFullRateSampleOperations()}
        mapper.CountOperationsOff()
        if stats["sample_ops"] < 0:
            return {}
        full = stats["full_rate_samples"]
        stats["sample_ratio_to_full"] = stats["sample_ops"] / full if full > 0 else float("nan")
        return stats

    def statistics(self, mapper):
        spacing = min(abs(s) for s in mapper.GetInput().GetSpacing())
        return {"slice_spacing_voxels": mapper.GetSliceSpacing() / spacing,
                "passes_per_frame": mapper.GetLastFramePasses(),
                "volume_gpu_bytes": mapper.GetBrickTextureMemorySize(),
                "oracle_gpu_bytes": mapper.GetOracleTextureMemorySize(),
                "volume_bricks": mapper.GetNumberOfBricks(),
                "volume_textures": mapper.GetNumberOfBrickTextures()}


METHODS = {m.name: m for m in (
    ReferenceMethod("reference", "CPU ground truth: exact cubic per cell, adaptive pieces "
                                 "(vtkVolumeReferenceIntegrator)"),
    ReferenceMethod("reference-cone", "the ground truth of shaded volumes with the cone "
                    "specular term that shaded pre-integration uses", "cone"),
    StockMethod("stock", "VTK's vtkOpenGLGPUVolumeRayCastMapper, composite, unchanged"),
    PreIntegrationMethod("preint1", "first-order pre-integration, 2D table "
                                    "(vtkPreIntegrationVolumeMapper)",
                         gl.vtkPreIntegrationVolumeMapper.FIRST_ORDER),
    PreIntegrationMethod("preint1-constant", "shaded first-order pre-integration, one normal "
                         "per segment: the average of its ends'", gl.vtkPreIntegrationVolumeMapper.FIRST_ORDER,
                         "constant"),
    PreIntegrationMethod("preint1-linear", "shaded first-order pre-integration, endpoint "
                         "shading faded linearly (Lum et al.)",
                         gl.vtkPreIntegrationVolumeMapper.FIRST_ORDER, "linear"),
    PreIntegrationMethod("preint1-nonlinear", "shaded first-order pre-integration, normals "
                         "along the arc (Guetat et al.)",
                         gl.vtkPreIntegrationVolumeMapper.FIRST_ORDER, "nonlinear"),
    PreIntegrationMethod("preint2", "second-order pre-integration, 3D table over (front, "
                                    "middle, back) (vtkPreIntegrationVolumeMapper)",
                         gl.vtkPreIntegrationVolumeMapper.SECOND_ORDER),
    AnalyticMethod("iso-analytic", "exact first hit of the trilinear isosurface, integer "
                   "traversal, cubic per cell (vtkAnalyticVolumeMapper)", "iso", True),
    AnalyticMethod("mip-analytic", "exact maximum intensity projection of the trilinear field "
                   "(vtkAnalyticVolumeMapper)", "mip", True),
    AnalyticMethod("minip-analytic", "exact minimum intensity projection of the trilinear "
                   "field (vtkAnalyticVolumeMapper)", "minip", True),
    AnalyticMethod("iso-stock", "VTK's sampled isosurface (ISOSURFACE_BLEND) at the step",
                   "iso", False),
    AnalyticMethod("mip-stock", "VTK's sampled maximum intensity projection at the step",
                   "mip", False),
    AnalyticMethod("minip-stock", "VTK's sampled minimum intensity projection at the step",
                   "minip", False),
    ObjectOrderMethod("objectorder", "object-order ray casting on the CPU: min-max octree, "
                      "hidden volume removal, pre-integrated segments, parallel projection "
                      "(vtkObjectOrderVolumeMapper)", core.vtkObjectOrderRayCaster.PREINTEGRATED),
    ObjectOrderMethod("objectorder-point", "object-order ray casting with the paper's "
                      "point-sampled classification (vtkObjectOrderVolumeMapper)",
                      core.vtkObjectOrderRayCaster.POINT_SAMPLED),
    FixedPointMethod("fixedpoint", "VTK's CPU ray caster (vtkFixedPointVolumeRayCastMapper)"),
    AdaptiveRayMethod("adaptive-ray", "adaptive sampling along each ray: first-order "
                      "pre-integration that skips samples as the oracle allows, on a global "
                      "slice grid of the step (vtkAdaptiveRayVolumeMapper)"),
    AdaptiveRayMethod("adaptive-ray-tricubic", "adaptive-ray with the volume reconstructed "
                      "by the cubic B-spline (8 trilinear fetches a sample); its full rate is "
                      "oracle min", tricubic=True),
    AdaptivePyramidMethod("adaptive-3d", "adaptive sampling in three dimensions on the GPU: "
                          "the oracle's slice pyramid, one slice per ray spacing, parallel "
                          "projection (vtkAdaptiveSamplingVolumeMapper)"),
    AdaptivePyramidCPUMethod("adaptive-cpu", "adaptive sampling in three dimensions on the "
                             "CPU: the oracle's slice pyramid, one slice per ray spacing, "
                             "parallel projection (vtkAdaptiveSamplingRayCaster)"),
)}


def get_method(name, threads=None, settings=None):
    """The method of that name; with ``threads``, pinned to that many threads; with
    ``settings`` (a dict), the method's variant with those settings (``Method.variant``)."""
    if name not in METHODS:
        raise HovrError("unknown method %r (known: %s)" % (name, ", ".join(METHODS)))
    method = METHODS[name]
    if settings:
        method = method.variant(settings)
    if threads is None:
        return method
    if not (isinstance(threads, int) and threads >= 1):
        raise HovrError("the thread count must be a positive integer, got %r" % (threads,))
    return ThreadedMethod(method, threads)
