//! The options the commands share, one definition each: where the data comes from and how it
//! is read and styled (`SceneArgs`), which glyphs are drawn (`SelectArgs`), the camera
//! (`CameraArgs`, for `render`, `demo` and `view`) and how much work a frame does (`DrawArgs`).

use std::path::PathBuf;
use std::str::FromStr;

use anyhow::{Result, anyhow, bail, ensure};
use clap::Args;
use clap::builder::{PossibleValuesParser, TypedValueParser};

use crate::camera::{Framing, ViewPreset};
use crate::defaults::Defaults;
use crate::effects::ao::AmbientOcclusion;
use crate::effects::{Effects, Outlines, Shading, Shadows, light};
use crate::field::{ComponentOrder, FieldKind, ReadOptions, TensorFrame};
pub use crate::frame::parse_size;
use crate::glyph::superquadric::{MAX_GAMMA, Sharpness};
use crate::glyph::{ColorScheme, GlyphStyle, Normalize, Scale, SizeBy};
use crate::request::{DrawOptions, GlyphKind, Method, Preset, ProxyShape, UnderlayView};
use crate::scene::UnderlaySource;
use crate::scene::odf::OdfNormalize;
use crate::select::{Mask, Plane, Selection, Slicing, parse_roi};
use crate::sh::ShBasis;
use crate::staging::{Demo, Recipe, Source};

/// A value parser for one of `names` (clap lists them in `--help` and in its error).
pub fn one_of<T>(names: &'static [&'static str]) -> impl TypedValueParser<Value = T>
where
    T: FromStr<Err = String> + Clone + Send + Sync + 'static,
{
    PossibleValuesParser::new(names).try_map(|s| s.parse::<T>())
}

