#!/usr/bin/env python3
"""FURY 2.1's ODF glyphs (fury.actor.sph_glyph) on one axial slice of 10x10 = 100 real fibre ODFs,
the same slice that tensorglyph draws exactly (ray cast) in fury_slice.sh, at 1024x768.

The data: tests/data/sh/mrtrix_lmax8.mif (MRtrix 3.0.3 dwi2fod, 4x4x4 voxels, lmax 8, 45
coefficients in MRtrix's tournier07 basis). Its axial slice z = 1 (as docs/bench/odf/tile_slice.py
takes by default) is tiled to 10x10 (voxel (x, y) takes the fit's (x % 4, y % 4, 1)) and

  * written as a 10x10x1 MRtrix .mif for tensorglyph (--write-mif), with an identity transform
    and 1 mm voxels, so that world = voxel = the frame of the SH coefficients (MRtrix's SH are in
    scanner space; the test fit's own transform tilts its lattice 14 degrees about x, which is
    dropped here, so the two programs draw the same glyphs on the same axis-aligned grid);
  * given to FURY's sph_glyph as a (10, 10, 1, 81) array in FURY's "standard" basis.

The basis conversion: sph_glyph's shader evaluates sum_i c_i * B[v, i] with B from
fury.utils.create_sh_basis_matrix (real SH, all orders 0..lmax, m = -l..l, (lmax+1)^2 = 81
columns, Condon-Shortley phase from scipy's lpmv). basis_type="descoteaux07" is not usable in
FURY 2.1.0: the basis matrix is the 81-column standard one whatever the type, while the shader
strides it by the 45 coefficients it was given. So the 45 tournier07 coefficients c are mapped
to 81 standard ones by least squares on 2,000 directions: M = lstsq(B_fury, B_tournier), with
B_tournier from DIPY (sh_to_sf_matrix(basis_type="tournier07", legacy=False), which is MRtrix3's
basis) and B_fury from FURY's own function, so the glyph radii are what FURY's shader computes.
The script prints the fit's residual (float32 round-off when the bases span the same space) and
the largest odd-order coefficient (zero). Each ODF is then scaled to its own largest value on a
dense sphere (tensorglyph's default --odf-normalize max), and the glyph scale is 0.5, so the
largest radius is half the grid spacing (tensorglyph's --scale auto). FURY draws |f| (negative
lobes mirrored, clamped to 1), colour "orientation" (direction colours, like tensorglyph's dec).

Rendering: FURY's ShowManager with an offscreen canvas (rendercanvas), 1024x768, a perspective
camera of 30 degrees' vertical field of view (tensorglyph's default) looking down -z at the
slice's centre, white background, FURY's default lights (ambient + a light on the camera).
Anti-aliasing (--aa):
  * noaa: renderer pixel_ratio 1 (no supersampling) and ppaa "none" (no post-process AA);
  * default: what FURY/pygfx do when nothing is set: pixel_scale 2 (the scene is rendered at
    2048x1536 and filtered down, "mitchell") plus ppaa "ddaa";
  * ssaa-only (pixel_scale 2, ppaa none) and ddaa-only (pixel_ratio 1, ddaa) to split the two.

Timing: two warm-up frames (pipelines, the compute shader's first run; the camera is placed
between them, see render()), then --frames frames, the median reported. Each frame is ShowManager._draw_canvas() (canvas.force_draw(): FURY's draw
function, pygfx's render and flush, the offscreen canvas's read-back of the image). Reported:
  * frame_ms: the sum over the frame's queue submissions of submit -> device idle (each
    submission waited on at once by a blocking device poll; wgpu 0.32's
    queue.on_submitted_work_done_async() fails here with a callback type mismatch against its
    wgpu-native), the read-back copy excluded: the same measure as tensorglyph's frame_ms
    (submit, then wait for the device). pygfx submits 3 times a frame: the compute + render
    passes, a small one (0.1-0.2 ms), and the output pass (the SSAA filter and DDAA, where on);
    submit_ms_medians gives each one's median;
  * draw_ms: the whole force_draw() call's wall time (Python, encoding, the read-back included).
The compute pass that deforms the sphere meshes by the SH series runs in every frame (pygfx's
renderer dispatches every object's compute pipelines in each render): it is part of FURY's
frame. It is one invocation a glyph (workgroups of 64: 128 invocations for the 100 glyphs), each
evaluating 362 vertices x 81 coefficients and accumulating its 720 faces' normals.

Setup (this machine: Python 3.12 is needed, FURY 2.1.0 requires >=3.12):
  python3.12 -m venv /tmp/furyenv
  /tmp/furyenv/bin/pip install "fury==2.1.0" "dipy==1.12.1"
  # installs pygfx 0.17.0, wgpu 0.32.0 (wgpu-native), rendercanvas 2.7.2, numpy, scipy
  export XDG_RUNTIME_DIR=/tmp/xdg; mkdir -p $XDG_RUNTIME_DIR   # wgpu picks lavapipe (Vulkan)

usage:
  fury_slice.py [--mif IN.mif] [--write-mif OUT.mif] [--png OUT.png]
                [--aa noaa|default|both|ssaa-only|ddaa-only] [--frames N] [--fill F]
                [--json] [--check]
  The driver fury_slice.sh runs it interleaved with tensorglyph and writes fury_slice.csv.
"""
import argparse
import json
import os
import statistics
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from tile_slice import mif_header  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", "..", "..", ".."))
N = 10  # glyphs a side
Z0 = 1  # the fit's slice
SIZE = (1024, 768)
FOV = 30.0


