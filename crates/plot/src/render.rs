//! Pixels from a figure: its SVG rendered by resvg (tiny-skia) with DejaVu Sans embedded in the
//! binary, so no system font is needed and the PNG shows exactly what the SVG says. Also PNG
//! and animated-GIF encoding of the pixels.

use std::sync::{Arc, OnceLock};

use resvg::{tiny_skia, usvg};
use thiserror::Error;

use crate::figure::Figure;

/// The figure font (DejaVu Sans: Latin, Greek, the math signs used in labels).
const FONT: &[u8] = include_bytes!("../fonts/DejaVuSans.ttf");
/// The family name the SVG asks for.
pub const FONT_FAMILY: &str = "DejaVu Sans";

/// Why a figure could not be turned into pixels or encoded.
#[derive(Debug, Error)]
pub enum RenderError {
    #[error("the figure's SVG does not parse: {0}")]
    Svg(#[from] usvg::Error),
    #[error("a {width} x {height} pixel image is too large to draw")]
    Size { width: u32, height: u32 },
    #[error("PNG encoding failed: {0}")]
    Png(#[from] png::EncodingError),
    #[error("GIF encoding failed: {0}")]
    Gif(#[from] gif::EncodingError),
    #[error("frame {index} is {got:?}, the first is {want:?}: a movie's frames share one size")]
    FrameSize {
        index: usize,
        got: (u32, u32),
        want: (u32, u32),
    },
}

/// An opaque RGB image, row-major from the top left.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
}

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

impl Image {
    /// PNG bytes (8-bit RGB).
    pub fn to_png(&self) -> Result<Vec<u8>, RenderError> {
        encode_png(self.width, self.height, &self.rgb)
    }
}

/// PNG bytes of an 8-bit RGB pixel block.
pub fn encode_png(width: u32, height: u32, rgb: &[u8]) -> Result<Vec<u8>, RenderError> {
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, width, height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut w = enc.write_header()?;
        w.write_image_data(rgb)?;
    }
    Ok(out)
}

/// An endlessly looping animated GIF of `frames`, `delay_cs` hundredths of a second each.
pub fn gif(frames: &[Image], delay_cs: u16) -> Result<Vec<u8>, RenderError> {
    let Some(first) = frames.first() else {
        return Ok(Vec::new());
    };
    let (w, h) = (first.width, first.height);
    let (gw, gh) = match (u16::try_from(w), u16::try_from(h)) {
        (Ok(a), Ok(b)) => (a, b),
        _ => {
            return Err(RenderError::Size {
                width: w,
                height: h,
            })
        }
    };
    let mut out = Vec::new();
    {
        let mut enc = gif::Encoder::new(&mut out, gw, gh, &[])?;
        enc.set_repeat(gif::Repeat::Infinite)?;
        for (index, f) in frames.iter().enumerate() {
            if (f.width, f.height) != (w, h) {
                return Err(RenderError::FrameSize {
                    index,
                    got: (f.width, f.height),
                    want: (w, h),
                });
            }
            let mut frame = gif::Frame::from_rgb_speed(gw, gh, &f.rgb, 10);
            frame.delay = delay_cs;
            enc.write_frame(&frame)?;
        }
    }
    Ok(out)
}
