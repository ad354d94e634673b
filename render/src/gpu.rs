//! Finding a GPU adapter and opening a device, with or without a window.

use crate::RenderError;

/// Which adapter to prefer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum AdapterPreference {
    /// A hardware GPU if there is one, else a software one.
    #[default]
    Hardware,
    /// A software rasteriser (Mesa lavapipe on Vulkan, else llvmpipe on GL): deterministic
    /// pictures for tests.
    Software,
}

/// An adapter, its device and queue.
#[derive(Debug)]
pub struct Gpu {
    pub instance: wgpu::Instance,
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
}

/// What to install when no adapter is found.
pub const NO_ADAPTER_HELP: &str = "no GPU adapter found: install Mesa's software Vulkan driver \
     (Debian: apt-get install mesa-vulkan-drivers) or a GPU driver";

impl Gpu {
    /// Opens a device without a window (off-screen rendering and tests).
    pub fn headless(preference: AdapterPreference) -> Result<Gpu, RenderError> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = pick_adapter(&instance, preference)?;
        Self::open(instance, adapter)
    }

    /// Opens a device that can draw into a window's `surface` (made by the caller from the
    /// window with `instance.create_surface`).
    pub fn for_surface(
        instance: wgpu::Instance,
        surface: &wgpu::Surface<'_>,
        preference: AdapterPreference,
    ) -> Result<Gpu, RenderError> {
        let adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
        let compatible: Vec<wgpu::Adapter> = adapters.into_iter().filter(|a| a.is_surface_supported(surface)).collect();
        let adapter = best_adapter(compatible, preference).ok_or_else(|| {
            RenderError::NoAdapter(format!("{NO_ADAPTER_HELP} (none of the adapters can draw into this window)"))
        })?;
        Self::open(instance, adapter)
    }

    /// Opens a device on a chosen adapter.
    pub fn open(instance: wgpu::Instance, adapter: wgpu::Adapter) -> Result<Gpu, RenderError> {
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("taut"),
            required_features: wgpu::Features::empty(),
            required_limits: adapter.limits(),
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .map_err(|e| RenderError::Device(e.to_string()))?;
        Ok(Gpu { instance, adapter, device, queue })
    }

    /// The adapter's name and backend, for messages.
    pub fn description(&self) -> String {
        let info = self.adapter.get_info();
        format!("{} ({:?}, {:?})", info.name, info.backend, info.device_type)
    }
}

/// Picks an adapter: hardware first unless software is asked for; among software adapters
/// Vulkan (lavapipe) before GL (llvmpipe).
pub fn pick_adapter(instance: &wgpu::Instance, preference: AdapterPreference) -> Result<wgpu::Adapter, RenderError> {
    let adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
    best_adapter(adapters, preference).ok_or_else(|| RenderError::NoAdapter(NO_ADAPTER_HELP.to_string()))
}

fn best_adapter(adapters: Vec<wgpu::Adapter>, preference: AdapterPreference) -> Option<wgpu::Adapter> {
    let rank = |a: &wgpu::Adapter| {
        let info = a.get_info();
        let software = info.device_type == wgpu::DeviceType::Cpu;
        let kind = match (preference, software) {
            (AdapterPreference::Software, true) | (AdapterPreference::Hardware, false) => 0,
            _ => 1,
        };
        let backend = if info.backend == wgpu::Backend::Vulkan { 0 } else { 1 };
        let discrete = if info.device_type == wgpu::DeviceType::DiscreteGpu { 0 } else { 1 };
        (kind, backend, discrete)
    };
    adapters.into_iter().min_by_key(rank)
}
