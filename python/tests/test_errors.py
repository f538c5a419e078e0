"""Bad input gives a ValueError (``tensorglyph.Error``) of one line naming the problem, or a
FileNotFoundError / OSError for files, and the interpreter goes on."""

import numpy as np
import pytest

import tensorglyph as tg
from test_truth import random_tensors


def one_line(excinfo):
    text = str(excinfo.value)
    assert text and "\n" not in text, repr(text)
    assert "panic" not in text.lower()
    return text


@pytest.mark.parametrize(
    "call, words",
    [
        (lambda: tg.render(np.ones((4, 4, 4, 5))), "(4, 4, 4, 5)"),
        (lambda: tg.render(np.ones((4, 4, 6)), layout="fsl"), "lattice"),
        (lambda: tg.render(np.full((3, 3, 3, 6), np.nan), layout="fsl"), "no"),
        (lambda: tg.render(np.ones((3, 3, 3, 6)), layout="upper"), "layout 'upper'"),
        (lambda: tg.render(np.ones((3, 3, 3, 6))), "layout="),
        (lambda: tg.render(random_tensors((3, 3, 3)), affine=np.eye(3)), "4×4"),
        (lambda: tg.render(random_tensors((3, 3, 3)), affine=np.diag([1.0, 0.0, 1.0, 1.0])), "singular"),
        (lambda: tg.render(random_tensors((3, 3, 3)), affine=np.full((4, 4), np.nan)), "affine"),
        (lambda: tg.render(random_tensors((3, 3, 3)), frame="scanner"), "frame 'scanner'"),
        (lambda: tg.render(random_tensors((5,)), positions=np.zeros((4, 3))), "positions"),
        (lambda: tg.render(demo="grid:3", view="up"), "view='up': "),
        (lambda: tg.render(demo="grid:3", glyph="banana"), "glyph='banana': not one of: ellipsoid"),
        (lambda: tg.render(demo="grid:3", glyhp="cylinder"), "glyhp=: no such option (did you mean glyph=?)"),
        (lambda: tg.render(demo="grid:3", size=(0, 10)), "size='0x10': "),
        (lambda: tg.render(demo="grid:3", ssaa=0), "ssaa=0: "),
        (lambda: tg.render(demo="grid:3", method="sigg", splat=16), "splat= applies to"),
        (lambda: tg.render(demo="grid:3", preset="splat", baseline=True), "preset= cannot be used with baseline="),
        (lambda: tg.read(np.ones((3, 3, 3, 6)), layout="fsl", array="x"), "apply to files"),
        (lambda: tg.render(demo="grid:3", output="x.png"), "image.save"),
        (lambda: tg.render("data.txt.vtk.nope"), "data.txt.vtk.nope"),
    ],
)
def test_bad_input_is_a_value_error_of_one_line(call, words):
    with pytest.raises(ValueError) as e:
        call()
    assert isinstance(e.value, tg.Error)
    assert words in one_line(e), str(e.value)
    # The interpreter goes on, and so does the renderer.
    assert tg.render(demo="grid:2", size=(32, 24)).array.shape == (24, 32, 3)


def test_files_that_are_not_there_or_broken(tmp_path):
    with pytest.raises(FileNotFoundError) as e:
        tg.render(tmp_path / "missing.nii.gz")
    assert isinstance(e.value, tg.Error) and "missing.nii.gz" in one_line(e)
    with pytest.raises(FileNotFoundError):
        tg.read(tmp_path / "missing.vtk")
    good = tmp_path / "t.vtk"
    from conftest import run_cli

    run_cli("demo", "--write-vtk", good, "-q")
    cut = tmp_path / "cut.vtk"
    cut.write_bytes(good.read_bytes()[: good.stat().st_size // 2])
    with pytest.raises(ValueError) as e:
        tg.read(cut)
    assert "cut.vtk" in one_line(e)
    with pytest.raises(OSError) as e:
        tg.read(tmp_path)  # a folder
    assert isinstance(e.value, tg.Error)
    with pytest.raises(OSError):
        tg.render(demo="grid:2").save(tmp_path / "no" / "such" / "folder.png")
    assert len(tg.read(good)) == 64000


@pytest.mark.parametrize(
    "keywords",
    [{"glyph": "banana"}, {"view": "up"}, {"size": (0, 10)}, {"ssaa": 0}, {"glyhp": "cylinder"}],
)
def test_option_errors_name_no_command_line_flag(keywords):
    """A Python user never typed ``--glyph <GLYPH>``: the message names the keyword."""
    with pytest.raises(tg.Error) as e:
        tg.render(demo="grid:3", **keywords)
    text = one_line(e)
    assert "--" not in text and "<" not in text, text
