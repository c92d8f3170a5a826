//! What the viewer knows of the design: the latest mesh, positions, texture, body, tool
//! state, pen and telemetry, all as cloth-sim and haptic-loop sent them (checked before
//! they get here). The UI only reads it; `Link` writes it.

use std::collections::VecDeque;
use std::time::Instant;

use shared::haptic_to_sim::DeviceSample;
use shared::sim_to_haptic::LocalModel;
use shared::sim_to_ui::{
    ListedPiece, MeshCorner, OutlineSegment, SeamEntry, SeamSegment, ToolState,
};
use shared::telemetry::{LoopTelemetry, SimTelemetry};

/// The cloth's triangles and what the renderer derives from them.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub topology: u64,
    pub vertices: usize,
    /// The vertices some triangle uses: a deleted piece's stay in `vertices` (an undo
    /// brings them back) but are no cloth.
    pub used: usize,
    pub corners: Vec<MeshCorner>,
    /// Edges with one triangle: the cloth's border and its cuts.
    pub border: Vec<[u32; 2]>,
    /// Edges whose two triangles map them to different places of the pattern: where
    /// pieces were sewn (a sew or a welded seam).
    pub sewn: Vec<[u32; 2]>,
    /// The pattern's pieces: each corner key (vertex and UV bits) to its piece, the
    /// triangles joined by shared keys (as cloth-sim finds its pieces).
    pub piece_of: std::collections::HashMap<Key, u32>,
    /// The pattern's outline edges (in one triangle only, by key), as pairs of pattern
    /// places (m) with the piece they belong to: what the pattern view draws.
    pub outline: Vec<OutlineEdge>,
}

/// An outline edge of the pattern: its two ends' pattern places (m) and its piece.
pub type OutlineEdge = ([f32; 2], [f32; 2], u32);

/// A corner of the pattern: its vertex and its UV's bits.
pub type Key = (u32, u32, u32);

/// The key of a corner.
pub fn key(vertex: u32, uv: [f32; 2]) -> Key {
    (vertex, uv[0].to_bits(), uv[1].to_bits())
}

