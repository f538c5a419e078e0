//! `tensorglyph._tensorglyph`: the Python package's extension module. Arguments and glue only:
//! every field, image and report is made by the `tensorglyph` library, the command line's own
//! code paths (`tensorglyph::cli`), with the data handed over in memory.
//!
//! The pure-Python layer (`python/tensorglyph/`) turns keyword arguments into the command
//! line's options and numpy arrays, DIPY fits and nibabel images into the arrays taken here.
//!
//! Every call that works releases the GIL (`Python::detach`) and runs under `catch_unwind`: a
//! Rust panic becomes a `tensorglyph.Error`, never a `PanicException`. Library errors become
//! `tensorglyph.Error` (a `ValueError`) with the command line's one-line message, file errors
//! `tensorglyph.FileNotFound` / `tensorglyph.FileError` (also `FileNotFoundError` / `OSError`);
//! the classes live in `tensorglyph/_errors.py`.

#![deny(unsafe_code)]

use std::ffi::OsString;
use std::ops::Deref;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, MutexGuard};

use numpy::ndarray::{Array2, Array3, Axis};
use numpy::{PyArray2, PyArray3, PyReadonlyArray3, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use tensorglyph::backend::Backend;
use tensorglyph::cli::args::SceneArgs;
use tensorglyph::cli::render::{FrameArgs, Rendered, render_frame};
use tensorglyph::error::{LoadError, LoadErrorKind};
use tensorglyph::field::array::{self, Components};
use tensorglyph::field::{ComponentOrder, Inputs, ScalarVolume, TensorField, TensorFrame, nifti};
use tensorglyph::progress::Silent;
use tensorglyph::request::Method;
use tensorglyph::scene::underlay::{NamedVolume, UnderlaySource};
use tensorglyph::select::Mask;
use tensorglyph::staging::{Demo, InMemory, InMemoryFile, Source};

/// How an error reaches Python: its class in `tensorglyph._errors` and its one line.
enum Failure {
    /// A file that is not there.
    Missing(String),
    /// A file that cannot be read (permissions, a folder, a FIFO).
    Unreadable(String),
    /// Everything else: bad data, bad options, a renderer that failed.
    Value(String),
}

impl Failure {
    fn value(e: impl std::fmt::Display) -> Self {
        Failure::Value(e.to_string())
    }

    /// The class the library's error belongs to, with the command line's message.
    fn of(e: &anyhow::Error) -> Self {
        // As the command line prints it (`error: ` left out: Python names the class).
        let line = format!("{e:#}");
        let load = e.chain().find_map(|c| {
            c.downcast_ref::<LoadError>().map(|l| &l.kind).or_else(|| {
                match c.downcast_ref::<tensorglyph::staging::StageError>() {
                    Some(tensorglyph::staging::StageError::Load(l)) => Some(&l.kind),
                    _ => None,
                }
            })
        });
        match load {
            Some(LoadErrorKind::Missing | LoadErrorKind::SetMemberMissing { .. }) => {
                Failure::Missing(line)
            }
            Some(LoadErrorKind::Io(_) | LoadErrorKind::NotRegularFile(_)) => {
                Failure::Unreadable(line)
            }
            // The library's own checks speak command-line flags: Python names keywords.
            _ => Failure::Value(keywords_of(&line)),
        }
    }

    fn into_py(self, py: Python<'_>) -> PyErr {
        let (class, line) = match self {
            Failure::Missing(l) => ("FileNotFound", l),
            Failure::Unreadable(l) => ("FileError", l),
            Failure::Value(l) => ("Error", l),
        };
        let made = py
            .import("tensorglyph._errors")
            .and_then(|m| m.getattr(class))
            .and_then(|c| c.call1((line.clone(),)));
        match made {
            Ok(err) => PyErr::from_value(err),
            // The package's own module is missing: still a ValueError with the message.
            Err(_) => PyValueError::new_err(line),
        }
    }
}

/// `line` with the command line's flags spelled as the Python keywords that give them
/// (`--ao-reach` → `ao_reach=`, `--fa-*` → `fa_*=`): a flag is `--` at the line's start or after
/// a space, bracket or quote, then a lowercase name. The rest of the line is left as it is.
fn keywords_of(line: &str) -> String {
    let b = line.as_bytes();
    let mut out = String::with_capacity(line.len());
    let mut copied = 0;
    let mut i = 0;
    while i + 2 < b.len() {
        let starts = b[i] == b'-'
            && b[i + 1] == b'-'
            && b[i + 2].is_ascii_lowercase()
            && (i == 0 || matches!(b[i - 1], b' ' | b'(' | b'\'' | b'"' | b'`'));
        if !starts {
            i += 1;
            continue;
        }
        let mut end = i + 2;
        while end < b.len()
            && (b[end].is_ascii_lowercase() || b[end].is_ascii_digit() || b[end] == b'-')
        {
            end += 1;
        }
        if end < b.len() && b[end] == b'*' {
            end += 1;
        }
        out.push_str(&line[copied..i]);
        out.push_str(&line[i + 2..end].trim_end_matches('-').replace('-', "_"));
        out.push('=');
        copied = end;
        i = end;
    }
    out.push_str(&line[copied..]);
    out
}

/// An option the command line's parser refused, named as Python spells the keyword that gave
/// it (`glyph='banana': not one of: ellipsoid, …`); the command line's line where the parser
/// names no option.
fn keyword_error(e: Box<tensorglyph::cli::OptionError>) -> Failure {
    let keyword = |flag: &str| flag.strip_prefix("--").map(|f| f.replace('-', "_"));
    let Some(name) = e.option.as_deref().and_then(keyword) else {
        return Failure::Value(e.to_string());
    };
    // Numbers as Python writes them, anything else as a quoted string.
    let value = match e.value.as_deref() {
        Some(v) if v.parse::<f64>().is_ok() => v.to_string(),
        Some(v) => format!("'{}'", v.escape_default()),
        None => String::new(),
    };
    let mut line = format!("{name}={value}: {}", e.reason);
    if let Some(other) = e.conflicts_with.as_deref().and_then(keyword) {
        line = format!("{name}= cannot be used with {other}=");
    } else if let Some(other) = e.suggested.as_deref().and_then(keyword) {
        line.push_str(&format!(" (did you mean {other}=?)"));
    }
    Failure::Value(line)
}

/// Run `work` without the GIL, a panic caught and turned into an error.
fn detached<T: Send>(
    py: Python<'_>,
    work: impl FnOnce() -> Result<T, Failure> + Send,
) -> PyResult<T> {
    let result = py.detach(|| {
        catch_unwind(AssertUnwindSafe(work)).unwrap_or_else(|panic| {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown".into());
            Err(Failure::Value(format!(
                "internal error (a bug in tensorglyph, please report it): {what}"
            )))
        })
    });
    result.map_err(|f| f.into_py(py))
}

/// The command line: `argv` as `sys.argv` holds it (the program's name first). Returns the exit
/// status; stdout and stderr are the process's, as the binary's are.
#[pyfunction]
fn cli_main(py: Python<'_>, argv: Vec<OsString>) -> i32 {
    py.detach(|| {
        let status = catch_unwind(AssertUnwindSafe(|| tensorglyph::cli::main(argv)))
            .unwrap_or_else(|_| {
                eprintln!("error: internal error (a bug in tensorglyph, please report it)");
                2
            });
        // Python, not Rust, ends the process: what Rust buffered goes out now.
        use std::io::Write;
        let _ = std::io::stdout().flush();
        status
    })
}

/// `fsl`, `nifti`, `mrtrix`, `vtk` or `bep016` (BIDS's derivative order, FSL's), or `full`
/// for nine values per tensor.
fn components(layout: &str) -> Result<Components, Failure> {
    match layout {
        "full" => Ok(Components::Nine),
        "bep016" => Ok(Components::Six(ComponentOrder::Fsl)),
        other => other
            .parse::<ComponentOrder>()
            .map(Components::Six)
            .map_err(|_| {
                Failure::Value(format!(
                    "layout '{other}' is not one of fsl, nifti, mrtrix, vtk, bep016"
                ))
            }),
    }
}

fn tensor_frame(frame: Option<&str>) -> Result<Option<TensorFrame>, Failure> {
    frame
        .map(|f| {
            f.parse::<TensorFrame>()
                .map_err(|_| Failure::Value(format!("frame '{f}' is not one of voxel, fsl, world")))
        })
        .transpose()
}

/// The values of an array in its memory order (C order: the last index fastest), copied once.
fn values_in_order(a: &PyReadonlyArrayDyn<'_, f64>) -> Vec<f64> {
    match a.as_slice() {
        Ok(values) => values.to_vec(),
        Err(_) => a.as_array().iter().copied().collect(),
    }
}

/// Eigenvalues `(N, 3)` and eigenvectors `(N, 3, 3)`.
type Eigen<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray3<f64>>);

