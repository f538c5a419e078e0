"""The example notebook (examples/dipy_glyphs.ipynb) runs top to bottom in a kernel, and the
book's DIPY example script makes its image."""

import os
import subprocess
import sys

import pytest

from conftest import REPO, require

NOTEBOOK = REPO / "examples" / "dipy_glyphs.ipynb"
required = os.environ.get("TENSORGLYPH_NOTEBOOK_TESTS") == "1"


def test_the_example_notebook_runs(tmp_path):
    if not required:
        pytest.importorskip("nbclient")
        pytest.importorskip("ipykernel")
        pytest.importorskip("jupyter_rfb")
    import nbformat
    from nbclient import NotebookClient

    nb = nbformat.read(NOTEBOOK, as_version=4)
    NotebookClient(nb, timeout=600, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}}).execute()
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])]
    assert not [o for o in outputs if o.get("output_type") == "error"]
    # The image cell shows a PNG, through Image._repr_png_.
    assert any("image/png" in o.get("data", {}) for o in outputs)


def test_the_books_dipy_example_makes_its_image(tmp_path):
    require("dipy")
    out = tmp_path / "dipy.png"
    script = REPO / "python" / "examples" / "dipy_figure.py"
    subprocess.run([sys.executable, str(script), str(out)], check=True, timeout=600)
    assert out.stat().st_size > 10_000