#[derive(Args, Debug, Clone)]
pub struct SceneArgs {
    /// Tensor array to use (default: the active tensors, else the first 9- or 6-component array).
    #[arg(long)]
    pub array: Option<String>,
    /// Component order of 6-component arrays where the file does not say (default: vtk for VTK
    /// files; fsl for NIfTI, where 5-D files with intent SYMMATRIX say nifti themselves; mrtrix
    /// for MRtrix .mif).
    #[arg(long, value_parser = one_of::<ComponentOrder>(ComponentOrder::NAMES))]
    pub order: Option<ComponentOrder>,
    /// The axes the file's tensors are in (default: voxel for NIfTI, world for NRRD and MRtrix
    /// .mif; VTK image tensors are rotated by the image's Direction): voxel (rotated into world
    /// by the voxel-to-world matrix), fsl (voxel, with FSL's x-flip for positive-determinant
    /// matrices) or world.
    #[arg(long, value_parser = one_of::<TensorFrame>(TensorFrame::NAMES))]
    pub tensor_frame: Option<TensorFrame>,
    /// The basis of a NIfTI or MRtrix file of SH coefficients (fibre ODFs): tournier07
    /// (MRtrix3), descoteaux07 or descoteaux07-legacy (DIPY's default). Default: tournier07 for
    /// files MRtrix wrote, descoteaux07-legacy for other NIfTI files. Given, it also reads a
    /// file of 6 volumes as SH (lmax 2) rather than tensors.
    #[arg(long, value_parser = one_of::<ShBasis>(ShBasis::NAMES))]
    pub sh_basis: Option<ShBasis>,
    /// What the file holds, where its header does not say: tensors, series (SH coefficients)
    /// or peaks (3 values a peak, as MRtrix's sh2peaks writes them). A NIfTI file of 9 volumes
    /// is full 3×3 tensors or three peaks, and is read only when this says which.
    #[arg(long, value_parser = one_of::<FieldKind>(FieldKind::NAMES))]
    pub holds: Option<FieldKind>,
    /// Colour scheme: shape classes, dec (direction), a scalar through a colour bar (fa, md;
    /// the stress measures von-mises, tresca, sigma1, sigma2, sigma3, mean, triaxiality), sign
    /// (tension red, compression blue), solid, or amplitude (ODF glyphs: the ODF's value in
    /// each direction, viridis). Default: auto (von-mises for stress fields, whose tensors are
    /// mostly indefinite, else shape); sign for --glyph principal; dec for DTI files, NIfTI and
    /// NRRD, and for files of SH series (dec, amplitude or solid).
    #[arg(long, value_parser = one_of::<ColorScheme>(ColorScheme::NAMES))]
    pub color: Option<ColorScheme>,
    /// The range a scalar colouring maps: LO and below take the colour bar's start, HI and
    /// above its end (a signed measure's map stays centred on zero). Default: the field's 2nd
    /// and 98th percentiles; 0,1 for fa.
    #[arg(long, value_name = "LO,HI", value_parser = parse_range, allow_hyphen_values = true)]
    pub color_range: Option<[f64; 2]>,
    /// The tensors' units, shown in a stress colouring's legend (default: from the array's
    /// name, as in "stress (MPa)").
    #[arg(long)]
    pub units: Option<String>,
    /// Glyph scale: `auto` (largest radius = half the grid spacing; on unstructured data, each
    /// glyph also within half its own spacing) or a factor on |λ|.
    #[arg(long, default_value = "auto")]
    pub scale: Scale,
    /// How radii follow |λ|: auto (with --scale auto, log for stress-like fields, whose tensors
    /// are mostly indefinite, else linear), linear, sqrt, log (for fields spanning orders of
    /// magnitude), fa (shape at a size ∝ FA) or none (shape only). Default: auto; none for DTI
    /// files (NIfTI, NRRD).
    #[arg(long, value_parser = one_of::<SizeBy>(SizeBy::NAMES))]
    pub size_by: Option<SizeBy>,
    /// Normalise eigenvalues before scaling.
    #[arg(long, default_value = "none", value_parser = one_of::<Normalize>(Normalize::NAMES))]
    pub normalize: Normalize,
    /// How each fibre ODF of a file of SH series is scaled: max (each voxel's to its own
    /// largest value, DIPY's odf_slicer), minmax (each voxel's [min, max] to [0, 1], mrview's
    /// normalise) or none (amplitudes comparable across voxels: the field's largest fills its
    /// voxel). Default: max.
    #[arg(long, value_parser = one_of::<OdfNormalize>(OdfNormalize::NAMES))]
    pub odf_normalize: Option<OdfNormalize>,
    /// Smallest radius as a fraction of the glyph's largest (keeps T invertible). Default 0.01;
    /// 0.25 for stress-like fields sized by the automatic log map (uniaxial stress is a needle
    /// otherwise).
    #[arg(long, value_name = "EPS")]
    pub min_radius: Option<f64>,
    /// Superquadric glyphs (--glyph superquadric): Kindlmann's sharpness γ ≥ 0, default 3 (0:
    /// ellipsoids; larger: boxier, sharper edges). Indefinite tensors take Schultz–Kindlmann's
    /// shapes, whose sharpness is fixed (β_max = 3).
    #[arg(long, value_name = "GAMMA", allow_hyphen_values = true)]
    pub sharpness: Option<f64>,
    /// Principal-stress glyphs (--glyph principal): a cone head at each end of every bar,
    /// pointing outward for tension and inward for compression.
    #[arg(long)]
    pub arrows: bool,
    /// Hide stresses below S in magnitude: principal-stress bars whose |σ| < S, and glyphs of
    /// other kinds whose largest |σ| < S (the stress twin of --fa-min).
    #[arg(long, value_name = "S")]
    pub min_stress: Option<f64>,
    /// No progress bars.
    #[arg(long, short)]
    pub quiet: bool,
}

impl SceneArgs {
    pub fn read_options(&self) -> ReadOptions {
        ReadOptions {
            array: self.array.clone(),
            order: self.order,
            tensor_frame: self.tensor_frame,
            sh_basis: self.sh_basis,
            holds: self.holds,
        }
    }

