//! Development probe: where are the worst interior angles of a demo mesh?
use delmesh::demos::mesh_demo_setup;
use delmesh::mesh2d::mesh_plc;

fn main() {
    let name = std::env::args().nth(1).unwrap_or("figure10b".into());
    let smooth = std::env::args().nth(2).is_none();
    let (plc, mut options) = mesh_demo_setup(&name).unwrap();
    if !smooth {
        options.smoothing = None;
    }
    let run = mesh_plc(&plc, &options).unwrap();
    let a = &run.arrays;
    let mut bad = Vec::new();
    for t in &a.triangles {
        if t.iter().any(|&v| a.on_boundary[v as usize]) {
            continue;
        }
        let p = t.map(|v| a.coords[v as usize]);
        let mut worst = 180.0f64;
        for k in 0..3 {
            let (o, u, w) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
            let (ux, uy, wx, wy) = (u[0] - o[0], u[1] - o[1], w[0] - o[0], w[1] - o[1]);
            worst = worst.min(
                (ux * wy - uy * wx)
                    .abs()
                    .atan2(ux * wx + uy * wy)
                    .to_degrees(),
            );
        }
        if worst < 25.0 {
            bad.push((worst, p));
        }
    }
    bad.sort_by(|a, b| a.0.total_cmp(&b.0));
    println!("{} interior triangles below 25°", bad.len());
    for (w, p) in bad.iter().take(15) {
        println!("{w:.2}° at {:?}", p[0]);
    }
}
