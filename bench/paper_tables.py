#!/usr/bin/env python3
"""The paper's tables beside ours, from what bench/paper_tables.sh left in OUT_DIR (python3's standard library only).

    python3 bench/paper_tables.py OUT_DIR bench/paper/paper.json

Reads OUT_DIR/runs/SCENE/*/{log.csv,run.json,config.json} (each training's evaluations: train --reference) and
OUT_DIR/path_tracer/SCENE/points.csv; writes OUT_DIR/tables.md (Tables 1, 2 and 4 with the paper's numbers beside
ours, and the time each method and the path tracer need to reach a MAPE) and OUT_DIR/SCENE-curves.svg (MAPE
against steps, against seconds with the path tracer on the same axes, and against the incident samples trained
on, steps x batch x N, in which runs of other batches and N compare).
"""
import csv
import json
import math
import os
import sys

METHODS = {"nr": "NR", "isnr-kl": "ISNR (KL)", "isnr-ikl": "ISNR (IKL)"}
PAPER_KEY = {"nr": "nr", "isnr-ikl": "isnr"}  # Tables 1 and 2 show NR and the full method only
ABLATION_KEY = {"nr": "nr", "isnr-kl": "kl", "isnr-ikl": "ikl"}
COLOURS = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000"]


def number(v, fmt="{:.4g}"):
    return "—" if v is None or (isinstance(v, float) and not math.isfinite(v)) else fmt.format(v)


def read_run(folder):
    rows = list(csv.DictReader(open(os.path.join(folder, "log.csv"))))
    evals = [(int(r["step"]), float(r["seconds"]), float(r["mape"]), float(r["mse"])) for r in rows if r.get("mape")]
    record = json.load(open(os.path.join(folder, "run.json")))
    config = json.load(open(os.path.join(folder, "config.json")))
    # Incident samples trained on (steps x batch x N): log.csv's column, or the same product for a log before it.
    per_step = (config.get("batch") or 0) * (config.get("samples") or 0)
    return {
        "evals": evals,
        "steps": int(rows[-1]["step"]) if rows else 0,
        "seconds": float(rows[-1]["seconds"]) if rows else 0.0,
        "memory_mib": record.get("peak_device_mib"),
        "batch": config.get("batch"),
        "samples": record["samples"],
        "per_step": per_step,
    }


def runs_of(scene_dir, table):
    runs = {}
    for key in METHODS:
        folder = os.path.join(scene_dir, f"t{table}-{key}")
        if os.path.exists(os.path.join(folder, "run.json")):
            runs[key] = read_run(folder)
    return runs


def final(run):
    return run["evals"][-1] if run["evals"] else (run["steps"], run["seconds"], None, None)