    /// The style asked for, with `defaults` (of the data's kind) for what was not.
    pub fn style(&self, defaults: &Defaults) -> Result<GlyphStyle> {
        let min_stress = self.min_stress.unwrap_or(0.0);
        ensure!(
            min_stress.is_finite() && min_stress >= 0.0,
            "--min-stress must be a finite number ≥ 0, got {min_stress}"
        );
        if let Some(e) = self.min_radius {
            ensure!(
                e.is_finite() && (0.0..=1.0).contains(&e),
                "--min-radius must be between 0 and 1, got {e}"
            );
        }
        let mut sharpness = Sharpness::default();
        if let Some(g) = self.sharpness {
            ensure!(
                g.is_finite() && (0.0..=MAX_GAMMA).contains(&g),
                "--sharpness must be between 0 and {MAX_GAMMA}, got {g}"
            );
            sharpness.gamma = g;
        }
        if let (Some(c), Some(_)) = (self.color, self.color_range)
            && c.measure().is_none()
        {
            bail!(
                "--color-range applies to the scalar colourings ({}), not --color {c}",
                scalar_schemes()
            );
        }
        Ok(GlyphStyle {
            color: self.color.unwrap_or(defaults.color),
            color_range: self.color_range,
            units: self.units.clone(),
            scale: self.scale,
            normalize: self.normalize,
            size_by: self.size_by.unwrap_or(defaults.size_by),
            min_radius: self.min_radius,
            sharpness,
            arrows: self.arrows,
            min_stress,
            ..GlyphStyle::default()
        })
    }

    /// The recipe of a scene of `glyph`s with these options and `selection`.
    pub fn recipe(
        &self,
        selection: Selection,
        glyph: GlyphKind,
        defaults: &Defaults,
    ) -> Result<Recipe> {
        ensure!(
            self.sharpness.is_none() || glyph.caps().sharpness,
            "--sharpness applies to --glyph {}",
            kinds_with(|c| c.sharpness)
        );
        ensure!(
            !self.arrows || glyph.caps().arrows,
            "--arrows applies to --glyph {}",
            kinds_with(|c| c.arrows)
        );
        let mut style = self.style(defaults)?;
        ensure!(
            glyph.colours(style.color),
            "--color {} applies to --glyph {}",
            style.color,
            kinds_with(|c| c.amplitude)
        );
        if let (None, Some(color)) = (self.color, glyph.shape().default_color()) {
            style.color = color;
        }
        let selection = Selection {
            min_stress: style.min_stress,
            ..selection
        };
        Ok(Recipe {
            read: self.read_options(),
            style,
            selection,
            glyph,
            underlay: None,
            middle_slice: false,
            underlay_side: None,
            odf_normalize: self.odf_normalize,
            peaks: false,
            peaks_over: false,
        })
    }
}

/// Which glyphs to draw (`render`, `demo`, `view`): the same selection as the viewer's panel.
/// Every flag narrows the selection; together they keep the glyphs that pass all of them.
#[derive(Args, Debug, Clone, Default)]
pub struct SelectArgs {
    /// Keep glyphs with FA ≥ F (0 to 1).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub fa_min: Option<f64>,
    /// Keep glyphs with FA ≤ F (0 to 1; 1 keeps indefinite tensors with FA above 1 too).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub fa_max: Option<f64>,
    /// Every N-th lattice position along each axis (file order for unstructured data); along a
    /// slice, every N-th position in its plane.
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub stride: usize,
    /// A lattice plane x=I, y=J or z=K (index from 0; structured data only). Repeatable: the
    /// union of the planes is kept. `all`: the whole lattice (DTI files, NIfTI and NRRD, show
    /// the middle axial slice when no --slice is given).
    #[arg(long = "slice", value_name = "AXIS=INDEX|all")]
    pub slices: Vec<SliceArg>,
    /// Region of interest: keep glyphs whose centre (world coordinates) is in the box
    /// x0,y0,z0,x1,y1,z1 (bounds included).
    #[arg(long, value_name = "X0,Y0,Z0,X1,Y1,Z1", value_parser = parse_roi, allow_hyphen_values = true)]
    pub roi: Option<[f64; 6]>,
    /// A greyscale image under the glyphs of every --slice plane (the middle z plane when no
    /// --slice is given): a measure of the tensors (fa, md, von-mises, tresca, sigma1, sigma2,
    /// sigma3, mean, triaxiality), or a scalar volume's file (NIfTI, NRRD), sampled through
    /// its own voxel-to-world matrix.
    #[arg(long, value_name = "MEASURE|FILE")]
    pub underlay: Option<UnderlaySource>,
    /// The underlay's window: LO and below black, HI and above white (default: the 2nd and
    /// 98th percentiles of its values).
    #[arg(long, value_name = "LO,HI", requires = "underlay", value_parser = parse_window,
          allow_hyphen_values = true)]
    pub underlay_range: Option<[f32; 2]>,
    /// A scalar volume (NIfTI, NRRD or VTK image data, in the tensors' world): keep glyphs
    /// whose centre's nearest voxel is non-zero (and not NaN or infinite); glyphs outside the
    /// volume are dropped. Its lattice need not be the tensors'.
    #[arg(long, value_name = "FILE")]
    pub mask: Option<PathBuf>,
    /// A mask handed over in memory instead of `--mask`'s file (the Python package's arrays).
    #[arg(skip)]
    pub mask_volume: Option<Mask>,
}

