#!/usr/bin/env python3
"""Figures of a `clradiosity sweep` directory (docs/sweeps.md), from its results.csv and the PNGs it wrote.

    python3 bench/plot_sweep.py SWEEP_DIR

mape_vs_time.png: MAPE against wall time, log-log, one line per method and N (the mean over seeds at each
budget; models at their training time) with the path tracer's progressive render on the same axes (its rendering
time). mape_vs_samples.png: the models' MAPE against the incident samples they trained on (steps x batch x N),
where results.csv has that column. strip.png: the reference, NR, ISNR and the path tracer at the largest budget (equal time), each with its
false-colour error map (blue 0, red >= 100 % relative error) under it. The sweep runs this when matplotlib is there.
"""
import csv
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402


def main(sweep_dir):
    with open(os.path.join(sweep_dir, "results.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    budget_rows = [r for r in rows if r["kind"] == "model" and r["point"] == "budget"]

    # MAPE against time, and against samples seen: per (method, N), the seeds' mean at each budget.
    curves = defaultdict(lambda: defaultdict(list))
    for r in budget_rows:
        curves[(r["method"], int(r["samples"]))][float(r["budget_minutes"])].append(r)

    def mean(rs, column):
        return sum(float(r[column]) for r in rs) / len(rs)

    def figure(name, column, x_label, path_tracer):
        fig, ax = plt.subplots(figsize=(6, 4.5))
        for (method, n), by_budget in sorted(curves.items()):
            pts = sorted((mean(rs, column), mean(rs, "mape")) for rs in by_budget.values())
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", label=f"{method}, N = {n}")
        pt = sorted((float(r["seconds"]), float(r["mape"])) for r in rows if r["kind"] == "path_tracing")
        if path_tracer and pt:
            ax.plot([p[0] for p in pt], [p[1] for p in pt], "s--", color="black", label="path tracing")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(x_label)
        ax.set_ylabel("MAPE")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(sweep_dir, name), dpi=120)
        plt.close(fig)

    figure("mape_vs_time.png", "seconds", "wall time [s] (training; path tracing: rendering)", True)
    if budget_rows and all(r.get("incident_samples") for r in budget_rows):
        figure("mape_vs_samples.png", "incident_samples", "incident samples trained on (steps x batch x N)", False)

    # The image strip at the largest budget: the first seed and N of NR and of the first ISNR variant.
    if not budget_rows:
        return
    last = max(float(r["budget_minutes"]) for r in budget_rows)
    at_last = sorted((r for r in budget_rows if float(r["budget_minutes"]) == last),
                     key=lambda r: (int(r["samples"]), int(r["seed"])))
    panels = [("reference", "reference.png", None)]
    for wanted in ("nr", "isnr"):
        match = [r for r in at_last if r["method"].startswith(wanted)]
        if match:
            r = match[0]
            panels.append((f"{r['method']}, N = {r['samples']}, MAPE {float(r['mape']):.3g}", r["image"],
                           r["error_map"]))
    pt_at = [r for r in rows if r["kind"] == "path_tracing" and r["point"] == "budget"
             and float(r["budget_minutes"]) == last]
    if pt_at:
        r = pt_at[0]
        panels.append((f"path tracing, {r['spp']} spp, MAPE {float(r['mape']):.3g}", r["image"], r["error_map"]))
    fig, axes = plt.subplots(2, len(panels), figsize=(3 * len(panels), 6), squeeze=False)
    for col, (title, image, error_map) in enumerate(panels):
        for row, path in enumerate((image, error_map)):
            ax = axes[row][col]
            ax.axis("off")
            if path:
                ax.imshow(mpimg.imread(os.path.join(sweep_dir, path)))
        axes[0][col].set_title(title, fontsize=8)
    fig.suptitle(f"equal time: {last:g} min (error maps: blue 0, red >= 100 %)", fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(sweep_dir, "strip.png"), dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__.split("\n\n")[1].strip())
    main(sys.argv[1])
