//! xtask's own exact check that a triangulation of integer points is Delaunay,
//! independent of delmesh's `--validate` and of any tie-breaking rule.
//!
//! On degenerate inputs (grids) the Delaunay triangulation is not unique, so delmesh
//! cannot be compared with CGAL cell by cell, and in 3D not even by the number of
//! cells: the 8 co-spherical corners of a grid cube can be split into 5 or into 6
//! tetrahedra, and both are Delaunay. What every Delaunay triangulation satisfies is
//! checked here instead, with exact integer arithmetic:
//!
//! - every facet belongs to one cell (hull) or two (interior), and the two cells of
//!   an interior facet lie on opposite sides of it (exact orientation);
//! - every interior facet is locally Delaunay: the vertex of one cell opposite the
//!   facet is not strictly inside the circumsphere (circumcircle) of the other
//!   cell, and vice versa. Ties (co-spherical points) are allowed, which is exactly
//!   the freedom a degenerate input leaves.
//!
//! Together with the total measure equal to the hull's (checked by the caller with
//! `formats::total_measure`) this makes the cells a triangulation of the hull whose
//! facets are all locally Delaunay, hence a Delaunay triangulation.

use anyhow::{bail, Result};

use crate::formats::{CellSet, NodeFile};

/// Largest coordinate magnitude handled: differences stay below 2^13, squared
/// lengths below 2^28, and the 4x4 insphere determinant below 2^72, inside `i128`.
pub const COORD_LIMIT: f64 = 4096.0;

/// What [`check_locally_delaunay`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LocalCheck {
    /// Facets shared by two cells.
    pub interior_facets: usize,
    /// Facets of one cell only (the hull's).
    pub hull_facets: usize,
}

/// Integer coordinates of every point, or `None` when some coordinate is not an
/// integer of magnitude at most [`COORD_LIMIT`].
fn integer_points(node: &NodeFile) -> Option<Vec<[i128; 3]>> {
    let ok = node
        .coords
        .iter()
        .all(|&x| x.fract() == 0.0 && x.abs() <= COORD_LIMIT);
    ok.then(|| {
        (0..node.len())
            .map(|i| {
                let mut p = [0i128; 3];
                for (d, &x) in node.point(i).iter().enumerate() {
                    p[d] = x as i128;
                }
                p
            })
            .collect()
    })
}

fn sub(a: [i128; 3], b: [i128; 3]) -> [i128; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn det3(a: [i128; 3], b: [i128; 3], c: [i128; 3]) -> i128 {
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}

/// Shewchuk's orient3d: positive when `d` is below the plane of `a, b, c` (seen from
/// above, `a, b, c` counterclockwise), i.e. det[a-d; b-d; c-d].
fn orient3(a: [i128; 3], b: [i128; 3], c: [i128; 3], d: [i128; 3]) -> i128 {
    det3(sub(a, d), sub(b, d), sub(c, d))
}

/// Shewchuk's orient2d: positive when `a, b, c` are counterclockwise.
fn orient2(a: [i128; 3], b: [i128; 3], c: [i128; 3]) -> i128 {
    (a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0])
}

/// Shewchuk's insphere: positive when `e` is inside the sphere through `a, b, c, d`
/// if `orient3(a, b, c, d) > 0` (the sign flips with the orientation).
fn insphere(p: [[i128; 3]; 4], e: [i128; 3]) -> i128 {
    let r: Vec<[i128; 4]> = p
        .iter()
        .map(|&q| {
            let v = sub(q, e);
            [v[0], v[1], v[2], v[0] * v[0] + v[1] * v[1] + v[2] * v[2]]
        })
        .collect();
    // Laplace expansion along the last column.
    let minor = |skip: usize| {
        let rows: Vec<[i128; 3]> = (0..4)
            .filter(|&i| i != skip)
            .map(|i| [r[i][0], r[i][1], r[i][2]])
            .collect();
        det3(rows[0], rows[1], rows[2])
    };
    -r[0][3] * minor(0) + r[1][3] * minor(1) - r[2][3] * minor(2) + r[3][3] * minor(3)
}

