//! The cloth's texture and painting on it.
//!
//! RGBA8, row 0 at the top (image order); UV (0, 0) is the bottom-left corner as in OBJ.
//! Changes are tracked per square tile so a viewer can upload only what changed.

use glam::Vec2;

/// Side of a dirty-tracking tile, texels.
pub const TILE: usize = 64;

#[derive(Clone, Debug)]
pub struct Texture {
    pub width: usize,
    pub height: usize,
    pub rgba: Vec<u8>,
    dirty: Vec<bool>,
    /// Bumped by every change made through [`Texture::apply`].
    pub version: u64,
}

/// A rectangle of texels before and after a brush stroke (so it can be undone).
#[derive(Clone, Debug, PartialEq)]
pub struct PaintPatch {
    pub x0: usize,
    pub y0: usize,
    pub w: usize,
    pub h: usize,
    pub old: Vec<u8>,
    pub new: Vec<u8>,
}

impl PaintPatch {
    pub fn inverse(self) -> Self {
        Self {
            old: self.new,
            new: self.old,
            ..self
        }
    }

    pub fn bytes(&self) -> usize {
        self.old.len() + self.new.len()
    }
}

impl Texture {
    pub fn new(width: usize, height: usize, fill: [u8; 4]) -> Self {
        let (width, height) = (width.max(1), height.max(1));
        Self {
            width,
            height,
            rgba: fill.repeat(width * height),
            dirty: vec![true; width.div_ceil(TILE) * height.div_ceil(TILE)],
            version: 0,
        }
    }

    pub fn tiles_x(&self) -> usize {
        self.width.div_ceil(TILE)
    }

    pub fn tiles_y(&self) -> usize {
        self.height.div_ceil(TILE)
    }

    /// Tiles `(tx, ty)` changed since the last call, and clears the marks.
    pub fn take_dirty(&mut self) -> Vec<(usize, usize)> {
        let tx = self.tiles_x();
        let out = self
            .dirty
            .iter()
            .enumerate()
            .filter(|(_, d)| **d)
            .map(|(i, _)| (i % tx, i / tx))
            .collect();
        self.dirty.iter_mut().for_each(|d| *d = false);
        out
    }

    pub fn texel(&self, x: usize, y: usize) -> [u8; 4] {
        let i = 4 * (y * self.width + x);
        [
            self.rgba[i],
            self.rgba[i + 1],
            self.rgba[i + 2],
            self.rgba[i + 3],
        ]
    }

    /// The texel under a UV coordinate (clamped to the texture).
    pub fn texel_of(&self, uv: Vec2) -> (usize, usize) {
        let x = (uv.x * self.width as f32)
            .floor()
            .clamp(0.0, (self.width - 1) as f32);
        let y = ((1.0 - uv.y) * self.height as f32)
            .floor()
            .clamp(0.0, (self.height - 1) as f32);
        (x as usize, y as usize)
    }

    /// Writes a patch's `new` texels (its `old` ones when `undo`).
    pub fn apply(&mut self, p: &PaintPatch, undo: bool) {
        self.version += 1;
        let src = if undo { &p.old } else { &p.new };
        for row in 0..p.h {
            let y = p.y0 + row;
            if y >= self.height || p.x0 >= self.width {
                continue;
            }
            let w = p.w.min(self.width - p.x0);
            let d = 4 * (y * self.width + p.x0);
            let s = 4 * row * p.w;
            self.rgba[d..d + 4 * w].copy_from_slice(&src[s..s + 4 * w]);
        }
        let tx = self.tiles_x();
        for ty in p.y0 / TILE..=((p.y0 + p.h).saturating_sub(1) / TILE).min(self.tiles_y() - 1) {
            for t in p.x0 / TILE..=((p.x0 + p.w).saturating_sub(1) / TILE).min(tx - 1) {
                self.dirty[ty * tx + t] = true;
            }
        }
    }

    /// The patch a round brush of `radius` texels at `center` (texel coordinates) would
    /// paint: full colour inside `hardness * radius`, fading to nothing at `radius`,
    /// blended over what is there by the colour's alpha. `None` if it misses the texture.
    pub fn brush(
        &self,
        center: Vec2,
        radius: f32,
        color: [u8; 4],
        hardness: f32,
    ) -> Option<PaintPatch> {
        let r = radius.max(0.5);
        let x0 = (center.x - r).floor().max(0.0) as usize;
        let y0 = (center.y - r).floor().max(0.0) as usize;
        let x1 = ((center.x + r).ceil() as usize).min(self.width);
        let y1 = ((center.y + r).ceil() as usize).min(self.height);
        if x0 >= x1 || y0 >= y1 {
            return None;
        }
        let (w, h) = (x1 - x0, y1 - y0);
        let mut old = Vec::with_capacity(4 * w * h);
        for y in y0..y1 {
            let i = 4 * (y * self.width + x0);
            old.extend_from_slice(&self.rgba[i..i + 4 * w]);
        }
        let mut new = old.clone();
        let soft = (r * (1.0 - hardness.clamp(0.0, 1.0))).max(0.5);
        let ca = color[3] as f32 / 255.0;
        for y in y0..y1 {
            for x in x0..x1 {
                let d = (Vec2::new(x as f32 + 0.5, y as f32 + 0.5) - center).length();
                let a = ((r - d) / soft).clamp(0.0, 1.0) * ca;
                if a <= 0.0 {
                    continue;
                }
                let i = 4 * ((y - y0) * w + (x - x0));
                for c in 0..3 {
                    let v = new[i + c] as f32 * (1.0 - a) + color[c] as f32 * a;
                    new[i + c] = v.round().clamp(0.0, 255.0) as u8;
                }
                new[i + 3] = (new[i + 3] as f32 * (1.0 - a) + 255.0 * a).round() as u8;
            }
        }
        Some(PaintPatch {
            x0,
            y0,
            w,
            h,
            old,
            new,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brush_paints_a_soft_disc_and_undo_restores() {
        let mut t = Texture::new(128, 128, [255; 4]);
        t.take_dirty();
        let p = t
            .brush(Vec2::new(64.0, 64.0), 10.0, [255, 0, 0, 255], 0.5)
            .unwrap();
        t.apply(&p, false);
        assert_eq!(t.texel(64, 64), [255, 0, 0, 255]);
        // Soft edge: partly red between 5 and 10 texels out, untouched beyond.
        let mid = t.texel(72, 64);
        assert!(mid[1] > 0 && mid[1] < 255, "{mid:?}");
        assert_eq!(t.texel(80, 64), [255; 4]);
        let dirty = t.take_dirty();
        assert_eq!(dirty, vec![(0, 0), (1, 0), (0, 1), (1, 1)]);
        t.apply(&p, true);
        assert_eq!(t.texel(64, 64), [255; 4]);
        assert!(t.brush(Vec2::new(-50.0, 10.0), 5.0, [0; 4], 1.0).is_none());
    }
}