/// A tensor field held by Python: read from a file, or made of arrays.
#[pyclass(frozen, module = "tensorglyph._tensorglyph")]
struct Field {
    field: Arc<TensorField>,
    /// What messages call it: the file, or "array".
    name: String,
    /// Diffusion data: the DTI defaults (NIfTI and NRRD files, lattices of arrays).
    diffusion: bool,
}

impl Field {
    fn new(field: TensorField, name: String, diffusion: bool) -> Self {
        Self {
            field: Arc::new(field),
            name,
            diffusion,
        }
    }
}

#[pymethods]
impl Field {
    /// Read a tensor file as the command line does; `args` are its scene options (`--order`,
    /// `--tensor-frame`, `--array`).
    #[staticmethod]
    fn read(py: Python<'_>, path: PathBuf, args: Vec<String>) -> PyResult<Self> {
        detached(py, || {
            let scene: SceneArgs = tensorglyph::cli::parse_options(args).map_err(keyword_error)?;
            let source = Source::File(path.clone());
            let diffusion = tensorglyph::defaults::DataKind::of(&source)
                == tensorglyph::defaults::DataKind::Diffusion;
            let field = tensorglyph::staging::read(&source, &scene.read_options(), &Silent)
                .map_err(|e| Failure::of(&e.into()))?;
            Ok(Field::new(field, path.display().to_string(), diffusion))
        })
    }

