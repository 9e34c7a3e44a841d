//! # cellsweep-plot
//!
//! Pictures without system dependencies: a [`Figure`] is a list of shapes rendered to SVG text
//! or to pixels ([`Raster`], PNG, animated GIF) with an embedded bitmap font. [`phase`] draws
//! phase diagrams, frequency heat maps and free-speed curves; [`frames`] draws trajectory
//! snapshots of the two cells.

pub mod figure;
pub mod frames;
pub mod phase;
pub mod raster;

pub use figure::{viridis, Anchor, Color, Figure, Shape};
pub use raster::{gif, Raster};
