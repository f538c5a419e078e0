//! CPU probes: the κ and µ forms of Gumhold's hit point on an f32 twin of the shader (case 1),
//! eigen frames and colours through a degeneracy (case 10), and the eigensolver (case 11).

use std::collections::BTreeMap;
use std::time::Instant;

use glam::{DMat3, DVec2, DVec3, Mat3, Mat4, Quat, Vec3};

use super::cases::{self, oblique};
use super::rng::Rng;
use super::{Row, Status, within};
use crate::camera::{Camera, Projection};
use crate::scene::{GlyphGeometry, GlyphInstance, GlyphSpec};
use crate::shape::ellipsoid;
use crate::twin::gumhold_ellipsoid;

fn row(case: &'static str, parameter: &'static str, value: f64, method: &str) -> Row {
    Row {
        case,
        parameter,
        value,
        label: format!("{value:e}"),
        method: method.into(),
        glyph: "ellipsoid".into(),
        depth_correction: true,
        status: Status::Pass,
        reason: String::new(),
        metrics: BTreeMap::new(),
    }
}

fn p99_max(mut v: Vec<f64>) -> (f64, f64) {
    if v.is_empty() {
        return (0.0, 0.0);
    }
    for x in &mut v {
        if x.is_nan() {
            *x = f64::INFINITY;
        }
    }
    v.sort_by(f64::total_cmp);
    let k = ((0.99 * v.len() as f64).ceil() as usize).clamp(1, v.len());
    (v[k - 1], v[v.len() - 1])
}

fn f32v(v: DVec3) -> Vec3 {
    v.as_vec3()
}

/// `orthonormal_pair` of common.wgsl in f32.
fn pair32(z: Vec3) -> (Vec3, Vec3) {
    let s = if z.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + z.z);
    let b = z.x * z.y * a;
    (
        Vec3::new(1.0 + s * z.x * z.x * a, s * b, -s * z.x),
        Vec3::new(b, s + z.y * z.y * a, -z.y),
    )
}

