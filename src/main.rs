//! The `tensorglyph` command line: demo, info, render, view, bench, stability
//! (`tensorglyph::cli`, where the arguments are parsed and the commands run).

// deny, not forbid: `quiet_device_select` below is the binary's one unsafe block.
#![deny(unsafe_code)]

use std::process::ExitCode;

fn main() -> ExitCode {
    quiet_device_select();
    let status = tensorglyph::cli::main(std::env::args_os());
    ExitCode::from(u8::try_from(status).unwrap_or(2))
}

/// Turn off Mesa's implicit Vulkan layer `VK_LAYER_MESA_device_select` for this process, unless
/// the user set `NODEVICE_SELECT` or one of the layer's own settings (`MESA_VK_DEVICE_SELECT`,
/// `MESA_VK_DEVICE_SELECT_FORCE_DEFAULT_DEVICE`), which ask for the layer.
///
/// The layer only reorders the physical devices, and wgpu picks its adapter itself; but without
/// `XDG_RUNTIME_DIR` (containers, batch jobs) it prints `error: XDG_RUNTIME_DIR is invalid or not
/// set in the environment.` twice on every run, lines that are not ours. wgpu 30 has no instance
/// option that skips implicit layers (its `BackendOptions` hold GL, DX12 and no-op options only),
/// and the Vulkan loader reads its layer switches from the environment alone, so the environment
/// it is. (The loader turns the layer off when `NODEVICE_SELECT` is set to anything, `0` too.)
#[allow(unsafe_code)]
fn quiet_device_select() {
    let asked = [
        "NODEVICE_SELECT",
        "MESA_VK_DEVICE_SELECT",
        "MESA_VK_DEVICE_SELECT_FORCE_DEFAULT_DEVICE",
    ];
    if asked.iter().any(|v| std::env::var_os(v).is_some()) {
        return;
    }
    // SAFETY: `set_var` is unsound only while another thread reads or writes the environment.
    // This runs first in `main`, before anything that could start a thread (the CLI, wgpu, the
    // viewer, rayon's pool); the standard library's runtime starts none before `main`.
    unsafe { std::env::set_var("NODEVICE_SELECT", "1") };
}
