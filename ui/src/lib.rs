//! Saiho `ui`: placeholder crate, filled in by its own issue.
