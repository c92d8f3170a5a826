//! Saiho `tests`: placeholder crate, filled in by its own issue.