/// Shewchuk's incircle: positive when `d` is inside the circle through `a, b, c` if
/// they are counterclockwise.
fn incircle(a: [i128; 3], b: [i128; 3], c: [i128; 3], d: [i128; 3]) -> i128 {
    let lift = |q: [i128; 3]| {
        let (x, y) = (q[0] - d[0], q[1] - d[1]);
        [x, y, x * x + y * y]
    };
    det3(lift(a), lift(b), lift(c))
}

/// True when `e` is strictly inside the circumsphere (circumcircle) of `cell`.
fn strictly_inside(pts: &[[i128; 3]], cell: &[u32], e: u32) -> bool {
    let p = |k: usize| pts[cell[k] as usize];
    let e = pts[e as usize];
    if cell.len() == 3 {
        let o = orient2(p(0), p(1), p(2));
        incircle(p(0), p(1), p(2), e).signum() * o.signum() > 0
    } else {
        let o = orient3(p(0), p(1), p(2), p(3));
        insphere([p(0), p(1), p(2), p(3)], e).signum() * o.signum() > 0
    }
}

/// Orientation sign of `facet` (`dim` vertices) with apex `v`.
fn side(pts: &[[i128; 3]], facet: &[u32], v: u32) -> i128 {
    let p = |i: u32| pts[i as usize];
    if facet.len() == 2 {
        orient2(p(facet[0]), p(facet[1]), p(v)).signum()
    } else {
        orient3(p(facet[0]), p(facet[1]), p(facet[2]), p(v)).signum()
    }
}

