//! # cellsweep-plot
//!
//! Pictures without system dependencies. A [`Figure`] is a list of shapes written once as SVG;
//! PNGs and GIF frames are that SVG rendered by resvg ([`render`], [`Image`]) with DejaVu Sans
//! embedded in the binary, so every format shows the same figure. [`phase`] draws phase
//! diagrams, frequency heat maps and free-speed curves; [`frames`] draws snapshots of the two
//! cells of a collision.

pub mod figure;
pub mod frames;
pub mod phase;
pub mod raster;
pub mod render;

pub use figure::{viridis, Anchor, Color, Figure, Shape};
pub use raster::{gif, Image, RenderError};