/// `LO,HI` with LO < HI, both finite.
fn parse_range(s: &str) -> Result<[f64; 2], String> {
    let bad = || format!("'{s}' is not LO,HI (two numbers, LO below HI)");
    let (lo, hi) = s.split_once(',').ok_or_else(bad)?;
    let lo: f64 = lo.trim().parse().map_err(|_| bad())?;
    let hi: f64 = hi.trim().parse().map_err(|_| bad())?;
    if !(lo.is_finite() && hi.is_finite() && lo < hi) {
        return Err(bad());
    }
    Ok([lo, hi])
}

/// [`parse_range`] in f32 (an underlay's window).
fn parse_window(s: &str) -> Result<[f32; 2], String> {
    let [lo, hi] = parse_range(s)?.map(|x| x as f32);
    if !(lo.is_finite() && hi.is_finite() && lo < hi) {
        return Err(format!("'{s}' is not LO,HI (two numbers, LO below HI)"));
    }
    Ok([lo, hi])
}

/// The names of the scalar colourings.
fn scalar_schemes() -> String {
    let names: Vec<&str> = ColorScheme::VALUES
        .iter()
        .filter(|c| c.measure().is_some())
        .map(|c| c.name())
        .collect();
    names.join(", ")
}

/// One `--slice`: a lattice plane, or `all` of the lattice.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SliceArg {
    Plane(Plane),
    All,
}

impl FromStr for SliceArg {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        if s.trim().eq_ignore_ascii_case("all") {
            Ok(SliceArg::All)
        } else {
            s.parse::<Plane>()
                .map(SliceArg::Plane)
                .map_err(|e| format!("{e}, or all"))
        }
    }
}

impl SelectArgs {
    /// Whether a data kind's default slice applies: no `--slice` was given.
    pub fn no_slice(&self) -> bool {
        self.slices.is_empty()
    }

    /// How the underlay is shown (`--underlay-range`).
    pub fn underlay_view(&self) -> UnderlayView {
        UnderlayView {
            shown: true,
            window: self.underlay_range,
        }
    }

    /// The selection these flags ask for, checked as far as it can be without the data; the
    /// mask file is read here, so a bad one stops the command before the tensors are read.
    pub fn selection(&self) -> Result<Selection> {
        let planes: Vec<Plane> = self
            .slices
            .iter()
            .filter_map(|s| match s {
                SliceArg::Plane(p) => Some(*p),
                SliceArg::All => None,
            })
            .collect();
        if !planes.is_empty() && planes.len() < self.slices.len() {
            bail!("--slice all cannot be given with planes");
        }
        let mask = match (&self.mask_volume, &self.mask) {
            (Some(mask), _) => Some(mask.clone()),
            // The load error names the file and the place; one line, no chain to repeat it.
            (None, Some(path)) => Some(Mask::read(path).map_err(|e| anyhow!("--mask {e}"))?),
            (None, None) => None,
        };
        let sel = Selection {
            fa_min: self.fa_min.unwrap_or(0.0),
            fa_max: self.fa_max.unwrap_or(1.0),
            stride: self.stride,
            slicing: if planes.is_empty() {
                Slicing::Whole
            } else {
                Slicing::Planes(planes)
            },
            roi: self.roi,
            mask,
            // From the scene options (SceneArgs::recipe), which hold --min-stress.
            min_stress: 0.0,
        };
        sel.check()?;
        Ok(sel)
    }
}

