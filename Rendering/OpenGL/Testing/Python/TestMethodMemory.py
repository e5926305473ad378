"""What each GPU method holds for a volume of N points, as docs/methods.md ("Memory") states it.

GPU: after one frame, the bytes of each texture a method makes (the mapper's own counters,
which add up the sizes of the textures it created) on a Marschner-Lobb volume of 97 x 81 x 66
points (no axis a multiple of another) stored as uint8, uint16 and float32:
- in one brick, the volume's texture is exactly b' N bytes, uploaded once over three frames, b' the bytes per texel the
  documentation gives (the data's own size, 8-bit data as 16-bit texels where the method
  filters it); the oracle of the adaptive methods 4 N; the pre-integration table within its
  memory limit;
- in bricks of at most 40 points a side, the bricks hold every point once plus the ghost planes
  each brick repeats ("a few planes per brick face": at most 4 at the 1-voxel step here) and,
  packed into one texture, the padding of smaller bricks to the tile: more than b' N, and at
  most b' times the product over the axes of n + 2 g k, with g = 4 ghost planes and k the
  bricks along the axis if each held 40 - 2 g points of its own.

CPU: peak resident memory of a process that draws one frame of the method on 320^3 float
points (128 MiB), over that of a process that only makes the volume and the window. Mesa's
llvmpipe keeps textures in the process's memory, so the excess may be the method's GPU bytes,
what the documentation says it holds on the CPU (the table's entries; the oracle array the
adaptive methods' filter adds, 4 N) and a fixed allowance of 96 MiB for the shader compiler and
the driver's per-draw state, which is less than a float copy of the volume (128 MiB): an
undocumented copy of the volume fails the test. Where the driver keeps textures elsewhere (a
real GPU), the excess only shrinks.
"""

import copy
import json
import math
import subprocess
import sys

import hovr
from hovr import io as hio
from hovr import methods as hm
from hovr.bench import rescale_transfer_function
from hovr.bench import peak_resident_mib
from hovrtesting import Checker, tf_path

DIMS = (97, 81, 66)
TYPES = {"uint8": (3, 1), "uint16": (5, 2), "float32": (10, 4)}  # VTK type, bytes per point
METHODS = ("preint1", "preint2", "iso-analytic", "mip-analytic", "adaptive-ray", "adaptive-3d")
# Bytes per texel of the volume's bricks, by method and stored bytes per point: pre-integration
# and adaptive sampling along rays filter 8-bit data as 16-bit texels; the analytic mapper and
# the pyramid read texels exactly, in the data's own type.
FILTERED = {"preint1", "preint2", "adaptive-ray"}
BRICK = 40
GHOSTS = 4
RSS_POINTS = 320
ALLOWANCE_MIB = 96.0


def volume(dims, scalar_type):
    source = hovr.vtkMarschnerLobbSource()
    source.SetDimensions(*dims)
    source.SetOutputScalarType(scalar_type)
    source.Update()
    return source.GetOutput()


def scene_for(image, name, size=(48, 48)):
    blend = "iso" if name.startswith("iso") else "mip" if name.startswith("mip") else "composite"
    color, opacity, _ = hio.read_transfer_function(
        tf_path("iso-opaque" if blend == "iso" else "marschner-lobb-spikes"))
    rescale_transfer_function(color, opacity, image)  # as the bench's tf_to_data_range
    low, high = image.GetPointData().GetScalars().GetRange()
    prop = hio.make_volume_property(color, opacity, 0.05)
    if blend == "iso":
        prop.GetIsoSurfaceValues().SetValue(0, 0.5 * (low + high))
    camera = hio.default_camera(image.GetBounds(), parallel=name == "adaptive-3d")
    return hm.Scene(image, prop, camera, size, blend)


def method_for(name, brick=None, mappers=None):
    """The method, its bricks at most ``brick`` points a side, its mappers kept in
    ``mappers``."""
    method = copy.copy(hm.get_method(name))
    make = method.make_mapper

    def make_mapper():
        mapper = make()
        if brick:
            mapper.SetMaximumBrickSize(brick)
        if mappers is not None:
            mappers.append(mapper)
        return mapper
    method.make_mapper = make_mapper
    return method


def texel_bytes(name, stored):
    return 2 if name in FILTERED and stored == 1 else stored


def child(request):
    """One frame in this process; prints its GPU bytes (empty for none: the window only)."""
    image = volume((RSS_POINTS,) * 3, TYPES["float32"][0])
    renderer = hm.Renderer()
    renderer._ensure_window((48, 48))
    stats = {}
    if request["method"]:
        stats = renderer.render(method_for(request["method"]),
                                scene_for(image, request["method"]), 1.0).extra
    renderer.close()
    result = {k: v for k, v in stats.items() if k.endswith("_bytes") or k == "table_size"}
    print(json.dumps(dict(result, peak_rss_mib=peak_resident_mib())))


