//! One module per subcommand: its arguments (`Args`) and its body (`run`).

pub mod check;
pub mod compile;
pub mod eval;
pub mod optics;

#[cfg(feature = "lab")]
pub mod accuracy;
#[cfg(all(feature = "lab", feature = "gpu"))]
pub mod bench;
#[cfg(all(feature = "lab", feature = "gpu"))]
pub mod images;
#[cfg(feature = "gpu")]
pub mod preview;
#[cfg(feature = "lab")]
pub mod stability;
#[cfg(feature = "lab")]
pub mod tables;
