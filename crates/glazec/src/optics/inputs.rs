//! Named inputs of a solve, as the CLI's flags and a CSV batch's columns give them, and the
//! CSV batch itself (`glazec optics --csv`).

use super::{Observation, OpticsError, Slab, SlabModel, Solution, diffuse_fresnel_external, solve};

/// Named inputs, as the CLI's flags and CSV columns give them (one channel or spectral sample).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Inputs {
    pub r_black: Option<f64>,
    pub r_white: Option<f64>,
    pub backing: Option<f64>,
    pub thickness: Option<f64>,
    pub r1: Option<f64>,
    pub d1: Option<f64>,
    pub r2: Option<f64>,
    pub d2: Option<f64>,
    pub reflectance: Option<f64>,
    pub scattering: Option<f64>,
    pub ratio: Option<f64>,
    pub mfp: Option<f64>,
    /// `seed` (eq. 1 as published) or `exponential` (default) for slab inversions.
    pub seed_model: bool,
    pub ior: Option<f64>,
    pub f_top: Option<f64>,
    pub f_bottom: Option<f64>,
    pub p_g: Option<f64>,
}

/// The CSV column / flag names of [`Inputs`], in order.
pub const INPUT_NAMES: [&str; 16] = [
    "r_black",
    "r_white",
    "backing",
    "thickness",
    "r1",
    "d1",
    "r2",
    "d2",
    "reflectance",
    "scattering",
    "ratio",
    "mfp",
    "ior",
    "f_top",
    "f_bottom",
    "p_g",
];

impl Inputs {
    /// Sets the input called `name` (one of [`INPUT_NAMES`]); `false` for an unknown name.
    pub fn set(&mut self, name: &str, value: f64) -> bool {
        let slot = match name {
            "r_black" => &mut self.r_black,
            "r_white" => &mut self.r_white,
            "backing" => &mut self.backing,
            "thickness" => &mut self.thickness,
            "r1" => &mut self.r1,
            "d1" => &mut self.d1,
            "r2" => &mut self.r2,
            "d2" => &mut self.d2,
            "reflectance" => &mut self.reflectance,
            "scattering" => &mut self.scattering,
            "ratio" => &mut self.ratio,
            "mfp" => &mut self.mfp,
            "ior" => &mut self.ior,
            "f_top" => &mut self.f_top,
            "f_bottom" => &mut self.f_bottom,
            "p_g" => &mut self.p_g,
            _ => return false,
        };
        *slot = Some(value);
        true
    }

    /// The slab of the slab models: F_dr,t from `f_top` or the external diffuse Fresnel of `ior`
    /// (default 1.5), F_dr,b = `f_bottom` (default 0, a black backing), P(g) = `p_g` (default ½).
    fn slab(&self) -> Slab {
        let eta = self.ior.unwrap_or(1.5);
        Slab {
            f_top: self.f_top.unwrap_or_else(|| diffuse_fresnel_external(eta)),
            f_bottom: self.f_bottom.unwrap_or(0.0),
            p_g: self.p_g.unwrap_or(0.5),
            eta,
        }
    }

