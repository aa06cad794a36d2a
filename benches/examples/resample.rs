//! Writes the public `rt-plunger` example resampled to N samples (linear interpolation) into
//! DIR: `cargo run --release -p geodesic-benches --example resample -- 1000000 target/m35`,
//! then `geodesic fit target/m35/rt-plunger-1000000.yaml --effects piezo` (issue 35: the
//! million-row fit the `fit_long` benchmark times).

fn main() {
    let mut args = std::env::args().skip(1);
    let n: usize = args
        .next()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let dir = std::path::PathBuf::from(args.next().unwrap_or_else(|| ".".into()));
    match geodesic_benches::resample_rt_plunger(n, &dir) {
        Ok(p) => println!("{}", p.display()),
        Err(e) => {
            eprintln!("resample: {e}");
            std::process::exit(2);
        }
    }
}
