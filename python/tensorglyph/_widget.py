"""A notebook widget on jupyter_rfb: every frame is rendered by the Rust renderer (the process's
shared one), dragging orbits the camera and the wheel zooms. The event handling is plain
Python, so it is tested without a browser (``python/tests/test_widget.py``)."""

from __future__ import annotations

from typing import Any

import numpy as np

try:
    from jupyter_rfb import RemoteFrameBuffer
except ImportError as e:  # pragma: no cover - the message is the point
    raise ImportError(
        "tensorglyph.widget needs jupyter_rfb: pip install tensorglyph[notebook]"
    ) from e

from . import Field, _field, read, render


class GlyphWidget(RemoteFrameBuffer):
    """Glyphs in a notebook: drag to orbit (azimuth, elevation), wheel to zoom. The field is
    read or converted once; each frame renders it at the widget's size with the options
    given, the camera's azimuth, elevation and zoom replaced by the mouse's."""

    #: Degrees of orbit per pixel dragged.
    DEGREES_PER_PIXEL = 0.5
    #: Zoom factor per wheel notch (100 units of dy).
    ZOOM_PER_NOTCH = 1.15

    def __init__(self, data: Any = None, **options: Any):
        super().__init__()
        placement = {k: options.pop(k) for k in ("affine", "layout", "frame", "positions") if k in options}
        if isinstance(data, (str, bytes)) or hasattr(data, "__fspath__"):
            self.field = read(data, **{k: v for k, v in placement.items() if k in ("layout", "frame")})
        elif isinstance(data, Field) or data is None:
            self.field = data
        else:
            self.field = Field(_field(data, placement.get("affine"), placement.get("layout"),
                                        placement.get("frame"), placement.get("positions"), []))
        self.demo = options.pop("demo", None)
        self.azimuth = float(options.pop("azimuth", 0.0))
        self.elevation = float(options.pop("elevation", 0.0))
        self.zoom = float(options.pop("zoom", 1.0))
        size = options.pop("size", (640, 480))
        self.frame_size = (int(size[0]), int(size[1]))
        self.pixel_ratio = 1.0
        self.options = options
        self.css_width = f"{self.frame_size[0]}px"
        self.css_height = f"{self.frame_size[1]}px"
        self._drag = None
        self.last_info: dict = {}

    def handle_event(self, event: dict) -> None:
        kind = event.get("event_type")
        if kind == "resize":
            w, h = event.get("width", 0), event.get("height", 0)
            self.pixel_ratio = float(event.get("pixel_ratio", 1.0) or 1.0)
            if w >= 1 and h >= 1:
                self.frame_size = (int(w), int(h))
                self.request_draw()
        elif kind == "pointer_down":
            self._drag = (event.get("x", 0.0), event.get("y", 0.0))
        elif kind == "pointer_up":
            self._drag = None
        elif kind == "pointer_move" and self._drag is not None and event.get("buttons"):
            x, y = event.get("x", 0.0), event.get("y", 0.0)
            dx, dy = x - self._drag[0], y - self._drag[1]
            self._drag = (x, y)
            self.azimuth = (self.azimuth - dx * self.DEGREES_PER_PIXEL) % 360.0
            self.elevation = float(np.clip(self.elevation + dy * self.DEGREES_PER_PIXEL, -89.0, 89.0))
            self.request_draw()
        elif kind == "wheel":
            notches = event.get("dy", 0.0) / 100.0
            self.zoom = float(np.clip(self.zoom * self.ZOOM_PER_NOTCH ** (-notches), 0.05, 50.0))
            self.request_draw()

    def frame_options(self) -> dict:
        """The render options of the next frame."""
        w, h = self.frame_size
        r = self.pixel_ratio
        return dict(
            self.options,
            size=(max(1, round(w * r)), max(1, round(h * r))),
            azimuth=self.azimuth,
            elevation=self.elevation,
            zoom=self.zoom,
        )

    def get_frame(self) -> np.ndarray:
        image = render(self.field, demo=self.demo, **self.frame_options())
        self.last_info = image.info
        return image.array
