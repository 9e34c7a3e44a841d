//! Any SPEC parameter as a grid axis: parsed in the axes' three forms, expanded outermost,
//! checked per point, seeded from the point's parameters (so a fixed value and a grid value
//! give the same jobs), and the lattices following R0 where the file gives none.

use cellsweep_scheduler::plan::{job_seed, prep_key, prep_seed};
use cellsweep_scheduler::{plan, Sweep};
use cellsweep_solver::Geometry;

fn parse(grid: &str, rest: &str) -> Result<Sweep, String> {
    let text = format!(
        "name = \"s\"\nseed = 7\nreplicates = 2\n[grid]\nalpha = [0.1, 0.12]\nbeta = [10, 14]\n\
         L = [90]\nsigma = [5]\n{grid}\n{rest}"
    );
    Sweep::parse(&text, "s.toml").map_err(|e| e.to_string())
}

#[test]
fn a_parameter_in_the_grid_gives_the_points_seeds_and_preps_of_it_fixed() {
    let grid = parse("E0 = [1000, 3000]", "").unwrap();
    assert_eq!(grid.grid.others.len(), 1);
    let points = grid.points();
    assert_eq!(points.len(), 8);
    // The other axis is outermost: the first four points are E0 = 1000, in the paper's order.
    assert!(points[..4].iter().all(|p| p.E0 == 1000.0));
    assert!(points[4..].iter().all(|p| p.E0 == 3000.0));
    assert_eq!((points[1].alpha, points[1].beta), (0.1, 14.0));
    assert_eq!(
        grid.axes_of(&points[5]).to_string(),
        "alpha = 0.1, beta = 14, L = 90, sigma = 5, E0 = 3000"
    );

    let fixed = parse("", "[params]\nE0 = 1000").unwrap();
    let (g, f) = (plan(&grid, "g"), plan(&fixed, "f"));
    for (i, p) in fixed.points().iter().enumerate() {
        assert_eq!(&points[i], p);
        for r in 0..2 {
            assert_eq!(g.points[i].jobs[r].seed, f.points[i].jobs[r].seed);
            assert_eq!(job_seed(7, p, r as u32), f.points[i].jobs[r].seed);
        }
        assert_eq!(g.points[i].config, f.points[i].config);
    }
    let ids = |n: &cellsweep_store::NewSweep| -> Vec<(String, u64)> {
        n.preps.iter().map(|p| (p.key.clone(), p.seed)).collect()
    };
    assert_eq!(ids(&g)[..f.preps.len()], ids(&f)[..]);
    // E0 = 3000 is another cell: other preps, other seeds.
    assert_eq!(g.preps.len(), 2 * f.preps.len());
    assert_ne!(g.points[4].jobs[0].seed, g.points[0].jobs[0].seed);
    assert_ne!(
        prep_seed(7, &prep_key(&points[4], &grid.protocol), 0),
        prep_seed(7, &prep_key(&points[0], &grid.protocol), 0)
    );
}

#[test]
fn a_sweep_without_other_axes_keeps_its_definition() {
    let s = parse("", "").unwrap();
    let json = s.canonical_json();
    assert!(
        !json.contains("others") && !json.contains("lattices_follow"),
        "{json}"
    );
    // The order written does not change the sweep; a range and one number work.
    let a = parse(
        "tau = [50, 100]\nE0 = { from = 1000, to = 2000, step = 1000 }",
        "",
    )
    .unwrap();
    let b = parse("E0 = [1000, 2000]\ntau = [50, 100]", "").unwrap();
    assert_eq!(a.canonical_json(), b.canonical_json());
    assert_eq!(a.grid.others[0].name, "E0", "SPEC order: E0 before tau");
    assert_eq!(parse("A = 150", "").unwrap().points().len(), 4);
}

