//! The fabric library: measured fabrics with their sources, and the conversions from the
//! units they were published in to the model's SI [`Material`].
//!
//! The data live in `sim-core/data/fabrics.toml` (built in); docs/fabrics.md documents
//! every field and conversion.

use serde::Deserialize;

use crate::solver::Material;

/// The built-in library.
pub const BUILTIN: &str = include_str!("../../data/fabrics.toml");

/// The library file's format version this build reads.
pub const FORMAT_VERSION: i64 = 1;

/// Standard gravity, m/s²: grams-force to newtons.
const G: f64 = 9.806_65;

/// A fabric's strain limit when its entry gives none: a woven's (the default material's,
/// [`crate::solver::material::DEFAULT_STRAIN_LIMIT`]).
pub const WOVEN_STRAIN_LIMIT: f64 = 0.2;

/// The contact thickness a fabric gets at least, m: thinner layers than this are held
/// apart at this distance (the contact's tolerance, not the cloth's own thickness).
pub const MIN_CONTACT_THICKNESS: f32 = 0.001;

/// How a fabric's mechanical values were published.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Units {
    /// CLO3D input units a source converted from KES-FB: g/s² and g·mm²/s².
    Clo,
    /// ARCSim material files: stiffness samples in N/m, hinge stiffness `ke` in N·m.
    Arcsim,
    /// KES-F: EMT (%), G (gf/(cm·°)), B (gf·cm²/cm).
    Kes,
    /// FAST: E100 (%), EB5 (%), B (µN·m).
    Fast,
}

impl Units {
    fn parse(s: &str) -> Option<Self> {
        match s {
            "clo" => Some(Self::Clo),
            "arcsim" => Some(Self::Arcsim),
            "kes" => Some(Self::Kes),
            "fast" => Some(Self::Fast),
            _ => None,
        }
    }

    /// Tensile stiffness, N/m, from the published value.
    pub fn stretch_si(self, v: f64) -> f64 {
        match self {
            // g/s² = 1e-3 kg/s² = 1e-3 N/m.
            Self::Clo => v * 1e-3,
            // c11 (or c22) of ARCSim's Green-strain energy: the same modulus as ours for
            // small strain.
            Self::Arcsim => v,
            // Secant modulus to 500 gf/cm at EMT % strain.
            Self::Kes => 500.0 * G * 1e-3 / 1e-2 / (v / 100.0),
            // Secant modulus to 100 gf/cm at E100 % strain.
            Self::Fast => 100.0 * G * 1e-3 / 1e-2 / (v / 100.0),
        }
    }

    /// Shear modulus, N/m (stress per radian of shear), from the published value.
    pub fn shear_si(self, v: f64) -> f64 {
        match self {
            Self::Clo => v * 1e-3,
            // ARCSim's energy density has c33 G12² with the Green shear strain G12 = γ/2;
            // ours has shear/2 γ²: shear = c33 / 2.
            Self::Arcsim => v * 0.5,
            // gf/cm per degree -> N/m per radian.
            Self::Kes => v * G * 1e-3 / 1e-2 * (180.0 / std::f64::consts::PI),
            // FAST's shear rigidity G = 123 / EB5 N/m (CSIRO's FAST manual).
            Self::Fast => 123.0 / v,
        }
    }

    /// Bending rigidity, N·m, from the published value.
    pub fn bending_si(self, v: f64) -> f64 {
        match self {
            // g·mm²/s² = 1e-3 kg * 1e-6 m² / s² = 1e-9 N·m.
            Self::Clo => v * 1e-9,
            // ARCSim's hinge energy ke l²/(8A) θ², with its curvature θ l / A being 2/3 of
            // the true one on a regular mesh, is ke κ² A / 18 against the continuum
            // B κ² A / 6 of the hinge's third of the area: B = ke / 3 (docs/fabrics.md).
            Self::Arcsim => v / 3.0,
            // gf·cm²/cm = 9.80665e-3 N * 1e-4 m² / 1e-2 m.
            Self::Kes => v * G * 1e-3 * 1e-4 / 1e-2,
            Self::Fast => v * 1e-6,
        }
    }
}

