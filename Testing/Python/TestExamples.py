"""The Python and C++ examples run and report both pre-integrations beating the stock
mapper, the analytic isosurface finding the thin surfaces VTK's sampled one misses, the
object-order CPU mapper hiding most of the volume with an error like VTK's CPU mapper, and
background refinement drawing a drag at once and its refined frame after."""

import os
import re
import subprocess
import sys
import tempfile

from hovrtesting import Checker, ROOT

c = Checker()
tmp = tempfile.mkdtemp(prefix="hovr-examples-")
runs = [("python", [sys.executable, os.path.join(ROOT, "Examples", "Python",
                                                 "preintegrated_volume.py"),
                    "--output", os.path.join(tmp, "python.png"), "--size", "160"],
         os.path.join(tmp, "python.png"))]
binary = os.path.join(os.environ.get("HOVR_BUILD", ""), "bin", "PreIntegratedVolume")
if os.path.isfile(binary):
    runs.append(("c++", [binary, os.path.join(tmp, "cxx.png")], os.path.join(tmp, "cxx.png")))
else:
    c.check(False, "the C++ example is built at %s" % binary)
for name, command, output in runs:
    process = subprocess.run(command, capture_output=True, text=True)
    print(name, process.stdout.strip())
    c.check(process.returncode == 0, "%s example exits 0 (%s)" % (name, process.stderr.strip()))
    match = re.search(r"RMSE stock ([0-9.e-]+), first-order pre-integration ([0-9.e-]+), "
                      r"second-order pre-integration ([0-9.e-]+)", process.stdout)
    c.check(match is not None, "%s example prints the three errors" % name)
    if match:
        stock, first, second = (float(match.group(g)) for g in (1, 2, 3))
        c.check(first < stock and second < stock, "%s example: pre-integration %.4f and %.4f "
                "< stock %.4f" % (name, first, second, stock))
    c.check(os.path.isfile(output) and os.path.getsize(output) > 1000, "%s writes a PNG" % name)
# The analytic isosurface examples: the thin features VTK's sampled isosurface misses.
analytic_runs = [("python", [sys.executable, os.path.join(ROOT, "Examples", "Python",
                                                          "analytic_isosurface.py"),
                             "--output", os.path.join(tmp, "analytic.png"), "--size", "160"],
                  os.path.join(tmp, "analytic.png"))]
analytic_binary = os.path.join(os.environ.get("HOVR_BUILD", ""), "bin", "AnalyticIsosurface")
if os.path.isfile(analytic_binary):
    analytic_runs.append(("c++", [analytic_binary, os.path.join(tmp, "analytic_cxx.png")],
                          os.path.join(tmp, "analytic_cxx.png")))
else:
    c.check(False, "the C++ analytic example is built at %s" % analytic_binary)
for name, command, output in analytic_runs:
    process = subprocess.run(command, capture_output=True, text=True)
    print(name, process.stdout.strip())
    c.check(process.returncode == 0, "%s analytic example exits 0 (%s)"
            % (name, process.stderr.strip()))
    match = re.search(r"missed surface pixels: stock (\d+), analytic (\d+)", process.stdout)
    c.check(match is not None, "%s analytic example prints the missed pixels" % name)
    if match:
        stock, analytic = int(match.group(1)), int(match.group(2))
        c.check(stock > 20 and analytic * 10 < stock, "%s analytic example: the analytic "
                "isosurface misses %d pixels, VTK's at 1/4 voxel %d" % (name, analytic, stock))
    c.check(os.path.isfile(output) and os.path.getsize(output) > 1000, "%s writes a PNG" % name)
# The object-order example: most non-transparent cells hidden, an error like VTK's CPU mapper.
process = subprocess.run([sys.executable, os.path.join(ROOT, "Examples", "Python",
                                                       "object_order.py"),
                          "--output", os.path.join(tmp, "object_order.png"), "--size", "160"],
                         capture_output=True, text=True)
print("python", process.stdout.strip())
c.check(process.returncode == 0, "object-order example exits 0 (%s)" % process.stderr.strip())
hidden = re.search(r"\(([0-9.]+)% hidden and skipped\)", process.stdout)
errors = re.search(r"RMSE fixedpoint ([0-9.e-]+), object-order ([0-9.e-]+)", process.stdout)
c.check(hidden is not None and float(hidden.group(1)) > 50.0,
        "object-order example: over half of the non-transparent cells hidden")
c.check(errors is not None and float(errors.group(2)) < 1.5 * float(errors.group(1)) + 0.01,
        "object-order example: an error comparable to VTK's CPU mapper")
