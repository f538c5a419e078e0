//! The geodesic sphere: the icosahedron split `level` times into four triangles per triangle,
//! each midpoint pushed onto the unit sphere (10·4^N + 2 vertices, 20·4^N triangles, neighbours
//! at most 63.4°/2^N apart). The ellipsoid's `mesh:N` baseline draws it, the SH peak finder
//! seeds its ascents on its vertices and the ODF scene samples series there: one construction,
//! so that the three agree vertex for vertex.

use std::collections::HashMap;

/// The vertices (unit vectors) and triangles (counter-clockwise seen from outside) of the
/// sphere split `level` times; the icosahedron's twelve vertices come first, each split's
/// midpoints after them in the order the triangles meet them.
pub fn icosphere(level: u32) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut points: Vec<[f64; 3]> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .into_iter()
    .map(unit)
    .collect();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut mid = |a: u32, b: u32, points: &mut Vec<[f64; 3]>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (points[a as usize], points[b as usize]);
                points.push(unit([p[0] + q[0], p[1] + q[1], p[2] + q[2]]));
                (points.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(faces.len() * 4);
        for [a, b, c] in faces {
            let ab = mid(a, b, &mut points);
            let bc = mid(b, c, &mut points);
            let ca = mid(c, a, &mut points);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    (points, faces)
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|x| x / l)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Euler's count, unit vertices, and every edge shared by two triangles.
    #[test]
    fn the_sphere_is_closed_and_on_the_unit_sphere() {
        for level in 0..4 {
            let (v, f) = icosphere(level);
            let n = 4usize.pow(level);
            assert_eq!((v.len(), f.len()), (10 * n + 2, 20 * n));
            for p in &v {
                let l = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
                assert!((l - 1.0).abs() < 1e-15, "{l}");
            }
            let mut edges: HashMap<(u32, u32), usize> = HashMap::new();
            for t in &f {
                for k in 0..3 {
                    let (a, b) = (t[k], t[(k + 1) % 3]);
                    *edges.entry((a.min(b), a.max(b))).or_default() += 1;
                }
            }
            assert!(edges.values().all(|&c| c == 2));
            assert_eq!(edges.len(), 30 * n);
        }
    }
}
