//! A cache hint: start loading a value the caller will read soon.
//!
//! Point generation evaluates and inserts its candidates from lists, so it knows which cells
//! the next ones will read long before it reads them. The mesh at 10^6 triangles is larger
//! than the last-level cache, and both otherwise spend much of their time waiting for the
//! cells and coordinates (`perf annotate` of the flips after an insertion: most of their time
//! on the loads of the cell across and of its vertex). Asking for them a few cells ahead
//! ([`crate::ConstrainedTriangulation2::prefetch_cell`] and its siblings) saves a quarter of
//! the evaluation's time and 12–15% of the insertions'.
//!
//! The one `unsafe` block of delmesh: `_mm_prefetch` is a hint that reads nothing the program
//! can observe and never faults, and the address comes from a reference, so no input can make
//! it unsound. On other architectures it does nothing.

/// Asks the processor to bring the cache line holding `value` into its caches.
#[inline(always)]
pub(crate) fn prefetch<T>(value: &T) {
    #[cfg(target_arch = "x86_64")]
    #[allow(unsafe_code)]
    // SAFETY: a prefetch has no architectural effect (no read the program observes, no fault,
    // whatever the address); the address is that of a live reference.
    unsafe {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        _mm_prefetch::<_MM_HINT_T0>((value as *const T).cast::<i8>());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}
