//! The adapter and device: Vulkan only, headless, created once per [`Gpu`].

use std::fmt;

/// What can go wrong on the GPU path. Every variant says what to do about it.
#[derive(Debug)]
pub enum GpuError {
    /// No Vulkan adapter was found: no driver installed, or none that wgpu accepts.
    NoAdapter(String),
    /// The adapter refused the device (its limits are below what the scene needs).
    Device(String),
    /// What the GPU path does not cover (a render setting its renderer refuses, with the reason).
    Unsupported(String),
    /// The scene does not fit the adapter's buffer limits.
    TooLarge {
        /// Which buffer.
        what: &'static str,
        /// Its size in bytes.
        bytes: u64,
        /// The adapter's largest storage buffer binding.
        limit: u64,
    },
    /// A dispatch or a read-back failed (the device was lost or ran out of memory).
    Dispatch(String),
    /// The driver cut a query's loops short even with its ray alone (Mesa's lavapipe ends every
    /// loop of a shader invocation after 65 535 loop passes in all; see `shaders/tree.wgsl`'s
    /// `loops_cut`), so its answer cannot be trusted: what was asked.
    LoopLimit(String),
}

impl fmt::Display for GpuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NoAdapter(why) => write!(
                f,
                "no Vulkan adapter found ({why}). Install a Vulkan driver: your GPU vendor's, or Mesa's \
                 software one (Debian/Ubuntu: `apt-get install mesa-vulkan-drivers libvulkan1`), and \
                 set XDG_RUNTIME_DIR if it is unset"
            ),
            Self::Device(why) => write!(f, "the Vulkan adapter refused the device: {why}"),
            Self::Unsupported(what) => write!(f, "not on the GPU yet: {what}; use --device cpu"),
            Self::TooLarge { what, bytes, limit } => write!(
                f,
                "the scene's {what} need {bytes} bytes, over the adapter's storage buffer limit of {limit} bytes; \
                 use --device cpu or a smaller scene"
            ),
            Self::Dispatch(why) => write!(f, "GPU dispatch failed: {why}"),
            Self::LoopLimit(what) => write!(
                f,
                "the Vulkan driver cut the loops of {what} short (Mesa's lavapipe stops every loop after \
                 65535 passes per shader invocation), so its answer would be wrong; use --device cpu"
            ),
        }
    }
}

impl std::error::Error for GpuError {}

/// A headless Vulkan device and its queue.
pub struct Gpu {
    pub(crate) device: wgpu::Device,
    pub(crate) queue: wgpu::Queue,
    info: wgpu::AdapterInfo,
    max_binding: u64,
    /// The first error the device reported and nobody has read yet.
    pub(crate) errors: std::sync::Arc<std::sync::Mutex<Option<String>>>,
}

impl Gpu {
    /// The first Vulkan adapter wgpu offers (high performance preferred), with the adapter's own
    /// storage-buffer limits so that large scenes fit. Errors: [`GpuError::NoAdapter`] without
    /// a driver, [`GpuError::Device`] when the device cannot be created.
    pub fn new() -> Result<Self, GpuError> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = wgpu::Backends::VULKAN;
        let instance = wgpu::Instance::new(desc);
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            ..Default::default()
        }))
        .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let have = adapter.limits();
        let limits = wgpu::Limits {
            max_storage_buffer_binding_size: have.max_storage_buffer_binding_size,
            max_buffer_size: have.max_buffer_size,
            max_storage_buffers_per_shader_stage: have.max_storage_buffers_per_shader_stage.min(8),
            ..wgpu::Limits::default()
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("tubecast"),
            required_limits: limits.clone(),
            ..Default::default()
        }))
        .map_err(|e| GpuError::Device(e.to_string()))?;
        let max_binding = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
        let errors = Self::catch_errors(&device);
        Ok(Self { device, queue, info: adapter.get_info(), max_binding, errors })
    }

    /// The adapter's name and driver, e.g. `llvmpipe (LLVM 15.0.6, 256 bits) (Mesa 22.3.6)`.
    pub fn describe(&self) -> String {
        let i = &self.info;
        format!("{} ({:?}, {} {})", i.name, i.device_type, i.driver, i.driver_info)
    }

    /// True on a CPU-emulated adapter (Mesa's lavapipe): its timings say nothing of a real GPU.
    pub fn is_software(&self) -> bool {
        self.info.device_type == wgpu::DeviceType::Cpu
    }

    /// The largest storage buffer binding the device allows, bytes.
    pub fn max_binding(&self) -> u64 {
        self.max_binding
    }

    /// Check that a buffer of `bytes` fits.
    pub(crate) fn fits(&self, what: &'static str, bytes: u64) -> Result<(), GpuError> {
        if bytes > self.max_binding {
            return Err(GpuError::TooLarge { what, bytes, limit: self.max_binding });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_adapter_names_what_to_install() {
        let msg = GpuError::NoAdapter("no suitable adapter".into()).to_string();
        assert!(
            msg.contains("apt-get install mesa-vulkan-drivers libvulkan1") && msg.contains("XDG_RUNTIME_DIR"),
            "{msg}"
        );
    }
}
