//! Material parameters in SI units, and the model choice.

use crate::collision::ContactParams;
use crate::error::{ConfigError, check_range, check_range_or_zero};

/// Which cloth model steps the cloth.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ModelKind {
    /// Vertex Block Descent with penetration-free contact (cloth-body and self).
    Vbd,
    /// Small-steps XPBD with membrane and bending constraints in physical units.
    #[default]
    Xpbd,
    /// The 2005 paper's model: unit masses, springs k(1 - l/l') on edges, explicit
    /// (symplectic) Euler, no damping.
    Seed,
    /// Backward Euler, Newton on the XPBD model's energy, sparse Cholesky in faer.
    Implicit,
}

impl ModelKind {
    pub fn parse(s: &str) -> Result<Self, ConfigError> {
        match s {
            "vbd" => Ok(Self::Vbd),
            "xpbd" => Ok(Self::Xpbd),
            "seed" => Ok(Self::Seed),
            "implicit" => Ok(Self::Implicit),
            other => Err(ConfigError::Unknown {
                what: "model",
                name: other.into(),
                expected: "vbd, xpbd, seed, implicit",
            }),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Vbd => "vbd",
            Self::Xpbd => "xpbd",
            Self::Seed => "seed",
            Self::Implicit => "implicit",
        }
    }
}

/// Default [`Material::shear_damping`], s: 1.5 substeps' worth at the default 5 substeps
/// of a 60 Hz frame. Chosen by measurement: a 128 x 128 cloth hung from two corners then
/// settles at 5 substeps (kinetic energy 9e-11 J after 15 s, against a steady 4e-6 J
/// without), and on the mannequin its energy falls 60x.
pub const DEFAULT_SHEAR_DAMPING: f32 = 0.005;

/// Default [`Material::bend_damping`], s: the hinges damped across their fold like the
/// shear, at 0.4 of the shear's time. Chosen by measurement (1, 2, 5, 20 and 50 ms tried,
/// docs/collision.md): without it the 128 x 128 mannequin drape keeps a flap over the
/// shoulder swinging about once a second for good (its contact search then renews every
/// frame) and the `dress-mannequin` dress keeps 4e-7 to 2e-6 J; with 2 ms both come to
/// rest (under 1e-9 J) and the drape's resting frame is cheaper; at 5 ms and more the
/// drape takes longer to come to rest. Off while a seam is being sewn or the pen holds
/// the cloth (`xpbd`).
pub const DEFAULT_BEND_DAMPING: f32 = 0.002;

fn default_bend_damping() -> f32 {
    DEFAULT_BEND_DAMPING
}

fn default_on() -> bool {
    true
}

fn default_one() -> f32 {
    1.0
}

/// Default [`Material::strain_limit`]: 0.2, a woven fabric's stiff end (its stress-strain
/// curve turns steeply up within a few per cent and its shear locks at 30-40°, where a
/// grid triangle's diagonal is 1.2-1.25x its rest length). With it the mannequin drape's
/// most stretched side is 1.23-1.24x its rest length instead of 1.41-1.43x, the shipped
/// dress closes every seam, and every drape comes to rest; it costs 30-50% more frame
/// (docs/models.md). The library's knits carry 0 (none) and its stretch wovens more
/// (`strain_limit` in `fabrics.toml`); `--strain-limit`, the studio's Hold stretch under
/// (`SET_STRAIN_LIMIT`) and a design file's material set it too.
pub const DEFAULT_STRAIN_LIMIT: f32 = 0.2;

fn default_strain_limit() -> f32 {
    DEFAULT_STRAIN_LIMIT
}

fn default_shear_damping() -> f32 {
    DEFAULT_SHEAR_DAMPING
}

/// Default [`Material::thickness`], m: the library's fabrics' floor. Contact that covers
/// the body's faces, edges and corners and the cloth's own (the xpbd model's guard, on by
/// default, and vbd) needs no more; at the 4 mm this was until 2026-11-28 (for the per-vertex
/// body planes of plain xpbd, whose triangles sag between their vertices), the sewn
/// layers of the paper's fit-cube, held 4 mm apart round the cube's edges, stacked into
/// pleats that never settled under the guard (docs/collision.md).
pub const DEFAULT_THICKNESS: f32 = 0.001;