    /// A lattice: `values` is `(X, Y, Z, C)` (C the layout's count), placed by `affine`.
    #[staticmethod]
    #[pyo3(signature = (values, layout, affine, frame=None))]
    fn from_lattice(
        py: Python<'_>,
        values: PyReadonlyArrayDyn<'_, f64>,
        layout: &str,
        affine: [[f64; 4]; 4],
        frame: Option<&str>,
    ) -> PyResult<Self> {
        let shape = values.shape().to_vec();
        let values = values_in_order(&values);
        let (layout, frame) = (layout.to_string(), frame.map(str::to_string));
        detached(py, move || {
            let components = components(&layout)?;
            let &[x, y, z, c] = shape.as_slice() else {
                return Err(Failure::value("a lattice is (X, Y, Z, C)"));
            };
            if c != components.len() {
                return Err(Failure::value(format!(
                    "{c} values per voxel for layout '{layout}'"
                )));
            }
            // NIfTI's voxel order, x fastest, from numpy's C order, z fastest.
            let mut xfast = Vec::with_capacity(values.len());
            for k in 0..z {
                for j in 0..y {
                    for i in 0..x {
                        let at = ((i * y + j) * z + k) * c;
                        xfast.extend_from_slice(&values[at..at + c]);
                    }
                }
            }
            let (values, dims) = (xfast, [x, y, z]);
            let frame = tensor_frame(frame.as_deref())?;
            let field = array::lattice(dims, affine, components, &values, frame)
                .map_err(|e| Failure::Value(e.to_string()))?;
            Ok(Field::new(field, "array".into(), true))
        })
    }

