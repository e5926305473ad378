"""Where a table-size measurement spends its time after each kind of change.

vtkPreIntegrationTableSizer measures a pre-integration table's sizes in phases, each reported
by a ProgressEvent: the reference along its rays (0.25), the rays' pieces (0.35), the exact
segment model (0.45), then one centre size of candidate tables after another. What a change
costs depends on what it leaves standing: an edit of the transfer functions keeps the rays'
pieces, recolours the reference when it edits colours alone, keeps the exact model of the
pieces away from what changed and the candidate entries that read nothing that changed; a
change of the sample distance keeps the reference only.

This script renders the latency preset's scene (Marschner-Lobb of the given size, the spike
transfer function, step 1 voxel, 512^2) once with a vtkPreIntegrationVolumeMapper of the
given order, then applies the bench's change (`opacity`: the middle opacity node up or down by
10%; `colour`: the middle colour node's colour by 0.05; `step`: the sample distance 1.125
voxels and back) and measures the sizes again in the foreground with the mapper's own table
and sizer settings, printing the time of each phase:

    ./hovr python Examples/Python/sizer_phases.py [--size 256] [--order 2]
        [--change colour] [--repeats 3]
"""

import argparse
import os
import time

from vtkmodules.vtkCommonCore import vtkCommand

import hovr
from hovr import bench, latency
from hovr.registry import get_method

PHASES = {0.25: "reference", 0.35: "pieces", 0.45: "exact model"}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--order", type=int, choices=(1, 2), default=2)
    parser.add_argument("--change", choices=("opacity", "colour", "step"), default="colour")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()

    base = os.path.join(os.environ["HOVR_ROOT"], "presets", "bench")
    spec = {"name": "ml", "input": "marschner-lobb:%d" % args.size,
            "tf": "../transfer-functions/marschner-lobb-spikes.json",
            "tf_to_data_range": True, "opacity_unit_distance": 0.05}
    scene, _, _ = bench._scene_for(spec, base, (512, 512))
    view = latency.View(get_method("preint%d" % args.order), scene, 1.0)
    try:
        view.mapper.SetRefineInBackground(False)
        view.frame()
        table = view.mapper.GetActiveTable()
        sizer = hovr.vtkPreIntegrationTableSizer()
        sizer.CopySettings(view.mapper.GetTableSizing().GetRefiner().GetSizerSettings())
        marks = []
        sizer.AddObserver(vtkCommand.ProgressEvent,
                          lambda caller, _: marks.append((caller.GetProgress(),
                                                          time.perf_counter())))
        image = scene.image
        scalars = image.GetPointData().GetScalars()
        step = view.mapper.GetSampleDistance()
        sizer.Choose(image, scalars, table, args.order, step)
        for k in range(args.repeats):
            if args.change == "opacity":
                latency._edit_opacity(scene.prop, k)
            elif args.change == "colour":
                latency._edit_colour(scene.prop, k)
            else:
                # The table integrates slabs of the step (segments for first order), as the
                # mapper sets it.
                step = scene.step_length(1.125 if k % 2 == 0 else 1.0)
                table.SetSegmentLength(args.order * step)
            marks.clear()
            start = time.perf_counter()
            if not sizer.Choose(image, scalars, table, args.order, step):
                raise SystemExit("the sizer failed")
            total = time.perf_counter() - start
            parts, last, level = [], start, 0
            for progress, when in marks:
                if progress <= 0.0:
                    continue
                if progress in PHASES:
                    name = PHASES[progress]
                elif progress < 1.0:
                    level += 1
                    name = "centre size %d" % level
                else:
                    name = "choice"
                parts.append("%s %.0f" % (name, 1000.0 * (when - last)))
                last = when
            sizes = [0, 0, 0]
            sizer.GetCandidateSizes(sizer.GetChosenCandidate(), sizes)
            print("%s %d: %.0f ms (%s); %d candidates, chosen %s" % (
                args.change, k + 1, 1000.0 * total, ", ".join(parts),
                sizer.GetNumberOfCandidates(), "x".join(map(str, sizes))), flush=True)
    finally:
        view.close()


if __name__ == "__main__":
    main()
