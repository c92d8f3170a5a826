//! Room in the texture for a new piece. The design has one texture, and each piece its
//! own part of it, so paint on one never shows on another. A new piece gets a part: the
//! texture coordinates of everything there shrink alike toward the texture's top-left
//! corner and the new piece takes the strip freed on the right, each at about the same
//! texels per metre of cloth. Shrinking and moving coordinates alike in both directions
//! keeps every triangle's warp direction, so the models need not follow ([`Prim::Uv`]);
//! paint already there is resampled to where its triangles now look.

use glam::Vec2;

use super::document::{CLOTH_COLOUR, Design};
use super::prim::Prim;
use super::texture::{PaintPatch, Texture};

/// The least and most of the texture's side the design's parts keep.
const KEEP: (f32, f32) = (0.3, 0.95);

/// A sliver of texture left between the parts, as a share of the side.
const MARGIN: f32 = 0.01;

/// Where everything goes: the design's coordinates shrink by `keep` toward the top-left
/// corner (UV (0, 1)); the new piece's are `(uv - from) * scale + to`.
pub(super) struct Room {
    pub keep: f32,
    from: Vec2,
    scale: f32,
    to: Vec2,
}

impl Room {
    /// A coordinate of the design as it will be.
    pub fn design(&self, uv: Vec2) -> Vec2 {
        Vec2::new(self.keep * uv.x, 1.0 - self.keep * (1.0 - uv.y))
    }

    /// A coordinate of the new piece's own (as its mesh has it) in the design's texture.
    pub fn piece(&self, uv: Vec2) -> Vec2 {
        ((uv - self.from) * self.scale + self.to).clamp(Vec2::ZERO, Vec2::ONE)
    }
}

/// The area of a triangle with these corners.
fn area2(p: [Vec2; 3]) -> f32 {
    0.5 * (p[1] - p[0]).perp_dot(p[2] - p[0]).abs()
}

impl Design {
    /// The room for a new piece whose own triangles have texture coordinates `uvs` and
    /// rest areas `areas` (m²), and the primitives that make it: every live triangle's
    /// coordinates shrunk, and the texture resampled unless it is one colour. `None`
    /// for a design without cloth (the piece keeps its own coordinates).
    pub(super) fn make_room(&self, uvs: &[[Vec2; 3]], areas: &[f32]) -> Option<(Room, Vec<Prim>)> {
        let live = &self.sim.cloth.live;
        let (mut old_uv, mut old_rest) = (0.0f32, 0.0f32);
        for (_, t) in live.iter() {
            old_uv += area2(t.uv);
            old_rest += t.rest_area();
        }
        if old_rest <= 0.0 {
            return None;
        }
        let new_uv: f32 = uvs.iter().map(|t| area2(*t)).sum();
        let new_rest: f32 = areas.iter().sum();
        let (lo, hi) = uvs
            .iter()
            .flatten()
            .fold((Vec2::MAX, Vec2::MIN), |(a, b), p| (a.min(*p), b.max(*p)));
        let size = (hi - lo).max(Vec2::splat(1e-6));
        // Equal texels per metre: keep² old_uv / old_rest = scale² new_uv / new_rest,
        // with the piece's width filling the strip, scale = (1 - keep) / width.
        let ratio = size.x * ((old_uv * new_rest) / (old_rest * new_uv.max(1e-12))).sqrt();
        let keep = (1.0 / (1.0 + ratio)).clamp(KEEP.0, KEEP.1);
        let strip = 1.0 - keep - 2.0 * MARGIN;
        let scale = (strip / size.x).min((1.0 - MARGIN) / size.y);
        let room = Room {
            keep,
            from: Vec2::new(lo.x, hi.y),
            scale,
            to: Vec2::new(keep + MARGIN, 1.0 - MARGIN),
        };
        let mut prims: Vec<Prim> = live
            .iter()
            .map(|(slot, t)| Prim::Uv {
                slot,
                old: t.uv,
                new: t.uv.map(|uv| room.design(uv)),
            })
            .collect();
        if let Some(patch) = resampled(&self.texture, keep) {
            prims.push(Prim::Paint(patch));
        }
        Some((room, prims))
    }
}

/// The whole texture shrunk by `keep` into its top-left corner (each new texel the mean
/// of the old ones it covers), the rest the cloth's colour; `None` when the texture is
/// one colour throughout (nothing to move).
fn resampled(tex: &Texture, keep: f32) -> Option<PaintPatch> {
    // Word by word: a slice comparison per texel cost about 15 ms a texture.
    let word = |t: &[u8]| u32::from_ne_bytes([t[0], t[1], t[2], t[3]]);
    let first = word(tex.rgba.get(..4)?);
    if tex.rgba.chunks_exact(4).all(|t| word(t) == first) {
        return None;
    }
    let (w, h) = (tex.width, tex.height);
    let mut new = CLOTH_COLOUR.repeat(w * h);
    let (kw, kh) = ((keep * w as f32) as usize, (keep * h as f32) as usize);
    for y in 0..kh {
        let (y0, y1) = span(y, keep, h);
        for x in 0..kw {
            let (x0, x1) = span(x, keep, w);
            let mut sum = [0u32; 4];
            for sy in y0..y1 {
                for sx in x0..x1 {
                    let t = tex.texel(sx, sy);
                    for c in 0..4 {
                        sum[c] += t[c] as u32;
                    }
                }
            }
            let n = ((y1 - y0) * (x1 - x0)).max(1) as u32;
            let i = 4 * (y * w + x);
            for c in 0..4 {
                new[i + c] = ((sum[c] + n / 2) / n) as u8;
            }
        }
    }
    Some(PaintPatch {
        x0: 0,
        y0: 0,
        w,
        h,
        old: tex.rgba.clone(),
        new,
    })
}

/// The old texels (along one side of `len`) that new texel `i` covers when shrunk by
/// `keep`: at least one.
fn span(i: usize, keep: f32, len: usize) -> (usize, usize) {
    let a = ((i as f32 / keep).floor() as usize).min(len - 1);
    let b = (((i + 1) as f32 / keep).ceil() as usize).clamp(a + 1, len);
    (a, b)
}