    /// Tensors at world positions: `values` is `(N, C)`, `positions` `(N, 3)`.
    #[staticmethod]
    fn from_points(
        py: Python<'_>,
        values: PyReadonlyArrayDyn<'_, f64>,
        layout: &str,
        positions: PyReadonlyArrayDyn<'_, f64>,
    ) -> PyResult<Self> {
        let values = values_in_order(&values);
        let positions: Vec<[f64; 3]> = positions
            .as_array()
            .rows()
            .into_iter()
            .map(|r| std::array::from_fn(|i| r.get(i).copied().unwrap_or(f64::NAN)))
            .collect();
        let layout = layout.to_string();
        detached(py, move || {
            let components = components(&layout)?;
            let field = array::points(positions, components, &values)
                .map_err(|e| Failure::Value(e.to_string()))?;
            Ok(Field::new(field, "array".into(), false))
        })
    }

    /// A NIfTI-1 file's bytes (a nibabel image's `to_bytes()`), read by the file reader;
    /// `args` as for `Field::read`.
    #[staticmethod]
    fn from_nifti_bytes(
        py: Python<'_>,
        bytes: Vec<u8>,
        name: String,
        args: Vec<String>,
    ) -> PyResult<Self> {
        detached(py, move || {
            let scene: SceneArgs = tensorglyph::cli::parse_options(args).map_err(keyword_error)?;
            let inputs = Inputs::named([(name.clone(), bytes)]);
            let field = inputs
                .open(Path::new(&name))
                .and_then(|input| nifti::read(&input, &scene.read_options()))
                .map_err(|kind| Failure::Value(LoadError::new(&name, kind).to_string()))?;
            Ok(Field::new(field, name, true))
        })
    }

    /// Tensors in the field (valid or not).
    fn __len__(&self) -> usize {
        self.field.len()
    }

    /// The lattice's dimensions, if the tensors sit on one (point data).
    #[getter]
    fn dims(&self) -> Option<[usize; 3]> {
        self.field.lattice_dims()
    }

    #[getter]
    fn name(&self) -> &str {
        &self.name
    }

    #[getter]
    fn diffusion(&self) -> bool {
        self.diffusion
    }

    /// `info --json` of this field, with `samples` (tensor indices in file order).
    fn info_json(&self, py: Python<'_>, samples: Vec<usize>) -> PyResult<String> {
        let field = self.field.clone();
        detached(py, move || {
            let set = tensorglyph::staging::decompose(&field, &Silent);
            let report =
                tensorglyph::info::info_report(&field, &set, &samples).map_err(Failure::Value)?;
            serde_json::to_string(&report).map_err(Failure::value)
        })
    }

    /// Eigenvalues `(N, 3)` (descending) and eigenvectors `(N, 3, 3)` (`[i, :, k]` is e_k, as
    /// DIPY's `evecs`) of every symmetrised world tensor, in file order; NaN where a tensor is
    /// not finite.
    fn eigen<'py>(&self, py: Python<'py>) -> PyResult<Eigen<'py>> {
        let field = self.field.clone();
        let (values, vectors) = detached(py, move || {
            use tensorglyph::tensor::eigen::{symmetric_eigen, symmetrise};
            let n = field.len();
            let mut values = Array2::<f64>::from_elem((n, 3), f64::NAN);
            let mut vectors = Array3::<f64>::from_elem((n, 3, 3), f64::NAN);
            for (i, (mut val, mut vec)) in values
                .axis_iter_mut(Axis(0))
                .zip(vectors.axis_iter_mut(Axis(0)))
                .enumerate()
            {
                let world = field.world_tensor(i);
                if world.iter().all(|x| x.is_finite()) {
                    let e = symmetric_eigen(&symmetrise(&world).0);
                    for k in 0..3 {
                        val[k] = e.values[k];
                        for r in 0..3 {
                            vec[[r, k]] = e.vectors[k][r];
                        }
                    }
                }
            }
            Ok((values, vectors))
        })?;
        Ok((
            PyArray2::from_owned_array(py, values),
            PyArray3::from_owned_array(py, vectors),
        ))
    }
}