/// Case 1 on the CPU: the shader's perspective path in f32 with the κ form (what ships) and
/// Gumhold's µ form (p = e + v E/(E+1) + µ v/(E+1)), against the exact f64 hit of the same ray,
/// over a 41×41 grid of quad attributes q inside the unit disc. The shader keeps the κ form;
/// the µ form is measured here rather than as a shader variant.
pub fn mu_form(quick: bool) -> Vec<Row> {
    let dists: &[f64] = if quick {
        &[10.0, 1e6]
    } else {
        &[10.0, 100.0, 1e3, 1e4, 1e5, 1e6]
    };
    let radii = DVec3::new(1.0, 0.6, 0.35);
    let rot = oblique();
    let o64 = DMat3::from_quat(rot);
    let t = o64 * DMat3::from_diagonal(radii) * o64.transpose();
    let t_inv = o64 * DMat3::from_diagonal(radii.recip()) * o64.transpose();
    let dir = DVec3::new(-1.0, 1.0, -0.7).normalize();
    let mut out = Vec::new();
    for &d in dists {
        let eye = -dir * d;
        let cam = Camera {
            eye,
            target: DVec3::ZERO,
            up: DVec3::Z,
            projection: Projection::Perspective {
                fov_y: 2.0 * (1.3 / d).atan(),
            },
            near: d - 2.0,
            far: d + 2.0,
            width: cases::W,
            height: cases::H,
            crop: None,
        };
        let view64 = cam.view(DVec3::ZERO);
        let view: Mat4 = view64.as_mat4();
        let setup =
            gumhold_ellipsoid::setup_perspective(&t_inv, DVec3::ZERO, eye).expect("outside");
        // The f32 vertex stage, as the shader computes it.
        let o = Mat3::from_quat(Quat::from_xyzw(
            rot.x as f32,
            rot.y as f32,
            rot.z as f32,
            rot.w as f32,
        ));
        let ot = o.transpose();
        let r32 = f32v(radii);
        let rinv = r32.recip();
        let e32 = f32v(eye);
        let e_t = o * ((ot * e32) * rinv);
        let e2 = e_t.dot(e_t);
        let en = e2.sqrt();
        let z_hat = -e_t / en;
        let m_t = e_t / e2;
        let r_t = ((e2 - 1.0) / e2).sqrt();
        let u = 1.0 / en;
        let (xh, yh) = pair32(z_hat);
        let n_mat = o * Mat3::from_cols(ot.x_axis * rinv, ot.y_axis * rinv, ot.z_axis * rinv);
        let mut errs: [(Vec<f64>, Vec<f64>, Vec<f64>); 2] = Default::default();
        let n = 41;
        for j in 0..n {
            for i in 0..n {
                let q = DVec2::new(
                    2.0 * f64::from(i) / f64::from(n - 1) - 1.0,
                    2.0 * f64::from(j) / f64::from(n - 1) - 1.0,
                );
                if q.length_squared() > 1.0 {
                    continue;
                }
                // Exact: the ray from the eye through the exact quad point V(q).
                let v = t * setup.quad_point_t(q);
                let rd = (v - eye).normalize();
                let Some((th, p_t_exact)) = ellipsoid::intersect(eye, rd, DVec3::ZERO, &t_inv)
                else {
                    continue;
                };
                let p_exact = eye + rd * th;
                let z_exact = view64.transform_point3(p_exact).z;
                let n_exact = (t_inv * p_t_exact).normalize();
                // f32 fragment stage.
                let (qx, qy) = (q.x as f32, q.y as f32);
                let vt_quad = m_t + r_t * (qx * xh + qy * yh);
                let v32 = o * ((ot * vt_quad) * r32);
                let vt_ray = vt_quad + z_hat / u;
                let v_view = view.transform_point3(v32);
                let q2 = qx * qx + qy * qy;
                let alpha = (1.0 - q2).max(0.0).sqrt();
                let beta = u * alpha;
                // κ form.
                let kappa = beta / (1.0 + beta);
                let pk_t = vt_quad - kappa * vt_ray;
                let zk = (1.0 - kappa) * v_view.z;
                // µ form: µ = (1 − α)/(1 + ũα), λ = (µ + E)/(E + 1), p~ = e~ + λ v~.
                let mu = (1.0 - alpha) / (1.0 + u * alpha);
                let lambda = (mu + en) / (en + 1.0);
                let pm_t = e_t + lambda * vt_ray;
                let zm = v_view.z * (en + mu) / (en + 1.0);
                for (k, (p_t, z)) in [(pk_t, zk), (pm_t, zm)].into_iter().enumerate() {
                    let n32 = (n_mat * p_t).as_dvec3().normalize();
                    let ang = n32
                        .cross(n_exact)
                        .length()
                        .atan2(n32.dot(n_exact))
                        .to_degrees();
                    errs[k]
                        .0
                        .push((f64::from(z) - z_exact).abs() / radii.max_element());
                    errs[k].1.push(ang);
                    errs[k].2.push((p_t.as_dvec3() - p_t_exact).length());
                }
            }
        }
        for (k, name) in ["gumhold-f32 κ form", "gumhold-f32 µ form"]
            .into_iter()
            .enumerate()
        {
            let mut r = row("1-distance-mu", "distance/size", d, name);
            let (dp, dm) = p99_max(errs[k].0.clone());
            let (np, nm) = p99_max(errs[k].1.clone());
            let (pp, pm) = p99_max(errs[k].2.clone());
            // The view distance itself is an f32: half an ulp of d, in glyph sizes.
            let z_ulp = f64::from(f32::EPSILON) * d / 2.0 / radii.max_element();
            for (key, v) in [
                ("depth_err_rel_p99", dp),
                ("depth_err_rel_max", dm),
                ("normal_err_deg_p99", np),
                ("normal_err_deg_max", nm),
                ("param_err_p99", pp),
                ("param_err_max", pm),
                ("f32_view_z_half_ulp_rel", z_ulp),
            ] {
                r.metrics.insert(key.into(), v);
            }
            let depth_ok = dp <= 1e-4_f64.max(4.0 * z_ulp);
            if !within(np, 0.1) || !depth_ok {
                r.status = Status::Degraded;
                r.reason = format!(
                    "normal p99 {np:.3e}° (bound 0.1°), depth p99 {dp:.3e} (bound max(1e-4, 4 half-ulp of d = {:.1e}))",
                    4.0 * z_ulp
                );
                if k == 1 && !within(np, 0.1) {
                    r.reason.push_str(" [documented limit: µ form cancels in e~ + λ v~; the shader uses the κ form]");
                }
            }
            if !within(np, 2.0) && k == 0 {
                r.status = Status::Fail;
            }
            out.push(r);
        }
    }
    out
}