/// The method, the glyph and the camera (`render`, `demo`, `view`).
#[derive(Args, Debug, Clone)]
pub struct CameraArgs {
    /// Rendering method: gumhold or sigg (GPU ray casting), reference (exact CPU ray caster), or
    /// the triangle-mesh baselines mesh:N (icosphere / prism subdivided N = 0..=6 times) and box.
    #[arg(long, default_value = "gumhold")]
    pub method: Method,
    /// The glyph: ellipsoid unless given (odf for a file of SH series, which refuses another;
    /// cylinder for a file of peaks, or capsule), or peaks: the field as the sticks of its
    /// peaks, a file of SH series its maxima (DIPY's peaks_from_model settings: at least half
    /// the voxel's largest, 25° apart, at most 5), tensors their principal directions (FSL's
    /// V1 lines, half a voxel step × FA long each side).
    #[arg(long, value_parser = one_of::<GlyphChoice>(GlyphChoice::NAMES))]
    pub glyph: Option<GlyphChoice>,
    /// Draw the peaks of a file of SH series over its ODF glyphs: white sticks (coloured by
    /// direction over solid ODFs) through each voxel's centre along its maxima (as --glyph
    /// peaks finds them), 1.25 times as long as their lobes; depth decides between a stick and
    /// an ODF. Not with --shadows.
    #[arg(long)]
    pub peaks: bool,
    /// Write the proxy's depth instead of the ray-cast depth.
    #[arg(long)]
    pub no_depth_correction: bool,
    /// View direction preset: ParaView's +X … −Z buttons (looking along that axis), iso
    /// (from +x, −y, +z), or in an anatomical (RAS) world axial (from superior), coronal (from
    /// posterior) and sagittal (from the left), the subject's right on the right. Default: iso,
    /// or for a DTI file (NIfTI, NRRD) showing one slice, that slice face-on.
    #[arg(long, allow_hyphen_values = true,
          value_parser = one_of::<ViewPreset>(ViewPreset::NAMES))]
    pub view: Option<ViewPreset>,
    /// Degrees about the up axis, after the preset.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub azimuth: f64,
    /// Degrees about the camera's right axis, after the preset.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub elevation: f64,
    /// > 1 moves closer.
    #[arg(long, default_value_t = 1.0)]
    pub zoom: f64,
    /// Vertical field of view in degrees.
    #[arg(long, default_value_t = 30.0)]
    pub fov: f64,
    /// Orthographic projection.
    #[arg(long)]
    pub ortho: bool,
}

/// What `--glyph` asks for: a glyph kind, or the field's peaks as sticks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GlyphChoice {
    Kind(GlyphKind),
    Peaks,
}

impl GlyphChoice {
    /// The glyph kinds' names, then `peaks`.
    pub const NAMES: &'static [&'static str] = &[
        "ellipsoid",
        "cylinder",
        "capsule",
        "superquadric",
        "principal",
        "odf",
        "peaks",
    ];
}

impl FromStr for GlyphChoice {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "peaks" => Ok(GlyphChoice::Peaks),
            _ => s.parse::<GlyphKind>().map(GlyphChoice::Kind),
        }
    }
}

impl CameraArgs {
    /// The glyph `--glyph` asks for, where a field of `kind` named `name` offers it, and
    /// whether the field is drawn as the sticks of its peaks (`--glyph peaks`).
    pub fn glyph_for(&self, kind: FieldKind, name: &str) -> Result<(GlyphKind, bool)> {
        let asked = match self.glyph {
            Some(GlyphChoice::Peaks) => {
                // The sticks of a peaks file; SH series and tensors are drawn as theirs.
                let sticks = FieldKind::Peaks.offers().glyphs[0];
                return Ok((sticks, kind != FieldKind::Peaks));
            }
            Some(GlyphChoice::Kind(g)) => Some(g),
            None => None,
        };
        Ok((kind.glyph(asked, name).map_err(anyhow::Error::msg)?, false))
    }

