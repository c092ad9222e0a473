//! Getting a device: a Vulkan adapter, a CPU one (lavapipe) preferred, or the one named by
//! `GLAZEC_ADAPTER`.

use crate::RunError;

/// Environment variable: a case-insensitive substring of the adapter name to use
/// (e.g. `llvmpipe`); without it a CPU adapter is preferred, then the first one found.
pub const ADAPTER_ENV: &str = "GLAZEC_ADAPTER";

/// A device and its queue, plus what the kernels need to know about them.
pub struct Gpu {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
    /// Whether passthrough SPIR-V modules can be created (needed for the HLSL path).
    pub passthrough: bool,
}

impl Gpu {
    /// Opens a device on a Vulkan adapter.
    ///
    /// # Errors
    /// [`RunError::NoAdapter`] if there is none (or none matching `GLAZEC_ADAPTER`);
    /// [`RunError::Device`] if the adapter refuses to open a device.
    pub fn new() -> Result<Gpu, RunError> {
        let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle();
        descriptor.backends = wgpu::Backends::VULKAN;
        let instance = wgpu::Instance::new(descriptor);
        let adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::VULKAN));
        let wanted = std::env::var(ADAPTER_ENV).ok().filter(|w| !w.is_empty());
        let available: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
        let chosen = match &wanted {
            Some(w) => {
                let w = w.to_lowercase();
                adapters.into_iter().find(|a| a.get_info().name.to_lowercase().contains(&w))
            }
            None => {
                let mut adapters = adapters;
                // A stable order: CPU adapters (lavapipe) first, then by name.
                adapters.sort_by_key(|a| {
                    let info = a.get_info();
                    (info.device_type != wgpu::DeviceType::Cpu, info.name)
                });
                adapters.into_iter().next()
            }
        };
        let Some(adapter) = chosen else {
            return Err(RunError::NoAdapter { wanted, available });
        };
        let info = adapter.get_info();
        let passthrough = adapter.features().contains(wgpu::Features::PASSTHROUGH_SHADERS);
        let required_features = if passthrough { wgpu::Features::PASSTHROUGH_SHADERS } else { wgpu::Features::empty() };
        let required_limits = wgpu::Limits {
            max_storage_buffer_binding_size: adapter.limits().max_storage_buffer_binding_size,
            max_buffer_size: adapter.limits().max_buffer_size,
            ..wgpu::Limits::default()
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("glazec"),
            required_features,
            required_limits,
            ..Default::default()
        }))
        .map_err(|e| RunError::Device { adapter: info.name.clone(), message: e.to_string() })?;
        Ok(Gpu { device, queue, info, passthrough })
    }

    /// "llvmpipe (LLVM 15.0.6, 256 bits) [Vulkan, Mesa 22.3.6 (LLVM 15.0.6)]".
    pub fn describe(&self) -> String {
        format!("{} [{:?}, {}]", self.info.name, self.info.backend, self.info.driver_info)
    }

    /// Runs `f` and turns any validation error it raised into [`RunError::Rejected`].
    pub(crate) fn checked<T>(&self, what: &str, f: impl FnOnce() -> T) -> Result<T, RunError> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let value = f();
        match pollster::block_on(scope.pop()) {
            None => Ok(value),
            Some(e) => Err(RunError::Rejected { what: what.to_string(), message: e.to_string() }),
        }
    }

    /// Waits until the device is idle.
    pub(crate) fn wait(&self) -> Result<(), RunError> {
        self.device.poll(wgpu::PollType::wait_indefinitely()).map(|_| ()).map_err(|e| RunError::Readback(e.to_string()))
    }

    /// Copies a buffer's contents back to the host.
    pub(crate) fn read_buffer(&self, source: &wgpu::Buffer, size: u64) -> Result<Vec<u8>, RunError> {
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = self.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(source, 0, &staging, 0, size);
        self.queue.submit([encoder.finish()]);
        let (sender, receiver) = std::sync::mpsc::channel();
        staging.slice(..).map_async(wgpu::MapMode::Read, move |result| {
            let _ = sender.send(result);
        });
        self.wait()?;
        match receiver.recv() {
            Ok(Ok(())) => {}
            Ok(Err(e)) => return Err(RunError::Readback(e.to_string())),
            Err(e) => return Err(RunError::Readback(e.to_string())),
        }
        let bytes = staging.slice(..).get_mapped_range().map_err(|e| RunError::Readback(e.to_string()))?.to_vec();
        staging.unmap();
        Ok(bytes)
    }
}
