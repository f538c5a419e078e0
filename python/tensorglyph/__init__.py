"""tensorglyph for Python: 3D symmetric tensor fields (diffusion MRI, stress) drawn as exact
ray-cast glyphs, from numpy arrays, DIPY fits, nibabel images or files.

    import tensorglyph as tg
    image = tg.render(fit, affine=img.affine)      # a DIPY TensorFit and its NIfTI's affine
    image.save("glyphs.png")                        # or show it: a notebook cell displays it

``render`` takes every option of the ``tensorglyph render`` command, spelled with underscores
(``size=(800, 600)``, ``glyph="superquadric"``, ``slice="z=5"``, ``outlines=True`` ...), with
the command line's defaults and checks: the options are turned into its own arguments and run
by the same library code, with the data handed over in memory. See the book's Python chapter.
"""

from __future__ import annotations

import json
import os
import threading
from typing import Any, Iterable, Optional, Sequence, Tuple

import numpy as np

# Mesa's implicit Vulkan layer VK_LAYER_MESA_device_select only reorders devices (the library
# picks its adapter itself) but prints two error lines on every run without XDG_RUNTIME_DIR
# (containers, batch jobs); the command line turns it off the same way (src/main.rs). Set before
# any Vulkan instance exists; left alone when the user set it or one of the layer's own settings.
if not any(
    v in os.environ
    for v in ("NODEVICE_SELECT", "MESA_VK_DEVICE_SELECT", "MESA_VK_DEVICE_SELECT_FORCE_DEFAULT_DEVICE")
):
    os.environ["NODEVICE_SELECT"] = "1"

from . import _tensorglyph
from ._errors import Error, FileError, FileNotFound

__all__ = [
    "Error",
    "Field",
    "FileError",
    "FileNotFound",
    "Image",
    "Renderer",
    "read",
    "render",
    "group_report",
    "report",
    "widget",
]

__version__ = _tensorglyph.__version__

#: The 6-component layouts ``layout=`` names (see the book's Python chapter).
LAYOUTS = ("fsl", "nifti", "mrtrix", "vtk", "bep016")

# Options taken by Python itself, not passed to the command line's parser.
_REFUSED = {
    "output": "render returns the Image; save it with image.save(path)",
    "o": "render returns the Image; save it with image.save(path)",
    "json": "the report is image.info",
}


def _arg_value(key: str, value: Any) -> str:
    if isinstance(value, (str, os.PathLike)):
        return os.fspath(value)
    if isinstance(value, (bool, np.bool_)):
        raise Error(f"{key}={value!r}: a flag is True or left out")
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        return repr(float(value))
    if isinstance(value, (tuple, list, np.ndarray)):
        parts = [_arg_value(key, v) for v in value]
        return ("x" if key == "size" else ",").join(parts)
    raise Error(f"{key}={value!r}: give a string, a number or a sequence of numbers")


def _cli_args(options: dict) -> list:
    """Keyword arguments as the command line's options: ``size=(640, 480)`` becomes
    ``--size 640x480``, ``outlines=True`` ``--outlines``, ``slice=["z=5", "x=3"]`` two
    ``--slice``; ``False`` and ``None`` leave an option out."""
    args = []
    for key, value in options.items():
        if key in _REFUSED:
            raise Error(f"{key}=: {_REFUSED[key]}")
        flag = "--" + key.replace("_", "-")
        if value is None or value is False or (isinstance(value, np.bool_) and not value):
            continue
        if value is True or isinstance(value, np.bool_):
            args.append(flag)
        elif key == "slice" and isinstance(value, (list, tuple)):
            for v in value:
                args += [flag, _arg_value(key, v)]
        else:
            args += [flag, _arg_value(key, value)]
    return args


def _is_nibabel(data: Any) -> bool:
    return (
        hasattr(data, "affine")
        and hasattr(data, "header")
        and hasattr(data, "dataobj")
        and type(data).__module__.startswith("nibabel")
    )