/// Each key's piece (pattern-connected triangles) and the outline edges.
fn pieces_of(corners: &[MeshCorner]) -> (std::collections::HashMap<Key, u32>, Vec<OutlineEdge>) {
    let mut id: std::collections::HashMap<Key, usize> = Default::default();
    let keys: Vec<usize> = corners
        .iter()
        .map(|c| {
            let n = id.len();
            *id.entry(key(c.vertex, [c.u, c.v])).or_insert(n)
        })
        .collect();
    let mut parent: Vec<usize> = (0..id.len()).collect();
    fn find(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    for t in keys.chunks_exact(3) {
        for k in 1..3 {
            let (a, b) = (find(&mut parent, t[0]), find(&mut parent, t[k]));
            parent[a] = b;
        }
    }
    let piece_of = id
        .iter()
        .map(|(&k, &i)| (k, find(&mut parent, i) as u32))
        .collect();
    let mut count: std::collections::HashMap<(usize, usize), u32> = Default::default();
    for t in keys.chunks_exact(3) {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    let place: Vec<[f32; 2]> = {
        let mut v = vec![[0.0; 2]; id.len()];
        for (c, &i) in corners.iter().zip(&keys) {
            v[i] = c.pattern;
        }
        v
    };
    let mut outline: Vec<OutlineEdge> = count
        .into_iter()
        .filter(|&(_, n)| n == 1)
        .map(|((a, b), _)| (place[a], place[b], find(&mut parent, a) as u32))
        .collect();
    outline.sort_by(|p, q| p.partial_cmp(q).unwrap_or(std::cmp::Ordering::Equal));
    (piece_of, outline)
}

impl Mesh {
    pub fn new(topology: u64, vertices: usize, corners: Vec<MeshCorner>) -> Self {
        // Per edge: its triangles, and the UVs the first one gives its two ends.
        type Uv = [u32; 2];
        let mut edges: std::collections::HashMap<(u32, u32), (u32, Uv, Uv, bool)> =
            Default::default();
        let uv = |c: &MeshCorner| [c.u.to_bits(), c.v.to_bits()];
        for t in corners.chunks_exact(3) {
            for k in 0..3 {
                let (p, q) = (&t[k], &t[(k + 1) % 3]);
                let (lo, hi) = if p.vertex < q.vertex { (p, q) } else { (q, p) };
                let e = edges
                    .entry((lo.vertex, hi.vertex))
                    .or_insert((0, uv(lo), uv(hi), false));
                if e.0 > 0 && (e.1 != uv(lo) || e.2 != uv(hi)) {
                    e.3 = true;
                }
                e.0 += 1;
            }
        }
        let mut border = Vec::new();
        let mut sewn = Vec::new();
        for (&(a, b), &(count, _, _, split)) in &edges {
            if count == 1 {
                border.push([a, b]);
            } else if split {
                sewn.push([a, b]);
            }
        }
        border.sort_unstable();
        sewn.sort_unstable();
        let (piece_of, outline) = pieces_of(&corners);
        let mut seen = vec![false; vertices];
        for c in &corners {
            if let Some(s) = seen.get_mut(c.vertex as usize) {
                *s = true;
            }
        }
        Self {
            topology,
            vertices,
            used: seen.iter().filter(|&&s| s).count(),
            corners,
            border,
            sewn,
            piece_of,
            outline,
        }
    }

    pub fn triangles(&self) -> usize {
        self.corners.len() / 3
    }
}

/// The cloth's texture as the tiles built it, and the regions changed since the renderer
/// last uploaded.
#[derive(Clone, Debug)]
pub struct Texture {
    pub width: usize,
    pub height: usize,
    pub rgba: Vec<u8>,
    pub dirty: Vec<[usize; 4]>,
    pub tiles_seen: usize,
    /// Tiles received at least once (by corner), and the texels they cover.
    seen: std::collections::HashSet<(usize, usize)>,
    covered: usize,
}

impl Default for Texture {
    fn default() -> Self {
        let (w, h) = (1024, 1024);
        Self {
            width: w,
            height: h,
            rgba: [235u8, 235, 230, 255].repeat(w * h),
            dirty: vec![[0, 0, w, h]],
            tiles_seen: 0,
            seen: Default::default(),
            covered: 0,
        }
    }
}

impl Texture {
    /// Writes a tile (already checked to lie inside a `width` x `height` texture); a new
    /// size resets the texture.
    pub fn apply(&mut self, width: usize, height: usize, rect: [usize; 4], rgba: &[u8]) {
        if (width, height) != (self.width, self.height) {
            *self = Self {
                width,
                height,
                rgba: [235u8, 235, 230, 255].repeat(width * height),
                dirty: vec![[0, 0, width, height]],
                tiles_seen: 0,
                seen: Default::default(),
                covered: 0,
            };
        }
        let [x0, y0, w, h] = rect;
        for r in 0..h {
            let dst = 4 * ((y0 + r) * width + x0);
            self.rgba[dst..dst + 4 * w].copy_from_slice(&rgba[4 * r * w..4 * (r + 1) * w]);
        }
        self.dirty.push(rect);
        self.tiles_seen += 1;
        if self.seen.insert((x0, y0)) {
            self.covered += w * h;
        }
    }

    /// Every texel has come from cloth-sim at least once.
    pub fn complete(&self) -> bool {
        self.covered >= self.width * self.height
    }
}

/// One point of the status plots.
#[derive(Clone, Copy, Debug, Default)]
pub struct Sample {
    pub t: f64,
    pub haptic_period_p999_us: f64,
    pub haptic_compute_p99_us: f64,
    pub model_age_p99_ms: f64,
    pub sim_frame_ms: f64,
}

/// Who was heard from, and when.
#[derive(Clone, Copy, Debug, Default)]
pub struct Heard {
    pub sim: Option<Instant>,
    pub haptic: Option<Instant>,
}

#[derive(Debug)]
pub struct Store {
    pub started: Instant,
    pub mesh: Option<Mesh>,
    /// Bumped with every mesh received (the renderer rebuilds its index on a change, even
    /// when a loaded design happens to have the same topology number).
    pub mesh_generation: u64,
    pub x: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
    pub frame: u64,
    pub texture: Texture,
    pub body: Option<shared::sim_to_ui::BodyMesh>,
    /// Bumped when the body changes (the renderer re-uploads).
    pub body_version: u64,
    pub tool: Option<ToolState>,
    pub pen: Option<DeviceSample>,
    pub model: Option<LocalModel>,
    pub loop_tel: Option<Box<LoopTelemetry>>,
    pub sim_tel: Option<Box<SimTelemetry>>,
    /// Open seam stitches of the newest frame: vertex pairs still pulling together, each
    /// with its seam's place in the seam list.
    pub stitches: Vec<[u32; 3]>,
    /// The last 600 points (one per loop telemetry message, 10 Hz: a minute).
    pub history: VecDeque<Sample>,
    pub heard: Heard,
    /// Messages refused because they failed their checks, and the last reason.
    pub rejected: u64,
    pub last_rejection: Option<String>,
    /// The newest protocol mismatch, if any: shown as a banner.
    pub mismatch: Option<String>,
    /// The design's pieces as cloth-sim lists them, and how many it has in all.
    pub pieces: Vec<ListedPiece>,
    pub pieces_total: u32,
    /// The design's seams as cloth-sim lists them (labelled A, B, ... by place).
    pub seams: Vec<SeamEntry>,
    pub seams_total: u32,
    /// The listed seams' outline edges in the pattern plane, each with its seam's place.
    pub seam_segments: Vec<SeamSegment>,
    /// The pattern's lines as cloth-sim's pattern out makes them (sewing lines, notches,
    /// grain lines), and how many it has (more than `outline` holds: the pattern view
    /// draws the mesh's own outline instead).
    pub outline: Vec<OutlineSegment>,
    pub outline_total: u32,
    /// The pattern file the design was made from, as cloth-sim lists it (empty: none).
    pub source: String,
    /// The pinned vertices as cloth-sim lists them (increasing), and how many the design
    /// has (more when over `MAX_PINS`): the views draw a pin at each.
    pub pins: Vec<u32>,
    pub pins_total: u32,
    /// The mesh piece (`Mesh::piece_of`) the 3D view and pattern view highlight.
    pub highlight: Option<u32>,
    /// The map the 3D view and the pattern view colour the cloth by (the threads' stretch
    /// or the ease), while the designer shows it; kept current by `mapper`.
    pub stretch: Option<crate::stretch::StretchMap>,
    /// The garment's girths at the body's bust, waist and hips while the Fit section is
    /// on (None: off, or a body that is no figure; empty: no cloth yet); kept current by
    /// `mapper`.
    pub fit: Option<Vec<sim_core::design::garment::fit::Girth>>,
}

impl Default for Store {
    fn default() -> Self {
        Self {
            started: Instant::now(),
            mesh: None,
            mesh_generation: 0,
            x: Vec::new(),
            normals: Vec::new(),
            frame: 0,
            texture: Texture::default(),
            body: None,
            body_version: 0,
            tool: None,
            pen: None,
            model: None,
            loop_tel: None,
            sim_tel: None,
            stitches: Vec::new(),
            history: VecDeque::new(),
            heard: Heard::default(),
            rejected: 0,
            last_rejection: None,
            mismatch: None,
            pieces: Vec::new(),
            pieces_total: 0,
            seams: Vec::new(),
            seams_total: 0,
            seam_segments: Vec::new(),
            source: String::new(),
            pins: Vec::new(),
            pins_total: 0,
            outline: Vec::new(),
            outline_total: 0,
            highlight: None,
            stretch: None,
            fit: None,
        }
    }
}

impl Store {
    /// A flat square cloth of `n x n` cells, 1 m wide at height `y`, for tests and the
    /// demo view when no cloth-sim is running.
    pub fn demo_cloth(n: usize, y: f32) -> (Mesh, Vec<[f32; 3]>) {
        let side = n + 1;
        let mut x = Vec::with_capacity(side * side);
        for r in 0..side {
            for c in 0..side {
                x.push([c as f32 / n as f32 - 0.5, y, r as f32 / n as f32 - 0.5]);
            }
        }
        let uv = |i: usize| ((i % side) as f32 / n as f32, (i / side) as f32 / n as f32);
        let mut corners = Vec::new();
        for r in 0..n {
            for c in 0..n {
                let i = r * side + c;
                for v in [i, i + side, i + 1, i + 1, i + side, i + side + 1] {
                    let (u, w) = uv(v);
                    corners.push(MeshCorner {
                        vertex: v as u32,
                        u,
                        v: w,
                        pattern: [u, -w],
                    });
                }
            }
        }
        (Mesh::new(1, x.len(), corners), x)
    }

    /// Installs positions and recomputes normals (used by the demo and tests).
    pub fn set_positions(&mut self, x: Vec<[f32; 3]>) {
        self.normals = vertex_normals(self.mesh.as_ref(), &x);
        self.x = x;
    }

    pub fn record(&mut self, e: &shared::MessageError) {
        self.rejected += 1;
        let s = e.to_string();
        if matches!(e, shared::MessageError::Protocol { .. }) {
            self.mismatch = Some(s.clone());
        }
        self.last_rejection = Some(s);
    }

    /// Adds a status-plot point from the newest telemetry.
    pub fn push_sample(&mut self) {
        let Some(l) = &self.loop_tel else { return };
        let us = |ns: u64| ns as f64 / 1000.0;
        let s = Sample {
            t: self.started.elapsed().as_secs_f64(),
            haptic_period_p999_us: us(l.period.quantile_ns(0.999)),
            haptic_compute_p99_us: us(l.compute.quantile_ns(0.99)),
            model_age_p99_ms: us(l.model_age.quantile_ns(0.99)) / 1000.0,
            sim_frame_ms: self
                .sim_tel
                .as_ref()
                .map_or(0.0, |s| us(s.frame_time.quantile_ns(0.5)) / 1000.0),
        };
        self.history.push_back(s);
        while self.history.len() > 600 {
            self.history.pop_front();
        }
    }
}

/// Area-weighted vertex normals of `mesh` at positions `x` (zero where unknown).
pub fn vertex_normals(mesh: Option<&Mesh>, x: &[[f32; 3]]) -> Vec<[f32; 3]> {
    use glam::Vec3;
    let mut n = vec![Vec3::ZERO; x.len()];
    if let Some(m) = mesh {
        for t in m.corners.chunks_exact(3) {
            let [a, b, c] = [t[0].vertex, t[1].vertex, t[2].vertex].map(|i| i as usize);
            if a >= x.len() || b >= x.len() || c >= x.len() {
                continue;
            }
            let (pa, pb, pc) = (Vec3::from(x[a]), Vec3::from(x[b]), Vec3::from(x[c]));
            let f = (pb - pa).cross(pc - pa);
            n[a] += f;
            n[b] += f;
            n[c] += f;
        }
    }
    n.into_iter()
        .map(|v| v.normalize_or(Vec3::Y).to_array())
        .collect()
}

impl Store {
    /// The mesh piece (`Mesh::piece_of`) of listed piece `index`, found from its anchor.
    pub fn mesh_piece(&self, index: usize) -> Option<u32> {
        let (v, uv) = self.pieces.get(index)?.anchor?;
        self.mesh.as_ref()?.piece_of.get(&key(v, uv)).copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_demo_cloth_has_its_border_and_nothing_inside() {
        let (m, x) = Store::demo_cloth(4, 0.5);
        assert_eq!((x.len(), m.triangles()), (25, 32));
        // 4 sides of 4 edges.
        assert_eq!(m.border.len(), 16);
        assert!(m.sewn.is_empty());
    }

    #[test]
    fn an_edge_two_pieces_share_at_different_pattern_places_is_sewn() {
        let c = |vertex, u: f32, v: f32| MeshCorner {
            vertex,
            u,
            v,
            pattern: [u, -v],
        };
        // Two triangles over edge (1, 2); the second maps it elsewhere on the pattern,
        // as after sewing two pieces. Edge (2, 3) shares its UVs: not sewn.
        let corners = vec![
            c(0, 0.0, 0.0),
            c(1, 0.5, 0.0),
            c(2, 0.0, 0.5),
            c(1, 0.9, 0.0),
            c(3, 0.9, 0.5),
            c(2, 0.6, 0.5),
        ];
        let m = Mesh::new(1, 4, corners.clone());
        assert_eq!(m.sewn, vec![[1, 2]]);
        assert_eq!(m.border.len(), 4);
        // The same triangles cut from one sheet (matching UVs): nothing sewn.
        let mut one = corners;
        one[3] = c(1, 0.5, 0.0);
        one[5] = c(2, 0.0, 0.5);
        assert!(Mesh::new(1, 4, one).sewn.is_empty());
    }

    #[test]
    fn tiles_land_where_they_say() {
        let mut t = Texture::default();
        t.apply(1024, 1024, [64, 128, 2, 2], &[9u8; 16]);
        assert_eq!(&t.rgba[4 * (128 * 1024 + 64)..][..8], &[9u8; 8]);
        assert_eq!(t.rgba[4 * (128 * 1024 + 66)], 235);
        assert_eq!(t.dirty.last(), Some(&[64, 128, 2, 2]));
        assert!(!t.complete());
        let mut small = Texture::default();
        small.apply(4, 2, [0, 0, 2, 2], &[1u8; 16]);
        small.apply(4, 2, [0, 0, 2, 2], &[1u8; 16]);
        assert!(!small.complete(), "a tile sent twice covers it once");
        small.apply(4, 2, [2, 0, 2, 2], &[1u8; 16]);
        assert!(small.complete());
    }
}
