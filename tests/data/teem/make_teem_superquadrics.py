#!/usr/bin/env python3
"""Superquadric glyphs against Teem: the README's side-by-side and its numbers.

    python3 tests/data/teem/make_teem_superquadrics.py [--tensorglyph target/debug/tensorglyph]
        [--out docs/images] [--gpu-method gumhold|sigg|none] [--gr 4,8,16,32,64]

Needs python3 + numpy, Debian's teem-apps (`teem-tend`, Teem 1.12) and a built tensorglyph.

1. Writes `tests/data/teem/superquadrics.nrrd` (beside this script): a 5x5 grid of positive
   definite tensors in the z = 0 plane, spacing 1, as `tend estim` writes them (float,
   `3D-masked-symmetric-matrix`: confidence 1, then xx xy xz yy yz zz). The lower-left
   triangle sweeps Kindlmann's barycentric shape space (isotropic at the top left, linear to
   planar along the bottom row); the other ten cells hold oblique rotations, a disc seen edge
   on, a linear glyph seen end on and the cl = cp tie. Every tensor has lambda1 = 1, so the
   radii are `F * lambda` with F = 0.4 and no glyph leaves its cell.
   `tests/data/teem/superquadrics.json` holds the truth: numpy's eigen decomposition of the
   float32 numbers stored, Westin cl and cp, the Kindlmann 2004 exponents (gamma = 3) and
   symmetry axis, the pixel cell, and the camera of both renderers.
2. Renders it with Teem: `tend glyph -rt` (its ray tracer, whose superquadric is analytic:
   Teem's echoSuperquad) and `tend glyph` EPS (a polygon mesh, limnObjectPolarSuperquadFancyAdd,
   at resolution `-gr`), with the camera below, and with `tensorglyph render --method reference`
   (and a GPU method) with the matching camera.
3. Compares coverage masks: per glyph cell the IoU and the mismatched pixels of Teem's image and
   ours, and the mismatch per unit of silhouette length (the mean distance between the two
   silhouettes, in pixels); for the EPS at each -gr the same numbers, which shrink as 1/gr^2,
   the area between a polygon inscribed in the silhouette and the silhouette.
4. Writes `OUT/teem_side_by_side.png` (Teem's ray tracing left, ours right, same pixels, and a
   third panel with the pixels where the coverage differs, ringed: red Teem's only, blue ours
   only) and `tests/data/teem/measured.json` (the numbers).

Conventions found in Teem 1.12 (ten/glyph.c tenGlyphGen, ten/tendGlyph.c, echo/renderEcho.c):
- glyph size: the glyph is the unit superquadric scaled by `-gsc * |lambda_i|` along e_i, so
  `-gsc F` is `--scale F --size-by linear --normalize none`.
- shape: cl, cp are Westin's trace-normalised measures (tenAniso_Cl1, Cp1), capped at 0.99;
  cl > cp: axis e1, alpha = (1 - cp)^gamma, beta = (1 - cl)^gamma, else axis e3 with cl and cp
  swapped; gamma is `-sh`. Glyphs with a negative eigenvalue are dropped from a grid (only
  `-p` point lists keep them), and `-atr` (default 0.5, on FA) and `-ctr` (confidence, 0.5)
  cull glyphs, so `-atr -1` is needed to see the isotropic ones.
- camera: `-fr/-at/-up` as usual; `-ur/-vr` are image plane ranges relative to `-at`; U is
  right, V is up (without `-rh`), and the ray-traced nrrd's first row is `vr` min (bottom).
  `-or` is honoured by the EPS path only: echo always casts rays from `-fr` (perspective), so the
  eye goes 1e4 units away (magnification error < 5e-5, well under 0.01 px here).
- `-gr` (facet resolution, default 10) is "postscript only": the mesh has 2*gr longitudes and
  gr latitudes; `-rt` ray-traces the analytic superquadric and ignores it.
- EPS: `-psc` is PostScript points per world unit; limn's PostScript window flips y on top of
  the camera's V, so without `-rh` the page is upside down relative to `-up` (and to `-rt`).
- limits: Teem's ray tracer loses flat discs seen face on (diag(1, 1, 0.1), beta = 0.003: 1984
  of the 2056 pixels Teem's own mesh and our reference cover; diag(1, 1, 0.05): 492; at
  diag(1, 1, 0.01) nothing), so the discs here are no flatter than lambda3 = 0.18 face on.
- colour: |e_c| as RGB (`-c`, default e1), saturation `-sat`, modulated by anisotropy `-am`/`-ga`
  towards gray `-gg`, then gamma `-gam` (0.7 by default): `-am 1 -ga fa -gg 0 -gam 1` is
  |e1| * FA, our `--color dec`. Without `-emap` or an `-al` light the ray tracer's diffuse term
  is 0 (black glyphs); `-al B U V N E` places a square light at (U, V, N) in view space
  relative to `-at`, so it is put far away here to act as a directional light.
"""