/// Cloth material. Membrane moduli are 2D (force per unit width), so they do not depend on
/// the mesh resolution; bending rigidity is force x length.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Material {
    /// Areal density, kg/m^2. Cotton shirting: ~0.12-0.2.
    pub density: f32,
    /// Stretch modulus along warp and weft (the UV axes), N/m.
    pub stretch: f32,
    /// In-plane shear modulus, N/m.
    pub shear: f32,
    /// Shear damping time, s: the weave's internal friction in shear (XPBD constraint
    /// damping with `gamma = shear_damping / h` per substep of `h`). It damps only the rate
    /// of shearing, so the rest shape does not change. Without it, Gauss–Seidel keeps a
    /// fine mesh's shear modes oscillating at rest (a 128 x 128 cloth never settles on the
    /// mannequin at 5 substeps). Design files without it get the default.
    #[serde(default = "default_shear_damping")]
    pub shear_damping: f32,
    /// Bending rigidity, N m, in the warp direction (bending the warp yarns: the fold
    /// line runs along the weft). Cotton: ~1e-6..1e-4 (bending length 1-3 cm).
    pub bending: f32,
    /// Bending damping time, s: internal friction in bending, like `shear_damping` (XPBD
    /// constraint damping with `gamma = bend_damping / h` on the hinges). It damps only
    /// the rate of bending, so the rest shape does not change; without it a fine cloth's
    /// loose flaps keep swinging at rest. XPBD only: across each hinge's fold, and not
    /// while a seam is being sewn or the pen holds the cloth. Design files without it
    /// get the default.
    #[serde(default = "default_bend_damping")]
    pub bend_damping: f32,
    /// Weft bending rigidity as a share of `bending` (woven fabrics: 0.3-3). Design files
    /// without it are isotropic.
    #[serde(default = "default_one")]
    pub bending_weft: f32,
    /// Bias (45°) bending rigidity as a share of `bending`; the rigidity at any other
    /// angle follows [`Material::bending_share`].
    #[serde(default = "default_one")]
    pub bending_bias: f32,
    /// Mass-proportional velocity damping, 1/s.
    pub damping: f32,
    /// Air drag on the normal velocity, kg/(m^2 s).
    pub drag: f32,
    /// Coulomb friction against bodies and the floor.
    pub friction: f32,
    /// Contact thickness: the cloth keeps this far from bodies, m.
    pub thickness: f32,
    /// Seed model only: the spring constant k of the paper, N/m, with unit masses.
    pub seed_stiffness: f32,
    /// XPBD only: long-range tethers from free vertices to pins (see `xpbd`).
    pub tethers: bool,
    /// XPBD only: the long-range stretch limits, a coarse lattice of links that carry a
    /// correction across many vertices per pass (see `limits`). Design files without it
    /// get them on.
    #[serde(default = "default_on")]
    pub stretch_limits: bool,
    /// XPBD only: the most a triangle stretches in any direction, over its rest length
    /// (its largest principal stretch is held at or under `1 + strain_limit`), projected
    /// hard in every substep (see `xpbd::strain_limit`); 0 turns it off.
    /// Design files without it get the default.
    #[serde(default = "default_strain_limit")]
    pub strain_limit: f32,
}

impl Default for Material {
    /// A cotton-like woven fabric.
    fn default() -> Self {
        Self {
            density: 0.15,
            stretch: 2000.0,
            shear: 40.0,
            shear_damping: DEFAULT_SHEAR_DAMPING,
            bending: 1.0e-5,
            bend_damping: DEFAULT_BEND_DAMPING,
            bending_weft: 1.0,
            bending_bias: 1.0,
            damping: 0.6,
            drag: 0.5,
            friction: 0.4,
            thickness: DEFAULT_THICKNESS,
            seed_stiffness: 2.0e4,
            tethers: true,
            stretch_limits: true,
            strain_limit: DEFAULT_STRAIN_LIMIT,
        }
    }
}

impl Material {
    /// Whether warp, weft and bias bend alike.
    pub fn isotropic_bending(&self) -> bool {
        self.bending_weft == 1.0 && self.bending_bias == 1.0
    }

    /// The bending rigidity in a direction at angle `θ` from the warp, as a share of
    /// [`bending`](Self::bending), given `cos²θ`: the orthotropic plate's
    /// `B(θ) = Bw c⁴ + 2 Bm c² s² + Bf s⁴`, with `Bm` set so that `B(45°)` is the bias
    /// rigidity (with the bias at the mean of warp and weft this is `Bw c² + Bf s²`).
    /// Never below a twentieth of the smaller of warp and weft.
    pub fn bending_share(&self, cos2: f32) -> f32 {
        let c2 = cos2.clamp(0.0, 1.0);
        let s2 = 1.0 - c2;
        let (w, b) = (self.bending_weft, self.bending_bias);
        let mixed = 2.0 * b - 0.5 * (1.0 + w);
        let share = c2 * c2 + 2.0 * mixed * c2 * s2 + w * s2 * s2;
        share.max(0.05 * w.min(1.0))
    }

