//! Every pipeline the renderer builds goes through [`Pipelines`]: it counts them, and on the
//! desktop hands the driver wgpu's pipeline cache, kept on disk between runs, so that a process
//! that renders one subject and exits does not compile the same pipelines again.
//!
//! The file is `<pipeline_cache_key>.bin` in `$TENSORGLYPH_PIPELINE_CACHE` (a folder; `0` turns
//! the cache off), else `$XDG_CACHE_HOME/tensorglyph`, else `$HOME/.cache/tensorglyph`. It is
//! read when the device opens and written (a temporary file, then a rename) when the renderer is
//! dropped, if the driver's data changed. Where the adapter lacks `PIPELINE_CACHE` or no folder
//! is writable the cache is off, silently: [`Pipelines::describe`] says why (`render --json`).
//!
//! This is the library's one unsafe call: wgpu's `Device::create_pipeline_cache` trusts that
//! the data came from `PipelineCache::get_data` on an adapter with the same
//! `wgpu::util::pipeline_cache_key`. The file therefore carries its own header (a magic, the
//! key, the data's length and CRC-32) and anything that does not match it whole is dropped
//! before wgpu sees it; wgpu and the driver check their own headers inside the data again.

#![allow(unsafe_code)]

use std::sync::atomic::{AtomicU32, Ordering};

/// Where and how the pipelines are built.
pub struct Pipelines {
    device: wgpu::Device,
    cache: Option<wgpu::PipelineCache>,
    /// Pipelines built by this process.
    built: AtomicU32,
    /// Why the cache is off, or where it lives and what was loaded.
    state: String,
    #[cfg(not(target_arch = "wasm32"))]
    disk: Option<disk::Slot>,
}

impl Pipelines {
    /// No cache: the viewer's window device, the browser, or `why`.
    pub fn without_cache(device: &wgpu::Device, why: &str) -> Self {
        Self {
            device: device.clone(),
            cache: None,
            built: AtomicU32::new(0),
            state: format!("off: {why}"),
            #[cfg(not(target_arch = "wasm32"))]
            disk: None,
        }
    }

    /// The pipelines of `device`, opened on `adapter` with `features`, with the cache on disk
    /// where there is one.
    pub fn new(
        device: &wgpu::Device,
        adapter: &wgpu::AdapterInfo,
        features: wgpu::Features,
    ) -> Self {
        #[cfg(target_arch = "wasm32")]
        {
            let _ = (adapter, features);
            Self::without_cache(device, "no disk in the browser")
        }
        #[cfg(not(target_arch = "wasm32"))]
        {
            if !features.contains(wgpu::Features::PIPELINE_CACHE) {
                return Self::without_cache(device, "the adapter has no PIPELINE_CACHE");
            }
            let Some(key) = wgpu::util::pipeline_cache_key(adapter) else {
                return Self::without_cache(device, "wgpu keeps no cache for this backend");
            };
            let slot = match disk::Slot::find(&key) {
                Ok(slot) => slot,
                Err(why) => return Self::without_cache(device, &why),
            };
            let data = slot.load();
            // SAFETY: `data` is what `get_data` returned on an adapter with this very
            // pipeline_cache_key, byte for byte: `Slot::load` drops any file whose key, length
            // or CRC-32 does not match (module doc).
            let cache = unsafe {
                device.create_pipeline_cache(&wgpu::PipelineCacheDescriptor {
                    label: Some("tensorglyph"),
                    data: data.as_deref(),
                    fallback: true,
                })
            };
            let state = match &data {
                Some(d) => format!("loaded {} bytes from {}", d.len(), slot.path.display()),
                None => format!("empty, kept in {}", slot.path.display()),
            };
            Self {
                device: device.clone(),
                cache: Some(cache),
                built: AtomicU32::new(0),
                state,
                disk: Some(slot.with_loaded(data.as_deref())),
            }
        }
    }

    /// A render pipeline, through the cache.
    pub fn render(&self, desc: &wgpu::RenderPipelineDescriptor<'_>) -> wgpu::RenderPipeline {
        self.built.fetch_add(1, Ordering::Relaxed);
        self.device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                cache: self.cache.as_ref(),
                ..desc.clone()
            })
    }

    /// Compute pipeline `entry` of `module` (labelled by its entry point), with `constants`
    /// for its overrides, through the cache.
    pub fn compute(
        &self,
        layout: &wgpu::PipelineLayout,
        module: &wgpu::ShaderModule,
        entry: &str,
        constants: &[(&str, f64)],
    ) -> wgpu::ComputePipeline {
        self.built.fetch_add(1, Ordering::Relaxed);
        self.device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(layout),
                module,
                entry_point: Some(entry),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants,
                    ..Default::default()
                },
                cache: self.cache.as_ref(),
            })
    }

    /// Pipelines built so far by this process (render and compute).
    pub fn built(&self) -> u32 {
        self.built.load(Ordering::Relaxed)
    }

    /// Whether the cache is on and where, or why it is off.
    pub fn describe(&self) -> &str {
        &self.state
    }

    /// Write the driver's cache data to disk if it changed since it was loaded; quietly nothing
    /// when the folder is not writable. Also done on drop.
    pub fn store(&self) {
        #[cfg(not(target_arch = "wasm32"))]
        if let (Some(cache), Some(slot)) = (&self.cache, &self.disk)
            && let Some(data) = cache.get_data()
        {
            slot.store(&data);
        }
    }
}

impl Drop for Pipelines {
    fn drop(&mut self) {
        self.store();
    }
}

/// The file on disk.
#[cfg(not(target_arch = "wasm32"))]
mod disk {
    use std::io::{Read as _, Write as _};
    use std::path::PathBuf;
    use std::sync::Mutex;
    use std::sync::atomic::{AtomicU32, Ordering};