import argparse
import json
import os
import struct
import subprocess
import sys
import tempfile
import zlib

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(os.path.dirname(HERE)))
DATA = HERE

NX, NY = 5, 5  # grid (x fastest), spacing 1, origin 0, plane z = 0
SCALE = 0.4  # radius = SCALE * |lambda|, lambda1 = 1
GAMMA = 3.0  # Kindlmann's sharpness (tend glyph -sh, tensorglyph --sharpness)
PX = 64  # pixels per world unit: one cell is 64 x 64 pixels
W, H = NX * PX, NY * PX
EYE_DISTANCE = 1e4  # Teem's ray tracer has no orthographic camera


# ---------------------------------------------------------------- the field


def rot(axis, deg):
    """Rotation matrix about `axis` by `deg` degrees (Rodrigues)."""
    a = np.asarray(axis, float)
    a = a / np.linalg.norm(a)
    t = np.radians(deg)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(t) * k + (1 - np.cos(t)) * (k @ k)


def evals_of(cl, cp, cs):
    """Eigenvalues (lambda1 = 1) with trace-normalised Westin measures cl, cp, cs."""
    l3 = cs
    l2 = l3 + 1.5 * cp
    l1 = l2 + 3.0 * cl
    return np.array([l1, l2, l3]) / l1


def field():
    """(i, j, label, eigenvalues, frame columns e1 e2 e3) for each of the 25 cells."""
    cells = {}
    # Barycentric triangle: row r from the top (j = 4 - r), column c <= r. cs = (4 - r)/4,
    # cp = c/4, cl = (r - c)/4, pulled towards the sphere by a quarter: the corners stay positive
    # definite and the thinnest glyph (the linear corner, lambda2 = 0.1) is 5 pixels wide.
    for r in range(5):
        for c in range(r + 1):
            cl, cp, cs = (r - c) / 4, c / 4, (4 - r) / 4
            cl, cp, cs = 0.75 * cl, 0.75 * cp, 0.25 + 0.75 * cs
            cells[(c, 4 - r)] = (f"bary cl={cl:.2f} cp={cp:.2f}", evals_of(cl, cp, cs), np.eye(3))
    # The upper-right cells: oblique and special views.
    extra = [
        ("linear, oblique", [1, 0.3, 0.2], rot([1, 2, 3], 50)),
        ("planar, oblique", [1, 0.9, 0.2], rot([1, -1, 0.5], 60)),
        ("disc edge-on (e3 along x)", [1, 0.95, 0.25], rot([0, 1, 0], 90)),
        ("linear end-on (e1 along z)", [1, 0.45, 0.3], rot([0, 1, 0], -90) @ rot([1, 0, 0], 20)),
        ("cl = cp tie, oblique", evals_of(0.3, 0.3, 0.4), rot([2, 1, -1], 35)),
        ("box-like, in-plane 30 deg", [1, 0.6, 0.2], rot([0, 0, 1], 30)),
        ("box-like, oblique", [1, 0.55, 0.15], rot([-1, 3, 2], 70)),
        ("near isotropic, oblique", [1, 0.9, 0.8], rot([1, 1, 1], 40)),
        ("prolate, oblique", [1, 0.45, 0.4], rot([0, 1, 1], 65)),
        ("planar, tilted 30 deg", [1, 0.85, 0.1], rot([1, 0, 0], 30) @ rot([0, 0, 1], 20)),
    ]
    free = [(i, j) for j in range(NY) for i in range(NX) if (i, j) not in cells]
    assert len(free) == len(extra)
    for (i, j), (label, ev, q) in zip(sorted(free, key=lambda ij: (-ij[1], ij[0])), extra):
        cells[(i, j)] = (label, np.asarray(ev, float), q)
    out = []
    for j in range(NY):
        for i in range(NX):
            label, ev, q = cells[(i, j)]
            out.append((i, j, label, ev, q))
    return out


