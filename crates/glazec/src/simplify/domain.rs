//! The parameter values a simplification must hold for: the scene's pinned values, the ends of
//! its ranges and Halton points inside the box they span.

use crate::diag::{Code, Diagnostic};
use crate::math::sampling::radical_inverse;
use crate::model::{Color, Material, ParamId, ParamValue, Scalar};
use crate::scene::{ParamDomain, Scene};

/// Where each of the material's parameters may lie in the scene.
#[derive(Clone, Debug)]
pub struct ParameterDomain {
    /// Per material parameter: (name, low, high); equal ends for a pinned value.
    bounds: Vec<(String, ParamValue, ParamValue, bool)>,
}

impl ParameterDomain {
    /// The scene's statements about `material`'s parameters; a parameter the scene does not
    /// name is free over its slot's natural range ([`natural_range`]). Names the material does
    /// not have are ignored here (a scene serves many materials; [`check_scene_params`](crate::check::check_scene_params) reports
    /// a name that no material of a set has).
    ///
    /// # Errors
    /// `E0304` for a colour given to a scalar parameter; `E0305` for a value outside what the
    /// parameter's slots accept ([`Param::range`](crate::model::Param::range)).
    pub fn new(material: &Material, scene: &Scene) -> Result<Self, Vec<Diagnostic>> {
        let mut errors = Vec::new();
        for p in &scene.params {
            let Some(param) = material.params.iter().find(|m| m.name == p.name) else { continue };
            let kinds_match = |v: ParamValue| {
                matches!((v, param.default), (ParamValue::Scalar(_), _) | (ParamValue::Rgb(_), ParamValue::Rgb(_)))
            };
            let ok = match p.domain {
                ParamDomain::Pinned(v) => kinds_match(v),
                ParamDomain::Range(lo, hi) => kinds_match(lo) && kinds_match(hi),
            };
            let [lo, hi] = param.range;
            let values = match p.domain {
                ParamDomain::Pinned(v) => v.components().to_vec(),
                ParamDomain::Range(a, b) => [a.components(), b.components()].concat(),
            };
            if let Some(x) = values.iter().find(|x| !(lo..=hi).contains(*x)) {
                errors.push(
                    Diagnostic::error(
                        Code::SceneParamRange,
                        format!(
                            "the scene gives `{}` of `{}` the value {x}, which its slots refuse",
                            p.name, material.name
                        ),
                        p.span,
                        format!("must lie in [{lo}, {hi}]"),
                    )
                    .with_help("a scene's value must be one the material would accept as a literal in that slot"),
                );
            }
            if !ok {
                errors.push(
                    Diagnostic::error(
                        Code::SceneParamType,
                        format!(
                            "`{}` is a scalar parameter of `{}`, but the scene gives it a colour",
                            p.name, material.name
                        ),
                        p.span,
                        "a scalar parameter",
                    )
                    .with_help("give it one number"),
                );
            }
        }
        if !errors.is_empty() {
            return Err(errors);
        }
        let bounds = material
            .params
            .iter()
            .enumerate()
            .map(|(i, param)| {
                let stated = scene.params.iter().find(|p| p.name == param.name);
                let widen = |v: ParamValue| match (v, param.default) {
                    (ParamValue::Scalar(x), ParamValue::Rgb(_)) => ParamValue::Rgb([x; 3]),
                    _ => v,
                };
                match stated.map(|p| p.domain) {
                    Some(ParamDomain::Pinned(v)) => (param.name.clone(), widen(v), widen(v), true),
                    Some(ParamDomain::Range(lo, hi)) => (param.name.clone(), widen(lo), widen(hi), false),
                    None => {
                        let (lo, hi) = natural_range(material, ParamId(i as u16));
                        let (lo, hi) = match param.default {
                            ParamValue::Scalar(_) => (ParamValue::Scalar(lo), ParamValue::Scalar(hi)),
                            ParamValue::Rgb(_) => (ParamValue::Rgb([lo; 3]), ParamValue::Rgb([hi; 3])),
                        };
                        (param.name.clone(), lo, hi, false)
                    }
                }
            })
            .collect();
        Ok(ParameterDomain { bounds })
    }

