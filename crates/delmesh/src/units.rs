//! Exact rescaling of a meshing problem by a power of two.
//!
//! The pipelines square and multiply lengths: α tests compare squared distances, the smoothers'
//! angle guards multiply four squared lengths, quality reports compute volumes. Far from
//! ordinary magnitudes (a domain 10^100 or 10^-100 across) those products overflow or underflow:
//! surface recovery then failed on a box 10^100 across, and 2D point generation added no point
//! to a disc 10^200 across. Multiplying every coordinate by a power of two changes no digit,
//! and every sum, product and comparison of the pipelines scales with it exactly (while no
//! value overflows or underflows), so [`crate::mesh2d::mesh_plc`] and
//! [`crate::mesh3d::mesh_plc3`] mesh a problem whose extent is outside [`ORDINARY`] scaled into
//! `[1, 2)`, then give every length, area and volume of the result back in the caller's units:
//! the mesh is the unit-size problem's, exactly, times the scale. Within [`ORDINARY`] nothing
//! is scaled. (An error found on the scaled problem that quotes a coordinate quotes it
//! scaled; the elements it names are the input's.)

use crate::mesh2d::{MeshOptions2, MeshRun2, Spacing};
use crate::mesh3d::{MeshOptions3, MeshRun3, Spacing3};
use crate::recovery::{Plc2, Plc3};
use crate::Error;

/// Extents (largest side of the bounding box) in this range are meshed as they are.
pub const ORDINARY: (f64, f64) = (1.0 / (1u64 << 32) as f64, (1u64 << 32) as f64);

/// The most a problem is scaled by: `2^±900`, so that its coordinates stay within the range the
/// triangulation handles exactly (`2^±1000`) on the way back.
const MAX_EXPONENT: i32 = 900;

