//! Saiho's tools: `cloth-latency` (measurements with reports and plots) and `cloth-lab`
//! (the launcher). The library holds what both binaries and their tests share.

pub mod cpu_plan;
pub mod headless;
pub mod lab;
pub mod latency;
pub mod plot;
pub mod soak;
pub mod stats;
