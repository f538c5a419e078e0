//! Unit meshes of the triangle-mesh baselines (`mesh:N`, `box`): each kind builds its own in its
//! parameter space ([`crate::shape::Shape::unit_mesh`]); `box` draws the [`cube`] for every kind.
//! The vertex shader (shaders/method/mesh.wgsl) places a unit-mesh point through the kind's
//! `shape_mesh_point`; every triangle winds counter-clockwise seen from outside, so back faces
//! can be culled.

use bytemuck::{Pod, Zeroable};

/// One vertex of a unit mesh. Keep in sync with `vs_main`'s inputs in shaders/mesh.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct MeshVertex {
    pub position: [f32; 3],
    /// Unit outward normal in the unit mesh's space.
    pub normal: [f32; 3],
}

/// An indexed triangle list.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Mesh {
    pub vertices: Vec<MeshVertex>,
    pub indices: Vec<u32>,
}

impl Mesh {
    pub fn triangles(&self) -> usize {
        self.indices.len() / 3
    }

    /// Bytes of the shared vertex and index buffers.
    pub fn bytes(&self) -> usize {
        std::mem::size_of_val(self.vertices.as_slice())
            + std::mem::size_of_val(self.indices.as_slice())
    }

    pub(crate) fn push(&mut self, position: [f64; 3], normal: [f64; 3]) -> u32 {
        let f = |v: [f64; 3]| v.map(|x| x as f32);
        self.vertices.push(MeshVertex {
            position: f(position),
            normal: f(normal),
        });
        (self.vertices.len() - 1) as u32
    }
}

pub(crate) fn normalize(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|x| x / l)
}

/// Sides of the `mesh:N` prism.
pub fn prism_sides(level: u8) -> u32 {
    6 << level
}

/// `cos` and `sin` of `2π k / n`, exactly 0 and ±1 at quarter turns: grid directions in the mirror
/// planes of the superquadric then have exact zeros, where the shader's powers of 0 take their
/// limits.
pub(crate) fn turn(k: u32, n: u32) -> (f64, f64) {
    let k = k % n;
    if (4 * k).is_multiple_of(n) {
        return match 4 * k / n {
            0 => (1.0, 0.0),
            1 => (0.0, 1.0),
            2 => (-1.0, 0.0),
            _ => (0.0, -1.0),
        };
    }
    let a = std::f64::consts::TAU * f64::from(k) / f64::from(n);
    (a.cos(), a.sin())
}

/// The cube [−1, 1]³ with flat faces: 24 vertices (4 per face), 12 triangles.
pub fn cube() -> Mesh {
    let mut mesh = Mesh::default();
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            let mut n = [0.0; 3];
            n[axis] = sign;
            // (u, v, n) right-handed, so (±u, ±v) in this order winds counter-clockwise about n.
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let base = mesh.vertices.len() as u32;
            for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let mut p = n;
                p[u] = a * sign;
                p[v] = b;
                mesh.push(p, n);
            }
            mesh.indices
                .extend([base, base + 1, base + 2, base, base + 2, base + 3]);
        }
    }
    mesh
}

#[cfg(test)]
pub(crate) mod checks {
    use super::*;
    use std::collections::HashMap;

    pub fn sub(a: [f32; 3], b: [f32; 3]) -> [f64; 3] {
        [0, 1, 2].map(|i| f64::from(a[i]) - f64::from(b[i]))
    }

    pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }

    pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }

    /// Closed (every edge, by vertex position, used once each way: faces with their own
    /// vertices still meet), outward counter-clockwise winding, unit normals on the outward side.
    pub fn check_closed_outward(name: &str, m: &Mesh) {
        let key = |i: u32| m.vertices[i as usize].position.map(f32::to_bits);
        let mut edges: HashMap<([u32; 3], [u32; 3]), i32> = HashMap::new();
        for t in m.indices.chunks_exact(3) {
            for k in 0..3 {
                let (a, b) = (key(t[k]), key(t[(k + 1) % 3]));
                *edges.entry((a.min(b), a.max(b))).or_default() += if a < b { 1 } else { -1 };
            }
            let [a, b, c] = [0, 1, 2].map(|k| m.vertices[t[k] as usize]);
            let face = cross(sub(b.position, a.position), sub(c.position, a.position));
            let centroid = [0, 1, 2].map(|i| {
                (f64::from(a.position[i]) + f64::from(b.position[i]) + f64::from(c.position[i]))
                    / 3.0
            });
            assert!(dot(face, centroid) > 0.0, "{name}: inward triangle {t:?}");
            for v in [a, b, c] {
                let n = v.normal.map(f64::from);
                assert!((dot(n, n) - 1.0).abs() < 1e-6, "{name}: normal {v:?}");
                assert!(dot(n, face) > 0.0, "{name}: normal against face {v:?}");
            }
        }
        assert!(edges.values().all(|&e| e == 0), "{name}: not closed");
        assert!(m.indices.iter().all(|&i| (i as usize) < m.vertices.len()));
    }
}

#[cfg(test)]
mod tests {
    use super::checks::check_closed_outward;
    use super::*;
    use crate::shape::GlyphKind;

    /// Every kind's unit mesh at every level, and the box: closed, wound outward, and as large
    /// as its stats say.
    #[test]
    fn unit_meshes_are_closed_outward_and_match_their_stats() {
        for &kind in GlyphKind::VALUES {
            let shape = kind.shape();
            for level in 0..=6 {
                let m = shape.unit_mesh(level);
                let name = format!("mesh:{level} {kind}");
                check_closed_outward(&name, &m);
                assert_eq!(
                    shape.mesh_stats(level),
                    (m.vertices.len(), m.triangles()),
                    "{name}"
                );
            }
        }
        check_closed_outward("box", &cube());
        for v in cube().vertices {
            assert!(v.position.iter().all(|x| x.abs() == 1.0));
        }
    }
}
