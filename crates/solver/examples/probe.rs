use cellsweep_solver::observables::components;
use cellsweep_solver::*;
fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|s| s.parse().unwrap())
        .collect();
    let params = Params {
        R0: args[0],
        L: args[1] as u32,
        ..Params::default()
    };
    let n = args[2] as usize;
    let lat = Lattice::new(n, n);
    let fibers = Fibers::new(&params, n);
    let mut cell = relax(&params, &lat, &fibers, args[3] as u64, &mut Silent);
    let comps: Vec<usize> = components(&lat, &cell.phi)
        .into_iter()
        .filter(|&c| c >= 10)
        .collect();
    println!(
        "relaxed: S={} ad={:?} comps={:?} max={}",
        cell.sums.area,
        cell.sums.adhesive,
        comps,
        observables::max_of(&cell.phi)
    );
    prep::kick(&lat, &mut cell);
    for k in 0..(args[4] as usize) {
        for _ in 0..500 {
            cell.step(&lat, &fibers, &params, [0.0, 0.0], true);
        }
        let comps: Vec<usize> = components(&lat, &cell.phi)
            .into_iter()
            .filter(|&c| c >= 10)
            .collect();
        println!(
            "t={} S={:.1} ad={:?} comps={:?} max={:.3} x={:.2}",
            k + 1,
            cell.sums.area,
            cell.sums.adhesive,
            comps,
            observables::max_of(&cell.phi),
            lat.centroid_x(&cell.phi)
        );
    }
}
