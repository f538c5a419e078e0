//! Adapter and device: CPU adapters (lavapipe) are welcome; optional features are taken where
//! the adapter has them.
//!
//! Waiting differs per platform. On the desktop the GPU is waited for by polling the device, and
//! an async step runs to its end at once inside `pollster::block_on`. In the browser nothing may
//! block: a read-back is mapped when the work that writes it is done, through the page's event
//! loop, so the core is async (read-backs, [`GpuContext::scope_error`]) and the desktop's
//! blocking calls wrap it.

use std::sync::{Arc, Mutex};

use crate::error::RenderError;
use crate::render::pipeline_cache::Pipelines;

/// Optional features taken where the adapter has them.
pub const WANTED_FEATURES: wgpu::Features = wgpu::Features::PIPELINE_STATISTICS_QUERY
    .union(wgpu::Features::TIMESTAMP_QUERY)
    .union(wgpu::Features::SHADER_EARLY_DEPTH_TEST)
    .union(wgpu::Features::PIPELINE_CACHE)
    .union(INT64_ATOMICS);

/// Storage buffers Gumhold's compute prepass binds in one stage: the glyph group's three and the
/// compute group's nine. WebGPU adapters may allow fewer per stage (SwiftShader in Chromium: 10);
/// there the prepass and splats are left out ([`GpuContext::prepass_fits`]). Kept here, with the
/// other device requirements, so that the context need not know the prepass.
pub const COMPUTE_STORAGE_BUFFERS: u32 = 12;

/// 64-bit atomic max in shaders: splats keep depth and id in one atomic (splat64.wgsl).
const INT64_ATOMICS: wgpu::Features =
    wgpu::Features::SHADER_INT64.union(wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX);

/// A wgpu device with what we learned about its adapter.
pub struct GpuContext {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub adapter_name: String,
    pub backend: String,
    pub limits: wgpu::Limits,
    /// Fragment- and vertex-shader invocation counts can be queried.
    pub pipeline_statistics: bool,
    pub timestamps: bool,
    pub early_depth_test: bool,
    /// SHADER_INT64 and SHADER_INT64_ATOMIC_MIN_MAX.
    pub int64_atomics: bool,
    /// Builds (and counts) every pipeline, through the cache on disk where there is one.
    pub pipelines: Arc<Pipelines>,
    /// GPU errors of steps that could not wait for them (the web build's pipeline creation and
    /// uploads): the viewer shows them when they arrive.
    late_errors: Arc<Mutex<Vec<String>>>,
}

impl GpuContext {
    /// The first adapter wgpu offers (a real GPU if present, else a CPU one), or
    /// [`RenderError::NoAdapter`].
    #[cfg(not(target_arch = "wasm32"))]
    pub fn new() -> Result<Self, RenderError> {
        pollster::block_on(Self::new_async())
    }

