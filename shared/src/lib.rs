//! Saiho `shared`: placeholder crate, filled in by its own issue.
