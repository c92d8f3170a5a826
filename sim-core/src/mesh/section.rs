//! Level sections of a triangle mesh: the loops a horizontal plane cuts from it, as a tape
//! measure reads a body or a garment round at one height.
//!
//! A vertex at or above the plane counts as above, so every edge is crossed or not the
//! same way in each triangle that has it, and a closed surface gives closed loops. Points
//! are (x, z): the plane's own coordinates.

use glam::{Vec2, Vec3};
use rustc_hash::FxHashMap as HashMap;

use super::{edge_ends, edge_key};

/// One connected run of a section: the points where the plane crosses the mesh's edges,
/// in order, and whether the last joins the first.
#[derive(Clone, Debug, PartialEq)]
pub struct Chain {
    pub points: Vec<Vec2>,
    pub closed: bool,
}

impl Chain {
    /// Its length along the surface, m (a closed one back to its start).
    pub fn length(&self) -> f32 {
        let open: f32 = self.points.windows(2).map(|w| w[0].distance(w[1])).sum();
        match (self.closed, self.points.first(), self.points.last()) {
            (true, Some(a), Some(b)) => open + a.distance(*b),
            _ => open,
        }
    }

    /// Whether it is closed and goes round `c` (its winding number about `c` is not 0).
    pub fn goes_round(&self, c: Vec2) -> bool {
        self.closed && winding(&self.points, c) != 0
    }

    /// The area it closes, m² (0 for an open chain).
    pub fn area(&self) -> f32 {
        if !self.closed {
            return 0.0;
        }
        let n = self.points.len();
        let twice: f32 = (0..n)
            .map(|i| self.points[i].perp_dot(self.points[(i + 1) % n]))
            .sum();
        0.5 * twice.abs()
    }
}

/// How many times the closed polygon `p` winds round `c`.
fn winding(p: &[Vec2], c: Vec2) -> i32 {
    let mut w = 0;
    for i in 0..p.len() {
        let (a, b) = (p[i], p[(i + 1) % p.len()]);
        let side = (b - a).perp_dot(c - a);
        if a.y <= c.y {
            if b.y > c.y && side > 0.0 {
                w += 1;
            }
        } else if b.y <= c.y && side < 0.0 {
            w -= 1;
        }
    }
    w
}

/// The chains the plane `y = level` cuts from triangles `tris` over vertices `x` (a
/// triangle naming a vertex past `x` is left out). Where more than two triangles share a
/// crossed edge (a non-manifold edge), a chain goes on through one of them.
pub fn section(x: &[Vec3], tris: &[[u32; 3]], level: f32) -> Vec<Chain> {
    let above = |v: u32| x[v as usize].y >= level;
    // Each crossed triangle's segment, as its two crossed edges.
    let mut segments: Vec<[u64; 2]> = Vec::new();
    for t in tris {
        if t.iter().any(|&v| v as usize >= x.len()) {
            continue;
        }
        let mut crossed = [0u64; 2];
        let mut n = 0;
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if above(a) != above(b) {
                if n < 2 {
                    crossed[n] = edge_key(a, b);
                }
                n += 1;
            }
        }
        if n == 2 {
            segments.push(crossed);
        }
    }
    let mut at: HashMap<u64, Vec<u32>> = HashMap::default();
    for (s, ends) in segments.iter().enumerate() {
        for e in ends {
            at.entry(*e).or_default().push(s as u32);
        }
    }
    let point = |key: u64| {
        let (a, b) = edge_ends(key);
        let (pa, pb) = (x[a as usize], x[b as usize]);
        let t = (level - pa.y) / (pb.y - pa.y);
        let p = pa.lerp(pb, t.clamp(0.0, 1.0));
        Vec2::new(p.x, p.z)
    };
    let mut used = vec![false; segments.len()];
    let mut chains = Vec::new();
    for start in 0..segments.len() {
        if used[start] {
            continue;
        }
        used[start] = true;
        // Walk forward from the segment's second edge, then backward from its first.
        let mut halves = [Vec::new(), Vec::new()];
        let mut closed = false;
        for (dir, half) in halves.iter_mut().enumerate() {
            let mut edge = segments[start][1 - dir];
            loop {
                half.push(edge);
                let next = at[&edge].iter().copied().find(|&s| !used[s as usize]);
                let Some(s) = next else {
                    closed = dir == 0 && at[&edge].len() > 1 && edge == segments[start][0];
                    break;
                };
                used[s as usize] = true;
                let [e0, e1] = segments[s as usize];
                edge = if e0 == edge { e1 } else { e0 };
            }
            if closed {
                break;
            }
        }
        let [fwd, back] = halves;
        let edges: Vec<u64> = if closed {
            // From the first segment's second edge round to its first: the first segment
            // closes the loop.
            fwd
        } else {
            back.iter().rev().chain(&fwd).copied().collect()
        };
        chains.push(Chain {
            points: edges.into_iter().map(point).collect(),
            closed,
        });
    }
    chains
}

