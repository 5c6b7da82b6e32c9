//! Full benchmark run: `cargo run --release -p pdbem-pd --example bench_full`.
fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let r = pdbem_pd::bench::run_bench(pdbem_pd::bench::BenchOptions { quick });
    println!("{r:#?}");
}
