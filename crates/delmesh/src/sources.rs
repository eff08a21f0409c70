//! Checks of the spacing sources before meshing (2D [`Source`], 3D [`Source3`]), in the
//! caller's units: values that are not lengths, and sources that ask for more elements than
//! delmesh can index. Point generation has no element budget of its own (a source 10^-6 wide
//! in a unit cube would run until memory runs out), so the count is estimated here.
//!
//! The estimate is a lower bound wherever the source lies inside the domain: within
//! `radius + h0 / growth` of the source (everywhere if it does not grow) the spacing is under
//! `2·h0`, so that region, clipped to the domain's bounding box, holds at least its measure
//! over the measure of an equilateral element of side `2·h0`.

use crate::Error;
use delmesh_point_gen::{Source, Source3};

/// Elements a source may ask for: as many as the mesh's 32-bit indices hold, with room.
pub(crate) const MAX_SOURCE_ELEMENTS: f64 = (1u64 << 30) as f64;

/// Checks `sources` for the domain of `points`.
///
/// # Errors
/// [`Error::Source`], naming the source and saying why.
pub(crate) fn check_sources2(sources: &[Source], points: &[[f64; 2]]) -> Result<(), Error> {
    let (lo, hi) = bounds(points);
    for (k, s) in sources.iter().enumerate() {
        let ends = [s.a, s.b].concat();
        check_values(k, &ends, s.h0, s.radius, s.growth)?;
        check_reach(k, &[s.a, s.b], &lo, &hi)?;
        let reach = reach(s.h0, s.radius, s.growth);
        let length = (s.b[0] - s.a[0]).hypot(s.b[1] - s.a[1]);
        let core = std::f64::consts::PI * reach * reach + 2.0 * reach * length;
        let clipped = clipped_box(&[s.a, s.b], reach, &lo, &hi);
        let side = 2.0 * s.h0;
        let elements = core.min(clipped) / (side * side * 3f64.sqrt() / 4.0);
        check_count(k, s.h0, elements, "triangles")?;
    }
    Ok(())
}

/// Checks `sources` for the domain of `points` in 3D.
///
/// # Errors
/// [`Error::Source`], naming the source and saying why.
pub(crate) fn check_sources3(sources: &[Source3], points: &[[f64; 3]]) -> Result<(), Error> {
    let (lo, hi) = bounds(points);
    for (k, s) in sources.iter().enumerate() {
        let ends = [s.a, s.b].concat();
        check_values(k, &ends, s.h0, s.radius, s.growth)?;
        check_reach(k, &[s.a, s.b], &lo, &hi)?;
        let reach = reach(s.h0, s.radius, s.growth);
        let d = [0, 1, 2].map(|i| s.b[i] - s.a[i]);
        let length = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let pi = std::f64::consts::PI;
        let core = 4.0 / 3.0 * pi * reach.powi(3) + pi * reach * reach * length;
        let clipped = clipped_box(&[s.a, s.b], reach, &lo, &hi);
        let side = 2.0 * s.h0;
        let elements = core.min(clipped) / (side.powi(3) / (6.0 * 2f64.sqrt()));
        check_count(k, s.h0, elements, "tetrahedra")?;
    }
    Ok(())
}

fn check_values(k: usize, ends: &[f64], h0: f64, radius: f64, growth: f64) -> Result<(), Error> {
    let refuse = |reason: String| {
        Err(Error::Source {
            number: k + 1,
            reason,
        })
    };
    if let Some(x) = ends.iter().find(|x| !x.is_finite()) {
        return refuse(format!("coordinate {x} is not finite"));
    }
    if !(h0 > 0.0 && h0.is_finite()) {
        return refuse(format!(
            "spacing H0 must be positive and finite (got {h0:?})"
        ));
    }
    if !(radius >= 0.0 && radius.is_finite() && growth >= 0.0 && growth.is_finite()) {
        return refuse(format!(
            "RADIUS and GROWTH must be finite and not negative (got {radius:?}, {growth:?})"
        ));
    }
    Ok(())
}

/// The farthest a source's end may lie from the domain, in multiples of the domain's size: the
/// distances to a segment are computed from exact cross products of its ends' offsets, whose
/// products overflow beyond about 1e150 (a line from -1e160 to 1e160 across a unit square
/// split nothing and gave the wrong mesh).
const FARTHEST: f64 = 1.0e120;