def _nifti_bytes(img: Any) -> bytes:
    """A nibabel image as the bytes of a NIfTI-1 file, as nibabel would save it."""
    import nibabel as nib

    if not isinstance(img, nib.Nifti1Image) or isinstance(img, nib.Nifti2Image):
        img = nib.Nifti1Image.from_image(img)
    return img.to_bytes()


def _affine(affine: Any) -> list:
    if affine is None:
        return np.eye(4).tolist()
    a = np.asarray(affine, dtype=np.float64)
    if a.shape != (4, 4):
        raise Error(f"affine of shape {a.shape}: a voxel-to-world matrix is 4×4")
    return a.tolist()


def _order_args(layout: Optional[str], frame: Optional[str]) -> list:
    args = []
    if layout is not None:
        if layout not in LAYOUTS:
            raise Error(f"layout '{layout}' is not one of {', '.join(LAYOUTS)}")
        args += ["--order", "fsl" if layout == "bep016" else layout]
    if frame is not None:
        args += ["--tensor-frame", str(frame)]
    return args


class Field:
    """A tensor field: read from a file (``tensorglyph.read``) or made of arrays
    (``Field.from_array``). ``render(field, ...)`` draws it; ``info()`` and ``eigen()``
    describe it."""

    def __init__(self, inner: "_tensorglyph.Field"):
        self._inner = inner

    @classmethod
    def from_array(
        cls,
        data: Any,
        *,
        affine: Any = None,
        layout: Optional[str] = None,
        frame: Optional[str] = None,
        positions: Any = None,
    ) -> "Field":
        """Tensors from an array: ``(..., 6)`` in ``layout`` (fsl, nifti, mrtrix, vtk,
        bep016) or ``(..., 3, 3)``. A lattice ``(X, Y, Z, ...)`` (or DIPY's ``(X, Y, Z, 1,
        6)``) is placed by ``affine`` (4×4 voxel to world, identity when absent) with its
        tensors in ``frame`` (voxel, the default, fsl or world); ``(N, ...)`` tensors sit at
        ``positions`` ``(N, 3)``, in world axes."""
        try:
            a = np.asarray(data, dtype=np.float64)
        except (TypeError, ValueError) as e:
            raise Error(f"data is not an array of numbers: {e}") from None
        shape = a.shape
        if a.ndim >= 3 and shape[-2:] == (3, 3):
            if layout not in (None, "full"):
                raise Error(f"layout='{layout}' is for (..., 6) arrays; this one is {shape}")
            a = a.reshape(shape[:-2] + (9,))
            kind = "full"
        elif a.ndim >= 2 and shape[-1] == 6:
            if layout is None:
                raise Error(
                    f"data of shape {shape}: six components need layout= one of "
                    f"{', '.join(LAYOUTS)} (DIPY's lower triangle is 'nifti')"
                )
            if layout not in LAYOUTS:
                raise Error(f"layout '{layout}' is not one of {', '.join(LAYOUTS)}")
            kind = layout
        elif a.ndim >= 2 and shape[-1] == 9 and layout in (None, "full"):
            kind = "full"
        else:
            raise Error(
                f"data of shape {shape}: tensors are (..., 6) with a layout, or (..., 3, 3)"
            )
        lead = a.shape[:-1]
        if positions is not None:
            if affine is not None:
                raise Error("affine= places a lattice; tensors at positions= need none")
            if frame not in (None, "world"):
                raise Error(f"frame='{frame}' applies to a lattice; tensors at positions are in world axes")
            p = np.asarray(positions, dtype=np.float64)
            if len(lead) != 1 or p.shape != (lead[0], 3):
                raise Error(
                    f"positions of shape {p.shape} for tensors of shape {shape}: "
                    "give (N, 3) positions for (N, 6) or (N, 3, 3) tensors"
                )
            return cls(_tensorglyph.Field.from_points(np.ascontiguousarray(a), kind, p))
        if len(lead) == 4 and lead[3] == 1:
            a = a.reshape(lead[:3] + a.shape[-1:])
            lead = lead[:3]
        if len(lead) != 3:
            raise Error(
                f"data of shape {shape}: a lattice is (X, Y, Z, ...); "
                "for N tensors at points give positions=(N, 3)"
            )
        return cls(_tensorglyph.Field.from_lattice(a, kind, _affine(affine), frame))

    def __len__(self) -> int:
        return len(self._inner)

    def __repr__(self) -> str:
        dims = f", dims={self.dims}" if self.dims else ""
        return f"<tensorglyph.Field {self._inner.name!r}: {len(self)} tensors{dims}>"

    @property
    def dims(self) -> Optional[Tuple[int, int, int]]:
        """The lattice's (X, Y, Z), or None for tensors at points."""
        d = self._inner.dims
        return tuple(d) if d is not None else None

    @property
    def name(self) -> str:
        return self._inner.name

    def info(self, samples: Iterable[int] = ()) -> dict:
        """What ``tensorglyph info --json`` reports: counts, layout and frames, eigenvalue
        ranges, FA, shape classes, and the tensors ``samples`` (indices in file order)."""
        return json.loads(self._inner.info_json([int(i) for i in samples]))

    def eigen(self) -> Tuple[np.ndarray, np.ndarray]:
        """Eigenvalues (descending) and unit eigenvectors of every tensor, in world axes:
        ``values[..., k]`` and ``vectors[..., :, k]`` (as DIPY's ``evals`` and ``evecs``),
        shaped as the lattice ``(X, Y, Z, ...)`` or ``(N, ...)``; NaN where a tensor is not
        finite."""
        values, vectors = self._inner.eigen()
        d = self.dims
        if d is not None and d[0] * d[1] * d[2] == len(self):
            x, y, z = d
            values = values.reshape(z, y, x, 3).transpose(2, 1, 0, 3)
            vectors = vectors.reshape(z, y, x, 3, 3).transpose(2, 1, 0, 3, 4)
        return values, vectors

    def render(self, **options: Any) -> "Image":
        """``tensorglyph.render(self, **options)``."""
        return render(self, **options)


