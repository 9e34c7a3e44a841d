//! The pictures are valid SVG, PNG and GIF files with the expected elements.

use cellsweep_plot::frames::{figure, Snapshot};
use cellsweep_plot::mark::Label;
use cellsweep_plot::phase::{diagram_figure, BetaLine, Diagram, Point};
use cellsweep_plot::{gif, Color};

fn diagram() -> Diagram {
    let mut points = Vec::new();
    for (k, mark) in Label::ALL.into_iter().enumerate() {
        points.push(Point {
            x: 0.1 + 0.02 * (k % 4) as f64,
            y: 10.0 + 4.0 * (k / 4) as f64,
            mark: Some(mark),
            freq: [0.2, 0.7, 0.1],
            n: 96,
            open: k == 0,
            boxed: k == 1,
            detail: format!("point {k}: n = 96 & <counts>"),
        });
    }
    Diagram {
        axes: Diagram::paper_axes(),
        title: "test".into(),
        points,
        lines: vec![BetaLine {
            label: "paper".into(),
            color: Color::BLACK,
            slope: 100.0,
            intercept: 0.0,
        }],
    }
}

#[test]
fn phase_diagrams_are_valid_svg_with_symbols_heat_maps_and_dashed_lines() {
    let fig = diagram_figure(&diagram());
    let svg = fig.to_svg();
    assert!(svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\""));
    assert!(svg.trim_end().ends_with("</svg>"));
    // Every element is closed (a crude well-formedness check: one tag per line).
    for line in svg.lines().skip(1) {
        assert!(
            line.ends_with("/>")
                || line.ends_with("</text>")
                || line.ends_with("</title>")
                || line == "</g>"
                || line == "</svg>",
            "{line}"
        );
    }
    assert!(svg.contains("<polygon"), "stars and diamonds are polygons");
    assert!(
        svg.contains("stroke-dasharray"),
        "beta_crit lines are dashed"
    );
    for name in [
        "walk-past",
        "training",
        "reversal",
        "coexistence",
        "unstable",
        "breakup",
        "box-limited (SPEC 4.5)",
    ] {
        assert!(svg.contains(name), "legend names {name}");
    }
    for title in [
        "(a) outcome",
        "(b) training",
        "(c) walk-past",
        "(d) reversal",
    ] {
        assert!(svg.contains(title));
    }
    // 8 points x 3 heat maps at least.
    assert!(svg.matches("<rect").count() >= 24);
    // Every point carries its counts as a tooltip, escaped, in each of the four panels.
    assert_eq!(svg.matches("<title>point ").count(), 4 * 8);
    assert!(svg.contains("<title>point 0: n = 96 &amp; &lt;counts&gt;</title>"));
    // Greek axis labels and a subscripted label.
    assert!(svg.contains(">α</text>") && svg.contains(">β</text>"));
}

#[test]
fn phase_diagrams_rasterize_to_valid_png() {
    let fig = diagram_figure(&diagram());
    let png = fig.to_png(2.0).unwrap();
    let decoder = png::Decoder::new(std::io::Cursor::new(&png));
    let reader = decoder.read_info().unwrap();
    let info = reader.info();
    assert_eq!((info.width, info.height), (2 * fig.width, 2 * fig.height));
    // Not blank: some pixels are coloured.
    let r = fig.rasterize(1.0).unwrap();
    assert!(r.rgb.chunks(3).any(|p| p[0] != p[1] || p[1] != p[2]));
}

#[test]
fn snapshots_render_and_animate() {
    let (nx, ny) = (40, 20);
    let blob = |cx: f64| -> Vec<f64> {
        (0..nx * ny)
            .map(|k| {
                let (i, j) = ((k % nx) as f64, (k / nx) as f64);
                let r = ((i - cx).powi(2) + (j - 10.0).powi(2)).sqrt();
                0.5 + 0.5 * ((6.0 - r) / 2.0).tanh()
            })
            .collect()
    };
    let (a, b, p) = (blob(10.0), blob(30.0), vec![0.3; nx * ny]);
    let rows = [9, 10];
    let snap = Snapshot {
        nx,
        ny,
        phi: [&a, &b],
        p: [&p, &p],
        fiber_rows: &rows,
        time: 12.0,
        note: String::new(),
    };
    let fig = figure(&snap);
    let svg = fig.to_svg();
    assert!(
        svg.contains("data:image/png;base64,"),
        "fields as embedded PNG"
    );
    assert!(
        svg.contains("10 µm") && svg.contains("6 min"),
        "scale bar, time in minutes"
    );
    let r = fig.rasterize(2.0).unwrap();
    assert_eq!(r.width, 2 * fig.width);
    // The 0.5 contour is drawn in black, inside the embedded field image.
    assert!(r.rgb.chunks(3).any(|px| px == [0, 0, 0]));
    let frame = || fig.rasterize(1.0).unwrap();
    let g = gif(&[frame(), frame()], 20).unwrap();
    assert_eq!(&g[..6], b"GIF89a");
}

/// Grey cells are named for what they are: a point its prep decided, or one not run yet
/// (a live page's diagram before its first results; issue 50, 6).
#[test]
fn the_legend_names_grey_cells_for_what_they_are() {
    let grey = |mark: Option<Label>| Point {
        x: 0.1,
        y: 10.0,
        mark,
        freq: [f64::NAN; 3],
        n: 0,
        open: false,
        boxed: false,
        detail: String::new(),
    };
    let with = |points: Vec<Point>| {
        diagram_figure(&Diagram {
            axes: Diagram::paper_axes(),
            title: "t".into(),
            points,
            lines: vec![],
        })
        .to_svg()
    };
    let waiting = with(vec![grey(None)]);
    assert!(waiting.contains(">not run yet</text>"), "{waiting}");
    assert!(!waiting.contains("prep unstable"));
    let decided = with(vec![grey(Some(Label::Unstable))]);
    assert!(decided.contains("no collision (prep unstable or broke up)"));
    assert!(!decided.contains("not run yet"));
    let both = with(vec![grey(Some(Label::Breakup)), grey(None)]);
    assert!(both.contains("or not run yet"));
}

/// A refined column (values a few tenths apart, in one column) keeps a legible axis: ticks and
/// labels at the grid's betas only, the added values small and named in the legend (issue
/// 50, 6: "17.75, 28.5, 40.375" piled up among the labels).
#[test]
fn refined_columns_keep_the_beta_axis_to_the_grid() {
    let mut points = Vec::new();
    let mark = |x: f64, y: f64| Point {
        x,
        y,
        mark: Some(Label::Train),
        freq: [1.0, 0.0, 0.0],
        n: 16,
        open: false,
        boxed: false,
        detail: String::new(),
    };
    for alpha in [0.1, 0.12, 0.14] {
        for k in 0..11 {
            points.push(mark(alpha, 10.0 + 4.0 * k as f64));
        }
    }
    for beta in [17.75, 17.875, 28.5, 40.375] {
        points.push(mark(0.12, beta));
    }
    let svg = diagram_figure(&Diagram {
        axes: Diagram::paper_axes(),
        title: "t".into(),
        points,
        lines: vec![],
    })
    .to_svg();
    for added in ["17.75", "17.875", "28.5", "40.375"] {
        assert!(
            !svg.contains(&format!(">{added}</text>")),
            "{added} labelled"
        );
    }
    for grid in ["10", "30", "50"] {
        assert!(
            svg.contains(&format!(">{grid}</text>")),
            "{grid} not labelled"
        );
    }
    assert!(svg.contains("small marks: beta values a refinement added"));
}