fn check_reach<const N: usize>(
    k: usize,
    ends: &[[f64; N]; 2],
    lo: &[f64; N],
    hi: &[f64; N],
) -> Result<(), Error> {
    let size = (0..N).map(|i| hi[i] - lo[i]).fold(0.0, f64::max);
    if !(size > 0.0 && size.is_finite()) {
        return Ok(()); // (no domain to measure against: the pipeline reports that)
    }
    let away = |p: &[f64; N]| {
        (0..N)
            .map(|i| (p[i] - 0.5 * (lo[i] + hi[i])).abs())
            .fold(0.0, f64::max)
    };
    match ends.iter().find(|p| away(p) > FARTHEST * size) {
        Some(p) => Err(Error::Source {
            number: k + 1,
            reason: format!(
                "an end, {p:?}, is more than {FARTHEST:e} times the domain's size ({size:e}) \
                 from it; end the segment nearer the domain"
            ),
        }),
        None => Ok(()),
    }
}

fn check_count(k: usize, h0: f64, elements: f64, what: &str) -> Result<(), Error> {
    if elements > MAX_SOURCE_ELEMENTS {
        return Err(Error::Source {
            number: k + 1,
            reason: format!(
                "spacing {h0:e} asks for at least {elements:.1e} {what} around the source, more \
                 than delmesh can index (2^30); give a larger spacing or radius"
            ),
        });
    }
    Ok(())
}

/// Distance from the source within which its spacing is under `2·h0`.
fn reach(h0: f64, radius: f64, growth: f64) -> f64 {
    if growth > 0.0 {
        radius + h0 / growth
    } else {
        f64::INFINITY
    }
}

/// The bounding box of `points`.
fn bounds<const N: usize>(points: &[[f64; N]]) -> ([f64; N], [f64; N]) {
    let (mut lo, mut hi) = ([f64::INFINITY; N], [f64::NEG_INFINITY; N]);
    for p in points.iter().filter(|p| p.iter().all(|x| x.is_finite())) {
        for i in 0..N {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    (lo, hi)
}

/// The measure of the box around `ends` grown by `reach`, clipped to the box `lo`–`hi`
/// (0 where they do not overlap).
fn clipped_box<const N: usize>(
    ends: &[[f64; N]; 2],
    reach: f64,
    lo: &[f64; N],
    hi: &[f64; N],
) -> f64 {
    (0..N)
        .map(|i| {
            let a = (ends[0][i].min(ends[1][i]) - reach).max(lo[i]);
            let b = (ends[0][i].max(ends[1][i]) + reach).min(hi[i]);
            (b - a).max(0.0)
        })
        .product()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> Vec<[f64; 3]> {
        vec![[0.0; 3], [1.0; 3]]
    }

    #[test]
    fn a_source_asking_too_much_is_refused_with_its_number() {
        let ok = Source3 {
            a: [0.5; 3],
            b: [0.5; 3],
            h0: 0.01,
            radius: 0.1,
            growth: 0.5,
        };
        let fine = Source3 { h0: 1e-6, ..ok };
        assert!(check_sources3(&[ok], &cube()).is_ok());
        let e = check_sources3(&[ok, fine], &cube()).unwrap_err();
        assert!(matches!(e, Error::Source { number: 2, .. }), "{e}");
        assert!(e.to_string().contains("2^30"), "{e}");
        // Far outside the domain: nothing is asked of it.
        let away = Source3 {
            a: [50.0; 3],
            b: [50.0; 3],
            ..fine
        };
        assert!(check_sources3(&[away], &cube()).is_ok());
        // No growth: the whole domain at H0.
        let flat = Source3 {
            h0: 5e-4,
            growth: 0.0,
            radius: 0.0,
            ..ok
        };
        assert!(check_sources3(&[flat], &cube()).is_err());
        let bad = Source3 { h0: -1.0, ..ok };
        assert!(check_sources3(&[bad], &cube()).is_err());
        let nan = Source3 {
            growth: f64::NAN,
            ..ok
        };
        assert!(check_sources3(&[nan], &cube()).is_err());
    }

    #[test]
    fn a_2d_source_is_checked_the_same_way() {
        let square = [[0.0, 0.0], [1.0, 1.0]];
        let ok = Source {
            a: [0.5, 0.5],
            b: [0.5, 0.5],
            h0: 1e-4,
            radius: 0.01,
            growth: 0.3,
        };
        assert!(check_sources2(&[ok], &square).is_ok());
        let fine = Source {
            h0: 1e-7,
            radius: 0.05,
            ..ok
        };
        assert!(matches!(
            check_sources2(&[fine], &square),
            Err(Error::Source { number: 1, .. })
        ));
    }
}
