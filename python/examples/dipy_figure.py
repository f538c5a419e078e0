"""The Python chapter's DIPY example: fit tensors to a DWI set DIPY ships, and draw them.

    python python/examples/dipy_figure.py [OUT.png]

writes docs/images/python_dipy.png (the book's figure) unless OUT.png is given; run from the
repository's top folder. python/tests/test_notebook.py runs it."""

import sys

import nibabel as nib
from dipy.core.gradients import gradient_table
from dipy.data import get_fnames
from dipy.io.gradients import read_bvals_bvecs
from dipy.reconst.dti import TensorModel

import tensorglyph as tg

# --8<-- [start:example]
fdwi, fbval, fbvec = get_fnames(name="small_64D")  # a 10x10x10 DWI set, 64 directions
img = nib.load(fdwi)
bvals, bvecs = read_bvals_bvecs(str(fbval), str(fbvec))
fit = TensorModel(gradient_table(bvals, bvecs=bvecs)).fit(img.get_fdata())

image = tg.render(fit, affine=img.affine, size=(800, 600), glyph="superquadric",
                  underlay="fa", outlines=0.5, ssaa=2, legend=True)
print(image.info["glyphs_drawn"], "glyphs,", image.info["backend"] or "reference")
# --8<-- [end:example]
image.save(sys.argv[1] if len(sys.argv) > 1 else "docs/images/python_dipy.png")