/// One fabric of the library, as its source gave it.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Fabric {
    pub name: String,
    pub description: String,
    pub source: String,
    pub units: Units,
    pub weight_gsm: f64,
    pub thickness_mm: f64,
    pub stretch_warp: f64,
    pub stretch_weft: f64,
    pub shear: f64,
    pub bend_warp: f64,
    pub bend_weft: f64,
    /// Bias bending; the mean of warp and weft when not measured.
    pub bend_bias: Option<f64>,
    pub friction: f64,
    /// The most a triangle stretches over its rest length (the xpbd model's hard limit,
    /// `Material::strain_limit`); 0: none, as for knits. Chosen, not measured.
    pub strain_limit: f64,
    /// The values the source did not measure, with what was chosen.
    pub assumed: Vec<String>,
    /// Cusick drape coefficient (0-1) the source measured.
    pub dc_measured: Option<f64>,
    /// Node count the source measured.
    pub nodes_measured: Option<u32>,
    /// The drape coefficient the source's own simulator gave, if it reported one.
    pub dc_source_sim: Option<f64>,
}

/// A fabric's parameters in SI units.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct FabricSi {
    /// kg/m².
    pub density: f64,
    /// m.
    pub thickness: f64,
    /// N/m.
    pub stretch_warp: f64,
    pub stretch_weft: f64,
    /// N/m per radian.
    pub shear: f64,
    /// N·m.
    pub bend_warp: f64,
    pub bend_weft: f64,
    pub bend_bias: f64,
    pub friction: f64,
    /// The most a triangle stretches over its rest length (0: no limit).
    pub strain_limit: f64,
    /// Bending length `(B / (ρ g))^(1/3)` along the warp, m (Peirce's cantilever).
    pub bending_length_warp: f64,
    pub bending_length_weft: f64,
}

impl Fabric {
    /// The fabric in SI units.
    pub fn si(&self) -> FabricSi {
        let u = self.units;
        let density = self.weight_gsm * 1e-3;
        let (bw, bf) = (u.bending_si(self.bend_warp), u.bending_si(self.bend_weft));
        let bias = self.bend_bias.map_or(0.5 * (bw + bf), |b| u.bending_si(b));
        let length = |b: f64| (b / (density * G)).cbrt();
        FabricSi {
            density,
            thickness: self.thickness_mm * 1e-3,
            stretch_warp: u.stretch_si(self.stretch_warp),
            stretch_weft: u.stretch_si(self.stretch_weft),
            shear: u.shear_si(self.shear),
            bend_warp: bw,
            bend_weft: bf,
            bend_bias: bias,
            friction: self.friction,
            strain_limit: self.strain_limit,
            bending_length_warp: length(bw),
            bending_length_weft: length(bf),
        }
    }

    /// The model's material for this fabric: membrane stretch isotropic at the
    /// geometric mean of warp and weft (the membrane has one stretch modulus), bending
    /// anisotropic, contact thickness at least [`MIN_CONTACT_THICKNESS`], the fabric's
    /// strain limit; damping, drag and the solver switches as in the default material.
    pub fn material(&self) -> Material {
        let s = self.si();
        Material {
            density: s.density as f32,
            stretch: (s.stretch_warp * s.stretch_weft).sqrt() as f32,
            shear: s.shear as f32,
            bending: s.bend_warp as f32,
            bending_weft: (s.bend_weft / s.bend_warp) as f32,
            bending_bias: (s.bend_bias / s.bend_warp) as f32,
            friction: s.friction as f32,
            thickness: (s.thickness as f32).max(MIN_CONTACT_THICKNESS),
            strain_limit: s.strain_limit as f32,
            ..Material::default()
        }
    }
}