def read(
    data: Any,
    *,
    affine: Any = None,
    layout: Optional[str] = None,
    frame: Optional[str] = None,
    positions: Any = None,
    **options: Any,
) -> Field:
    """Read tensors into a ``Field`` as ``render`` takes them, with the same signature: a
    file's path (any format the command line reads, as ``tensorglyph info`` and ``render`` read
    it), a ``Field``, a numpy array of tensors (with ``layout``, ``affine`` or ``positions``),
    a DIPY ``TensorFit`` (with its image's ``affine``) or a nibabel image. Options of files:
    ``order=`` (as ``layout=``), ``tensor_frame=`` (as ``frame=``: voxel, fsl, world),
    ``array=`` (by name)."""
    extra = set(options) - {"order", "tensor_frame", "array"}
    if extra:
        raise Error(
            f"read() takes affine, layout, frame, positions, order, tensor_frame and array, "
            f"not {', '.join(sorted(extra))}"
        )
    if options and not isinstance(data, (str, os.PathLike)):
        raise Error(f"{', '.join(sorted(options))}= apply to files; arrays take layout= and frame=")
    args: list = []
    inner = _field(data, affine, layout, frame, positions, args)
    if isinstance(inner, _tensorglyph.NamedBytes):
        if "peaks" in args:
            raise Error("peaks hold no tensors: render() draws them as sticks")
        raise Error("a fit in spherical harmonics holds no tensors: render() draws it as ODF glyphs")
    if isinstance(inner, str):
        return Field(_tensorglyph.Field.read(inner, args + _cli_args(options)))
    return data if isinstance(data, Field) else Field(inner)


