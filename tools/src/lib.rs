//! Saiho `tools`: placeholder crate, filled in by its own issue.