    /// What starts every file, before the key.
    const MAGIC: &[u8; 8] = b"TGPIPE1\n";
    /// Larger files are not read (drivers' caches of our few pipelines are a few MB).
    const MAX_BYTES: u64 = 256 << 20;

    pub struct Slot {
        pub path: PathBuf,
        key: String,
        /// The CRC-32 and length of the data as last loaded or stored.
        last: Mutex<Option<(u32, usize)>>,
    }

    /// The cache folder the environment names, or why there is none.
    fn folder() -> Result<PathBuf, String> {
        let var = |k| std::env::var_os(k).filter(|v| !v.is_empty());
        if let Some(v) = var("TENSORGLYPH_PIPELINE_CACHE") {
            if v == "0" {
                return Err("TENSORGLYPH_PIPELINE_CACHE=0".into());
            }
            return Ok(PathBuf::from(v));
        }
        if let Some(v) = var("XDG_CACHE_HOME") {
            return Ok(PathBuf::from(v).join("tensorglyph"));
        }
        var("HOME")
            .map(|h| PathBuf::from(h).join(".cache").join("tensorglyph"))
            .ok_or_else(|| "no XDG_CACHE_HOME or HOME".into())
    }

    impl Slot {
        /// The file for `key`, in a folder that exists (made if need be).
        pub fn find(key: &str) -> Result<Self, String> {
            let dir = folder()?;
            if std::fs::create_dir_all(&dir).is_err() || !dir.is_dir() {
                return Err(format!("no cache folder at {}", dir.display()));
            }
            Ok(Self {
                path: dir.join(format!("{key}.bin")),
                key: key.to_string(),
                last: Mutex::new(None),
            })
        }

        pub fn with_loaded(self, data: Option<&[u8]>) -> Self {
            *self.last.lock().unwrap_or_else(|e| e.into_inner()) =
                data.map(|d| (crc32fast::hash(d), d.len()));
            self
        }

        /// The data of the file when it is whole and made for this key, else `None`.
        pub fn load(&self) -> Option<Vec<u8>> {
            let file = std::fs::File::open(&self.path).ok()?;
            if file.metadata().ok()?.len() > MAX_BYTES {
                return None;
            }
            let mut bytes = Vec::new();
            file.take(MAX_BYTES).read_to_end(&mut bytes).ok()?;
            parse(&bytes, &self.key).map(<[u8]>::to_vec)
        }

        /// Write `data` (whole: a temporary file, then a rename) unless it is what the file
        /// already holds.
        pub fn store(&self, data: &[u8]) {
            let sum = (crc32fast::hash(data), data.len());
            let mut last = self.last.lock().unwrap_or_else(|e| e.into_inner());
            if *last == Some(sum) || data.is_empty() {
                return;
            }
            static COUNTER: AtomicU32 = AtomicU32::new(0);
            let n = COUNTER.fetch_add(1, Ordering::Relaxed);
            let tmp = self
                .path
                .with_extension(format!("{}-{n}.tmp", std::process::id()));
            let written = (|| {
                let mut f = std::fs::File::create(&tmp)?;
                f.write_all(&header(&self.key, data))?;
                f.write_all(data)?;
                f.sync_all()?;
                std::fs::rename(&tmp, &self.path)
            })();
            if written.is_ok() {
                *last = Some(sum);
            } else {
                let _ = std::fs::remove_file(&tmp);
            }
        }
    }

    /// MAGIC, the key's length (u32 LE) and bytes, the data's length (u64 LE) and CRC-32.
    fn header(key: &str, data: &[u8]) -> Vec<u8> {
        let mut h = MAGIC.to_vec();
        h.extend((key.len() as u32).to_le_bytes());
        h.extend(key.as_bytes());
        h.extend((data.len() as u64).to_le_bytes());
        h.extend(crc32fast::hash(data).to_le_bytes());
        h
    }

    /// The data of a file's `bytes` when its header matches `key` and the data whole.
    pub(super) fn parse<'a>(bytes: &'a [u8], key: &str) -> Option<&'a [u8]> {
        let rest = bytes.strip_prefix(MAGIC)?;
        let (len, rest) = rest.split_first_chunk::<4>()?;
        let (k, rest) = rest.split_at_checked(u32::from_le_bytes(*len) as usize)?;
        if k != key.as_bytes() {
            return None;
        }
        let (len, rest) = rest.split_first_chunk::<8>()?;
        let (sum, data) = rest.split_first_chunk::<4>()?;
        (u64::try_from(data.len()).ok()? == u64::from_le_bytes(*len)
            && crc32fast::hash(data) == u32::from_le_bytes(*sum))
        .then_some(data)
    }

    #[cfg(test)]
    mod tests {
        use super::*;

        #[test]
        fn only_a_whole_file_of_the_same_key_is_taken() {
            let data = b"driver bytes".to_vec();
            let mut file = header("wgpu_pipeline_cache_vulkan_1_2", &data);
            file.extend(&data);
            assert_eq!(
                parse(&file, "wgpu_pipeline_cache_vulkan_1_2"),
                Some(&data[..])
            );
            assert_eq!(parse(&file, "wgpu_pipeline_cache_vulkan_1_3"), None);
            assert_eq!(
                parse(&file[..file.len() - 1], "wgpu_pipeline_cache_vulkan_1_2"),
                None
            );
            let mut flipped = file.clone();
            *flipped.last_mut().unwrap() ^= 1;
            assert_eq!(parse(&flipped, "wgpu_pipeline_cache_vulkan_1_2"), None);
            let mut longer = file.clone();
            longer.push(0);
            assert_eq!(parse(&longer, "wgpu_pipeline_cache_vulkan_1_2"), None);
            assert_eq!(parse(b"", "k"), None);
        }
    }
}