def _field(data: Any, affine: Any, layout: Any, frame: Any, positions: Any, args: list):
    """What ``_tensorglyph.Renderer.render`` takes for ``data``: a field, or a path (which the
    command line's reader reads, exactly as ``tensorglyph render FILE`` does)."""
    given = {"affine": affine, "positions": positions}
    if isinstance(data, Field):
        if any(v is not None for v in given.values()) or layout or frame:
            raise Error("a Field is placed already: affine, layout, frame and positions apply to arrays")
        return data._inner
    if isinstance(data, (str, os.PathLike)):
        if any(v is not None for v in given.values()):
            raise Error("affine and positions apply to arrays; a file places its tensors itself")
        args += _order_args(layout, frame)
        return os.fspath(data)
    if hasattr(data, "peak_dirs") and hasattr(data, "peak_values") and not isinstance(data, np.ndarray):
        # DIPY's peaks (PeaksAndMetrics, from peaks_from_model or load_pam; its shm_coeff, if
        # any, is the ODFs they were found on): unit directions in
        # the voxel axes scaled by their values, 3 values a peak as sh2peaks lays them out (the
        # NIfTI file DIPY's workflows save, with its values applied): render draws the sticks.
        if positions is not None or layout:
            raise Error("peaks sit on their lattice: give affine, not layout or positions")
        import nibabel as nib

        # In float32, as the files are and as their reader scales them.
        dirs = np.asarray(data.peak_dirs, dtype=np.float32)
        values = np.asarray(data.peak_values, dtype=np.float32)
        if dirs.ndim != 5 or dirs.shape[-1] != 3 or values.shape != dirs.shape[:-1]:
            raise Error(
                f"peak_dirs of shape {dirs.shape} and peak_values of shape {values.shape}: "
                "peaks are (X, Y, Z, N, 3) and (X, Y, Z, N)"
            )
        if affine is None:
            affine = getattr(data, "affine", None)
        vectors = (dirs * values[..., None]).reshape(dirs.shape[:3] + (-1,))
        args += _order_args(None, frame) + ["--holds", "peaks"]
        img = nib.Nifti1Image(vectors, np.asarray(_affine(affine), dtype=np.float64))
        return _tensorglyph.NamedBytes(_nifti_bytes(img), "peak_dirs.nii")
    if hasattr(data, "shm_coeff") and not isinstance(data, np.ndarray):
        # A DIPY fit in spherical harmonics (CsdFit, or any fit with shm_coeff): its series in
        # the voxel axes and DIPY's default basis (descoteaux07, legacy; sh_basis= says
        # otherwise), read as the NIfTI file nibabel would save of them: render draws ODF glyphs.
        if positions is not None or layout:
            raise Error("a fit in spherical harmonics sits on its lattice: give affine, not layout or positions")
        import nibabel as nib

        coef = np.asarray(data.shm_coeff, dtype=np.float64)
        if coef.ndim != 4:
            raise Error(f"shm_coeff of shape {coef.shape}: a fit's series are (X, Y, Z, coefficients)")
        # The series of a fit, whatever its count (15 is also five peaks' in a file).
        args += _order_args(None, frame) + ["--holds", "series"]
        img = nib.Nifti1Image(coef, np.asarray(_affine(affine), dtype=np.float64))
        return _tensorglyph.NamedBytes(_nifti_bytes(img), "shm_coeff.nii")
    if hasattr(data, "quadratic_form") and not isinstance(data, np.ndarray):
        # A DIPY TensorFit: tensors in the voxel axes, taken as DIPY saves them (its
        # lower_triangular, NIfTI's order): quadratic_form is V Λ Vᵀ, symmetric only to
        # round-off, and its lower triangle is what a file of the fit holds.
        q = np.asarray(data.quadratic_form, dtype=np.float64)
        lower = q[..., [0, 1, 1, 2, 2, 2], [0, 0, 1, 0, 1, 2]]
        return Field.from_array(
            lower, layout="nifti", affine=affine, frame=frame, positions=positions
        )._inner
    if _is_nibabel(data):
        if any(v is not None for v in given.values()):
            raise Error("a nibabel image has its affine; affine and positions apply to arrays")
        name = getattr(data, "get_filename", lambda: None)() or "nibabel image"
        read_args = _order_args(layout, frame)
        return _tensorglyph.Field.from_nifti_bytes(_nifti_bytes(data), str(name), read_args)
    return Field.from_array(
        data, affine=affine, layout=layout, frame=frame, positions=positions
    )._inner


def _volume(value: Any, affine: Optional[list], what: str):
    """A mask or underlay given as an array or a nibabel image."""
    if _is_nibabel(value):
        name = getattr(value, "get_filename", lambda: None)() or f"{what} image"
        return _tensorglyph.Volume.from_nifti_bytes(_nifti_bytes(value), str(name))
    a = np.asarray(value, dtype=np.float64)
    if a.ndim != 3:
        raise Error(f"{what} of shape {a.shape}: a volume is (X, Y, Z)")
    return _tensorglyph.Volume.from_array(a, affine or np.eye(4).tolist(), what)