c.check(os.path.isfile(os.path.join(tmp, "object_order.png")), "object-order example writes a PNG")
object_binary = os.path.join(os.environ.get("HOVR_BUILD", ""), "bin", "ObjectOrderVolume")
if c.check(os.path.isfile(object_binary), "the C++ object-order example is built"):
    process = subprocess.run([object_binary, os.path.join(tmp, "object_order_cxx.png")],
                             capture_output=True, text=True)
    print("c++", process.stdout.strip())
    hidden = re.search(r"\(([0-9.]+)% hidden and skipped\)", process.stdout)
    c.check(process.returncode == 0 and hidden is not None and float(hidden.group(1)) > 50.0,
            "C++ object-order example: over half of the non-transparent cells hidden (%s)"
            % process.stderr.strip())
# The table sweep: the sizer's choice, the exact segment model and a sweep, each with an RMSE.
process = subprocess.run([sys.executable, os.path.join(ROOT, "Examples", "Python",
                                                       "table_sweep.py"),
                          "--size", "32", "--centres", "33"], capture_output=True, text=True)
print("table sweep", process.stdout.strip())
c.check(process.returncode == 0, "table sweep exits 0 (%s)" % process.stderr.strip())
errors = [float(e) for e in re.findall(r"RMSE ([0-9.]+)", process.stdout)]
c.check(re.search(r"chosen by the sizer: \d+x\d+x\d+", process.stdout) is not None
        and len(errors) >= 4 and all(0.0 < e < 1.0 for e in errors),
        "table sweep prints the chosen table and the errors of the exact model and the sweep")
# Answer first, refine after, in an interactor's event loop: a drag of timer edits, each drawn
# at once, then the refined frame the mapper's event asks for (or the measurement's
# confirmation of the table drawn).
process = subprocess.run([sys.executable, os.path.join(ROOT, "Examples", "Python",
                                                       "interactive_refinement.py"),
                          "--offscreen", "--points", "64", "--edits", "10"],
                         capture_output=True, text=True, timeout=300)
print("interactive refinement", process.stdout.strip())
c.check(process.returncode == 0, "interactive refinement exits 0 (%s)" % process.stderr.strip())
c.check(re.search(r"drag: 10 edits drawn at once, .*refining: True", process.stdout) is not None,
        "interactive refinement: the last edit of the drag is drawn before its measurement")
c.check(re.search(r"refined frame [0-9.]+ s after the last edit", process.stdout) is not None,
        "interactive refinement: TablesRefinedEvent brings the refined frame, or the "
        "measurement confirms the table drawn")
# The same drag with adaptive sampling: the oracle answers first and refines after.
process = subprocess.run([sys.executable, os.path.join(ROOT, "Examples", "Python",
                                                       "interactive_refinement.py"),
                          "--offscreen", "--points", "64", "--edits", "10",
                          "--method", "adaptive-ray"],
                         capture_output=True, text=True, timeout=300)
print("interactive refinement, adaptive-ray", process.stdout.strip())
c.check(process.returncode == 0, "interactive refinement (adaptive-ray) exits 0 (%s)"
        % process.stderr.strip())
c.check(re.search(r"drag: 10 edits drawn at once, .*refining: True", process.stdout) is not None,
        "interactive refinement (adaptive-ray): the drag's last edit is drawn with the last "
        "oracle distances")
c.check(re.search(r"refined frame [0-9.]+ s after the last edit .*; oracle", process.stdout)
        is not None, "interactive refinement (adaptive-ray): OracleRefinedEvent brings the "
        "refined frame")
# The provisional tables' error over the measured tables', on seeded random edits.
process = subprocess.run([sys.executable, os.path.join(ROOT, "Examples", "Python",
                                                       "provisional_tables.py"),
                          "--cases", "2", "--points", "32"], capture_output=True, text=True,
                         timeout=300)
print("provisional tables", process.stdout.strip())
c.check(process.returncode == 0, "provisional tables exits 0 (%s)" % process.stderr.strip())
summaries = re.findall(r"order (\d), (drag|spike) *: 2 edits, .* median ([0-9.]+), within 2% in "
                       r"\d+, worst ([0-9.]+)", process.stdout)
c.check(len(summaries) == 4 and all(0.0 < float(m) <= float(w) for _, _, m, w in summaries),
        "provisional tables prints a summary per order and edit")
# Where a measurement spends its time: a phase per ProgressEvent, after each of two edits.
for change in ("colour", "step"):
    process = subprocess.run([sys.executable, os.path.join(ROOT, "Examples", "Python",
                                                           "sizer_phases.py"),
                              "--size", "48", "--change", change, "--repeats", "2"],
                             capture_output=True, text=True, timeout=300)
    print("sizer phases", process.stdout.strip())
    c.check(process.returncode == 0, "sizer phases (%s) exits 0 (%s)" % (
        change, process.stderr.strip()))
    c.check(len(re.findall(r"^%s \d: \d+ ms \(reference \d+, pieces \d+, exact model \d+, "
                           r"centre size 1 \d+.*choice \d+\); \d+ candidates, chosen \d+x\d+x\d+$"
                           % change, process.stdout, re.M)) == 2,
            "sizer phases (%s) prints the phases of both measurements" % change)
c.finish()