def read_mif(path):
    """The image as an array indexed [x, y, z, volume], from MRtrix's layout (stride ranks,
    a minus sign for an axis stored from its far end)."""
    raw = open(path, "rb").read()
    end = raw.index(b"\nEND\n")
    head = {}
    for line in raw[:end].decode("latin-1").split("\n")[1:]:
        key, _, value = line.partition(":")
        head.setdefault(key.strip(), value.strip())
    dim = [int(v) for v in head["dim"].split(",")]
    layout = [v.strip() for v in head["layout"].split(",")]
    assert head["datatype"] == "Float32LE"
    name, offset = head["file"].split()
    assert name == "."
    count = int(np.prod(dim))
    flat = np.frombuffer(raw, dtype="<f4", count=count, offset=int(offset))
    ranks = [abs(int(v)) for v in layout]
    # Axes in storage order, slowest first: the highest rank is slowest.
    order = sorted(range(len(dim)), key=lambda a: -ranks[a])
    arr = flat.reshape([dim[a] for a in order])
    arr = np.transpose(arr, np.argsort(order))  # back to [x, y, z, v]
    for a, v in enumerate(layout):
        if v.startswith("-"):
            arr = np.flip(arr, axis=a)
    return np.ascontiguousarray(arr, dtype=np.float32)


def slice_10x10(fit):
    """(N, N, 45): voxel (x, y) takes the fit's (x % 4, y % 4, Z0)."""
    nx, ny = fit.shape[:2]
    ix = np.arange(N) % nx
    iy = np.arange(N) % ny
    return fit[ix[:, None], iy[None, :], Z0, :]


def write_mif(path, sl):
    """A 10x10x1 image of 45 volumes, volume-fastest (layout +1,+2,+3,+0), identity transform."""
    nx, ny, nv = sl.shape
    header = [
        "mrtrix image",
        "dim: %d,%d,1,%d" % (nx, ny, nv),
        "vox: 1,1,1,1",
        "layout: +1,+2,+3,+0",
        "datatype: Float32LE",
        "transform: 1,0,0,0",
        "transform: 0,1,0,0",
        "transform: 0,0,1,0",
        "command_history: fury_slice.py (10x10 tiling of tests/data/sh/mrtrix_lmax8.mif z=1)",
        "mrtrix_version: 3.0.3",
    ]
    blob = mif_header(header)
    # [z][y][x][v] in memory = x-major after v.
    data = np.transpose(sl, (1, 0, 2)).astype("<f4").tobytes()
    with open(path, "wb") as f:
        f.write(blob + data)


def fibonacci_sphere(n):
    i = np.arange(n) + 0.5
    z = 1 - 2 * i / n
    r = np.sqrt(1 - z * z)
    phi = np.pi * (1 + 5 ** 0.5) * i
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)


def tournier_matrix(dirs, lmax=8):
    """(n_dirs, 45): MRtrix3's basis (DIPY tournier07, legacy=False) at the directions."""
    from dipy.core.sphere import Sphere
    from dipy.reconst.shm import sh_to_sf_matrix

    sph = Sphere(xyz=dirs)
    b = sh_to_sf_matrix(sph, sh_order_max=lmax, basis_type="tournier07", legacy=False,
                           return_inv=False)
    return np.asarray(b, dtype=np.float64).T


def fury_matrix(dirs, lmax=8):
    from fury.utils import create_sh_basis_matrix

    return np.asarray(create_sh_basis_matrix(np.asarray(dirs, dtype=np.float64), lmax),
                      dtype=np.float64)


