//! Rendering a [`Figure`] to pixels, and PNG / GIF encoding. Text uses the public-domain 8x8
//! bitmap font of `font8x8`, scaled by whole pixels: no system fonts needed.

use font8x8::UnicodeFonts;

use crate::figure::{Anchor, Color, Figure, Shape};

/// An RGB image.
#[derive(Debug, Clone, PartialEq)]
pub struct Raster {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
}

impl Raster {
    pub fn new(width: u32, height: u32, background: Color) -> Self {
        let mut rgb = Vec::with_capacity((width * height * 3) as usize);
        for _ in 0..width * height {
            rgb.extend_from_slice(&[background.0, background.1, background.2]);
        }
        Raster { width, height, rgb }
    }

    /// Blend `c` over pixel (x, y) with coverage `a` in [0, 1].
    pub fn blend(&mut self, x: i64, y: i64, c: Color, a: f64) {
        if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 || a <= 0.0 {
            return;
        }
        let k = ((y as u32 * self.width + x as u32) * 3) as usize;
        let a = a.min(1.0);
        for (ch, v) in [c.0, c.1, c.2].into_iter().enumerate() {
            let old = self.rgb[k + ch] as f64;
            self.rgb[k + ch] = (old + (v as f64 - old) * a).round() as u8;
        }
    }

    fn fill_rect(&mut self, x: f64, y: f64, w: f64, h: f64, c: Color) {
        let (x0, y0) = (x.round() as i64, y.round() as i64);
        let (x1, y1) = ((x + w).round() as i64, (y + h).round() as i64);
        for py in y0..y1 {
            for px in x0..x1 {
                self.blend(px, py, c, 1.0);
            }
        }
    }

