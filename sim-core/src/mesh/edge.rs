//! Undirected edges as one sortable key.

/// The canonical key of the undirected edge `(a, b)`.
pub fn edge_key(a: u32, b: u32) -> u64 {
    ((a.min(b) as u64) << 32) | a.max(b) as u64
}

/// The two vertices of an `edge_key`, lower first.
pub fn edge_ends(key: u64) -> (u32, u32) {
    ((key >> 32) as u32, key as u32)
}
