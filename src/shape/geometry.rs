//! A glyph instance as the GPU reads it and as the f64 code sees it: the vocabulary every
//! kind's geometry, the scene, the back ends and the twins share.

use glam::{DMat3, DQuat, DVec3};

/// One glyph instance at full f32 precision, as built on the CPU: the reference ray casts these,
/// the GPU reads them packed ([`crate::render::gpu_data::GpuGlyph`], 32 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GlyphInstance {
    /// Centre relative to the scene origin.
    pub centre: [f32; 3],
    /// RGBA8 (R in the lowest byte).
    pub color: u32,
    /// Unit quaternion (x, y, z, w) of the instance frame.
    pub rotation: [f32; 4],
    /// Semi-axes along the frame's columns.
    pub radii: [f32; 3],
    /// Index into the glyph list the scene was built from (instances may be reordered).
    pub glyph: u32,
    /// The kind's parameter words: a superquadric's exponents (α, β, c) as the GPU reads them
    /// ([`crate::glyph::superquadric::pack_exponents`]; its frame's third column is then the
    /// symmetry axis and `radii` are in local (x, y, z) order); `[0, 0]` for kinds without
    /// parameters.
    pub shape: [u32; 2],
}

impl GlyphInstance {
    /// The superquadric exponents (α, β, c) stored in [`Self::shape`].
    pub fn exponents(&self) -> [f32; 3] {
        crate::glyph::superquadric::unpack_exponents(self.shape)
    }

    pub fn pack_color(rgba: [u8; 4]) -> u32 {
        u32::from_le_bytes(rgba)
    }

    pub fn color_rgba(&self) -> [u8; 4] {
        self.color.to_le_bytes()
    }
}

impl GlyphInstance {
    /// The instance as the GPU stores it ([`crate::render::gpu_data::GpuGlyph`]): the rotation
    /// through its 20-bit "smallest three" code and drawable radii through their 24-bit floats,
    /// decoded as `load_glyph` in common.wgsl decodes them. Scenes keep their instances so, and
    /// the reference casts what every method draws: the rotation code alone turns a glyph by up
    /// to ~2e-6 rad, which moves a needle's tip across its section when k ≳ 1e4 (normals of
    /// needles at k = 1e4: 2.3–5.0° measured against the unstored instance, 0.2–1.0° against
    /// this). What storing costs against the field is stated on its own (the Accuracy page).
    pub fn stored(mut self) -> Self {
        self.rotation = unpack_rotation(pack_rotation(self.rotation));
        if crate::shape::rules::drawable_radii(self.radii) {
            self.radii = self.radii.map(|r| unpack_radius(pack_radius(r)));
        }
        self
    }

    /// Whether its radii span more than [`THIN_RATIO`], as the shaders decide it (load_glyph).
    pub fn is_thin(&self) -> bool {
        let r = self.radii;
        let (hi, lo) = (r[0].max(r[1]).max(r[2]), r[0].min(r[1]).min(r[2]));
        hi > THIN_RATIO * lo
    }
}

/// Bits of each of a stored quaternion's three smaller components.
const QUAT_BITS: u32 = 20;
/// One step of a stored component: 1.5 · 2⁻²⁰, so that (n − 2¹⁹) · step, the decode, is exact in
/// f32 (21 significant bits) on every device, fused or not; the codes span ±0.75 ⊃ ±1/√2.
pub const QUAT_STEP: f32 = 1.430_511_5e-6;
const QUAT_HALF: i32 = 1 << (QUAT_BITS - 1);