impl Fabric {
    /// `base` with this fabric's values (density, stretch, shear, bending in warp, weft
    /// and bias, friction, thickness, strain limit); its damping, drag and solver
    /// switches stay, being the designer's settings rather than the cloth's.
    pub fn material_over(&self, base: &Material) -> Material {
        let f = self.material();
        Material {
            density: f.density,
            stretch: f.stretch,
            shear: f.shear,
            bending: f.bending,
            bending_weft: f.bending_weft,
            bending_bias: f.bending_bias,
            friction: f.friction,
            thickness: f.thickness,
            strain_limit: f.strain_limit,
            ..*base
        }
    }
}

/// What is wrong with a fabric file.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum FabricError {
    #[error("fabric file: {0}")]
    Syntax(String),
    #[error("fabric file: version {found}, this build reads version {FORMAT_VERSION}")]
    Version { found: String },
    #[error("fabric file: no [[fabric]] entries")]
    Empty,
    #[error("fabric {index} ({name}): {reason}")]
    Field {
        index: usize,
        name: String,
        reason: String,
    },
    #[error("fabric {name}: named twice")]
    Duplicate { name: String },
    #[error("no fabric named {name:?}; the library has: {known}")]
    Unknown { name: String, known: String },
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Raw {
    name: String,
    description: String,
    source: String,
    units: String,
    weight_gsm: f64,
    thickness_mm: f64,
    stretch_warp: f64,
    stretch_weft: f64,
    shear: f64,
    bend_warp: f64,
    bend_weft: f64,
    bend_bias: Option<f64>,
    friction: f64,
    strain_limit: Option<f64>,
    #[serde(default)]
    assumed: Vec<String>,
    dc_measured: Option<f64>,
    nodes_measured: Option<u32>,
    dc_source_sim: Option<f64>,
}

/// The fabric library.
#[derive(Clone, Debug, PartialEq)]
pub struct Library {
    pub fabrics: Vec<Fabric>,
}

impl Library {
    /// The built-in library.
    pub fn builtin() -> Self {
        // The built-in file is checked by the tests; it cannot fail at run time.
        Self::parse(BUILTIN).unwrap_or(Self {
            fabrics: Vec::new(),
        })
    }

    /// Reads a library file's text: every fabric whole, in range and named once, or an
    /// error naming the fabric and the field.
    pub fn parse(text: &str) -> Result<Self, FabricError> {
        let table: toml::Table =
            toml::from_str(text).map_err(|e| FabricError::Syntax(e.to_string()))?;
        match table.get("version") {
            Some(toml::Value::Integer(FORMAT_VERSION)) => {}
            other => {
                return Err(FabricError::Version {
                    found: other.map_or("none".into(), |v| v.to_string()),
                });
            }
        }
        if let Some(extra) = table.keys().find(|k| *k != "version" && *k != "fabric") {
            return Err(FabricError::Syntax(format!(
                "unknown key {extra:?} (expected version and [[fabric]])"
            )));
        }
        let entries = match table.get("fabric") {
            Some(toml::Value::Array(a)) if !a.is_empty() => a,
            _ => return Err(FabricError::Empty),
        };
        let mut fabrics: Vec<Fabric> = Vec::with_capacity(entries.len());
        for (i, entry) in entries.iter().enumerate() {
            let name = entry
                .get("name")
                .and_then(|n| n.as_str())
                .unwrap_or("unnamed")
                .to_string();
            let field = |reason: String| FabricError::Field {
                index: i + 1,
                name: name.clone(),
                reason,
            };
            types(entry).map_err(&field)?;
            let raw: Raw = entry
                .clone()
                .try_into()
                .map_err(|e: toml::de::Error| field(e.message().trim().to_string()))?;
            let fabric = check(raw).map_err(field)?;
            if fabrics.iter().any(|f| f.name == fabric.name) {
                return Err(FabricError::Duplicate { name: fabric.name });
            }
            fabrics.push(fabric);
        }
        Ok(Self { fabrics })
    }

    /// The fabric called `name`.
    pub fn get(&self, name: &str) -> Result<&Fabric, FabricError> {
        self.fabrics
            .iter()
            .find(|f| f.name == name)
            .ok_or_else(|| FabricError::Unknown {
                name: name.into(),
                known: self.names().join(", "),
            })
    }

