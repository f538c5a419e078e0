"""Images from Python against the command line on the same tensors saved as files: the same
pixels, every one. The tensors are DIPY's fits of real DWI sets (the small sets DIPY's wheel
ships), random tensors in every layout, and tensors at points."""

import numpy as np
import pytest

import tensorglyph as tg
from conftest import cli_render, read_png, same_pixels, save_dipy_tensors

DATASETS = ("small_101D", "small_64D", "small_25")


@pytest.mark.parametrize("name", DATASETS)
def test_a_dipy_fit_renders_as_the_cli_renders_its_saved_tensors(dipy_fits, name, tmp_path):
    fit, affine = dipy_fits[name]
    path = save_dipy_tensors(fit, affine, tmp_path / "tensors.nii.gz")
    image = tg.render(fit, affine=affine, size=(320, 240))
    same_pixels(image, cli_render(path, tmp_path, "--size", "320x240"))
    # DTI defaults, as for the file: direction-encoded colour on black, the middle slice.
    assert image.info["glyphs_selected"] < image.info["glyphs_total"]
    assert (image.array[0, 0] == 0).all()


@pytest.mark.parametrize("name", DATASETS)
def test_a_nibabel_image_renders_as_the_cli_renders_its_file(dipy_fits, name, tmp_path):
    import nibabel as nib

    fit, affine = dipy_fits[name]
    path = save_dipy_tensors(fit, affine, tmp_path / "tensors.nii.gz")
    opts = ["--glyph", "superquadric", "--slice", "all", "--color", "fa", "--size", "300x200"]
    image = tg.render(nib.load(str(path)), glyph="superquadric", slice="all", color="fa", size=(300, 200))
    same_pixels(image, cli_render(path, tmp_path, *opts))
    # And the path itself, read by the command line's reader.
    same_pixels(tg.render(path, glyph="superquadric", slice="all", color="fa", size=(300, 200)),
                cli_render(path, tmp_path, *opts, name="again.png"))


def test_options_reach_the_renderer_as_the_cli_spells_them(dipy_fits, tmp_path):
    fit, affine = dipy_fits["small_64D"]
    path = save_dipy_tensors(fit, affine, tmp_path / "t.nii.gz")
    opts = dict(size=(256, 192), slice=["z=3", "x=4"], view="iso", azimuth=30.0, glyph="cylinder",
                outlines=0.6, ssaa=2, background=(0.2, 0.3, 0.4), underlay="fa", legend=True)
    args = ["--size", "256x192", "--slice", "z=3", "--slice", "x=4", "--view", "iso",
            "--azimuth", "30", "--glyph", "cylinder", "--outlines", "0.6", "--ssaa", "2",
            "--background", "0.2,0.3,0.4", "--underlay", "fa", "--legend"]
    same_pixels(tg.render(fit, affine=affine, **opts), cli_render(path, tmp_path, *args))


def random_tensors(shape, seed=7):
    """Symmetric positive-definite tensors of DTI size (1e-3 mm²/s), some anisotropic."""
    rng = np.random.default_rng(seed)
    q, _ = np.linalg.qr(rng.normal(size=shape + (3, 3)))
    lam = rng.uniform(0.2e-3, 2.0e-3, size=shape + (3,))
    return np.einsum("...ij,...j,...kj->...ik", q, lam, q)


SLOTS = {
    "fsl": [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)],
    "bep016": [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)],
    "nifti": [(0, 0), (0, 1), (1, 1), (0, 2), (1, 2), (2, 2)],
    "mrtrix": [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)],
    "vtk": [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2)],
}


def six(t, layout):
    return np.stack([t[..., i, j] for i, j in SLOTS[layout]], axis=-1)


OBLIQUE = np.array([
    [1.9, 0.3, 0.0, -10.0],
    [-0.3, 1.9, 0.2, 4.0],
    [0.0, -0.2, 2.5, 7.5],
    [0.0, 0.0, 0.0, 1.0],
], dtype=np.float32).astype(np.float64)


