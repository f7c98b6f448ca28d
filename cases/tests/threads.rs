//! Results are bitwise identical for any thread count (docs/DESIGN.md §5).

use meshmove::{Method, Mode, Options, Solver};
use meshmove_cases::setups::free_surface_case;

#[test]
fn one_and_two_threads_agree_bitwise() {
    let case = free_surface_case("threads", 1.0 / 96.0, 0.1, 1);
    let (mesh, bcs, motion) = (&case.mesh, &case.bcs, &case.motion);
    assert!(mesh.num_vertices() > 8000, "mesh large enough for the parallel paths");
    for method in [Method::Biharmonic, Method::Laplacian] {
        for mode in [Mode::Default, Mode::PaperFaithful] {
            let run = |threads| {
                let mut o = Options { method, threads, ..Default::default() };
                o.solve.mode = mode;
                // The paper's stationary cycle is slow on the re-referenced step: a looser
                // tolerance keeps it short (an unconverged step is an error).
                o.solve.tol = if mode == Mode::Default { 1e-6 } else { 1e-4 };
                o.solve.max_cycles = 2000;
                let mut s = Solver::new(mesh, bcs, o).unwrap();
                let d = s.solve(motion).unwrap().displacement;
                s.move_in_steps(motion, 2).unwrap();
                (d, s.mesh().coords().to_vec())
            };
            let (a, b) = (run(1), run(2));
            assert!(
                a.0.len() == b.0.len() && a.0.iter().zip(&b.0).all(|(p, q)| p.to_bits() == q.to_bits()),
                "{method:?} {mode:?}"
            );
            assert!(
                a.1.len() == b.1.len() && a.1.iter().zip(&b.1).all(|(p, q)| p.to_bits() == q.to_bits()),
                "{method:?} {mode:?} steps"
            );
        }
    }
}

/// Ten steps by `Solver::advance`, some of whose re-references keep the coarse levels of an
/// earlier one: bitwise the same positions with one and two threads, and the same choices.
#[test]
fn ten_advanced_steps_agree_bitwise_on_one_and_two_threads() {
    let case = free_surface_case("threads", 1.0 / 96.0, 0.1, 1);
    let (mesh, bcs, motion) = (&case.mesh, &case.bcs, &case.motion);
    for method in [Method::Biharmonic, Method::Laplacian] {
        let run = |threads| {
            let mut s = Solver::new(mesh, bcs, Options { method, threads, ..Default::default() }).unwrap();
            let mut kept = Vec::new();
            for i in 0..10 {
                s.advance(&motion.increment(i, 10)).unwrap();
                kept.push(s.phases().coarse_kept);
            }
            (s.mesh().coords().to_vec(), kept)
        };
        let (a, b) = (run(1), run(2));
        assert!(a.0.iter().zip(&b.0).all(|(p, q)| p.to_bits() == q.to_bits()), "{method:?}");
        assert_eq!(a.1, b.1, "{method:?}");
        assert!(a.1.iter().any(|&k| k), "{method:?}: some re-reference keeps the coarse levels: {:?}", a.1);
    }
}
