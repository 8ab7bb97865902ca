"""The worked example of docs/python.md: train the bundled Cornell box for two minutes with the error logged against
a path-traced reference, render the model from three views, path-trace each view, and plot the error.

    python python/examples/three_views.py [OUT_DIR]
"""
import sys
import time
from pathlib import Path

import clradiosity as cr

root = Path(__file__).resolve().parents[2]
out = Path(sys.argv[1] if len(sys.argv) > 1 else "three-views")
out.mkdir(parents=True, exist_ok=True)

scene = cr.load_scene(root / "scenes" / "cornell-box.xml", res=128)
reference_file = out / "reference.exr"
if not reference_file.exists():
    cr.write_image(reference_file, cr.reference(scene, spp=1024))

# Two minutes of ISNR with MAPE/MSE/relMSE logged every 100 steps (outside the training time).
run = cr.train(scene, out / "run", minutes=2, reference=reference_file, eval_every=100)
trained_s = run.log[-1]["seconds"]
print(f"trained {run.steps} steps in {trained_s:.0f} s")

views = {
    "sensor": None,
    "left": [-0.6, 1.2, 3.5, 0.2, 0.8, 0, 0, 1, 0, 45],
    "low": [0.3, 0.25, 3.0, -0.2, 1.0, 0, 0, 1, 0, 50],
}
for name, camera in views.items():
    start = time.perf_counter()
    image = run.render(spp=16, camera=camera)
    model_s = time.perf_counter() - start
    reference = cr.reference(scene, spp=1024, camera=camera, seed=7)
    m = cr.compare(image, reference)
    cr.write_image(out / f"{name}.png", image)
    print(f"{name:6s} model MAPE {m['mape']:.4f}  relMSE {m['relmse']:.4f}  ({model_s:.2f} s to render)")

# The path tracer's side: the sensor's view at doubling spp until it has spent the training's time.
spp, spent = 1, 0.0
while True:
    start = time.perf_counter()
    image = cr.reference(scene, spp=spp, seed=11)
    seconds = time.perf_counter() - start
    if spent + seconds > trained_s:
        break
    spent += seconds
    best = (spp, seconds, cr.compare(image, cr.read_image(reference_file))["mape"])
    spp *= 2
print("path tracer: %d spp in %.1f s, MAPE %.4f (within the training's %.0f s)" % (best[0], best[1], best[2], trained_s))

evaluated = [row for row in run.log if row["mape"] is not None]
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5, 3.2))
    ax.loglog([r["seconds"] for r in evaluated], [r["mape"] for r in evaluated], label="ISNR (model)")
    ax.axhline(best[2], color="gray", linestyle="--", label="path tracer, %d spp" % best[0])
    ax.set_xlabel("training seconds")
    ax.set_ylabel("MAPE")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "mape.png", dpi=120)
    print("figure:", out / "mape.png")
except ImportError:
    for r in evaluated:
        print(f"step {r['step']:6.0f}  {r['seconds']:6.1f} s  MAPE {r['mape']:.4f}")