/// Colour by principal direction, |e1| as RGB, optionally weighted by cl = (λ1 − λ2)/λ1.
fn dir_colour(e: &cases::Eigen, weighted: bool) -> DVec3 {
    let c = DVec3::from(e.vectors[0]).abs();
    if weighted {
        let l1 = e.values[0];
        let cl = if l1 > 0.0 {
            (l1 - e.values[1]) / l1
        } else {
            0.0
        };
        c * cl
    } else {
        c
    }
}

/// What storing an instance may cost its tensor ([`GlyphInstance::stored`]), relative to the
/// largest |λ|: radii to 2⁻¹⁷ (7.6e-6) and a frame turned by at most 2·√3·7.2e-7 = 2.5e-6 rad
/// (three components off by half a 20-bit step each), which moves T by at most twice that.
const STORED_RECONSTRUCTION: f64 = 1.3e-5;

/// Case 10 on the CPU: a tensor passing through λ1 = λ2 (T(t) = R diag(0.5 + t, 0.5 − t, 0.2) Rᵀ):
/// the glyph the renderers get (f32 quaternion + radii) must reproduce T for every t (the frame
/// may turn: it is undefined at the degeneracy); the principal-direction colour jumps across
/// t = 0 unless weighted by cl.
pub fn degeneracy(quick: bool) -> Vec<Row> {
    let ts: Vec<f64> = if quick {
        vec![1e-1, 1e-6, 0.0]
    } else {
        vec![1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 0.0]
    };
    let r = DMat3::from_quat(oblique());
    let tensor = |t: f64| {
        let m = r * DMat3::from_diagonal(DVec3::new(0.5 + t, 0.5 - t, 0.2)) * r.transpose();
        m.to_cols_array()
    };
    let mut out = Vec::new();
    for &t in &ts {
        let mut worst_rec = 0.0f64;
        let mut worst_stored = 0.0f64;
        let mut e1 = [DVec3::ZERO; 2];
        for (k, s) in [t, -t].into_iter().enumerate() {
            let a = tensor(s);
            let e = cases::symmetric_eigen(&a).expect("finite");
            let spec: GlyphSpec = cases::glyph_from_tensor(&a, DVec3::ZERO, [0; 4]).expect("glyph");
            // The f32 instance (quaternion and radii) and what the GPU stores of it, back to T
            // (scaled by the largest |λ|).
            let q = spec.rotation.normalize();
            let built = GlyphInstance {
                centre: [0.0; 3],
                color: 0,
                rotation: [q.x as f32, q.y as f32, q.z as f32, q.w as f32],
                radii: spec.radii.as_vec3().to_array(),
                glyph: 0,
                shape: [0; 2],
            };
            let scale = e.values[0].abs();
            let want = DMat3::from_cols_array(&a);
            let err = |g: &GlyphInstance| {
                let rec = GlyphGeometry::of(g).t() * scale;
                (0..3)
                    .map(|c| (rec.col(c) - want.col(c)).length())
                    .fold(0.0, f64::max)
                    / scale
            };
            worst_rec = worst_rec.max(err(&built));
            worst_stored = worst_stored.max(err(&built.stored()));
            e1[k] = DVec3::from(e.vectors[0]);
        }
        // Colour difference between T(t) and T(−t): the jump a viewer sees.
        let ea = cases::symmetric_eigen(&tensor(t)).expect("finite");
        let eb = cases::symmetric_eigen(&tensor(-t)).expect("finite");
        let jump_raw = (dir_colour(&ea, false) - dir_colour(&eb, false)).length();
        let jump_cl = (dir_colour(&ea, true) - dir_colour(&eb, true)).length();
        let frame_turn = e1[0].dot(e1[1]).abs().clamp(0.0, 1.0).acos().to_degrees();
        let mut rw = row(
            "10-degeneracy-sweep",
            "λ1 − λ2 = 2t",
            t,
            "glyph build (f64 eigen → f32 instance)",
        );
        rw.metrics
            .insert("tensor_reconstruction_rel".into(), worst_rec);
        rw.metrics
            .insert("tensor_reconstruction_stored_rel".into(), worst_stored);
        rw.metrics
            .insert("e1_turn_deg_t_vs_minus_t".into(), frame_turn);
        rw.metrics.insert("colour_jump_raw".into(), jump_raw);
        rw.metrics.insert("colour_jump_cl_weighted".into(), jump_cl);
        if !within(worst_rec, 1e-6) {
            rw.status = Status::Fail;
            rw.reason = format!("glyph does not reproduce the tensor: {worst_rec:.3e} > 1e-6");
        } else if !within(worst_stored, STORED_RECONSTRUCTION) {
            rw.status = Status::Fail;
            rw.reason = format!(
                "stored glyph does not reproduce the tensor: {worst_stored:.3e} > {STORED_RECONSTRUCTION:e}"
            );
        } else if jump_raw > 0.05 {
            rw.status = Status::Degraded;
            rw.reason = format!(
                "principal-direction colour jumps {jump_raw:.3} across the degeneracy (cl-weighted: {jump_cl:.1e}) [documented limit: e1 is undefined at λ1 = λ2; weight direction colour by cl]"
            );
        }
        out.push(rw);
    }
    out
}

