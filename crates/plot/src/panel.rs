//! The geometry shared by the figures: a data rectangle in pixels with its frame and ticks
//! (the one drawer of every figure's axes), axis ranges, round ticks, the clipping of a line,
//! and the width of a label.

use crate::figure::{Anchor, Color, Figure, Shape};

/// The distinct values, sorted.
pub(crate) fn axis(v: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut a: Vec<f64> = v.collect();
    a.sort_by(|x, y| x.total_cmp(y));
    a.dedup();
    a
}

/// Data range with half a grid step of room on each side.
pub(crate) fn span(values: &[f64]) -> (f64, f64) {
    let (lo, hi) = (values[0], values[values.len() - 1]);
    // The widest gap: an even grid's step, and a refined axis keeps its grid's margins.
    let step = if values.len() > 1 {
        values.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max)
    } else {
        lo.abs().max(1.0) * 0.2
    };
    (lo - step / 2.0, hi + step / 2.0)
}

/// Clip the segment of y = m x + c over [x0, x1] to y in [y0, y1].
pub(crate) fn clip(
    m: f64,
    c: f64,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> Option<((f64, f64), (f64, f64))> {
    let (mut a, mut b) = (x0, x1);
    if m.abs() < 1e-300 {
        return (c >= y0 && c <= y1).then_some(((x0, c), (x1, c)));
    }
    let (xa, xb) = ((y0 - c) / m, (y1 - c) / m);
    let (lo, hi) = (xa.min(xb), xa.max(xb));
    a = a.max(lo);
    b = b.min(hi);
    (a < b).then_some(((a, m * a + c), (b, m * b + c)))
}

/// A rectangle of the figure that maps data (a, b) to pixels: `ax` along x, `by` up.
pub(crate) struct Panel {
    pub x: f64,
    pub y: f64,
    pub w: f64,
    pub h: f64,
    pub ax: (f64, f64),
    pub by: (f64, f64),
}

impl Panel {
    pub fn px(&self, alpha: f64) -> f64 {
        self.x + (alpha - self.ax.0) / (self.ax.1 - self.ax.0) * self.w
    }
    pub fn py(&self, beta: f64) -> f64 {
        self.y + self.h - (beta - self.by.0) / (self.by.1 - self.by.0) * self.h
    }

    /// The panel's outline, in black.
    pub fn frame(&self, fig: &mut Figure) {
        fig.push(Shape::Rect {
            x: self.x,
            y: self.y,
            w: self.w,
            h: self.h,
            fill: None,
            stroke: Some(Color::BLACK),
        });
    }

    /// A tick below the panel at `v` along x, with its value when `labelled`.
    pub fn x_tick(&self, fig: &mut Figure, v: f64, labelled: bool) {
        let (x, bottom) = (self.px(v), self.y + self.h);
        fig.line(x, bottom, x, bottom + 5.0, Color::BLACK, 1.0);
        if labelled {
            fig.text(x, bottom + 19.0, 12.0, Anchor::Middle, format!("{v}"));
        }
    }

    /// A tick left of the panel at `v` up the y axis, with its value when `labelled`.
    pub fn y_tick(&self, fig: &mut Figure, v: f64, labelled: bool) {
        let y = self.py(v);
        fig.line(self.x - 5.0, y, self.x, y, Color::BLACK, 1.0);
        if labelled {
            fig.text(self.x - 8.0, y + 4.0, 12.0, Anchor::End, format!("{v}"));
        }
    }

    /// The outline and round, labelled ticks on both axes (at most about `nx` across and `ny`
    /// up, [`nice_ticks`]).
    pub fn frame_with_round_ticks(&self, fig: &mut Figure, nx: usize, ny: usize) {
        self.frame(fig);
        for v in nice_ticks(self.ax.0, self.ax.1, nx) {
            self.x_tick(fig, v, true);
        }
        for v in nice_ticks(self.by.0, self.by.1, ny) {
            self.y_tick(fig, v, true);
        }
    }
}

/// Round tick values covering [lo, hi]: steps of 1, 2 or 5 times a power of ten, at most
/// about `max` of them.
pub fn nice_ticks(lo: f64, hi: f64, max: usize) -> Vec<f64> {
    if !(lo.is_finite() && hi.is_finite()) || hi <= lo || max == 0 {
        return vec![lo];
    }
    let raw = (hi - lo) / max as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last)
        .map(|k| {
            let v = k as f64 * step;
            // Shed the float noise of k x step (0.30000000000000004).
            format!("{v:.10}").parse().unwrap_or(v)
        })
        .collect()
}

/// Width in pixels of `text` at font size `size` (DejaVu Sans averages about 0.6 em).
pub(crate) fn text_width(text: &str, size: f64) -> f64 {
    0.6 * size
        * text
            .chars()
            .filter(|c| !matches!(c, '_' | '{' | '}'))
            .count() as f64
}

#[cfg(test)]
mod tests {
    use super::nice_ticks;

    #[test]
    fn ticks_are_round() {
        assert_eq!(nice_ticks(0.0, 0.76, 6), vec![0.0, 0.2, 0.4, 0.6]);
        assert_eq!(nice_ticks(8.0, 52.0, 8), vec![10.0, 20.0, 30.0, 40.0, 50.0]);
        assert_eq!(nice_ticks(0.0, 1.0, 4), vec![0.0, 0.5, 1.0]);
    }
}