    pub fn names(&self) -> Vec<&str> {
        self.fabrics.iter().map(|f| f.name.as_str()).collect()
    }
}

/// Names the first field of the wrong type (serde's message does not).
fn types(entry: &toml::Value) -> Result<(), String> {
    let Some(table) = entry.as_table() else {
        return Err("expected a table of fields".into());
    };
    for (key, value) in table {
        let want = match key.as_str() {
            "name" | "description" | "source" | "units" => "a string",
            "assumed" => "a list of strings",
            "nodes_measured" => "a whole number",
            _ => "a number",
        };
        let ok = match want {
            "a string" => value.is_str(),
            "a list of strings" => value
                .as_array()
                .is_some_and(|a| a.iter().all(|v| v.is_str())),
            "a whole number" => value.is_integer(),
            _ => value.is_float() || value.is_integer(),
        };
        if !ok {
            return Err(format!("{key}: expected {want}, found {value}"));
        }
    }
    Ok(())
}

/// Range checks, in the published units (wide: chiffon to canvas and knits), and on the
/// SI values the model receives.
fn check(raw: Raw) -> Result<Fabric, String> {
    let units = Units::parse(&raw.units)
        .ok_or_else(|| format!("units {:?}: expected clo, arcsim, kes or fast", raw.units))?;
    let name_ok = !raw.name.is_empty()
        && raw
            .name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-');
    if !name_ok {
        return Err("name: lower-case letters, digits and '-' only".into());
    }
    if raw.source.trim().is_empty() {
        return Err("source: every fabric names where its values come from".into());
    }
    let positive = |field: &str, v: f64| -> Result<(), String> {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err(format!("{field}: {v} is not a positive number"))
        }
    };
    for (field, v) in [
        ("weight_gsm", raw.weight_gsm),
        ("thickness_mm", raw.thickness_mm),
        ("stretch_warp", raw.stretch_warp),
        ("stretch_weft", raw.stretch_weft),
        ("shear", raw.shear),
        ("bend_warp", raw.bend_warp),
        ("bend_weft", raw.bend_weft),
    ] {
        positive(field, v)?;
    }
    if let Some(b) = raw.bend_bias {
        positive("bend_bias", b)?;
    }
    let within = |field: &str, v: f64, lo: f64, hi: f64, unit: &str| -> Result<(), String> {
        if (lo..=hi).contains(&v) {
            Ok(())
        } else {
            Err(format!("{field}: {v}{unit} is outside {lo}..{hi}{unit}"))
        }
    };
    within("weight_gsm", raw.weight_gsm, 5.0, 1500.0, " g/m²")?;
    within("thickness_mm", raw.thickness_mm, 0.02, 10.0, " mm")?;
    within("friction", raw.friction, 0.0, 3.0, "")?;
    let strain_limit = raw.strain_limit.unwrap_or(WOVEN_STRAIN_LIMIT);
    if strain_limit != 0.0 {
        // As `Material::validate` takes it: 0 (none), or 0.01-10.
        within("strain_limit", strain_limit, 0.01, 10.0, " (or 0 for none)")?;
    }
    if let Some(dc) = raw.dc_measured {
        within("dc_measured", dc, 0.0, 1.0, "")?;
    }
    if let Some(dc) = raw.dc_source_sim {
        within("dc_source_sim", dc, 0.0, 1.0, "")?;
    }
    if let Some(n) = raw.nodes_measured {
        within("nodes_measured", n as f64, 2.0, 30.0, "")?;
    }
    let fabric = Fabric {
        name: raw.name,
        description: raw.description,
        source: raw.source,
        units,
        weight_gsm: raw.weight_gsm,
        thickness_mm: raw.thickness_mm,
        stretch_warp: raw.stretch_warp,
        stretch_weft: raw.stretch_weft,
        shear: raw.shear,
        bend_warp: raw.bend_warp,
        bend_weft: raw.bend_weft,
        bend_bias: raw.bend_bias,
        friction: raw.friction,
        strain_limit,
        assumed: raw.assumed,
        dc_measured: raw.dc_measured,
        nodes_measured: raw.nodes_measured,
        dc_source_sim: raw.dc_source_sim,
    };
    let s = fabric.si();
    within(
        "stretch (SI)",
        s.stretch_warp.min(s.stretch_weft),
        1.0,
        1e7,
        " N/m",
    )?;
    within("shear (SI)", s.shear, 1e-3, 1e7, " N/m")?;
    within(
        "bending (SI)",
        s.bend_warp.min(s.bend_weft),
        1e-9,
        1e-2,
        " N·m",
    )?;
    let m = fabric.material();
    m.validate().map_err(|e| format!("as a material: {e}"))?;
    Ok(fabric)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, rel: f64) -> bool {
        (a - b).abs() <= rel * b.abs()
    }

    #[test]
    fn the_builtin_library_loads_whole_and_sourced() {
        let lib = Library::parse(BUILTIN).expect("the built-in library");
        assert!(lib.fabrics.len() >= 12, "{}", lib.fabrics.len());
        for f in &lib.fabrics {
            assert!(!f.source.trim().is_empty(), "{}", f.name);
            f.material().validate().expect("a valid material");
        }
        let measured = lib.fabrics.iter().filter(|f| f.dc_measured.is_some());
        assert!(measured.count() >= 6);
        // A knit among them, and denim.
        assert!(lib.get("jersey-interlock").is_ok() && lib.get("denim").is_ok());
        assert!(matches!(
            lib.get("chiffon-x"),
            Err(FabricError::Unknown { .. })
        ));
    }

    /// The conversions, worked by hand.
    #[test]
    fn published_units_convert_to_si_as_worked_by_hand() {
        // KES-F: B = 0.1 gf·cm²/cm = 0.1 * 9.80665e-3 N * 1e-4 m² / 1e-2 m.
        assert!(close(Units::Kes.bending_si(0.1), 9.80665e-6, 1e-9));
        // G = 1 gf/(cm·°): 0.980665 N/m per degree, 56.19 N/m per radian.
        assert!(close(Units::Kes.shear_si(1.0), 56.187, 1e-4));
        // EMT 5 % at 500 gf/cm (490.33 N/m): a secant modulus of 9,806.65 N/m.
        assert!(close(Units::Kes.stretch_si(5.0), 9806.65, 1e-9));
        // FAST: B 5 µN·m; G = 123 / EB5 = 61.5 N/m at EB5 2 %; E100 2 % at 98.07 N/m.
        assert!(close(Units::Fast.bending_si(5.0), 5e-6, 1e-12));
        assert!(close(Units::Fast.shear_si(2.0), 61.5, 1e-12));
        assert!(close(Units::Fast.stretch_si(2.0), 4903.325, 1e-9));
        // CLO: 1950 g·mm²/s² = 1.95e-6 N·m; 41000 g/s² = 41 N/m.
        assert!(close(Units::Clo.bending_si(1950.0), 1.95e-6, 1e-12));
        assert!(close(Units::Clo.shear_si(41000.0), 41.0, 1e-12));
        // ARCSim: B = ke / 3; shear = c33 / 2.
        assert!(close(Units::Arcsim.bending_si(64.2e-6), 21.4e-6, 1e-9));
        assert!(close(Units::Arcsim.shear_si(53.4), 26.7, 1e-12));
        // One fabric whole: Petrak's M1 as the model gets it.
        let lib = Library::builtin();
        let f = lib.get("polyester-twill").expect("M1");
        let m = f.material();
        assert!((m.density - 0.13517).abs() < 1e-6);
        assert!((m.bending - 1.95e-6).abs() < 1e-12);
        assert!((m.bending_weft - 610.0 / 1950.0).abs() < 1e-6);
        assert!((m.bending_bias - 0.5 * (1.0 + 610.0 / 1950.0)).abs() < 1e-6);
        assert!((m.stretch - (477.226f32 * 458.614).sqrt()).abs() < 1e-2);
        assert!(
            (m.thickness - MIN_CONTACT_THICKNESS).abs() < 1e-9,
            "0.31 mm, floored"
        );
        // Peirce's bending length: (1.95e-6 / (0.13517 * 9.80665))^(1/3) = 1.14 cm.
        assert!((f.si().bending_length_warp - 0.01137).abs() < 1e-4);
    }

    /// Wovens hold 1.2x unless their entry says otherwise (stretch wovens 1.3x), knits
    /// nothing, and choosing a fabric brings its limit with it.
    #[test]
    fn each_fabric_carries_its_own_strain_limit() {
        let lib = Library::builtin();
        let limit = |name: &str| lib.get(name).expect(name).material().strain_limit;
        assert_eq!(limit("denim"), 0.2);
        assert_eq!(limit("polyester-twill"), 0.2);
        assert_eq!(limit("wool-stretch-twill"), 0.3);
        for knit in [
            "jersey-interlock",
            "rib-knit",
            "sweatshirt-knit",
            "ponte-roma",
        ] {
            assert_eq!(limit(knit), 0.0, "{knit}");
        }
        let knit = lib.get("jersey-interlock").expect("a knit");
        assert_eq!(knit.material_over(&Material::default()).strain_limit, 0.0);
        // An entry without the field is a woven's; 0 is none.
        let plain = Library::parse(&one(GOOD)).expect("good");
        assert_eq!(plain.fabrics[0].strain_limit, WOVEN_STRAIN_LIMIT);
        let none = Library::parse(&one(&(GOOD.to_string() + "strain_limit = 0\n")));
        assert_eq!(none.expect("0 is none").fabrics[0].strain_limit, 0.0);
    }

    fn one(body: &str) -> String {
        format!("version = 1\n[[fabric]]\n{body}")
    }

    const GOOD: &str = r#"name = "test-cloth"