/// Case 11: nalgebra `SymmetricEigen` in f32 and f64 on T = R diag(1, 1 − g, 0.3) Rᵀ for gaps
/// g = 10⁻³ … 10⁻¹²: residual max_i |T v_i − λ_i v_i| / |T| (in f64), angle of e1 and e3 from
/// the truth, and tensors per second.
pub fn eigensolver(quick: bool) -> Vec<Row> {
    let gaps: Vec<f64> = if quick {
        vec![1e-3, 1e-12]
    } else {
        (3..=12).map(|k| 10f64.powi(-k)).collect()
    };
    let n = if quick { 2000 } else { 20000 };
    let mut out = Vec::new();
    for &g in &gaps {
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15 ^ g.to_bits());
        let rots: Vec<DMat3> = (0..n).map(|_| rng.rotation()).collect();
        let tensors: Vec<DMat3> = rots
            .iter()
            .map(|r| *r * DMat3::from_diagonal(DVec3::new(1.0, 1.0 - g, 0.3)) * r.transpose())
            .collect();
        for solver in ["nalgebra f32", "nalgebra f64", "tensor::eigen (Jacobi f64)"] {
            let single = solver == "nalgebra f32";
            let start = Instant::now();
            let sols: Vec<([f64; 3], [DVec3; 3])> = tensors
                .iter()
                .map(|t| {
                    let a = t.to_cols_array();
                    if solver.starts_with("tensor") {
                        let e =
                            crate::tensor::eigen::symmetric_eigen(&t.transpose().to_cols_array());
                        (e.values, e.vectors.map(DVec3::from))
                    } else if single {
                        let m = nalgebra::Matrix3::<f32>::from_column_slice(&a.map(|x| x as f32));
                        let e = nalgebra::SymmetricEigen::new(m);
                        sorted(
                            [0, 1, 2].map(|i| f64::from(e.eigenvalues[i])),
                            [0, 1, 2].map(|i| {
                                let c = e.eigenvectors.column(i);
                                DVec3::new(f64::from(c[0]), f64::from(c[1]), f64::from(c[2]))
                            }),
                        )
                    } else {
                        let m = nalgebra::Matrix3::<f64>::from_column_slice(&a);
                        let e = nalgebra::SymmetricEigen::new(m);
                        sorted(
                            [0, 1, 2].map(|i| e.eigenvalues[i]),
                            [0, 1, 2].map(|i| {
                                let c = e.eigenvectors.column(i);
                                DVec3::new(c[0], c[1], c[2])
                            }),
                        )
                    }
                })
                .collect();
            let secs = start.elapsed().as_secs_f64();
            let mut res = Vec::with_capacity(n);
            let mut a1 = Vec::with_capacity(n);
            let mut a3 = Vec::with_capacity(n);
            let mut nonfinite = 0usize;
            for ((t, r), (vals, vecs)) in tensors.iter().zip(&rots).zip(&sols) {
                if vals.iter().any(|x| !x.is_finite()) {
                    nonfinite += 1;
                }
                let mut worst = 0.0f64;
                for i in 0..3 {
                    worst = worst.max((*t * vecs[i] - vecs[i] * vals[i]).length());
                }
                res.push(worst);
                // atan2(|a × b|, |a · b|): acos near 1 would floor at √ε.
                let ang = |a: DVec3, b: DVec3| {
                    let a = a.normalize();
                    a.cross(b).length().atan2(a.dot(b).abs()).to_degrees()
                };
                a1.push(ang(vecs[0], r.x_axis));
                a3.push(ang(vecs[2], r.z_axis));
            }
            let eps = if single {
                f64::from(f32::EPSILON)
            } else {
                f64::EPSILON
            };
            let name = solver;
            let mut rw = row("11-eigensolver", "eigenvalue gap", g, name);
            rw.glyph = "-".into();
            let (rp, rm) = p99_max(res);
            let (a1p, a1m) = p99_max(a1);
            let (a3p, a3m) = p99_max(a3);
            for (k, v) in [
                ("residual_rel_p99", rp),
                ("residual_rel_max", rm),
                ("e1_angle_deg_p99", a1p),
                ("e1_angle_deg_max", a1m),
                ("e3_angle_deg_p99", a3p),
                ("e3_angle_deg_max", a3m),
                ("tensors_per_s", n as f64 / secs.max(1e-9)),
                ("nonfinite", nonfinite as f64),
                (
                    "e1_angle_bound_deg",
                    (eps / g).min(1.0).asin().to_degrees() * 10.0,
                ),
            ] {
                rw.metrics.insert(k.into(), v);
            }
            // Residual: a backward-stable solver gives a few ε |T|. e1 is only determined to
            // ~ε/gap (Davis–Kahan): beyond that it is the inherent limit, not an error.
            if nonfinite > 0 || !within(rm, 100.0 * eps) || !within(a3m, (1e3 * eps).to_degrees()) {
                rw.status = Status::Fail;
                rw.reason = format!(
                    "residual max {rm:.3e} (bound 100ε = {:.1e}), e3 angle max {a3m:.3e}°, non-finite {nonfinite}",
                    100.0 * eps
                );
            } else if a1p > (10.0 * eps / g).min(1.0).asin().to_degrees() {
                rw.status = Status::Degraded;
                rw.reason = format!("e1 angle p99 {a1p:.3e}° beyond 10ε/gap");
            } else if eps / g > 1e-3 {
                rw.status = Status::Degraded;
                rw.reason = format!(
                    "e1 angle p99 {a1p:.3e}° [documented limit: e1 is defined only to ε/gap = {:.1e} rad; the shape T is still exact]",
                    eps / g
                );
            }
            out.push(rw);
        }
    }
    out
}

fn sorted(vals: [f64; 3], vecs: [DVec3; 3]) -> ([f64; 3], [DVec3; 3]) {
    let mut idx = [0usize, 1, 2];
    idx.sort_by(|&a, &b| vals[b].total_cmp(&vals[a]));
    (idx.map(|i| vals[i]), idx.map(|i| vecs[i]))
}
