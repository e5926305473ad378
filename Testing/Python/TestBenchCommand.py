"""``hovr bench``: a small configuration gives the CSV, images, difference images, the plot
and the summary; optional datasets whose data is missing are skipped with a message; the
reference is cached between runs; a broken configuration is a clear error. A small latency
configuration gives a row per method and change, the refinement of the methods that answer
first, and the first and refined frames' errors. ``hovr tables`` builds small second-order
tables on the CPU and the GPU and finds them equal."""

import csv
import json
import os
import tempfile
import time

from hovrtesting import Checker, PRESETS, run_cli

c = Checker()
tmp = tempfile.mkdtemp(prefix="hovr-bench-")
config = {
    "size": [48, 40],
    "repeat": 2,
    "methods": ["stock", "preint1"],
    "steps": [1, 2],
    "baseline": ["stock", 1],
    "datasets": [
        {"name": "ml17", "input": "marschner-lobb:17",
         "tf": os.path.join(PRESETS, "transfer-functions", "marschner-lobb-spikes.json"),
         "opacity_unit_distance": 0.1},
        {"name": "absent", "input": os.path.join(tmp, "nothing.raw"), "dims": [4, 4, 4],
         "type": "uint8", "tf": "x.json", "optional": True},
    ],
}
path = os.path.join(tmp, "bench.json")
with open(path, "w") as stream:
    json.dump(config, stream)
out = os.path.join(tmp, "report")
start = time.time()
code, stdout, stderr = run_cli("bench", path, "--output", out)
first = time.time() - start
c.check("skipping absent" in stderr, "a missing optional dataset is skipped with a message")
c.check("ml17" in stdout and "preint1" in stdout, "summary printed")
with open(os.path.join(out, "results.csv")) as stream:
    rows = list(csv.DictReader(stream))
c.check(len(rows) == 4, "one row per method and step (%d rows)" % len(rows))
for row in rows:
    for key in ("median_ms", "rmse", "max_error", "rmse_a", "samples_per_frame"):
        c.check(row.get(key) not in (None, ""), "row %s/%s has %s" % (row["method"], row["step"],
                                                                     key))
    c.check(float(row["rmse"]) > 0 and float(row["rmse"]) < 0.5, "plausible RMSE %s" % row["rmse"])
    c.check(row["ms_ratio_to_stock"] != "", "ratio to stock in the same run")
    c.check(row["ms_ratio_paired"] != "" and float(row["ms_ratio_paired_min"]) <=
            float(row["ms_ratio_paired"]) <= float(row["ms_ratio_paired_max"]),
            "paired ratio to the baseline, between its extremes")
    stem = "ml17_%s_step%g" % (row["method"], float(row["step"]))
    for suffix in (".png", "_diff.png"):
        c.check(os.path.isfile(os.path.join(out, "images", stem + suffix)), stem + suffix)
stock = {float(r["step"]): float(r["rmse"]) for r in rows if r["method"] == "stock"}

base_row = [r for r in rows if r["method"] == "stock" and float(r["step"]) == 1][0]
c.check(float(base_row["ms_ratio_paired"]) == 1.0, "the baseline's paired ratio is 1")

# Paired ratios: round by round, then the median (here 2, where the ratio of the medians is
# 3); none for runs that were not interleaved or whose rounds do not pair up.
from hovr import bench as hb
paired = hb.paired_ratio({"_times": [10.0, 40.0, 30.0], "_interleaved": True},
                         {"_times": [10.0, 20.0, 10.0], "_interleaved": True})
c.check(paired == {"ms_ratio_paired": 2.0, "ms_ratio_paired_min": 1.0,
                   "ms_ratio_paired_max": 3.0}, "paired ratio round by round: %s" % paired)
c.check(hb.paired_ratio({"_times": [1.0], "_interleaved": False},
                        {"_times": [1.0], "_interleaved": True}) == {} and
        hb.paired_ratio({"_times": [1.0, 2.0], "_interleaved": True},
                        {"_times": [1.0], "_interleaved": True}) == {},
        "no paired ratio without interleaved rounds that pair up")
c.check(stock[1] < stock[2], "stock error shrinks with the step (%s)" % stock)
for name in ("tradeoff.png", "summary.txt", os.path.join("images", "ml17_reference.png")):
    c.check(os.path.isfile(os.path.join(out, name)), name + " written")
with open(os.path.join(out, "tradeoff.png"), "rb") as stream:
    c.check(stream.read(4) == b"\x89PNG", "the plot is a PNG")
cached = [f for f in os.listdir(os.path.join(out, "cache")) if f.endswith(".vti")]
c.check(len(cached) == 1, "the reference is cached")
mtime = os.path.getmtime(os.path.join(out, "cache", cached[0]))
run_cli("bench", path, "--output", out)
c.check(os.path.getmtime(os.path.join(out, "cache", cached[0])) == mtime,
        "the cached reference is reused")

broken = os.path.join(tmp, "broken.json")
with open(broken, "w") as stream:
    stream.write('{"datasets": [], "methods": ["nope"]}')