def convert(sl, check=False):
    """Tournier07 (45) -> FURY standard (81), each ODF scaled to its own maximum 1."""
    dirs = fibonacci_sphere(2000)
    bt = tournier_matrix(dirs)
    bf = fury_matrix(dirs)
    m, *_ = np.linalg.lstsq(bf, bt, rcond=None)  # (81, 45)
    resid = np.abs(bf @ m - bt).max()
    odd = [i for l in range(9) for i in range(l * l, (l + 1) ** 2) if l % 2]
    flat = sl.reshape(-1, sl.shape[-1]).astype(np.float64)
    amps = flat @ bt.T  # (100, 2000)
    peak = amps.max(axis=1)
    coeffs = (flat @ m.T) / peak[:, None]
    info = {
        "basis_fit_max_residual": float(resid),
        "basis_fit_max_odd_coefficient": float(np.abs(m[odd]).max()),
        "negative_lobe_min_over_max": float((amps.min(axis=1) / peak).min()),
    }
    if check:
        # FURY's own evaluation on its glyph sphere against DIPY's tournier07 amplitudes.
        import fury.primitive as fp

        verts, _ = fp.prim_sphere(name="symmetric362")
        verts = np.asarray(verts, dtype=np.float64)
        verts /= np.linalg.norm(verts, axis=1, keepdims=True)
        f_fury = coeffs @ fury_matrix(verts).T
        f_mrtrix = (flat @ tournier_matrix(verts).T) / peak[:, None]
        info["fury_vs_tournier_max_abs_diff_on_glyph_sphere"] = float(
            np.abs(f_fury - f_mrtrix).max())
        # The largest lobe's direction of the first ODFs, for a look at the pictures.
        info["peak_dirs_first4"] = [
            [round(float(c), 3) for c in dirs[np.argmax(amps[k])]] for k in range(4)]
    return coeffs.reshape(sl.shape[0], sl.shape[1], 1, 81).astype(np.float32), info


class SubmitTimer:
    """Wraps GPUQueue.submit: each submission is waited on at once and timed (submit -> work
    done); the offscreen canvas's read-back (submitted from rendercanvas) is counted apart."""

    def __init__(self):
        import wgpu.backends.wgpu_native._api as api

        from pygfx.renderers.wgpu import get_shared

        self.api = api
        self.device = get_shared().device
        self.orig = api.GPUQueue.submit
        self.render_s = 0.0
        self.readback_s = 0.0
        self.count = 0
        self.each = []
        timer = self

        def submit(queue, command_buffers):
            caller = sys._getframe(1).f_globals.get("__name__", "")
            t = time.perf_counter()
            timer.orig(queue, command_buffers)
            # wgpu 0.32's on_submitted_work_done_async() fails (a callback type mismatch with
            # its wgpu-native), so wait as tensorglyph does: poll the device until idle.
            timer.device._poll_wait()
            dt = time.perf_counter() - t
            if caller.startswith("rendercanvas"):
                timer.readback_s += dt
            else:
                timer.render_s += dt
                timer.count += 1
                timer.each.append(dt)

        api.GPUQueue.submit = submit

    def reset(self):
        self.render_s = self.readback_s = 0.0
        self.count = 0
        self.each = []