class Image:
    """A rendered image: ``array`` (uint8, H×W×3, or H×W×4 with ``transparent=True``),
    ``info`` (the keys of ``render --json``), ``save(path)``; a notebook shows it."""

    def __init__(self, rgba: np.ndarray, info: dict, transparent: bool, dpi: Optional[float]):
        self._rgba = rgba
        self.info = info
        self.transparent = transparent
        self.dpi = dpi
        self._array = None

    @property
    def array(self) -> np.ndarray:
        if self._array is None:
            self._array = self._rgba if self.transparent else np.ascontiguousarray(self._rgba[..., :3])
        return self._array

    @property
    def width(self) -> int:
        return self._rgba.shape[1]

    @property
    def height(self) -> int:
        return self._rgba.shape[0]

    def save(self, path: "str | os.PathLike") -> None:
        """Write the PNG the command line writes for the same options (RGBA, atomically)."""
        _tensorglyph.write_png(os.fspath(path), self._rgba, self.dpi)

    def to_png(self) -> bytes:
        return bytes(_tensorglyph.encode_png(self._rgba, self.dpi))

    def _repr_png_(self) -> bytes:
        return self.to_png()

    def __repr__(self) -> str:
        return (
            f"<tensorglyph.Image {self.width}x{self.height}, {self.info.get('glyphs_drawn')} "
            f"glyphs, {self.info.get('backend') or 'reference'}>"
        )


class Renderer:
    """A renderer that lives as long as it is kept: the GPU device, pipelines and shader
    modules are made on its first image and reused. ``backend``: ``"auto"`` (the GPU, or the
    exact CPU reference without an adapter), ``"gpu"`` or ``"cpu"``. Safe to share between
    threads (frames are drawn one at a time, data is read and staged in parallel)."""

    def __init__(self, backend: str = "auto"):
        self._inner = _tensorglyph.Renderer(backend)

    @property
    def backend(self) -> str:
        return self._inner.backend

    def render(
        self,
        data: Any = None,
        *,
        affine: Any = None,
        layout: Optional[str] = None,
        frame: Optional[str] = None,
        positions: Any = None,
        demo: Optional[str] = None,
        **options: Any,
    ) -> Image:
        """See ``tensorglyph.render``."""
        options.setdefault("quiet", True)
        mask = options.pop("mask", None)
        underlay = options.pop("underlay", None)
        args: list = []
        field = None if data is None else _field(data, affine, layout, frame, positions, args)
        arrays = [v for v in (mask, underlay) if v is not None and not isinstance(v, (str, os.PathLike))]
        if arrays and isinstance(field, str):
            # Arrays take the tensors' lattice: read the file first to know it.
            field, args = _tensorglyph.Field.read(field, args), []
        vol_affine = None
        if arrays and isinstance(field, _tensorglyph.Field) and field.dims is not None:
            info = json.loads(field.info_json([]))
            vol_affine = (info.get("frame") or {}).get("voxel_to_world")
        mask_volume = underlay_volume = None
        if mask is not None and not isinstance(mask, (str, os.PathLike)):
            mask_volume = _volume(mask, vol_affine, "mask")
            mask = None
        if underlay is not None and not isinstance(underlay, (str, os.PathLike)):
            underlay_volume = _volume(underlay, vol_affine, "underlay")
            underlay = None
        options["mask"] = mask
        options["underlay"] = underlay
        args += _cli_args(options)
        rgba, report, fell_back = self._inner.render(
            field, args, demo=demo, mask=mask_volume, underlay=underlay_volume
        )
        info = json.loads(report)
        info["fell_back_to_reference"] = fell_back
        dpi = options.get("dpi")
        return Image(rgba, info, bool(options.get("transparent")), None if dpi is None else float(dpi))


_shared = None
_shared_lock = threading.Lock()