    /// Which observation the given inputs make (see the module docs' table).
    ///
    /// # Errors
    /// [`OpticsError::SingleReflectance`] for a reflectance alone, [`OpticsError::Missing`] for
    /// an incomplete observation.
    pub fn observation(&self) -> Result<Observation, OpticsError> {
        let need = |v: Option<f64>, name: &'static str, why: &'static str| v.ok_or(OpticsError::Missing(name, why));
        let model = if self.seed_model { SlabModel::Seed } else { SlabModel::Exponential };
        if self.r_black.is_some() || self.r_white.is_some() {
            const WHY: &str = "Kubelka–Munk needs r_black, r_white, backing and thickness";
            return Ok(Observation::BlackWhite {
                r_black: need(self.r_black, "r_black", WHY)?,
                r_white: need(self.r_white, "r_white", WHY)?,
                backing: need(self.backing, "backing", WHY)?,
                thickness: need(self.thickness, "thickness", WHY)?,
            });
        }
        if self.r1.is_some() || self.r2.is_some() {
            const WHY: &str = "two thicknesses need r1, d1, r2 and d2";
            return Ok(Observation::TwoThicknesses {
                model,
                slab: self.slab(),
                d1: need(self.d1, "d1", WHY)?,
                r1: need(self.r1, "r1", WHY)?,
                d2: need(self.d2, "d2", WHY)?,
                r2: need(self.r2, "r2", WHY)?,
            });
        }
        let r = need(self.reflectance, "reflectance", "give a reflectance (or r_black/r_white, or r1/r2)")?;
        if let Some(mfp) = self.mfp {
            return Ok(Observation::MeanFreePath { r, mfp, eta: self.ior.unwrap_or(1.5) });
        }
        const WHY: &str = "a reflectance with a prior needs the sample's thickness";
        if let Some(sigma_s) = self.scattering {
            return Ok(Observation::KnownScattering {
                model,
                slab: self.slab(),
                d: need(self.thickness, "thickness", WHY)?,
                r,
                sigma_s,
            });
        }
        if let Some(ratio) = self.ratio {
            return Ok(Observation::KnownRatio {
                model,
                slab: self.slab(),
                d: need(self.thickness, "thickness", WHY)?,
                r,
                ratio,
            });
        }
        Ok(Observation::Single { r })
    }
}

/// A CSV batch that cannot be read at all.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BatchError {
    #[error("the batch has no header line")]
    Empty,
    #[error("unknown column `{column}` (columns: {})", INPUT_NAMES.join(", "))]
    UnknownColumn { column: String },
}

/// One observation of a batch and what it solved to, or why it did not.
#[derive(Clone, Debug, PartialEq)]
pub struct BatchRow {
    /// The row's text as given.
    pub line: String,
    pub result: Result<Solution, String>,
}

/// A CSV batch: a header naming columns (from [`INPUT_NAMES`]) and one observation per row.
#[derive(Clone, Debug, PartialEq)]
pub struct Batch {
    pub header: Vec<String>,
    pub rows: Vec<BatchRow>,
}

impl Batch {
    /// Reads and solves every row of `text` (blank lines skipped; an empty cell is an input not
    /// given). `seed_model` and `ior` apply to every row, as `--model` and `--ior` do.
    ///
    /// # Errors
    /// A missing header or an unknown column; a bad row fails that row only.
    pub fn solve(text: &str, seed_model: bool, ior: Option<f64>) -> Result<Batch, BatchError> {
        let mut lines = text.lines().filter(|l| !l.trim().is_empty());
        let header: Vec<String> =
            lines.next().ok_or(BatchError::Empty)?.split(',').map(|h| h.trim().to_string()).collect();
        if let Some(column) = header.iter().find(|name| !INPUT_NAMES.contains(&name.as_str())) {
            return Err(BatchError::UnknownColumn { column: column.clone() });
        }
        let rows = lines
            .enumerate()
            .map(|(row, line)| {
                // Rows count from 1 at the header, as a spreadsheet numbers them.
                let number = row + 2;
                let cells: Vec<&str> = line.split(',').map(str::trim).collect();
                let mut inputs = Inputs { seed_model, ior, ..Default::default() };
                let mut bad = None;
                for (name, cell) in header.iter().zip(&cells).filter(|(_, cell)| !cell.is_empty()) {
                    match cell.parse::<f64>() {
                        Ok(v) => {
                            inputs.set(name, v);
                        }
                        Err(_) => bad = Some(format!("row {number}: `{cell}` in column {name} is not a number")),
                    }
                }
                if cells.len() != header.len() {
                    bad = Some(format!("row {number}: {} cells for {} columns", cells.len(), header.len()));
                }
                let result = match bad {
                    Some(message) => Err(message),
                    None => inputs.observation().and_then(|o| solve(&o)).map_err(|e| e.to_string()),
                };
                BatchRow { line: line.to_string(), result }
            })
            .collect();
        Ok(Batch { header, rows })
    }
}
