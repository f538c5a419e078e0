//! Component order of 6-component symmetric tensor arrays.

/// How the six unique entries of a symmetric tensor are ordered in a 6-component array.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ComponentOrder {
    /// XX, YY, ZZ, XY, YZ, XZ: what VTK and ParaView write (legacy `TENSORS6` too).
    #[default]
    Vtk,
    /// xx, xy, xz, yy, yz, zz (FSL's dtifit).
    Fsl,
    /// xx, xy, yy, xz, yz, zz (NIfTI lower triangle).
    Nifti,
    /// D11, D22, D33, D12, D13, D23 (MRtrix `dwi2tensor`).
    Mrtrix,
}

crate::names::named_values!(ComponentOrder {
    Vtk => "vtk",
    Fsl => "fsl",
    Nifti => "nifti",
    Mrtrix => "mrtrix",
});

impl ComponentOrder {
    /// (row, column) of each stored component.
    pub fn slots(self) -> [(usize, usize); 6] {
        match self {
            ComponentOrder::Vtk => [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2)],
            ComponentOrder::Fsl => [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)],
            ComponentOrder::Nifti => [(0, 0), (0, 1), (1, 1), (0, 2), (1, 2), (2, 2)],
            ComponentOrder::Mrtrix => [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)],
        }
    }

    /// Expand six stored components into a row-major symmetric 3x3 tensor.
    pub fn expand(self, c: &[f64]) -> [f64; 9] {
        let mut t = [0.0; 9];
        for (k, (i, j)) in self.slots().into_iter().enumerate() {
            t[3 * i + j] = c[k];
            t[3 * j + i] = c[k];
        }
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orders_place_off_diagonals_where_their_tools_do() {
        let c = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        // VTK: XX YY ZZ XY YZ XZ
        assert_eq!(
            ComponentOrder::Vtk.expand(&c),
            [1.0, 4.0, 6.0, 4.0, 2.0, 5.0, 6.0, 5.0, 3.0]
        );
        // FSL: xx xy xz yy yz zz
        assert_eq!(
            ComponentOrder::Fsl.expand(&c),
            [1.0, 2.0, 3.0, 2.0, 4.0, 5.0, 3.0, 5.0, 6.0]
        );
        // NIfTI: xx xy yy xz yz zz
        assert_eq!(
            ComponentOrder::Nifti.expand(&c),
            [1.0, 2.0, 4.0, 2.0, 3.0, 5.0, 4.0, 5.0, 6.0]
        );
        // MRtrix: D11 D22 D33 D12 D13 D23
        assert_eq!(
            ComponentOrder::Mrtrix.expand(&c),
            [1.0, 4.0, 5.0, 4.0, 2.0, 6.0, 5.0, 6.0, 3.0]
        );
    }
}
