//! Times the 3D pipeline on a demo, stage by stage, with options from the command line.
//!
//! `cargo run --release -p delmesh --example pipeline3d -- [DEMO] [--alpha A] [--iterations N]
//! [--no-guard] [--no-smoothing] [--no-restoration]`
//!
//! DEMO is a 3D demo name (`figure9`, the double ellipsoid with automatic points, by default).
//! Prints the run's summary (Table 2, generation passes, quality, seconds per stage).

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
    let run = mesh_plc3(&plc, &options)?;
    print!("{}", run.summary());
    Ok(())
}
