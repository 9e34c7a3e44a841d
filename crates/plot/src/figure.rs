//! A figure as a list of shapes in pixel coordinates (y down), rendered to SVG or to a raster.

use std::fmt::Write as _;

/// The family name the SVG asks for (the renderer embeds this font).
pub const FONT_FAMILY: &str = "DejaVu Sans";

use base64::engine::general_purpose::STANDARD as B64;
use base64::Engine;

/// An RGB colour.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Color(pub u8, pub u8, pub u8);

impl Color {
    pub const BLACK: Color = Color(0, 0, 0);
    pub const WHITE: Color = Color(255, 255, 255);
    pub const GREY: Color = Color(150, 150, 150);
    pub const LIGHT: Color = Color(225, 225, 225);
    pub const RED: Color = Color(200, 30, 30);
    pub const BLUE: Color = Color(30, 70, 200);
    pub const CYAN: Color = Color(0, 170, 200);
    pub const GREEN: Color = Color(20, 140, 60);
    pub const ORANGE: Color = Color(230, 120, 0);

    pub fn hex(self) -> String {
        format!("#{:02x}{:02x}{:02x}", self.0, self.1, self.2)
    }

    /// Linear mix: t = 0 gives self, t = 1 gives other.
    pub fn mix(self, other: Color, t: f64) -> Color {
        let t = t.clamp(0.0, 1.0);
        let m = |a: u8, b: u8| (a as f64 + (b as f64 - a as f64) * t).round() as u8;
        Color(m(self.0, other.0), m(self.1, other.1), m(self.2, other.2))
    }
}

/// A perceptually ordered map of [0, 1] (viridis, by five stops).
pub fn viridis(t: f64) -> Color {
    const STOPS: [Color; 5] = [
        Color(68, 1, 84),
        Color(59, 82, 139),
        Color(33, 145, 140),
        Color(94, 201, 98),
        Color(253, 231, 37),
    ];
    if !t.is_finite() {
        return Color::LIGHT;
    }
    let x = t.clamp(0.0, 1.0) * 4.0;
    let i = (x.floor() as usize).min(3);
    STOPS[i].mix(STOPS[i + 1], x - i as f64)
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Anchor {
    Start,
    Middle,
    End,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    Rect {
        x: f64,
        y: f64,
        w: f64,
        h: f64,
        fill: Option<Color>,
        stroke: Option<Color>,
    },
    Line {
        x1: f64,
        y1: f64,
        x2: f64,
        y2: f64,
        color: Color,
        width: f64,
        dash: Option<f64>,
    },
    Circle {
        cx: f64,
        cy: f64,
        r: f64,
        fill: Option<Color>,
        stroke: Option<Color>,
    },
    Polygon {
        points: Vec<(f64, f64)>,
        fill: Option<Color>,
        stroke: Option<Color>,
    },
    /// Text at (x, y) (the baseline), with `_{sub}` and `^{sup}` markup, turned `rotate`
    /// degrees about (x, y) (-90: reading upwards).
    Text {
        x: f64,
        y: f64,
        size: f64,
        anchor: Anchor,
        color: Color,
        text: String,
        rotate: f64,
    },
    /// Shapes that belong together under a tooltip (`<title>` in the SVG: a point's counts).
    Group { title: String, shapes: Vec<Shape> },
    /// A block of pixels (row-major RGB, top row first), scaled to `w x h` at (x, y) without
    /// smoothing (an embedded PNG in the SVG).
    Image {
        x: f64,
        y: f64,
        w: f64,
        h: f64,
        cols: usize,
        rows: usize,
        rgb: Vec<Color>,
    },
}

/// A figure of `width x height` pixels on a white background.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    pub width: u32,
    pub height: u32,
    pub shapes: Vec<Shape>,
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn paint(fill: Option<Color>, stroke: Option<Color>) -> String {
    format!(
        "fill=\"{}\" stroke=\"{}\"",
        fill.map_or("none".into(), Color::hex),
        stroke.map_or("none".into(), Color::hex)
    )
}

impl Figure {
    pub fn new(width: u32, height: u32) -> Self {
        Figure {
            width,
            height,
            shapes: Vec::new(),
        }
    }

    pub fn push(&mut self, s: Shape) {
        self.shapes.push(s);
    }

    pub fn text(&mut self, x: f64, y: f64, size: f64, anchor: Anchor, text: impl Into<String>) {
        self.push(Shape::Text {
            x,
            y,
            size,
            anchor,
            color: Color::BLACK,
            text: text.into(),
            rotate: 0.0,
        });
    }

    /// Text reading upwards (an axis label on the left).
    pub fn vtext(&mut self, x: f64, y: f64, size: f64, text: impl Into<String>) {
        self.push(Shape::Text {
            x,
            y,
            size,
            anchor: Anchor::Middle,
            color: Color::BLACK,
            text: text.into(),
            rotate: -90.0,
        });
    }

    pub fn line(&mut self, x1: f64, y1: f64, x2: f64, y2: f64, color: Color, width: f64) {
        self.push(Shape::Line {
            x1,
            y1,
            x2,
            y2,
            color,
            width,
            dash: None,
        });
    }

    /// The figure as an SVG document (text in DejaVu Sans, which the PNG renderer embeds).
    pub fn to_svg(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" font-family=\"{font}, sans-serif\">",
            w = self.width,
            h = self.height,
            font = FONT_FAMILY,
        );
        let _ = writeln!(
            s,
            "<rect x=\"0\" y=\"0\" width=\"{}\" height=\"{}\" fill=\"#ffffff\"/>",
            self.width, self.height
        );
        for shape in &self.shapes {
            write_shape(&mut s, shape);
        }
        s.push_str("</svg>\n");
        s
    }
}

