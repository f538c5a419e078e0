"""Nothing on stderr but tensorglyph's own words: without ``XDG_RUNTIME_DIR`` (containers,
batch jobs) Mesa's device-select layer would print two error lines on every render; importing
the package turns the layer off for the process (the command line does the same)."""

import os
import subprocess
import sys

SCRIPT = """
import numpy as np
import tensorglyph as tg
d = np.zeros((3, 3, 3, 6))
d[..., 0], d[..., 3], d[..., 5] = 3.0, 1.0, 0.5
image = tg.render(d, layout="fsl", size=(64, 48))
"""


def test_a_render_without_xdg_runtime_dir_says_nothing():
    env = {
        k: v
        for k, v in os.environ.items()
        if k not in ("XDG_RUNTIME_DIR", "NODEVICE_SELECT", "MESA_VK_DEVICE_SELECT")
    }
    done = subprocess.run(
        [sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    assert done.stderr == "", done.stderr
