//! A scalar volume handed over as bytes (the page's underlay input): read at once, then offered
//! in the panel and shown under the slices as `view --underlay FILE` does, and read with every
//! field opened after it.

use std::path::PathBuf;
use std::sync::Arc;

use super::ViewerApp;
use crate::field::{Inputs, read_scalar_volume_from};
use crate::scene::UnderlaySource;
use crate::scene::underlay::NamedVolume;
use crate::viewer::loader::main_file;
use crate::viewer::panel::choose_underlay;

impl ViewerApp {
    /// Read the volume from `files` (through the one that names the others, as for tensors); a
    /// file that does not read gets its error line, and the underlay shown stays.
    pub(super) fn open_underlay(&mut self, files: Vec<(String, Vec<u8>)>) {
        let names: Vec<String> = files.iter().map(|(n, _)| n.clone()).collect();
        let Some(main) = main_file(&names).map(PathBuf::from) else {
            return;
        };
        let volume = match read_scalar_volume_from(&Inputs::named(files), &main) {
            Ok(v) => Arc::new(v),
            Err(e) => {
                self.error = Some(e.to_string());
                return;
            }
        };
        let source = UnderlaySource::Volume(NamedVolume {
            name: main.display().to_string(),
            volume: volume.clone(),
        });
        self.underlay_file = Some(source.clone());
        let dims = self.data.as_mut().and_then(|d| {
            d.underlay = Some(volume);
            d.field.lattice_dims()
        });
        match dims {
            Some(dims) => choose_underlay(&mut self.settings, Some(source), dims),
            None => self.settings.underlay = Some(source),
        }
        self.error = None;
    }
}
