//! Log-aesthetic curves (Miura, Yoshida and Saito, "Discrete log-aesthetic filter", seed
//! `003_0c1161d9995b9b01`; our reading is `shared/spec/log-aesthetic.md`).

pub mod law;
pub mod segment;

pub use law::{LineFit, fit_line};
pub use segment::AestheticSegment;
