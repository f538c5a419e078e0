"""Fields: eigenvalues and eigenvectors against numpy's eigh, info against ``info --json``."""

import numpy as np
import pytest

import tensorglyph as tg
from conftest import REPO, cli_info, save_dipy_tensors
from test_truth import OBLIQUE, random_tensors, six


def polar(m):
    u, _, vt = np.linalg.svd(m)
    return u @ vt


def check_eigen(values, vectors, world):
    """``values``/``vectors`` against numpy's eigh of the symmetric ``world`` tensors, to 1e-12
    of each tensor's largest eigenvalue."""
    w, v = np.linalg.eigh(world)
    w, v = w[..., ::-1], v[..., ::-1]
    scale = np.abs(w).max(axis=-1, keepdims=True)
    assert np.all(np.abs(values - w) <= 1e-12 * scale)
    # Vectors: each matches numpy's up to sign, and V Λ Vᵀ rebuilds the tensor.
    dots = np.abs(np.einsum("...ik,...ik->...k", vectors, v))
    assert np.all(np.abs(dots - 1.0) <= 1e-10)
    rebuilt = np.einsum("...ik,...k,...jk->...ij", vectors, values, vectors)
    assert np.all(np.abs(rebuilt - world) <= 1e-12 * scale[..., None])


def test_eigen_of_a_lattice_is_numpys_eigh_in_world_axes():
    t = random_tensors((5, 4, 3), seed=21)
    field = tg.Field.from_array(six(t, "nifti"), layout="nifti", affine=OBLIQUE)
    values, vectors = field.eigen()
    assert values.shape == (5, 4, 3, 3) and vectors.shape == (5, 4, 3, 3, 3)
    r = polar(OBLIQUE[:3, :3])
    check_eigen(values, vectors, r @ t @ r.T)


def test_eigen_of_a_dipy_fit_is_dipys_and_numpys(dipy_fits):
    fit, affine = dipy_fits["small_101D"]
    values, vectors = tg.Field.from_array(fit.quadratic_form, affine=affine).eigen()
    r = polar(affine[:3, :3])
    q = np.asarray(fit.quadratic_form)
    check_eigen(values, vectors, r @ q @ r.T)
    # The eigenvalues do not depend on the frame: DIPY's own.
    assert np.allclose(values, fit.evals, rtol=0, atol=1e-12 * np.abs(fit.evals).max())


def test_eigen_of_points_and_of_nan_tensors():
    t = random_tensors((10,), seed=2)
    t[3] = np.nan
    values, vectors = tg.Field.from_array(t, positions=np.zeros((10, 3))).eigen()
    assert values.shape == (10, 3) and np.isnan(values[3]).all() and np.isnan(vectors[3]).all()
    keep = np.arange(10) != 3
    check_eigen(values[keep], vectors[keep], t[keep])


def test_info_is_info_json_of_the_same_file(tmp_path):
    path = REPO / "tests" / "data" / "dti" / "dipy_small101" / "tensors.nii.gz"
    assert tg.read(path).info(samples=[0, 5]) == cli_info(path, "--sample", "0", "--sample", "5")
    assert tg.read(path, layout="mrtrix").info() == cli_info(path, "--order", "mrtrix")


def test_info_of_a_fit_is_info_json_of_its_saved_tensors(dipy_fits, tmp_path):
    fit, affine = dipy_fits["small_64D"]
    path = save_dipy_tensors(fit, affine, tmp_path / "t.nii.gz")
    lower = np.asarray(fit.quadratic_form)[..., [0, 1, 1, 2, 2, 2], [0, 0, 1, 0, 1, 2]]
    ours = tg.Field.from_array(lower, layout="nifti", affine=affine).info(samples=[1])
    theirs = cli_info(path, "--sample", "1")
    # What differs is what it was read from: an array, its layout given, not a NIfTI file.
    assert (ours["format"], ours["tensor_array"]) == ("array", {"name": "array", "components": 6, "location": "point"})
    assert ours["layout"] == {"order": "nifti", "why": "flag"} and theirs["layout"]["why"] == "file"
    assert ours["frame"]["source"] == "affine" and theirs["frame"]["source"] == "sform"
    for key in ("format", "tensor_array", "layout", "frame"):
        ours.pop(key), theirs.pop(key)
    assert ours == theirs


def test_a_bep016_map_is_read_through_its_sidecar_as_the_cli_reads_it():
    path = (REPO / "tests" / "data" / "bids" / "derivatives" / "sub-02" / "dwi"
            / "sub-02_model-DTI_param-tensor_dwimap.nii.gz")
    info = tg.read(path).info(samples=[0])
    assert info == cli_info(path, "--sample", "0")
    assert info["layout"] == {"order": "fsl", "why": "sidecar"}
    assert info["frame"]["tensor_frame"] == "world"
    assert info["bep016_sidecar"] == {"name": "sub-02_model-DTI_dwimap.json", "reference_axes": "xyz"}


def test_read_takes_what_render_takes(dipy_fits, tmp_path):
    """One signature: ``read(fit, affine=...)`` is the field ``render(fit, affine=...)`` draws,
    and its eigenvalues are DIPY's own."""
    fit, affine = dipy_fits["small_101D"]
    field = tg.read(fit, affine=affine)
    values, _ = field.eigen()
    finite = np.isfinite(values).all(axis=-1)
    assert np.allclose(values[finite], np.asarray(fit.evals)[finite], rtol=0, atol=1e-12 * np.abs(fit.evals).max())
    a = tg.render(field, size=(96, 72)).array
    b = tg.render(fit, affine=affine, size=(96, 72)).array
    assert np.array_equal(a, b)
    t = random_tensors((4, 3, 2), seed=5)
    assert len(tg.read(six(t, "fsl"), layout="fsl", affine=OBLIQUE)) == 24
    assert len(tg.read(t[:, 0, 0], positions=np.zeros((4, 3)))) == 4
    with pytest.raises(tg.Error):
        tg.read("tests/data/missing.vtk", affine=np.eye(4))