def results_table(lines, title, runs, paper_rows, paper_scene):
    lines += [f"#### {title}", ""]
    lines += ["| method | step | samples seen (M) | time (min) | memory (GiB) | MAPE | MSE | paper: step | time (min) | "
              "memory (GB) | MAPE | MSE |",
              "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for key, run in runs.items():
        step, seconds, mape, mse = final(run)
        paper = paper_rows.get(paper_scene, {}).get(PAPER_KEY.get(key, ""), {}) if paper_scene else {}
        memory = run["memory_mib"] / 1024 if run["memory_mib"] is not None else None
        lines.append(
            f"| {METHODS[key]} | {step} | {number(step * run['per_step'] / 1e6 or None, '{:.4g}')} | "
            f"{number(seconds / 60, '{:.3g}')} | {number(memory, '{:.2f}')} | "
            f"{number(mape, '{:.4f}')} | {number(mse, '{:.3g}')} | {number(paper.get('step'), '{:.0f}')} | "
            f"{number(paper.get('minutes'), '{:.0f}')} | {number(paper.get('memory_gb'), '{:.2f}')} | "
            f"{number(paper.get('mape'), '{:.3f}')} | {number(paper.get('mse'), '{:.3g}')} |")
    lines.append("")


def at_step(run, step):
    """The run's evaluation at `step`, or the first after it; None past its end."""
    for e in run["evals"]:
        if e[0] >= step:
            return e
    return None


def ablation_table(lines, runs, paper):
    t4 = paper["table4"]
    # The paper's steps where the runs reach its first; runs shorter than that (a smoke test) at the same shares of
    # their budget.
    longest = max(r["steps"] for r in runs.values())
    scale = 1.0 if longest >= t4["steps"][0] else longest / t4["steps"][-1]
    lines += ["#### Table 4: ablation (w/o I-Module = NR, w/o IKL = ISNR (KL), full = ISNR (IKL)); the paper's on "
              + t4["scene"], ""]
    if scale < 1:
        lines += [f"Runs of {longest} steps: each row at the paper's step × {scale:.3g} (the same share of the "
                  "budget), its first evaluation at or after that step.", ""]
    keys = [k for k in METHODS if k in runs]
    head = " | ".join(f"MAPE {METHODS[k]}" for k in keys) + " | " + " | ".join(f"MSE {METHODS[k]}" for k in keys)
    lines += [f"| step | evaluated at | {head} | paper MAPE nr / kl / ikl | paper MSE nr / kl / ikl |",
              "| ---: | ---: | " + " | ".join("---:" for _ in range(2 * len(keys))) + " | ---: | ---: |"]
    for i, paper_step in enumerate(t4["steps"]):
        step = max(1, round(paper_step * scale))
        cells = [at_step(runs[k], step) for k in keys]
        mapes = " | ".join(number(c[2] if c else None, "{:.4f}") for c in cells)
        mses = " | ".join(number(c[3] if c else None, "{:.3g}") for c in cells)
        pm = " / ".join(f"{t4['mape'][k][i]:.4f}" for k in ("nr", "kl", "ikl"))
        ps = " / ".join(f"{t4['mse'][k][i]:.4f}" for k in ("nr", "kl", "ikl"))
        evaluated = ", ".join(sorted({str(c[0]) for c in cells if c})) or "—"
        lines.append(f"| {step} | {evaluated} | {mapes} | {mses} | {pm} | {ps} |")
    lines.append("")


def path_tracer_points(folder):
    file = os.path.join(folder, "points.csv")
    if not os.path.exists(file):
        return []
    return sorted((float(r["seconds"]), float(r["mape"])) for r in csv.DictReader(open(file)))


def path_tracer_time_to(points, mape):
    """Seconds the path tracer needs for `mape`: log-log between the points around it, else from the nearest point
    with MAPE ∝ t^-1/2 (Monte Carlo's rate; marked as extrapolated)."""
    usable = [(t, m) for t, m in points if t > 0 and m > 0]
    if not usable:
        return None, False
    for (t0, m0), (t1, m1) in zip(usable, usable[1:]):
        if m1 <= mape <= m0 and m0 != m1:
            f = math.log(m0 / mape) / math.log(m0 / m1)
            return math.exp(math.log(t0) + f * math.log(t1 / t0)), False
    t, m = usable[-1] if mape < usable[-1][1] else usable[0]
    return t * (m / mape) ** 2, True


def time_to_quality(lines, runs, points):
    targets = sorted({final(r)[2] for r in runs.values() if final(r)[2] is not None}, reverse=True)
    if not targets:
        return
    keys = [k for k in METHODS if k in runs]
    lines += ["#### Time to quality: training seconds until an evaluation reaches the MAPE (— never), and the "
              "path tracer's rendering seconds for it (~ extrapolated with MAPE ∝ t^-1/2)", "",
              "| MAPE | " + " | ".join(METHODS[k] for k in keys) + " | path tracer |",
              "| ---: | " + " | ".join("---:" for _ in keys) + " | ---: |"]
    for target in targets:
        cells = []
        for k in keys:
            reached = next((e for e in runs[k]["evals"] if e[2] <= target), None)
            cells.append(number(reached[1] if reached else None, "{:.3g}"))
        pt, extrapolated = path_tracer_time_to(points, target)
        cells.append(("~" if extrapolated else "") + number(pt, "{:.3g}"))
        lines.append(f"| {target:.4f} | " + " | ".join(cells) + " |")
    lines.append("")


def svg_curves(file, title, panels):
    width, height, left, right, top, bottom = 440, 320, 72, 16, 34, 46

    def panel(x_off, name, x_label, series):
        pts = [(x, y) for _, xs, ys in series for x, y in zip(xs, ys) if y > 0 and math.isfinite(x)]
        out = [f'<text x="{x_off + left + (width - left - right) / 2}" y="{28 + 20}" text-anchor="middle" '
               f'font-size="13">{name}</text>']
        w, h, px, py = width - left - right, height - top - bottom, x_off + left, 28 + top
        out.append(f'<rect x="{px}" y="{py}" width="{w}" height="{h}" fill="none" stroke="#444"/>')
        if not pts:
            return out
        x0, x1 = min(p[0] for p in pts), max(p[0] for p in pts)
        y0, y1 = min(p[1] for p in pts), max(p[1] for p in pts)
        x1 = x1 if x1 > x0 else x0 + 1
        y0, y1 = 10 ** math.floor(math.log10(y0) * 4 / 4), 10 ** math.ceil(math.log10(y1))
        sx = lambda x: px + (x - x0) / (x1 - x0) * w  # noqa: E731
        sy = lambda y: py + h - math.log(y / y0) / math.log(y1 / y0) * h  # noqa: E731
        for k in range(5):
            x = x0 + (x1 - x0) * k / 4
            out.append(f'<text x="{sx(x):.1f}" y="{py + h + 15}" text-anchor="middle" font-size="11">{x:.4g}</text>')
        decade = 10 ** math.floor(math.log10(y0))
        while decade <= y1:
            if decade >= y0:
                out.append(f'<line x1="{px}" y1="{sy(decade):.1f}" x2="{px + w}" y2="{sy(decade):.1f}" stroke="#ddd"/>'
                           f'<text x="{px - 5}" y="{sy(decade) + 4:.1f}" text-anchor="end" font-size="11">'
                           f'{decade:.0e}</text>')
            decade *= 10
        out.append(f'<text x="{px + w / 2}" y="{py + h + 34}" text-anchor="middle" font-size="12">{x_label}</text>')
        out.append(f'<text x="{x_off + 16}" y="{py + h / 2}" text-anchor="middle" font-size="12" '
                   f'transform="rotate(-90 {x_off + 16} {py + h / 2})">MAPE (log)</text>')
        for i, (label, xs, ys) in enumerate(series):
            colour = COLOURS[i % len(COLOURS)]
            p = [(sx(x), sy(y)) for x, y in zip(xs, ys) if y > 0 and math.isfinite(x)]
            if len(p) > 1:
                out.append(f'<polyline fill="none" stroke="{colour}" stroke-width="1.5" points="'
                           + " ".join(f"{a:.1f},{b:.1f}" for a, b in p) + '"/>')
            out += [f'<circle cx="{a:.1f}" cy="{b:.1f}" r="2.5" fill="{colour}"/>' for a, b in p]
            out.append(f'<line x1="{px + w - 130}" y1="{py + 14 + 15 * i}" x2="{px + w - 110}" y2="{py + 14 + 15 * i}" '
                       f'stroke="{colour}" stroke-width="2"/><text x="{px + w - 105}" y="{py + 18 + 15 * i}" '
                       f'font-size="11">{label}</text>')
        return out

    body = [part for i, (name, x_label, series) in enumerate(panels) for part in panel(i * width, name, x_label, series)]
    with open(file + ".tmp", "w") as f:
        f.write(f'<svg xmlns="http://www.w3.org/2000/svg" width="{len(panels) * width}" height="{height + 28}" '
                f'font-family="sans-serif">\n<rect width="100%" height="100%" fill="white"/>\n'
                f'<text x="{len(panels) * width / 2}" y="20" text-anchor="middle" font-size="15">{title}</text>\n'
                + "\n".join(body) + "\n</svg>\n")
    os.replace(file + ".tmp", file)


def main(out_dir, paper_file):
    paper = json.load(open(paper_file))
    lines = ["# The paper's tables, regenerated", "",
             f"Written by bench/paper_tables.py from {out_dir}. Paper: {paper['source']}", ""]
    for scene in sorted(os.listdir(os.path.join(out_dir, "runs"))):
        scene_dir = os.path.join(out_dir, "runs", scene)
        info = json.load(open(os.path.join(scene_dir, "scene.json")))
        paper_scene = info.get("paper_scene") or None
        lines += [f"### {scene}" + (f" (the paper's {paper_scene})" if paper_scene else " (not in the paper)"), "",
                  f"Evaluations at {info['width']}x{info['height']}, {info['eval_spp']} spp, against "
                  f"{info['reference']}; preset `{info['preset'] or 'none (device defaults)'}`.", ""]
        points = path_tracer_points(os.path.join(out_dir, "path_tracer", scene))
        t1, t2 = runs_of(scene_dir, 1), runs_of(scene_dir, 2)
        for table, runs in ((1, t1), (2, t2)):
            if runs:
                n = paper[f"table{table}"]["samples"]
                batch = {r["batch"] for r in runs.values()}
                results_table(lines, f"Table {table} (N = {n}; batch {', '.join(map(str, sorted(batch)))})", runs,
                              paper[f"table{table}"]["rows"], paper_scene)
        if t1:
            ablation_table(lines, t1, paper)
        series_steps, series_seconds, series_samples = [], [], []
        for table, runs in ((1, t1), (2, t2)):
            for key, run in runs.items():
                label = f"{METHODS[key]}, N = {run['samples']}"
                mapes = [e[2] for e in run["evals"]]
                series_steps.append((label, [e[0] for e in run["evals"]], mapes))
                series_seconds.append((label, [e[1] for e in run["evals"]], mapes))
                series_samples.append((label, [e[0] * run["per_step"] / 1e6 for e in run["evals"]], mapes))
            if runs:
                time_to_quality(lines, runs, points)
        if points:
            series_steps.append(("path tracer", [], []))  # keeps its colour the same in every panel
            series_samples.append(("path tracer", [], []))
            series_seconds.append(("path tracer", [p[0] for p in points], [p[1] for p in points]))
            lines += ["Path tracer (rendering seconds, MAPE): "
                      + ", ".join(f"{t:.3g} s {m:.4f}" for t, m in points), ""]
        figure = f"{scene}-curves.svg"
        svg_curves(os.path.join(out_dir, figure), f"MAPE during training: {scene}",
                   [("against steps", "step", series_steps),
                    ("against seconds", "seconds (training; path tracer: rendering)", series_seconds),
                    ("against samples seen", "incident samples trained on (millions)", series_samples)])
        lines += [f"![MAPE against steps, seconds and samples seen]({figure})", ""]
    with open(os.path.join(out_dir, "tables.md.tmp"), "w") as f:
        f.write("\n".join(lines))
    os.replace(os.path.join(out_dir, "tables.md.tmp"), os.path.join(out_dir, "tables.md"))
    print(f"tables: {os.path.join(out_dir, 'tables.md')}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