/// A unit quaternion (x, y, z, w) as "smallest three": the index of the largest component (made
/// positive) in bits 28..30 of word 1 and the other three, in order, as 20-bit codes n with
/// component (n − 2¹⁹) · [`QUAT_STEP`] (error ≤ 7.2e-7 each): a = w0[0..20],
/// b = w0[20..32] | w1[0..8] << 12, c = w1[8..28]. A quaternion that is not finite or zero is
/// stored as the identity.
pub fn pack_rotation(q: [f32; 4]) -> [u32; 2] {
    let q = q.map(f64::from);
    let len = q.iter().map(|c| c * c).sum::<f64>().sqrt();
    let q = if len > 0.0 && len.is_finite() {
        q.map(|c| c / len)
    } else {
        [0.0, 0.0, 0.0, 1.0]
    };
    let largest = (0..4)
        .max_by(|&a, &b| q[a].abs().total_cmp(&q[b].abs()))
        .unwrap_or(3);
    let sign = if q[largest] < 0.0 { -1.0 } else { 1.0 };
    let max = f64::from((1u32 << QUAT_BITS) - 1);
    let mut rest = [0u32; 3];
    let mut k = 0;
    for (i, c) in q.iter().enumerate() {
        if i != largest {
            let n = (sign * c / f64::from(QUAT_STEP)).round() + f64::from(QUAT_HALF);
            rest[k] = n.clamp(0.0, max) as u32;
            k += 1;
        }
    }
    let [a, b, c] = rest;
    [
        a | (b << 20),
        (b >> 12) | (c << 8) | ((largest as u32) << 28),
    ]
}

/// The decode of `load_glyph` in common.wgsl: the three codes are exact in f32, and the largest
/// component is √(1 − a² − b² − c²), exact in f64 but for the square root, rounded once to f32
/// (the shader forms it in double-f32 and rounds it the same way, `quat_largest`).
pub fn unpack_rotation(w: [u32; 2]) -> [f32; 4] {
    let a = w[0] & 0xfffff;
    let b = (w[0] >> 20) | ((w[1] & 0xff) << 12);
    let c = (w[1] >> 8) & 0xfffff;
    let largest = ((w[1] >> 28) & 3) as usize;
    let dec = |n: u32| (n as i32 - QUAT_HALF) as f32 * QUAT_STEP;
    let rest = [dec(a), dec(b), dec(c)];
    let [x, y, z] = rest.map(f64::from);
    let big = (1.0 - (x * x + y * y + z * z)).max(0.0).sqrt() as f32;
    let mut q = [0.0f32; 4];
    let mut k = 0;
    for (i, slot) in q.iter_mut().enumerate() {
        if i == largest {
            *slot = big;
        } else {
            *slot = rest[k];
            k += 1;
        }
    }
    q
}

/// Radii spanning more than this make a glyph thin: its quaternion's fourth component and (in
/// the shaders with it) its rays are formed in double-f32 (common.wgsl's THIN_RATIO,
/// THIN_EXACT).
pub const THIN_RATIO: f32 = 100.0;

/// A radius ≥ 0 as an unsigned 24-bit float (f32 without sign and the 7 lowest mantissa bits,
/// rounded to nearest: relative error ≤ 2⁻¹⁷).
pub fn pack_radius(r: f32) -> u32 {
    let bits = r.max(0.0).to_bits();
    ((bits + 0x40) >> 7).min(0x00ff_ffff)
}

/// The radius [`pack_radius`] stored.
pub fn unpack_radius(w: u32) -> f32 {
    f32::from_bits(w << 7)
}

/// A glyph instance's geometry in f64, as both the reference and the tests need it.
#[derive(Debug, Clone, Copy)]
pub struct GlyphGeometry {
    /// Centre relative to the scene origin.
    pub centre: DVec3,
    /// The instance frame O (columns).
    pub frame: DMat3,
    pub radii: DVec3,
    /// Superquadric exponents (α, β, c) ([`GlyphInstance::exponents`]; 0 for other glyphs).
    pub exponents: DVec3,
    /// The kind's parameter words as stored ([`GlyphInstance::shape`]).
    pub params: [u32; 2],
}