def _renderer() -> Renderer:
    global _shared
    with _shared_lock:
        if _shared is None:
            _shared = Renderer("auto")
        return _shared


def render(
    data: Any = None,
    *,
    affine: Any = None,
    layout: Optional[str] = None,
    frame: Optional[str] = None,
    positions: Any = None,
    demo: Optional[str] = None,
    renderer: Optional[Renderer] = None,
    **options: Any,
) -> Image:
    """Render tensors to an ``Image``.

    ``data``: a file's path (any format the command line reads), a ``Field``, a numpy array of
    tensors (``(..., 6)`` with ``layout`` or ``(..., 3, 3)``), a DIPY ``TensorFit`` or a nibabel
    image; or ``demo="grid40"``. A DIPY fit in spherical harmonics (``CsdFit``, any fit with
    ``shm_coeff``), with its image's ``affine``, and files of SH series are drawn as ODF glyphs;
    DIPY's peaks (``PeaksAndMetrics``: ``peak_dirs`` scaled by ``peak_values``, its ``affine`` or
    ``affine=``) and files of peaks as sticks. A lattice ``(X, Y, Z, ...)`` takes ``affine`` (4×4 voxel to
    world; identity when absent), an ``(N, ...)`` array ``positions`` ``(N, 3)``. ``frame``:
    the axes the tensors are in (``voxel``, the default for arrays, fits and NIfTI; ``fsl``;
    ``world``), as ``--tensor-frame``.

    ``options``: every option of ``tensorglyph render`` with underscores (``size=(w, h)``,
    ``glyph=``, ``color=``, ``method=``, ``view=``, ``slice="z=5"`` or a list, ``underlay="fa"``
    or an array or a path, ``mask=``, ``scale=``, ``size_by=``, ``ssaa=``, ``outlines=``,
    ``shadows=``, ``legend=``, ``transparent=``, ``background=``, ``reference_check=`` ...),
    with the command line's defaults for the same data (arrays on a lattice, fits and NIfTI
    images are DTI data: the DTI defaults). ``quiet=False`` shows progress bars. The module's
    renderer is shared by the process; ``renderer=`` picks another."""
    return (renderer or _renderer()).render(
        data,
        affine=affine,
        layout=layout,
        frame=frame,
        positions=positions,
        demo=demo,
        **options,
    )