    pub fn framing(&self) -> Result<Framing> {
        if !(self.fov > 0.0 && self.fov < 180.0) {
            bail!("--fov must be between 0 and 180 degrees, got {}", self.fov);
        }
        if !(self.zoom.is_finite() && self.zoom > 0.0) {
            bail!("--zoom must be a positive number, got {}", self.zoom);
        }
        Ok(Framing {
            view: self.view.unwrap_or_default(),
            azimuth: self.azimuth,
            elevation: self.elevation,
            zoom: self.zoom,
            fov_deg: self.fov,
            ortho: self.ortho,
            toward: None,
        })
    }
}

/// How much work a frame does: a preset, and options on top of it. The defaults are what
/// measured fastest on lavapipe with the reference's accuracy
/// (docs/book/src/concepts/doing-less-work.md).
#[derive(Args, Debug, Clone)]
pub struct DrawArgs {
    /// A named way of drawing: baseline (a quad per glyph, no culling, file order), culled,
    /// octagon, triangle, conservative, sorted, prepass, or splat (the default); the options
    /// below change it further.
    #[arg(long, default_value = "splat", value_parser = one_of::<Preset>(Preset::NAMES))]
    pub preset: Preset,
    /// The same as --preset baseline.
    #[arg(long, conflicts_with_all = ["preset", "prepass", "conservative_depth", "sort", "proxy", "splat", "no_cull"])]
    pub baseline: bool,
    /// Proxy polygon of Gumhold's ray casters: quad, octagon (fewer pixels, more triangles) or
    /// triangle (one triangle, more pixels).
    #[arg(long, value_parser = one_of::<ProxyShape>(ProxyShape::NAMES))]
    pub proxy: Option<ProxyShape>,
    /// Move Gumhold ellipsoid proxies to the glyph's nearest plane (conservative depth), and
    /// declare it for early depth tests where the adapter supports that.
    #[arg(long)]
    pub conservative_depth: bool,
    /// Draw glyphs outside the view frustum too (by default they are culled).
    #[arg(long)]
    pub no_cull: bool,
    /// Skip glyphs whose projected bounding sphere is smaller than this radius in pixels
    /// (0: draw all; glyphs under ~0.3 px rarely cover a pixel centre).
    #[arg(long, default_value_t = 0.0, value_name = "PX")]
    pub min_pixel_radius: f32,
    /// Draw front to back (in depth layers of a few glyph diameters) instead of in file order:
    /// pays where early depth tests reject hidden fragments, and in the splats' compute pass
    /// (the splat preset sorts already); the prepass's drawn glyphs keep no fixed order.
    #[arg(long)]
    pub sort: bool,
    /// Gumhold ellipsoids and superquadrics: build each glyph's proxy once in a compute pass
    /// (not once per vertex) and draw only the glyphs it keeps, so culled glyphs cost nothing in
    /// the draw (on whenever --splat is above 0).
    #[arg(long)]
    pub prepass: bool,
    /// Gumhold ellipsoids and superquadrics with depth correction: ray cast glyphs whose proxy
    /// spans at most PX pixels across per pixel in a compute pass instead of drawing them (0:
    /// draw every glyph; default 32 with the splat preset).
    #[arg(long, value_name = "PX")]
    pub splat: Option<u32>,
}

impl DrawArgs {
    fn preset(&self) -> Preset {
        if self.baseline {
            Preset::Baseline
        } else {
            self.preset
        }
    }

    /// The options asked for, refused where `method` drawing `glyph` would ignore one that was
    /// given explicitly.
    pub fn options(
        &self,
        method: Method,
        glyph: GlyphKind,
        depth_correction: bool,
    ) -> Result<DrawOptions> {
        ensure!(
            self.min_pixel_radius.is_finite() && self.min_pixel_radius >= 0.0,
            "--min-pixel-radius must be a number of pixels ≥ 0, got {}",
            self.min_pixel_radius
        );
        let preset = self.preset().options();
        let opts = DrawOptions {
            proxy: self.proxy.unwrap_or(preset.proxy),
            conservative: preset.conservative || self.conservative_depth,
            prepass: preset.prepass || self.prepass,
            splat: self.splat.unwrap_or(preset.splat),
            cull: preset.cull && !self.no_cull,
            min_pixel_radius: self.min_pixel_radius,
        };
        if let Err((flag, who)) = opts.check(&preset, method, glyph, depth_correction) {
            bail!("{flag} applies to {who} only (here: {method}, {glyph}s)");
        }
        Ok(opts)
    }

