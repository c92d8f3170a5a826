//! Materials by region of the cloth's rest (pattern) plane: how pieces of different
//! fabrics hang side by side in one cloth.
//!
//! A zone is a band of the rest plane's x (a design lays its pieces side by side along x
//! there, each in a band of its own). A triangle whose rest centre lies in a zone's band
//! has the zone's mass and stiffness: density, stretch, shear and bending with its weft
//! and bias shares, and under xpbd its strain limit. Everything else (damping, drag, shear damping, friction and contact
//! thickness) stays the simulation's, one for the whole cloth: contact keeps one
//! thickness between every pair of layers. A cloth of one material has no zones, and
//! then every element is exactly what it was without them.
//!
//! The models see zones as factors on each element: a membrane's stretch and shear
//! stiffness and a hinge's bending weight are scaled by the zone's modulus over the
//! solver's (see [`MaterialZones::reference`]), and each vertex's lumped mass sums its
//! triangles' own densities. Cut, torn and sewn triangles keep their rest corners, so
//! they stay in their piece's zone.

use glam::Vec3;

use super::material::Material;
use crate::error::ConfigError;

/// Slack on a band's ends, m (as the design's own band test has it).
const BAND_SLACK: f32 = 1e-4;

/// One band of the rest plane's x with its material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Zone {
    pub lo: f32,
    pub hi: f32,
    pub material: Material,
}

/// The zones of a cloth, first match wins (see the module's note).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MaterialZones {
    zones: Vec<Zone>,
    /// The simulation's material, which triangles outside every zone have.
    base: Material,
}

/// What an element's zone multiplies its stiffness by, relative to the solver's material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scales {
    pub stretch: f32,
    pub shear: f32,
    pub bending: f32,
}

impl Scales {
    pub const ONE: Scales = Scales {
        stretch: 1.0,
        shear: 1.0,
        bending: 1.0,
    };
}

/// Whether two materials give the same mass, stiffness and strain limit (the fields
/// zones carry).
fn same_cloth(a: &Material, b: &Material) -> bool {
    a.density == b.density
        && a.stretch == b.stretch
        && a.shear == b.shear
        && a.bending == b.bending
        && a.bending_weft == b.bending_weft
        && a.bending_bias == b.bending_bias
        && a.strain_limit == b.strain_limit
}

fn ratio(value: f32, reference: f32) -> f32 {
    if reference > 0.0 {
        value / reference
    } else {
        0.0
    }
}

impl MaterialZones {
    /// Zones over `base` (the simulation's material). Zones whose material hangs as
    /// `base` does are dropped, so a cloth whose pieces share one fabric has none. Each
    /// zone's material must pass [`Material::validate`] and its band be finite.
    pub fn new(zones: Vec<Zone>, base: &Material) -> Result<Self, ConfigError> {
        for z in &zones {
            if !(z.lo.is_finite() && z.hi.is_finite() && z.lo <= z.hi) {
                return Err(ConfigError::OutOfRange {
                    name: "material zone",
                    rule: "a finite band, low end first",
                    value: format!("{}..{}", z.lo, z.hi),
                });
            }
            z.material.validate()?;
        }
        // Keep the first-match order: a dropped zone would let a later overlapping one
        // take its triangles, so zones equal to the base are dropped only when no zone
        // differs from it.
        if zones.iter().all(|z| same_cloth(&z.material, base)) {
            return Ok(Self::default());
        }
        Ok(Self { zones, base: *base })
    }

    /// The same zones over a changed simulation material.
    pub fn rebase(&mut self, base: &Material) {
        if !self.zones.is_empty() {
            self.base = *base;
        }
    }

    pub fn is_empty(&self) -> bool {
        self.zones.is_empty()
    }

    pub fn zones(&self) -> &[Zone] {
        &self.zones
    }

    /// The zone a triangle with these rest corners lies in.
    fn zone_of(&self, rest: &[Vec3; 3]) -> Option<&Zone> {
        self.zone_index(rest).map(|i| &self.zones[i])
    }

    /// The index in [`zones`](Self::zones) of the zone a triangle with these rest corners
    /// lies in.
    pub fn zone_index(&self, rest: &[Vec3; 3]) -> Option<usize> {
        if self.zones.is_empty() {
            return None;
        }
        let x = (rest[0].x + rest[1].x + rest[2].x) / 3.0;
        self.zones
            .iter()
            .position(|z| x >= z.lo - BAND_SLACK && x <= z.hi + BAND_SLACK)
    }

