//! Snapshots of a collision: both cells' phi (cell 1 red, cell 2 blue) with their 0.5 contours
//! and the fibers, above the polarity field (positive red, negative blue).

use crate::figure::Color;
use crate::raster::Raster;

/// The fields of one instant on an `nx x ny` lattice (row-major, y up).
pub struct Snapshot<'a> {
    pub nx: usize,
    pub ny: usize,
    pub phi: [&'a [f64]; 2],
    pub p: [&'a [f64]; 2],
    pub fiber_rows: &'a [usize],
    pub caption: String,
}

const HEADER: u32 = 24;

/// Render with `scale` pixels per lattice site: phi panel above, polarity panel below.
pub fn render(s: &Snapshot, scale: u32) -> Raster {
    let (w, h) = (s.nx as u32 * scale, s.ny as u32 * scale);
    let mut r = Raster::new(w, 2 * h + HEADER + 4, Color::WHITE);
    let pmax =
        s.p.iter()
            .flat_map(|f| f.iter())
            .fold(0.0f64, |m, v| m.max(v.abs()))
            .max(1e-9);
    let is_fiber = |j: usize| s.fiber_rows.contains(&j);
    for j in 0..s.ny {
        for i in 0..s.nx {
            let k = j * s.nx + i;
            let (a, b) = (s.phi[0][k].clamp(0.0, 1.0), s.phi[1][k].clamp(0.0, 1.0));
            let mut c = Color::WHITE
                .mix(Color(215, 40, 40), a * 0.85)
                .mix(Color(40, 70, 215), b * 0.85);
            if is_fiber(j) {
                c = c.mix(Color(60, 60, 60), 0.55);
            }
            // The 0.5 contour: phi crosses 0.5 towards the right or upper neighbour.
            let right = j * s.nx + (i + 1) % s.nx;
            let up = ((j + 1) % s.ny) * s.nx + i;
            for f in s.phi {
                if (f[k] - 0.5) * (f[right] - 0.5) <= 0.0 && f[k] != f[right]
                    || (f[k] - 0.5) * (f[up] - 0.5) <= 0.0 && f[k] != f[up]
                {
                    c = Color::BLACK;
                }
            }
            let pv = (s.p[0][k] + s.p[1][k]) / pmax;
            let mut q = if pv >= 0.0 {
                Color::WHITE.mix(Color(200, 20, 20), pv)
            } else {
                Color::WHITE.mix(Color(20, 50, 200), -pv)
            };
            if is_fiber(j) {
                q = q.mix(Color(60, 60, 60), 0.35);
            }
            // y up: lattice row j is drawn from the bottom.
            let py = (s.ny - 1 - j) as u32 * scale;
            for dy in 0..scale {
                for dx in 0..scale {
                    r.blend(
                        (i as u32 * scale + dx) as i64,
                        (HEADER + py + dy) as i64,
                        c,
                        1.0,
                    );
                    r.blend(
                        (i as u32 * scale + dx) as i64,
                        (HEADER + 4 + h + py + dy) as i64,
                        q,
                        1.0,
                    );
                }
            }
        }
    }
    let mut cap = crate::figure::Figure::new(w, 2 * h + HEADER + 4);
    cap.text(
        6.0,
        17.0,
        16.0,
        crate::figure::Anchor::Start,
        s.caption.clone(),
    );
    r.draw(&cap);
    r
}
