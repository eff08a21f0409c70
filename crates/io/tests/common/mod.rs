//! The unit cube in six tetrahedra with regions, markers and names: the fixture of the
//! tetrahedral-mesh writers' tests.
#![allow(dead_code, unreachable_pub)]

use delmesh_io::TetMeshOut;

/// Corner `i` of the unit cube is `(i & 1, i >> 1 & 1, i >> 2 & 1)`.
pub const CUBE: [[f64; 3]; 8] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [1.0, 0.0, 1.0],
    [0.0, 1.0, 1.0],
    [1.0, 1.0, 1.0],
];
/// The six positively oriented Kuhn tetrahedra around the diagonal 0-7.
pub const TETS: [[u32; 4]; 6] = [
    [0, 1, 3, 7],
    [0, 1, 7, 5],
    [0, 2, 7, 3],
    [0, 2, 6, 7],
    [0, 4, 5, 7],
    [0, 4, 7, 6],
];
pub const REGIONS: [f64; 6] = [1.0, 1.0, 1.0, 2.0, 2.0, 2.0];
/// The twelve boundary triangles, facing out; markers: x = 0 is 1, x = 1 is 2, y = 0 and
/// y = 1 are 3, z = 0 is 0 (no marker), z = 1 is 4.
pub const FACES: [[u32; 3]; 12] = [
    [0, 4, 6],
    [1, 7, 5],
    [0, 5, 4],
    [2, 6, 7],
    [0, 2, 3],
    [4, 7, 6],
    [0, 6, 2],
    [1, 3, 7],
    [0, 1, 5],
    [2, 7, 3],
    [0, 3, 1],
    [4, 5, 7],
];
pub const FACE_MARKERS: [i32; 12] = [1, 2, 3, 3, 0, 4, 1, 2, 3, 3, 0, 4];
pub const POINT_MARKERS: [i32; 8] = [1, 2, 1, 2, 1, 2, 1, 2];
pub const NAMES: [(i32, &str); 2] = [(1, "inlet"), (2, "outlet")];

pub fn cube() -> TetMeshOut<'static> {
    TetMeshOut {
        coords: &CUBE,
        tets: &TETS,
        regions: Some(&REGIONS),
        faces: &FACES,
        face_markers: &FACE_MARKERS,
        point_markers: Some(&POINT_MARKERS),
        marker_names: &NAMES,
    }
}