    /// The material of a triangle with these rest corners: its zone's, else `base`.
    pub fn material_at<'a>(&'a self, rest: &[Vec3; 3], base: &'a Material) -> &'a Material {
        self.zone_of(rest).map_or(base, |z| &z.material)
    }

    /// The areal density of a triangle with these rest corners, kg/m² (`base` when
    /// there are no zones).
    pub fn density_at(&self, rest: &[Vec3; 3], base: f32) -> f32 {
        if self.zones.is_empty() {
            return base;
        }
        self.zone_of(rest)
            .map_or(self.base.density, |z| z.material.density)
    }

    /// The material the models are built with: `base`, with any modulus that is zero
    /// there raised to the zones' largest (so a zone stiffer than nothing still has a
    /// scale; `base`'s own triangles then scale by zero).
    pub fn reference(&self, base: &Material) -> Material {
        let mut m = *base;
        // Stretch is never zero (`Material::validate`); shear and bending may be.
        for z in &self.zones {
            if base.shear <= 0.0 {
                m.shear = m.shear.max(z.material.shear);
            }
            if base.bending <= 0.0 {
                m.bending = m.bending.max(z.material.bending);
            }
        }
        m
    }

    /// The scales of a triangle with these rest corners against `reference` (the
    /// solver's material, [`reference`](Self::reference) of the simulation's): exactly
    /// one when there are no zones.
    pub fn scales(&self, rest: &[Vec3; 3], reference: &Material) -> Scales {
        if self.zones.is_empty() {
            return Scales::ONE;
        }
        let m = self.material_at(rest, &self.base);
        Scales {
            stretch: ratio(m.stretch, reference.stretch),
            shear: ratio(m.shear, reference.shear),
            bending: ratio(m.bending, reference.bending),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri_at(x: f32) -> [Vec3; 3] {
        [
            Vec3::new(x - 0.01, 0.0, 0.0),
            Vec3::new(x + 0.01, 0.0, 0.0),
            Vec3::new(x, 0.0, -0.01),
        ]
    }

    #[test]
    fn a_triangle_takes_its_bands_material_and_the_base_elsewhere() {
        let base = Material::default();
        let denim = Material {
            density: 0.4,
            stretch: 8000.0,
            bending: 4e-5,
            bending_weft: 0.5,
            ..base
        };
        let z = MaterialZones::new(
            vec![Zone {
                lo: 1.0,
                hi: 2.0,
                material: denim,
            }],
            &base,
        )
        .unwrap();
        let r = z.reference(&base);
        assert_eq!(r, base);
        assert_eq!(z.scales(&tri_at(0.5), &r), Scales::ONE);
        let s = z.scales(&tri_at(1.5), &r);
        assert_eq!((s.stretch, s.shear, s.bending), (4.0, 1.0, 4.0));
        assert_eq!(z.density_at(&tri_at(1.5), base.density), 0.4);
        assert_eq!(z.density_at(&tri_at(2.5), base.density), base.density);
        assert_eq!(z.material_at(&tri_at(1.5), &base).bending_weft, 0.5);
    }

    #[test]
    fn zones_like_the_base_are_none_and_bad_zones_are_refused() {
        let base = Material::default();
        let same = Zone {
            lo: 0.0,
            hi: 1.0,
            material: Material {
                friction: 0.9,
                ..base
            },
        };
        assert!(MaterialZones::new(vec![same], &base).unwrap().is_empty());
        let nan = Zone {
            lo: f32::NAN,
            ..same
        };
        assert!(MaterialZones::new(vec![nan], &base).is_err());
        let soft = Zone {
            material: Material {
                density: -1.0,
                ..base
            },
            ..same
        };
        assert!(MaterialZones::new(vec![soft], &base).is_err());
    }

    #[test]
    fn a_zone_stiffer_than_a_limp_base_still_bends() {
        let base = Material {
            bending: 0.0,
            shear: 0.0,
            ..Material::default()
        };
        let stiff = Material {
            bending: 2e-5,
            shear: 30.0,
            ..Material::default()
        };
        let z = MaterialZones::new(
            vec![Zone {
                lo: 0.0,
                hi: 1.0,
                material: stiff,
            }],
            &base,
        )
        .unwrap();
        let r = z.reference(&base);
        assert_eq!((r.bending, r.shear), (2e-5, 30.0));
        let inside = z.scales(&tri_at(0.5), &r);
        let outside = z.scales(&tri_at(3.0), &r);
        assert_eq!((inside.bending, inside.shear), (1.0, 1.0));
        assert_eq!((outside.bending, outside.shear), (0.0, 0.0));
    }
}
