//! How much memory a run may still take: a spacing field that asks for far more elements than
//! fit is refused before generation starts filling memory (an allocation failure aborts the
//! process, after minutes of work, with nothing written).

/// Bytes a 2D mesh takes per triangle at least while it is generated, smoothed and written:
/// its cells and their neighbours, the vertices with their spacing, the smoother's and the
/// output's arrays. Measured peaks are larger (580 bytes per triangle for 10^6 triangles
/// written to `.vtu`), so only a field asking for well beyond the memory is refused.
pub(crate) const BYTES_PER_TRIANGLE: f64 = 150.0;

/// As [`BYTES_PER_TRIANGLE`], per tetrahedron (measured: 900 bytes at 200,000 tetrahedra
/// written to `.vtu`).
pub(crate) const BYTES_PER_TETRAHEDRON: f64 = 300.0;

/// The bytes this process may still allocate: the smaller of the system's available memory
/// and what its address-space and data-size limits leave (`ulimit -v`, `ulimit -d`). Read from
/// Linux's `/proc`; `None` elsewhere, or if nothing there could be read.
pub(crate) fn available() -> Option<f64> {
    let kib = |text: &str, key: &str| -> Option<f64> {
        let line = text.lines().find(|l| l.starts_with(key))?;
        let value: f64 = line[key.len()..].split_whitespace().next()?.parse().ok()?;
        Some(value * 1024.0)
    };
    let mut least: Option<f64> = None;
    let mut keep = |bytes: Option<f64>| {
        if let Some(b) = bytes {
            least = Some(least.map_or(b, |l| l.min(b)));
        }
    };
    if let Ok(info) = std::fs::read_to_string("/proc/meminfo") {
        keep(kib(&info, "MemAvailable:"));
    }
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    if let Ok(limits) = std::fs::read_to_string("/proc/self/limits") {
        // "Max address space  <soft> <hard> bytes", "unlimited" if none.
        let soft = |key: &str| -> Option<f64> {
            let line = limits.lines().find(|l| l.starts_with(key))?;
            line[key.len()..].split_whitespace().next()?.parse().ok()
        };
        for (limit, used) in [
            ("Max address space", "VmSize:"),
            ("Max data size", "VmData:"),
        ] {
            if let Some(l) = soft(limit) {
                keep(Some((l - kib(&status, used).unwrap_or(0.0)).max(0.0)));
            }
        }
    }
    least
}

/// The most elements of `bytes_each` that fit in `available` bytes (unbounded if unknown).
pub(crate) fn elements_fitting(available: Option<f64>, bytes_each: f64) -> f64 {
    available.map_or(f64::INFINITY, |a| a / bytes_each)
}

/// "1.2 GB", "350 MB" for a number of bytes.
pub(crate) fn size(bytes: f64) -> String {
    if bytes >= 1e9 {
        format!("{:.1} GB", bytes / 1e9)
    } else {
        format!("{:.0} MB", (bytes / 1e6).max(1.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn this_machine_has_some_memory_and_sizes_read_well() {
        if cfg!(target_os = "linux") {
            let a = available().expect("/proc is readable");
            assert!(a > 1e6, "{a}");
        }
        assert_eq!(elements_fitting(None, 150.0), f64::INFINITY);
        assert_eq!(elements_fitting(Some(300.0), 150.0), 2.0);
        assert_eq!(size(6.9e10), "69.0 GB");
        assert_eq!(size(3.5e8), "350 MB");
    }
}
