//! Pixels from a figure: its SVG rendered by resvg (tiny-skia) with DejaVu Sans embedded in the
//! binary, so no system font is needed and the PNG shows exactly what the SVG says. The pixels
//! and their encodings are in [`crate::raster`].

use std::sync::{Arc, OnceLock};

use resvg::{tiny_skia, usvg};

use crate::figure::{Figure, FONT_FAMILY};
use crate::raster::{Image, RenderError};

/// The figure font (DejaVu Sans: Latin, Greek, the math signs used in labels).
const FONT: &[u8] = include_bytes!("../fonts/DejaVuSans.ttf");

fn options() -> &'static usvg::Options<'static> {
    static OPTIONS: OnceLock<usvg::Options<'static>> = OnceLock::new();
    OPTIONS.get_or_init(|| {
        let mut db = usvg::fontdb::Database::new();
        db.load_font_data(FONT.to_vec());
        usvg::Options {
            font_family: FONT_FAMILY.to_string(),
            fontdb: Arc::new(db),
            ..usvg::Options::default()
        }
    })
}

/// Render SVG text at `scale` device pixels per SVG pixel, on white.
pub fn rasterize_svg(svg: &str, scale: f32) -> Result<Image, RenderError> {
    let tree = usvg::Tree::from_str(svg, options())?;
    let size = tree.size();
    let (width, height) = (
        (size.width() * scale).ceil() as u32,
        (size.height() * scale).ceil() as u32,
    );
    let mut pixmap =
        tiny_skia::Pixmap::new(width, height).ok_or(RenderError::Size { width, height })?;
    pixmap.fill(tiny_skia::Color::WHITE);
    resvg::render(
        &tree,
        tiny_skia::Transform::from_scale(scale, scale),
        &mut pixmap.as_mut(),
    );
    // Opaque on a white ground: premultiplied RGB is plain RGB.
    let rgb = pixmap
        .data()
        .chunks_exact(4)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    Ok(Image { width, height, rgb })
}

impl Figure {
    /// The figure in pixels, `scale` per SVG pixel (2 for print).
    pub fn rasterize(&self, scale: f32) -> Result<Image, RenderError> {
        rasterize_svg(&self.to_svg(), scale)
    }

    /// The figure as PNG bytes.
    pub fn to_png(&self, scale: f32) -> Result<Vec<u8>, RenderError> {
        self.rasterize(scale)?.to_png()
    }
}