    /// The contact settings this material gives, over a floor at `floor` if any.
    pub fn contact_params(&self, floor: Option<f32>) -> ContactParams {
        ContactParams {
            thickness: self.thickness,
            friction: self.friction,
            floor,
        }
    }

    /// Checks every value against the range the models are built for (wide around real
    /// fabrics: chiffon to canvas, and beyond for experiments).
    pub fn validate(&self) -> Result<(), ConfigError> {
        check_range("density", self.density, 0.001, 10.0, " kg/m²")?;
        check_range("stretch", self.stretch, 1.0, 1.0e7, " N/m")?;
        check_range_or_zero("shear", self.shear, 1.0e-3, 1.0e7, " N/m")?;
        check_range_or_zero("shear damping", self.shear_damping, 1.0e-6, 1.0, " s")?;
        check_range_or_zero("bending", self.bending, 1.0e-9, 1.0, " N m")?;
        check_range_or_zero("bend damping", self.bend_damping, 1.0e-6, 1.0, " s")?;
        check_range("weft bending", self.bending_weft, 0.05, 20.0, " x warp")?;
        check_range("bias bending", self.bending_bias, 0.05, 20.0, " x warp")?;
        check_range_or_zero("damping", self.damping, 1.0e-6, 1000.0, " /s")?;
        check_range_or_zero("drag", self.drag, 1.0e-6, 1000.0, " kg/(m² s)")?;
        check_range_or_zero("friction", self.friction, 1.0e-4, 10.0, "")?;
        check_range("thickness", self.thickness, 1.0e-4, 0.05, " m")?;
        check_range_or_zero("strain limit", self.strain_limit, 0.01, 10.0, "")?;
        check_range(
            "seed stiffness",
            self.seed_stiffness,
            1.0e-3,
            1.0e12,
            " N/m",
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bending_share_runs_from_warp_through_bias_to_weft() {
        let m = Material {
            bending_weft: 0.3,
            bending_bias: 0.5,
            ..Material::default()
        };
        assert!((m.bending_share(1.0) - 1.0).abs() < 1e-6);
        assert!((m.bending_share(0.0) - 0.3).abs() < 1e-6);
        assert!((m.bending_share(0.5) - 0.5).abs() < 1e-6);
        // With the bias at the mean, B = Bw cos² + Bf sin².
        let mean = Material {
            bending_weft: 3.0,
            bending_bias: 2.0,
            ..Material::default()
        };
        for c2 in [0.0f32, 0.2, 0.7, 1.0] {
            assert!((mean.bending_share(c2) - (c2 + 3.0 * (1.0 - c2))).abs() < 1e-5);
        }
        assert!(Material::default().isotropic_bending());
        let bad = Material {
            bending_weft: 0.0,
            ..Material::default()
        };
        assert!(bad.validate().is_err());
    }

    /// Found by the commands fuzzer: a shear of 3.6e-43 N/m (subnormal) was in range and
    /// made every frame take hundreds of milliseconds. Off (0) or a real value passes.
    #[test]
    fn a_property_is_off_or_real_never_subnormal() {
        let tiny = 3.59e-43f32;
        assert!(!tiny.is_normal());
        let with = |f: fn(&mut Material, f32), v: f32| {
            let mut m = Material::default();
            f(&mut m, v);
            m.validate()
        };
        type Set = fn(&mut Material, f32);
        let fields: [(&str, Set); 7] = [
            ("shear", |m, v| m.shear = v),
            ("shear damping", |m, v| m.shear_damping = v),
            ("bending", |m, v| m.bending = v),
            ("bend damping", |m, v| m.bend_damping = v),
            ("damping", |m, v| m.damping = v),
            ("drag", |m, v| m.drag = v),
            ("friction", |m, v| m.friction = v),
        ];
        for (name, set) in fields {
            let e = with(set, tiny).expect_err(name).to_string();
            assert!(
                e.starts_with(&format!("{name} must be 0 or between")),
                "{e}"
            );
            assert!(e.ends_with("got 3.59e-43"), "{e}");
            assert!(with(set, 0.0).is_ok(), "{name} off");
            assert!(with(set, -1.0).is_err(), "{name} negative");
        }
    }
}