    pub(super) fn pinned_names(&self) -> Vec<String> {
        self.bounds.iter().filter(|b| b.3).map(|b| b.0.clone()).collect()
    }

    pub(super) fn pinned(&self, name: &str) -> Option<ParamValue> {
        self.bounds.iter().find(|b| b.0 == name && b.3).map(|b| b.1)
    }

    /// A point of the box: `t` ∈ [0, 1] per parameter (per channel of a colour).
    pub(super) fn point(&self, t: &dyn Fn(usize) -> f32) -> Vec<(String, ParamValue)> {
        let mut axis = 0;
        self.bounds
            .iter()
            .map(|(name, lo, hi, _)| {
                let value = match (lo, hi) {
                    (ParamValue::Scalar(a), ParamValue::Scalar(b)) => {
                        axis += 1;
                        ParamValue::Scalar(a + (b - a) * t(axis - 1))
                    }
                    (ParamValue::Rgb(a), ParamValue::Rgb(b)) => {
                        let mut c = [0.0; 3];
                        for k in 0..3 {
                            c[k] = a[k] + (b[k] - a[k]) * t(axis + k);
                        }
                        axis += 3;
                        ParamValue::Rgb(c)
                    }
                    _ => *lo,
                };
                (name.clone(), value)
            })
            .collect()
    }

    pub(super) fn axes(&self) -> usize {
        self.bounds.iter().map(|(_, lo, _, _)| if matches!(lo, ParamValue::Scalar(_)) { 1 } else { 3 }).sum()
    }

    /// The parameter vectors a sample set uses: the box's centre, each axis's two ends with the
    /// others at the centre, and `halton` points of the Halton sequence (bases 2, 3, 5, …)
    /// starting at `offset`.
    pub fn vectors(&self, halton: usize, offset: usize) -> Vec<Vec<(String, ParamValue)>> {
        if self.bounds.is_empty() {
            return vec![Vec::new()];
        }
        let axes = self.axes();
        let mut out = vec![self.point(&|_| 0.5)];
        for axis in 0..axes {
            for end in [0.0, 1.0] {
                out.push(self.point(&|a| if a == axis { end } else { 0.5 }));
            }
        }
        for i in 0..halton {
            out.push(self.point(&|a| radical_inverse(PRIMES[a % PRIMES.len()], (i + offset + 1) as u32)));
        }
        out.dedup();
        out
    }
}

const PRIMES: [u32; 16] = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53];

/// The range a free parameter is taken over, from the slot it feeds: roughness, albedo,
/// reflectance and σ [0, 1]; IOR [1, 3] (the tables' range); absorption and thickness from 0 to
/// twice the default (at least 2: what a material author tunes around).
pub fn natural_range(material: &Material, id: ParamId) -> (f32, f32) {
    let default = match material.params[id.0 as usize].default {
        ParamValue::Scalar(x) => x,
        ParamValue::Rgb(c) => c.iter().copied().fold(0.0, f32::max),
    };
    let is = |s: &Scalar| *s == Scalar::Param(id);
    let open = (0.0, (2.0 * default).max(2.0));
    for coat in &material.coats {
        if is(&coat.ior) {
            return (1.0, 3.0);
        }
        if is(&coat.thickness) || coat.absorption == Color::Param(id) {
            return open;
        }
    }
    (0.0, 1.0)
}

/// The values of `material` for a named parameter vector (defaults for names it lacks).
pub fn values_for(material: &Material, named: &[(String, ParamValue)]) -> Vec<ParamValue> {
    material.params.iter().map(|p| named.iter().find(|(n, _)| *n == p.name).map_or(p.default, |(_, v)| *v)).collect()
}
