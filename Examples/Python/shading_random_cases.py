"""Seeded random shaded scenes: how far shaded pre-integration's automatic choice of the arc
clamp (vtkVolumeShadingModel::MinimumCosHalfAngle, 0.5) is from the best of a sweep, and how
non-linear interpolation compares with linear, against the reference with the cone.

Each case: a volume of 3-7 Gaussian blobs (every third with a plane wave added), a random
transfer function of 1-3 opacity peaks, a random unit distance, random Ka/Kd/Ks (summing to
1) and specular power, a random step of 1/2 to 4 voxels.

    ./hovr python Examples/Python/shading_random_cases.py [--cases 12] [--size 64]
"""

import argparse

import numpy
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPiecewiseFunction
from vtkmodules.vtkRenderingCore import vtkColorTransferFunction
from vtkmodules.util.numpy_support import numpy_to_vtk

from hovr import io as hio
from hovr import methods as hm
from hovr import registry as hr

CLAMPS = (0.3, 0.5, 0.7, 0.9, 1.0)  # 1.0: no arc, the linear interpolation


def random_scene(seed, size):
    rng = numpy.random.default_rng(100 + seed)
    g = numpy.linspace(0.0, 1.0, 40)
    z, y, x = numpy.meshgrid(g, g, g, indexing="ij")
    v = numpy.zeros_like(x)
    for _ in range(rng.integers(3, 8)):
        c = rng.uniform(0.2, 0.8, 3)
        s = rng.uniform(0.05, 0.2)
        v += rng.uniform(0.5, 1.0) * numpy.exp(
            -((x - c[0]) ** 2 + (y - c[1]) ** 2 + (z - c[2]) ** 2) / (2 * s * s))
    if seed % 3 == 0:
        v += 0.3 * numpy.sin(rng.uniform(5, 20) * x + rng.uniform(5, 20) * y)
    v = (v - v.min()) / (v.max() - v.min())
    image = vtkImageData()
    image.SetDimensions(40, 40, 40)
    array = numpy_to_vtk(v.astype(numpy.float32).ravel(), deep=True)
    array.SetName("scalars")
    image.GetPointData().SetScalars(array)
    color, opacity = vtkColorTransferFunction(), vtkPiecewiseFunction()
    for k in range(4):
        color.AddRGBPoint(k / 3.0, *rng.uniform(0.2, 1.0, 3))
    opacity.AddPoint(0.0, 0.0)
    for _ in range(rng.integers(1, 4)):
        c, w = rng.uniform(0.2, 0.9), rng.uniform(0.02, 0.2)
        opacity.AddPoint(max(c - w, 0.01), 0.0)
        opacity.AddPoint(c, rng.uniform(0.2, 1.0))
        opacity.AddPoint(min(c + w, 0.99), 0.0)
    prop = hio.make_volume_property(color, opacity, rng.uniform(0.02, 0.5))
    ks = rng.uniform(0.0, 0.5)
    kd = rng.uniform(0.3, 1.0 - ks)
    prop.ShadeOn()
    prop.SetAmbient(1.0 - ks - kd)
    prop.SetDiffuse(kd)
    prop.SetSpecular(ks)
    prop.SetSpecularPower(float(rng.choice([5, 20, 60, 128])))
    step = float(rng.choice([0.5, 1.0, 2.0, 4.0]))
    return hm.Scene(image, prop, hio.default_camera(image.GetBounds()), (size, size)), step


class Clamped(hr.PreIntegrationMethod):
    """Non-linear interpolation with a given arc clamp."""

    def __init__(self, clamp):
        super().__init__("nonlinear-%g" % clamp, "", 1, "nonlinear")
        self.clamp = clamp

    def make_mapper(self):
        mapper = super().make_mapper()
        mapper.GetShadingModel().SetMinimumCosHalfAngle(self.clamp)
        return mapper


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=12)
    parser.add_argument("--size", type=int, default=64)
    args = parser.parse_args()
    renderer = hm.Renderer()
    ratios, gains = [], []
    for seed in range(args.cases):
        scene, step = random_scene(seed, args.size)
        reference = renderer.render("reference-cone", scene, 1.0).image
        errors = [hm.compare(renderer.render(Clamped(c), scene, step).image, reference)[0]["rmse"]
                  for c in CLAMPS]
        linear = hm.compare(renderer.render("preint1-linear", scene, step).image,
                            reference)[0]["rmse"]
        default = errors[CLAMPS.index(0.5)]
        ratios.append(default / min(errors))
        gains.append(default / linear)
        print("case %2d, step %g: %s; linear %.5f; default / best %.3f, default / linear %.3f" % (
            seed, step, " ".join("%g: %.5f" % p for p in zip(CLAMPS, errors)), linear,
            ratios[-1], gains[-1]))
    print("default clamp over the best: median %.3f, worst %.3f; non-linear over linear: median "
          "%.3f, range %.3f-%.3f" % (numpy.median(ratios), max(ratios), numpy.median(gains),
                                      min(gains), max(gains)))
    renderer.close()


if __name__ == "__main__":
    main()
