//! Pixels: an RGB [`Image`], its PNG and GIF encodings, and [`RenderError`] for whatever turns
//! a figure into them.

use resvg::usvg;
use thiserror::Error;

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
