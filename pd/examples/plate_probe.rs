//! Probe: plate with hole, pure ADR converged per step vs switching.
use pdbem_pd::cases::plate_hole;
use pdbem_pd::solvers::{adr, switching, Convergence};
use pdbem_pd::PdModel;

fn map(m: &PdModel, n: usize) {
    let phi = m.damage();
    let x = m.positions();
    let dx = m.grid().dx;
    let mut grid = vec![vec![' '; n]; n];
    for i in 0..m.n_real() {
        let ix = (x[i][0] / dx) as usize;
        let iy = (x[i][1] / dx) as usize;
        let c = if phi[i] > 0.38 {
            '#'
        } else if phi[i] > 0.1 {
            '+'
        } else if phi[i] > 0.0 {
            '.'
        } else {
            'o'
        };
        grid[iy][ix] = c;
    }
    for row in grid.iter().rev() {
        println!("{}", row.iter().collect::<String>());
    }
}

fn sym(m: &PdModel) -> (f64, usize) {
    let phi = m.damage();
    let x = m.positions();
    let c = 0.025;
    let dx = m.grid().dx;
    let key = |p: [f64; 2]| {
        (
            ((p[0] - c) / dx * 2.0).round() as i64,
            ((p[1] - c) / dx * 2.0).round() as i64,
        )
    };
    let mp: std::collections::HashMap<_, _> =
        (0..m.n_real()).map(|i| (key(x[i]), phi[i])).collect();
    let mut worst: f64 = 0.0;
    let mut cnt = 0;
    for i in 0..m.n_real() {
        let p = x[i];
        let qs = if std::env::var("C2").is_ok() {
            vec![[2.0 * c - p[0], 2.0 * c - p[1]]]
        } else {
            vec![[2.0 * c - p[0], p[1]], [p[0], 2.0 * c - p[1]]]
        };
        for q in qs {
            let v = mp[&key(q)];
            if (v - phi[i]).abs() > 1e-12 {
                cnt += 1;
                if std::env::var("SYMV").is_ok() {
                    println!("mismatch at {:?}: {:.3} vs {:.3}", key(p), phi[i], v);
                }
            }
            worst = worst.max((v - phi[i]).abs());
        }
    }
    (worst, cnt)
}

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let n: usize = a.get(1).and_then(|s| s.parse().ok()).unwrap_or(20);
    let k: usize = a.get(2).and_then(|s| s.parse().ok()).unwrap_or(60);
    let tol: f64 = a.get(3).and_then(|s| s.parse().ok()).unwrap_or(1e-6);
    let disp = a.get(4).map(|s| s == "d").unwrap_or(false);
    let conv = if disp {
        Convergence::Displacement { e0: tol }
    } else {
        Convergence::Residual { tol }
    };
    let case = if std::env::var("TPB").is_ok() {
        pdbem_pd::cases::three_point_bend(4 * n, n)
    } else {
        plate_hole(n)
    };
    let mut ma = PdModel::new(&case.problem).unwrap();
    let p = adr::AdrParams {
        steps: k,
        iters_per_step: None,
        convergence: conv,
        break_during_iterations: std::env::var("BDI").is_ok(),
        ..Default::default()
    };
    let t = std::time::Instant::now();
    let ia = adr::solve(&mut ma, &p).unwrap();
    let ta = t.elapsed().as_secs_f64();
    let mut ms = PdModel::new(&case.problem).unwrap();
    let ps = switching::SwitchingParams {
        implicit_steps: 3,
        explicit_steps: k,
        convergence: conv,
        break_during_iterations: std::env::var("BDI").is_ok(),
        ..Default::default()
    };
    let t = std::time::Instant::now();
    let is = switching::solve(&mut ms, &ps).unwrap();
    let ts = t.elapsed().as_secs_f64();
    for s in &ia.steps {
        if s.broken_bonds > 0 || s.iterations > 1000 {
            println!(
                "ADR {:.4} it {} broken {} smax {:.4}",
                s.load, s.iterations, s.broken_bonds, s.max_stretch
            );
        }
    }
    for s in &is.steps {
        println!(
            "SW {:?} {:.4} it {} broken {} smax {:.4}",
            s.kind, s.load, s.iterations, s.broken_bonds, s.max_stretch
        );
    }
    let diff = ma
        .bond_intact()
        .iter()
        .zip(ms.bond_intact())
        .filter(|(a, b)| a != b)
        .count()
        / 2;
    let (mut d2, mut n2) = (0.0, 0.0);
    for (ua, us) in ma.displacements().iter().zip(ms.displacements()) {
        for c in 0..2 {
            d2 += (ua[c] - us[c]).powi(2);
            n2 += ua[c].powi(2);
        }
    }
    println!("ADR {:.2}s it {} broken {}; SW {:.2}s it {} broken {} (impl {:.2}s fact {:.3}s nfact {}, expl {:.2}s); speedup {:.2}; differing {}; field diff {:.3e}",
        ta, ia.iterations, ma.broken_bonds(), ts, is.iterations, ms.broken_bonds(), is.time_implicit_s, is.time_factorization_s, is.factorizations, is.time_explicit_s, ta / ts, diff, (d2 / n2).sqrt());
    for sp in &is.switch_points {
        println!("switch {:?}", sp);
    }
    println!("phases {}", is.phases.len());
    println!("sym ADR {:?} SW {:?}", sym(&ma), sym(&ms));
    map(&ma, n);
    println!();
    map(&ms, n);
}
