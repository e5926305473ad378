"""The Python and C++ examples run and report both pre-integrations beating the stock
mapper."""

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
c.finish()