/// Label text with `_{sub}` and `^{sup}` as SVG tspans, the rest escaped; `_x` and `^x` take
/// one character.
pub fn text_markup(text: &str, size: f64) -> String {
    let mut out = String::new();
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        let shift = match c {
            '_' => "sub",
            '^' => "super",
            _ => {
                out.push_str(&esc(&c.to_string()));
                continue;
            }
        };
        let mut inner = String::new();
        if chars.peek() == Some(&'{') {
            chars.next();
            for d in chars.by_ref() {
                if d == '}' {
                    break;
                }
                inner.push(d);
            }
        } else if let Some(d) = chars.next() {
            inner.push(d);
        }
        let _ = write!(
            out,
            "<tspan baseline-shift=\"{shift}\" font-size=\"{:.1}\">{}</tspan>",
            size * 0.72,
            esc(&inner)
        );
    }
    out
}

fn write_shape(s: &mut String, shape: &Shape) {
    let _ = match shape {
        Shape::Rect { x, y, w, h, fill, stroke } => writeln!(
            s,
            "<rect x=\"{x:.1}\" y=\"{y:.1}\" width=\"{w:.1}\" height=\"{h:.1}\" {}/>",
            paint(*fill, *stroke)
        ),
        Shape::Line { x1, y1, x2, y2, color, width, dash } => writeln!(
            s,
            "<line x1=\"{x1:.1}\" y1=\"{y1:.1}\" x2=\"{x2:.1}\" y2=\"{y2:.1}\" stroke=\"{}\" stroke-width=\"{width}\"{}/>",
            color.hex(),
            dash.map_or(String::new(), |d| format!(" stroke-dasharray=\"{d} {d}\""))
        ),
        Shape::Circle { cx, cy, r, fill, stroke } => writeln!(
            s,
            "<circle cx=\"{cx:.1}\" cy=\"{cy:.1}\" r=\"{r:.1}\" {} stroke-width=\"1.5\"/>",
            paint(*fill, *stroke)
        ),
        Shape::Polygon { points, fill, stroke } => {
            let pts: Vec<String> = points.iter().map(|(x, y)| format!("{x:.1},{y:.1}")).collect();
            writeln!(s, "<polygon points=\"{}\" {} stroke-width=\"1.5\"/>", pts.join(" "), paint(*fill, *stroke))
        }
        Shape::Text { x, y, size, anchor, color, text, rotate } => writeln!(
            s,
            "<text x=\"{x:.1}\" y=\"{y:.1}\" font-size=\"{size}\" fill=\"{}\" text-anchor=\"{}\"{}>{}</text>",
            color.hex(),
            match anchor {
                Anchor::Start => "start",
                Anchor::Middle => "middle",
                Anchor::End => "end",
            },
            if *rotate != 0.0 {
                format!(" transform=\"rotate({rotate} {x:.1} {y:.1})\"")
            } else {
                String::new()
            },
            text_markup(text, *size)
        ),
        Shape::Group { title, shapes } => {
            let _ = writeln!(s, "<g><title>{}</title>", esc(title));
            for inner in shapes {
                write_shape(s, inner);
            }
            writeln!(s, "</g>")
        }
        Shape::Image { x, y, w, h, cols, rows, rgb } => {
            let bytes: Vec<u8> = rgb.iter().flat_map(|c| [c.0, c.1, c.2]).collect();
            match crate::raster::encode_png(*cols as u32, *rows as u32, &bytes) {
                Ok(png) => writeln!(
                    s,
                    "<image x=\"{x:.1}\" y=\"{y:.1}\" width=\"{w:.1}\" height=\"{h:.1}\" preserveAspectRatio=\"none\" image-rendering=\"optimizeSpeed\" style=\"image-rendering:pixelated\" href=\"data:image/png;base64,{}\"/>",
                    B64.encode(png)
                ),
                // A block that cannot be encoded (0 pixels) draws nothing.
                Err(_) => Ok(()),
            }
        }
    };
}
