//! Tests of the eigendecomposition: properties (proptest), nalgebra agreement, extremes.

use super::*;
use proptest::prelude::*;

fn frob(t: &[f64; 9]) -> f64 {
    t.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn det(f: &[[f64; 3]; 3]) -> f64 {
    dot(f[0], cross(f[1], f[2]))
}

fn check(a: &[f64; 9]) {
    check_eigen(&symmetric_eigen(a), a);
    check_eigen(&jacobi_eigen(a), a);
    check_eigen(&jacobi_core(a), a);
}

fn check_eigen(e: &Eigen, a: &[f64; 9]) {
    assert!(e.values[0] >= e.values[1] && e.values[1] >= e.values[2]);
    for i in 0..3 {
        for j in 0..3 {
            let d = dot(e.vectors[i], e.vectors[j]);
            let want = if i == j { 1.0 } else { 0.0 };
            assert!((d - want).abs() < 1e-12, "not orthonormal: {d}");
        }
    }
    assert!((det(&e.vectors) - 1.0).abs() < 1e-12);
    let r = reconstruct(e.values, &e.vectors);
    let diff: [f64; 9] = std::array::from_fn(|k| r[k] - a[k]);
    assert!(
        frob(&diff) <= 1e-12 * frob(a) + f64::MIN_POSITIVE,
        "reconstruction error {} for {:?}",
        frob(&diff),
        a
    );
}

fn rot(axis: [f64; 3], angle: f64) -> [[f64; 3]; 3] {
    let n = dot(axis, axis).sqrt();
    let (x, y, z) = (axis[0] / n, axis[1] / n, axis[2] / n);
    let (s, c) = angle.sin_cos();
    let t = 1.0 - c;
    // Columns of the rotation matrix.
    [
        [t * x * x + c, t * x * y + s * z, t * x * z - s * y],
        [t * x * y - s * z, t * y * y + c, t * y * z + s * x],
        [t * x * z + s * y, t * y * z - s * x, t * z * z + c],
    ]
}

fn eigen_strategy() -> impl Strategy<Value = [f64; 3]> {
    let v = -10.0..10.0f64;
    prop_oneof![
        // general
        (v.clone(), v.clone(), v.clone()).prop_map(|(a, b, c)| [a, b, c]),
        // repeated (double), positive or negative
        (v.clone(), v.clone()).prop_map(|(a, b)| [a, a, b]),
        // triple
        v.clone().prop_map(|a| [a, a, a]),
        // nearly repeated (relative gaps 1e-14 .. 1e-4)
        (v.clone(), v.clone(), -14i32..-4).prop_map(|(a, b, e)| [a, a * (1.0 + 10f64.powi(e)), b]),
        (v.clone(), -14i32..-4, -14i32..-4).prop_map(|(a, e1, e2)| [
            a,
            a * (1.0 + 10f64.powi(e1)),
            a * (1.0 - 10f64.powi(e2))
        ]),
        // rank 1 and rank 2
        v.clone().prop_map(|a| [a, 0.0, 0.0]),
        (v.clone(), v.clone()).prop_map(|(a, b)| [a, b, 0.0]),
        // negative definite
        (0.01..10.0f64, 0.01..10.0f64, 0.01..10.0f64).prop_map(|(a, b, c)| [-a, -b, -c]),
        // indefinite
        (0.01..10.0f64, -10.0..10.0f64, 0.01..10.0f64).prop_map(|(a, b, c)| [a, b, -c]),
        // zero
        Just([0.0, 0.0, 0.0]),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn eigen_properties(
        ev in eigen_strategy(),
        axis in (-1.0..1.0f64, -1.0..1.0f64, 0.1..1.0f64),
        angle in 0.0..std::f64::consts::TAU,
        scale_exp in -6i32..6,
    ) {
        let f = rot([axis.0, axis.1, axis.2], angle);
        let s = 10f64.powi(scale_exp);
        let a = reconstruct(ev.map(|x| x * s), &f);
        // exactly symmetric input
        let (a, _) = symmetrise(&a);
        check(&a);
    }

    #[test]
    fn jacobi_matches_nalgebra(
        ev in eigen_strategy(),
        axis in (-1.0..1.0f64, -1.0..1.0f64, 0.1..1.0f64),
        angle in 0.0..std::f64::consts::TAU,
    ) {
        let a = symmetrise(&reconstruct(ev, &rot([axis.0, axis.1, axis.2], angle))).0;
        let j = jacobi_eigen(&a);
        let n = nalgebra_eigen(&a);
        let scale = frob(&a).max(f64::MIN_POSITIVE);
        for k in 0..3 {
            prop_assert!((j.values[k] - n.values[k]).abs() <= 1e-13 * scale);
        }
        check_eigen(&n, &a);
    }

    #[test]
    fn random_symmetric(vals in proptest::array::uniform6(-100.0..100.0f64)) {
        let [a, b, c, d, e, f] = vals;
        check(&[a, d, e, d, b, f, e, f, c]);
    }

    #[test]
    fn quaternion_round_trip(
        axis in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64),
        angle in 0.0..std::f64::consts::TAU,
    ) {
        prop_assume!(axis.0.abs() + axis.1.abs() + axis.2.abs() > 1e-3);
        let f = rot([axis.0, axis.1, axis.2], angle);
        let q = frame_to_quat(&f);
        let back = quat_to_frame(q);
        for i in 0..3 {
            for k in 0..3 {
                prop_assert!((back[i][k] - f[i][k]).abs() < 1e-6);
            }
        }
    }
}

#[test]
fn extreme_scales() {
    let base = [2.0, 0.3, -0.1, 0.3, 1.0, 0.2, -0.1, 0.2, 0.5];
    let ref_e = symmetric_eigen(&base);
    for s in [1e-300, 1e-200, 1e200, 1e300] {
        let a = base.map(|x| x * s);
        let e = symmetric_eigen(&a);
        for k in 0..3 {
            assert!(
                (e.values[k] / s - ref_e.values[k]).abs() < 1e-14,
                "scale {s}"
            );
            assert!((dot(e.vectors[k], ref_e.vectors[k]).abs() - 1.0).abs() < 1e-14);
        }
    }
}

/// Eigenvalues of `t` computed by nalgebra on the same problem scaled by 2^-k into a
/// comfortable range (an exact scaling), scaled back.
fn scaled_reference(t: &[f64; 9], k: i32) -> [f64; 3] {
    let s = symmetrise(&t.map(|x| mul_pow2(x, -k))).0;
    nalgebra_eigen(&s).values.map(|v| mul_pow2(v, k))
}

/// Entries near f64::MAX and subnormal ones: `symmetrise` used to overflow (`a + b`), the
/// rescale used to overflow (`2^1060`), `fa` divided by a subnormal; all gave NaN/inf.
#[test]
fn extreme_but_finite_entries() {
    let base = [2.0, 0.3, -0.1, 0.3, 1.0, 0.2, -0.1, 0.2, 0.5];
    let m = f64::MAX;
    let tiny = f64::from_bits(1); // 2^-1074, the smallest subnormal
    let cases: Vec<([f64; 9], i32)> = vec![
        (base.map(|x| mul_pow2(x, 1021)), 1021),
        // A non-symmetric off-diagonal pair whose sum overflows.
        (
            [0.0, 0.9 * m, 0.0, 0.8 * m, 0.0, 0.0, 0.0, 0.0, 0.1 * m],
            1023,
        ),
        // Eigenvalues 0.9m and (−0.5 ± √0.5)/2 · m.
        (
            [
                0.9 * m,
                0.0,
                0.0,
                0.0,
                -0.5 * m,
                0.25 * m,
                0.0,
                0.25 * m,
                0.0,
            ],
            1023,
        ),
        (base.map(|x| mul_pow2(x, -1030)), -1030),
        (base.map(|x| mul_pow2(x, -1060)), -1060),
        (
            [0.0, tiny, 0.0, tiny, 0.0, 0.0, 0.0, 0.0, 3.0 * tiny],
            -1074,
        ),
    ];
    for (t, k) in cases {
        let (sym, _) = symmetrise(&t);
        assert!(sym.iter().all(|x| x.is_finite()), "{t:?}");
        let e = symmetric_eigen(&sym);
        let want = scaled_reference(&t, k);
        let big = want.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        // Results below 2^-1022 are rounded to the subnormal grid.
        let slack = 4.0 * tiny;
        for i in 0..3 {
            assert!(e.values[i].is_finite(), "{t:?}: {:?}", e.values);
            assert!(
                (e.values[i] - want[i]).abs() <= 1e-12 * big + slack,
                "{t:?}: {:?} vs {want:?}",
                e.values
            );
            for j in 0..3 {
                let d = dot(e.vectors[i], e.vectors[j]);
                assert!((d - f64::from(u8::from(i == j))).abs() < 1e-12);
            }
        }
        let fa = crate::tensor::shape::fa(e.values);
        let fa_want = crate::tensor::shape::fa(want.map(|v| mul_pow2(v, -k)));
        let rel = 1e-12 + 8.0 * slack / big;
        assert!(
            fa.is_finite() && (fa - fa_want).abs() <= rel,
            "{fa} vs {fa_want}"
        );
        assert!(crate::tensor::shape::md(e.values).is_finite());
    }
}

#[test]
fn symmetrise_near_max() {
    let m = f64::MAX;
    let (s, flag) = symmetrise(&[0.0, 0.9 * m, 0.0, 0.8 * m, 0.0, 0.0, 0.0, 0.0, 0.0]);
    assert!(flag);
    assert_eq!(s[1], s[3]);
    assert!((s[1] / m - 0.85).abs() < 1e-15);
    let (s, flag) = symmetrise(&[m, m, -m, m, m, 0.0, -m, 0.0, m]);
    assert!(!flag);
    assert_eq!(s, [m, m, -m, m, m, 0.0, -m, 0.0, m]);
    // Opposite signs: the difference overflows, which is (rightly) non-symmetric.
    let (s, flag) = symmetrise(&[0.0, m, 0.0, -m, 0.0, 0.0, 0.0, 0.0, 1.0]);
    assert!(flag);
    assert_eq!((s[1], s[3]), (0.0, 0.0));
}

#[test]
fn mul_pow2_is_exact_across_the_range() {
    assert_eq!(mul_pow2(1.0, 1023), 2f64.powi(1023));
    assert_eq!(mul_pow2(f64::from_bits(1), 1074), 1.0);
    assert_eq!(mul_pow2(1.0, -1074), f64::from_bits(1));
    assert_eq!(mul_pow2(3.0, -2000), 0.0);
    assert_eq!(mul_pow2(1.5, 2000), f64::INFINITY);
    assert_eq!(mul_pow2(f64::MAX, -1023), f64::MAX / 2f64.powi(1023));
}

#[test]
fn diagonal_fast_path() {
    let e = symmetric_eigen(&[1.0, 0.0, 0.0, 0.0, 3.0, 0.0, 0.0, 0.0, 2.0]);
    assert_eq!(e.values, [3.0, 2.0, 1.0]);
    assert_eq!(e.vectors[0], [0.0, 1.0, 0.0]);
    assert_eq!(e.vectors[1], [0.0, 0.0, 1.0]);
    assert_eq!(e.vectors[2], [1.0, 0.0, 0.0]);
    check(&[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1.0]);
    check(&[0.0; 9]);
}

#[test]
fn symmetrise_tolerance() {
    let a = [1.0, 0.5, 0.0, 0.5 + 1e-9, 1.0, 0.0, 0.0, 0.0, 1.0];
    let (s, flag) = symmetrise(&a);
    assert!(!flag);
    assert_eq!(s[1], s[3]);
    let b = [1.0, 0.5, 0.0, 0.4, 1.0, 0.0, 0.0, 0.0, 1.0];
    let (s, flag) = symmetrise(&b);
    assert!(flag);
    assert!((s[1] - 0.45).abs() < 1e-15 && s[1] == s[3]);
    // relative: tiny tensors with relatively large asymmetry are flagged
    let c = b.map(|x| x * 1e-20);
    assert!(symmetrise(&c).1);
}

#[test]
fn quaternion_identity_and_half_turns() {
    let id = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    assert_eq!(frame_to_quat(&id), [0.0, 0.0, 0.0, 1.0]);
    // 180 degrees about z: e1 = -x, e2 = -y, e3 = z
    let f = [[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]];
    let q = frame_to_quat(&f);
    assert!((q[2].abs() - 1.0).abs() < 1e-7);
    let m = quat_to_matrix(q);
    assert!((m[0][0] + 1.0).abs() < 1e-7 && (m[2][2] - 1.0).abs() < 1e-7);
}
