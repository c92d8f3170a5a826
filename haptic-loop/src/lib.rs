//! Saiho `haptic-loop`: placeholder crate, filled in by its own issue.