description = "d"
source = "s"
units = "kes"
weight_gsm = 150
thickness_mm = 0.4
stretch_warp = 4
stretch_weft = 5
shear = 0.8
bend_warp = 0.08
bend_weft = 0.05
friction = 0.3
"#;

    #[test]
    fn a_malformed_file_names_the_fabric_and_the_field() {
        assert!(Library::parse(&one(GOOD)).is_ok());
        let cases = [
            (GOOD.replace("shear = 0.8\n", ""), "missing field `shear`"),
            (
                GOOD.replace("bend_warp = 0.08", "bend_warp = -1"),
                "bend_warp",
            ),
            (
                GOOD.replace("weight_gsm = 150", "weight_gsm = 5000"),
                "weight_gsm",
            ),
            (GOOD.replace("units = \"kes\"", "units = \"cgs\""), "units"),
            (
                GOOD.replace("friction = 0.3", "friction = \"high\""),
                "friction",
            ),
            (GOOD.to_string() + "colour = \"red\"\n", "colour"),
            (GOOD.replace("source = \"s\"", "source = \" \""), "source"),
            (
                GOOD.replace("bend_weft = 0.05", "bend_weft = 50"),
                "material",
            ),
            (GOOD.to_string() + "strain_limit = 0.001\n", "strain_limit"),
            (GOOD.to_string() + "strain_limit = nan\n", "strain_limit"),
        ];
        for (body, field) in cases {
            let err = Library::parse(&one(&body)).expect_err(field);
            let text = err.to_string();
            assert!(
                text.contains("fabric 1 (test-cloth)") && text.contains(field),
                "{field}: {text}"
            );
        }
        let twice = one(GOOD) + "[[fabric]]\n" + GOOD;
        assert!(matches!(
            Library::parse(&twice),
            Err(FabricError::Duplicate { .. })
        ));
        assert!(matches!(
            Library::parse(&GOOD.replace("name", "version = 2\n[[fabric]]\nname")),
            Err(FabricError::Version { .. })
        ));
        assert!(matches!(
            Library::parse("version = 1\n"),
            Err(FabricError::Empty)
        ));
        assert!(matches!(
            Library::parse("version = 1\n[[fabric]\n"),
            Err(FabricError::Syntax(_))
        ));
    }
}
