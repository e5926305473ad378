"""Render the Marschner-Lobb volume with first- and second-order pre-integration and measure.

A plain VTK pipeline: hovr's vtkPreIntegrationVolumeMapper replaces vtkGPUVolumeRayCastMapper,
everything else (volume property, renderer, camera) is VTK's. The float capture and the
reference integrator then give the error of the image, next to VTK's stock mapper at the same
step.

    ./hovr python Examples/Python/preintegrated_volume.py [--output image.png] [--step 1]
"""

import argparse

from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPiecewiseFunction
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkRenderingCore import (vtkColorTransferFunction, vtkRenderer,
                                         vtkRenderWindow, vtkVolume, vtkVolumeProperty,
                                         vtkWindowToImageFilter)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (OpenGL window factory)
import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401
from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper

import hovr

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--output", default="preintegrated_volume.png")
parser.add_argument("--step", type=float, default=1.0, help="step in voxels")
parser.add_argument("--size", type=int, default=400)
args = parser.parse_args()

# The volume: the Marschner-Lobb test signal on [-1, 1]^3, 41^3 points.
source = hovr.vtkMarschnerLobbSource()
source.SetDimensions(41, 41, 41)
source.Update()
spacing = source.GetOutput().GetSpacing()[0]

# Transfer functions with three narrow opacity spikes: hard for point sampling.
color = vtkColorTransferFunction()
color.AddRGBPoint(0.0, 0.2, 0.3, 1.0)
color.AddRGBPoint(0.5, 0.1, 0.9, 0.3)
color.AddRGBPoint(1.0, 1.0, 0.1, 0.1)
opacity = vtkPiecewiseFunction()
for centre, peak in ((0.25, 0.5), (0.5, 0.7), (0.75, 0.9)):
    opacity.AddPoint(centre - 0.02, 0.0)
    opacity.AddPoint(centre, peak)
    opacity.AddPoint(centre + 0.02, 0.0)
prop = vtkVolumeProperty()
prop.SetColor(color)
prop.SetScalarOpacity(opacity)
prop.SetScalarOpacityUnitDistance(0.05)
prop.SetInterpolationTypeToLinear()

window = vtkRenderWindow()
window.SetOffScreenRendering(1)
window.SetMultiSamples(0)
window.SetSize(args.size, args.size)
renderer = vtkRenderer()
renderer.SetBackground(0, 0, 0)
renderer.SetBackgroundAlpha(0)
window.AddRenderer(renderer)
camera = renderer.GetActiveCamera()
camera.SetPosition(2.5, -4.0, 2.2)
camera.SetFocalPoint(0, 0, 0)
camera.SetViewUp(0, 0, 1)
camera.SetViewAngle(30)

# Float colour buffer, so errors of 1e-3 can be measured (8 bits would hide them).
capture = hovr.vtkFloatRGBARenderCapture()
capture.Attach(window)

# Ground truth for this camera and image size.
reference = hovr.vtkVolumeReferenceIntegrator()
reference.SetInputConnection(source.GetOutputPort())
reference.SetVolumeProperty(prop)
reference.SetCamera(camera)
reference.SetImageSize(args.size, args.size)
reference.Update()


def render(mapper):
    mapper.SetInputConnection(source.GetOutputPort())
    mapper.SetAutoAdjustSampleDistances(0)
    mapper.SetSampleDistance(args.step * spacing)
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    renderer.RemoveAllViewProps()
    renderer.AddVolume(volume)
    renderer.ResetCameraClippingRange()
    window.Render()
    image = vtkImageData()
    capture.Capture(image)
    metrics = hovr.vtkRGBAErrorMetrics()
    metrics.SetInputData(image)
    metrics.SetReferenceConnection(reference.GetOutputPort())
    metrics.Update()
    return metrics.GetRMSE()


stock_rmse = render(vtkOpenGLGPUVolumeRayCastMapper())
preint = hovr.vtkPreIntegrationVolumeMapper()
preint_rmse = render(preint)
first = preint.GetFirstOrderTable()
second_order = hovr.vtkPreIntegrationVolumeMapper()
second_order.SetIntegrationToSecondOrder()
second_rmse = render(second_order)
second = second_order.GetSecondOrderTable()
print("step %g voxel: RMSE stock %.5f, first-order pre-integration %.5f, second-order "
      "pre-integration %.5f" % (args.step, stock_rmse, preint_rmse, second_rmse))
print("tables: %d^2 built in %.1f ms, %d^3 built in %.1f ms on the %s (%.1f MB on the GPU)" % (
    first.GetTableSize(), 1000 * preint.GetLastTableBuildTime(), second.GetTableSize(),
    1000 * second_order.GetLastTableBuildTime(),
    "GPU" if second_order.GetLastTableBuiltOnGPU() else "CPU",
    second_order.GetTableTextureMemorySize() / 1e6))

grab = vtkWindowToImageFilter()
grab.SetInput(window)
grab.ReadFrontBufferOff()
writer = vtkPNGWriter()
writer.SetFileName(args.output)
writer.SetInputConnection(grab.GetOutputPort())
writer.Write()
print("wrote", args.output)