@pytest.mark.parametrize("layout", sorted(SLOTS))
def test_full_matrices_and_every_six_component_layout_give_one_image(layout, tmp_path):
    import nibabel as nib

    t = random_tensors((5, 4, 3))
    opts = dict(size=(200, 150), slice="all", color="fa")
    full = tg.render(t, affine=OBLIQUE, **opts)
    same_pixels(tg.render(six(t, layout), layout=layout, affine=OBLIQUE, **opts), full._rgba)
    # And the command line, on the 4-D NIfTI of the same numbers (FSL's order, voxel frame).
    path = tmp_path / "fsl.nii.gz"
    nib.save(nib.Nifti1Image(six(t, "fsl"), OBLIQUE), str(path))
    same_pixels(full, cli_render(path, tmp_path, "--size", "200x150", "--slice", "all", "--color", "fa"))


@pytest.mark.parametrize("frame", ["voxel", "fsl", "world"])
def test_the_tensor_frame_is_the_clis(frame, tmp_path):
    import nibabel as nib

    t = random_tensors((4, 4, 2), seed=3)
    path = tmp_path / "t.nii.gz"
    nib.save(nib.Nifti1Image(six(t, "fsl"), OBLIQUE), str(path))
    same_pixels(tg.render(t, affine=OBLIQUE, frame=frame, slice="all", size=(160, 120)),
                cli_render(path, tmp_path, "--tensor-frame", frame, "--slice", "all", "--size", "160x120"))


def write_vtk_points(path, positions, tensors):
    """A legacy ASCII VTK point set with 3×3 tensors, numbers written exactly (repr)."""
    n = len(positions)
    lines = ["# vtk DataFile Version 4.2", "points", "ASCII", "DATASET POLYDATA",
             f"POINTS {n} double"]
    lines += [" ".join(repr(float(x)) for x in p) for p in positions]
    lines += [f"VERTICES {n} {2 * n}"] + [f"1 {i}" for i in range(n)]
    lines += [f"POINT_DATA {n}", "TENSORS t double"]
    for m in tensors:
        lines += [" ".join(repr(float(x)) for x in row) for row in m]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_tensors_at_points_render_as_the_cli_renders_a_vtk_point_set(tmp_path):
    rng = np.random.default_rng(11)
    positions = rng.uniform(-1.0, 1.0, size=(60, 3))
    t = random_tensors((60,), seed=5) * 100.0
    path = write_vtk_points(tmp_path / "points.vtk", positions, t)
    cli = cli_render(path, tmp_path, "--size", "240x180")
    for layout in ("vtk", "nifti"):
        same_pixels(tg.render(six(t, layout), layout=layout, positions=positions, size=(240, 180)), cli)
    same_pixels(tg.render(t, positions=positions, size=(240, 180)), cli)
    # General defaults, as for a VTK file: white background.
    assert (tg.render(t, positions=positions, size=(60, 40)).array[0, 0] == 255).all()


def test_a_saved_image_is_the_clis_png_byte_for_byte(tmp_path):
    image = tg.render(demo="grid:6", size=(120, 90), outlines=True)
    image.save(tmp_path / "py.png")
    from conftest import run_cli

    run_cli("render", "--demo", "grid:6", "--size", "120x90", "--outlines", "-o", tmp_path / "cli.png", "-q")
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
    assert image.to_png() == (tmp_path / "cli.png").read_bytes()
    assert image.array.shape == (90, 120, 3) and image.array.dtype == np.uint8
    t = tg.render(demo="grid:6", size=(120, 90), transparent=True)
    assert t.array.shape == (90, 120, 4) and t.array[0, 0, 3] == 0
    assert (read_png(tmp_path / "py.png")[..., 3] == 255).all()


def test_ambient_occlusion_is_the_clis_and_darkens(tmp_path):
    from conftest import run_cli

    image = tg.render(demo="grid:6", size=(120, 90), ao=True, ao_reach=6)
    image.save(tmp_path / "py.png")
    run_cli("render", "--demo", "grid:6", "--size", "120x90", "--ao", "--ao-reach", "6",
            "-o", tmp_path / "cli.png", "-q")
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
    plain = tg.render(demo="grid:6", size=(120, 90)).array.astype(int)
    # Occlusion only darkens: never a brighter pixel, and some darker.
    assert (image.array.astype(int) <= plain + 1).all()
    assert (image.array.astype(int) < plain - 2).any()
    # The library's own check, in Python's words: the keyword, not the command line's flag.
    with pytest.raises(ValueError, match=r"^ao= takes a strength between 0 and 1") as refused:
        tg.render(demo="grid:6", size=(120, 90), ao=2)
    assert "--" not in str(refused.value)
