//! Full benchmark run: `cargo run --release -p pdbem-pd --features bench --example bench_full`.
//! `--quick` for the smoke-test sizes; `--parts` measures only the cases
//! given as `plate:N:NE[:REPEATS]` or `tpb:NX:NY:NE[:REPEATS]` and prints
//! each as it finishes.
use pdbem_pd::bench::{compare, run_bench, table, BenchOptions, BenchReport};
use pdbem_pd::cases::{plate_hole, three_point_bend};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.iter().any(|a| a == "--parts") {
        for a in args.iter().filter(|a| a.contains(':')) {
            let f: Vec<usize> = a.split(':').skip(1).map(|v| v.parse().unwrap()).collect();
            let r = if a.starts_with("plate") {
                compare(
                    &plate_hole(f[0]),
                    f[1],
                    0.025,
                    f.get(2).copied().unwrap_or(1),
                )
            } else {
                compare(
                    &three_point_bend(f[0], f[1]),
                    f[2],
                    0.03,
                    f.get(3).copied().unwrap_or(1),
                )
            };
            let report = BenchReport {
                threads: rayon::current_num_threads(),
                protocol: pdbem_pd::bench::protocol(),
                kernel: Vec::new(),
                switching: vec![r],
                branching: Vec::new(),
                refined_ramp: None,
            };
            print!("{}", table(&report));
        }
        return;
    }
    let quick = args.iter().any(|a| a == "--quick");
    print!("{}", table(&run_bench(BenchOptions { quick })));
}
