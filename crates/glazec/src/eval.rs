//! CPU evaluation: a material's BRDF at given direction pairs, through the same [`crate::math`]
//! code that `lower` turns into shaders (here with `F = f32`).
//!
//! **Input:** a [`Material`], parameter values, and pairs (wi, wo) in the local shading frame
//! (z = normal, both directions pointing away from the surface). **Output:** f(wi, wo) per pair,
//! RGB, **without** the cosine. This is `glazec eval --backend cpu`; the direction-pair text
//! format lives here too, so that every backend reads the same input.

use glam::Vec3;

use crate::math::Slot;
use crate::math::layering::{self, Inputs};
use crate::math::tables::{curves_for, with_curves};
use crate::model::{Material, ParamValue};

/// f(wi, wo) of `material` with the given parameter values (one per [`Material::params`]).
pub fn brdf(material: &Material, values: &[ParamValue], wi: Vec3, wo: Vec3) -> Vec3 {
    with_curves(curves_for(material), || layering::brdf(material, &inputs(values), Vec3::Z, wo, wi))
}

/// [`brdf`] with shading normals for the layers that have normal maps: (layer, unit normal in
/// the local frame, n = +z); coats are layers 0…, the base is layer `coats.len()`.
pub fn brdf_with_normals(
    material: &Material,
    values: &[ParamValue],
    normals: &[(usize, Vec3)],
    wi: Vec3,
    wo: Vec3,
) -> Vec3 {
    let inputs = inputs(values).with_normals(normals.to_vec());
    with_curves(curves_for(material), || layering::brdf(material, &inputs, Vec3::Z, wo, wi))
}

/// The lobes of `material` under image-based lighting, seen from `v` at normal `n` (see
/// [`layering::environment`]): the split sum is Σ weight · lookup(direction, roughness).
pub fn environment_lobes(
    material: &Material,
    values: &[ParamValue],
    n: Vec3,
    v: Vec3,
) -> Vec<layering::environment::EnvironmentLobe<f32>> {
    with_curves(curves_for(material), || layering::environment::environment_lobes(material, &inputs(values), n, v))
}

/// The reflectance of the material's mirror (delta) lobe towards `wo` (see
/// [`layering::mirror_reflectance`]).
pub fn mirror_reflectance(material: &Material, values: &[ParamValue], wo: Vec3) -> Vec3 {
    with_curves(curves_for(material), || layering::mirror_reflectance(material, &inputs(values), Vec3::Z, wo))
}

/// The CPU inputs of a material for parameter values (one per [`Material::params`]).
pub fn inputs(values: &[ParamValue]) -> Inputs<f32> {
    let params = values
        .iter()
        .map(|v| match *v {
            ParamValue::Scalar(x) => Slot::S(x),
            ParamValue::Rgb(c) => Slot::V(Vec3::from_array(c)),
        })
        .collect();
    Inputs::new((), params)
}

/// A direction pair: the light direction `wi` and the view direction `wo`, both unit vectors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pair {
    pub wi: Vec3,
    pub wo: Vec3,
}

/// A malformed line in a pairs file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("line {line}: {message}")]
pub struct PairsError {
    pub line: usize,
    pub message: String,
}

/// Reads lines `wi_x,wi_y,wi_z,wo_x,wo_y,wo_z`. A first line that is not six numbers is a
/// header; blank lines are skipped. Directions are normalised; a zero or non-finite vector is
/// an error.
///
/// # Errors
/// The first malformed line.
pub fn parse_pairs(text: &str) -> Result<Vec<Pair>, PairsError> {
    let mut pairs = Vec::new();
    for (index, line) in text.lines().enumerate() {
        let line_no = index + 1;
        let trimmed = line.trim();
        if trimmed.is_empty() {
            continue;
        }
        let fields: Vec<&str> = trimmed.split(',').map(str::trim).collect();
        let numbers: Result<Vec<f32>, _> = fields.iter().map(|f| f.parse::<f32>()).collect();
        let numbers = match numbers {
            Ok(n) => n,
            Err(_) if index == 0 => continue, // a header line
            Err(_) => {
                return Err(PairsError { line: line_no, message: format!("expected six numbers, found `{trimmed}`") });
            }
        };
        if numbers.len() != 6 {
            return Err(PairsError {
                line: line_no,
                message: format!("expected 6 values (wi_x,wi_y,wi_z,wo_x,wo_y,wo_z), found {}", numbers.len()),
            });
        }
        let unit = |v: Vec3, what: &str| {
            let len = v.length();
            if len.is_finite() && len > 0.0 {
                Ok(v / len)
            } else {
                Err(PairsError {
                    line: line_no,
                    message: format!("{what} is not a direction (zero length or not finite)"),
                })
            }
        };
        let wi = unit(Vec3::new(numbers[0], numbers[1], numbers[2]), "wi")?;
        let wo = unit(Vec3::new(numbers[3], numbers[4], numbers[5]), "wo")?;
        pairs.push(Pair { wi, wo });
    }
    Ok(pairs)
}

/// One output line `r,g,b`, each value printed with the shortest text that reads back as the
/// same f32 (Rust's `Display`), so no precision is lost.
pub fn format_rgb(rgb: Vec3) -> String {
    format!("{},{},{}", rgb.x, rgb.y, rgb.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairs_with_header_and_blank_lines() {
        let pairs =
            parse_pairs("wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0,2, 0,0,1\n\n0.6,0,0.8,-0.6,0,0.8\n").expect("parses");
        assert_eq!(pairs.len(), 2);
        assert_eq!(pairs[0].wi, Vec3::Z);
        assert_eq!(parse_pairs("0,0,1,0,0\n").unwrap_err().line, 1);
        assert_eq!(parse_pairs("0,0,1,0,0,1\n0,0,x,0,0,1\n").unwrap_err().line, 2);
        assert!(parse_pairs("0,0,0,0,0,1\n").is_err());
    }

    #[test]
    fn rgb_round_trips() {
        let v = Vec3::new(0.1, 1.0 / 3.0, 1e-9);
        let text = format_rgb(v);
        let back: Vec<f32> = text.split(',').map(|x| x.parse().expect("number")).collect();
        assert_eq!(back, [v.x, v.y, v.z]);
    }
}
