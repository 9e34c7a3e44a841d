//! # cellsweep-plot
//!
//! Pictures without system dependencies. A [`Figure`] is a list of shapes written once as SVG;
//! PNGs and GIF frames are that SVG rendered by resvg ([`render`], [`Image`]) with DejaVu Sans
//! embedded in the binary, so every format shows the same figure. [`phase`] draws phase
//! diagrams and frequency heat maps (with the symbols of [`mark`]), [`speed`] free-speed
//! curves, [`collapse`] every column's beta* against alpha~/L~; [`frames`] draws snapshots of the two
//! cells of a collision.

pub mod collapse;
pub mod figure;
pub mod frames;
pub mod mark;
mod panel;
pub mod phase;
pub mod raster;
pub mod render;
pub mod speed;

pub use figure::{viridis, Anchor, Color, Figure, Shape};
pub use raster::{gif, Image, RenderError};