/// The exponent `e` such that `2^e` times the extent of `points` is in `[1, 2)`, or 0 when the
/// extent is within [`ORDINARY`] (or not positive and finite: the pipeline reports that). The
/// largest coordinate is kept below `2^MAX_EXPONENT` after scaling.
pub(crate) fn normalising_exponent<const N: usize>(points: &[[f64; N]]) -> i32 {
    let (mut lo, mut hi) = ([f64::INFINITY; N], [f64::NEG_INFINITY; N]);
    for p in points {
        for k in 0..N {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let extent = (0..N).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
    let largest = (0..N)
        .map(|k| lo[k].abs().max(hi[k].abs()))
        .fold(0.0, f64::max);
    if !(extent.is_finite() && extent > 0.0) || (ORDINARY.0..=ORDINARY.1).contains(&extent) {
        return 0;
    }
    let e = -(extent.log2().floor() as i32);
    // Scaling up stops where the largest coordinate would pass 2^MAX_EXPONENT.
    let room = (MAX_EXPONENT - largest.log2().ceil() as i32).max(0);
    e.clamp(-MAX_EXPONENT, MAX_EXPONENT.min(room))
}

/// The range delmesh meshes: coordinates up to `2^RANGE` in magnitude, domains at least
/// `2^-RANGE` across (a margin under the triangulation's `2^±1000`, which its own scaling and
/// the normalisation above share).
const RANGE: i32 = 990;

/// Refuses, before any meshing, a domain beyond [`RANGE`], naming the point (numbered from
/// `first`) with the largest coordinate, or saying how small the domain is. (Non-finite
/// coordinates are left to the triangulation, which names them.)
pub(crate) fn check_range<const N: usize>(points: &[[f64; N]], first: u32) -> Result<(), Error> {
    let limit = 2f64.powi(RANGE);
    let magnitude = |p: &[f64; N]| p.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let Some((k, p)) = points
        .iter()
        .enumerate()
        .filter(|(_, p)| p.iter().all(|x| x.is_finite()))
        .max_by(|a, b| magnitude(a.1).total_cmp(&magnitude(b.1)))
    else {
        return Ok(());
    };
    let number = k as u64 + u64::from(first);
    if magnitude(p) > limit {
        return Err(Error::OutOfRange {
            what: format!("point {number} has a coordinate of {:e}", magnitude(p)),
        });
    }
    let (mut lo, mut hi) = ([f64::INFINITY; N], [f64::NEG_INFINITY; N]);
    for p in points.iter().filter(|p| p.iter().all(|x| x.is_finite())) {
        for i in 0..N {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    let extent = (0..N).map(|i| hi[i] - lo[i]).fold(0.0, f64::max);
    if extent > 0.0 && extent < 1.0 / limit {
        return Err(Error::OutOfRange {
            what: format!("the points lie within {extent:e} of each other"),
        });
    }
    Ok(())
}

fn scale<const N: usize>(p: [f64; N], f: f64) -> [f64; N] {
    p.map(|x| x * f)
}

/// `plc` and `options` in units `2^e` times larger.
pub(crate) fn scale_problem2(plc: &Plc2, options: &MeshOptions2, e: i32) -> (Plc2, MeshOptions2) {
    let f = 2f64.powi(e);
    let mut plc = plc.clone();
    for p in plc.points.iter_mut().chain(&mut plc.holes) {
        *p = scale(*p, f);
    }
    for r in &mut plc.regions {
        r.point = scale(r.point, f);
        r.max_area = r.max_area.map(|a| a * f * f);
    }
    let mut options = options.clone();
    for p in &mut options.extra_points {
        *p = scale(*p, f);
    }
    if let Spacing::Background(bg) = &mut options.spacing {
        *bg = bg.scaled(e);
    }
    for s in &mut options.sources {
        *s = s.scaled(e);
    }
    (plc, options)
}

/// `plc` and `options` in units `2^e` times larger.
pub(crate) fn scale_problem3(plc: &Plc3, options: &MeshOptions3, e: i32) -> (Plc3, MeshOptions3) {
    let f = 2f64.powi(e);
    let mut plc = plc.clone();
    for p in plc.points.iter_mut().chain(&mut plc.holes) {
        *p = scale(*p, f);
    }
    for r in &mut plc.regions {
        r.point = scale(r.point, f);
        r.max_volume = r.max_volume.map(|v| v * f * f * f);
    }
    let mut options = options.clone();
    for p in &mut options.extra_points {
        *p = scale(*p, f);
    }
    if let Spacing3::Background(bg) = &mut options.spacing {
        **bg = bg.scaled(e);
    }
    for s in &mut options.sources {
        *s = s.scaled(e);
    }
    options.surface_spacing = options.surface_spacing.map(|h| h * f);
    (plc, options)
}

fn out_of_range(e: i32) -> Error {
    Error::Input {
        file: "(scaled problem)".into(),
        message: format!("the mesh cannot be given back in units 2^{e} times larger"),
    }
}

/// The result of a problem scaled by [`scale_problem2`] with `2^-e`, in the caller's units.
pub(crate) fn unscale_run2(run: &mut MeshRun2, e: i32) -> Result<(), Error> {
    if !run.mesh.rescale_units(e) {
        return Err(out_of_range(e));
    }
    let f = 2f64.powi(e);
    for p in &mut run.arrays.coords {
        *p = scale(*p, f);
    }
    let q = &mut run.quality;
    for a in [&mut q.min_area, &mut q.max_area, &mut q.total_area] {
        *a *= f * f;
    }
    Ok(())
}

/// The result of a problem scaled by [`scale_problem3`] with `2^-e`, in the caller's units.
pub(crate) fn unscale_run3(run: &mut MeshRun3, e: i32) -> Result<(), Error> {
    if !run.mesh.rescale_units(e) {
        return Err(out_of_range(e));
    }
    let f = 2f64.powi(e);
    for p in &mut run.arrays.coords {
        *p = scale(*p, f);
    }
    for q in std::iter::once(&mut run.quality).chain(&mut run.quality_before_smoothing) {
        for v in [&mut q.min_volume, &mut q.max_volume, &mut q.total_volume] {
            *v *= f * f * f;
        }
    }
    Ok(())
}

/// An error of the problem solved in units `2^e` times larger, its coordinates in the
/// caller's units again (a coordinate-range error named the scaled values).
pub(crate) fn unscale_error(err: Error, e: i32) -> Error {
    match err {
        Error::Recovery(delmesh_boundary_recovery::RecoveryError::Triangulation(t)) => {
            Error::Recovery(delmesh_boundary_recovery::RecoveryError::Triangulation(
                t.in_units(2f64.powi(-e)),
            ))
        }
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn domains_beyond_the_range_are_refused_naming_a_point() {
        // Both meshed for nothing and then refused as "(scaled problem): the mesh cannot be
        // given back in units 2^900 times larger", naming no point.
        let err = check_range(&[[0.0, 0.0], [1e308, 0.0], [0.0, 1e308]], 1).unwrap_err();
        assert!(
            err.to_string()
                .starts_with("point 3 has a coordinate of 1e308"),
            "{err}"
        );
        let tiny = [[0.0, 0.0, 0.0], [5e-324, 0.0, 0.0], [0.0, 5e-324, 1e-320]];
        let err = check_range(&tiny, 0).unwrap_err();
        assert!(
            err.to_string().starts_with("the points lie within 1e-320"),
            "{err}"
        );
        for extent in [1e-290, 1e-100, 1.0, 1e100, 1e290] {
            check_range(&[[0.0, 0.0], [extent, extent]], 0).unwrap();
        }
        // Non-finite coordinates are the triangulation's to name; a single point is fine here.
        check_range(&[[f64::NAN, 0.0], [1.0, 1.0]], 0).unwrap();
        check_range(&[[1.0, 1.0]], 0).unwrap();
    }

    #[test]
    fn ordinary_extents_are_not_scaled_and_others_land_in_one_to_two() {
        assert_eq!(normalising_exponent(&[[0.0, 0.0], [3.0, 1.0]]), 0);
        assert_eq!(normalising_exponent(&[[1e12, 0.0], [1e12 + 1.0, 1.0]]), 0);
        assert_eq!(normalising_exponent::<2>(&[]), 0);
        assert_eq!(normalising_exponent(&[[5.0, 5.0, 5.0]]), 0);
        for extent in [1e-250, 1e-100, 3e-12, 7e11, 1e100, 1e250] {
            let e = normalising_exponent(&[[0.0, 0.0, 0.0], [extent, extent / 2.0, 0.0]]);
            let scaled = extent * 2f64.powi(e);
            assert!(
                (1.0..2.0).contains(&scaled),
                "{extent}: 2^{e} gives {scaled}"
            );
        }
        // At most 2^±900.
        assert_eq!(
            normalising_exponent(&[[0.0, 0.0], [1e300, 1.0]]),
            -MAX_EXPONENT
        );
        assert_eq!(
            normalising_exponent(&[[0.0, 0.0], [1e-300, 0.0]]),
            MAX_EXPONENT
        );
        // A tiny extent far from the origin is not scaled beyond the range of f64.
        assert_eq!(normalising_exponent(&[[1e300, 0.0], [1e300, 1e-20]]), 0);
        let e = normalising_exponent(&[[1e250, 0.0], [1e250, 1e-20]]);
        assert!(
            e > 0 && 1e250 * 2f64.powi(e) <= 2f64.powi(MAX_EXPONENT),
            "2^{e}"
        );
    }
}