/// A scalar volume held by Python, for `mask=` and `underlay=`.
#[pyclass(frozen, module = "tensorglyph._tensorglyph")]
struct Volume {
    volume: Arc<ScalarVolume>,
    name: String,
}

#[pymethods]
impl Volume {
    /// `values` is `(X, Y, Z)`, placed by `affine`.
    #[staticmethod]
    fn from_array(
        py: Python<'_>,
        values: PyReadonlyArrayDyn<'_, f64>,
        affine: [[f64; 4]; 4],
        name: String,
    ) -> PyResult<Self> {
        let view = values.as_array();
        let shape = view.shape().to_vec();
        let values: Vec<f32> = view.reversed_axes().iter().map(|&x| x as f32).collect();
        detached(py, move || {
            let dims: [usize; 3] = shape
                .try_into()
                .map_err(|_| Failure::value(format!("{name}: a volume has three dimensions")))?;
            let volume = array::scalar_volume(dims, values, affine)
                .map_err(|e| Failure::Value(format!("{name}: {e}")))?;
            Ok(Volume {
                volume: Arc::new(volume),
                name,
            })
        })
    }

    /// A NIfTI-1 file's bytes, read by the scalar-volume reader.
    #[staticmethod]
    fn from_nifti_bytes(py: Python<'_>, bytes: Vec<u8>, name: String) -> PyResult<Self> {
        detached(py, move || {
            let inputs = Inputs::named([(name.clone(), bytes)]);
            let volume = inputs
                .open(Path::new(&name))
                .and_then(|input| nifti::read_scalar(&input))
                .map_err(|kind| Failure::Value(LoadError::new(&name, kind).to_string()))?;
            Ok(Volume {
                volume: Arc::new(volume),
                name,
            })
        })
    }
}

/// A file's bytes in memory under its name (`fit.nii`), rendered as the file of that name is:
/// the package's DIPY fits in spherical harmonics, which nibabel writes as NIfTI bytes.
#[pyclass(frozen, module = "tensorglyph._tensorglyph")]
struct NamedBytes {
    file: InMemoryFile,
}

#[pymethods]
impl NamedBytes {
    #[new]
    fn new(bytes: Vec<u8>, name: String) -> Self {
        NamedBytes {
            file: InMemoryFile {
                name,
                bytes: Arc::new(bytes),
            },
        }
    }
}

/// What a render is of.
#[derive(FromPyObject)]
enum Data<'py> {
    Field(PyRef<'py, Field>),
    Bytes(PyRef<'py, NamedBytes>),
    Path(PathBuf),
}

/// The GPU device and its pipelines, made on first use and kept.
enum Gpu {
    NotYet,
    Ready(Backend),
    /// No adapter: `auto` renders with the reference, `gpu` fails.
    Missing,
}

/// What a frame is drawn with: the kept GPU (locked while drawing) or the exact reference.
enum Held<'a> {
    Gpu(MutexGuard<'a, Gpu>),
    Reference(Backend),
}

impl Deref for Held<'_> {
    type Target = Backend;
    fn deref(&self) -> &Backend {
        match self {
            Held::Gpu(g) => match &**g {
                Gpu::Ready(b) => b,
                _ => unreachable!("Renderer::back_end holds the lock only on a ready GPU"),
            },
            Held::Reference(b) => b,
        }
    }
}

/// A renderer that lives for the process: the GPU device, its pipelines and shader modules
/// are made on the first frame and reused by every later one. `backend`: `auto` (the GPU, or
/// the exact CPU reference where there is no adapter), `gpu` (an error without one) or `cpu`
/// (the reference). Frames from several threads are drawn one at a time; reading and staging
/// run in parallel.
#[pyclass(frozen, module = "tensorglyph._tensorglyph")]
struct Renderer {
    choice: String,
    gpu: Mutex<Gpu>,
}

