//! Compute plumbing: one pipeline per entry point over a fixed binding layout (a uniform at
//! binding 0, read-only storage inputs after it, one read-write output last), dispatch over a
//! 2-D grid of 64-thread workgroups, read-back.

use crate::device::{Gpu, GpuError};
use bytemuck::Pod;
use std::sync::{Arc, Mutex};
use wgpu::util::DeviceExt;

/// Threads per workgroup (the shaders' `@workgroup_size`).
pub(crate) const GROUP: u32 = 64;

/// A compute pipeline and its bind group layout.
pub(crate) struct Kernel {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    inputs: usize,
}

impl Gpu {
    /// Errors the device reported since the last call (validation or out-of-memory), which
    /// wgpu would otherwise turn into a panic.
    fn take_error(&self) -> Result<(), GpuError> {
        match self.errors.lock().map(|mut e| e.take()) {
            Ok(None) => Ok(()),
            Ok(Some(e)) => Err(GpuError::Dispatch(e)),
            Err(_) => Err(GpuError::Dispatch("error log poisoned".into())),
        }
    }

    /// Route the device's uncaptured errors into [`Gpu::take_error`].
    pub(crate) fn catch_errors(device: &wgpu::Device) -> Arc<Mutex<Option<String>>> {
        let log = Arc::new(Mutex::new(None));
        let sink = log.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            if let Ok(mut s) = sink.lock() {
                s.get_or_insert_with(|| e.to_string());
            }
        }));
        log
    }

    /// The pipeline of entry point `entry` of `source`, with `inputs` read-only storage buffers.
    pub(crate) fn kernel(&self, source: &str, entry: &str, inputs: usize) -> Result<Kernel, GpuError> {
        let module = self.device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(entry),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let storage = |i: usize, read_only: bool| wgpu::BindGroupLayoutEntry {
            binding: i as u32,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let mut entries = vec![wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }];
        entries.extend((1..=inputs).map(|i| storage(i, true)));
        entries.push(storage(inputs + 1, false));
        let layout = self
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(entry), entries: &entries });
        let pl = self.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(entry),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = self.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: Some(&pl),
            module: &module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        });
        self.take_error()?;
        Ok(Kernel { pipeline, layout, inputs })
    }

    /// A read-only storage buffer holding `data`; an empty `data` gets one zeroed element (a
    /// binding must be at least one element long; the shaders never read it).
    pub(crate) fn upload<T: Pod>(&self, what: &'static str, data: &[T]) -> Result<wgpu::Buffer, GpuError> {
        self.upload_within(what, data, self.max_binding())
    }

    /// [`Self::upload`] within `cap` bytes (at most [`Gpu::max_binding`]).
    fn upload_within<T: Pod>(&self, what: &'static str, data: &[T], cap: u64) -> Result<wgpu::Buffer, GpuError> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        if bytes.len() as u64 > cap {
            return Err(GpuError::TooLarge { what, bytes: bytes.len() as u64, limit: cap });
        }
        self.fits(what, bytes.len() as u64)?;
        let pad = vec![0u8; std::mem::size_of::<T>().max(16)];
        let contents = if bytes.is_empty() { &pad[..] } else { bytes };
        let buf = self.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(what),
            contents,
            usage: wgpu::BufferUsages::STORAGE,
        });
        self.take_error()?;
        Ok(buf)
    }

    /// `data` split on record boundaries into [`Gpu::SPLIT`] read-only storage buffers of at
    /// most `cap` bytes each (the unused ones one zeroed record long: a binding cannot be
    /// empty, and the shaders never read them), with the records per buffer (every buffer but
    /// the last full). Errors: [`GpuError::TooLarge`] where `data` needs more buffers.
    pub(crate) fn upload_split<T: Pod>(
        &self,
        what: &'static str,
        data: &[T],
        cap: u64,
    ) -> Result<(Vec<wgpu::Buffer>, u32), GpuError> {
        let size = std::mem::size_of::<T>() as u64;
        // Record indices are u32 in the shaders.
        let per = (cap / size).min(u64::from(u32::MAX));
        let bytes = data.len() as u64 * size;
        let limit = Self::SPLIT as u64 * per * size;
        if bytes > limit {
            return Err(GpuError::TooLarge { what, bytes, limit });
        }
        let mut bufs = Vec::with_capacity(Self::SPLIT);
        for chunk in data.chunks(per.max(1) as usize) {
            bufs.push(self.upload_within(what, chunk, cap)?);
        }
        while bufs.len() < Self::SPLIT {
            bufs.push(self.upload_within::<T>(what, &[], cap)?);
        }
        Ok((bufs, per as u32))
    }

    /// Run `k` over `n` threads with the uniform `params` and `inputs`, returning `n` outputs.
    pub(crate) fn run<P: Pod, O: Pod>(
        &self,
        k: &Kernel,
        params: &P,
        inputs: &[&wgpu::Buffer],
        n: usize,
    ) -> Result<Vec<O>, GpuError> {
        self.run_sized(k, params, inputs, n, n)
    }

    /// [`Self::run`] over `threads` threads with `n` outputs (zeroed where no thread runs).
    pub(crate) fn run_sized<P: Pod, O: Pod>(
        &self,
        k: &Kernel,
        params: &P,
        inputs: &[&wgpu::Buffer],
        threads: usize,
        n: usize,
    ) -> Result<Vec<O>, GpuError> {
        assert_eq!(inputs.len(), k.inputs, "binding count of the kernel");
        if n == 0 || threads == 0 {
            return Ok(vec![O::zeroed(); n]);
        }
        let size = (n * std::mem::size_of::<O>()) as u64;
        self.fits("outputs", size)?;
        let uniform = self.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("params"),
            contents: bytemuck::bytes_of(params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let out = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("out"),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let back = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("read-back"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut entries = vec![wgpu::BindGroupEntry { binding: 0, resource: uniform.as_entire_binding() }];
        entries.extend(
            inputs
                .iter()
                .enumerate()
                .map(|(i, b)| wgpu::BindGroupEntry { binding: i as u32 + 1, resource: b.as_entire_binding() }),
        );
        entries.push(wgpu::BindGroupEntry { binding: inputs.len() as u32 + 1, resource: out.as_entire_binding() });
        let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &k.layout,
            entries: &entries,
        });
        let mut enc = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: None, timestamp_writes: None });
            pass.set_pipeline(&k.pipeline);
            pass.set_bind_group(0, &group, &[]);
            let groups = (threads as u64).div_ceil(u64::from(GROUP));
            let x = groups.min(65_535);
            let y = groups.div_ceil(x);
            pass.dispatch_workgroups(x as u32, y as u32, 1);
        }
        enc.copy_buffer_to_buffer(&out, 0, &back, 0, size);
        self.queue.submit([enc.finish()]);
        let slice = back.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| GpuError::Dispatch(e.to_string()))?;
        match rx.recv() {
            Ok(Ok(())) => {}
            Ok(Err(e)) => return Err(GpuError::Dispatch(e.to_string())),
            Err(e) => return Err(GpuError::Dispatch(e.to_string())),
        }
        self.take_error()?;
        let data = slice.get_mapped_range().map_err(|e| GpuError::Dispatch(e.to_string()))?;
        let v = bytemuck::pod_collect_to_vec(&data[..]);
        drop(data);
        back.unmap();
        Ok(v)
    }
}
