//! Spacing fields (placeholder being written).