impl Renderer {
    fn back_end(&self, method: Method) -> anyhow::Result<(Held<'_>, bool)> {
        if !method.is_gpu() || self.choice == "cpu" {
            return Ok((Held::Reference(Backend::Reference), false));
        }
        let mut gpu = self.gpu.lock().unwrap_or_else(|e| e.into_inner());
        if matches!(*gpu, Gpu::NotYet) {
            *gpu = match Backend::for_method(method)? {
                (b @ Backend::Gpu(_), _) => Gpu::Ready(b),
                (Backend::Reference, _) => Gpu::Missing,
            };
        }
        match *gpu {
            Gpu::Ready(_) => Ok((Held::Gpu(gpu), false)),
            _ if self.choice == "gpu" => anyhow::bail!(
                "no GPU adapter available (Renderer(backend=\"gpu\")); \
                 backend=\"auto\" falls back to the exact CPU reference"
            ),
            _ => Ok((Held::Reference(Backend::Reference), true)),
        }
    }
}

#[pymethods]
impl Renderer {
    #[new]
    #[pyo3(signature = (backend="auto"))]
    fn new(backend: &str) -> PyResult<Self> {
        if !["auto", "gpu", "cpu"].contains(&backend) {
            return Err(PyValueError::new_err(format!(
                "backend '{backend}' is not one of auto, gpu, cpu"
            )));
        }
        Ok(Self {
            choice: backend.to_string(),
            gpu: Mutex::new(Gpu::NotYet),
        })
    }

    #[getter]
    fn backend(&self) -> &str {
        &self.choice
    }

