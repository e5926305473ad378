"""``hovr tables``: build times of the second-order table on the CPU and the GPU.

For each table size n and cap of integration steps, the 3D table of a transfer function (n
entries on each axis: chord centres, chords and deviations over the whole range, as
``vtkPreIntegrationVolumeMapper::SetTableSize(n)`` gives) is built with
vtkSecondOrderPreIntegrationTable (CPU, vtkSMPTools) and with
vtkOpenGLPreIntegrationTableBuilder (a render pass writing the 3D texture), and the median
wall time of a few builds is reported; the CPU and GPU tables are compared. The paper
(El Hajjar et al., Figure 6) reports 165 s (CPU) and 2.74 s (GPU) for 256^3 with 64
iterations.
"""

import csv
import statistics
import time

from vtkmodules.vtkRenderingCore import vtkRenderWindow
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
from vtkmodules.vtkRenderingOpenGL2 import vtkTextureObject
from vtkmodules.vtkCommonCore import vtkFloatArray

from . import hovrRenderingCore as core
from . import hovrRenderingOpenGL as gl
from . import io as hio

GL_RGBA16F = 0x881A
GL_RGBA32F = 0x8814


def measure(tf_path, sizes, iterations, repeat=3, slab_length=4.0, unit=1.0, scalar_range=(0, 255),
            gpu=True, log=print):
    color, opacity, _ = hio.read_transfer_function(tf_path)
    prop = hio.make_volume_property(color, opacity, unit)
    window = None
    if gpu:
        window = vtkRenderWindow()
        window.SetOffScreenRendering(1)
        window.SetSize(8, 8)
        window.Initialize()
        window.MakeCurrent()
    rows = []
    for n in sizes:
        for steps in iterations:
            table = core.vtkSecondOrderPreIntegrationTable()
            table.SetVolumeProperty(prop)
            table.SetScalarRange(*scalar_range)
            table.SetTableSize(n)
            table.SetChordSize(n)
            table.SetDeviationSize(n)
            table.SetIterations(steps)
            table.SetSegmentLength(slab_length)
            cpu_times = []
            for r in range(repeat):
                table.SetSegmentLength(slab_length * (1.0 + 1e-9 * r))  # force a rebuild
                start = time.perf_counter()
                table.Update()
                cpu_times.append(time.perf_counter() - start)
            row = {"size": n, "iterations": steps, "cpu_s": statistics.median(cpu_times),
                   "cpu_mib": n ** 3 * 16 / 2 ** 20}
            if window is not None:
                builder = gl.vtkOpenGLPreIntegrationTableBuilder()
                texture = vtkTextureObject()
                reference = vtkFloatArray()
                reference.DeepCopy(table.GetTable())
                table.SetComputeEntries(False)
                gpu_times = []
                for r in range(repeat):
                    table.SetSegmentLength(slab_length * (1.0 + 1e-9 * (r + repeat)))
                    table.Update()
                    if not builder.Build(window, table, texture, GL_RGBA32F):
                        break
                    gpu_times.append(builder.GetLastBuildTime())
                if gpu_times:
                    row["gpu_s"] = statistics.median(gpu_times[1:] or gpu_times)
                    # Compare with a CPU table of the same last settings.
                    table.SetComputeEntries(True)
                    table.Update()
                    built = vtkFloatArray()
                    builder.DownloadTable(texture, built)
                    import numpy
                    from vtkmodules.util.numpy_support import vtk_to_numpy
                    row["max_abs_difference"] = float(numpy.abs(
                        vtk_to_numpy(built) - vtk_to_numpy(table.GetTable())).max())
                texture.ReleaseGraphicsResources(window)
            rows.append(row)
            log("%4d^3 x %4d iterations: CPU %.3f s%s" % (
                n, steps, row["cpu_s"], (", GPU %.3f s, max |GPU - CPU| %.2g" % (
                    row["gpu_s"], row["max_abs_difference"])) if "gpu_s" in row else ""))
    if window is not None:
        window.Finalize()
    return rows


def write_csv(rows, path):
    fields = ["size", "iterations", "cpu_s", "gpu_s", "max_abs_difference", "cpu_mib"]
    with open(path, "w", newline="", encoding="utf-8") as stream:
        writer = csv.DictWriter(stream, fieldnames=fields, extrasaction="ignore")
        writer.writeheader()
        for row in rows:
            writer.writerow(row)