    /// Whether to sort the instances front to back before upload (--sort, or a preset that
    /// sorts: sorted, splat).
    pub fn sort(&self) -> bool {
        self.sort || self.preset().sorts()
    }

    /// Whether front-to-back order was asked for itself (--sort, --preset sorted), which the
    /// viewer refuses; its splats are drawn in file order.
    pub fn sort_asked(&self) -> bool {
        self.sort || self.preset() == Preset::Sorted
    }
}

/// Exactly one of a file and `--demo`.
pub fn source(file: Option<PathBuf>, demo: Option<Demo>) -> Result<Source> {
    match (file, demo) {
        (Some(f), None) => Ok(Source::File(f)),
        (None, Some(d)) => Ok(Source::Demo(d)),
        (None, None) => bail!("give a FILE or --demo grid40"),
        (Some(_), Some(_)) => bail!("give either a FILE or --demo, not both"),
    }
}

pub fn parse_color(s: &str) -> Result<[f64; 4], String> {
    let named = match s.to_ascii_lowercase().as_str() {
        "white" => Some([1.0, 1.0, 1.0]),
        "black" => Some([0.0, 0.0, 0.0]),
        "grey" | "gray" => Some([0.5, 0.5, 0.5]),
        "paraview" => Some([0.32, 0.34, 0.43]),
        _ => None,
    };
    let rgb = if let Some(c) = named {
        c
    } else if let Some(hex) = s.strip_prefix('#') {
        if hex.len() != 6 {
            return Err(format!("colour '{s}' is not #rrggbb"));
        }
        let v = u32::from_str_radix(hex, 16).map_err(|_| format!("colour '{s}' is not #rrggbb"))?;
        [
            f64::from((v >> 16) & 255) / 255.0,
            f64::from((v >> 8) & 255) / 255.0,
            f64::from(v & 255) / 255.0,
        ]
    } else {
        let parts: Vec<f64> = s
            .split(',')
            .map(|p| p.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| format!("unknown colour '{s}': use a name, #rrggbb or r,g,b"))?;
        if parts.len() != 3 || parts.iter().any(|x| !(0.0..=1.0).contains(x)) {
            return Err(format!("colour '{s}' needs three numbers in [0, 1]"));
        }
        [parts[0], parts[1], parts[2]]
    };
    Ok([rgb[0], rgb[1], rgb[2], 1.0])
}

/// Figure effects (`render`, `demo`, `view`): deferred shading, outlines, shadows and ambient
/// occlusion.
#[derive(Args, Debug, Clone, Default)]
pub struct EffectArgs {
    /// Where glyphs are lit: in each method's shaders (direct), or once per pixel after all
    /// glyphs are drawn (deferred; picked by --outlines and --shadows).
    #[arg(long, value_parser = one_of::<Shading>(Shading::NAMES))]
    pub shading: Option<Shading>,
    /// Outline silhouettes, touching glyphs and creases (Sobel over depth, normal and glyph id);
    /// STRENGTH in [0, 1] is how dark (default 0.85).
    #[arg(long, value_name = "STRENGTH", num_args = 0..=1,
          default_missing_value = "0.85")]
    pub outlines: Option<f32>,
    /// Outline width in output pixels (it scales with --ssaa).
    #[arg(long, value_name = "PX", default_value_t = 1,
          value_parser = clap::value_parser!(u32).range(1..=16))]
    pub outline_width: u32,
    /// Soft shadows from a key light (a shadow map of the ray-cast glyphs, filtered with
    /// percentage-closer filtering).
    #[arg(long)]
    pub shadows: bool,
    /// Direction towards the key light in view space, X,Y,Z (x right, y up, z towards the
    /// viewer); default above-left of the camera, -0.5,0.8,0.35.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true, value_parser = parse_light)]
    pub light: Option<[f64; 3]>,
    /// Shadow map side in texels; the map is fitted to the part of the field the view shows
    /// (default: as many texels as the image has samples, at least 512², raised up to twice that
    /// side until the mean glyph spans 9 texels).
    #[arg(long, value_name = "N",
          value_parser = clap::value_parser!(u32).range(64..=8192))]
    pub shadow_map: Option<u32>,
    /// Shadow softness: the percentage-closer filter's radius in shadow map texels (a
    /// (2R+1)² kernel; 0: hard shadows).
    #[arg(long, value_name = "R", default_value_t = Shadows::default().pcf_radius,
          value_parser = clap::value_parser!(u32).range(0..=8))]
    pub pcf_radius: u32,
    /// Ambient occlusion: darken where glyphs crowd each other's sky (a density volume of the
    /// glyphs, marched by four cones per pixel); STRENGTH in [0, 1] is how far (default 0.8).
    #[arg(long, value_name = "STRENGTH", num_args = 0..=1,
          default_missing_value = "0.8")]
    pub ao: Option<f32>,
    /// With --ao: how far occlusion reaches, in mean largest glyph radii (default 4: two
    /// lattice steps of a field at --scale auto).
    #[arg(long, value_name = "RADII")]
    pub ao_reach: Option<f32>,
}