def westin(ev):
    s = ev.sum()
    return (ev[0] - ev[1]) / s, 2 * (ev[1] - ev[2]) / s


def kindlmann(ev, gamma):
    cl, cp = westin(ev)
    cl, cp = min(cl, 0.99), min(cp, 0.99)
    if cl > cp:  # Teem's test (Kindlmann writes >=; at a tie both give the same solid)
        return dict(axis="e1", alpha=(1 - cp) ** gamma, beta=(1 - cl) ** gamma)
    return dict(axis="e3", alpha=(1 - cl) ** gamma, beta=(1 - cp) ** gamma)


def write_field():
    os.makedirs(DATA, exist_ok=True)
    cells = field()
    data = np.zeros((NY, NX, 7), np.float32)
    truth = []
    for i, j, label, ev, q in cells:
        d = q @ np.diag(ev) @ q.T
        data[j, i] = [1.0, d[0, 0], d[0, 1], d[0, 2], d[1, 1], d[1, 2], d[2, 2]]
        stored = data[j, i].astype(np.float64)
        t = np.array([[stored[1], stored[2], stored[3]],
                      [stored[2], stored[4], stored[5]],
                      [stored[3], stored[5], stored[6]]])
        w, v = np.linalg.eigh(t)
        w, v = w[::-1], v[:, ::-1]
        cl, cp = westin(w)
        # half extents of the box around the glyph (the local unit box scaled and rotated),
        # which is what our camera frames
        reach = np.abs(v * (SCALE * w)).sum(axis=1)
        truth.append(dict(
            i=i, j=j, label=label,
            centre=[float(i), float(j), 0.0],
            tensor=[float(x) for x in stored[1:]],
            eigenvalues=[float(x) for x in w],
            eigenvectors=[[float(x) for x in v[:, k]] for k in range(3)],
            cl=float(cl), cp=float(cp),
            kindlmann=kindlmann(w, GAMMA),
            box_half=[float(x) for x in reach],
            pixels=dict(x0=i * PX, y0=(NY - 1 - j) * PX, size=PX),
        ))
    hdr = (
        "NRRD0004\n"
        "# superquadric glyphs against Teem: tests/data/teem/make_teem_superquadrics.py\n"
        "type: float\n"
        "dimension: 4\n"
        f"sizes: 7 {NX} {NY} 1\n"
        "kinds: 3D-masked-symmetric-matrix space space space\n"
        "space: right-anterior-superior\n"
        "space directions: none (1,0,0) (0,1,0) (0,0,1)\n"
        "space origin: (0,0,0)\n"
        "endian: little\n"
        "encoding: raw\n\n"
    )
    with open(os.path.join(DATA, "superquadrics.nrrd"), "wb") as f:
        f.write(hdr.encode() + data.astype("<f4").tobytes())
    return truth


# ---------------------------------------------------------------- images


def png_write(path, rgba):
    """8-bit RGBA (h, w, 4) to PNG."""
    h, w, _ = rgba.shape
    raw = b"".join(b"\x00" + rgba[y].astype(np.uint8).tobytes() for y in range(h))

    def chunk(tag, payload):
        c = struct.pack(">I", len(payload)) + tag + payload
        return c + struct.pack(">I", zlib.crc32(tag + payload) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 9)))
        f.write(chunk(b"IEND", b""))