impl GlyphGeometry {
    pub fn of(g: &GlyphInstance) -> Self {
        let q = DQuat::from_xyzw(
            f64::from(g.rotation[0]),
            f64::from(g.rotation[1]),
            f64::from(g.rotation[2]),
            f64::from(g.rotation[3]),
        );
        Self {
            centre: DVec3::from(g.centre.map(f64::from)),
            // The shader normalises nothing: use the quaternion exactly as stored, like it does.
            frame: quat_to_mat3_unnormalised(q),
            radii: DVec3::from(g.radii.map(f64::from)),
            exponents: DVec3::from(g.exponents().map(f64::from)),
            params: g.shape,
        }
    }

    /// T = O diag(r) Oᵀ.
    pub fn t(&self) -> DMat3 {
        self.frame * DMat3::from_diagonal(self.radii) * self.frame.transpose()
    }

    /// T⁻¹ = O diag(1/r) Oᵀ, from the eigen data (never by inverting T).
    pub fn t_inv(&self) -> DMat3 {
        self.frame * DMat3::from_diagonal(self.radii.recip()) * self.frame.transpose()
    }

    /// Half-extents of the axis-aligned box around the ellipsoid: |row i of T|.
    pub fn half_extents(&self) -> DVec3 {
        let t = self.t();
        DVec3::new(t.row(0).length(), t.row(1).length(), t.row(2).length())
    }

    /// Half-extents of a box holding the glyph drawn as an ellipsoid or as a capped cylinder
    /// (axis = first column): the cylinder's box, which contains the ellipsoid's.
    pub fn glyph_half_extents(&self) -> DVec3 {
        let a = self.frame.x_axis * self.radii.x;
        let u = self.frame.y_axis * self.radii.y;
        let v = self.frame.z_axis * self.radii.z;
        a.abs() + DVec3::new(u.x.hypot(v.x), u.y.hypot(v.y), u.z.hypot(v.z))
    }

    /// `p` (relative to the scene origin) in the instance frame.
    pub fn local(&self, p: DVec3) -> DVec3 {
        self.frame.transpose() * (p - self.centre)
    }

    pub fn max_radius(&self) -> f64 {
        self.radii.max_element()
    }
}

/// `bounding_radius` of common.wgsl: a sphere around the glyph as ellipsoid or capped cylinder.
pub fn bounding_radius(r: [f32; 3]) -> f64 {
    f64::from(r[0]).hypot(f64::from(r[1].max(r[2])))
}

/// The same formula as `quat_to_mat3` in common.wgsl.
pub(crate) fn quat_to_mat3_unnormalised(q: DQuat) -> DMat3 {
    let (x2, y2, z2) = (q.x + q.x, q.y + q.y, q.z + q.z);
    let (xx, xy, xz) = (q.x * x2, q.x * y2, q.x * z2);
    let (yy, yz, zz) = (q.y * y2, q.y * z2, q.z * z2);
    let (wx, wy, wz) = (q.w * x2, q.w * y2, q.w * z2);
    DMat3::from_cols(
        DVec3::new(1.0 - (yy + zz), xy + wz, xz - wy),
        DVec3::new(xy - wz, 1.0 - (xx + zz), yz + wx),
        DVec3::new(xz + wy, yz - wx, 1.0 - (xx + yy)),
    )
}

/// The frame whose columns are columns `cols` of `rotation`'s, column `flip` negated where that
/// order is a reflection (so it stays a rotation), and the radii in the same order.
pub fn permuted_frame(
    rotation: [f32; 4],
    radii: [f32; 3],
    cols: [usize; 3],
    flip: usize,
) -> ([f32; 4], [f32; 3]) {
    let q = DQuat::from_xyzw(
        f64::from(rotation[0]),
        f64::from(rotation[1]),
        f64::from(rotation[2]),
        f64::from(rotation[3]),
    )
    .normalize();
    let m = DMat3::from_quat(q);
    let mut f = DMat3::from_cols(m.col(cols[0]), m.col(cols[1]), m.col(cols[2]));
    if f.determinant() < 0.0 {
        *f.col_mut(flip) = -f.col(flip);
    }
    let q = DQuat::from_mat3(&f).normalize();
    (
        [q.x as f32, q.y as f32, q.z as f32, q.w as f32],
        cols.map(|i| radii[i]),
    )
}