    /// [`Self::new`], without blocking.
    pub async fn new_async() -> Result<Self, RenderError> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = wgpu::Backends::from_env().unwrap_or(wgpu::Backends::PRIMARY);
        let instance = wgpu::Instance::new(desc);
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                compatible_surface: None,
                apply_limit_buckets: false,
            })
            .await
            .map_err(|_| RenderError::NoAdapter)?;
        Self::from_adapter(adapter).await
    }

    pub async fn from_adapter(adapter: wgpu::Adapter) -> Result<Self, RenderError> {
        let info = adapter.get_info();
        let available = adapter.features();
        let features = available & WANTED_FEATURES;
        let limits = adapter.limits();
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("tensorglyph"),
                required_features: features,
                required_limits: limits.clone(),
                ..Default::default()
            })
            .await
            .map_err(|e| RenderError::Gpu(format!("cannot open device: {e}")))?;
        Ok(Self {
            pipelines: Arc::new(Pipelines::new(&device, &info, features)),
            device,
            queue,
            adapter_name: info.name.clone(),
            backend: format!("{:?}", info.backend).to_lowercase(),
            limits,
            pipeline_statistics: features.contains(wgpu::Features::PIPELINE_STATISTICS_QUERY),
            timestamps: features.contains(wgpu::Features::TIMESTAMP_QUERY),
            early_depth_test: features.contains(wgpu::Features::SHADER_EARLY_DEPTH_TEST),
            int64_atomics: features.contains(INT64_ATOMICS),
            late_errors: Arc::default(),
        })
    }

    /// Wrap a device someone else opened (the viewer's window integration), reading its
    /// features back.
    pub fn from_device(adapter: &wgpu::Adapter, device: wgpu::Device, queue: wgpu::Queue) -> Self {
        let info = adapter.get_info();
        let features = device.features();
        Self {
            pipelines: Arc::new(Pipelines::new(&device, &info, features)),
            limits: device.limits(),
            device,
            queue,
            adapter_name: info.name.clone(),
            backend: format!("{:?}", info.backend).to_lowercase(),
            pipeline_statistics: features.contains(wgpu::Features::PIPELINE_STATISTICS_QUERY),
            timestamps: features.contains(wgpu::Features::TIMESTAMP_QUERY),
            early_depth_test: features.contains(wgpu::Features::SHADER_EARLY_DEPTH_TEST),
            int64_atomics: features.contains(INT64_ATOMICS),
            late_errors: Arc::default(),
        }
    }

    /// `req` as this device can draw it at the camera's size (see
    /// [`crate::render::GpuRenderer::within_limits`]; the shadow map's pass asks it too).
    pub fn within_limits(
        &self,
        req: &crate::request::FrameRequest,
        camera: &crate::camera::Camera,
    ) -> crate::request::FrameRequest {
        let mut req = *req;
        if !self.prepass_fits() {
            req.method.drop_prepass();
        }
        let key_bytes = if self.int64_atomics { 8 } else { 4 };
        let pixels = u64::from(camera.width) * u64::from(camera.height);
        if req.splat_pixels() > 0
            && pixels.saturating_mul(key_bytes) > self.limits.max_storage_buffer_binding_size
        {
            req.method.drop_splats();
        }
        req
    }

    /// Whether the device binds as many storage buffers per shader stage as Gumhold's compute
    /// prepass needs (Vulkan devices do; some WebGPU adapters do not).
    pub fn prepass_fits(&self) -> bool {
        self.limits.max_storage_buffers_per_shader_stage >= COMPUTE_STORAGE_BUFFERS
    }

    /// Wait for all submitted work. lavapipe can take many seconds on large frames.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn wait(&self) -> Result<(), RenderError> {
        self.device
            .poll(wgpu::PollType::Wait {
                submission_index: None,
                timeout: Some(std::time::Duration::from_secs(600)),
            })
            .map(|_| ())
            .map_err(|e| RenderError::Gpu(format!("waiting for the GPU: {e}")))
    }

    /// The error an error scope caught, for a step that goes on without it where it cannot wait
    /// (the browser): there the error arrives later, and [`Self::take_late_errors`] hands it
    /// over, `what` saying what failed.
    pub fn scope_error(&self, scope: wgpu::ErrorScopeGuard, what: &str) -> Option<String> {
        #[cfg(not(target_arch = "wasm32"))]
        {
            pollster::block_on(scope.pop()).map(|e| format!("{what}: {e}"))
        }
        #[cfg(target_arch = "wasm32")]
        {
            // Popped now (the scope ends here), its error awaited on the page's event loop.
            let (error, late, what) = (scope.pop(), self.late_errors.clone(), what.to_string());
            wasm_bindgen_futures::spawn_local(async move {
                if let Some(e) = error.await {
                    late.lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .push(format!("{what}: {e}"));
                }
            });
            None
        }
    }

    /// GPU errors that arrived after the step that caused them returned (browser only).
    pub fn take_late_errors(&self) -> Vec<String> {
        std::mem::take(&mut *self.late_errors.lock().unwrap_or_else(|e| e.into_inner()))
    }
}
