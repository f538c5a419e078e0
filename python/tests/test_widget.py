"""The notebook widget's frames and mouse handling, without a browser: events are fed to it as
jupyter_rfb delivers them, frames taken as jupyter_rfb takes them."""

import os

import numpy as np
import pytest

if os.environ.get("TENSORGLYPH_NOTEBOOK_TESTS") == "1":
    import jupyter_rfb  # noqa: F401  (CI installs the notebook extras: they must be there)
else:
    pytest.importorskip("jupyter_rfb")

import tensorglyph as tg
from test_truth import random_tensors


def test_frames_are_the_renderers_images_at_the_widgets_size():
    w = tg.widget(demo="grid:5", size=(200, 150), glyph="capsule")
    frame = w.get_frame()
    assert frame.shape == (150, 200, 3) and frame.dtype == np.uint8
    same = tg.render(demo="grid:5", size=(200, 150), glyph="capsule", azimuth=0.0, elevation=0.0, zoom=1.0)
    assert np.array_equal(frame, same.array)
    w.handle_event({"event_type": "resize", "width": 120, "height": 80, "pixel_ratio": 2.0})
    assert w.get_frame().shape == (160, 240, 3)


def test_dragging_orbits_and_the_wheel_zooms():
    w = tg.widget(random_tensors((5, 5, 3)), size=(160, 120), slice="all")
    first = w.get_frame()
    w.handle_event({"event_type": "pointer_down", "x": 50, "y": 50, "button": 1, "buttons": [1]})
    w.handle_event({"event_type": "pointer_move", "x": 90, "y": 30, "button": 0, "buttons": [1]})
    w.handle_event({"event_type": "pointer_up", "x": 90, "y": 30, "button": 1, "buttons": []})
    assert (w.azimuth, w.elevation) == ((0.0 - 40 * w.DEGREES_PER_PIXEL) % 360, -20 * w.DEGREES_PER_PIXEL)
    orbited = w.get_frame()
    assert not np.array_equal(first, orbited)
    assert np.array_equal(orbited, tg.render(random_tensors((5, 5, 3)), size=(160, 120), slice="all",
                                             azimuth=w.azimuth, elevation=w.elevation).array)
    # Moving without a button pressed does nothing.
    w.handle_event({"event_type": "pointer_move", "x": 10, "y": 10, "button": 0, "buttons": []})
    assert w.azimuth == (0.0 - 40 * w.DEGREES_PER_PIXEL) % 360
    w.handle_event({"event_type": "wheel", "dx": 0, "dy": -200, "x": 5, "y": 5})
    assert w.zoom == pytest.approx(w.ZOOM_PER_NOTCH**2)
    assert w.last_info["glyphs_total"] == 75


def test_a_file_is_read_once(tmp_path):
    from conftest import run_cli

    path = tmp_path / "g.vtk"
    run_cli("demo", "--write-vtk", path, "-q")
    w = tg.widget(path, size=(64, 48))
    assert isinstance(w.field, tg.Field) and len(w.field) == 64000
    assert w.get_frame().shape == (48, 64, 3)
