//! Analytic geometry of the demos (placeholder being written).