def render(coeffs, aa, frames, fill, png=None):
    from fury import actor, window

    scene = window.Scene(background=(1, 1, 1, 1))
    glyph = actor.sph_glyph(coeffs, basis_type="standard", color_type="orientation")
    glyph.scale = 0.5
    scene.add(glyph)
    kw = {"pixel_ratio": 1.0} if aa in ("noaa", "ddaa-only") else {}
    sm = window.ShowManager(scene=scene, size=SIZE, window_type="offscreen", **kw)
    if aa in ("noaa", "ssaa-only"):
        sm.renderer.ppaa = "none"
    elif aa == "ddaa-only":
        sm.renderer.ppaa = "ddaa"
    info = {
        "aa": aa,
        "pixel_scale": float(sm.renderer.pixel_scale),
        "ppaa": sm.renderer.ppaa,
        "internal_size": [int(SIZE[0] * sm.renderer.pixel_scale),
                          int(SIZE[1] * sm.renderer.pixel_scale)],
    }
    t = time.perf_counter()
    sm._draw_canvas()  # warm-up: pipelines, first compute
    first_ms = (time.perf_counter() - t) * 1e3
    # The camera is set after the first frame: ShowManager's first draw handles the canvas's
    # resize event by framing the scene (camera.show_object), which would undo it.
    cam = sm.screens[0].camera
    cam.fov = FOV
    # pygfx applies the fov to the mean of the camera's width and height (its aspect); with
    # aspect 1 and a wider viewport the fov is the vertical one, as in tensorglyph.
    cam.width = cam.height = 1.0
    cam.zoom = 1.0
    # The grid spans [-0.5, N - 0.5] (glyph radius 0.5 at spacing 1): its height fills `fill`
    # of the image's height.
    c = (N - 1) / 2.0
    half = N / 2.0 / fill
    dist = half / np.tan(np.radians(FOV / 2))
    cam.world.reference_up = (0, 1, 0)
    cam.local.position = (c, c, dist)
    cam.look_at((c, c, 0.0))
    sm._draw_canvas()  # a second warm-up, with the camera in place
    timer = SubmitTimer()
    frame_ms, draw_ms, readback_ms, each_ms = [], [], [], []
    for _ in range(frames):
        timer.reset()
        t = time.perf_counter()
        sm._draw_canvas()
        draw_ms.append((time.perf_counter() - t) * 1e3)
        frame_ms.append(timer.render_s * 1e3)
        readback_ms.append(timer.readback_s * 1e3)
        each_ms.append([v * 1e3 for v in timer.each])
    info["first_frame_ms"] = first_ms
    info["camera"] = {"fov": cam.fov, "aspect": cam.aspect, "zoom": cam.zoom,
                      "position": [round(float(v), 3) for v in cam.local.position]}
    info["submits_per_frame"] = timer.count
    info["frame_ms"] = statistics.median(frame_ms)
    info["draw_ms"] = statistics.median(draw_ms)
    info["readback_ms"] = statistics.median(readback_ms)
    info["frame_ms_all"] = [round(v, 2) for v in frame_ms]
    # Each submission's median: pygfx's compute pass (the SH evaluation and the normals of
    # every glyph's mesh), the render pass (+ DDAA where on), the output pass (SSAA filter).
    info["submit_ms_medians"] = [round(statistics.median(v), 2) for v in zip(*each_ms)]
    if png:
        img = np.asarray(sm.snapshot(fname=png))
        rgb = img[..., :3].astype(int)
        fg = np.any(rgb < 250, axis=2)
        ys, xs = np.nonzero(fg)
        info["png"] = png
        info["foreground_pixels"] = int(fg.sum())
        info["foreground_bbox_xywh"] = ([int(xs.min()), int(ys.min()),
                                         int(xs.max() - xs.min() + 1),
                                         int(ys.max() - ys.min() + 1)] if len(xs) else None)
    timer.api.GPUQueue.submit = timer.orig
    sm.window.close()
    return info


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--mif", default=os.path.join(ROOT, "tests/data/sh/mrtrix_lmax8.mif"))
    p.add_argument("--write-mif", help="write the 10x10x1 slice for tensorglyph and exit")
    p.add_argument("--png", help="save the last setting's image")
    p.add_argument("--aa", default="both",
                   choices=["noaa", "default", "both", "ssaa-only", "ddaa-only"],
                   help="noaa: pixel_ratio 1, ppaa none; default: FURY's (2x2 SSAA + DDAA); "
                   "ssaa-only: pixel_scale 2, ppaa none; ddaa-only: pixel_ratio 1, ddaa")
    p.add_argument("--frames", type=int, default=5)
    p.add_argument("--fill", type=float, default=0.9,
                   help="fraction of the image height the 10x10 grid spans")
    p.add_argument("--json", action="store_true", help="one JSON object on stdout")
    p.add_argument("--check", action="store_true", help="check the basis conversion")
    a = p.parse_args()
    t0 = time.perf_counter()
    sl = slice_10x10(read_mif(a.mif))
    if a.write_mif:
        write_mif(a.write_mif, sl)
        print("wrote %s: %dx%dx1, %d coefficients" % (a.write_mif, N, N, sl.shape[-1]))
        return
    coeffs, out = convert(sl, check=a.check)
    import fury
    import pygfx
    import wgpu

    out["versions"] = {"fury": fury.__version__, "pygfx": pygfx.__version__,
                       "wgpu": wgpu.__version__, "python": sys.version.split()[0]}
    out["adapter"] = wgpu.gpu.request_adapter_sync().summary
    out["runs"] = []
    settings = ["noaa", "default"] if a.aa == "both" else [a.aa]
    for i, aa in enumerate(settings):
        png = a.png if (a.png and i == 0) else None
        out["runs"].append(render(coeffs, aa, a.frames, a.fill, png))
    out["whole_process_s"] = time.perf_counter() - t0
    if a.json:
        print(json.dumps(out))
    else:
        for k, v in out.items():
            if k != "runs":
                print("%s: %s" % (k, v))
        for r in out["runs"]:
            print(r)


main()
