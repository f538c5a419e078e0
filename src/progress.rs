//! Progress of long stages (reading, eigendecomposition, building a scene), reported through a
//! callback so the library stays free of any terminal or UI: the command line draws bars with
//! indicatif, the viewer shows a bar in its panel, tests and examples pass [`Silent`].

/// What a long stage reports. Every method has a default that ignores it.
pub trait Progress: Sync {
    /// A stage begins: its name and, where known, how many items (tensors, glyphs) it has.
    fn begin(&self, _stage: &str, _items: Option<u64>) {}
    /// `n` more items are done.
    fn advance(&self, _n: u64) {}
    /// The stage is done.
    fn end(&self) {}
    /// Something the user should know about the data (what was assumed and why), one line.
    fn notice(&self, _line: &str) {}
}

/// Reports nothing.
#[derive(Debug, Clone, Copy, Default)]
pub struct Silent;

impl Progress for Silent {}

/// Run `work` as one stage of `progress`.
pub fn stage<T>(
    progress: &dyn Progress,
    name: &str,
    items: Option<u64>,
    work: impl FnOnce() -> T,
) -> T {
    progress.begin(name, items);
    let out = work();
    progress.end();
    out
}