    /// Render `data` (a `Field`, a file's path, or `None` with `demo`) with the `render`
    /// options `args` as the command line spells them; `mask` and `underlay` are volumes
    /// handed over in memory. Returns the RGBA pixels `(H, W, 4)`, `render --json`'s report and
    /// whether the reference stood in for a missing GPU.
    #[pyo3(signature = (data, args, demo=None, mask=None, underlay=None))]
    fn render<'py>(
        &self,
        py: Python<'py>,
        data: Option<Data<'py>>,
        args: Vec<String>,
        demo: Option<String>,
        mask: Option<PyRef<'_, Volume>>,
        underlay: Option<PyRef<'_, Volume>>,
    ) -> PyResult<(Bound<'py, PyArray3<u8>>, String, bool)> {
        let source = match (data, demo) {
            (Some(Data::Field(f)), None) => Source::Field(InMemory {
                field: f.field.clone(),
                name: f.name.clone(),
                diffusion: f.diffusion,
            }),
            (Some(Data::Path(p)), None) => Source::File(p),
            (Some(Data::Bytes(b)), None) => Source::Bytes(b.file.clone()),
            (None, Some(d)) => Source::Demo(d.parse::<Demo>().map_err(PyValueError::new_err)?),
            (None, None) => return Err(PyValueError::new_err("give data or demo")),
            (Some(_), Some(_)) => {
                return Err(PyValueError::new_err("give either data or demo, not both"));
            }
        };
        let mask = mask.map(|m| (m.volume.clone(), m.name.clone()));
        let underlay = underlay.map(|u| NamedVolume {
            name: u.name.clone(),
            volume: u.volume.clone(),
        });
        let (rendered, fell_back) = detached(py, move || {
            let mut frame: FrameArgs =
                tensorglyph::cli::render::parse_frame_args(args).map_err(keyword_error)?;
            if let Some((volume, name)) = mask {
                let m = Mask::new(name, volume).map_err(Failure::value)?;
                frame.select.mask_volume = Some(m);
            }
            if let Some(u) = underlay {
                frame.select.underlay = Some(UnderlaySource::Volume(u));
            }
            let mut fell_back = false;
            let rendered = render_frame(
                &source,
                &frame,
                |method| {
                    let (held, fell) = self.back_end(method)?;
                    fell_back = fell;
                    Ok(held)
                },
                &Silent,
            )
            .map_err(|e| Failure::of(&e))?;
            if let (Some(path), Some(diff)) = (&frame.image.diff, &rendered.diff) {
                // Never over a file the render read (its data, mask, underlay, pieces).
                let read: Vec<&std::path::Path> =
                    rendered.read.iter().map(|p| p.as_path()).collect();
                tensorglyph::image_out::write_png(
                    path,
                    &read,
                    rendered.width,
                    rendered.height,
                    diff,
                )
                .map_err(|e| {
                    Failure::Unreadable(format!("{}: cannot write: {e}", path.display()))
                })?;
            }
            Ok((rendered, fell_back))
        })?;
        let Rendered {
            width,
            height,
            color,
            report,
            ..
        } = rendered;
        let json =
            serde_json::to_string(&report).map_err(|e| PyValueError::new_err(e.to_string()))?;
        let pixels = Array3::from_shape_vec((height as usize, width as usize, 4), color)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok((PyArray3::from_owned_array(py, pixels), json, fell_back))
    }

    /// `tensorglyph report` with this renderer's back end: the reports of `files`, or of the
    /// participants of the BIDS derivatives folder `bids_dir` (those of `participant_label`
    /// when it names some), in `out_dir`. Returns JSON: `written` (name, page, figures) and
    /// `failed` (name, the command line's error line without `error: `). `tile_size` and
    /// `zoom_region` (`"I,J,K:SIZE"`) are `--tile-size` and `--zoom-region`, `sh_basis` and
    /// `odf_normalize` are `--sh-basis` and `--odf-normalize`, `color` is `--color` (of the ODF
    /// maps), `reproducible` is `--reproducible`; a bad one raises, naming the keyword.
    #[pyo3(signature = (out_dir, files=None, bids_dir=None, participant_label=Vec::new(), tile_size=None, zoom_region=None, sh_basis=None, odf_normalize=None, color=None, reproducible=false))]
    #[allow(clippy::too_many_arguments)]
    fn report(
        &self,
        py: Python<'_>,
        out_dir: PathBuf,
        files: Option<Vec<PathBuf>>,
        bids_dir: Option<PathBuf>,
        participant_label: Vec<String>,
        tile_size: Option<u32>,
        zoom_region: Option<String>,
        sh_basis: Option<String>,
        odf_normalize: Option<String>,
        color: Option<String>,
        reproducible: bool,
    ) -> PyResult<String> {
        use tensorglyph::report::inset;
        let mut options = tensorglyph::report::Options {
            reproducible,
            ..Default::default()
        };
        if let Some(px) = tile_size {
            options.tile = inset::check_tile(px)
                .map_err(|e| Failure::value(format!("tile_size={e}")).into_py(py))?;
        }
        if let Some(z) = zoom_region {
            options.zoom = Some(
                z.parse::<inset::ZoomRegion>()
                    .map_err(|e| Failure::value(format!("zoom_region={e}")).into_py(py))?,
            );
        }
        if let Some(b) = sh_basis {
            options.sh_basis = Some(
                b.parse::<tensorglyph::sh::ShBasis>()
                    .map_err(|e| Failure::value(format!("sh_basis={e}")).into_py(py))?,
            );
        }
        if let Some(n) = odf_normalize {
            options.odf_normalize = n
                .parse::<tensorglyph::scene::odf::OdfNormalize>()
                .map_err(|e| Failure::value(format!("odf_normalize={e}")).into_py(py))?;
        }
        if let Some(c) = color {
            options.odf_color = tensorglyph::cli::report::parse_odf_color(&c)
                .map_err(|e| Failure::value(format!("color={e}")).into_py(py))?;
        }
        let job = match (files, bids_dir) {
            (Some(files), None) if participant_label.is_empty() => {
                tensorglyph::report::Job::Files(files)
            }
            (Some(_), None) => {
                return Err(
                    Failure::value("participant_label applies to bids_dir, not to files")
                        .into_py(py),
                );
            }
            (None, Some(dir)) => tensorglyph::report::Job::Bids {
                dir,
                labels: participant_label,
            },
            _ => {
                return Err(
                    Failure::value("give either files or bids_dir (exactly one)").into_py(py),
                );
            }
        };
        detached(py, move || {
            let plan = tensorglyph::report::Plan::new(&job)
                .map_err(Failure::value)?
                .with_options(options);
            let (held, _) = self
                .back_end(Method::Gumhold)
                .map_err(|e| Failure::of(&e))?;
            let outcome = plan.run(&out_dir, &held, &Silent).map_err(Failure::value)?;
            let failed: Vec<serde_json::Value> = outcome
                .failed
                .iter()
                .map(|f| {
                    serde_json::json!({"name": f.name, "error": format!("{}: {}", f.name, f.error)})
                })
                .collect();
            Ok(serde_json::json!({"written": outcome.written, "failed": failed}).to_string())
        })
    }
}

