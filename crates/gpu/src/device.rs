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
    /// The scene (or a query's buffer) does not fit the adapter's buffer limits.
    TooLarge {
        /// Which buffer.
        what: &'static str,
        /// Its size in bytes.
        bytes: u64,
        /// The most the GPU path binds for it: the adapter's largest storage buffer binding
        /// (whole records of it), times the bindings a scene's nodes or primitives are split
        /// across ([`Gpu::SPLIT`]; one for the other buffers).
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
                "the scene's {what} need {bytes} bytes, over the adapter's storage buffer limit of {limit} bytes \
                 (its storage buffer bindings, as many as the GPU path splits them across); \
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
    /// The per-binding sizes a scene's nodes and primitives are split by
    /// ([`Gpu::with_split_limits`]); `max_binding` unless set.
    pub(crate) split: [u64; 2],
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
        if have.max_storage_buffers_per_shader_stage < Self::STORAGE_BUFFERS {
            return Err(GpuError::Device(format!(
                "it offers {} storage buffers per shader stage, and the GPU path binds {} (a scene's \
                 nodes and primitives split across {} bindings each, the rays, the interval offsets and \
                 the output)",
                have.max_storage_buffers_per_shader_stage,
                Self::STORAGE_BUFFERS,
                Self::SPLIT
            )));
        }
        let limits = wgpu::Limits {
            max_storage_buffer_binding_size: have.max_storage_buffer_binding_size,
            max_buffer_size: have.max_buffer_size,
            max_storage_buffers_per_shader_stage: Self::STORAGE_BUFFERS,
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
        Ok(Self { device, queue, info: adapter.get_info(), max_binding, split: [max_binding; 2], errors })
    }

    /// The bindings a scene's tree nodes, and likewise its primitives, are split across, each
    /// within the adapter's binding limit: a scene's nodes and primitives may each take up to
    /// this many times [`Gpu::max_binding`] (`shaders/tree.wgsl`'s `node_at`, `prim_at`).
    pub const SPLIT: usize = 4;

    /// The storage buffers a query binds: the split nodes and primitives, the rays, the line
    /// interval offsets (`list_lines`) and the output.
    const STORAGE_BUFFERS: u32 = 2 * Self::SPLIT as u32 + 3;

    /// This device with every buffer binding held to at most `bytes` (at most the adapter's own
    /// limit): scenes split into more bindings, queries run in more dispatches. For tests (a
    /// small scene split as a large one is on a real adapter) and tuning.
    ///
    /// ```no_run
    /// # fn main() -> Result<(), tubecast_gpu::GpuError> {
    /// let gpu = tubecast_gpu::Gpu::new()?.with_binding_limit(1 << 20);
    /// assert!(gpu.max_binding() <= 1 << 20);
    /// # Ok(())
    /// # }
    /// ```
    pub fn with_binding_limit(mut self, bytes: u64) -> Self {
        self.max_binding = self.max_binding.min(bytes);
        self.split = self.split.map(|s| s.min(bytes));
        self
    }

    /// [`Gpu::with_binding_limit`] for the scene's tree nodes and primitives apart (each at most
    /// [`Gpu::max_binding`]): their sizes differ by a factor that depends on the tree, so a
    /// test that splits both into several bindings needs two caps.
    #[doc(hidden)]
    pub fn with_split_limits(mut self, nodes: u64, prims: u64) -> Self {
        self.split = [nodes.min(self.max_binding), prims.min(self.max_binding)];
        self
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

    /// The largest storage buffer binding the device allows (or [`Gpu::with_binding_limit`]'s),
    /// bytes: the most one dispatch's rays or outputs take, and a scene's nodes and primitives
    /// [`Gpu::SPLIT`] times it each.
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