impl EffectArgs {
    /// The effects asked for an image of `size` output pixels with `ssaa`×`ssaa` samples each
    /// (outlines `ssaa` samples wide per output pixel).
    pub fn effects(&self, size: (u32, u32), ssaa: u32) -> Result<Effects> {
        if let Some(s) = self.outlines {
            ensure!(
                s.is_finite() && (0.0..=1.0).contains(&s),
                "--outlines takes a strength between 0 and 1, got {s}"
            );
        }
        if self.light.is_some() && !self.shadows {
            bail!("--light places the shadows' key light: add --shadows");
        }
        if let Some(s) = self.ao {
            ensure!(
                s.is_finite() && (0.0..=1.0).contains(&s),
                "--ao takes a strength between 0 and 1, got {s}"
            );
        }
        match self.ao_reach {
            Some(_) if self.ao.is_none() => {
                bail!("--ao-reach sets ambient occlusion's reach: add --ao")
            }
            Some(r) => ensure!(
                r.is_finite() && r > 0.0 && r <= 100.0,
                "--ao-reach takes a number of radii above 0 and at most 100, got {r}"
            ),
            None => {}
        }
        let effects = Effects {
            shading: self.shading.unwrap_or_default(),
            outlines: self.outlines.map(|strength| Outlines {
                strength,
                width: self.outline_width,
                ..Outlines::default()
            }),
            shadows: self.shadows.then(|| Shadows {
                light: self.light.unwrap_or(Shadows::DEFAULT_LIGHT),
                map_size: self.shadow_map.unwrap_or_else(|| {
                    Shadows::map_for(size.0.saturating_mul(ssaa), size.1.saturating_mul(ssaa))
                }),
                pcf_radius: self.pcf_radius,
                glyph_fit: self.shadow_map.is_none(),
                ..Shadows::default()
            }),
            ao: self.ao.map(|strength| AmbientOcclusion {
                strength,
                reach: self.ao_reach.unwrap_or(AmbientOcclusion::DEFAULT_REACH),
            }),
        };
        if self.shading == Some(Shading::Direct) && effects.any() {
            bail!(
                "--outlines, --shadows and --ao are drawn with deferred shading: drop --shading direct"
            );
        }
        Ok(effects.resolved().supersampled(ssaa))
    }
}

fn parse_light(s: &str) -> Result<[f64; 3], String> {
    let parts: Vec<f64> = s
        .split(',')
        .map(|p| p.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("light direction '{s}' is not X,Y,Z"))?;
    match parts[..] {
        [x, y, z] if light::view_direction([x, y, z]).is_some() => Ok([x, y, z]),
        _ => Err(format!(
            "light direction '{s}' needs three finite numbers, not all zero"
        )),
    }
}

/// The kinds whose capabilities pass `has`, as `--glyph` spells them ("superquadric").
fn kinds_with(has: fn(&crate::shape::Capabilities) -> bool) -> String {
    let names: Vec<&str> = GlyphKind::VALUES
        .iter()
        .filter(|k| has(&k.caps()))
        .map(|k| k.name())
        .collect();
    names.join(" or --glyph ")
}
