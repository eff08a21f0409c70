//! Times the 3D pipeline on a demo, stage by stage, with options from the command line.
//!
//! `cargo run --release -p delmesh --example pipeline3d -- [DEMO] [--alpha A] [--iterations N]
//! [--no-guard] [--no-smoothing] [--no-restoration] [--repeat R]`
//!
//! DEMO is a 3D demo name (`figure9`, the double ellipsoid with automatic points, by default).
//! Prints the last run's summary (Table 2, generation passes, quality, seconds per stage).
//! With `--repeat R` the pipeline runs R times and each stage's best and median seconds are
//! printed, with those of recovery + field points + smoothing (the 0.5 s target for
//! `figure9`) and how many runs met that target: the machine is shared, so one run says
//! little.

use delmesh::demos::mesh3_demo_setup;
use delmesh::mesh3d::mesh_plc3;
use delmesh::smoothing::Smoother3;

fn main() -> Result<(), delmesh::Error> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let name = args
        .first()
        .filter(|a| !a.starts_with("--"))
        .map_or("figure9", String::as_str);
    let (plc, mut options) = mesh3_demo_setup(name)?;
    let value = |flag: &str| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1))
            .and_then(|v| v.parse::<f64>().ok())
    };
    if let (Some(a), Some(g)) = (value("--alpha"), options.generation.as_mut()) {
        g.alpha = a;
    }
    if let Some(n) = value("--iterations") {
        options.smoothing = Some(Smoother3::new().iterations(n as usize));
    }
    if args.iter().any(|a| a == "--no-guard") {
        options.smoothing = options
            .smoothing
            .map(|s| s.dihedral_guard(delmesh::smoothing::DihedralGuard::Off))
            .transpose()?;
    }
    if args.iter().any(|a| a == "--no-smoothing") {
        options.smoothing = None;
    }
    if args.iter().any(|a| a == "--no-restoration") {
        options.delaunay = false;
    }
    let repeat = value("--repeat").map_or(1, |r| r.max(1.0) as usize);
    let mut stages: Vec<(&'static str, Vec<f64>)> = Vec::new();
    let mut three = Vec::new();
    let mut last = None;
    for _ in 0..repeat {
        let run = mesh_plc3(&plc, &options)?;
        for (k, &(name, t)) in run.timings.iter().enumerate() {
            if stages.len() <= k {
                stages.push((name, Vec::new()));
            }
            stages[k].1.push(t);
        }
        let stage = |name: &str| {
            run.timings
                .iter()
                .filter(|t| t.0 == name)
                .map(|t| t.1)
                .sum::<f64>()
        };
        three.push(stage("boundary recovery") + stage("point generation") + stage("smoothing"));
        last = Some(run);
    }
    if let Some(run) = last {
        print!("{}", run.summary());
    }
    if repeat > 1 {
        let best_median = |v: &mut Vec<f64>| {
            v.sort_by(f64::total_cmp);
            (v[0], v[v.len() / 2])
        };
        println!("time per stage over {repeat} runs (best, median):");
        for (name, v) in &mut stages {
            let (b, m) = best_median(v);
            println!("  {name:<26} {b:.4} s  {m:.4} s");
        }
        let met = three.iter().filter(|&&t| t < 0.5).count();
        let (b, m) = best_median(&mut three);
        println!(
            "  recovery + field points + smoothing: {b:.4} s  {m:.4} s ({met} of {repeat} runs \
             under 0.5 s)"
        );
    }
    Ok(())
}