#[test]
fn geometry_is_an_axis_of_names() {
    let s = parse("geometry = [\"one\", \"two\"]", "").unwrap();
    let points = s.points();
    assert_eq!(points.len(), 8);
    assert_eq!(points[0].geometry, Geometry::One);
    assert_eq!(points[4].geometry, Geometry::Two);
    assert!(s
        .axes_of(&points[0])
        .to_string()
        .ends_with("geometry = one"));
    let e = parse("geometry = [\"one\", \"one\"]", "").unwrap_err();
    assert!(e.contains("grid.geometry: one is listed twice"), "{e}");
    let e = parse("geometry = [\"three\"]", "").unwrap_err();
    assert!(
        e.starts_with("s.toml: grid.geometry[0]: unknown variant `three`"),
        "{e}"
    );
    let e = Sweep::parse(
        "name = \"s\"\nseed = 1\ngeometry = \"two\"\n[grid]\nalpha = 0.1\nbeta = 10\nL = 90\nsigma = 5\ngeometry = \"one\"",
        "s.toml",
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("grid.geometry: also set at the top level"),
        "{e}"
    );
}

#[test]
fn bad_other_axes_are_one_line_naming_the_key() {
    let cases = [
        ("radius = [1, 2]", "", "s.toml: grid.radius: unknown parameter (known: alpha, beta, L, sigma, geometry, d, R0,"),
        ("E0 = [1000]", "[params]\nE0 = 2000", "s.toml: grid.E0: also set in [params]"),
        ("E0 = []", "", "s.toml: grid.E0: "),
        ("E0 = [1000, 1000]", "", "s.toml: grid.E0: "),
        ("E0 = \"big\"", "", "s.toml: grid.E0: "),
        ("E0 = [-5]", "", "s.toml: grid.E0: at alpha = 0.1, beta = 10, L = 90, sigma = 5, E0 = -5: "),
        ("dt = [0.002, 0.5]", "", "s.toml: grid.dt: at "),
        ("R0 = [0]", "", "s.toml: grid.R0: at "),
    ];
    for (grid, rest, start) in cases {
        let e = parse(grid, rest).unwrap_err();
        assert!(e.starts_with(start), "{grid} / {rest}: {e}");
        assert_eq!(e.lines().count(), 1, "{e}");
    }
}

#[test]
fn lattices_follow_r0_unless_the_file_gives_them() {
    let s = parse("R0 = [32, 40, 48]", "").unwrap();
    assert!(s.lattices_follow_r0);
    let sides: Vec<[usize; 2]> = s
        .points()
        .iter()
        .step_by(4)
        .map(|p| s.protocol_for(p).single_lattice)
        .collect();
    assert_eq!(sides, vec![[160, 160], [200, 200], [240, 240]]);
    let p = &s.points()[8];
    assert_eq!(s.protocol_for(p).pair_lattice, [480, 240]);
    // The R0 = 40 points are the paper's, lattices and seeds included.
    let paper = parse("", "").unwrap();
    let (g, f) = (plan(&s, "g"), plan(&paper, "f"));
    assert_eq!(g.points[4].config, f.points[0].config);
    assert_eq!(g.points[4].jobs[1].seed, f.points[0].jobs[1].seed);
    // A fixed R0 off the paper's follows too; given lattices stay as given.
    let fixed = parse("", "[params]\nR0 = 31").unwrap();
    assert_eq!(
        fixed.protocol_for(&fixed.points()[0]).single_lattice,
        [156, 156]
    );
    let given = parse("R0 = [32, 48]", "[protocol]\nsingle_lattice = [300, 300]").unwrap();
    assert!(!given.lattices_follow_r0);
    assert_eq!(
        given.protocol_for(&given.points()[0]).single_lattice,
        [300, 300]
    );
    // A lattice too small for the cell is refused at its point.
    let e = parse("R0 = [32, 110]", "[protocol]\nsingle_lattice = [200, 200]").unwrap_err();
    assert!(e.contains("R0 = 110"), "{e}");
}
