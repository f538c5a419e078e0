"""ODF glyphs from Python: a DIPY CSD fit renders as the command line renders the NIfTI file of
its ``shm_coeff`` saved by nibabel, pixel for pixel, and a file of SH series (MRtrix's
``dwi2fod`` output) as the command line renders it; DIPY's peaks (``PeaksAndMetrics``) as the
command line renders the peak files DIPY saved of them."""

import numpy as np
import pytest

import tensorglyph as tg
from conftest import REPO, cli_render, require, same_pixels


def test_a_file_of_sh_series_renders_as_the_command_line_renders_it(tmp_path):
    path = REPO / "tests" / "data" / "sh" / "mrtrix_lmax8.mif"
    image = tg.render(path, size=(160, 120))
    assert image.info["glyph"] == "odf"
    same_pixels(image, cli_render(path, tmp_path, "--size", "160x120"))


def test_a_csd_fit_renders_as_its_saved_series(tmp_path):
    require("dipy")
    nib = require("nibabel")
    from dipy.core.gradients import gradient_table
    from dipy.data import get_fnames
    from dipy.io import read_bvals_bvecs
    from dipy.reconst.csdeconv import ConstrainedSphericalDeconvModel, auto_response_ssst

    dwi, bval, bvec = get_fnames(name="small_64D")
    img = nib.load(dwi)
    data = np.asarray(img.dataobj, dtype=np.float64)
    bvals, bvecs = read_bvals_bvecs(bval, bvec)
    gtab = gradient_table(bvals, bvecs=bvecs)
    response, _ = auto_response_ssst(gtab, data, roi_radii=10, fa_thr=0.7)
    block = img.slicer[3:7, 3:7, 3:7]
    fit = ConstrainedSphericalDeconvModel(gtab, response, sh_order_max=8).fit(data[3:7, 3:7, 3:7])
    image = tg.render(fit, affine=block.affine, size=(160, 120))
    assert image.info["glyph"] == "odf"
    assert image.info["glyphs_drawn"] == 16, image.info
    path = tmp_path / "fod.nii.gz"
    nib.save(nib.Nifti1Image(np.asarray(fit.shm_coeff, dtype=np.float64), block.affine), path)
    same_pixels(image, cli_render(path, tmp_path, "--size", "160x120"))
    # A fit in SH holds no tensors to read.
    with pytest.raises(tg.Error, match="holds no tensors"):
        tg.read(fit, affine=block.affine)


def test_odf_normalize_is_the_command_lines(tmp_path):
    path = REPO / "tests" / "data" / "sh" / "mrtrix_lmax8.mif"
    for how in ["minmax", "none"]:
        image = tg.render(path, size=(160, 120), odf_normalize=how)
        same_pixels(image, cli_render(path, tmp_path, "--size", "160x120", "--odf-normalize", how))
    with pytest.raises(ValueError, match="odf_normalize= applies to files of SH series"):
        tg.render(REPO / "tests" / "data" / "extremes" / "needles.vtk", odf_normalize="max")


def test_dipy_peaks_render_as_the_files_dipy_saved_of_them(tmp_path):
    require("dipy")
    nib = require("nibabel")
    from dipy.io.peaks import niftis_to_pam

    sh = REPO / "tests" / "data" / "sh"
    dirs = nib.load(sh / "dipy5d_peak_dirs.nii.gz")
    values = np.asarray(nib.load(sh / "dipy5d_peak_values.nii.gz").dataobj)
    indices = np.zeros(values.shape, dtype=np.int32)
    # DIPY's own loader of the files makes the PeaksAndMetrics (its affine the files').
    pam = niftis_to_pam(dirs.affine, np.asarray(dirs.dataobj), values, indices)
    image = tg.render(pam, size=(160, 120))
    assert image.info["glyph"] == "cylinder", image.info
    assert image.info["glyphs_drawn"] > 0, image.info
    same_pixels(image, cli_render(sh / "dipy5d_peak_dirs.nii.gz", tmp_path, "--size", "160x120"))
    with pytest.raises(tg.Error, match="peaks hold no tensors"):
        tg.read(pam)


def test_the_peaks_of_a_file_of_sh_series_are_the_command_lines(tmp_path):
    path = REPO / "tests" / "data" / "sh" / "mrtrix_lmax8.mif"
    image = tg.render(path, size=(160, 120), glyph="peaks")
    assert image.info["glyph"] == "cylinder", image.info
    same_pixels(image, cli_render(path, tmp_path, "--size", "160x120", "--glyph", "peaks"))


def test_peaks_over_odfs_are_the_command_lines(tmp_path):
    path = REPO / "tests" / "data" / "sh" / "mrtrix_lmax8.mif"
    image = tg.render(path, size=(160, 120), peaks=True)
    alone = tg.render(path, size=(160, 120), glyph="peaks")
    assert image.info["glyph"] == "odf", image.info
    # The 16 ODFs of the middle slice and the sticks `glyph="peaks"` draws alone.
    assert image.info["glyphs_drawn"] == 16 + alone.info["glyphs_drawn"], image.info
    same_pixels(image, cli_render(path, tmp_path, "--size", "160x120", "--peaks"))
    with pytest.raises(ValueError, match="shadows= .*not with peaks= over ODFs"):
        tg.render(path, peaks=True, shadows=True)
