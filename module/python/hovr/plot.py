"""The speed/accuracy trade as a picture: RMSE against time per frame, one line per method."""

import math

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402

COLORS = {"stock": "#555555", "preint1": "#1f77b4", "preint2": "#d62728", "reference": "#2ca02c"}


def tradeoff(rows, path):
    """Write a PNG with one panel per dataset: x = median ms per frame, y = RMSE (log-log),
    each method's points joined in step order and labelled with the step."""
    datasets = []
    for row in rows:
        if row["dataset"] not in datasets and row["method"] != "reference":
            datasets.append(row["dataset"])
    if not datasets:
        return
    columns = min(3, len(datasets))
    lines = int(math.ceil(len(datasets) / columns))
    figure, axes = plt.subplots(lines, columns, figsize=(5.0 * columns, 4.0 * lines),
                                squeeze=False)
    for index, name in enumerate(datasets):
        axis = axes[index // columns][index % columns]
        methods = []
        for row in rows:
            if row["dataset"] == name and row["method"] not in methods \
                    and row["method"] != "reference":
                methods.append(row["method"])
        for method in methods:
            points = sorted((r["step"], r["median_ms"], r["rmse"]) for r in rows
                            if r["dataset"] == name and r["method"] == method)
            xs = [p[1] for p in points]
            ys = [max(p[2], 1e-7) for p in points]
            axis.plot(xs, ys, "o-", label=method, color=COLORS.get(method))
            for step, x, y in zip([p[0] for p in points], xs, ys):
                axis.annotate("%g" % step, (x, y), textcoords="offset points", xytext=(4, 4),
                              fontsize=7)
        axis.set_xscale("log")
        axis.set_yscale("log")
        axis.set_xlabel("median ms per frame")
        axis.set_ylabel("RMSE vs reference (premultiplied RGBA)")
        axis.set_title(name + " (labels: step in voxels)")
        axis.grid(True, which="both", alpha=0.3)
        axis.legend()
    for index in range(len(datasets), lines * columns):
        axes[index // columns][index % columns].axis("off")
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)
