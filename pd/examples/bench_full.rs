//! Full benchmark run: `cargo run --release -p pdbem-pd --example bench_full`.
//! `--quick` for the smoke-test sizes; `--parts` prints each measurement as
//! it finishes (kernel sizes, then the switching cases given as
//! `plate:N:NE` or `tpb:NX:NY:NE`).
fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.iter().any(|a| a == "--parts") {
        for n in [19, 60, 189] {
            println!("{:?}", pdbem_pd::bench::kernel(n, 1.0));
        }
        for a in args.iter().filter(|a| a.contains(':')) {
            let f: Vec<&str> = a.split(':').collect();
            let num = |i: usize| f[i].parse::<usize>().unwrap();
            let case = match f[0] {
                "plate" => {
                    let mut c = pdbem_pd::cases::plate_hole(num(1));
                    c.explicit_steps = num(2);
                    c
                }
                _ => {
                    let mut c = pdbem_pd::cases::three_point_bend(num(1), num(2));
                    c.explicit_steps = num(3);
                    c
                }
            };
            println!("{:?}", pdbem_pd::bench::compare(case));
        }
        return;
    }
    let quick = args.iter().any(|a| a == "--quick");
    let r = pdbem_pd::bench::run_bench(pdbem_pd::bench::BenchOptions { quick });
    println!("{r:#?}");
}