    /// Anti-aliased thick segment: coverage from the distance of each pixel centre.
    fn segment(&mut self, x1: f64, y1: f64, x2: f64, y2: f64, c: Color, width: f64) {
        let half = width.max(1.0) / 2.0;
        let (minx, maxx) = (x1.min(x2) - half - 1.0, x1.max(x2) + half + 1.0);
        let (miny, maxy) = (y1.min(y2) - half - 1.0, y1.max(y2) + half + 1.0);
        let (dx, dy) = (x2 - x1, y2 - y1);
        let len2 = dx * dx + dy * dy;
        for py in miny.floor() as i64..=maxy.ceil() as i64 {
            for px in minx.floor() as i64..=maxx.ceil() as i64 {
                let (cx, cy) = (px as f64 + 0.5, py as f64 + 0.5);
                let t = if len2 > 0.0 {
                    (((cx - x1) * dx + (cy - y1) * dy) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let d = ((cx - x1 - t * dx).powi(2) + (cy - y1 - t * dy).powi(2)).sqrt();
                self.blend(px, py, c, half + 0.5 - d);
            }
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn line(
        &mut self,
        x1: f64,
        y1: f64,
        x2: f64,
        y2: f64,
        c: Color,
        width: f64,
        dash: Option<f64>,
    ) {
        match dash {
            None => self.segment(x1, y1, x2, y2, c, width),
            Some(d) => {
                let len = ((x2 - x1).powi(2) + (y2 - y1).powi(2)).sqrt();
                let n = (len / d).ceil() as usize;
                for k in (0..n).step_by(2) {
                    let (t0, t1) = (k as f64 * d / len, ((k + 1) as f64 * d / len).min(1.0));
                    self.segment(
                        x1 + t0 * (x2 - x1),
                        y1 + t0 * (y2 - y1),
                        x1 + t1 * (x2 - x1),
                        y1 + t1 * (y2 - y1),
                        c,
                        width,
                    );
                }
            }
        }
    }

    fn circle(&mut self, cx: f64, cy: f64, r: f64, fill: Option<Color>, stroke: Option<Color>) {
        for py in (cy - r - 2.0).floor() as i64..=(cy + r + 2.0).ceil() as i64 {
            for px in (cx - r - 2.0).floor() as i64..=(cx + r + 2.0).ceil() as i64 {
                let d = ((px as f64 + 0.5 - cx).powi(2) + (py as f64 + 0.5 - cy).powi(2)).sqrt();
                if let Some(f) = fill {
                    self.blend(px, py, f, r + 0.5 - d);
                }
                if let Some(s) = stroke {
                    self.blend(px, py, s, 1.25 - (d - r).abs());
                }
            }
        }
    }

    fn polygon(&mut self, pts: &[(f64, f64)], fill: Option<Color>, stroke: Option<Color>) {
        if let Some(f) = fill {
            let (minx, maxx) = pts
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
            let (miny, maxy) = pts
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.1), b.max(p.1)));
            for py in miny.floor() as i64..=maxy.ceil() as i64 {
                for px in minx.floor() as i64..=maxx.ceil() as i64 {
                    let (x, y) = (px as f64 + 0.5, py as f64 + 0.5);
                    let mut inside = false;
                    for i in 0..pts.len() {
                        let (a, b) = (pts[i], pts[(i + 1) % pts.len()]);
                        if (a.1 > y) != (b.1 > y) && x < a.0 + (y - a.1) * (b.0 - a.0) / (b.1 - a.1)
                        {
                            inside = !inside;
                        }
                    }
                    if inside {
                        self.blend(px, py, f, 1.0);
                    }
                }
            }
        }
        if let Some(s) = stroke {
            for i in 0..pts.len() {
                let (a, b) = (pts[i], pts[(i + 1) % pts.len()]);
                self.segment(a.0, a.1, b.0, b.1, s, 1.5);
            }
        }
    }

    fn text(&mut self, x: f64, y: f64, size: f64, anchor: Anchor, c: Color, text: &str) {
        let scale = (size / 8.0).round().max(1.0) as i64;
        let w = text.chars().count() as i64 * 8 * scale;
        let x0 = match anchor {
            Anchor::Start => x.round() as i64,
            Anchor::Middle => x.round() as i64 - w / 2,
            Anchor::End => x.round() as i64 - w,
        };
        // y is the baseline, as in SVG: glyph rows 0..7 sit above it (row 7 is the descender).
        let y0 = y.round() as i64 - 7 * scale;
        for (k, ch) in text.chars().enumerate() {
            let Some(glyph) = font8x8::BASIC_FONTS
                .get(ch)
                .or_else(|| font8x8::LATIN_FONTS.get(ch))
            else {
                continue;
            };
            for (row, bits) in glyph.iter().enumerate() {
                for col in 0..8 {
                    if bits & (1 << col) != 0 {
                        for sy in 0..scale {
                            for sx in 0..scale {
                                self.blend(
                                    x0 + (k as i64 * 8 + col) * scale + sx,
                                    y0 + row as i64 * scale + sy,
                                    c,
                                    1.0,
                                );
                            }
                        }
                    }
                }
            }
        }
    }

    /// Draw a figure's shapes.
    pub fn draw(&mut self, fig: &Figure) {
        for shape in &fig.shapes {
            match shape {
                Shape::Rect {
                    x,
                    y,
                    w,
                    h,
                    fill,
                    stroke,
                } => {
                    if let Some(f) = fill {
                        self.fill_rect(*x, *y, *w, *h, *f);
                    }
                    if let Some(s) = stroke {
                        for (a, b, c, d) in [
                            (x, y, x + w, *y),
                            (&(x + w), y, x + w, y + h),
                            (x, &(y + h), x + w, y + h),
                            (x, y, *x, y + h),
                        ] {
                            self.segment(*a, *b, c, d, *s, 1.0);
                        }
                    }
                }
                Shape::Line {
                    x1,
                    y1,
                    x2,
                    y2,
                    color,
                    width,
                    dash,
                } => self.line(*x1, *y1, *x2, *y2, *color, *width, *dash),
                Shape::Circle {
                    cx,
                    cy,
                    r,
                    fill,
                    stroke,
                } => self.circle(*cx, *cy, *r, *fill, *stroke),
                Shape::Polygon {
                    points,
                    fill,
                    stroke,
                } => self.polygon(points, *fill, *stroke),
                Shape::Text {
                    x,
                    y,
                    size,
                    anchor,
                    color,
                    text,
                } => self.text(*x, *y, *size, *anchor, *color, text),
                Shape::Image {
                    x,
                    y,
                    w,
                    h,
                    cols,
                    rows,
                    rgb,
                } => {
                    let (cw, ch) = (w / *cols as f64, h / *rows as f64);
                    for (k, c) in rgb.iter().enumerate() {
                        let (i, j) = ((k % cols) as f64, (k / cols) as f64);
                        let (px0, py0) = ((x + i * cw).round() as i64, (y + j * ch).round() as i64);
                        let (px1, py1) = (
                            (x + (i + 1.0) * cw).round() as i64,
                            (y + (j + 1.0) * ch).round() as i64,
                        );
                        for py in py0..py1.max(py0 + 1) {
                            for px in px0..px1.max(px0 + 1) {
                                self.blend(px, py, *c, 1.0);
                            }
                        }
                    }
                }
            }
        }
    }

    /// PNG bytes (8-bit RGB).
    pub fn to_png(&self) -> Vec<u8> {
        let mut out = Vec::new();
        {
            let mut enc = png::Encoder::new(&mut out, self.width, self.height);
            enc.set_color(png::ColorType::Rgb);
            enc.set_depth(png::BitDepth::Eight);
            let mut w = enc.write_header().expect("png header");
            w.write_image_data(&self.rgb).expect("png data");
        }
        out
    }
}

impl Figure {
    /// The figure rendered to pixels.
    pub fn rasterize(&self) -> Raster {
        let mut r = Raster::new(self.width, self.height, Color::WHITE);
        r.draw(self);
        r
    }
}

/// An animated GIF of equally sized frames, `delay_cs` hundredths of a second apart.
pub fn gif(frames: &[Raster], delay_cs: u16) -> Result<Vec<u8>, String> {
    let first = frames.first().ok_or("no frames")?;
    let (w, h) = (first.width as u16, first.height as u16);
    let mut out = Vec::new();
    {
        let mut enc = gif::Encoder::new(&mut out, w, h, &[]).map_err(|e| e.to_string())?;
        enc.set_repeat(gif::Repeat::Infinite)
            .map_err(|e| e.to_string())?;
        for f in frames {
            let mut frame = gif::Frame::from_rgb_speed(w, h, &f.rgb, 10);
            frame.delay = delay_cs;
            enc.write_frame(&frame).map_err(|e| e.to_string())?;
        }
    }
    Ok(out)
}
