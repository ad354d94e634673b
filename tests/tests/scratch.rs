use taut_core::nusd::surface::*;
use taut_tests::*;
#[test]
fn scratch() {
    for (name, cage) in [("cube", cube()), ("prism", prism(5, 300.0, 300.0)), ("grid", grid(4, 3, 1.0, |x, y| (x * 0.7).sin() + 0.3 * y * y))] {
        for tol in [1e-3, 1e-6] {
            let doc = document(cage.clone(), 3, tol);
            let mut s = SurfaceSolver::new(&doc).unwrap();
            let t = std::time::Instant::now();
            let reps = s.solve().unwrap();
            println!("{name} tol {tol}: {:?} {:?}", t.elapsed(), reps.iter().map(|r| (r.iterations, r.last_step, r.remaining, r.converged)).collect::<Vec<_>>());
            s.surface().validate().unwrap();
            let p = s.surface_positions();
            println!("  v0 {:?} max|p| {}", p[0], p.iter().map(|q| q.length()).fold(0.0, f64::max));
        }
    }
}