code, stdout, stderr = run_cli("bench", broken, "--output", out, expect=2)
c.check("unknown method" in stderr, "unknown method in a configuration is reported")
code, stdout, stderr = run_cli("bench", os.path.join(tmp, "none.json"), expect=2)
c.check("bench configuration file not found" in stderr, "missing configuration is reported")

# A run's settings: a pre-integration method's table memory limit shrinks its automatic table
# (rows named after the setting); a setting the method does not take is an error.
limited = dict(config, runs=[["preint2", 1], ["preint2", 1, {"table_memory_mib": 0.01}]],
               baseline=["preint2", 1], datasets=config["datasets"][:1])
limited.pop("methods")
limited.pop("steps")
with open(broken, "w") as stream:
    json.dump(limited, stream)
run_cli("bench", broken, "--output", os.path.join(tmp, "limited"))
with open(os.path.join(tmp, "limited", "results.csv")) as stream:
    sizes = {r["method"]: int(r["table_gpu_bytes"]) for r in csv.DictReader(stream)}
c.check(sorted(sizes) == ["preint2", "preint2(table_memory_mib=0.01)"]
        and 0 < sizes["preint2(table_memory_mib=0.01)"] <= 0.01 * 2**20 < sizes["preint2"],
        "table_memory_mib bounds the table's GPU memory (%s)" % sizes)
for method, message in (("preint1", "unknown setting(s) lmax of preint1"),
                        ("stock", "method stock takes no settings")):
    limited["runs"] = [[method, 1, {"lmax": 2}]]
    with open(broken, "w") as stream:
        json.dump(limited, stream)
    code, stdout, stderr = run_cli("bench", broken, "--output", out, expect=2)
    c.check(message in stderr, "a setting %s lacks is an error (%s)" % (method,
                                                                       stderr.strip()[-200:]))

# A latency configuration: every change of every method, beside stock's, with the refined
# frame of those that answer first (pre-integration's table, adaptive sampling's oracle).
latency = {
    "kind": "latency", "size": [48, 40], "changes": 2, "step": 1, "reference_pixels": 0.5,
    "methods": ["stock", "preint2", "adaptive-ray"],
    "datasets": [{"name": "ml24", "input": "marschner-lobb:24",
                  "tf": os.path.join(PRESETS, "transfer-functions", "marschner-lobb-spikes.json"),
                  "tf_to_data_range": True, "opacity_unit_distance": 0.1}],
}
latency_path = os.path.join(tmp, "latency.json")
with open(latency_path, "w") as stream:
    json.dump(latency, stream)
latency_out = os.path.join(tmp, "latency")
run_cli("bench", latency_path, "--output", latency_out)
with open(os.path.join(latency_out, "latency.csv")) as stream:
    latency_rows = list(csv.DictReader(stream))
changes = ("switch", "camera", "opacity", "colour", "step", "data")
c.check(sorted((r["method"], r["change"]) for r in latency_rows) ==
        sorted((m, k) for m in latency["methods"] for k in changes),
        "latency: one row per method and change")
for row in latency_rows:
    c.check(float(row["median_ms"]) > 0 and float(row["bound_ratio"]) > 0,
            "latency: %s %s has a time and a bound ratio" % (row["method"], row["change"]))
    if row["change"] == "opacity":
        first, refined = float(row["rmse_first"]), float(row["rmse_refined"])
        c.check(0 < first < 0.5 and 0 < refined < 0.5,
                "latency: %s's first and refined errors (%s, %s)" % (row["method"], first, refined))
        if row["method"] != "stock":
            c.check(row["refined_ms"] != "" and float(row["refined_ms"]) > 0,
                    "latency: %s refines in the background after the opacity edits"
                    % row["method"])
c.check(os.path.isfile(os.path.join(latency_out, "summary.txt")), "latency: summary.txt")

# hovr tables: CPU and GPU builds of small second-order tables agree; the CSV has every row.
tables_csv = os.path.join(tmp, "tables.csv")
code, stdout, stderr = run_cli("tables", "--sizes", 12, 20, "--iterations", 8, 16, "--repeat", 1,
                               "--csv", tables_csv)
with open(tables_csv) as stream:
    table_rows = list(csv.DictReader(stream))
c.check([(int(r["size"]), int(r["iterations"])) for r in table_rows]
        == [(12, 8), (12, 16), (20, 8), (20, 16)], "hovr tables: one row per size and iterations")
for row in table_rows:
    c.check(float(row["cpu_s"]) > 0 and float(row["gpu_s"]) > 0,
            "hovr tables: CPU and GPU times for %s^3" % row["size"])
    c.check(float(row["max_abs_difference"]) <= 1e-6,
            "hovr tables: CPU and GPU tables agree for %s^3 (%s)" % (row["size"],
                                                                   row["max_abs_difference"]))
c.check("CPU" in stdout or "CPU" in stderr, "hovr tables prints the times")
code, stdout, stderr = run_cli("tables", "--sizes", 1, expect=2)
c.check("size" in stderr, "hovr tables refuses a table size below 2 (%s)" % stderr.strip())
c.finish()
