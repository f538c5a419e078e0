//! GPU work whose result comes later: a figure's read-back, the id under the pointer. The
//! desktop waits for it where it is asked (the GPU is polled, as `render` does); the browser
//! cannot block, so the page's event loop runs it and the app takes the result at a later
//! frame, woken when it is there. The app's code is the same for both.

use std::future::Future;
use std::sync::{Arc, Mutex};

/// The result of a future, once it is there.
pub struct Pending<T>(Arc<Mutex<Option<T>>>);

impl<T: 'static> Pending<T> {
    /// Run `work`: to its end now on the desktop, on the page's event loop in the browser
    /// (repainting `ctx` when it ends).
    pub fn spawn(work: impl Future<Output = T> + 'static, ctx: &egui::Context) -> Self {
        let slot = Arc::new(Mutex::new(None));
        #[cfg(not(target_arch = "wasm32"))]
        {
            let _ = ctx;
            *slot.lock().unwrap_or_else(|e| e.into_inner()) = Some(pollster::block_on(work));
        }
        #[cfg(target_arch = "wasm32")]
        {
            let (into, ctx) = (slot.clone(), ctx.clone());
            wasm_bindgen_futures::spawn_local(async move {
                let out = work.await;
                *into.lock().unwrap_or_else(|e| e.into_inner()) = Some(out);
                ctx.request_repaint();
            });
        }
        Self(slot)
    }

    /// The result, once (`None` while the work runs).
    pub fn take(&self) -> Option<T> {
        self.0.lock().unwrap_or_else(|e| e.into_inner()).take()
    }
}
