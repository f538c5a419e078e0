"""Shared helpers of the Python tests: the command line to compare with, and the truths.

The command line is the Rust binary when ``TENSORGLYPH_CLI`` names it (CI: the one ``cargo
test`` built), else the ``tensorglyph`` console script the wheel installed."""

import importlib
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]


def require(module: str):
    """``pytest.importorskip``, except under ``CI``, which installs every test dependency: there
    a missing module fails the test instead of skipping it."""
    if os.environ.get("CI"):
        return importlib.import_module(module)
    return pytest.importorskip(module)


def cli_path() -> str:
    exe = os.environ.get("TENSORGLYPH_CLI") or shutil.which("tensorglyph")
    if not exe:
        exe = str(Path(sys.executable).with_name("tensorglyph"))
    return exe


def run_cli(*args, check=True) -> subprocess.CompletedProcess:
    p = subprocess.run(
        [cli_path(), *map(str, args)], capture_output=True, text=True, timeout=600
    )
    if check and p.returncode != 0:
        raise AssertionError(f"tensorglyph {' '.join(map(str, args))}: {p.stderr}")
    return p


def read_png(path) -> np.ndarray:
    from PIL import Image

    with Image.open(path) as im:
        return np.asarray(im.convert("RGBA"))


def cli_render(src, tmp_path, *args, name="cli.png") -> np.ndarray:
    """The RGBA pixels ``tensorglyph render`` writes for ``src`` with ``args``."""
    out = tmp_path / name
    run_cli("render", src, "-o", out, "-q", *args)
    return read_png(out)


def cli_info(src, *args) -> dict:
    return json.loads(run_cli("info", src, "--json", *args).stdout)


def same_pixels(image, rgba: np.ndarray) -> None:
    """The image's pixels are the command line's, every one."""
    ours = image._rgba
    assert ours.shape == rgba.shape, (ours.shape, rgba.shape)
    diff = np.any(ours != rgba, axis=-1)
    assert not diff.any(), f"{int(diff.sum())} of {diff.size} pixels differ"
    assert (rgba[..., :3] > 0).any(), "an image of nothing proves nothing"


@pytest.fixture(scope="session")
def dipy_fits():
    """DIPY's tensor fits of the small DWI sets its wheel ships, with their affines."""
    dipy_data = require("dipy.data")
    from dipy.core.gradients import gradient_table
    from dipy.io.gradients import read_bvals_bvecs
    from dipy.reconst.dti import TensorModel
    import nibabel as nib

    fits = {}
    for name in ("small_101D", "small_64D", "small_25"):
        fdwi, fbval, fbvec = dipy_data.get_fnames(name=name)
        img = nib.load(fdwi)
        bvals, bvecs = read_bvals_bvecs(str(fbval), str(fbvec))
        gtab = gradient_table(bvals, bvecs=bvecs)
        data = np.asarray(img.dataobj, dtype=np.float64)
        fits[name] = (TensorModel(gtab).fit(data), img.affine)
    return fits


def save_dipy_tensors(fit, affine, path):
    """The fit's tensors as DIPY's dipy_fit_dti writes them: 5-D lower triangle, intent
    SYMMATRIX, float64."""
    import nibabel as nib
    from dipy.io.utils import nifti1_symmat
    from dipy.reconst.dti import lower_triangular

    nib.save(nifti1_symmat(lower_triangular(fit.quadratic_form), affine), str(path))
    return path
