//! The paper's Figure 1 / Table 1: nine points, their Delaunay triangulation and its Voronoi
//! structure (forming points and neighbouring Voronoi vertices, `*` on the hull).
//!
//! The paper gives no coordinates; `data/figure1.node` holds nine points whose triangulation is
//! exactly Table 1. Our Voronoi vertices are numbered by their sorted forming points, the
//! paper's are not, so the test compares the two tables as sets of rows expressed in forming
//! points, and snapshots our table.

use delmesh_delaunay_core::{Triangulation2, VoronoiDiagram};
use std::collections::BTreeSet;

const NODE: &str = include_str!("../../../data/figure1.node");
const TABLE: &str = include_str!("../../../data/figure1-table1.txt");

/// Each row as (sorted forming points, set of neighbours' sorted forming points, hull sides).
type Row = (Vec<u32>, BTreeSet<Vec<u32>>, usize);

fn rows_of(table: &str) -> BTreeSet<Row> {
    let parsed: Vec<(Vec<u32>, Vec<Option<usize>>)> = table
        .lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let cols: Vec<&str> = l.split('\t').collect();
            let mut forming: Vec<u32> = cols[1]
                .split_whitespace()
                .map(|x| x.parse().unwrap())
                .collect();
            forming.sort_unstable();
            let neighbors = cols[2]
                .split_whitespace()
                .map(|x| {
                    if x == "*" {
                        None
                    } else {
                        Some(x.parse::<usize>().unwrap() - 1)
                    }
                })
                .collect();
            (forming, neighbors)
        })
        .collect();
    parsed
        .iter()
        .map(|(forming, neighbors)| {
            let ns = neighbors
                .iter()
                .flatten()
                .map(|&j| parsed[j].0.clone())
                .collect();
            (
                forming.clone(),
                ns,
                neighbors.iter().filter(|n| n.is_none()).count(),
            )
        })
        .collect()
}

fn figure1_points() -> Vec<[f64; 2]> {
    NODE.lines()
        .map(|l| l.split('#').next().unwrap().trim())
        .filter(|l| !l.is_empty())
        .skip(1)
        .map(|l| {
            let f: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            [f[1], f[2]]
        })
        .collect()
}

#[test]
fn figure1_reproduces_table1() {
    let pts = figure1_points();
    assert_eq!(pts.len(), 9);
    let tri = Triangulation2::new(&pts).unwrap();
    tri.validate().unwrap();
    let ours = VoronoiDiagram::new(&tri).table(1);
    assert_eq!(rows_of(&ours), rows_of(TABLE), "ours:\n{ours}");
    insta::assert_snapshot!(ours);
}
