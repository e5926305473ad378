"""Image regression for every method: the Marschner-Lobb volume with the narrow-spike
transfer function, 128 x 128, rendered by each method of ``hovr render`` and compared with a
baseline PNG (Testing/Data/Baseline/MethodBaseline_<method>.png). Isosurface methods draw
the shaded isosurface 0.5 with the iso-opaque transfer function, projections the spike one;
the reference is drawn in every blend mode (MethodBaseline_reference-<blend>.png).

Parallel-only methods (objectorder) draw the same view in parallel projection. The shaded
variants of first-order pre-integration (preint1-constant, -linear, -nonlinear) draw the
composite scene with --shade's lighting, where their interpolations differ.

Tolerance: the PNGs are 8-bit, so a pixel may differ by 1/255 from rounding alone; llvmpipe
results vary slightly between CPUs, so up to 0.5% of the pixels may differ
by up to 8/255 and none by more. A missing baseline is written and the test fails: that is how
a baseline is made (look at it before committing it).
"""

import os

import numpy
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader

from hovr import io as hio
from hovr import methods as hm
from hovrtesting import Checker, ROOT, marschner_lobb_scene, tf_path

c = Checker()
baselines = os.path.join(ROOT, "Testing", "Data", "Baseline")
out_dir = os.path.join(os.environ.get("HOVR_BUILD", "."), "Testing", "Temporary")
os.makedirs(out_dir, exist_ok=True)
composite = marschner_lobb_scene((128, 128))


def shaded_scene():
    """The composite scene lit as --shade lights it."""
    from hovr import appearance as ha
    color, opacity, _ = hio.read_transfer_function(tf_path("marschner-lobb-spikes"))
    prop = hio.make_volume_property(color, opacity, composite.prop.GetScalarOpacityUnitDistance())
    ha.shade(prop)
    return hm.Scene(composite.image, prop, composite.camera, composite.size)


def blend_scene(blend):
    if blend == "composite":
        return composite
    prop = composite.prop
    if blend == "iso":
        color, opacity, _ = hio.read_transfer_function(tf_path("iso-opaque"))
        prop = hio.make_volume_property(color, opacity, 1.0)
        prop.ShadeOn()
        prop.GetIsoSurfaceValues().SetValue(0, 0.5)
    return hm.Scene(composite.image, prop, composite.camera, composite.size, blend)


runs = [(m, m.name, m.blend) for m in map(hm.get_method, sorted(hm.METHODS)) if m.blend]
runs += [(hm.get_method("reference"), "reference" + ("" if b == "composite" else "-" + b), b)
         for b in hm.BLEND_MODES]
renderer = hm.Renderer()
for method, name, blend in runs:
    scene = shaded_scene() if getattr(method, "interpolation", None) else blend_scene(blend)
    if method.parallel_only:  # the same view in parallel projection
        scene = hm.Scene(scene.image, scene.prop, hio.default_camera(scene.image.GetBounds(),
                                                                     parallel=True),
                         scene.size, scene.blend)
    result = renderer.render(method, scene, 1.0)
    method = name
    test_png = os.path.join(out_dir, "MethodBaseline_%s.png" % method)
    hio.rgba_to_png(result.image, test_png)
    baseline = os.path.join(baselines, "MethodBaseline_%s.png" % method)
    if not os.path.isfile(baseline):
        hio.rgba_to_png(result.image, baseline)
        c.check(False, "%s: no baseline; wrote %s" % (method, baseline))
        continue
    images = []
    for path in (test_png, baseline):
        reader = vtkPNGReader()
        reader.SetFileName(path)
        reader.Update()
        images.append(vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars())
                      .astype(int))
    difference = numpy.abs(images[0] - images[1]).max(axis=1)
    large = (difference > 1).mean()
    print("%-9s max difference %d/255, %.3f%% of pixels above 1/255" % (
        method, difference.max(), 100 * large))
    c.check(difference.max() <= 8 and large <= 0.005,
            "%s matches its baseline (see %s)" % (method, test_png))
renderer.close()
c.finish()