def report(
    files: "str | os.PathLike | Sequence[str | os.PathLike] | None" = None,
    out_dir: "str | os.PathLike | None" = None,
    *,
    bids_dir: "str | os.PathLike | None" = None,
    participant_label: "Sequence[str] | str | None" = None,
    tile_size: Optional[int] = None,
    zoom_region: "str | Sequence[int] | None" = None,
    sh_basis: Optional[str] = None,
    odf_normalize: Optional[str] = None,
    color: Optional[str] = None,
    reproducible: bool = False,
    renderer: Optional[Renderer] = None,
) -> dict:
    """Glyph reports, as ``tensorglyph report`` makes them: ``report(files, out_dir)`` writes one
    report per tensor file (``report FILE... -o OUT_DIR``); ``report(bids_dir=...,
    out_dir=..., participant_label=[...])`` one per participant of a BIDS derivatives folder of
    BEP016 tensor maps (``report BIDS_DIR OUT_DIR participant --participant-label ...``).

    Returns ``{"written": {name: {"page": path, "figures": [paths]}}, "failed": {name:
    message}}``: a report that fails is named there, the others are written whole. Raises
    ``tensorglyph.Error`` (a ``ValueError``) for a usage error (both or neither of ``files``
    and ``bids_dir``, no ``out_dir``, an unknown participant, a bad ``tile_size`` or
    ``zoom_region``, the message naming the keyword).

    ``tile_size`` is ``--tile-size``: the overview tiles' side in pixels (128 to 1024, default
    256). ``zoom_region`` is ``--zoom-region``: the voxel each figure's zoomed inset is centred
    on and its side in voxels, as ``"I,J,K:SIZE"`` or ``(i, j, k, size)``; by default the
    48-voxel square of each row's middle slice where FA is highest. ``sh_basis`` is
    ``--sh-basis``: the basis of the files of SH series (``"tournier07"``, ``"descoteaux07"``,
    ``"descoteaux07-legacy"``); by default each file's writer's. ``odf_normalize`` is
    ``--odf-normalize`` for the ODF maps' figures (``"max"``, the default, ``"minmax"``,
    ``"none"``). ``color`` is ``--color`` for the ODF maps' figures (``"dec"``, the default,
    or ``"amplitude"``). ``reproducible`` is ``--reproducible``: the pages leave out times and
    memory, so that two runs over the same data on the same machine write the same bytes (a
    cohort run in parallel, e.g. one Dask task per participant, checked against a serial run).
    The participant level also writes ``sub-<label>.json`` beside each page, which
    :func:`group_report` reads."""
    if out_dir is None:
        raise Error("report needs out_dir, the folder the reports go to")
    if color is not None and not isinstance(color, str):
        raise Error(f"color={color!r}: give 'dec' or 'amplitude'")
    if not isinstance(reproducible, bool):
        raise Error(f"reproducible={reproducible!r}: give True or False")
    if isinstance(files, (str, os.PathLike)):
        files = [files]
    if isinstance(participant_label, str):
        participant_label = [participant_label]
    if tile_size is not None and (
        isinstance(tile_size, bool) or not isinstance(tile_size, int) or not 0 <= tile_size < 2**32
    ):
        raise Error(f"tile_size={tile_size!r}: the tile side must be a whole number of pixels")
    if zoom_region is not None and not isinstance(zoom_region, str):
        try:
            i, j, k, size = (int(v) for v in zoom_region)
        except (TypeError, ValueError):
            raise Error(
                f"zoom_region={zoom_region!r}: give 'I,J,K:SIZE' or (i, j, k, size)"
            ) from None
        zoom_region = f"{i},{j},{k}:{size}"
    if sh_basis is not None and not isinstance(sh_basis, str):
        raise Error(f"sh_basis={sh_basis!r}: give a basis's name, e.g. 'tournier07'")
    if odf_normalize is not None and not isinstance(odf_normalize, str):
        raise Error(f"odf_normalize={odf_normalize!r}: give 'max', 'minmax' or 'none'")
    text = (renderer or _renderer())._inner.report(
        os.fspath(out_dir),
        files=None if files is None else [os.fspath(f) for f in files],
        bids_dir=None if bids_dir is None else os.fspath(bids_dir),
        participant_label=list(participant_label or []),
        tile_size=tile_size,
        zoom_region=zoom_region,
        sh_basis=sh_basis,
        odf_normalize=odf_normalize,
        color=color,
        reproducible=reproducible,
    )
    done = json.loads(text)
    return {
        "written": {
            w["name"]: {"page": w["page"], "figures": w["figures"]} for w in done["written"]
        },
        "failed": {f["name"]: f["error"] for f in done["failed"]},
    }


def group_report(
    bids_dir: "str | os.PathLike",
    out_dir: "str | os.PathLike",
    *,
    participant_label: "Sequence[str] | str | None" = None,
) -> dict:
    """The group level, as ``tensorglyph report BIDS_DIR OUT_DIR group``: ``group.html`` and
    ``group.tsv`` in ``out_dir`` over the participant level's reports there (one row per map,
    outliers flagged by robust z-scores; a participant whose report failed or is missing is a
    row saying so). No image is drawn. Returns ``{"page", "table", "participants", "maps",
    "without_report": [names], "flagged": [[participant, map]]}``; raises ``tensorglyph.Error``
    for a usage error (no such folder, an unknown participant)."""
    if isinstance(participant_label, str):
        participant_label = [participant_label]
    return json.loads(
        _tensorglyph.group_report(
            os.fspath(bids_dir), os.fspath(out_dir), list(participant_label or [])
        )
    )


def widget(data: Any = None, **options: Any):
    """An interactive view in a Jupyter notebook (``pip install tensorglyph[notebook]``):
    frames rendered by the Rust renderer, the mouse orbits (drag) and zooms (wheel). Takes
    ``render``'s arguments."""
    from ._widget import GlyphWidget

    return GlyphWidget(data, **options)
