//! Which glyphs to show: an FA range, a stride over the lattice and axis-aligned slices.
//!
//! A [`Selection`] maps a field's [`GlyphSet`] to the indices (into `set.glyphs`) of the glyphs
//! to draw; the scene is then built from those glyphs only. Stride and slices use the lattice of
//! structured data ([`TensorField::lattice_dims`], x fastest); unstructured data has no lattice,
//! so there the stride runs over file order and slicing is not available.

use crate::field::TensorField;
use crate::glyph::GlyphSet;
use crate::tensor::shape;

/// Which part of the lattice to show.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Slicing {
    /// Every lattice position.
    #[default]
    Whole,
    /// One plane perpendicular to `axis` (0 = x, 1 = y, 2 = z) at lattice `index`.
    Slice { axis: usize, index: usize },
    /// Three orthogonal planes through the lattice position `at`.
    Orthogonal { at: [usize; 3] },
}

/// What to draw of a field.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Selection {
    /// Inclusive FA range. An upper bound of 1 or more has no effect: FA of positive-definite
    /// tensors is at most 1, and indefinite ones (stress, strain) above 1 are kept with it.
    pub fa_min: f64,
    pub fa_max: f64,
    /// Every `stride`-th lattice position along each axis (1 = all).
    pub stride: usize,
    pub slicing: Slicing,
}

impl Default for Selection {
    fn default() -> Self {
        Self {
            fa_min: 0.0,
            fa_max: 1.0,
            stride: 1,
            slicing: Slicing::Whole,
        }
    }
}

/// Lattice coordinates (i, j, k) of file-order index `n` on a lattice of `dims` (x fastest).
pub fn lattice_coords(n: usize, dims: [usize; 3]) -> [usize; 3] {
    let [nx, ny, _] = dims.map(|d| d.max(1));
    [n % nx, (n / nx) % ny, n / (nx * ny)]
}

impl Selection {
    /// True when this selection keeps every glyph.
    pub fn is_everything(&self) -> bool {
        self.fa_min <= 0.0
            && self.fa_max >= 1.0
            && self.stride <= 1
            && self.slicing == Slicing::Whole
    }

    /// Indices into `set.glyphs` of the selected glyphs, in order.
    pub fn select(&self, field: &TensorField, set: &GlyphSet) -> Vec<usize> {
        let dims = field.lattice_dims();
        let stride = self.stride.max(1);
        let fa_all = self.fa_min <= 0.0 && self.fa_max >= 1.0;
        set.glyphs
            .iter()
            .enumerate()
            .filter(|(_, g)| {
                let n = g.index as usize;
                let lattice_ok = match dims {
                    Some(d) => self.keeps_lattice(lattice_coords(n, d), stride),
                    None => n.is_multiple_of(stride),
                };
                lattice_ok
                    && (fa_all || {
                        let fa = shape::fa(g.eigenvalues.map(f64::from));
                        fa >= self.fa_min && (self.fa_max >= 1.0 || fa <= self.fa_max)
                    })
            })
            .map(|(k, _)| k)
            .collect()
    }

    fn keeps_lattice(&self, c: [usize; 3], stride: usize) -> bool {
        // Stride applies along the axes in a plane, not across it (a slice stays a slice).
        let on_stride = |axes: &[usize]| axes.iter().all(|&a| c[a].is_multiple_of(stride));
        match self.slicing {
            Slicing::Whole => on_stride(&[0, 1, 2]),
            Slicing::Slice { axis, index } => {
                let axis = axis.min(2);
                c[axis] == index && on_stride(&others(axis))
            }
            Slicing::Orthogonal { at } => {
                (0..3).any(|axis| c[axis] == at[axis] && on_stride(&others(axis)))
            }
        }
    }

    /// A subset of `set` holding the selected glyphs; the field statistics stay those of the
    /// whole field, so scale and colours do not change with the selection.
    pub fn subset(set: &GlyphSet, indices: &[usize]) -> GlyphSet {
        GlyphSet {
            glyphs: indices.iter().map(|&k| set.glyphs[k]).collect(),
            stats: set.stats.clone(),
        }
    }
}

fn others(axis: usize) -> [usize; 2] {
    match axis {
        0 => [1, 2],
        1 => [0, 2],
        _ => [0, 1],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::synthetic::grid;
    use crate::glyph::derive_glyphs;

    fn demo(n: usize) -> (TensorField, GlyphSet) {
        let f = grid(n);
        let s = derive_glyphs(&f, None);
        (f, s)
    }

    #[test]
    fn default_keeps_everything() {
        let (f, s) = demo(6);
        assert!(Selection::default().is_everything());
        assert_eq!(Selection::default().select(&f, &s).len(), s.glyphs.len());
    }

    #[test]
    fn stride_and_slices_count_lattice_positions() {
        let (f, s) = demo(6);
        assert_eq!(s.glyphs.len(), 216, "the demo grid has no invalid tensors");
        let sel = |stride, slicing| {
            Selection {
                stride,
                slicing,
                ..Selection::default()
            }
            .select(&f, &s)
        };
        assert_eq!(sel(2, Slicing::Whole).len(), 27);
        assert_eq!(sel(1, Slicing::Slice { axis: 2, index: 3 }).len(), 36);
        assert_eq!(sel(2, Slicing::Slice { axis: 0, index: 1 }).len(), 9);
        // Three planes of 36 share 3 lines of 6 and one point: 3·36 − 3·6 + 1.
        assert_eq!(sel(1, Slicing::Orthogonal { at: [2, 2, 2] }).len(), 91);
        for k in sel(1, Slicing::Slice { axis: 1, index: 4 }) {
            let c = lattice_coords(s.glyphs[k].index as usize, [6, 6, 6]);
            assert_eq!(c[1], 4);
        }
        assert!(sel(1, Slicing::Slice { axis: 2, index: 99 }).is_empty());
    }

    #[test]
    fn fa_range_filters_by_anisotropy() {
        let (f, s) = demo(6);
        let sel = Selection {
            fa_min: 0.5,
            fa_max: 1.0,
            ..Selection::default()
        };
        let kept = sel.select(&f, &s);
        assert!(!kept.is_empty() && kept.len() < s.glyphs.len());
        for k in &kept {
            assert!(shape::fa(s.glyphs[*k].eigenvalues.map(f64::from)) >= 0.5);
        }
        let sub = Selection::subset(&s, &kept);
        assert_eq!(sub.glyphs.len(), kept.len());
        assert_eq!(sub.stats, s.stats);
    }

    #[test]
    fn lattice_coordinates_run_x_fastest() {
        assert_eq!(lattice_coords(0, [4, 3, 2]), [0, 0, 0]);
        assert_eq!(lattice_coords(5, [4, 3, 2]), [1, 1, 0]);
        assert_eq!(lattice_coords(23, [4, 3, 2]), [3, 2, 1]);
    }
}
