"""``tensorglyph.report`` against the command line's ``report`` (the same figures, pixel for
pixel) and the page's FA and MD against numpy's of the maps nibabel reads (tests/data/bids)."""

import re

import numpy as np
import pytest

import tensorglyph
from conftest import REPO, require, run_cli

BIDS = REPO / "tests" / "data" / "bids" / "derivatives"
SUB01 = BIDS / "sub-01" / "dwi" / "sub-01_model-DTI_param-tensor_dwimap.nii.gz"
SUB04 = BIDS / "sub-04" / "dwi" / "sub-04_model-DTI_param-tensor_dwimap.nii.gz"


def pixels(path):
    Image = require("PIL.Image")
    with Image.open(path) as im:
        return np.asarray(im.convert("RGBA"))


def figures(folder):
    return sorted(p.relative_to(folder) for p in folder.rglob("*.png"))


def test_the_bids_form_writes_what_the_command_line_writes(tmp_path):
    cli, py = tmp_path / "cli", tmp_path / "py"
    p = run_cli("report", BIDS, cli, "participant", "--participant-label", "01", "04", check=False)
    assert p.returncode == 1, p.stderr
    done = tensorglyph.report(bids_dir=BIDS, out_dir=py, participant_label=["01", "sub-04"])
    assert list(done["written"]) == ["sub-01"]
    assert list(done["failed"]) == ["sub-04"]
    # The command line's error line, without its "error: ".
    assert "error: " + done["failed"]["sub-04"] in p.stderr
    assert not (py / "sub-04.html").exists() and not (py / "sub-04").exists()
    written = done["written"]["sub-01"]
    assert written["page"] == str(py / "sub-01.html")
    assert len(written["figures"]) == 3
    assert figures(cli) == figures(py) and len(figures(py)) == 3
    for f in figures(py):
        assert np.array_equal(pixels(cli / f), pixels(py / f)), f
    assert (py / "dataset_description.json").exists()


def row(page, name):
    m = re.search(rf"<th>{name}</th><td>min (\S+), median (\S+), mean (\S+), max (\S+)</td>", page)
    assert m, name
    return [float(v) for v in m.groups()]


def test_the_files_form_and_the_numbers_on_the_page(tmp_path):
    nib = require("nibabel")
    done = tensorglyph.report([SUB01, SUB04], tmp_path)
    name = "sub-01_model-DTI_param-tensor_dwimap"
    assert list(done["written"]) == [name]
    assert list(done["failed"]) == ["sub-04_model-DTI_param-tensor_dwimap"]
    page = (tmp_path / f"{name}.html").read_text()
    # numpy's truth of what nibabel reads: BEP016's Dxx, Dxy, Dxz, Dyy, Dyz, Dzz; FA and MD do
    # not depend on the frame the tensors are in.
    d = np.asarray(nib.load(str(SUB01)).dataobj, dtype=np.float64).reshape(-1, 6)
    t = np.stack(
        [d[:, [0, 1, 2]], d[:, [1, 3, 4]], d[:, [2, 4, 5]]], axis=1
    )
    valid = np.all(np.isfinite(d), axis=1) & np.any(d != 0, axis=1)
    w = np.linalg.eigvalsh(t[valid])
    md = w.mean(axis=1)
    fa = np.sqrt(1.5 * ((w - md[:, None]) ** 2).sum(axis=1) / (w**2).sum(axis=1))
    # The page rounds FA to 4 decimals, MD to 4 significant digits.
    for name_, values, rtol, atol in [("FA", fa, 0, 6e-5), ("MD", md, 6e-4, 0)]:
        want = [values.min(), np.median(values), values.mean(), values.max()]
        got = row(page, name_)
        assert np.allclose(got, want, rtol=rtol, atol=atol), (name_, got, want)
    assert f"{int(valid.sum())} valid" in page


def test_usage_errors_raise(tmp_path):
    with pytest.raises(tensorglyph.Error):
        tensorglyph.report(out_dir=tmp_path)
    with pytest.raises(tensorglyph.Error):
        tensorglyph.report([SUB01], tmp_path, bids_dir=BIDS)
    with pytest.raises(ValueError, match="no participant 99"):
        tensorglyph.report(bids_dir=BIDS, out_dir=tmp_path, participant_label="99")
    with pytest.raises(tensorglyph.Error):
        tensorglyph.report([SUB01])


def test_the_figure_options_are_the_command_lines(tmp_path):
    # tile_size and zoom_region (as text and as four numbers) draw what --tile-size and
    # --zoom-region draw, pixel for pixel; the caption names the region asked for.
    cli, py, seq = tmp_path / "cli", tmp_path / "py", tmp_path / "seq"
    run_cli("report", SUB01, "-o", cli, "--tile-size", "320", "--zoom-region", "4,5,2:6")
    done = tensorglyph.report(SUB01, py, tile_size=320, zoom_region="4,5,2:6")
    assert list(done["written"]) == ["sub-01_model-DTI_param-tensor_dwimap"]
    tensorglyph.report(SUB01, seq, tile_size=320, zoom_region=(4, 5, 2, 6))
    assert figures(cli) == figures(py) == figures(seq) and len(figures(py)) == 3
    for f in figures(py):
        a = pixels(cli / f)
        assert np.array_equal(a, pixels(py / f)), f
        assert np.array_equal(a, pixels(seq / f)), f
        # Five 320-px tiles at most, the inset and the 200-px legend.
        assert (a.shape[1] - 200 - a.shape[0]) % 320 == 0, a.shape
    page = (py / "sub-01_model-DTI_param-tensor_dwimap.html").read_text()
    assert "as asked (zoom region)" in page
    assert "px per voxel" in page


@pytest.mark.parametrize(
    "options, keyword",
    [
        ({"tile_size": 64}, "tile_size"),
        ({"tile_size": "wide"}, "tile_size"),
        ({"tile_size": True}, "tile_size"),
        ({"zoom_region": "4,5:6"}, "zoom_region"),
        ({"zoom_region": "4,5,2:1"}, "zoom_region"),
        ({"zoom_region": (4, 5, 2)}, "zoom_region"),
        ({"zoom_region": (-1, 5, 2, 6)}, "zoom_region"),
        ({"sh_basis": "mrtrix"}, "sh_basis"),
        ({"sh_basis": 8}, "sh_basis"),
        ({"odf_normalize": "mean"}, "odf_normalize"),
    ],
)
def test_bad_figure_options_raise_naming_the_keyword(tmp_path, options, keyword):
    with pytest.raises(tensorglyph.Error, match=keyword):
        tensorglyph.report(SUB01, tmp_path / "out", **options)
    assert not (tmp_path / "out").exists()