/// Checks that `cells` form a properly glued, locally Delaunay complex (see the
/// module docs). Returns `Ok(None)` when the coordinates are not small integers (the
/// check is exact only for those), and an error describing the first violation.
pub fn check_locally_delaunay(node: &NodeFile, cells: &CellSet) -> Result<Option<LocalCheck>> {
    let Some(pts) = integer_points(node) else {
        return Ok(None);
    };
    let arity = cells.arity;
    let cell_list: Vec<&[u32]> = cells.iter().collect();
    // (facet vertices padded to 3, cell index, opposite vertex), sorted by facet.
    let mut facets: Vec<([u32; 3], u32, u32)> = Vec::with_capacity(cell_list.len() * arity);
    for (ci, c) in cell_list.iter().enumerate() {
        for skip in 0..arity {
            let mut f = [u32::MAX; 3];
            let mut k = 0;
            for (j, &v) in c.iter().enumerate() {
                if j != skip {
                    f[k] = v;
                    k += 1;
                }
            }
            facets.push((f, ci as u32, c[skip]));
        }
    }
    facets.sort_unstable_by_key(|r| r.0);
    let mut result = LocalCheck {
        interior_facets: 0,
        hull_facets: 0,
    };
    let mut i = 0;
    while i < facets.len() {
        let mut j = i + 1;
        while j < facets.len() && facets[j].0 == facets[i].0 {
            j += 1;
        }
        let f = &facets[i].0[..arity - 1];
        match j - i {
            1 => result.hull_facets += 1,
            2 => {
                result.interior_facets += 1;
                let (a, b) = (facets[i], facets[i + 1]);
                let (sa, sb) = (side(&pts, f, a.2), side(&pts, f, b.2));
                if sa == 0 || sb == 0 || sa == sb {
                    bail!(
                        "cells {:?} and {:?} share facet {f:?} but are not on opposite sides of it",
                        cell_list[a.1 as usize],
                        cell_list[b.1 as usize]
                    );
                }
                for (cell, other) in [(a, b), (b, a)] {
                    if strictly_inside(&pts, cell_list[cell.1 as usize], other.2) {
                        bail!(
                            "not Delaunay: vertex {} of cell {:?} is strictly inside the \
                             circumsphere of its neighbour {:?}",
                            other.2,
                            cell_list[other.1 as usize],
                            cell_list[cell.1 as usize]
                        );
                    }
                }
            }
            n => bail!("facet {f:?} belongs to {n} cells"),
        }
        i = j;
    }
    Ok(Some(result))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn node(dim: usize, coords: &[f64]) -> NodeFile {
        NodeFile {
            dim,
            first_index: 0,
            coords: coords.to_vec(),
            nattr: 0,
            attrs: vec![],
        }
    }

    #[test]
    fn predicate_signs() {
        let a = [0, 0, 0];
        let (x, y, z) = ([4, 0, 0], [0, 4, 0], [0, 0, 4]);
        // `z` is above the counterclockwise triangle a, x, y: orient3 is negative.
        assert!(orient3(a, x, y, z) < 0);
        assert!(orient3(a, y, x, z) > 0);
        let tet = [a, y, x, z];
        assert!(insphere(tet, [1, 1, 1]) > 0, "centre region is inside");
        assert!(insphere(tet, [9, 9, 9]) < 0);
        assert_eq!(
            insphere(tet, [4, 4, 0]),
            0,
            "a cube corner is on the sphere"
        );
        assert!(orient2(a, x, y) > 0);
        assert!(incircle(a, x, y, [1, 1, 0]) > 0);
        assert!(incircle(a, x, y, [5, 5, 0]) < 0);
        assert_eq!(incircle(a, x, y, [4, 4, 0]), 0);
    }

    #[test]
    fn square_either_diagonal_is_delaunay() {
        // (0,0) (1,0) (0,1) (1,1): co-circular, both splits are fine.
        let n = node(2, &[0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 1.0]);
        for cells in [[[0, 1, 3, 0], [0, 3, 2, 0]], [[0, 1, 2, 0], [1, 3, 2, 0]]] {
            let c = CellSet::new(3, cells.to_vec());
            let r = check_locally_delaunay(&n, &c).unwrap().unwrap();
            assert_eq!((r.interior_facets, r.hull_facets), (1, 4));
        }
    }

    #[test]
    fn finds_non_delaunay_and_bad_gluing() {
        // A flat rhombus: only the short diagonal is Delaunay.
        let n = node(2, &[0.0, 0.0, 4.0, -1.0, 8.0, 0.0, 4.0, 1.0]);
        let good = CellSet::new(3, vec![[0, 1, 3, 0], [1, 2, 3, 0]]);
        assert!(check_locally_delaunay(&n, &good).unwrap().is_some());
        let bad = CellSet::new(3, vec![[0, 1, 2, 0], [0, 2, 3, 0]]);
        let err = check_locally_delaunay(&n, &bad).unwrap_err().to_string();
        assert!(err.starts_with("not Delaunay"), "{err}");
        // Two triangles on the same side of their shared edge (overlapping).
        let overlap = CellSet::new(3, vec![[0, 1, 2, 0], [0, 2, 3, 0], [0, 2, 3, 0]]);
        let err = check_locally_delaunay(&n, &overlap)
            .unwrap_err()
            .to_string();
        assert!(err.contains("belongs to 3 cells"), "{err}");
        let same_side = node(2, &[0.0, 0.0, 4.0, 0.0, 1.0, 1.0, 2.0, 1.0]);
        let c = CellSet::new(3, vec![[0, 1, 2, 0], [0, 1, 3, 0]]);
        let err = check_locally_delaunay(&same_side, &c)
            .unwrap_err()
            .to_string();
        assert!(err.contains("not on opposite sides"), "{err}");
    }

    #[test]
    fn cube_in_five_or_six_tets() {
        let mut coords = Vec::new();
        for i in 0..8 {
            coords.extend([(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64]);
        }
        let n = node(3, &coords);
        // Five: the corner tets around the regular tet 0-3-5-6.
        let five = CellSet::new(
            3 + 1,
            vec![
                [0, 3, 5, 6],
                [0, 1, 3, 5],
                [0, 2, 3, 6],
                [0, 4, 5, 6],
                [3, 5, 6, 7],
            ],
        );
        // Six: around the diagonal 0-7.
        let six = CellSet::new(
            4,
            vec![
                [0, 1, 3, 7],
                [0, 1, 5, 7],
                [0, 2, 3, 7],
                [0, 2, 6, 7],
                [0, 4, 5, 7],
                [0, 4, 6, 7],
            ],
        );
        for (c, interior) in [(five, 4), (six, 6)] {
            let r = check_locally_delaunay(&n, &c).unwrap().unwrap();
            assert_eq!((r.interior_facets, r.hull_facets), (interior, 12));
        }
        let off_grid = node(3, &[0.5; 24]);
        assert_eq!(
            check_locally_delaunay(&off_grid, &CellSet::new(4, vec![])).unwrap(),
            None
        );
    }
}