def isolated(name):
    """The GPU bytes and the peak resident memory (its own, not the parent's it was forked
    from: hovr.bench.peak_resident_mib) of a frame in a process of its own."""
    process = subprocess.run([sys.executable, __file__, "--child", json.dumps({"method": name})],
                             stdout=subprocess.PIPE, check=False)
    if process.returncode != 0:
        raise RuntimeError("the frame of %s failed (status %d)" % (name, process.returncode))
    result = json.loads(process.stdout.decode().strip().splitlines()[-1])
    return result, result.pop("peak_rss_mib")


if len(sys.argv) > 2 and sys.argv[1] == "--child":
    child(json.loads(sys.argv[2]))
    sys.exit(0)

c = Checker()
renderer = hm.Renderer()
points = DIMS[0] * DIMS[1] * DIMS[2]
bricked_limit = 1.0
for n in DIMS:
    bricked_limit *= (n + 2 * GHOSTS * math.ceil(n / (BRICK - 2 * GHOSTS))) / n
for type_name, (vtk_type, stored) in TYPES.items():
    image = volume(DIMS, vtk_type)
    for name in METHODS:
        scene = scene_for(image, name)
        expected = texel_bytes(name, stored) * points
        for brick in (None, BRICK):
            mappers = []
            stats = renderer.render(method_for(name, brick, mappers), scene, 1.0, 2).extra
            label = "%s, %s, %s" % (name, type_name, "bricks of %d" % brick if brick else
                                    "one brick")
            print("%s: %s" % (label, ", ".join("%s %.3f N" % (k, v / points)
                                               for k, v in sorted(stats.items())
                                               if k.endswith("_bytes"))))
            held = stats["volume_gpu_bytes"]
            if brick is None:
                c.check(held == expected, "%s: the volume's texture holds %d bytes per point (%.3f)"
                        % (label, expected // points, held / points))
                uploads = mappers[0].GetBrickUploadCount()
                c.check(uploads == 1, "%s: the volume is uploaded once over three frames (%d "
                        "times)" % (label, uploads))
            else:
                c.check(expected < held <= bricked_limit * expected,
                        "%s: the bricks hold every point and their ghosts, %.3f of b' N (at "
                        "most %.3f)" % (label, held / expected, bricked_limit))
            if name.startswith("adaptive"):
                c.check(stats["oracle_gpu_bytes"] == 4 * points if brick is None else
                        4 * points < stats["oracle_gpu_bytes"] <= bricked_limit * 4 * points,
                        "%s: the oracle holds 4 bytes per point (%.3f)"
                        % (label, stats["oracle_gpu_bytes"] / points))
            if name.startswith("preint"):
                c.check(0 < stats["table_gpu_bytes"] <= 64 * 2 ** 20,
                        "%s: the table is within its 64 MiB limit (%d bytes)"
                        % (label, stats["table_gpu_bytes"]))
                c.check(stats["normal_gpu_bytes"] == 0, label + ": no normal texture unshaded")
renderer.close()

# CPU: one process per method, against one that holds only the volume and the window.
n = RSS_POINTS ** 3
_, base = isolated(None)
print("volume and window only: peak %.0f MiB" % base)
for name in METHODS:
    stats, peak = isolated(name)
    gpu = sum(v for k, v in stats.items() if k.endswith("_bytes"))
    # The CPU side the documentation names: the pre-integration table's entries (RGBA float)
    # and the oracle array of the adaptive methods.
    entries = 1
    for size in stats.get("table_size", "0").split("x"):
        entries *= int(size)
    cpu = (16 * entries if name.startswith("preint") else 0) + \
        (4 * n if name.startswith("adaptive") else 0)
    allowed = (gpu + cpu) / 2 ** 20 + ALLOWANCE_MIB
    print("%s: peak %.0f MiB, %.0f over the volume's process (GPU %.0f MiB, CPU %.0f MiB)"
          % (name, peak, peak - base, gpu / 2 ** 20, cpu / 2 ** 20))
    c.check(peak - base <= allowed, "%s at %d^3 float: peak resident memory %.0f MiB over the "
            "volume's process, at most %.0f (GPU %.0f MiB, CPU %.0f MiB, allowance %.0f)"
            % (name, RSS_POINTS, peak - base, allowed, gpu / 2 ** 20, cpu / 2 ** 20,
               ALLOWANCE_MIB))
c.finish()