/// `tensorglyph report BIDS_DIR OUT_DIR group`: the group page over the participant level's
/// reports in `out_dir` (no image is drawn). Returns the outcome as JSON.
#[pyfunction]
#[pyo3(signature = (bids_dir, out_dir, participant_label=Vec::new()))]
fn group_report(
    py: Python<'_>,
    bids_dir: PathBuf,
    out_dir: PathBuf,
    participant_label: Vec<String>,
) -> PyResult<String> {
    detached(py, move || {
        let o = tensorglyph::report::group::run(&bids_dir, &out_dir, &participant_label)
            .map_err(Failure::value)?;
        serde_json::to_string(&o).map_err(Failure::value)
    })
}

/// The PNG of RGBA pixels `(H, W, 4)`, as the command line writes it (`dpi` in its pHYs).
#[pyfunction]
#[pyo3(signature = (rgba, dpi=None))]
fn encode_png<'py>(
    py: Python<'py>,
    rgba: PyReadonlyArray3<'_, u8>,
    dpi: Option<f64>,
) -> PyResult<Bound<'py, PyBytes>> {
    let (h, w) = (rgba.shape()[0] as u32, rgba.shape()[1] as u32);
    let pixels: Vec<u8> = rgba.as_array().iter().copied().collect();
    let bytes = detached(py, move || {
        let mut out = Vec::new();
        tensorglyph::image_out::encode_png(&mut out, w, h, &pixels, dpi).map_err(Failure::value)?;
        Ok(out)
    })?;
    Ok(PyBytes::new(py, &bytes))
}

/// Write RGBA pixels `(H, W, 4)` to `path` as the command line does (atomically).
#[pyfunction]
#[pyo3(signature = (path, rgba, dpi=None))]
fn write_png(
    py: Python<'_>,
    path: PathBuf,
    rgba: PyReadonlyArray3<'_, u8>,
    dpi: Option<f64>,
) -> PyResult<()> {
    let (h, w) = (rgba.shape()[0] as u32, rgba.shape()[1] as u32);
    let pixels: Vec<u8> = rgba.as_array().iter().copied().collect();
    detached(py, move || {
        tensorglyph::image_out::write_png_dpi(&path, &[], w, h, &pixels, dpi).map_err(|e| {
            let line = format!("{}: cannot write: {e}", path.display());
            if e.kind() == std::io::ErrorKind::NotFound {
                Failure::Missing(line)
            } else {
                Failure::Unreadable(line)
            }
        })
    })
}

#[pymodule]
fn _tensorglyph(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Field>()?;
    m.add_class::<Volume>()?;
    m.add_class::<NamedBytes>()?;
    m.add_class::<Renderer>()?;
    m.add_function(wrap_pyfunction!(cli_main, m)?)?;
    m.add_function(wrap_pyfunction!(encode_png, m)?)?;
    m.add_function(wrap_pyfunction!(group_report, m)?)?;
    m.add_function(wrap_pyfunction!(write_png, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
