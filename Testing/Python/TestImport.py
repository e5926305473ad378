"""hovr imports from the build tree and a CPU pipeline runs: source -> reference -> metrics."""

import hovr
from hovrtesting import Checker, tf_path

c = Checker()
for name in ("vtkPreIntegrationVolumeMapper", "vtkExtensibleGPUVolumeRayCastMapper",
             "vtkFloatRGBARenderCapture", "vtkVolumeReferenceIntegrator",
             "vtkVolumeTransferFunctionSampler", "vtkFirstOrderPreIntegrationTable",
             "vtkCameraRayModel", "vtkRGBAErrorMetrics", "vtkMarschnerLobbSource"):
    c.check(hasattr(hovr, name), "hovr.%s exists" % name)
c.check(hovr.vtkPreIntegrationVolumeMapper.FIRST_ORDER == 1, "integration enumeration wrapped")

from hovr import io as hio  # noqa: E402
from vtkmodules.vtkCommonCore import vtkCommand  # noqa: E402

source = hovr.vtkMarschnerLobbSource()
source.SetDimensions(17, 17, 17)
color, opacity, _ = hio.read_transfer_function(tf_path("marschner-lobb-spikes"))
prop = hio.make_volume_property(color, opacity, 0.05)
reference = hovr.vtkVolumeReferenceIntegrator()
reference.SetInputConnection(source.GetOutputPort())
reference.SetVolumeProperty(prop)
reference.SetCamera(hio.default_camera((-1, 1, -1, 1, -1, 1)))
reference.SetImageSize(24, 20)
progress = []
reference.AddObserver(vtkCommand.ProgressEvent,
                      lambda obj, event: progress.append(obj.GetProgress()))
reference.Update()
image = reference.GetOutput()
c.check(image.GetDimensions() == (24, 20, 1), "reference image size W x H x 1")
rgba = image.GetPointData().GetArray("RGBA")
c.check(rgba is not None and rgba.GetNumberOfComponents() == 4, "RGBA array with 4 components")
c.check(rgba.GetRange(3)[1] > 0.05, "something is visible (max alpha %g)" % rgba.GetRange(3)[1])
c.check(reference.GetNumberOfSamples() > 0, "samples counted")
c.check(progress and progress[-1] == 1.0, "progress events reach 1")

metrics = hovr.vtkRGBAErrorMetrics()
metrics.SetInputData(image)
metrics.SetReferenceData(image)
metrics.Update()
c.check(metrics.GetRMSE() == 0.0 and metrics.GetMaximumError() == 0.0, "self-comparison is 0")
c.finish()
