"""The Python chapter's speed numbers: the package against the command line on the same data.

    python python/examples/speed.py [--cli PATH] [--runs 3]

1. `import tensorglyph` and the first image of the demo field grid40, in a fresh interpreter,
   against `tensorglyph render --demo grid40 -o g.png -q` (wall clock of each process, to the image in
   memory or on disk);
2. a second `render` in the same process against the first (the renderer's device and
   pipelines are kept);
3. a whole-brain DIPY TensorFit (128×128×70, DIPY's TensorFit from eigenvalues and
   eigenvectors) to its default image, against the command line on the same tensors saved as
   DIPY saves them (5-D lower triangle, float32, gzip).

Prints a Markdown table (median of --runs runs)."""

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np


def wall(cmd):
    t = time.perf_counter()
    subprocess.run(cmd, check=True, capture_output=True)
    return time.perf_counter() - t


def brain_fit(shape=(128, 128, 70), seed=1):
    """A synthetic brain-sized fit: an ellipsoidal head of white-matter-like tensors whose
    principal direction turns with position, CSF-like spheres inside, zeros outside."""
    from dipy.core.gradients import gradient_table
    from dipy.reconst.dti import TensorFit, TensorModel

    x, y, z = np.meshgrid(*[np.linspace(-1, 1, n) for n in shape], indexing="ij")
    inside = x**2 + y**2 + (z * 1.2) ** 2 < 0.9
    theta = np.arctan2(y, x) + np.pi / 2
    e1 = np.stack([np.cos(theta), np.sin(theta), 0.3 * z], axis=-1)
    e1 /= np.linalg.norm(e1, axis=-1, keepdims=True)
    e3 = np.stack([np.zeros_like(x), np.zeros_like(x), np.ones_like(x)], axis=-1)
    e3 -= (e3 * e1).sum(-1, keepdims=True) * e1
    e3 /= np.linalg.norm(e3, axis=-1, keepdims=True)
    e2 = np.cross(e3, e1)
    rng = np.random.default_rng(seed)
    l1 = rng.uniform(1.2e-3, 1.8e-3, shape)
    l2 = rng.uniform(0.3e-3, 0.6e-3, shape)
    l3 = rng.uniform(0.2e-3, 0.4e-3, shape)
    evals = np.stack([l1, l2, l3], -1) * inside[..., None]
    evecs = np.stack([e1, e2, e3], -1)
    params = np.concatenate([evals, evecs.reshape(shape + (9,))], -1)
    bvals = np.array([0.0] + [1000.0] * 6)
    bvecs = np.vstack([[0, 0, 0], np.eye(3), np.array([[1, 1, 0], [1, 0, 1], [0, 1, 1]]) / np.sqrt(2)])
    return TensorFit(TensorModel(gradient_table(bvals, bvecs=bvecs)), params)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cli", default=str(Path(sys.executable).with_name("tensorglyph")))
    ap.add_argument("--runs", type=int, default=3)
    a = ap.parse_args()
    tmp = Path(tempfile.mkdtemp())
    med = statistics.median
    rows = []

    cli = med(wall([a.cli, "render", "--demo", "grid40", "-o", str(tmp / "g.png"), "-q"]) for _ in range(a.runs))
    py = med(wall([sys.executable, "-c", "import tensorglyph as tg; tg.render(demo='grid40')"]) for _ in range(a.runs))
    rows.append(("import + first image of grid40 (process wall clock)", py, cli, py / cli, "≤ 1.5"))

    import tensorglyph as tg

    r = tg.Renderer()
    t = time.perf_counter(); r.render(demo="grid40"); first = time.perf_counter() - t
    seconds = []
    for _ in range(a.runs):
        t = time.perf_counter(); r.render(demo="grid40"); seconds.append(time.perf_counter() - t)
    second = med(seconds)
    rows.append(("second render of grid40 in the process, against the first", second, first, second / first, "≤ 0.5"))

    import nibabel as nib
    from dipy.io.utils import nifti1_symmat
    from dipy.reconst.dti import lower_triangular

    affine = np.diag([1.8, 1.8, 2.0, 1.0]); affine[:3, 3] = [-115, -115, -70]
    fit = brain_fit()
    path = tmp / "brain.nii.gz"
    nib.save(nifti1_symmat(lower_triangular(fit.quadratic_form).astype(np.float32), affine), str(path))
    cli = med(wall([a.cli, "render", str(path), "-o", str(tmp / "b.png"), "-q"]) for _ in range(a.runs))
    seconds = []
    for _ in range(a.runs):
        fit = brain_fit()  # DIPY computes quadratic_form on first use: part of the cost
        t = time.perf_counter(); tg.render(fit, affine=affine); seconds.append(time.perf_counter() - t)
    py = med(seconds)
    rows.append(("whole-brain TensorFit 128×128×70 to its default image, against the CLI on its file", py, cli, py / cli, "≤ 2"))

    print("| measurement | Python (s) | against (s) | ratio | target |")
    print("|---|---|---|---|---|")
    for name, p, c, ratio, target in rows:
        print(f"| {name} | {p:.2f} | {c:.2f} | {ratio:.2f} | {target} |")


if __name__ == "__main__":
    main()