def png_read(path):
    """8-bit non-interlaced PNG (gray, RGB, RGBA) to an (h, w, 4) uint8 array."""
    with open(path, "rb") as f:
        blob = f.read()
    assert blob[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat, ihdr = 8, b"", None
    while pos < len(blob):
        (n,) = struct.unpack(">I", blob[pos:pos + 4])
        tag, payload = blob[pos + 4:pos + 8], blob[pos + 8:pos + 8 + n]
        if tag == b"IHDR":
            ihdr = struct.unpack(">IIBBBBB", payload)
        elif tag == b"IDAT":
            idat += payload
        pos += 12 + n
    w, h, depth, ctype, _, _, interlace = ihdr
    assert depth == 8 and interlace == 0 and ctype in (0, 2, 4, 6), ihdr
    ch = {0: 1, 2: 3, 4: 2, 6: 4}[ctype]
    raw = np.frombuffer(zlib.decompress(idat), np.uint8).reshape(h, 1 + w * ch)
    out = np.zeros((h, w * ch), np.int32)
    prev = np.zeros(w * ch, np.int32)
    for y in range(h):
        ft, line = raw[y, 0], raw[y, 1:].astype(np.int32)
        if ft == 0:
            cur = line
        elif ft == 2:
            cur = (line + prev) & 255
        else:
            cur = np.zeros_like(line)
            for x in range(w * ch):
                a = cur[x - ch] if x >= ch else 0
                b = prev[x]
                c = prev[x - ch] if x >= ch else 0
                if ft == 1:
                    p = a
                elif ft == 3:
                    p = (a + b) >> 1
                else:
                    pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                    p = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                cur[x] = (line[x] + p) & 255
        out[y] = cur
        prev = cur
    img = out.reshape(h, w, ch).astype(np.uint8)
    if ch == 4:
        return img
    rgba = np.full((h, w, 4), 255, np.uint8)
    if ch in (1, 2):
        rgba[..., :3] = img[..., :1]
        if ch == 2:
            rgba[..., 3] = img[..., 1]
    else:
        rgba[..., :3] = img
    return rgba


def nrrd_read_float(path):
    """A raw little-endian float nrrd as tend glyph -rt writes it: (sizes reversed) array."""
    with open(path, "rb") as f:
        blob = f.read()
    end = blob.index(b"\n\n")
    fields = {}
    for line in blob[:end].decode().splitlines()[1:]:
        if ":" in line and not line.startswith("#"):
            k, v = line.split(":", 1)
            fields[k.strip()] = v.strip()
    assert fields["type"] == "float" and fields["encoding"] == "raw", fields
    assert fields.get("endian", "little") == "little", fields
    sizes = [int(s) for s in fields["sizes"].split()]
    return np.frombuffer(blob[end + 2:], "<f4").reshape(sizes[::-1])


def eps_polygons(path):
    """The filled polygons of a limn EPS (`x y M`, `x y L`..., `CP r g b RGB F`)."""
    polys, cur = [], []
    with open(path) as f:
        for line in f:
            p = line.split()
            if len(p) == 3 and p[2] == "M":
                cur = [(float(p[0]), float(p[1]))]
            elif len(p) == 3 and p[2] == "L":
                cur.append((float(p[0]), float(p[1])))
            elif p and p[0] == "CP" and p[-1] == "F":
                polys.append(np.array(cur))
                cur = []
    return polys


def rasterize(polys, w, h):
    """Coverage of pixel centres by the union of polygons given in pixel units, x to the right
    from the image's left edge and y down from its top edge.

    Vectorised: polygons are padded to the same vertex count (repeating the last vertex adds a
    zero-length edge), grouped by the size of the block of pixel centres their box spans, and
    each group is tested against its blocks at once (even-odd rule, half-open in y)."""
    mask = np.zeros((h, w), bool)
    if not polys:
        return mask
    nv = max(len(p) for p in polys)
    pts = np.array([np.vstack([p, np.repeat(p[-1:], nv - len(p), axis=0)]) for p in polys])
    c0 = np.ceil(pts[..., 0].min(axis=1) - 0.5).astype(int)  # first column whose centre is in
    c1 = np.floor(pts[..., 0].max(axis=1) - 0.5).astype(int)
    r0 = np.ceil(pts[..., 1].min(axis=1) - 0.5).astype(int)
    r1 = np.floor(pts[..., 1].max(axis=1) - 0.5).astype(int)
    span = np.maximum(c1 - c0, r1 - r0) + 1
    keep = (c1 >= c0) & (r1 >= r0)
    size = np.where(keep, 2 ** np.ceil(np.log2(np.maximum(span, 1))).astype(int), 0)
    for b in np.unique(size[keep]):
        idx = np.nonzero(size == b)[0]
        for chunk in np.array_split(idx, max(1, len(idx) * b * b // 4_000_000 + 1)):
            off = np.arange(b)
            cols = c0[chunk, None, None] + off[None, None, :]  # (m, 1, b)
            rows = r0[chunk, None, None] + off[None, :, None]  # (m, b, 1)
            px, py = cols + 0.5, rows + 0.5
            inside = np.zeros((len(chunk), b, b), bool)
            poly = pts[chunk]
            for k in range(nv):
                ax, ay = poly[:, k, 0, None, None], poly[:, k, 1, None, None]
                bx, by = poly[:, (k + 1) % nv, 0, None, None], poly[:, (k + 1) % nv, 1, None, None]
                crosses = (ay > py) != (by > py)
                dy = np.where(by == ay, 1.0, by - ay)
                xint = ax + (py - ay) * (bx - ax) / dy
                inside ^= crosses & (px < xint)
            ok = (inside & (cols <= c1[chunk, None, None]) & (rows <= r1[chunk, None, None])
                  & (cols >= 0) & (cols < w) & (rows >= 0) & (rows < h))
            m_, rr, cc = np.nonzero(ok)
            mask[rows[m_, rr, 0], cols[m_, 0, cc]] = True
    return mask


# ---------------------------------------------------------------- renderers


def teem_camera(centre, height):
    """tend glyph camera options: looking down -z at `centre`, ortho window `height` world
    units high (and W/H times as wide)."""
    cx, cy = centre
    half_v = height / 2
    half_u = half_v * W / H
    return [
        "-fr", repr(cx), repr(cy), repr(EYE_DISTANCE), "-at", repr(cx), repr(cy), "0",
        "-up", "0", "1", "0", "-or", "-ur", repr(-half_u), repr(half_u),
        "-vr", repr(-half_v), repr(half_v), "-dn", "-1", "-df", "1",
    ]


TEEM_GLYPH = ["-g", "superquad", "-sh", repr(GAMMA), "-gsc", repr(SCALE), "-atr", "-1",
              "-ctr", "0.5", "-c", "0", "-am", "1", "-ga", "fa", "-gg", "0"]


def teem_rt(nrrd, centre, height, tmp):
    out = os.path.join(tmp, "teem_rt.nrrd")
    subprocess.run(["teem-tend", "glyph", "-rt", "-i", nrrd, "-o", out, *TEEM_GLYPH,
                    *teem_camera(centre, height), "-is", str(W), str(H), "-ns", "1",
                    # for the figure only: a distant light above left (as ours), some specular,
                    # and gamma 1/2.2 for a look close to ours (colours are not compared)
                    "-bg", "1", "1", "1", "-adsp", "0.3", "0.7", "0.3", "30",
                    "-al", "1", "-50", "80", "-35", "1", "-shadow", "0", "-gam", "0.4545",
                    "-nt", "1"],
                   check=True, capture_output=True)
    img = nrrd_read_float(out)  # (H, W, 5): rows from vr min (bottom)
    assert img.shape == (H, W, 5), img.shape
    return img[::-1]


def teem_eps(nrrd, centre, height, gr, tmp):
    out = os.path.join(tmp, f"teem_gr{gr}.eps")
    # -psc: PostScript points per world unit = pixels per world unit, so the EPS coordinates
    # are pixels; -wd 0 0 0 draws no edge strokes. limn's PostScript window flips y (yFlip) on
    # top of the camera's V, so the page shows V pointing down: with -rh (V = down) the page
    # is upright, its y counting up from the image's bottom edge.
    subprocess.run(["teem-tend", "glyph", "-i", nrrd, "-o", out, *TEEM_GLYPH,
                    *teem_camera(centre, height), "-rh", "-gr", str(gr), "-psc",
                    repr(H / height), "-wd", "0", "0", "0"], check=True, capture_output=True)
    polys = [np.column_stack([p[:, 0], H - p[:, 1]]) for p in eps_polygons(out)]
    return rasterize(polys, W, H)


def ours(binary, nrrd, method, zoom, tmp):
    out = os.path.join(tmp, f"ours_{method}.png")
    cmd = [binary, "render", nrrd, "-o", out, "--method", method, "--glyph", "superquadric",
           "--sharpness", repr(GAMMA), "--scale", repr(SCALE), "--size-by", "linear",
           "--normalize", "none", "--view", "axial", "--ortho", "--zoom", repr(zoom),
           "--size", f"{W}x{H}", "--color", "dec", "--background", "white", "--transparent",
           "--quiet"]
    env = dict(os.environ)
    env.setdefault("XDG_RUNTIME_DIR", tempfile.gettempdir())
    subprocess.run(cmd, check=True, capture_output=True, env=env)
    return png_read(out)


def our_framing(truth):
    """Our camera for `--view axial --ortho --zoom Z`: Camera::frame_box fits the box of the
    glyphs' boxes (centre +- half) with a 3 % margin, height = max(2 hy, 2 hx / aspect) * 1.03
    / zoom. Returns (box centre x, y) and the zoom giving a window exactly NY world units high."""
    lo = np.min([np.array(t["centre"][:2]) - t["box_half"][:2] for t in truth], axis=0)
    hi = np.max([np.array(t["centre"][:2]) + t["box_half"][:2] for t in truth], axis=0)
    centre, half = (lo + hi) / 2, (hi - lo) / 2
    fit = max(2 * half[1], 2 * half[0] / (W / H)) * 1.03
    return (float(centre[0]), float(centre[1])), float(fit / NY)


def teem_version():
    about = subprocess.run(["teem-tend", "about"], capture_output=True, text=True)
    lines = [l.strip() for l in (about.stdout + about.stderr).splitlines() if "Teem version" in l]
    return lines[0] if lines else "unknown"


# ---------------------------------------------------------------- comparison


def compare(a, b, truth):
    """Per glyph cell: IoU, mismatched pixels, and mismatch per silhouette length (pixels)."""
    cells = []
    for t in truth:
        p = t["pixels"]
        sa = a[p["y0"]:p["y0"] + p["size"], p["x0"]:p["x0"] + p["size"]]
        sb = b[p["y0"]:p["y0"] + p["size"], p["x0"]:p["x0"] + p["size"]]
        inter, union, xor = (sa & sb).sum(), (sa | sb).sum(), (sa ^ sb).sum()
        perim = perimeter(sa)
        # no glyph reaches its cell's border, so cells compare glyph by glyph
        edge = np.concatenate([sa[0], sa[-1], sa[:, 0], sa[:, -1], sb[0], sb[-1], sb[:, 0],
                               sb[:, -1]])
        assert not edge.any(), f"glyph {t['i']}, {t['j']} touches its cell's border"
        cells.append(dict(i=t["i"], j=t["j"], iou=round(float(inter / union), 6) if union else 1.0,
                          mismatch=int(xor), area=int(sa.sum()),
                          mean_gap_px=round(float(xor / perim), 6) if perim else 0.0))
    xor = int((a ^ b).sum())
    return dict(
        cells=cells,
        min_iou=min(c["iou"] for c in cells),
        max_mean_gap_px=max(c["mean_gap_px"] for c in cells),
        mismatch=xor,
        mismatch_fraction=xor / a.size,
    )


def perimeter(m):
    """Silhouette length in pixels: covered/uncovered 4-neighbour edges (an over-estimate of
    the true length by up to 4/pi on slanted edges; used only to turn areas into distances)."""
    return int((m[1:] != m[:-1]).sum() + (m[:, 1:] != m[:, :-1]).sum())


def composite(rgba, bg=255):
    a = rgba[..., 3:4].astype(float) / 255
    return (rgba[..., :3] * a + bg * (1 - a)).astype(np.uint8)


def teem_rgba(img):
    rgb = np.clip(np.round(np.nan_to_num(img[..., :3], nan=1.0) * 255), 0, 255)
    a = np.clip(np.round(img[..., 3] * 255), 0, 255)
    return np.concatenate([rgb, a[..., None]], axis=-1).astype(np.uint8)


def figure(teem, our, path):
    """Teem left, ours right, and on the right the coverage of both (grey) and the pixels whose
    coverage differs (red: only Teem's, blue: only ours; ringed), all on white."""
    gap = 8
    diff = np.full((H, W, 3), 255, np.uint8)
    ta, oa = teem[..., 3] > 127, our[..., 3] > 127
    diff[ta & oa] = (225, 225, 225)
    yy, xx = np.mgrid[0:H, 0:W]
    for only, col in ((ta & ~oa, (220, 30, 30)), (~ta & oa, (30, 60, 220))):
        for y, x in zip(*np.nonzero(only)):  # single pixels, ringed so that they show
            d = np.hypot(yy - y, xx - x)
            diff[(d >= 4.5) & (d <= 6)] = col
        diff[only] = col
    white = np.full((H, gap, 3), 255, np.uint8)
    rgb = np.concatenate([composite(teem), white, composite(our), white, diff], axis=1)
    for k in (1, 2):  # thin separators
        rgb[:, k * W + (k - 1) * gap + gap // 2 - 1:k * W + (k - 1) * gap + gap // 2 + 1] = 160
    alpha = np.full(rgb.shape[:2] + (1,), 255, np.uint8)
    png_write(path, np.concatenate([rgb, alpha], axis=-1))


# ---------------------------------------------------------------- main


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tensorglyph", default=os.path.join(REPO, "target", "debug", "tensorglyph"))
    ap.add_argument("--out", default=os.path.join(REPO, "docs", "images"))
    ap.add_argument("--gpu-method", default="gumhold", help="gumhold, sigg or none")
    ap.add_argument("--gr", default="4,8,16,32,64", help="Teem EPS mesh resolutions")
    ap.add_argument("--measured", default=os.path.join(DATA, "measured.json"))
    args = ap.parse_args()

    truth = write_field()
    centre, zoom = our_framing(truth)
    height = float(NY)
    meta = dict(
        grid=[NX, NY], pixels_per_unit=PX, image=[W, H], scale=SCALE, sharpness=GAMMA,
        teem_gsc=SCALE, our_zoom=zoom, view_centre=list(centre), view_height=height,
        teem_version=teem_version(),
        teem_camera=teem_camera(centre, height),
        our_camera=["--view", "axial", "--ortho", "--zoom", repr(zoom), "--size", f"{W}x{H}"],
    )
    with open(os.path.join(DATA, "superquadrics.json"), "w") as f:
        json.dump(dict(meta=meta, glyphs=truth), f, indent=1)
        f.write("\n")
    nrrd = os.path.join(DATA, "superquadrics.nrrd")
    os.makedirs(args.out, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        rt = teem_rt(nrrd, centre, height, tmp)
        t_rgba = teem_rgba(rt)
        t_mask = rt[..., 3] > 0.5
        assert np.all((rt[..., 3] == 0) | (rt[..., 3] == 1)), "one sample per pixel: A is 0 or 1"
        ref = ours(args.tensorglyph, nrrd, "reference", zoom, tmp)
        r_mask = ref[..., 3] > 127
        results = dict(meta=meta)
        results["teem_rt_vs_reference"] = compare(t_mask, r_mask, truth)
        if args.gpu_method != "none":
            gpu = ours(args.tensorglyph, nrrd, args.gpu_method, zoom, tmp)
            results[f"{args.gpu_method}_vs_reference"] = compare(gpu[..., 3] > 127, r_mask, truth)
            results[f"teem_rt_vs_{args.gpu_method}"] = compare(t_mask, gpu[..., 3] > 127, truth)
        eps = {}
        for gr in [int(g) for g in args.gr.split(",")]:
            m = teem_eps(nrrd, centre, height, gr, tmp)
            eps[str(gr)] = dict(vs_reference=compare(m, r_mask, truth),
                                vs_teem_rt=compare(m, t_mask, truth))
        results["teem_eps_by_gr"] = eps
        figure(t_rgba, ref, os.path.join(args.out, "teem_side_by_side.png"))

    for c in results["teem_rt_vs_reference"]["cells"]:
        c["label"] = truth[c["j"] * NX + c["i"]]["label"]
    with open(args.measured, "w") as f:
        json.dump(results, f, indent=1)
        f.write("\n")
    summary(results)


def summary(results):
    r = results["teem_rt_vs_reference"]
    print(f"Teem -rt vs reference: min IoU {r['min_iou']:.5f}, mismatched pixels "
          f"{r['mismatch']} of {W * H}, worst mean gap {r['max_mean_gap_px']:.4f} px")
    for k in results:
        if k.endswith("_vs_reference") and not k.startswith("teem"):
            g = results[k]
            print(f"{k}: min IoU {g['min_iou']:.5f}, mismatched pixels {g['mismatch']}")
    print(" -gr | vs reference: min IoU, mismatch px, worst gap px | vs Teem -rt: min IoU")
    for gr, e in results["teem_eps_by_gr"].items():
        a, b = e["vs_reference"], e["vs_teem_rt"]
        print(f"{gr:>4} | {a['min_iou']:.5f} {a['mismatch']:6d} {a['max_mean_gap_px']:.4f}"
              f" | {b['min_iou']:.5f}")


if __name__ == "__main__":
    sys.exit(main())
