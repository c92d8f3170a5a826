//! Proximity: which primitives of the cloth and the body can come near each other over a
//! frame, the direction that separates each such pair, and the guard that keeps every
//! vertex move on its side of them. Together they make the cloth's contact
//! penetration-free: see `pairs.rs` for the argument and ARCHITECTURE.md for what it
//! covers.

mod body_pairs;
mod body_side;
mod bvh;
mod cloth_side;
mod contacts;
mod distance;
mod grid;
mod guard;
mod incremental;
mod pair;
mod pairs;
mod reach;

pub use body_side::BodyGrids;
pub use contacts::count_self_contacts;
pub use distance::{barycentric, point_triangle, segment_segment};
pub use grid::{Aabb, BoxGrid, unique_edges};
pub use guard::{Guarded, constrain};
pub use incremental::Changed;
pub use pair::{ClothView, NONE, Pair, PairCounts, PairKind, ProximityParams};
pub use pairs::Proximity;
pub use reach::Reach;