/// The convex hull of `points`, its corners in order round it (counter-clockwise in x, z).
pub fn hull(points: &[Vec2]) -> Vec<Vec2> {
    let mut p: Vec<Vec2> = points.to_vec();
    p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    // Andrew's monotone chain: the lower hull, then the upper.
    let mut h: Vec<Vec2> = Vec::with_capacity(2 * p.len());
    for pass in 0..2 {
        let base = h.len();
        for i in 0..p.len() {
            let q = if pass == 0 { p[i] } else { p[p.len() - 1 - i] };
            while h.len() >= base + 2
                && (h[h.len() - 1] - h[h.len() - 2]).perp_dot(q - h[h.len() - 2]) <= 0.0
            {
                h.pop();
            }
            h.push(q);
        }
        h.pop();
    }
    h
}

/// The length round the closed polygon `p`, m.
pub fn perimeter(p: &[Vec2]) -> f32 {
    (0..p.len())
        .map(|i| p[i].distance(p[(i + 1) % p.len()]))
        .sum()
}

/// The perimeter of the convex hull of `points`, m: what a tape measure laid round them
/// reads (it bridges every hollow).
pub fn hull_perimeter(points: &[Vec2]) -> f32 {
    perimeter(&hull(points))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed cylinder of `n` sides, radius `r`, from y 0 to 1, wound outward.
    fn cylinder(n: u32, r: f32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let mut x = Vec::new();
        for k in 0..n {
            let a = std::f32::consts::TAU * k as f32 / n as f32;
            x.push(Vec3::new(r * a.cos(), 0.0, r * a.sin()));
            x.push(Vec3::new(r * a.cos(), 1.0, r * a.sin()));
        }
        let mut t = Vec::new();
        for k in 0..n {
            let (a, b) = (2 * k, 2 * ((k + 1) % n));
            t.push([a, b, a + 1]);
            t.push([b, b + 1, a + 1]);
        }
        (x, t)
    }

    #[test]
    fn a_cylinders_section_is_one_closed_loop_its_polygons_length_round() {
        let (x, t) = cylinder(48, 0.15);
        let c = section(&x, &t, 0.37);
        assert_eq!(c.len(), 1, "{c:?}");
        assert!(c[0].closed);
        // A point on each side's upright edge and one on its diagonal, on the chord.
        assert_eq!(c[0].points.len(), 96);
        let side = 2.0 * 0.15 * (std::f32::consts::PI / 48.0).sin();
        assert!(
            (c[0].length() - 48.0 * side).abs() < 1e-4,
            "{}",
            c[0].length()
        );
        assert!((hull_perimeter(&c[0].points) - 48.0 * side).abs() < 1e-4);
        assert!(c[0].goes_round(Vec2::ZERO));
        assert!(!c[0].goes_round(Vec2::new(0.2, 0.0)));
    }

    #[test]
    fn a_level_through_vertices_still_gives_one_closed_loop() {
        // Two cylinders stacked on a shared ring at y 1, cut through that ring: its
        // vertices count as above, so the loop runs just under it, round once.
        let (mut x, mut t) = cylinder(12, 0.1);
        let n = x.len() as u32;
        let (x2, t2) = cylinder(12, 0.1);
        x.extend(x2.iter().map(|p| *p + Vec3::Y));
        // The upper cylinder's bottom ring is the lower one's top ring.
        let shared = |v: u32| if v.is_multiple_of(2) { v + 1 } else { v + n };
        t.extend(t2.iter().map(|t| t.map(shared)));
        let c = section(&x, &t, 1.0);
        assert_eq!(c.len(), 1, "{c:?}");
        assert!(c[0].closed);
        assert!(c[0].goes_round(Vec2::ZERO));
    }

    #[test]
    fn a_slit_cylinder_gives_one_open_chain_and_no_level_outside_gives_nothing() {
        let (x, mut t) = cylinder(24, 0.1);
        // Take away the two triangles of one side: the loop is cut there.
        t.drain(0..2);
        let c = section(&x, &t, 0.5);
        assert_eq!(c.len(), 1, "{c:?}");
        assert!(!c[0].closed);
        assert_eq!(c[0].points.len(), 47);
        assert!(!c[0].goes_round(Vec2::ZERO));
        assert!(section(&x, &t, 1.5).is_empty());
    }

    #[test]
    fn a_tape_bridges_a_hollow() {
        // A square with a notch: the hull is the square.
        let p = [
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.5, 0.5),
            Vec2::new(0.0, 1.0),
        ];
        assert!((hull_perimeter(&p) - 4.0).abs() < 1e-6);
        let notched = Chain {
            points: p.to_vec(),
            closed: true,
        };
        assert!((notched.length() - (3.0 + 2.0 * 0.5f32.sqrt())).abs() < 1e-5);
        assert!((notched.area() - 0.75).abs() < 1e-6);
    }
}
