//! What each field kind offers the front ends: the glyphs it is drawn as and the options that
//! apply to it. `render`, `view`, the viewer, Python and the report ask this table (through
//! [`FieldKind::glyph`] and [`FieldKind::offers`]) instead of branching on what a file holds.

use crate::field::FieldKind;
use crate::shape::GlyphKind;

/// What a field kind offers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Offers {
    /// The glyph kinds it is drawn as; the first when none is asked.
    pub glyphs: &'static [GlyphKind],
    /// `--odf-normalize` (its series scaled per voxel or by the largest value).
    pub normalize: bool,
    /// The viewer (and the page, which shares its loader) opens it.
    pub viewer: bool,
    /// The tensors' selection and underlay apply (`--fa-*`, `--stride`, `--roi`, `--mask`,
    /// `--underlay`); otherwise it is selected by `--slice` alone.
    pub tensor_selection: bool,
}

impl FieldKind {
    pub fn offers(self) -> Offers {
        match self {
            // Any glyph, a tensor's ODF profile included.
            FieldKind::Tensors => Offers {
                glyphs: GlyphKind::VALUES,
                normalize: false,
                viewer: true,
                tensor_selection: true,
            },
            FieldKind::Series => Offers {
                glyphs: &[GlyphKind::Odf],
                normalize: true,
                viewer: true,
                tensor_selection: false,
            },
            // Sticks: a cylinder or a capsule along each peak.
            FieldKind::Peaks => Offers {
                glyphs: &[GlyphKind::Cylinder, GlyphKind::Capsule],
                normalize: false,
                viewer: true,
                tensor_selection: false,
            },
        }
    }

    /// `None` where the viewer opens a field of this kind named `name`, else the one line
    /// that says it does not.
    pub fn viewer_refusal(self, name: &str) -> Option<String> {
        (!self.offers().viewer).then(|| {
            format!(
                "{}: holds {}, which the viewer does not open yet (render draws them)",
                crate::error::escape_path(std::path::Path::new(name)),
                self.holds()
            )
        })
    }

    /// The glyph a field of this kind named `name` is drawn as: `asked` where the kind offers it,
    /// its first glyph where none is asked, else one line saying what it is drawn as.
    pub fn glyph(self, asked: Option<GlyphKind>, name: &str) -> Result<GlyphKind, String> {
        let glyphs = self.offers().glyphs;
        match asked {
            None => Ok(glyphs[0]),
            Some(g) if glyphs.contains(&g) => Ok(g),
            Some(other) => Err(format!(
                "{}: holds {}, drawn as {}, not {other}",
                crate::error::escape_path(std::path::Path::new(name)),
                self.holds(),
                glyphs
                    .iter()
                    .map(|g| format!("--glyph {g}"))
                    .collect::<Vec<_>>()
                    .join(" or "),
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every kind is drawn as some glyph, and the default is the first it offers: tensors as
    /// ellipsoids (`GlyphKind::VALUES` starts with it), series as ODFs.
    #[test]
    fn each_kind_offers_its_glyphs() {
        for &k in FieldKind::VALUES {
            assert!(!k.offers().glyphs.is_empty(), "{k}");
        }
        assert_eq!(
            FieldKind::Tensors.glyph(None, "t"),
            Ok(GlyphKind::Ellipsoid)
        );
        assert_eq!(FieldKind::Series.glyph(None, "s"), Ok(GlyphKind::Odf));
        assert_eq!(
            FieldKind::Tensors.glyph(Some(GlyphKind::Odf), "t"),
            Ok(GlyphKind::Odf)
        );
        assert_eq!(
            FieldKind::Series.glyph(Some(GlyphKind::Cylinder), "a/s.mif"),
            Err("a/s.mif: holds SH series, drawn as --glyph odf, not cylinder".into())
        );
    }
}
